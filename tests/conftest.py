"""Shared fixtures: running the real ``rlff`` entry point and locating the shared data."""

from __future__ import annotations

import os
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
SHARED_DATA = REPO.parent / "shared" / "data"
MSR_THROWS = SHARED_DATA / "msr-action3d-throws"


@dataclass
class CliResult:
    code: int
    stdout: str
    stderr: str


def run_cli(*args: str, cwd: Path | None = None, timeout: float = 300, env: dict | None = None) -> CliResult:
    """Run ``rlff ARGS`` as a separate process through the installed entry point."""
    full_env = dict(os.environ)
    full_env.update(env or {})
    full_env.setdefault("MPLBACKEND", "Agg")
    proc = subprocess.run(
        [sys.executable, "-m", "rlff", *args],
        capture_output=True,
        text=True,
        cwd=cwd,
        timeout=timeout,
        env=full_env,
    )
    return CliResult(proc.returncode, proc.stdout, proc.stderr)


@pytest.fixture
def cli():
    """``cli(*args)`` runs the real command line in a subprocess and returns a CliResult."""
    return run_cli


@pytest.fixture
def rlff(capsys):
    """``rlff(*args)``: the real entry point (``rlff.cli.main``) in this process, which saves the
    interpreter start and the imports of a subprocess per call; returns a CliResult."""
    from rlff.cli import main

    def run(*args: str) -> CliResult:
        capsys.readouterr()
        code = main(list(args))
        captured = capsys.readouterr()
        return CliResult(code, captured.out, captured.err)

    return run


@pytest.fixture
def msr_dir() -> Path:
    """The real MSR Action3D throwing recordings; skips when the shared folder is absent."""
    if not MSR_THROWS.is_dir():
        pytest.skip(f"{MSR_THROWS} is absent")
    return MSR_THROWS


@pytest.fixture(scope="session")
def msr_throws(tmp_path_factory):
    """The real MSR Action3D throws as a user gets them: imported (elbow, shoulder and wrist,
    with the landings estimated from the hand's release) and cleaned by the thesis preset through
    the command line; skips when the shared folder is absent."""
    if not MSR_THROWS.is_dir():
        pytest.skip(f"{MSR_THROWS} is absent")
    folder = tmp_path_factory.mktemp("msr")
    imported = run_cli("data", "import", *map(str, sorted(MSR_THROWS.glob("a06_*.txt"))), "--format", "msr", "-o",
                       str(folder / "msr.csv"))
    assert imported.code == 0, imported.stderr
    cleaned = run_cli("data", "preprocess", str(folder / "msr.csv"), "--preset", "thesis", "-o",
                      str(folder / "clean.csv"))
    assert cleaned.code == 0, cleaned.stderr
    from rlff.formats import read_dataset

    demos = read_dataset(folder / "clean.csv")
    assert {"shoulder", "shoulder_velocity", "wrist", "wrist_velocity"} <= set(demos.columns)
    return demos
