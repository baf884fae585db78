"""``rlff report FOLDER`` of one's own chain: what it shows of the attempts logs (the robot, the
joints and the bearing their runs threw with) and how it treats rlff's other outputs."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from rlff.chain_report import chain_run
from rlff.plots.learning import read_learning_log


def _log(path: Path, record: dict, basket: dict, joints: list[str] | None = None, misses=(-0.3, 0.01)) -> Path:
    """An attempts log whose header holds ``record`` (:func:`rlff.learn.log.robot_record`)."""
    run = {"basket": basket, "feedback": "binary", "update": "calibrate", "seed": 0, "robot": record,
           "pedestal": 0.0, "until": "hit"}
    if joints is not None:
        run["joints"] = joints
    lines = [{"format": "rlff-attempts", "version": 1, "run": run}]
    lines += [{"attempt": i + 1, "miss": m, "hit": m is not None and abs(m) < 0.1} for i, m in enumerate(misses)]
    path.write_text("".join(json.dumps(line) + "\n" for line in lines))
    return path


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
    assert row[:5] == ["out.json", "traj.csv", "comau_smart5_six", "1.5", "0°"]
    assert row[6] == ("hit" if outcome["hit"] else f"miss {outcome['miss']:+.2f} m")
    cleaning = json.loads((folder / "clean.json").read_text())
    row = _cells(html, "clean.json")
    assert row[2] == f"{cleaning['trajectories']['before']} → {cleaning['trajectories']['after']}"
    assert "not reported" in html  # the report's header says what it left out, too


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
