"""``rlff demo -o DIR`` replaces only what an earlier demo wrote in DIR, and one run at a time.

The user's own files under the demo's names (an attempts log of ``rlff learn``, a figure, a
``run.json`` of ``write_run``) had been replaced with exit 0; a small demo after a full one had
left the full one's logs beside its own; two demos into one folder had both ended with exit 0,
the first printing results the folder no longer held. The folder's listing and lock are
:mod:`rlff.report.folder`'s (its rules: ``test_demo_folder_rules.py``); the tests here run the
real demo, through its entry point where they can."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time

import pytest

from rlff.report.folder import LISTING

DEMO = ("demo", "--small", "--no-frames")
#: The lock a run holds its folder with, as docs/demo.md names it.
LOCK = ".rlff-run.lock"


def _one_line_error(result, *fragments: str) -> str:
    assert result.code == 2, (result.code, result.stdout, result.stderr)
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("rlff: error: "), result.stderr
    for fragment in fragments:
        assert fragment in lines[0], (fragment, lines[0])
    return lines[0]


@pytest.mark.integration
def test_the_users_own_attempts_log_figure_and_run_json_in_the_folder_are_refused_and_kept(rlff, tmp_path):
    """The tester's folder: an attempts log and a figure of the user's under the demo's names, and
    a run.json of their own (docs/report.md's write_run), which had let the demo replace them all."""
    from attempts_logs import write_attempts_log
    from rlff.report import Run, Section, write_run

    mine = tmp_path / "mine"
    for folder in ("attempts", "figures"):
        (mine / folder).mkdir(parents=True)
    log = write_attempts_log(mine / "attempts" / "calibrate.jsonl",
                             {"basket": {"distance": 1.3}, "update": "donut"}, [-0.3, 0.05])
    figure = mine / "figures" / "learning.png"
    figure.write_bytes(b"my figure")
    write_run(Run("my run", "2026-12-06T10:00:00+00:00", {}, [Section("s", "S")], []), mine)
    before = {path: path.read_bytes() for path in (log, figure, mine / "run.json")}

    result = rlff(*DEMO, "-o", str(mine))
    _one_line_error(result, f"{mine}: holds 3 files rlff demo would write, and no list of the files a run of "
                            "rlff demo wrote there (.rlff-run; ", "so it cannot tell them from files of yours: "
                            "run.json, attempts/calibrate.jsonl, figures/learning.png; nothing was written or removed: ")
    assert {path: path.read_bytes() for path in before} == before
    assert not (mine / "demos.csv").exists()


@pytest.mark.integration
def test_the_users_files_of_names_the_demo_does_not_write_are_left_alone_and_the_demo_runs(cli, rlff, tmp_path):
    """A figure and attempts logs of the user's beside the demo's, and frames a run without
    --frames does not draw: the folder had been refused for names like the demo's, though the
    run would have touched none of them. The run is the suite's demo in human words (each demo run
    takes a minute): with -q its summary table and no progress display."""
    from rlff.demo import STAGES

    out = tmp_path / "demo"
    mine = {out / name: f"mine: {name}".encode() for name in (
        "figures/mine.png", "figures/mine.svg", "attempts/notes.jsonl", "attempts/whole-arm/notes.jsonl",
        "figures/frames/frame_0000.png", "figures/frames/throw.gif")}
    for path, content in mine.items():
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(content)

    result = cli("-q", *DEMO, "-o", str(out), timeout=600)
    assert result.code == 0, result.stderr
    for fragment in ("simulated throws", "executed in MuJoCo", "Learning from failure at", "Whole-arm learning",
                     "report:"):
        assert fragment in result.stdout
    assert f"{len(STAGES)}/{len(STAGES)}" not in result.stderr  # -q: no progress display
    assert {path: path.read_bytes() for path in mine} == mine
    assert (out / "report.html").is_file() and (out / "attempts" / "calibrate.jsonl").is_file()
    listed = json.loads((out / LISTING).read_text())["files"]
    assert not {path.relative_to(out).as_posix() for path in mine} & set(listed)  # nor taken for the demo's
    (out / "figures" / "learning.png").write_bytes(b"edited: mine now")  # a name it writes: refused
    _one_line_error(rlff(*DEMO, "-o", str(out)), "figures/learning.png (changed since rlff demo wrote it)")
    assert {path: path.read_bytes() for path in mine} == mine


@pytest.mark.slow
def test_a_small_demo_after_a_full_one_leaves_none_of_the_full_runs_files(tmp_path):
    """The full demo's learning runs log hindsight, failure and secant, which the small one does
    not run: their logs had stayed beside the small run's, to be read as its own."""
    from rlff.demo import run_demo

    def stop_at(words: str):
        def progress(stage: str, done: int, total: int) -> None:
            if words in stage:
                raise KeyboardInterrupt
        return progress

    out = tmp_path / "demo"
    with pytest.raises(KeyboardInterrupt):  # the full run, stopped at hindsight's first attempt
        run_demo(out, size="full", frames=False, progress=stop_at("hindsight, attempt 1"))
    assert (out / "attempts" / "hindsight.jsonl").is_file()
    with pytest.raises(KeyboardInterrupt):  # the small run, stopped as it starts its first stage
        run_demo(out, size="small", frames=False, progress=stop_at("simulating"))
    left = sorted(p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_file())
    assert [name for name in left if name.startswith("attempts/")] == []  # the full run's logs
    assert left == [LISTING, LOCK]  # nor any other file of it; the listing is the small run's, empty yet
    assert json.loads((out / LISTING).read_text())["files"] == {}


@pytest.mark.integration
@pytest.mark.timeout(300)  # a second run let through would run the whole demo
def test_a_second_demo_into_a_folder_in_use_is_refused_at_once_naming_the_first(rlff, tmp_path):
    """Two demos into one folder: the second had run to the end too, over the first's files."""
    out = tmp_path / "demo"
    env = {**os.environ, "MPLBACKEND": "Agg"}
    first = subprocess.Popen([sys.executable, "-m", "rlff", "-q", *DEMO, "-o", str(out)], env=env,
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 120
        # the first run is under way: it holds the folder (or, without the lock, wrote its first file)
        while not ((out / LOCK).is_file() and (out / LOCK).read_text()) and not (out / "demos.csv").exists():
            assert first.poll() is None, first.stderr.read()
            assert time.monotonic() < deadline, "the first demo did not start"
            time.sleep(0.1)
        result = rlff(*DEMO, "-o", str(out))
        _one_line_error(result, f"{out} is in use by rlff demo, pid {first.pid} on host ",
                        f"(lock file {out / LOCK}); wait for that run to end, or give another folder with -o")
        # refused without disturbing the first: it runs on, holding the folder
        assert first.poll() is None and f"pid {first.pid} " in (out / LOCK).read_text()
    finally:
        first.send_signal(signal.SIGINT)
        first.communicate(timeout=120)
    assert first.returncode == 130
    assert (out / LOCK).read_text() == ""  # released: the next run may take the folder
