"""``rlff report FOLDER`` of one's own chain: what it shows of the attempts logs (the robot, the
joints and the bearing their runs threw with) and how it treats rlff's other outputs."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

from attempts_logs import write_attempts_log
from rlff.chain_report import chain_run
from rlff.plots.learning import read_learning_log


def _log(path: Path, record: dict, basket: dict, joints: list[str] | None = None, misses=(-0.3, 0.01),
         budget: int | None = None, **settings) -> Path:
    """An attempts log whose header holds ``record`` (:func:`rlff.learn.log.robot_record`),
    ``settings`` (``gap``, ``until``) and ``budget`` (None: none, as an older log's)."""
    run = {"basket": basket, "feedback": "binary", "update": "calibrate", "seed": 0, "robot": record,
           "pedestal": 0.0, "until": "hit", **settings}
    if joints is not None:
        run["joints"] = joints
    return write_attempts_log(path, run, misses, budget=budget)


def _cells(html: str, row_start: str) -> list[str]:
    """The cells of the table row of the report whose first cell is ``row_start``."""
    for row in re.findall(r"<tr>(.*?)</tr>", html, re.S):
        cells = [re.sub(r"<[^>]+>", "", c).strip() for c in re.findall(r"<t[dh][^>]*>(.*?)</t[dh]>", row, re.S)]
        if cells and cells[0] == row_start:
            return cells
    raise AssertionError(f"no row {row_start!r}")


def test_an_attempts_log_is_shown_with_the_robot_joints_and_bearing_it_threw_with(tmp_path):
    # the report showed method, feedback and basket only: a log of another arm, other joints or a
    # basket off to the side read like one of the Comau's joint 2 straight ahead
    from rlff.learn.log import robot_record
    from rlff.robot import ArmMapping, RobotMapping, load_robot

    folder = tmp_path / "mine"
    folder.mkdir()
    one = robot_record(RobotMapping.for_robot(load_robot()))
    arm = robot_record(ArmMapping.for_robot(load_robot(), ("joint_2", "joint_3")))
    _log(folder / "ahead.jsonl", one, {"distance": 1.5, "rim_height": 0.3, "opening": 0.35})
    _log(folder / "side.jsonl", arm, {"distance": 3.0, "rim_height": 0.3, "opening": 0.35, "bearing": 60.0},
         ["joint_3", "joint_2"])
    side = read_learning_log(folder / "side.jsonl")
    assert (side.robot, side.digest, side.joints, side.bearing) == ("comau_smart5_six", arm["digest"],
                                                                    ("joint_2", "joint_3"), 60.0)
    assert read_learning_log(folder / "ahead.jsonl").joints == ("joint_2",)  # the one-joint mapping's

    run, passed, not_reported = chain_run(folder, tmp_path / "run" / "figures")
    assert passed == [] and not_reported == ""
    (section,) = run.sections
    (table,) = section.tables
    assert table.columns[:4] == ["file", "robot", "joints", "bearing"]
    rows = {row[0]: row for row in table.rows}
    assert rows["ahead.jsonl"][1:4] == [f"comau_smart5_six ({one['digest']})", "joint_2", "0°"]
    assert rows["side.jsonl"][1:4] == [f"comau_smart5_six ({arm['digest']})", "joint_2, joint_3", "60°"]
    titles = sorted(figure.title for figure in run.figures)
    assert titles == ["Learning at 1.5 m, comau_smart5_six", "Learning at 3 m, bearing 60°, comau_smart5_six"]


def test_two_robot_files_of_one_name_are_told_apart_by_their_digests(tmp_path):
    from rlff.learn.log import robot_record
    from rlff.robot import RobotMapping, load_robot

    folder = tmp_path / "mine"
    folder.mkdir()
    record = robot_record(RobotMapping.for_robot(load_robot()))
    changed = json.loads(json.dumps(record))
    changed["digest"] = "0123456789abcdef"
    basket = {"distance": 1.5, "rim_height": 0.3, "opening": 0.35}
    _log(folder / "a.jsonl", record, basket)
    _log(folder / "b.jsonl", changed, basket)
    run, _, _ = chain_run(folder, tmp_path / "run" / "figures")
    assert (f"comau_smart5_six threw with joint_2 as 2 robots of that name (0123456789abcdef, {record['digest']})"
            in run.sections[0].text)
    assert len(run.figures) == 2  # one curve per robot: two arms' misses are not one learning curve


@pytest.mark.slow
def test_rlffs_own_outputs_are_reported_or_counted_in_one_line_not_warned_of_each(rlff, tmp_path):
    # a folder of the chain's outputs gave a "passed over ... not an rlff dataset" warning for each
    # generated path, robot trajectory, sim throw outcome and --report JSON: 14 in two folders
    folder = tmp_path / "mine"
    folder.mkdir()
    demos, clean = folder / "demos.csv", folder / "clean.csv"
    assert rlff("data", "synth", "throws", "--subjects", "2", "--throws", "3", "--seed", "3", "-o", str(demos)).code == 0
    assert rlff("data", "preprocess", str(demos), "--preset", "thesis", "-o", str(clean),
                "--report", str(folder / "clean.json")).code == 0
    assert rlff("fit", str(clean), "-o", str(folder / "model.json"), "--max-components", "3").code == 0
    assert rlff("generate", str(folder / "model.json"), "--context", "distance=1.5", "-o", str(folder / "traj.csv")).code == 0
    thrown = rlff("sim", "throw", str(folder / "traj.csv"), "--basket", "1.5", "--json")
    assert thrown.code == 0, thrown.stderr
    (folder / "out.json").write_text(thrown.stdout)
    for kind in ("json", "csv"):
        exported = rlff("robot", "export", str(folder / "traj.csv"), "--format", kind, "-o", str(folder / f"t.{kind}"))
        assert exported.code == 0, exported.stderr
    (folder / "notes.json").write_text('{"what": "my own notes"}')

    result = rlff("report", str(folder), "-o", str(tmp_path / "r.html"))
    assert result.code == 0, result.stderr
    warnings = [line for line in result.stderr.splitlines() if line.startswith("warning:")]
    assert warnings == [f"warning: {folder}: passed over notes.json: not an rlff dataset or model"]  # really unknown
    assert f"{folder}: not reported: 1 generated path (traj.csv), 2 robot trajectories (t.csv, t.json)" in result.stderr
    html = (tmp_path / "r.html").read_text()
    outcome = json.loads(thrown.stdout)
    row = _cells(html, "out.json")
    assert row[:6] == ["out.json", "traj.csv", "comau_smart5_six", "1.5", "0°", "0.3"]  # the rim's height too
    assert row[7] == ("hit" if outcome["hit"] else f"miss {outcome['miss']:+.2f} m")
    cleaning = json.loads((folder / "clean.json").read_text())
    row = _cells(html, "clean.json")
    assert row[2] == f"{cleaning['trajectories']['before']} → {cleaning['trajectories']['after']}"
    assert "not reported" in html  # the report's header says what it left out, too


def test_the_report_of_a_folder_tells_each_file_it_reads_and_each_figure_it_draws(tmp_path):
    # a folder of four lab-sized datasets took 80 s without a word: reading each, drawing each
    from rlff.formats import write_dataset
    from rlff.learn.log import robot_record
    from rlff.model import Model
    from rlff.robot import RobotMapping, load_robot
    from rlff.synthetic.throws import simulate_throws

    folder = tmp_path / "mine"
    folder.mkdir()
    for seed, name in enumerate(("a.csv", "b.csv")):
        write_dataset(simulate_throws(seed, subjects=1, distances=(1.5, 2.0), throws_per_distance=2), folder / name)
    Model.fit(simulate_throws(0, subjects=1, distances=(1.5, 2.0)), inputs=("angle", "distance"), outputs="velocity",
              components="auto", max_components=2, seed=0).save(folder / "model.json")
    _log(folder / "ahead.jsonl", robot_record(RobotMapping.for_robot(load_robot())),
         {"distance": 1.5, "rim_height": 0.3, "opening": 0.35})
    told = []
    run, _, _ = chain_run(folder, tmp_path / "run" / "figures", progress=lambda *said: told.append(said))
    assert len(run.figures) == 4
    assert told == [
        ("reading a.csv", 0, 4), ("reading ahead.jsonl", 1, 4), ("reading b.csv", 2, 4), ("reading model.json", 3, 4),
        ("drawing a.csv: the throws at each distance", 4, 7), ("drawing b.csv: the throws at each distance", 5, 7),
        ("drawing model.json: choosing K", 6, 7),
        ("drawing the learning curves at 1.5 m (1 attempts log)", 7, 8),  # known once the logs' tasks are
        ("done", 8, 8),
    ]


def test_rlff_report_of_a_folder_says_its_progress_on_stderr_and_keeps_stdout_to_the_json(rlff, tmp_path):
    from rlff.formats import write_dataset
    from rlff.synthetic.throws import simulate_throws

    folder = tmp_path / "mine"
    folder.mkdir()
    for seed, name in enumerate(("a.csv", "b.csv")):
        write_dataset(simulate_throws(seed, subjects=1, distances=(1.5, 2.0), throws_per_distance=2), folder / name)
    result = rlff("report", str(folder), "-o", str(tmp_path / "r.html"), "--json")
    assert result.code == 0, result.stderr
    assert json.loads(result.stdout) == {"report": str(tmp_path / "r.html")}
    said = [re.sub(r" \d+:\d\d:\d\d$", "", line) for line in result.stderr.splitlines()
            if re.search(r" \d+/[\d?]+( \(\d+ %\))? \d+:\d\d:\d\d$", line)]
    assert said == [f"report of {folder} 0/?", "reading b.csv 1/2 (50 %)",
                    "drawing a.csv: the throws at each distance 2/4 (50 %)",
                    "drawing b.csv: the throws at each distance 3/4 (75 %)", "done 4/4 (100 %)"], result.stderr
    quiet = rlff("-q", "report", str(folder), "-o", str(tmp_path / "q.html"))
    assert quiet.code == 0 and quiet.stderr == "", quiet.stderr


def test_a_live_runs_log_with_misses_nobody_measured_is_reported(tmp_path):
    # a "miss" typed at the prompt of a live run is logged with "miss": null; the report passed
    # the whole log over ("without float() argument must be ... not 'NoneType'")
    from rlff.learn.log import robot_record
    from rlff.robot import RobotMapping, load_robot

    folder = tmp_path / "live"
    folder.mkdir()
    record = robot_record(RobotMapping.for_robot(load_robot()))
    _log(folder / "ros1.jsonl", record, {"distance": 1.5, "rim_height": 0.3, "opening": 0.35}, misses=(None, 0.0))
    logged = read_learning_log(folder / "ros1.jsonl")
    assert logged.hits == [False, True] and logged.misses[1] == 0.0 and logged.misses[0] != logged.misses[0]
    run, passed, _ = chain_run(folder, tmp_path / "run" / "figures")
    assert passed == [] and [row[0] for row in run.sections[0].tables[0].rows] == ["ros1.jsonl"]


def test_a_folder_s_recordings_are_passed_over_in_one_line_not_a_warning_each(tmp_path):
    # a folder holding the raw recordings beside the demonstrations gave a warning per recording,
    # each listing its 31 columns
    from rlff.formats import write_dataset
    from rlff.synthetic.throws import simulate_throws

    write_dataset(simulate_throws(1, subjects=1, throws_per_distance=1), tmp_path / "demos.csv")
    for name in ("s01.csv", "s02.csv", "s03.csv", "s04.csv"):
        (tmp_path / name).write_text("Time (s),RShoulder.X,RShoulder.Y\n0.0,0.1,0.2\n")
    run, passed, _ = chain_run(tmp_path, tmp_path / "figures")
    assert passed == ["4 CSV files without a 'trajectory' column, not rlff datasets (s01.csv, s02.csv, s03.csv, ...): "
                      "recordings? `rlff data import` turns them into one"]
    assert run.settings["datasets"] == 1


def test_a_dataset_that_starts_with_a_byte_order_mark_is_reported(tmp_path):
    # it was passed over as "1 CSV file without a 'trajectory' column", while preprocess and fit
    # read it
    from rlff.formats import write_dataset
    from rlff.synthetic.throws import simulate_throws

    plain = tmp_path / "plain.csv"
    write_dataset(simulate_throws(1, subjects=1, throws_per_distance=1), plain)
    folder = tmp_path / "run"
    folder.mkdir()
    (folder / "bom.csv").write_bytes(b"\xef\xbb\xbf" + plain.read_bytes())
    run, passed, _ = chain_run(folder, tmp_path / "figures")
    assert passed == [] and run.settings["datasets"] == 1


def test_a_dataset_in_degrees_or_saved_with_semicolons_is_passed_over_saying_so(tmp_path):
    # degrees were drawn as a dataset (angles up to 180) that fit and plot refuse; semicolons were
    # "CSV files without a 'trajectory' column ... recordings? rlff data import turns them into one"
    import pandas as pd

    from rlff.formats import write_dataset
    from rlff.synthetic.throws import simulate_throws

    plain = tmp_path / "plain.csv"
    write_dataset(simulate_throws(1, subjects=1, throws_per_distance=1), plain)
    folder = tmp_path / "run"
    folder.mkdir()
    frame = pd.read_csv(plain)
    frame[["angle", "velocity"]] = np.degrees(frame[["angle", "velocity"]])
    frame.to_csv(folder / "degrees.csv", index=False)
    pd.read_csv(plain).to_csv(folder / "semicolons.csv", index=False, sep=";")
    (folder / "demos.csv").write_bytes(plain.read_bytes())
    run, passed, _ = chain_run(folder, tmp_path / "figures")
    assert run.settings["datasets"] == 1
    assert len(passed) == 2, passed
    assert passed[0].startswith("degrees.csv: column 'angle' reaches") and "degrees?" in passed[0]
    assert passed[1].startswith("semicolons.csv: ") and "the file looks separated by ';'" in passed[1]


def test_a_log_of_another_rim_arm_or_stop_rule_says_so_and_keeps_to_its_own_task(rlff, tmp_path):
    # a 1 m rim run and an arm at 90 % speed looked like default runs, and were drawn in one
    # figure with them; logs were listed by file name, 1m after 1.75m
    from rlff.learn.log import robot_record
    from rlff.robot import RobotMapping, load_robot

    folder = tmp_path / "mine"
    folder.mkdir()
    record = robot_record(RobotMapping.for_robot(load_robot()))
    basket = {"distance": 1.75, "rim_height": 0.3, "opening": 0.35}
    _log(folder / "1.75m.jsonl", record, basket)
    _log(folder / "1.75m-rim1.jsonl", record, {**basket, "rim_height": 1.0})
    _log(folder / "1.75m-slow.jsonl", record, basket, gap="speed:0.9")
    _log(folder / "1.75m-centred.jsonl", record, basket, until="centred")
    _log(folder / "1m.jsonl", record, {**basket, "distance": 1.0})
    run, passed, _ = chain_run(folder, tmp_path / "run" / "figures")
    assert passed == []
    (table,) = run.sections[0].tables
    assert table.columns[:10] == ["file", "robot", "joints", "bearing", "rim (m)", "method", "feedback", "arm gap", "until",
                                  "basket (m)"]
    rows = [[row[0], *row[4:10]] for row in table.rows]
    assert rows == [["1m.jsonl", 0.3, "calibrate", "binary", "none", "hit", 1.0],
                    ["1.75m-centred.jsonl", 0.3, "calibrate", "binary", "none", "centred", 1.75],
                    ["1.75m-rim1.jsonl", 1.0, "calibrate", "binary", "none", "hit", 1.75],
                    ["1.75m-slow.jsonl", 0.3, "calibrate", "binary", "speed:0.9", "hit", 1.75],
                    ["1.75m.jsonl", 0.3, "calibrate", "binary", "none", "hit", 1.75]]
    # the 1 m rim is a task of its own; the arm's gap and the stop rule name their curves
    assert [figure.title for figure in run.figures] == ["Learning at 1 m, comau_smart5_six",
                                                        "Learning at 1.75 m, comau_smart5_six",
                                                        "Learning at 1.75 m, rim 1 m, comau_smart5_six"]
    svg = (tmp_path / "run" / "figures" / Path(run.figures[1].file).name).with_suffix(".svg").read_text()
    for name in ("calibrate, until centred (2 attempts)", "calibrate, arm speed:0.9 (2 attempts)",
                 "calibrate (2 attempts)"):
        assert f">{name}</text>" in svg

    # the summary on stderr names what the folder holds, not the kinds it does not
    alone = tmp_path / "alone"
    alone.mkdir()
    _log(alone / "1m.jsonl", record, {**basket, "distance": 1.0})
    result = rlff("report", str(alone), "-o", str(tmp_path / "alone.html"))
    assert result.code == 0, result.stderr
    assert f"{alone}: no run.json: a report of its 1 attempts log\n" in result.stderr


def test_a_learning_benchmark_is_reported_with_its_rows(tmp_path):
    # a bench.json of `rlff bench learning --json` was passed over as "not an rlff dataset or model"
    row = {"method": "calibrate", "feedback": "binary", "scenario": "short", "landings": "none", "baseline": False,
           "median": 2.0, "mean": 3.0, "hits": 4, "runs": 4, "budget": 10}
    never = {**row, "method": "imitation", "baseline": True, "median": 11.0, "mean": 11.0, "hits": 0}
    (tmp_path / "bench.json").write_text(json.dumps({
        "robot": {"name": "comau_smart5_six", "file": None, "digest": "28eb07a30a541d82"}, "rows": [row, never],
        "comparisons": [{"method": "calibrate", "baseline": "imitation", "feedback": "binary", "scenario": "short",
                         "landings": "none", "p_value": 0.125, "mean_method": 3.0, "mean_baseline": 11.0, "pairs": 4}]}))
    run, passed, _ = chain_run(tmp_path, tmp_path / "run" / "figures")
    assert passed == [] and run.settings["learning benchmarks"] == 1
    (section,) = run.sections
    (table,) = section.tables
    assert table.rows == [["bench.json", "comau_smart5_six", "short", "none", "binary", "calibrate", False, 2.0, 3.0,
                           "4 of 4", 10],
                          ["bench.json", "comau_smart5_six", "short", "none", "binary", "imitation", True, "> 10", 11.0,
                           "0 of 4", 10]]


def _one_joint_record() -> dict:
    from rlff.learn.log import robot_record
    from rlff.robot import RobotMapping, load_robot

    return robot_record(RobotMapping.for_robot(load_robot()))


BASKET = {"distance": 1.3, "rim_height": 0.3, "opening": 0.35}


def test_a_log_cut_mid_line_is_said_to_be_one_not_tabled_as_a_run_that_never_hit(tmp_path):
    # a log cut after attempt 1 of a 12-attempt run read "no hit in 1", as a finished run, and
    # nothing said its last line was cut
    folder = tmp_path / "rep"
    folder.mkdir()
    cut = _log(folder / "interrupted.jsonl", _one_joint_record(), BASKET, misses=(0.69,))
    cut.write_text(cut.read_text() + '{"attempt": 2, "target": 1.')  # killed while writing attempt 2
    _log(folder / "whole.jsonl", _one_joint_record(), {**BASKET, "distance": 1.5}, misses=(0.69, 0.4))
    run, passed, _ = chain_run(folder, tmp_path / "run" / "figures")
    assert passed == []
    (section,) = run.sections
    rows = {row[0]: row for row in section.tables[0].rows}
    assert rows["interrupted.jsonl"][10:12] == [1, "stopped after 1, no hit (log cut)"]
    assert rows["whole.jsonl"][10:12] == [2, "no hit in 2"]
    assert ("interrupted.jsonl ends in a line cut short: its run was killed while writing attempt 2, which is lost, so "
            "the log stops short of the run's budget (2 attempts or more) without a hit; `rlff learn` with the run's "
            "options and --log interrupted.jsonl resumes it.") in section.text
    assert "whole.jsonl ends" not in section.text


def test_a_log_without_a_hit_says_whether_its_run_used_its_budget(tmp_path):
    # the header recorded no budget: a run that spent it and one stopped after 1 of 12 read alike,
    # "no hit in N", and a cut log "stopped after 1, no hit (log cut)"
    folder = tmp_path / "rep"
    folder.mkdir()
    record = _one_joint_record()
    _log(folder / "spent.jsonl", record, BASKET, misses=(0.69, 0.4), budget=2)
    _log(folder / "stopped.jsonl", record, {**BASKET, "distance": 1.4}, misses=(0.69,), budget=12)
    cut = _log(folder / "cut.jsonl", record, {**BASKET, "distance": 1.5}, misses=(0.69,), budget=12)
    cut.write_text(cut.read_text() + '{"attempt": 2, "target": 1.')  # killed while writing attempt 2
    _log(folder / "older.jsonl", record, {**BASKET, "distance": 1.6}, misses=(0.69, 0.4))  # no budget recorded
    run, passed, _ = chain_run(folder, tmp_path / "run" / "figures")
    assert passed == []
    (section,) = run.sections
    rows = {row[0]: row[10:12] for row in section.tables[0].rows}
    assert rows == {"spent.jsonl": [2, "used its budget of 2, no hit"],
                    "stopped.jsonl": [1, "stopped after 1 of 12, no hit"],
                    "cut.jsonl": [1, "stopped after 1 of 12, no hit (log cut)"],
                    "older.jsonl": [2, "no hit in 2"]}
    assert ("cut.jsonl ends in a line cut short: its run was killed while writing attempt 2, which is lost, so the "
            "log stops short of the run's budget of 12 without a hit;") in section.text


def test_copies_of_one_log_are_named_together_and_drawn_once(tmp_path):
    # nine copies of one log were drawn as nine identical curves, with nothing saying so
    folder = tmp_path / "lab"
    folder.mkdir()
    first = _log(folder / "full.jsonl", _one_joint_record(), BASKET, misses=(0.3, 0.01))
    for name in ("k9.jsonl", "m_INT1.jsonl"):
        (folder / name).write_bytes(first.read_bytes())
    # the same seed run again: the same throws, another wall time
    lines = first.read_text().splitlines()
    lines[1] = json.dumps({**json.loads(lines[1]), "seconds": 2.5})
    (folder / "rerun.jsonl").write_text("\n".join(lines) + "\n")
    _log(folder / "other.jsonl", _one_joint_record(), BASKET, misses=(0.2, 0.05))  # another run of that task
    run, passed, _ = chain_run(folder, tmp_path / "run" / "figures")
    assert passed == []
    (section,) = run.sections
    assert len(section.tables[0].rows) == 5  # every log has its row
    assert ("full.jsonl, k9.jsonl, m_INT1.jsonl and rerun.jsonl hold one run (the same header and the same throws, "
            "attempt for attempt, their timings aside: copies of one log, or its seed run again): drawn once, as "
            "full.jsonl.") in section.text
    assert "other.jsonl" not in section.text
    (figure,) = run.figures
    assert figure.caption.endswith(" full.jsonl stands for the 4 logs of its run.")
    svg = (tmp_path / "run" / "figures" / Path(figure.file).name).with_suffix(".svg").read_text()
    curves = re.findall(r">(calibrate[^<]*)</text>", svg)
    assert curves == ["calibrate (full.jsonl) (2 attempts)", "calibrate (other.jsonl) (2 attempts)"]  # not five


def test_a_stray_temporary_file_of_a_killed_write_is_named_as_one_safe_to_delete(tmp_path):
    # it was warned of as "not JSON (a damaged or cut-short file?)"; one of a dataset whose write
    # was killed at its last byte was even tabled as a dataset of its own
    from rlff.formats import write_dataset
    from rlff.synthetic.throws import simulate_throws

    write_dataset(simulate_throws(1, subjects=1, throws_per_distance=1), tmp_path / "demos.csv")
    (tmp_path / ".demos.k2j4h1x0.tmp.csv").write_bytes((tmp_path / "demos.csv").read_bytes())
    (tmp_path / ".model.x1y2.tmp.json").write_text('{"format": "rlff-model", "version": 1, "columns": ["an')
    run, passed, _ = chain_run(tmp_path, tmp_path / "figures")
    assert passed == ["2 stray temporary files (.demos.k2j4h1x0.tmp.csv, .model.x1y2.tmp.json) of writes that were "
                      "killed (rlff writes an output such as demos.csv to one, then renames it into place, so the "
                      "output itself is whole or as it was): safe to delete"]
    assert run.settings["datasets"] == 1
    (tmp_path / ".demos.k2j4h1x0.tmp.csv").unlink()
    _, passed, _ = chain_run(tmp_path, tmp_path / "figures")
    assert passed == [".model.x1y2.tmp.json: a stray temporary file of a write that was killed (rlff writes an output "
                      "such as model.json to one, then renames it into place, so the output itself is whole or as it "
                      "was): safe to delete"]


@pytest.mark.slow
def test_a_run_until_centred_is_judged_by_its_centred_hit_not_its_first_hit(tmp_path):
    # a run --until centred killed at attempt 1101 without a centred hit was tabled "hit at
    # attempt 1", and one centred at attempt 23 "hit at attempt 13": the first hit, which did not
    # stop either run
    from rlff.learn import learn
    from rlff.preprocess import Pipeline
    from rlff.synthetic.throws import simulate_throws

    raw = simulate_throws(3, subjects=3, distances=(1.0, 1.25, 1.5), throws_per_distance=2, all_short=True)
    demos, _ = Pipeline.preset("thesis").run(raw)
    folder = tmp_path / "lab"
    folder.mkdir()
    options = {"feedback": "binary", "update": "calibrate", "seed": 0, "until": "centred", "centre_share": 0.25}
    centred = learn(demos, 1.4, budget=20, log_path=folder / "centred.jsonl", **options)
    short = learn(demos, 1.4, budget=9, log_path=folder / "short.jsonl", **options)
    first_hit = next(a.index for a in centred.history if a.hit)
    # the run this test needs: a hit outside the centre window before the centred one, within 9
    assert centred.centred and first_hit < 9 < len(centred.history), [(a.hit, a.miss) for a in centred.history]
    assert not short.centred and len(short.history) == 9
    run, passed, _ = chain_run(folder, tmp_path / "run" / "figures")
    assert passed == []
    (section,) = run.sections
    rows = {row[0]: row[10:12] for row in section.tables[0].rows}
    attempts = len(centred.history)
    assert rows == {"centred.jsonl": [attempts, f"centred hit at attempt {attempts} (first hit at {first_hit})"],
                    "short.jsonl": [9, f"used its budget of 9, no centred hit (first hit at {first_hit})"]}

    # killed while writing attempt 10 of 20: stopped short of its budget, and said to be
    cut = folder / "short.jsonl"
    lines = (folder / "centred.jsonl").read_text().splitlines(keepends=True)
    cut.write_text("".join(lines[:10]) + lines[10][:20])
    run, passed, _ = chain_run(folder, tmp_path / "run" / "figures")
    (section,) = run.sections
    rows = {row[0]: row[10:12] for row in section.tables[0].rows}
    assert rows["short.jsonl"] == [9, f"stopped after 9 of 20, no centred hit (log cut) (first hit at {first_hit})"]
    assert ("short.jsonl ends in a line cut short: its run was killed while writing attempt 10, which is lost, so the "
            "log stops short of the run's budget of 20 without a centred hit;") in section.text


def test_a_centred_run_whose_centre_share_is_no_number_is_passed_over_not_a_crash(tmp_path):
    # the log was kept for the table before its centre share was refused, and the report ended
    # in "rlff: internal error: KeyError"
    folder = tmp_path / "lab"
    folder.mkdir()
    _log(folder / "good.jsonl", {"name": "comau"}, BASKET)
    _log(folder / "edited.jsonl", {"name": "comau"}, BASKET, until="centred", centre_share="half")
    run, passed, _ = chain_run(folder, tmp_path / "run" / "figures")
    assert passed == ["edited.jsonl: the run until='centred' has a centre_share 'half' in its header: it must be a "
                      "number (a share of the half-opening); is the log edited?"]
    (section,) = run.sections
    assert [row[0] for row in section.tables[0].rows] == ["good.jsonl"]
