"""The rules of a demo's output folder (:mod:`rlff.report.folder`) on folders of real files: what
a run lists as its own, what the next run removes, what it refuses, and the lock; the demo's own
names (:data:`rlff.demo.WRITES`) and the files a run writes (:func:`rlff.demo.run_files`). The
demo itself: ``test_demo_folder.py``."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from rlff.demo import FIGURES, PROGRAM, WRITES, run_files
from rlff.errors import InputError
from rlff.report.folder import LISTING, LOCK, FolderInUse, RunFolder, check_run_folder


def _write(folder: RunFolder, relative: str, text: str) -> Path:
    path = folder.file(relative)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    return path


def test_a_finished_runs_files_are_replaced_only_as_it_wrote_them(tmp_path):
    with RunFolder(tmp_path, WRITES, PROGRAM) as run:
        _write(run, "demos.csv", "the demo's")
        _write(run, "figures/learning.png", "the demo's")
        run.finish()
    (tmp_path / "figures" / "learning.png").write_text("edited since")
    with pytest.raises(InputError, match=r"holds 1 file rlff demo would write that the last rlff demo there did not write, or changed since: "
                                         r"figures/learning\.png \(changed since rlff demo wrote it\); nothing was "
                                         r"written or removed: move or remove those files, or give another folder with -o$"):
        RunFolder(tmp_path, WRITES, PROGRAM)
    assert (tmp_path / "figures" / "learning.png").read_text() == "edited since"
    assert (tmp_path / "demos.csv").read_text() == "the demo's"  # nothing removed before the refusal
    (tmp_path / "figures" / "learning.png").write_text("the demo's")  # as the demo wrote it again
    with RunFolder(tmp_path, WRITES, PROGRAM):  # removed, and the figures folder they leave empty
        assert not (tmp_path / "demos.csv").exists() and not (tmp_path / "figures").exists()


def test_a_stopped_runs_listed_files_and_folders_are_its_own_and_nothing_else_is(tmp_path):
    with RunFolder(tmp_path, WRITES, PROGRAM) as run:  # stopped: never finished
        _write(run, "attempts/calibrate.jsonl", "the demo's")
        frames = run.folder("figures/frames")
        frames.mkdir(parents=True)
        (frames / "frame_0000.png").write_text("the demo's")
    (tmp_path / "attempts" / "whole-arm").mkdir()
    (tmp_path / "attempts" / "whole-arm" / "2m-0deg.jsonl").write_text("mine")
    (tmp_path / "notes.txt").write_text("mine, of no name the demo writes")
    with pytest.raises(InputError, match=r"did not write: attempts/whole-arm/2m-0deg\.jsonl; nothing was"):
        RunFolder(tmp_path, WRITES, PROGRAM)
    (tmp_path / "attempts" / "whole-arm" / "2m-0deg.jsonl").unlink()
    with RunFolder(tmp_path, WRITES, PROGRAM):
        left = sorted(p.relative_to(tmp_path).as_posix() for p in tmp_path.rglob("*") if p.is_file())
        assert left == [LISTING, LOCK, "notes.txt"]


def test_a_listing_names_only_files_of_the_demos_names_to_remove(tmp_path):
    """A listing written by hand (or damaged) cannot make a run remove other files."""
    (tmp_path / "notes.txt").write_text("mine")
    (tmp_path / LISTING).write_text(json.dumps({"format": "rlff-run-files", "version": 1, "finished": False,
                                                "files": {"notes.txt": None, "../outside.csv": None, "/": None}}))
    with RunFolder(tmp_path, WRITES, PROGRAM) as run:
        assert (tmp_path / "notes.txt").read_text() == "mine"
        with pytest.raises(ValueError, match="notes.txt: not among the files this rlff demo said it would write"):
            run.file("notes.txt")


def test_a_folder_held_by_a_run_is_refused_naming_it(tmp_path):
    from rlff.demo import check_demo_options

    with RunFolder(tmp_path, WRITES, PROGRAM):
        assert f"rlff demo, pid {os.getpid()} on host " in (tmp_path / LOCK).read_text()
        with pytest.raises(FolderInUse, match=f"is in use by rlff demo, pid {os.getpid()} on host "):
            check_demo_options(tmp_path, "small")
        with pytest.raises(FolderInUse):
            RunFolder(tmp_path, WRITES, PROGRAM)
    check_demo_options(tmp_path, "small")


def test_a_users_file_the_run_does_not_write_is_left_alone_and_one_it_writes_is_refused(tmp_path):
    """Files of the demo's kinds of names that this run writes under no name (a figure, a log of
    the user's; a full run's log, the frames of a run with frames, for a small run without) had
    made the folder refused, though the run would not have touched them."""
    small = run_files("small", frames=False)
    mine = {name: f"mine: {name}" for name in ("figures/mine.png", "attempts/notes.jsonl",
                                                "attempts/whole-arm/notes.jsonl", "attempts/hindsight.jsonl",
                                                "figures/frames/frame_0000.png", "figures/frames/notes.png")}
    for name, text in mine.items():
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text(text)
    with RunFolder(tmp_path, small, PROGRAM, names=WRITES) as run:
        _write(run, "figures/learning.png", "the demo's")
        with pytest.raises(ValueError, match=r"figures/mine\.png: not among the files this rlff demo said"):
            run.file("figures/mine.png")
        run.finish()
    assert {name: (tmp_path / name).read_text() for name in mine} == mine
    with RunFolder(tmp_path, small, PROGRAM, names=WRITES):  # the demo's removed, the user's kept
        assert not (tmp_path / "figures" / "learning.png").exists()
    assert {name: (tmp_path / name).read_text() for name in mine} == mine
    (tmp_path / "figures" / "learning.png").write_text("mine, of a name the run writes")
    with pytest.raises(InputError, match=r"did not write: figures/learning\.png; nothing was"):
        RunFolder(tmp_path, small, PROGRAM, names=WRITES)
    assert (tmp_path / "figures" / "learning.png").read_text() == "mine, of a name the run writes"


def test_a_file_of_the_last_run_changed_since_is_refused_only_by_a_run_that_writes_it(tmp_path):
    """The full run's hindsight log, gone on with by `rlff learn --log`: a small run, which runs no
    hindsight, neither removes nor refuses it; a full run, which would replace it, refuses."""
    with RunFolder(tmp_path, run_files("full", frames=False), PROGRAM, names=WRITES) as run:
        _write(run, "attempts/hindsight.jsonl", "the demo's")
        _write(run, "attempts/calibrate.jsonl", "the demo's")
        run.finish()
    (tmp_path / "attempts" / "hindsight.jsonl").write_text("the demo's, and the user's attempts after")
    with RunFolder(tmp_path, run_files("small", frames=False), PROGRAM, names=WRITES):
        left = sorted(p.relative_to(tmp_path).as_posix() for p in tmp_path.rglob("*") if p.is_file())
        assert left == [LISTING, LOCK, "attempts/hindsight.jsonl"]
    with pytest.raises(InputError, match=r"did not write: attempts/hindsight\.jsonl; nothing was"):  # not the last run's now
        RunFolder(tmp_path, run_files("full", frames=False), PROGRAM, names=WRITES)


def test_every_file_a_run_writes_is_of_the_demos_names(tmp_path):
    """Else the next run could not remove it: its listing names only files of WRITES."""
    with pytest.raises(ValueError, match=r"notes\.txt: not of the names rlff demo writes"):
        check_run_folder(tmp_path / "missing", [*run_files("small"), "notes.txt"], PROGRAM, names=WRITES)
    for size in ("full", "small"):
        check_run_folder(tmp_path / "missing", run_files(size), PROGRAM, names=WRITES)


def test_an_older_demos_folder_is_refused_once_naming_every_file_and_what_to_do(tmp_path):
    """A demo before the listing wrote none: its folder's files are refused (they may be the
    user's), and the refusal had named five of them and counted the rest ("and 79 more"), as
    files the demo 'did not write there', for the user to move or remove."""
    small = run_files("small")
    older = [name for name in small if not name.startswith("figures/frames/")]
    older += [f"figures/frames/frame_{number:04d}.png" for number in range(38)] + ["figures/frames/throw.gif"]
    for name in older:
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text("an older demo's")
    (tmp_path / "notes.txt").write_text("mine")

    with pytest.raises(InputError) as refused:
        RunFolder(tmp_path, small, PROGRAM, names=WRITES)
    figures = ", ".join(f"{stem}.{suffix}" for stem in sorted(FIGURES) for suffix in ("png", "svg"))
    assert str(refused.value) == (
        f"{tmp_path}: holds {len(older)} files rlff demo would write, and no list of the files a run of rlff demo "
        "wrote there (.rlff-run; an rlff demo older than that list kept none), so it cannot tell them from files "
        "of yours: clean.csv, demos.csv, model.json, report.html, run.json, whole-arm-clean.csv, "
        "whole-arm-demos.csv, attempts/ (calibrate.jsonl, calibrate.jsonl.lock, imitation.jsonl, "
        "imitation.jsonl.lock), attempts/whole-arm/ (2m-0deg.jsonl, 2m-0deg.jsonl.lock, 3.75m-60deg.jsonl, "
        "3.75m-60deg.jsonl.lock, 4.5m-90deg.jsonl, 4.5m-90deg.jsonl.lock), "
        f"figures/ ({figures}), figures/frames/ (frame_0000.png to frame_0037.png, throw.gif); nothing was "
        "written or removed: if an older rlff demo wrote them, remove them (or move them out of the folder) and "
        "run rlff demo again; if any are yours, move them, or give another folder with -o")
    assert sorted(p.relative_to(tmp_path).as_posix() for p in tmp_path.rglob("*") if p.is_file()) == sorted(
        [*older, "notes.txt", LOCK])  # nothing written but the lock it tried, nothing removed
    for name in older:  # as the refusal says: the older demo's files removed, the run goes ahead
        (tmp_path / name).unlink()
    with RunFolder(tmp_path, small, PROGRAM, names=WRITES):
        assert (tmp_path / "notes.txt").read_text() == "mine"
