"""The output layer through the real commands: an output that is an input is refused before any
work, and an existing output is only ever replaced by a complete one.

The overwrite cases are those of issue 11, each of which destroyed its input before.
"""

from __future__ import annotations

import hashlib
import json
import os
import stat
import sys
from importlib import resources
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from rlff.robot import RobotMapping, load_robot

sys.path.insert(0, str(Path(__file__).resolve().parent))

import bagfactory as bf  # noqa: E402


def digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


@pytest.fixture(scope="module")
def made(tmp_path_factory) -> dict[str, Path]:
    """Real inputs: simulated throws, a model, a generated path, a robot-ready path, a bag, a run."""
    from rlff.cli import main

    folder = tmp_path_factory.mktemp("outputs")
    raw, model, path = folder / "raw.csv", folder / "m1.json", folder / "t.csv"
    assert main(["-q", "data", "synth", "throws", "--subjects", "2", "--distances", "1,2,3", "-o", str(raw)]) == 0
    assert main(["-q", "fit", str(raw), "-k", "2", "-o", str(model)]) == 0
    assert main(["-q", "generate", str(model), "-c", "distance=2", "-o", str(path)]) == 0
    mapping = RobotMapping.for_robot(load_robot())
    throw = folder / "throw.csv"
    positions = np.linspace(-0.5, 1.5, 21)
    pd.DataFrame({"angle": (positions - mapping.angle_offset) / mapping.angle_scale,
                  "velocity": np.full(21, 2.0 / mapping.velocity_scale), "pdf": 1.0, "exploration": 0.0,
                  "gmr_mean": 0.0}).to_csv(throw, index=False)
    bag = bf.write_ros1_bag(folder / "rec.bag", bf.standard_simulation(seed=3, n_throws=1))
    manifest = folder / "manifest.csv"
    manifest.write_text("file,throw,distance\nrec.bag,1,2.0\n")
    run = folder / "run"
    from rlff.report import FigureEntry, Run, Section, write_run

    (run / "figures").mkdir(parents=True)
    (run / "figures" / "dot.png").write_bytes(
        bytes.fromhex("89504e470d0a1a0a0000000d49484452000000010000000108060000001f15c4890000000d"
                      "4944415478da63f8cfc0f01f0005000201a5f5d2c80000000049454e44ae426082"))
    write_run(Run("r", "2026-01-01T00:00:00+00:00", sections=[Section("a", "A", facts={"n": 1})],
                  figures=[FigureEntry("figures/dot.png", "a", "Dot")]), run)
    arm = folder / "arm.toml"  # the user's own robot file
    arm.write_text((resources.files("rlff") / "robots" / "comau_smart5_six.toml").read_text(encoding="utf-8"))
    return {"folder": folder, "raw": raw, "model": model, "path": path, "throw": throw, "bag": bag,
            "manifest": manifest, "run_json": run / "run.json", "figure": run / "figures" / "dot.png", "run": run,
            "arm": arm}


# (arguments, the input that must survive, fragments of the one line)
OVERWRITES = {
    "fit c1.csv -o c1.csv": (["fit", "{raw}", "-o", "{raw}"], "raw", ["-o/--output", "is the input DATA"]),
    "preprocess -o the input": (["data", "preprocess", "{raw}", "--preset", "thesis", "-o", "{raw}"], "raw",
                                ["is the input DATA"]),
    "preprocess --report the input": (["data", "preprocess", "{raw}", "-o", "{tmp}/c.csv", "--report", "{raw}"],
                                      "raw", ["--report", "is the input DATA"]),
    "preprocess --report equal to -o": (["data", "preprocess", "{raw}", "-o", "{tmp}/c.csv", "--report",
                                         "{tmp}/c.csv"], "raw", ["-o/--output and --report are the same file"]),
    "generate m1.json -o m1.json": (["generate", "{model}", "-c", "distance=2", "-o", "{model}"], "model",
                                    ["is the input MODEL"]),
    "robot export t.csv -o t.csv": (["robot", "export", "{throw}", "--format", "csv", "-o", "{throw}"], "throw",
                                    ["is the input TRAJECTORY"]),
    "robot export --out alias": (["robot", "export", "{throw}", "--format", "json", "--out", "{throw}"], "throw",
                                 ["is the input TRAJECTORY"]),
    "data import rec.bag -o rec.bag": (["data", "import", "{bag}", "-o", "{bag}"], "bag", ["is the input FILES"]),
    "data import -o manifest.csv": (["data", "import", "{bag}", "--manifest", "{manifest}", "-o", "{manifest}"],
                                    "manifest", ["is the input --manifest"]),
    "report run -o run/run.json": (["report", "{run}", "-o", "{run_json}"], "run_json", ["is the input RUN"]),
    "report -o a figure": (["report", "{run}", "-o", "{figure}"], "figure", ["is the input RUN"]),
    "plot over its input": (["plot", "dataset", "{raw}", "-o", "{folder}/raw.csv"], "raw", []),
    "learn --log the demonstrations": (["learn", "{raw}", "--basket", "2", "--log", "{raw}"], "raw",
                                                 ["--log", "is the input DEMOS"]),
    "learn --out the robot file": (["learn", "{raw}", "--basket", "2", "--robot", "{arm}", "--out", "{arm}",
                                    "--format", "csv"], "arm", ["-o/--out", "is the input --robot"]),
    "robot export -o the robot file": (["robot", "export", "{throw}", "--robot", "{arm}", "--format", "json", "-o",
                                        "{arm}"], "arm", ["is the input --robot"]),
    "the same file by another name": (["fit", "{raw}", "-o", "{folder}/../{folder_name}/raw.csv"], "raw",
                                      ["is the input DATA"]),
}


@pytest.mark.parametrize("case", list(OVERWRITES))
def test_an_output_that_is_an_input_is_refused_before_any_work(rlff, made, tmp_path, case):
    template, survivor, fragments = OVERWRITES[case]
    values = {**made, "tmp": tmp_path, "folder_name": made["folder"].name}
    before = digest(made[survivor])
    result = rlff("-q", *[part.format(**values) for part in template])
    if case == "plot over its input":  # plot writes OUT.png and OUT.svg beside, never OUT itself
        assert result.code == 0, result.stderr
        assert (made["folder"] / "raw.csv-3d.png").is_file()
    else:
        assert result.code == 2, (result.stdout, result.stderr)
        line = result.stderr.strip()
        assert line.count("\n") == 0 and line.startswith("rlff: error: ") and "Traceback" not in line, line
        for fragment in fragments:
            assert fragment in line, line
        assert not (tmp_path / "c.csv").exists()  # refused before anything was written
    assert digest(made[survivor]) == before


def test_a_symlink_to_the_input_is_the_input(rlff, made, tmp_path):
    link = tmp_path / "link.csv"
    link.symlink_to(made["raw"])
    before = digest(made["raw"])
    result = rlff("-q", "data", "preprocess", str(made["raw"]), "-o", str(link))
    assert result.code == 2 and "is the input DATA" in result.stderr
    assert digest(made["raw"]) == before


def test_an_input_folder_protects_its_files(rlff, made, tmp_path):
    bag = tmp_path / "ros2bag"
    bf.write_ros2_bag(bag, bf.standard_simulation(seed=4, n_throws=1))
    inside = next(path for path in bag.iterdir() if path.is_file())
    before = digest(inside)
    result = rlff("-q", "data", "import", str(bag), "-o", str(inside))
    assert result.code == 2 and "is a file of the input FILES" in result.stderr, result.stderr
    assert digest(inside) == before


def test_an_existing_output_is_replaced_only_by_a_complete_one(rlff, made, tmp_path):
    out = tmp_path / "model.json"
    out.write_text('{"old": true}\n')
    out.chmod(0o640)
    assert rlff("-q", "fit", str(made["raw"]), "-k", "2", "-o", str(out)).code == 0
    assert json.loads(out.read_text())["format"] == "rlff-model"
    assert out.stat().st_mode & 0o777 == 0o640  # the file keeps its permissions
    assert [p.name for p in tmp_path.iterdir()] == ["model.json"]  # no temporary file left behind
    before = digest(out)
    # a run that fails after reading (a model column the data lacks) leaves the output as it was
    assert rlff("-q", "fit", str(made["raw"]), "--outputs", "nope", "-o", str(out)).code == 2
    assert digest(out) == before


def test_every_writer_goes_through_the_atomic_layer(rlff, made, tmp_path, monkeypatch):
    """Each command's files appear only through os.replace of a temporary file beside them."""
    import os

    import rlff.fileio as fileio

    replaced: list[str] = []
    real_replace = os.replace

    def spy(src, dst):
        assert Path(src).parent == Path(dst).parent and Path(src).name.startswith(".")
        replaced.append(Path(dst).name)
        return real_replace(src, dst)

    monkeypatch.setattr(fileio.os, "replace", spy)
    commands = {
        "clean.csv": ["data", "preprocess", str(made["raw"]), "-o", str(tmp_path / "clean.csv"),
                      "--report", str(tmp_path / "report.json")],
        "d.parquet": ["data", "synth", "thesis", "--trajectories", "2", "--points", "5", "-o", str(tmp_path / "d.parquet")],
        "d.npz": ["data", "synth", "thesis", "--trajectories", "2", "--points", "5", "-o", str(tmp_path / "d.npz")],
        "d.txt": ["data", "synth", "thesis", "--trajectories", "2", "--points", "5", "-o", str(tmp_path / "d.txt")],
        "m.json": ["fit", str(made["raw"]), "-k", "1", "-o", str(tmp_path / "m.json")],
        "g.csv": ["generate", str(made["model"]), "-c", "distance=2", "-o", str(tmp_path / "g.csv")],
        "r.bag": ["robot", "export", str(made["throw"]), "-f", "ros1-bag", "-o", str(tmp_path / "r.bag")],
        "r.prg": ["robot", "export", str(made["throw"]), "-f", "comau", "-o", str(tmp_path / "r.prg")],
        "r.csv": ["robot", "export", str(made["throw"]), "-f", "csv", "-o", str(tmp_path / "r.csv")],
        "fig.png": ["plot", "donuts", "-o", str(tmp_path / "fig")],
        "report.html": ["report", str(made["run"]), "-o", str(tmp_path / "report.html")],
    }
    for name, args in commands.items():
        assert rlff("-q", *args).code == 0, name
        assert name in replaced, (name, replaced)
    assert {"report.json", "fig.svg"} <= set(replaced)
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]  # no temporary file left


def test_a_ros2_bag_folder_is_replaced_whole(rlff, made, tmp_path):
    out = tmp_path / "bag2"
    assert rlff("-q", "robot", "export", str(made["throw"]), "-f", "ros2-bag", "-o", str(out)).code == 0
    from rlff.robot.export import read_bag

    assert len(read_bag(out)) == 1
    assert [p.name for p in tmp_path.iterdir()] == ["bag2"]


# (arguments, the option and the usual file name the message suggests)
FOLDERS_FOR_FILES = {
    "fit -o results/": (["fit", "{raw}", "-k", "1", "-o", "{out}/"], "-o/--output", "model.json"),
    "generate -o out/": (["generate", "{model}", "-c", "distance=2", "-o", "{out}/"], "-o/--output", "traj.csv"),
    "preprocess --report r/": (["data", "preprocess", "{raw}", "-o", "{tmp}/c.csv", "--report", "{out}/"],
                               "--report", "report.json"),
    "learn --log logs/": (["learn", "{raw}", "--basket", "2", "--log", "{out}/"], "--log", "attempts.jsonl"),
    "robot export -f json -o j/": (["robot", "export", "{throw}", "-f", "json", "-o", "{out}/"], "-o/--output", "throw"),
    "robot urdf -o u/": (["robot", "urdf", "-o", "{out}/"], "-o/--output", "robot.urdf"),
}


@pytest.mark.parametrize("case", list(FOLDERS_FOR_FILES))
def test_an_output_file_named_as_a_folder_is_refused_with_a_file_name_in_it(rlff, made, tmp_path, case):
    # Path("results/") is "results": `-o results/` wrote a file called results
    template, option, example = FOLDERS_FOR_FILES[case]
    out = tmp_path / "results"
    result = rlff("-q", *[part.format(**made, tmp=tmp_path, out=out) for part in template])
    assert result.code == 2 and result.stderr.strip() == (
        f"rlff: error: {option} {out}/ names a folder; give a file name, e.g. {out / example}"), result.stderr
    assert not out.exists() and not (tmp_path / "c.csv").exists()
    out.mkdir()  # an existing folder, without the slash: the same words
    result = rlff("-q", *[part.format(**made, tmp=tmp_path, out=out).rstrip("/") for part in template])
    assert result.code == 2 and f"{option} {out} names a folder; give a file name, e.g. {out / example}" in result.stderr
    assert list(out.iterdir()) == []


# rlff learn names its -o/--out as it is documented (it was "-o/--output" there too until 2026-12-07)
BAG = ("{option} here is a ROS 2 bag (a path without a suffix, or --format ros2-bag), which is a folder; give a "
       "new folder's path for the bag, or a file name whose suffix says its format (e.g. {example}.json)")
DEMO_FOLDER = ("-o/--output is the folder for the demo's report, figures, data and model; give a folder's path (a "
               "new one is created)")
# (arguments, the one line after "rlff: error: "): a device, a FIFO, a file or a socket where the
# output is of another kind; a folder output had said "is a file; give a folder" of them all
KINDS = {
    "learn --out a device": (["learn", "{raw}", "--basket", "2", "--out", "/dev/full"],
                             "/dev/full is a device, not a folder: " + BAG.format(option="-o/--out", example="learned")),
    "learn --out a FIFO": (["learn", "{raw}", "--basket", "2", "--out", "{pipe}"],
                           "{pipe} is a FIFO (named pipe), not a folder: " + BAG.format(option="-o/--out", example="learned")),
    "robot export -o a device": (["robot", "export", "{throw}", "-o", "/dev/null"],
                                 "/dev/null is a device, not a folder: " + BAG.format(option="-o/--output", example="throw")),
    "robot export -f ros2-bag -o a file": (["robot", "export", "{throw}", "-f", "ros2-bag", "-o", "{file}"],
                                           "{file} is a file, not a folder: " + BAG.format(option="-o/--output", example="throw")),
    "demo -o a device": (["demo", "--small", "-o", "/dev/null"], "/dev/null is a device, not a folder: " + DEMO_FOLDER),
    "demo -o a FIFO": (["demo", "--small", "-o", "{pipe}"], "{pipe} is a FIFO (named pipe), not a folder: " + DEMO_FOLDER),
    "demo -o a broken link": (["demo", "--small", "-o", "{link}"],
                              "{link} is a broken link (to {tmp}/nowhere), not a folder: " + DEMO_FOLDER),
    "sim throw --frames a FIFO": (["sim", "throw", "{throw}", "--basket", "2", "--frames", "{pipe}"],
                                  "{pipe} is a FIFO (named pipe), not a folder: --frames takes a folder; give a "
                                  "folder's path (a new one is created)"),
    "data synth -o a socket": (["data", "synth", "thesis", "-o", "{socket}"],
                               "{socket} is a socket, not a file: give a file name for -o/--output, e.g. {tmp}/data.csv"),
}


@pytest.mark.parametrize("case", list(KINDS))
def test_an_output_of_another_kind_is_refused_saying_what_it_is_and_what_goes_there(rlff, made, tmp_path, case):
    import socket

    os.mkfifo(tmp_path / "pipe")
    (tmp_path / "file").write_text("mine\n")
    (tmp_path / "link").symlink_to(tmp_path / "nowhere")
    with socket.socket(socket.AF_UNIX) as server:
        server.bind(str(tmp_path / "sock.csv"))
        paths = {"pipe": tmp_path / "pipe", "file": tmp_path / "file", "link": tmp_path / "link",
                 "socket": tmp_path / "sock.csv", "tmp": tmp_path}
        template, line = KINDS[case]
        result = rlff("-q", *[part.format(**made, **paths) for part in template])
        assert result.code == 2 and result.stderr.strip() == f"rlff: error: {line.format(**paths)}", result.stderr
        assert stat.S_ISFIFO(os.lstat(tmp_path / "pipe").st_mode) and stat.S_ISSOCK(os.lstat(tmp_path / "sock.csv").st_mode)
    assert (tmp_path / "file").read_text() == "mine\n" and (tmp_path / "link").is_symlink()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file", "link", "pipe", "sock.csv"]


def test_a_folder_output_may_end_in_a_slash(rlff, made, tmp_path):
    assert rlff("-q", "robot", "export", str(made["throw"]), "-o", f"{tmp_path / 'bag'}/").code == 0
    assert (tmp_path / "bag" / "metadata.yaml").is_file()


def test_json_output_is_strict_json_with_null_for_what_is_not_finite(capsys):
    """Python writes NaN and Infinity, which are no JSON: jq, browsers and strict parsers refuse
    them. A payload with them anywhere (numpy arrays included) prints them as null."""
    import json

    import numpy as np

    from rlff.cli._common import emit_json

    def strict(text):
        return json.loads(text, parse_constant=lambda name: pytest.fail(f"{name} in the JSON"))

    emit_json({"landing": float("nan"), "reach": [1.5, float("-inf")], "misses": np.array([np.nan, -0.25])})
    assert strict(capsys.readouterr().out) == {"landing": None, "reach": [1.5, None], "misses": [None, -0.25]}
    emit_json({"miss": -0.25, "hit": True})  # a finite payload prints as it is
    assert strict(capsys.readouterr().out) == {"miss": -0.25, "hit": True}


def test_a_ros2_bag_rlff_wrote_is_replaced_whole_by_export_and_learn(rlff, made, tmp_path):
    # "exists: a ROS 2 bag is a new folder, remove it first", where every output file is replaced
    from rlff.robot.export import read_bag

    bag = tmp_path / "bag"
    for period in ("0.002", "0.01"):
        result = rlff("-q", "robot", "export", str(made["throw"]), "-f", "ros2-bag", "-o", str(bag), "--period", period)
        assert result.code == 0, result.stderr
    assert np.median(np.diff(read_bag(bag)[0].time)) == pytest.approx(0.01)  # the second export's
    result = rlff("-q", "learn", str(made["raw"]), "--preset", "thesis", "--basket", "2", "--budget", "1", "--out", str(bag),
                  "--json")
    assert result.code == 0, result.stderr
    assert json.loads(result.stdout)["out"]["format"] == "ros2-bag"
    assert np.median(np.diff(read_bag(bag)[0].time)) == pytest.approx(0.002)  # learn's
    assert sorted(p.name for p in bag.iterdir()) == ["bag.db3", "metadata.yaml"]
    assert [p.name for p in tmp_path.iterdir()] == ["bag"]  # no temporary folder left


def test_a_ros2_bag_never_replaces_a_folder_that_is_no_bag_of_trajectories(rlff, made, tmp_path):
    bag = tmp_path / "bag"
    assert rlff("-q", "robot", "export", str(made["throw"]), "-o", str(bag)).code == 0
    (bag / "notes.txt").write_text("mine\n")  # a bag with the user's file beside it
    recording = tmp_path / "recording"  # a skeleton recording: /tf, no trajectory
    bf.write_ros2_bag(recording, bf.standard_simulation(seed=4, n_throws=1))
    empty = tmp_path / "empty"
    empty.mkdir()
    for folder in (bag, recording, empty):
        before = sorted((p.name, digest(p)) for p in folder.iterdir())
        for command in (["robot", "export", str(made["throw"]), "-f", "ros2-bag", "-o", str(folder)],
                        ["learn", str(made["raw"]), "--basket", "2", "--budget", "1", "--out", str(folder)]):
            result = rlff("-q", *command)
            assert result.code == 2 and result.stderr.strip() == (
                f"rlff: error: {folder}: a folder, and not a ROS 2 bag of robot trajectories (one rlff wrote is "
                "replaced whole): refusing to replace it; give a new folder name for the bag"), result.stderr
        assert sorted((p.name, digest(p)) for p in folder.iterdir()) == before


@pytest.mark.parametrize("file", ["robots/comau_smart5_six.toml", "presets/thesis.toml"])
def test_rlffs_own_files_are_no_outputs(rlff, tmp_path, file):
    # `rlff robot urdf -o .../rlff/robots/comau_smart5_six.toml` wrote URDF over the built-in robot,
    # and every command's default robot broke
    own = Path(str(resources.files("rlff") / file))
    before = own.read_bytes()
    link = tmp_path / "robot.toml"
    link.symlink_to(own)
    for target in (own, link):
        result = rlff("robot", "urdf", "-o", str(target))
        assert result.code == 2 and "is inside rlff's own package" in result.stderr, result.stderr
    assert own.read_bytes() == before


@pytest.mark.parametrize(("args", "line"), [
    (["fit", "{raw}", "-o", "-"], "-o/--output -: rlff writes a file there, not standard output: give its name "
                                  "(e.g. model.json), or /dev/stdout for its bytes"),
    (["robot", "export", "{throw}", "-o", "-"], "-o/--output -: rlff writes a file (or, without a suffix, a ROS 2 "
                                                "bag's folder) there, not standard output: give its name (e.g. throw.json)"),
    (["demo", "--small", "-o", "-"], "-o/--output -: rlff writes a folder there, not standard output: give its name"),
])
def test_an_output_named_dash_is_no_standard_output(rlff, made, tmp_path, monkeypatch, args, line):
    # fit and generate wrote a file named "-", robot export a ROS 2 bag folder named "-"
    monkeypatch.chdir(tmp_path)
    result = rlff("-q", *[part.format(**made) for part in args])
    assert result.code == 2 and result.stderr.strip() == f"rlff: error: {line}", result.stderr
    assert list(tmp_path.iterdir()) == []
