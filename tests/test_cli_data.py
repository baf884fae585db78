"""``rlff data synth throws`` and ``rlff data preprocess`` through the real command line."""

from __future__ import annotations

import json

import numpy as np
import pytest

from rlff.cli import main
from rlff.formats import read_dataset


@pytest.mark.integration
def test_synth_throws_then_preprocess_with_the_thesis_preset(cli, tmp_path):
    demos = tmp_path / "demos.csv"
    made = cli("data", "synth", "throws", "-o", str(demos), "--seed", "3", "--subjects", "3",
               "--inconsistent-distance", "2.75", "--json")
    assert made.code == 0, made.stderr
    summary = json.loads(made.stdout)
    dataset = read_dataset(demos)
    assert summary["trajectories"] == len(dataset) == 3 * 10 * 4
    assert summary["hits"] == sum(t.meta["hit"] for t in dataset)

    clean, report = tmp_path / "clean.parquet", tmp_path / "report.json"
    result = cli("data", "preprocess", str(demos), "--preset", "thesis", "-o", str(clean), "--report", str(report))
    assert result.code == 0, result.stderr
    assert "reject_contexts" in result.stdout and "spike_filter" in result.stdout
    assert "context distance=2.75 rejected" in result.stderr
    written = json.loads(report.read_text())
    assert written["trajectories"]["after"] == len(read_dataset(clean))
    assert [s["step"] for s in written["steps"]][0] == "spike_filter"
    (rejected,) = [c for s in written["steps"] for c in s["contexts"]]
    assert rejected["context"] == {"distance": 2.75}
    assert "balance kept at most 10 throws per basket" in result.stderr  # of the 12 thrown at each


def test_preprocess_says_how_to_keep_more_throws_than_balance_keeps(capsys, tmp_path):
    # 93 % of a long recording went in balance, and nothing said how to keep them
    demos = tmp_path / "demos.npz"
    assert main(["data", "synth", "throws", "-o", str(demos), "--subjects", "1", "--throws", "4"]) == 0
    config = tmp_path / "steps.toml"
    config.write_text('[[step]]\nname = "balance"\nmax_per_context = 3\n')
    capsys.readouterr()
    assert main(["data", "preprocess", str(demos), "--config", str(config), "-o", str(tmp_path / "c.csv")]) == 0
    assert ("balance kept at most 3 throws per basket: to keep more, raise its max_per_context in a copy of the "
            "pipeline") in capsys.readouterr().err


# the cases below run the same entry point in-process (``rlff.cli.main``), to spare start-ups


def test_preprocess_json_and_config(capsys, tmp_path):
    demos = tmp_path / "demos.npz"
    assert main(["data", "synth", "throws", "-o", str(demos), "--subjects", "1", "--throws", "2"]) == 0
    config = tmp_path / "steps.toml"
    config.write_text('[[step]]\nname = "crop"\n\n[[step]]\nname = "min_points"\nmin_points = 4\n')
    capsys.readouterr()
    code = main(["data", "preprocess", str(demos), "--config", str(config), "-o", str(tmp_path / "c.csv"), "--json"])
    assert code == 0
    payload = json.loads(capsys.readouterr().out)
    assert [s["step"] for s in payload["steps"]] == ["crop", "min_points"]
    assert payload["pipeline"] == str(config)


def test_fit_and_preprocess_warn_of_throws_given_twice(rlff, tmp_path):
    # a file holding every throw twice under other ids: K grew with nothing pointing at the copies;
    # and a copy labelled with another basket went unseen
    from rlff.formats import write_dataset

    demos = tmp_path / "demos.csv"
    assert rlff("data", "synth", "throws", "-o", str(demos), "--subjects", "1", "--throws", "2").code == 0
    dataset = read_dataset(demos)
    doubled = tmp_path / "doubled.csv"
    copies = [t.replace(id=f"{t.id}_copy") for t in dataset]
    copies[0] = copies[0].with_columns(distance=copies[0]["distance"] + 0.5)
    write_dataset(dataset.replace([*dataset, *copies]), doubled)
    first = f"(the first: {dataset.ids[0]} and {dataset.ids[0]}_copy)"
    for args in (["fit", str(doubled), "-k", "1"], ["data", "preprocess", str(doubled)]):
        result = rlff(*args, "-o", str(tmp_path / "out.csv" if args[0] == "data" else tmp_path / "m.json"))
        assert result.code == 0, result.stderr
        assert (f"warning: {doubled}: {len(dataset)} throws repeat another sample for sample, distance aside {first}"
                in result.stderr)
    quiet = rlff("fit", str(demos), "-k", "1", "-o", str(tmp_path / "m.json"))
    assert "sample for sample" not in quiet.stderr


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--config", "{config}"], "step 1: unknown step 'smooth'"),
        (["--preset", "paper"], "unknown preset 'paper'"),
        (["--preset", "thesis", "--config", "{config}"], "either --preset or --config"),
    ],
)
def test_preprocess_bad_input_is_one_line_and_exit_2(capsys, tmp_path, args, message):
    demos = tmp_path / "demos.csv"
    demos.write_text("trajectory,angle,distance,velocity\na,0.1,2,0\na,0.2,2,1\n")
    config = tmp_path / "steps.toml"
    config.write_text('[[step]]\nname = "smooth"\n')
    args = [a.format(config=config) for a in args]
    assert main(["data", "preprocess", str(demos), *args, "-o", str(tmp_path / "c.csv")]) == 2
    stderr = capsys.readouterr().err
    assert message in stderr
    assert len(stderr.strip().splitlines()) == 1


def test_preprocess_of_data_without_a_distance_is_refused_before_its_progress(capsys, tmp_path):
    # the thesis preset ran eight steps, then said "step 'reject_contexts': reject_contexts: 'distance'
    # is not a context column"
    demos = tmp_path / "demos.csv"
    demos.write_text("trajectory,angle,Distance,velocity\na,0.1,2,0\na,0.2,2,1\n")
    assert main(["data", "preprocess", str(demos), "--preset", "thesis", "-o", str(tmp_path / "c.csv")]) == 2
    stderr = capsys.readouterr().err
    assert stderr.startswith("rlff: error: preset 'thesis', step 'reject_contexts' judges the throws by their "
                             "'distance' (the basket distance each throw aimed at, m), a context column the data "
                             "lacks (columns: angle, Distance, velocity; context: none)"), stderr
    assert len(stderr.strip().splitlines()) == 1


@pytest.mark.parametrize("header", ["trajectory,time,angle,distance,velocity", "trajectory,angle,distance,velocity"])
def test_a_csv_named_parquet_is_one_line_and_exit_2(capsys, tmp_path, header):
    # four names are no MSR recording's row of four numbers (it was taken for one)
    demos = tmp_path / "demos.parquet"
    rows = "a,0,0.1,2,0\na,0.1,0.2,2,1\n" if header.count(",") == 4 else "a,0.1,2,0\na,0.2,2,1\n"
    demos.write_text(f"{header}\n{rows}")
    assert main(["data", "preprocess", str(demos), "--preset", "thesis", "-o", str(tmp_path / "c.csv")]) == 2
    stderr = capsys.readouterr().err
    assert stderr.startswith(f"rlff: error: {demos} is text (its first line: '{header}'), "
                             "not a Parquet file: rlff reads a dataset by its suffix")
    assert len(stderr.strip().splitlines()) == 1


def test_preprocess_that_removes_every_throw_writes_nothing_and_names_the_step(capsys, tmp_path):
    demos, clean = tmp_path / "demos.csv", tmp_path / "c.csv"
    demos.write_text("trajectory,angle,distance,velocity\na,1,2,3\na,2,2,3\nb,1,2.5,4\nb,2,2.5,5\n")
    assert main(["data", "preprocess", str(demos), "-o", str(clean)]) == 2
    assert (
        f"rlff: error: step 'min_points' removed the last throw (b: 2 samples, fewer than 4): no throw "
        f"left, {clean} not written"
    ) in capsys.readouterr().err
    assert not clean.exists()


@pytest.mark.parametrize(
    ("text", "message"),
    [("", "no step"), ('description = "x"\n', "no step"),
     ('[[step]]\nname = "crop"\nenabled = false\n', "no enabled step")],
)
@pytest.mark.parametrize("command", [["data", "preprocess"], ["plot", "preprocess"]])
def test_a_pipeline_file_without_a_step_is_refused(capsys, tmp_path, command, text, message):
    demos, config, out = tmp_path / "demos.csv", tmp_path / "steps.toml", tmp_path / "out.csv"
    demos.write_text("trajectory,angle,distance,velocity\na,0.1,2,0\na,0.2,2,1\n")
    config.write_text(text)
    assert main([*command, str(demos), "--config", str(config), "-o", str(out)]) == 2
    assert f"rlff: error: {config}: {message}: a pipeline needs at least one [[step]]" in capsys.readouterr().err
    assert set(tmp_path.iterdir()) == {demos, config}


def test_preprocess_names_the_bad_line_of_the_input(capsys, tmp_path):
    demos = tmp_path / "demos.csv"
    demos.write_text("trajectory,angle,distance,velocity\na,0.1,2,0\na,oops,2,1\n")
    assert main(["data", "preprocess", str(demos), "-o", str(tmp_path / "c.csv")]) == 2
    assert f"{demos}, line 3: column 'angle'" in capsys.readouterr().err


def test_synth_throws_rejects_a_bad_rate(capsys, tmp_path):
    assert main(["data", "synth", "throws", "-o", str(tmp_path / "d.csv"), "--rate", "60"]) == 2
    assert "15 to 30 Hz" in capsys.readouterr().err


@pytest.mark.parametrize(
    ("args", "message"),
    [
        # 400 throws of 2 samples each
        (["--dropped-frames", "nan"], "--dropped-frames nan: a probability per frame, from 0 to below 0.5"),
        (["--glitches", "nan"], "--glitches nan: a probability per frame"),
        # taken, and nan blamed a trajectory's angle without naming the option
        (["--noise", "1e9"], "--noise 1e+09: the angle noise is a standard deviation in rad, from 0 to 0.5"),
        (["--noise", "nan"], "--noise nan: the angle noise is a standard deviation in rad"),
        (["--rate", "nan"], "--rate nan: a depth camera records at 15 to 30 Hz"),
        (["--distances", "1,nan"], "--distances: nan is not a number"),
        (["--distances", "1,1"], "--distances: 1 m is given twice; give each once"),  # duplicate trajectory id
        # silently ignored
        (["--inconsistent-distance", "9"], "--inconsistent-distance 9 m is not among --distances (1, 1.5, 2, 2.25"),
        (["--whole-arm", "--bearings", "0,0"], "--bearings: 0 deg is given twice"),
        (["--whole-arm", "--heights", "0.3,1,0.3"], "--heights: 0.3 m is given twice"),
    ],
)
def test_synth_throws_options_are_checked_by_name(capsys, tmp_path, args, message):
    assert main(["data", "synth", "throws", "-o", str(tmp_path / "d.csv"), *args]) == 2
    stderr = capsys.readouterr().err
    assert message in stderr and len(stderr.strip().splitlines()) == 1, stderr
    assert not (tmp_path / "d.csv").exists()


def test_synth_whole_arm_throws_preprocess_and_fit(rlff, tmp_path):
    demos, clean, model = tmp_path / "demos.csv", tmp_path / "clean.csv", tmp_path / "model.json"
    made = rlff("data", "synth", "throws", "--whole-arm", "--joints", "shoulder,elbow,wrist", "--subjects", "3",
                "--distances", "1,2,3,4", "--bearings", "0,90", "--heights", "0.3,1", "--seed", "4",
                "-o", str(demos), "--json")
    assert made.code == 0, made.stderr
    summary = json.loads(made.stdout)
    assert summary["trajectories"] == 3 * 4 * 2 * 2
    assert summary["columns"] == ["time", "angle", "velocity", "shoulder", "shoulder_velocity", "wrist",
                                  "wrist_velocity", "distance", "bearing", "height"]
    result = rlff("data", "preprocess", str(demos), "--preset", "thesis", "-o", str(clean), "--json")
    assert result.code == 0, result.stderr
    report = json.loads(result.stdout)
    (spikes,) = [s for s in report["steps"] if s["step"] == "spike_filter"]
    assert "velocity, shoulder_velocity, wrist_velocity recomputed from angle, shoulder, wrist" in " ".join(spikes["notes"])
    cleaned = read_dataset(clean)
    assert cleaned.context == ("distance", "bearing", "height") and len(cleaned) > 30
    raised = []
    for trajectory in cleaned:
        # densified on the elbow's angle like every other column: a throw up to its release
        assert np.all(np.diff(trajectory["angle"]) > 0)
        shoulder = trajectory["shoulder"]
        assert np.all((shoulder > 1.0) & (shoulder < np.pi)) and shoulder[-1] > np.pi / 2
        assert np.all((trajectory["wrist"] > 1.8) & (trajectory["wrist"] <= np.pi + 0.3))
        raised.append(shoulder[-1] - shoulder[0])
    assert np.median(raised) > 0.3, "the upper arm rises through the extension"
    fitted = rlff("fit", str(clean), "-o", str(model), "--inputs", "angle,distance,height",
                  "--outputs", "velocity,shoulder,shoulder_velocity,wrist,wrist_velocity", "--components", "3")
    assert fitted.code == 0, fitted.stderr
    saved = json.loads(model.read_text())
    assert saved["outputs"] == ["velocity", "shoulder", "shoulder_velocity", "wrist", "wrist_velocity"]


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--heights", "1"], "--heights: only with --whole-arm"),
        (["--joints", "shoulder,elbow"], "--joints: only with --whole-arm"),
        (["--whole-arm", "--inconsistent-distance", "2.75"], "only for one-joint throws"),
        (["--whole-arm", "--joints", "shoulder,wrist"], "the elbow must throw"),
        (["--whole-arm", "--bearings", "0,east"], "--bearings: '0,east' is not a comma-separated list"),
    ],
)
def test_synth_whole_arm_bad_options_are_one_line_and_exit_2(capsys, tmp_path, args, message):
    assert main(["data", "synth", "throws", "-o", str(tmp_path / "d.csv"), *args]) == 2
    stderr = capsys.readouterr().err
    assert message in stderr and len(stderr.strip().splitlines()) == 1


def test_a_thesis_matrix_output_that_cannot_hold_the_data_is_refused_before_any_work(rlff, tmp_path, monkeypatch):
    # --help offered .txt, and every dataset with a time column failed at the write, preprocess
    # after running its whole pipeline
    from rlff.capture import importer
    from rlff.preprocess import Pipeline
    from rlff.synthetic import throws

    def work(*args, **kwargs):
        raise AssertionError("the work ran before the output was checked")

    demos = tmp_path / "demos.csv"
    assert rlff("data", "synth", "throws", "-o", str(demos), "--subjects", "1", "--distances", "2").code == 0
    monkeypatch.setattr(throws, "simulate_throws", work)
    monkeypatch.setattr(Pipeline, "run", work)
    monkeypatch.setattr(importer, "read_recording", work)
    msr = tmp_path / "a06_s01_e01_skeleton3D.txt"
    msr.write_text("".join(f"0.{j} 0.2 2.5 1\n" for j in range(40)))
    refusals = [
        (("data", "synth", "throws"), "the simulated throws"),
        (("data", "preprocess", str(demos)), str(demos)),
        (("data", "import", str(msr), "--joints", "elbow"), "the imported throws"),
    ]
    for command, what in refusals:
        out = tmp_path / "out.txt"
        result = rlff(*command, "-o", str(out))
        assert result.code == 2, command
        assert result.stderr.strip().splitlines()[-1] == (
            f"rlff: error: {out}: .txt is the thesis matrix, which holds only angle, distance, velocity (a text row "
            f"each per trajectory), not the column time of {what}: write .csv, .npz or .parquet to keep them")
        assert not out.exists()


def test_a_thesis_matrix_goes_through_synth_preprocess_and_import_as_a_thesis_matrix(rlff, tmp_path):
    matrix = tmp_path / "thesis.txt"
    assert rlff("data", "synth", "thesis", "-o", str(matrix)).code == 0
    imported = tmp_path / "imported.txt"
    result = rlff("data", "import", str(matrix), "-o", str(imported))
    assert result.code == 0, result.stderr
    assert read_dataset(imported).equals(read_dataset(matrix))
    clean = tmp_path / "clean.txt"
    result = rlff("data", "preprocess", str(matrix), "-o", str(clean))
    assert result.code == 0, result.stderr
    assert read_dataset(clean).columns == ("angle", "distance", "velocity")


def test_preprocess_refuses_a_velocity_in_degrees_per_second(rlff, tmp_path):
    # the recording went through the thesis preset into a clean file of deg/s, fitted without a word
    import pandas as pd

    demos, data = tmp_path / "demos.csv", tmp_path / "deg.csv"
    assert rlff("data", "synth", "throws", "-o", str(demos), "--subjects", "1", "--throws", "2").code == 0
    frame = pd.read_csv(demos)
    frame["velocity"] *= 180 / np.pi
    frame.to_csv(data, index=False)
    result = rlff("data", "preprocess", str(data), "--preset", "thesis", "-o", str(tmp_path / "clean.csv"))
    assert result.code == 2
    assert result.stderr.startswith(f"rlff: error: {data}: column 'velocity' integrates over the throws' time column "
                                    "to a median 50.4 times their angle's change (along the throw, back and forth)"), result.stderr
    assert len(result.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "clean.csv").exists()
