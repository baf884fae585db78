"""kill -9 at random moments of ``data import``, ``data preprocess``, ``fit`` and ``data synth
throws`` never leaves a partial output: the file is the previous one, byte for byte, or the complete new one.

Each command runs in a process of its own over an existing output, forked from this one once
the libraries are loaded (so that a trial costs the command's work, not the interpreter's start),
and killed with SIGKILL. Half of the trials kill it at a random moment of its whole run; the other
half watch its folder and kill it a random few milliseconds after it starts writing (its temporary
file appears, or the output changes), that is inside the write itself. A kill leaves at most a hidden temporary file beside the
output, never a cut output.
"""

from __future__ import annotations

import os
import random
import signal
import sys
import time
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))

import bagfactory as bf  # noqa: E402

pytestmark = pytest.mark.slow

TRIALS = 20
OLD = b"trajectory,angle\nthe previous complete output,1\n"


class _Command:
    """``rlff -q ARGS`` in a forked child process: poll(), kill(), wait() like a Popen."""

    def __init__(self, args: list[str]):
        from rlff.cli import main

        self.code: int | None = None
        self.pid = os.fork()
        if self.pid == 0:  # the child: run the command, never return into pytest
            code = 1
            try:
                devnull = os.open(os.devnull, os.O_WRONLY)
                os.dup2(devnull, 1)
                os.dup2(devnull, 2)
                code = main(["-q", *args])
            finally:
                os._exit(code)

    def _reap(self, flags: int) -> int | None:
        if self.code is None:
            pid, status = os.waitpid(self.pid, flags)
            if pid:
                self.code = os.waitstatus_to_exitcode(status)
        return self.code

    def poll(self) -> int | None:
        return self._reap(os.WNOHANG)

    def kill(self) -> None:
        os.kill(self.pid, signal.SIGKILL)

    def wait(self) -> int:
        return self._reap(0)


def _start(args: list[str]) -> _Command:
    return _Command(args)


def _writing(out: Path) -> bool:
    """The command has started writing: its temporary file is there, or the output itself changed."""
    changed = not out.exists() or out.stat().st_size != len(OLD)
    return changed or any(name.startswith(f".{out.stem}.") for name in os.listdir(out.parent))


def _kill_trials(args: list[str], out: Path, seed: int) -> dict[str, int]:
    """Run ``args`` (writing ``out``) TRIALS times, killing it; returns what the trials saw."""
    from rlff.cli import main

    assert main(["-q", *args]) == 0  # loads every library the command needs before the forks
    done = _start(args)
    started = time.monotonic()
    assert done.wait() == 0
    duration = time.monotonic() - started
    new = out.read_bytes()
    assert new != OLD
    rng = random.Random(seed)
    seen = {"old": 0, "new": 0, "killed": 0, "killed while writing": 0}
    for trial in range(TRIALS):
        out.write_bytes(OLD)
        for stale in out.parent.glob(f".{out.stem}.*"):
            stale.unlink()
        process = _start(args)
        writing = False
        if trial % 2:  # inside the write: a few ms after the temporary file appears
            while process.poll() is None and not _writing(out):
                time.sleep(0.0002)
            writing = process.poll() is None
            time.sleep(rng.uniform(0.0, 0.004))
        else:  # anywhere in the run
            time.sleep(rng.uniform(0.0, duration * 1.1))
        if process.poll() is None:
            process.kill()
            seen["killed"] += 1
            seen["killed while writing"] += writing
        process.wait()
        content = out.read_bytes()
        assert content in (OLD, new), f"trial {trial}: {len(content)} bytes, neither the old file nor the new"
        seen["old" if content == OLD else "new"] += 1
    return seen


@pytest.fixture(scope="module")
def inputs(tmp_path_factory) -> dict[str, Path]:
    from rlff.cli import main

    folder = tmp_path_factory.mktemp("kill")
    bag = bf.write_ros1_bag(folder / "six.bag", bf.standard_simulation(seed=5, n_throws=6))
    demos = folder / "demos.csv"
    assert main(["-q", "data", "synth", "throws", "--subjects", "4", "-o", str(demos)]) == 0
    return {"bag": bag, "demos": demos}


@pytest.mark.parametrize(
    ("name", "command"),
    [
        ("data import", lambda i, out: ["data", "import", str(i["bag"]), "-o", str(out)]),
        ("data preprocess", lambda i, out: ["data", "preprocess", str(i["demos"]), "--preset", "thesis", "-o", str(out)]),
        ("fit", lambda i, out: ["fit", str(i["demos"]), "--max-components", "3", "-o", str(out)]),
        ("data synth throws", lambda i, out: ["data", "synth", "throws", "--subjects", "4", "-o", str(out)]),
    ],
)
def test_kill_9_never_leaves_a_partial_output(inputs, tmp_path, name, command):
    out = tmp_path / ("model.json" if name == "fit" else "out.csv")
    seen = _kill_trials(command(inputs, out), out, seed=len(name))
    assert seen["old"] + seen["new"] == TRIALS
    assert seen["killed"] >= TRIALS // 2, seen  # the trials did interrupt the command
    assert seen["killed while writing"] >= 1, seen  # and some of them inside the write
