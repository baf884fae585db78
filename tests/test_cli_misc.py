"""``rlff plot``, ``rlff report`` and ``rlff demo`` through the real entry point (a subprocess):
what they write on success, and a one-line reason with exit code 2 on bad input."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import typer

from attempts_logs import write_attempts_log
from rlff.dataset import Dataset, Trajectory, write_csv
from rlff.report import FigureEntry, Run, Section, write_run

pytestmark = pytest.mark.slow


def one_line_error(result, *fragments: str) -> str:
    """The single error line of a failed command; checks exit code 2 and no traceback."""
    assert result.code == 2, (result.code, result.stdout, result.stderr)
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith("rlff: error: ")
    assert "Traceback" not in result.stderr
    for fragment in fragments:
        assert fragment in lines[0]
    return lines[0]


def error_after_progress(result, *fragments: str) -> str:
    """The error line of a failed command that had started its work: its progress lines (the
    work's start, each file read) may come first, then the one-line reason, exit code 2."""
    assert result.code == 2, (result.code, result.stdout, result.stderr)
    *before, last = result.stderr.strip().splitlines()
    assert all(line.startswith(("report of ", "reading ")) for line in before), result.stderr
    assert last.startswith("rlff: error: ") and "Traceback" not in result.stderr
    for fragment in fragments:
        assert fragment in last
    return last


def written(result) -> list[Path]:
    assert result.code == 0, result.stderr
    return [Path(p) for p in json.loads(result.stdout)["files"]]


@pytest.fixture
def throws_csv(tmp_path) -> Path:
    trajectories = []
    for distance in (1.5, 2.5, 3.5):
        for index in range(4):
            angle = np.linspace(0.3, 1.6, 20)
            velocity = (2.0 + distance + 0.1 * index) * np.sin(np.pi * (angle - 0.3) / 1.3)
            trajectories.append(
                Trajectory(f"z{distance}-{index}",
                           {"angle": angle, "distance": np.full(20, distance), "velocity": velocity},
                           {"hit": index == 1})
            )
    path = tmp_path / "throws.csv"
    write_csv(Dataset(trajectories), path)
    return path


# -- rlff report --------------------------------------------------------------------------------


def test_report_builds_html_from_a_run(cli, tmp_path):
    run_dir = tmp_path / "run"
    (run_dir / "figures").mkdir(parents=True)
    # a 1x1 PNG is enough for the builder; the figures themselves are tested elsewhere
    (run_dir / "figures" / "dot.png").write_bytes(
        bytes.fromhex("89504e470d0a1a0a0000000d49484452000000010000000108060000001f15c4890000000d"
                      "4944415478da63f8cfc0f01f0005000201a5f5d2c80000000049454e44ae426082")
    )
    write_run(Run("cli run", "2026-01-01T00:00:00+00:00", sections=[Section("a", "Alpha", facts={"n": 1})],
                  figures=[FigureEntry("figures/dot.png", "a", "Dot")]), run_dir)
    result = cli("report", str(run_dir), "--json")
    assert result.code == 0, result.stderr
    out = Path(json.loads(result.stdout)["report"])
    assert out == run_dir / "report.html"
    text = out.read_text()
    assert "<h2>Alpha</h2>" in text and "data:image/png;base64," in text

    result = cli("report", str(run_dir), "-o", str(tmp_path / "elsewhere" / "r.html"))
    assert result.code == 0 and (tmp_path / "elsewhere" / "r.html").is_file()
    assert "r.html" in result.stdout


def test_report_bad_input(rlff, tmp_path):
    one_line_error(rlff("report", str(tmp_path / "absent")), "absent: no such run directory")
    debug = rlff("--debug", "report", str(tmp_path / "absent"))  # --debug adds the traceback
    assert debug.code == 2 and "Traceback" in debug.stderr and "no such run directory" in debug.stderr
    verbose = rlff("-v", "report", str(tmp_path / "absent"))  # -v does not
    assert verbose.code == 2 and "Traceback" not in verbose.stderr
    one_line_error(rlff("report", str(tmp_path)), "no run.json, and no rlff dataset (.csv, .npz, .parquet), model, simulated "
                   "throw, cleaning report or learning benchmark (.json) or attempts log (.jsonl) in it")
    picture = tmp_path / "pic.png"
    picture.write_bytes(b"\x89PNG")
    # without -o it was RUN/report.html refused as an output, with -o "no such run directory"
    for output in ([], ["-o", str(tmp_path / "r.html")]):
        # a folder of one's own files is reported too: the message had asked for a folder holding run.json
        one_line_error(rlff("report", str(picture), *output), "pic.png: is a file, not a folder (one that rlff demo "
                       "wrote, holding run.json and its figures, or one holding your own datasets, models and attempts logs)")
    # a learn run has an attempts log, no run.json: the figure it can have is named
    log = tmp_path / "attempts.jsonl"
    log.write_text("")
    one_line_error(rlff("report", str(log)), "`rlff plot learning LOG -o OUT` draws its learning curve")
    # an empty log is no log: passed over, named (after the progress of reading it)
    error_after_progress(rlff("report", str(tmp_path)), "(passed over attempts.jsonl: an empty file, not an rlff attempts log",
                   "give a folder that `rlff demo` wrote, or one holding your own chain's files")
    (tmp_path / "run.json").write_text('{"format": "rlff-run", "version": 9}')
    one_line_error(rlff("report", str(tmp_path)), "unsupported version 9")


def test_report_of_a_folder_of_ones_own_chain(rlff, tmp_path):
    """No run.json: the datasets, models and attempts logs the folder holds, each in a section with
    its figures, embedded; other files passed over and named."""
    import base64
    import re

    folder = tmp_path / "mine"
    folder.mkdir()
    demos = folder / "demos.csv"
    assert rlff("data", "synth", "throws", "--subjects", "2", "--throws", "3", "--seed", "3", "-o", str(demos)).code == 0
    assert rlff("fit", str(demos), "-o", str(folder / "model.json"), "--max-components", "3").code == 0
    learned = rlff("learn", str(demos), "--preset", "thesis", "--basket", "1.5", "--budget", "2", "--log", str(folder / "a.jsonl"))
    assert learned.code == 0, learned.stderr
    (folder / "notes.json").write_text('{"what": "my own notes"}')
    from rlff.formats import read_dataset, write_dataset

    write_dataset(read_dataset(demos), folder / "demos.parquet")  # any dataset format the project writes
    result = rlff("report", str(folder), "-o", str(tmp_path / "r.html"))
    assert result.code == 0, result.stderr
    assert "passed over notes.json: not an rlff dataset or model" in result.stderr
    text = (tmp_path / "r.html").read_text()
    for title in ("Demonstrations", "Models", "Learning", "demos.csv", "demos.parquet", "model.json", "a.jsonl"):
        assert title in text
    images = re.findall(r'src="data:image/png;base64,([^"]+)"', text)
    assert len(images) == 4 and all(base64.b64decode(i).startswith(b"\x89PNG") for i in images)  # 2 data, K, learning
    assert not list(folder.glob("*.png")) and not (folder / "run.json").exists()  # nothing written in the folder


# -- rlff plot ----------------------------------------------------------------------------------


def test_plot_dataset_writes_both_figures(rlff, throws_csv, tmp_path):
    files = written(rlff("plot", "dataset", str(throws_csv), "-o", str(tmp_path / "fig" / "demos"), "--json"))
    assert sorted(p.name for p in files) == ["demos-3d.png", "demos-3d.svg", "demos-slices.png", "demos-slices.svg"]
    assert all(p.stat().st_size > 1000 for p in files)


def test_plot_learning_from_logs(rlff, tmp_path):
    logs = []
    for method, misses in (("calibrate", [-0.4, -0.1, 0.0]), ("imitation", [-0.5, -0.5])):
        path = tmp_path / f"{method}.jsonl"
        write_attempts_log(path, {"basket": {"distance": 2.1}, "feedback": "binary", "update": method}, misses,
                           [m == 0.0 for m in misses], tail='{"attempt": 4, "mi')  # crash mid-write
        logs.append(str(path))
    files = written(rlff("plot", "learning", *logs, "--tolerance", "0.14", "-o", str(tmp_path / "curves"), "--json"))
    assert [p.suffix for p in files] == [".png", ".svg"]
    assert "calibrate" in files[1].read_text() and "imitation" in files[1].read_text()

    other = tmp_path / "other.jsonl"
    write_attempts_log(other, {"basket": {"distance": 3.0}, "update": "x"}, [])
    one_line_error(rlff("plot", "learning", logs[0], str(other), "-o", str(tmp_path / "x")),
                   "different tasks: basket 2.1 m (calibrate.jsonl), 3 m (other.jsonl)")
    # --tolerance is checked as the distance options are: metres, more than 0
    one_line_error(rlff("plot", "learning", logs[0], "--tolerance", "15", "-o", str(tmp_path / "x")),
                   "--tolerance: 15 m is wider than the basket is far (2.1 m) (centimetres? the tolerance is in metres: "
                   "0.15)")
    one_line_error(rlff("plot", "learning", logs[0], "--tolerance", "-0.1", "-o", str(tmp_path / "x")),
                   "--tolerance: -0.1 m is no half-width of a band: give a positive number of metres")
    one_line_error(rlff("plot", "learning", str(tmp_path / "none.jsonl"), "-o", str(tmp_path / "x")),
                   "none.jsonl: no such attempts log")
    (tmp_path / "bad.jsonl").write_text('{"format": "something else"}\n')
    one_line_error(rlff("plot", "learning", str(tmp_path / "bad.jsonl"), "-o", str(tmp_path / "x")),
                   "not an rlff attempts log")


def test_plot_throw_from_the_sim_json(rlff, tmp_path):
    from rlff.robot import RobotMapping, load_robot
    from rlff.sim import Basket, simulate_throw

    angle = np.linspace(1.0, 2.6, 40)
    velocity = 10.0 * np.sin(np.pi * (angle - 1.0) / 1.8) + 0.5
    trajectory, _ = RobotMapping.for_robot(load_robot()).to_robot(angle, velocity, clip=True)
    outcome = simulate_throw(trajectory, Basket(1.8), check_reach=False, check_motion=False)  # mapped, unplanned
    record = tmp_path / "outcome.json"
    record.write_text(json.dumps(outcome.to_dict(), default=float))
    files = written(rlff("plot", "throw", str(record), "-o", str(tmp_path / "throw"), "--json"))
    assert files[0].name == "throw.png"
    # the arm is the outcome's: it drew the built-in Comau on the floor for any robot on any pedestal
    other = tmp_path / "other.json"
    other.write_text(json.dumps({**outcome.to_dict(), "robot": "my_arm", "pedestal": 0.5}, default=float))
    one_line_error(rlff("plot", "throw", str(other), "-o", str(tmp_path / "t")),
                   "other.json was thrown by robot 'my_arm', from a robot file: give that file with --robot")
    # the Comau asked for was drawn, with a warning, for another arm's throw, the ball floating off it
    one_line_error(rlff("plot", "throw", str(other), "--robot", "comau_smart5_six", "-o", str(tmp_path / "t")),
                   "other.json was thrown by robot 'my_arm', not 'comau_smart5_six' (--robot comau_smart5_six): "
                   "give the robot file of 'my_arm' with --robot")
    assert not (tmp_path / "t.png").exists()
    record.write_text("{broken")
    one_line_error(rlff("plot", "throw", str(record), "-o", str(tmp_path / "t")), "outcome.json: not valid JSON")
    record.write_text('{"hit": true}')
    one_line_error(rlff("plot", "throw", str(record), "-o", str(tmp_path / "t")), "missing or malformed field")


@pytest.fixture
def model_json(throws_csv, tmp_path) -> Path:
    from rlff.dataset import read_csv
    from rlff.model import Model

    path = tmp_path / "model.json"
    Model.fit(read_csv(throws_csv), components=2, seed=0).save(path)
    return path


def test_plot_model_figures(rlff, throws_csv, model_json, tmp_path):
    for kind, *args in (
        ("components", str(model_json), str(throws_csv), "--distance", "2.5"),
        ("dmm", str(model_json), "--distance", "3.0", "--data", str(throws_csv)),
        ("outputs", str(model_json), "--distances", "1.5,3.0,4.5", "--data", str(throws_csv)),
        ("kmeans-em", str(throws_csv), "--k", "2,3", "--distance", "2.5"),
        ("bic", str(throws_csv), "--max-components", "3"),
        ("bic", str(throws_csv), "--max-components", "3", "--effective-samples", "all"),
        ("donuts", "--eps", "0,0.5,1"),
    ):
        files = written(rlff("plot", kind, *args, "-o", str(tmp_path / kind), "--json"))
        assert [p.name for p in files] == [f"{kind}.png", f"{kind}.svg"], kind
        assert files[0].stat().st_size > 5000


@pytest.mark.parametrize("suffix", [".parquet", ".npz"])
def test_plot_reads_datasets_as_fit_does(rlff, throws_csv, model_json, tmp_path, suffix):
    from rlff.dataset import read_csv
    from rlff.formats import write_dataset

    data = tmp_path / f"throws{suffix}"
    write_dataset(read_csv(throws_csv), data)
    for kind, *args in (
        ("dataset", str(data)),
        ("components", str(model_json), str(data), "--distance", "2.5"),
        ("dmm", str(model_json), "--distance", "3.0", "--data", str(data)),
        ("outputs", str(model_json), "--distances", "1.5", "--data", str(data)),
        ("kmeans-em", str(data), "--k", "2"),
        ("bic", str(data), "--max-components", "2"),
        ("preprocess", str(data)),
    ):
        assert written(rlff("plot", kind, *args, "-o", str(tmp_path / kind), "--json")), kind
    one_line_error(rlff("plot", "bic", str(model_json), "-o", str(tmp_path / "x")), "model.json is an rlff model (rlff fit writes it), not a dataset")


def test_plot_preprocess_runs_the_pipeline(rlff, tmp_path):
    from rlff.synthetic.throws import simulate_throws

    raw = tmp_path / "raw.csv"
    write_csv(simulate_throws(0, subjects=2, distances=(1.0, 2.0, 3.0), throws_per_distance=2), raw)
    files = written(rlff("plot", "preprocess", str(raw), "--preset", "thesis", "-o", str(tmp_path / "steps"), "--json"))
    svg = files[1].read_text()
    for step in ("spike_filter", "crop", "cut_release"):
        assert step in svg


@pytest.mark.parametrize("kind", [("dataset", "{data}"), ("bic", "{data}"), ("donuts",), ("kmeans-em", "{data}")])
@pytest.mark.parametrize("folder", ["made/", "existing"])
def test_plot_refuses_a_folder_as_the_file_stem(rlff, throws_csv, tmp_path, kind, folder):
    # -o p/ wrote ./p-3d.png and ./p-slices.png beside the folder
    (tmp_path / "existing").mkdir()
    out = str(tmp_path / folder) + ("/" if folder.endswith("/") else "")
    args = [part.format(data=throws_csv) for part in kind]
    line = one_line_error(rlff("plot", *args, "-o", out), "a folder, and -o is the figures' file stem",
                          f"e.g. -o {tmp_path / folder.rstrip('/') / 'figure'}")
    assert line
    assert sorted(p.name for p in tmp_path.iterdir() if p.name != "throws.csv") == ["existing"]


def test_plot_bad_input(rlff, throws_csv, tmp_path):
    one_line_error(rlff("plot", "dataset", str(tmp_path / "none.csv"), "-o", str(tmp_path / "x")), "none.csv: no such file")
    one_line_error(rlff("plot", "kmeans-em", str(throws_csv), "--k", "2,x", "-o", str(tmp_path / "x")),
                   "--k: 'x' is not a number")
    one_line_error(rlff("plot", "kmeans-em", str(throws_csv), "--k", "100000", "-o", str(tmp_path / "x")),
                   "--k: number of components 100000 must be between 1 and the")
    # only the bad values are named: 1 is a valid K
    one_line_error(rlff("plot", "kmeans-em", str(throws_csv), "--k", "0,1,-2", "-o", str(tmp_path / "x")),
                   "--k: numbers of components 0, -2 must be between 1 and the")
    one_line_error(rlff("plot", "preprocess", str(throws_csv), "--preset", "thesis", "--config", "a.toml",
                       "-o", str(tmp_path / "x")), "either --preset or --config")
    one_line_error(rlff("plot", "donuts", "--eps", "0,2", "-o", str(tmp_path / "x")), "exploration factor 2 is outside [0, 1]")
    for kind in ("bic", "kmeans-em"):
        one_line_error(rlff("plot", kind, str(throws_csv), "--effective-samples", "x", "-o", str(tmp_path / "x")),
                       "--effective-samples: give all, measured or a number > 0, got 'x'")
    one_line_error(rlff("plot", "outputs", str(tmp_path / "none.json"), "--distances", "2", "-o", str(tmp_path / "x")),
                   "none.json")
    one_line_error(rlff("plot", "kmeans-em", str(throws_csv), "--distance", "9", "-o", str(tmp_path / "x")),
                   "no trajectories at distance = 9 (values: 1.5, 2.5, 3.5)")


def test_every_plot_kind_has_help(rlff):
    result = rlff("plot", "--help")
    assert result.code == 0
    kinds = ["dataset", "components", "kmeans-em", "bic", "donuts", "dmm", "outputs", "preprocess", "learning", "throw",
             "cuts"]
    for kind in kinds:
        assert kind in result.stdout
    for kind in kinds[:3]:
        assert rlff("plot", kind, "--help").code == 0


# -- rlff demo ----------------------------------------------------------------------------------


def test_demo_bad_input(rlff, tmp_path):
    occupied = tmp_path / "file"
    occupied.write_text("not a folder")
    for option in ("--out", "--output"):
        one_line_error(rlff("demo", "--small", option, str(occupied)),
                       f"{occupied} is a file, not a folder: -o/--output is the folder for the demo's report")
    # a folder of the user's own files under the run's names, not an earlier run's: kept, refused
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "demos.csv").write_text("my recordings")
    (mine / "model.json").write_text("{}")
    one_line_error(rlff("demo", "--small", "--out", str(mine)),
                   f"{mine}: holds 2 files rlff demo would write, and no list of the files a run of rlff demo wrote "
                   "there (.rlff-run; an rlff demo older than that list kept none), so it cannot tell them from files "
                   "of yours: demos.csv, model.json; nothing was written or removed: if an older rlff demo wrote them, "
                   "remove them (or move them out of the folder) and run rlff demo again; if any are yours, move them, "
                   "or give another folder with -o")
    assert (mine / "demos.csv").read_text() == "my recordings"
    assert rlff("demo", "--help").code == 0


def test_a_demo_stopped_before_its_run_json_may_be_run_again_into_its_folder(tmp_path):
    from rlff.demo import check_demo_options, run_demo

    def stop_at_the_fit(stage, done, total):
        if stage.startswith("choosing K"):
            raise KeyboardInterrupt

    out = tmp_path / "demo"
    with pytest.raises(KeyboardInterrupt):
        run_demo(out, size="small", progress=stop_at_the_fit, frames=False)
    assert (out / "clean.csv").exists() and not (out / "run.json").exists()
    check_demo_options(out, "small")  # its own files: no refusal


def test_an_option_counts_as_given_only_when_typed_and_a_name_no_parameter_has_is_a_bug():
    from typer.testing import CliRunner

    from rlff.cli._common import given

    app = typer.Typer()
    seen = {}

    @app.command()
    def command(ctx: typer.Context, centre_share: float = typer.Option(0.5, "--centre-share"),
                typo: bool = typer.Option(False, "--typo")) -> None:
        seen["given"] = given(ctx, "centre_share")
        if typo:
            given(ctx, "centre_shares")  # no such parameter: it had counted as given

    runner = CliRunner()
    assert runner.invoke(app, []).exit_code == 0 and seen["given"] == []
    assert runner.invoke(app, ["--centre-share", "0.5"]).exit_code == 0 and seen["given"] == ["--centre-share"]
    assert isinstance(runner.invoke(app, ["--typo"]).exception, ValueError)
