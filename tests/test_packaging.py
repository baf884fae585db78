"""What pyproject.toml declares: the dependency floors rlff was run at, the files a wheel carries.

The floors are measured by hand, not here (a fresh venv per version is minutes of downloads): a
throwaway venv with the dependency at the version below and everything else from the project's
venv, then ``rlff --version``, ``rlff fit --help``, a usage error (``rlff fit --nope``) and
``rlff data synth throws`` / ``fit`` / ``generate`` / ``sim throw`` from outside the clone.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest
from packaging.requirements import Requirement
from packaging.version import Version

REPO = Path(__file__).resolve().parents[1]

#: The lowest version of each dependency every command above worked with, and what failed below it.
MEASURED_FLOORS = {
    # 0.12.0-0.12.5: "Type not yet supported: str | None" or "Secondary flag is not valid for
    # non-boolean flag" on every command; 0.13.0-0.15.3: --help fails with the click >= 8.2 they
    # install ("make_metavar() takes 1 positional argument but 2 were given"); 0.15.4 caps click
    # below 8.2, which lacks what the error boundary needs (next line)
    "typer": "0.16.0",
    # 8.1: no NoArgsIsHelpError, which rlff.cli's error boundary tells apart (every usage error
    # became an internal error)
    "click": "8.2.0",
    "rich": "13.0.0",  # with typer 0.16.0 and click 8.2.0
}


def _project() -> dict:
    return tomllib.loads((REPO / "pyproject.toml").read_text(encoding="utf-8"))["project"]


def _floor(requirement: Requirement) -> Version | None:
    floors = [Version(spec.version) for spec in requirement.specifier if spec.operator in (">=", "==")]
    return max(floors) if floors else None


@pytest.mark.parametrize("name", sorted(MEASURED_FLOORS))
def test_dependency_floor_is_one_rlff_works_with(name):
    declared = {Requirement(line).name: Requirement(line) for line in _project()["dependencies"]}
    assert name in declared, f"rlff imports {name} but pyproject.toml does not declare it"
    floor = _floor(declared[name])
    assert floor is not None and floor >= Version(MEASURED_FLOORS[name]), (
        f"pyproject.toml lets pip install {name} {floor}, below {MEASURED_FLOORS[name]}, the first "
        "version rlff's commands were seen to work with")
