"""The error boundary: every failure a user can cause is one line and exit 2, a bug is exit 1.

The cases are the tracebacks a hostile but realistic user met (issue 11): values of 1e308 in the
data and the model, folders where files go and files where folders go, TOML ``step = nan``, a
truncated ``.npz``, ``--distances 1e308``, ``--landings nope``, ``ROS_MASTER_URI=notaurl``; then
option parsing, numpy's warnings, markup in names, plurals and the fit's K.
"""

from __future__ import annotations

import csv
import json
import re
import time
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from rlff.robot import RobotMapping, load_robot


def one_line_error(result, *fragments: str, code: int = 2) -> str:
    """The single line a failed command printed; checks the exit code and that no traceback shows."""
    assert result.code == code, (result.code, result.stdout, result.stderr)
    assert "Traceback" not in result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith("rlff: error: " if code == 2 else "rlff: internal error: "), lines[0]
    for fragment in fragments:
        assert fragment in lines[0], (fragment, lines[0])
    return lines[0]


@pytest.fixture(scope="module")
def files(tmp_path_factory) -> dict[str, Path]:
    """Small real inputs: the thesis set, a model fitted to it, a generated path, and broken copies."""
    from rlff.cli import main

    folder = tmp_path_factory.mktemp("errors")
    data, model, path = folder / "data.csv", folder / "model.json", folder / "path.csv"
    assert main(["-q", "data", "synth", "thesis", "--trajectories", "5", "--points", "20", "-o", str(data)]) == 0
    assert main(["-q", "fit", str(data), "-k", "2", "-o", str(model)]) == 0
    assert main(["-q", "generate", str(model), "-c", "distance=3", "-o", str(path)]) == 0
    rows = list(csv.reader(data.open()))
    rows[5][rows[0].index("velocity")] = "1e308"
    huge = folder / "huge.csv"
    with huge.open("w", newline="") as handle:
        csv.writer(handle).writerows(rows)
    document = json.loads(model.read_text())
    document["means"][0][0] = 1e308
    huge_model = folder / "huge-model.json"
    huge_model.write_text(json.dumps(document))
    npz = folder / "data.npz"
    assert main(["-q", "data", "synth", "thesis", "--trajectories", "3", "--points", "20", "-o", str(npz)]) == 0
    cut = folder / "cut.npz"
    cut.write_bytes(npz.read_bytes()[: npz.stat().st_size // 2])
    nan_toml = folder / "nan.toml"
    nan_toml.write_text('[[step]]\nname = "densify"\nstep = nan\n')
    mapping = RobotMapping.for_robot(load_robot())
    throw = folder / "throw.csv"
    positions = np.linspace(-0.5, 1.5, 21)
    pd.DataFrame({"angle": (positions - mapping.angle_offset) / mapping.angle_scale,
                  "velocity": np.full(21, 2.0 / mapping.velocity_scale), "pdf": 1.0, "exploration": 0.0,
                  "gmr_mean": 0.0}).to_csv(throw, index=False)
    throw_degrees = folder / "throw-degrees.csv"
    generated = pd.read_csv(throw)
    generated["angle"] = np.degrees(generated["angle"])
    generated.to_csv(throw_degrees, index=False)
    degrees = folder / "degrees.csv"
    frame = pd.read_csv(data)
    frame["angle"] = 18.0 * frame["angle"]  # the thesis set's 0-10 as 0-180
    frame.to_csv(degrees, index=False)
    return {"folder": folder, "data": data, "model": model, "path": path, "huge": huge, "huge_model": huge_model,
            "cut": cut, "nan_toml": nan_toml, "throw": throw, "degrees": degrees,
            "throw_degrees": throw_degrees}


# (arguments with {name} placeholders for the files above, fragments the one line must hold)
TRACEBACK_CASES = {
    "fit 1e308 in the data": (["fit", "{huge}", "-o", "{tmp}/m.json"], ["huge.csv", "'velocity'", "1e+308"]),
    "learn 1e308 in the data": (["learn", "{huge}", "--basket", "2"], ["huge.csv", "1e+308"]),
    "plot bic 1e308 in the data": (["plot", "bic", "{huge}", "-o", "{tmp}/bic"], ["huge.csv", "1e+308"]),
    "plot dataset 1e308 in the data": (["plot", "dataset", "{huge}", "-o", "{tmp}/d"], ["huge.csv", "1e+308"]),
    "preprocess 1e308 in the data": (["data", "preprocess", "{huge}", "-o", "{tmp}/c.csv"], ["huge.csv", "1e+308"]),
    "generate, model mean 1e308": (["generate", "{huge_model}", "-c", "distance=2", "-o", "{tmp}/g.csv"],
                                   ["huge-model.json", "'means'", "1e+308"]),
    "plot dmm, model mean 1e308": (["plot", "dmm", "{huge_model}", "--distance", "2", "-o", "{tmp}/dmm"],
                                   ["huge-model.json", "'means'"]),
    "robot export, folder as input": (["robot", "export", "{folder}", "-f", "json", "-o", "{tmp}/t.json"],
                                      ["is a folder"]),
    "robot export, folder as output": (["robot", "export", "{throw}", "-f", "json", "-o", "{folder}"],
                                       ["names a folder", "give a file name, e.g."]),
    "robot send, folder as input": (["robot", "send", "{folder}"], ["a folder, but not a ROS 2 bag"]),
    "fit, folder as input": (["fit", "{folder}", "-o", "{tmp}/m.json"], ["is a folder, not a file"]),
    "fit, folder as output": (["fit", "{data}", "-o", "{folder}"], ["names a folder", "model.json"]),
    "fit, output under a file": (["fit", "{data}", "-o", "{data}/m.json"], ["is a file, not a folder"]),
    "report, folder as output": (["report", "{folder}", "-o", "{folder}"], ["names a folder"]),
    "report, file as run": (["report", "{data}"], ["data.csv"]),
    "learn --log a folder": (["learn", "{data}", "--basket", "2", "--log", "{folder}"], ["names a folder"]),
    "sim throw --frames a file": (["sim", "throw", "{throw}", "--basket", "2", "--frames", "{data}"],
                                  ["is a file, not a folder: --frames takes a folder; give a folder's path"]),
    "sim throw, folder as input": (["sim", "throw", "{folder}", "--basket", "2"], ["is a folder"]),
    "TOML densify step = nan": (["data", "preprocess", "{data}", "--config", "{nan_toml}", "-o", "{tmp}/c.csv"],
                                ["nan.toml", "densify", "step", "finite"]),
    "truncated .npz": (["fit", "{cut}", "-o", "{tmp}/m.json"], ["cut.npz", "an NPZ cut short or damaged"]),
    "synth --distances 1e308": (["data", "synth", "throws", "--distances", "1e308", "-o", "{tmp}/s.csv"],
                                ["1e+308", "0.3 to 20 m"]),
    "bench --landings nope": (["bench", "learning", "--landings", "nope"], ["--landings", "'nope'", "noisy:STD"]),
    # a model said "line 1: corrupt attempts log (not a JSON object)", as if it were a damaged log
    "plot learning, a model as the log": (["plot", "learning", "{model}", "-o", "{tmp}/pl"],
                                          ["model.json is an rlff model (rlff fit writes it), not an rlff attempts log",
                                           "the attempts logs (JSONL) that rlff learn --log writes"]),
    "plot learning, a dataset as the log": (["plot", "learning", "{data}", "-o", "{tmp}/pl"],
                                            ["data.csv is text (its first line: 'trajectory,", "not an rlff attempts log"]),
}


def _args(template: list[str], files: dict[str, Path], tmp: Path) -> list[str]:
    return [part.format(tmp=tmp, **files) for part in template]


@pytest.mark.parametrize("case", list(TRACEBACK_CASES))
def test_a_reported_traceback_is_one_line(rlff, files, tmp_path, case):
    template, fragments = TRACEBACK_CASES[case]
    one_line_error(rlff("-q", *_args(template, files, tmp_path)), *fragments)


def test_ros_master_uri_that_is_not_a_url(cli, files):
    result = cli("-q", "robot", "send", str(files["throw"]), "--timeout", "1", env={"ROS_MASTER_URI": "notaurl"})
    one_line_error(result, "ROS_MASTER_URI", "'notaurl'", "http://")


def test_a_missing_output_folder_is_created(rlff, files, tmp_path):
    out = tmp_path / "new" / "deeper" / "model.json"
    assert rlff("-q", "fit", str(files["data"]), "-k", "1", "-o", str(out)).code == 0
    assert json.loads(out.read_text())["format"] == "rlff-model"
    exported = tmp_path / "fresh" / "t.json"
    assert rlff("-q", "robot", "export", str(files["throw"]), "-f", "json", "-o", str(exported)).code == 0
    assert exported.is_file()


# -- validation up front ------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("args", "fragments"),
    [
        (["learn", "{data}", "--basket", "0.01"], ["basket distance", "0.01 m", "0.3 to 20 m"]),
        (["learn", "{data}", "--basket", "2", "--pedestal", "100"], ["pedestal", "100 m", "0 to 5 m"]),
        (["sim", "throw", "{throw}", "--basket", "2", "--pedestal", "-1"], ["pedestal", "-1 m"]),
        # --pedestal before any file is read: a model given as the data is not named first
        (["learn", "{model}", "--basket", "2", "--pedestal", "-1"], ["--pedestal: -1 m is outside the range 0 to 5 m"]),
        (["sim", "throw", "{model}", "--basket", "2", "--pedestal", "nan"], ["--pedestal: nan is not a number"]),
        (["sim", "reach", "--robot", "{model}", "--pedestal", "9"], ["--pedestal: 9 m is outside the range 0 to 5 m"]),
        (["plot", "throw", "{model}", "--pedestal", "-2", "-o", "{tmp}/p"], ["--pedestal: -2 m is outside"]),
        (["data", "synth", "throws", "--distances", "-1,2", "-o", "{tmp}/s.csv"], ["-1 m", "0.3 to 20 m"]),
        (["generate", "{model}", "-c", "distance=1", "-c", "distance=2", "-o", "{tmp}/g.csv"],
         ["--context", "distance given twice"]),
        (["generate", "{model}", "-c", "distance=inf", "-o", "{tmp}/g.csv"], ["--context", "finite"]),
        (["generate", "{model}", "-c", "distance=1e300", "-o", "{tmp}/g.csv", "--json"],
         ["--context distance: 1e+300 m is outside the range 0.3 to 20 m"]),
        (["generate", "{model}", "-c", "distance=0", "-o", "{tmp}/g.csv"], ["--context distance: 0 m is outside"]),
        (["generate", "{model}", "-c", "distance=2", "-c", "bearing=400", "-o", "{tmp}/g.csv"],
         ["--context bearing: give -180..180 degrees, got 400"]),
        (["generate", "{model}", "-c", "distance=2", "-c", "height=-1", "-o", "{tmp}/g.csv"],
         ["--context height: give a positive height (m), got -1"]),
        (["plot", "dmm", "{model}", "--distance", "1e300", "-o", "{tmp}/p"],
         ["--distance: 1e+300 m is outside the range 0.3 to 20 m"]),
        (["plot", "components", "{model}", "{data}", "--distance", "-1", "-o", "{tmp}/p"], ["--distance: -1 m"]),
        (["plot", "kmeans-em", "{data}", "--distance", "25", "-o", "{tmp}/p"], ["--distance: 25 m"]),
        (["plot", "outputs", "{model}", "--distances", "2,1e300", "-o", "{tmp}/p"], ["--distances: 1e+300 m"]),
        (["generate", "{model}", "-c", "distance=2", "--grid", "angle=8:2:50", "-o", "{tmp}/g.csv"],
         ["--grid", "START 8 is above STOP 2"]),
        (["data", "import", "{data}", "{data}", "-o", "{tmp}/i.csv"], ["data.csv", "given twice"]),
        (["data", "import", "{data}", "--format", "msr", "--rate", "1e300", "-o", "{tmp}/i.csv"],
         ["--rate: 1e+300 Hz is outside the range 1 to 1000 Hz"]),
        # angles in degrees: refused as they are read, not after cleaning into 1.2 million samples
        (["data", "preprocess", "{degrees}", "-o", "{tmp}/c.csv"],
         ["degrees.csv: column 'angle' reaches", "beyond two turns in radians: degrees?"]),
        (["robot", "export", "{throw_degrees}", "-o", "{tmp}/t.json"],
         ["the path's angle reaches", "degrees?"]),
        # one rlff file where another goes: what it is, not "unknown dataset extension '.json'"
        (["fit", "{model}", "-o", "{tmp}/m.json"],
         ["model.json is an rlff model (rlff fit writes it), not a dataset of demonstrations"]),
        (["learn", "{model}", "--basket", "2"], ["is an rlff model (rlff fit writes it), not a dataset"]),
        (["sim", "throw", "{model}", "--basket", "2"],
         ["is an rlff model (rlff fit writes it), not a robot trajectory (rlff-joint-trajectory)"]),
    ],
)
def test_bad_values_are_refused_up_front(rlff, files, tmp_path, args, fragments):
    one_line_error(rlff("-q", *_args(args, files, tmp_path)), *fragments)


def test_the_same_recording_twice_under_two_names_is_refused(rlff, files, tmp_path, monkeypatch):
    monkeypatch.chdir(files["folder"])
    absolute = str(files["folder"] / "data.csv")
    one_line_error(rlff("-q", "data", "import", "data.csv", absolute, "-o", str(tmp_path / "i.csv")),
                   f"data.csv and {absolute} are the same file", "given twice")
    (files["folder"] / "link.csv").symlink_to(files["data"])
    one_line_error(rlff("-q", "data", "import", "data.csv", "link.csv", "-o", str(tmp_path / "i.csv")),
                   "data.csv and link.csv are the same file")


# -- the size limits, before anything is allocated -----------------------------------------------


def test_a_huge_grid_is_refused_with_its_numbers(rlff, files, tmp_path):
    line = one_line_error(rlff("-q", "generate", str(files["model"]), "-c", "distance=2", "--grid",
                               "angle=0:10:100000000", "-o", str(tmp_path / "g.csv")))
    assert "100,000,000" in line and "2,000,000" in line
    assert not (tmp_path / "g.csv").exists()


def test_a_tiny_densify_step_is_refused_with_its_numbers(rlff, files, tmp_path):
    config = tmp_path / "tiny.toml"
    config.write_text('[[step]]\nname = "densify"\nstep = 1e-9\n')
    line = one_line_error(rlff("-q", "data", "preprocess", str(files["data"]), "--config", str(config),
                               "-o", str(tmp_path / "c.csv")))
    assert "densify step 1e-09" in line and "20,000,000" in line and "larger step" in line


# -- option parsing and the internal-error line --------------------------------------------------


@pytest.mark.parametrize(
    ("args", "fragments"),
    [
        (["fit", "--no-such-option"], ["rlff fit", "--no-such-option", "rlff fit --help"]),
        (["fit"], ["rlff fit", "Missing argument"]),
        # an option's value missing at the end: click gives no context, the command is still named
        (["-q", "bench", "learning", "--seeds"], ["rlff bench learning: Option '--seeds' requires an argument",
                                                  "rlff bench learning --help"]),
        (["bench", "learning", "--gap", "speed:2"], ["--gap", "'speed:2'", "0 < G <= 1"]),
        (["fit", "{data}", "-o", "{tmp}/m.json", "--json", "true"], ["rlff fit", "(true)"]),
        (["generate", "{model}", "-o", "{tmp}/g.csv", "--exploration-scale", "lots"], ["--exploration-scale", "valid number", "(got 'lots')"]),
        (["fit", "{data}", "-o", "{tmp}/m.json", "--components", "lots"], ["--components", "integer >= 1", "'lots'"]),
        # the fit's settings by the options typed, not Model.fit's parameter names
        (["fit", "{data}", "-o", "{tmp}/m.json", "-k", "100000"], ["-k/--components 100000 is more than the", "samples"]),
        (["fit", "{data}", "-o", "{tmp}/m.json", "--max-components", "0"], ["'--max-components'", "(got '0')"]),
        (["fit", "{data}", "-o", "{tmp}/m.json", "--n-init", "0"], ["'--n-init'", "(got '0')"]),
        (["fit", "{data}", "-o", "{tmp}/m.json", "--criterion", "bci"], ["--criterion must be bic or aic, got 'bci'"]),
        (["plot", "bic", "{data}", "-o", "{tmp}/b", "--criterion", "bci"], ["--criterion must be bic or aic"]),
        # a decimal comma where a float is asked for: the number with a point
        (["generate", "{model}", "-o", "{tmp}/g.csv", "--exploration-scale", "1,5"],
         ["(got '1,5')", "numbers take a decimal point: 1.5"]),
        (["no-such-command"], ["rlff: error: No such command 'no-such-command'", "(see rlff --help)"]),
        (["data", "no-such-command"], ["rlff: error: rlff data: No such command 'no-such-command'",
                                       "(see rlff data --help)"]),
        # rlff's own option after the subcommand: where it goes
        (["data", "preprocess", "{data}", "-o", "{tmp}/c.csv", "-q"],
         ["No such option: -q", "-q goes before the subcommand: rlff -q data preprocess ..."]),
        # a context typed as an option: generate says how contexts go
        (["generate", "{model}", "-o", "{tmp}/g.csv", "--distance", "2"], ["--distance", "-c distance=..."]),
        (["generate", "{model}", "-o", "{tmp}/g.csv", "--exploraton", "2"], ["Possible options: --exploration"]),
    ],
)
def test_option_parsing_errors_are_one_line(rlff, files, tmp_path, args, fragments):
    result = rlff(*_args(args, files, tmp_path))
    line = one_line_error(result, *fragments)
    assert "╭" not in result.stderr and "Usage:" not in result.stderr, line


def test_a_bug_is_an_internal_error_with_exit_1(rlff, files, tmp_path, monkeypatch):
    from rlff.model import Model

    def broken(*args, **kwargs):
        raise ZeroDivisionError("float division by zero")

    monkeypatch.setattr(Model, "load", classmethod(broken))
    args = ("generate", str(files["model"]), "-c", "distance=2", "-o", str(tmp_path / "g.csv"))
    line = one_line_error(rlff(*args), "ZeroDivisionError", "--debug", code=1)
    assert "bug" in line
    debug = rlff("--debug", *args)
    assert debug.code == 1 and "Traceback" in debug.stderr and "ZeroDivisionError" in debug.stderr


def test_a_robot_that_cannot_be_reached_is_one_error_line_with_exit_1(rlff, monkeypatch):
    """Not the input (exit 2) and not a bug: an RlffError, here ROS missing, is said in one line."""
    from rlff.robot import ros1

    monkeypatch.setattr(ros1, "missing", lambda: "ROS 1 is not reachable (no rospy):\n  install it")
    result = rlff("robot", "serve")
    assert result.code == 1 and "Traceback" not in result.stderr
    assert result.stderr.strip().splitlines() == ["rlff: error: ROS 1 is not reachable (no rospy): install it"]
    debug = rlff("--debug", "robot", "serve")
    assert debug.code == 1 and "Traceback" in debug.stderr and "RlffError" in debug.stderr

def test_numpy_warnings_are_silenced_unless_debug(rlff, files, tmp_path, monkeypatch):
    from rlff.model import Model

    load = Model.load

    def noisy(cls, path):
        np.log(np.zeros(3))  # RuntimeWarning: divide by zero
        return load(path)

    monkeypatch.setattr(Model, "load", classmethod(noisy))
    args = ("generate", str(files["model"]), "-c", "distance=2", "-o", str(tmp_path / "g.csv"))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        quiet = rlff("-q", *args)
    assert quiet.code == 0 and quiet.stderr == "", quiet.stderr
    assert not [w for w in caught if issubclass(w.category, RuntimeWarning)]
    with pytest.warns(RuntimeWarning, match="divide by zero"):
        assert rlff("-q", "--debug", *args).code == 0


# -- what the commands print ---------------------------------------------------------------------


def _untimed(lines: list[str]) -> list[str]:
    """Progress lines without their elapsed time (``importing 2/20 (10 %) 0:00:01``)."""
    for line in lines:
        assert re.fullmatch(r".* \d+:\d\d:\d\d", line), line
    return [line.rsplit(" ", 1)[0] for line in lines]


def test_progress_on_a_stderr_that_is_no_terminal_is_a_line_every_tenth(capsys, monkeypatch):
    # stderr redirected to a file: rich's bar showed nothing until the command ended, and a long
    # lab job looked hung
    from rlff.cli._common import progress, verbosity

    monkeypatch.setattr(verbosity, "quiet", False)
    with progress("importing", total=20) as advance:
        for _ in range(5):
            advance()
        during = capsys.readouterr().err.splitlines()
        for _ in range(15):
            advance()
    after = capsys.readouterr().err.splitlines()
    assert _untimed(during) == ["importing 0/20 (0 %)", "importing 2/20 (10 %)", "importing 4/20 (20 %)"]
    assert _untimed(after) == [f"importing {2 * k}/20 ({10 * k} %)" for k in range(3, 11)]
    advance(5)  # late, as a robot's feedback after its goal ended: the last line stands
    assert capsys.readouterr().err == ""


def test_progress_in_shares_of_a_unit_fills_by_them_and_counts_whole_units(capsys, monkeypatch):
    # one long file imported: its parts (read, cut, each throw labelled) move the work on, the
    # count says no file is done until it is, and ten tenths are one file, not 0.9999999999999999
    from rlff.cli._common import progress, verbosity

    monkeypatch.setattr(verbosity, "quiet", False)
    with progress("importing", total=1) as advance:
        advance(0.0, description="long.bag: reading")
        advance(0.4, description="long.bag: cutting throws")
        for _ in range(6):
            advance(0.1, description="long.bag: labelling throws")
    lines = _untimed(capsys.readouterr().err.splitlines())
    assert lines == ["importing 0/1 (0 %)", "long.bag: cutting throws 0/1 (40 %)",
                     *[f"long.bag: labelling throws 0/1 ({share} %)" for share in (50, 60, 70, 80, 90)],
                     "long.bag: labelling throws 1/1 (100 %)"], lines


def test_progress_in_shares_on_a_terminal_ends_whole(monkeypatch):
    # the bar's count is rich's int(completed): 0.9999999999999999 of the one file read "0/1" at the end
    import io

    from rich.console import Console

    from rlff.cli import _common

    monkeypatch.setattr(_common.verbosity, "quiet", False)
    screen = io.StringIO()
    monkeypatch.setattr(_common, "stderr", lambda: Console(file=screen, force_terminal=True, width=100, color_system=None))
    with _common.progress("importing", total=1) as advance:
        for _ in range(10):
            advance(0.1, description="long.bag: labelling throws")
    assert re.findall(r" (\d+/\d+) \d+:\d\d:\d\d", screen.getvalue())[-1] == "1/1", screen.getvalue()


def test_progress_on_a_stderr_that_is_no_terminal_is_said_now_and_then(capsys, monkeypatch):
    # work that advances seldom, or has no total, is said every PLAIN_SECONDS (30 s) all the same
    from rlff.cli import _common

    monkeypatch.setattr(_common.verbosity, "quiet", False)
    monkeypatch.setattr(_common, "PLAIN_SECONDS", 0.2)
    with _common.progress("fitting", total=None) as advance:
        advance(description="fitting: 1 of ? values of K tried")
        time.sleep(0.9)
        during = capsys.readouterr().err.splitlines()
    assert _untimed(during[:1]) == ["fitting 0/?"] and len(during) >= 3, during
    # the same progress again says the work goes on and for how long, where it repeated the line
    # before (a log of a long fit showed one line over and over)
    said, still = [], []
    for line in during:
        going_on = re.fullmatch(r"(.*) \.\.\. still working \(\d+ s\)", line)
        if going_on:
            assert going_on[1] == said[-1], during
            still.append(line)
        else:
            said += _untimed([line])
    assert said == ["fitting 0/?", "fitting: 1 of ? values of K tried 1/?"] and still, during
    assert capsys.readouterr().err == ""  # the end said nothing new
    assert [_common._duration(s) for s in (0.4, 45, 90, 3600, 7325.9)] == [
        "0 s", "45 s", "1 min 30 s", "1 h 0 min 0 s", "2 h 2 min 5 s"]


def test_a_command_s_progress_without_a_terminal_is_plain_lines(rlff, files, tmp_path):
    result = rlff("data", "preprocess", str(files["data"]), "--preset", "thesis", "-o", str(tmp_path / "c.csv"))
    assert result.code == 0, result.stderr
    lines = [line for line in result.stderr.splitlines() if re.fullmatch(r".* \d+/\d+ \(\d+ %\) \d+:\d\d:\d\d", line)]
    assert lines[0].startswith("preprocessing 0/") and "(100 %)" in lines[-1], result.stderr
    assert "━" not in result.stderr  # no bar drawn into a file


def test_markup_and_emoji_codes_in_names_print_literally(rlff, tmp_path):
    out = tmp_path / "[bold]a:smile:b.csv"
    result = rlff("data", "synth", "thesis", "--trajectories", "2", "--points", "5", "-o", str(out))
    assert result.code == 0 and str(out) in result.stdout, result.stdout
    missing = one_line_error(rlff("fit", str(tmp_path / "[red]x:b:y.csv"), "-o", str(tmp_path / "m.json")))
    assert "[red]x:b:y.csv" in missing


def test_counts_take_the_right_plural(rlff, tmp_path):
    one = rlff("data", "synth", "throws", "--subjects", "1", "--distances", "1", "--throws", "1",
               "-o", str(tmp_path / "one.csv"))
    assert one.code == 0 and one.stdout.startswith("1 throw (") and "1 throws" not in one.stdout, one.stdout
    assert "1 hit" in one.stdout or "0 hits" in one.stdout


def test_version(rlff):
    from rlff import __version__

    result = rlff("--version")
    assert result.code == 0 and result.stdout.strip() == f"rlff {__version__}"


def test_flags_are_shown_as_flags_in_help(rlff):
    result = rlff("fit", "--help")
    assert result.code == 0
    flag_line = next(line for line in result.stdout.splitlines() if "--json" in line)
    assert "<bool>" not in flag_line and "<bool>" not in result.stdout
    assert "<int" in result.stdout  # options that take values still say what they take ("<int range>")


def test_fit_names_the_k_chosen_and_warns_at_the_top_of_the_range(rlff, files, tmp_path):
    # five trajectories of the thesis set: BIC wants more than 2 components and fewer than 10
    capped = rlff("fit", str(files["data"]), "--max-components", "2", "-o", str(tmp_path / "m2.json"))
    assert capped.code == 0
    assert len(json.loads((tmp_path / "m2.json").read_text())["weights"]) == 2
    assert "K = 2 chosen" in capped.stdout and "fitted K=" not in capped.stderr
    assert "BIC chose K = 2, the largest tried" in capped.stderr and "--max-components" in capped.stderr
    wide = rlff("fit", str(files["data"]), "--max-components", "10", "-o", str(tmp_path / "m10.json"))
    k = len(json.loads((tmp_path / "m10.json").read_text())["weights"])
    assert k < 10 and f"K = {k} chosen" in wide.stdout
    assert "the largest tried" not in wide.stderr


@pytest.mark.parametrize(
    ("status", "code", "name", "text", "line"),
    [
        ("cancelled", 0, "SUCCESSFUL", "preempted by a newer goal", "goal cancelled: preempted by a newer goal"),
        ("succeeded", 0, "SUCCESSFUL", "", "goal succeeded (SUCCESSFUL)"),
        ("aborted", -4, "PATH_TOLERANCE_VIOLATED", "joint_2 off", "goal aborted (PATH_TOLERANCE_VIOLATED): joint_2 off"),
    ],
)
def test_a_preempted_goal_is_not_reported_successful(status, code, name, text, line):
    from rlff.cli.robot import goal_message
    from rlff.robot.send import SendResult

    assert goal_message(SendResult(status, code, name, text, 0.0, 1.0, 3)) == line


def test_help_lists_the_allowed_values(rlff):
    from rlff.capture.importer import ARMS
    from rlff.capture.importer import FORMATS as RECORDING_FORMATS
    from rlff.learn.loop import METHODS
    from rlff.learn.method import FEEDBACKS
    from rlff.learn.scenarios import DEMONSTRATORS
    from rlff.robot.formats import FORMATS as EXPORT_FORMATS

    def help_text(*command: str) -> str:
        result = rlff(*command, "--help")
        assert result.code == 0
        return " ".join(result.stdout.replace("│", " ").split())

    expected = {
        ("bench", "learning"): list(DEMONSTRATORS) + ["exact", "noisy:STD", "none", "false-miss:RATE"],
        ("robot", "export"): list(EXPORT_FORMATS),
        # ablations are a DMM method's name with a suffix: the help names the methods and suffixes
        ("learn",): sorted({m.split(":")[0] for m in METHODS}) + [":no-exploration", ":gmr-mean"] + list(FEEDBACKS),
        ("data", "import"): list(RECORDING_FORMATS) + list(ARMS),
        ("fit",): ["bic", "aic", "auto"],
    }
    for command, values in expected.items():
        text = help_text(*command)
        missing = [value for value in values if value not in text]
        assert not missing, (command, missing)


def test_preprocess_names_every_throw_it_removed_and_why(rlff, tmp_path):
    demos, report = tmp_path / "demos.csv", tmp_path / "report.json"
    assert rlff("-q", "data", "synth", "throws", "--subjects", "3", "--inconsistent-distance", "2.75",
                "-o", str(demos)).code == 0
    result = rlff("data", "preprocess", str(demos), "--preset", "thesis", "-o", str(tmp_path / "c.csv"),
                  "--report", str(report))
    assert result.code == 0
    steps = json.loads(report.read_text())["steps"]
    removed = [(step["step"], r["trajectory"], r["reason"]) for step in steps for r in step["removed"]]
    rejected = [(step["step"], c) for step in steps for c in step["contexts"]]
    assert removed and rejected  # the inconsistent basket and some single throws go
    lines = result.stderr.splitlines()
    for step, context in rejected:
        label = ", ".join(f"{k}={v:g}" for k, v in context["context"].items())
        line = next(line for line in lines if line.startswith(f"{step}: context {label} rejected"))
        assert context["reason"] in line and all(t in line for t in context["trajectories"])
    in_contexts = {t for _, c in rejected for t in c["trajectories"]}
    said = [(step, trajectory, reason) for step, trajectory, reason in removed if trajectory not in in_contexts]
    for name in {step for step, _, _ in said}:
        # the first ten of a step by name; the rest counted (hundreds of lines buried the rejections)
        of_step = [(trajectory, reason) for step, trajectory, reason in said if step == name]
        for trajectory, reason in of_step[:10]:
            assert f"{name}: removed throw {trajectory}: {reason}" in lines
        assert sum(line.startswith(f"{name}: removed throw") for line in lines) == min(10, len(of_step))
        if len(of_step) > 10:
            assert f"... and {len(of_step) - 10} more (--report FILE lists every one)" in lines
    assert any(len([r for r in said if r[0] == name]) > 10 for name in {r[0] for r in said})
    quiet = rlff("-q", "data", "preprocess", str(demos), "--preset", "thesis", "-o", str(tmp_path / "c2.csv"))
    assert "removed throw" not in quiet.stderr


def _seed_options() -> list[tuple[str, object]]:
    """Every seed option of the command tree, as (command path, click parameter)."""
    from rlff.cli import _command

    found, stack = [], [("rlff", _command())]
    while stack:
        path, command = stack.pop()
        stack += [(f"{path} {name}", sub) for name, sub in getattr(command, "commands", {}).items()]
        found += [(path, p) for p in command.params if any("seed" in o and o != "--seeds" for o in p.opts)]
    return found


def test_every_seed_option_takes_0_to_2_to_the_32_minus_1():
    options = _seed_options()
    assert {path for path, _ in options} >= {"rlff fit", "rlff plot bic", "rlff plot kmeans-em", "rlff learn",
                                             "rlff demo", "rlff bench learning", "rlff data synth throws"}
    for path, option in options:
        assert (option.min, option.max) == (0, 2**32 - 1), (path, option.opts)


@pytest.mark.parametrize("seed", ["-1", "4294967296"])
def test_a_seed_out_of_range_is_a_usage_error(rlff, files, tmp_path, seed):
    one_line_error(rlff("fit", str(files["data"]), "-o", str(tmp_path / "m.json"), "--seed", seed),
                   "Invalid value for '--seed'", f"(got '{seed}')")
    assert not (tmp_path / "m.json").exists()


def test_bench_seeds_past_the_largest_are_refused(rlff):
    one_line_error(rlff("bench", "learning", "--quick", "--first-seed", str(2**32 - 1)),
                   "--first-seed 4294967295 with --seeds 2 runs past the largest seed")


def test_an_option_given_twice_warns_and_the_last_is_taken(rlff, files, tmp_path):
    # click took the last without a word (sim throw --basket 1.75 --basket 2 threw at 2 m), and an
    # error of it quoted the first, until 2026-12-07; a script's options overridden at its end still work
    first, second = tmp_path / "first.csv", tmp_path / "second.csv"
    result = rlff("generate", str(files["model"]), "-c", "distance=2", "-o", str(first), "--output", str(second))
    assert result.code == 0, result.stderr
    assert (f"warning: --output given twice (-o {first}, then --output {second}): the last, {second}, is taken"
            in result.stderr.splitlines())
    assert second.is_file() and not first.exists()
    refused = rlff("fit", str(files["data"]), "-o", str(tmp_path / "m.json"), "--n-init", "1", "--n-init=0")
    lines = refused.stderr.strip().splitlines()
    assert refused.code == 2 and len(lines) == 2, refused.stderr
    assert lines[0] == "warning: --n-init given twice (--n-init 1, then --n-init 0): the last, 0, is taken"
    assert lines[1].startswith("rlff: error: ") and "'--n-init'" in lines[1] and "(got '0')" in lines[1]


def test_an_option_given_twice_with_one_value_is_taken_without_a_word(rlff, files, tmp_path):
    out = tmp_path / "g.csv"
    result = rlff("generate", str(files["model"]), "-c", "distance=2", "-o", str(out), "--output", str(out))
    assert result.code == 0, result.stderr
    assert out.is_file() and "given twice" not in result.stderr
