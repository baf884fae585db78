"""What pyproject.toml and MANIFEST.in declare: the dependency floors rlff was run at, the one
place the version is written, the files a wheel and an sdist carry.

The floors are measured by hand, not here (a fresh venv per version is minutes of downloads): a
throwaway venv with the dependency at the version below and everything else from the project's
venv, then ``rlff --version``, ``rlff fit --help``, a usage error (``rlff fit --nope``) and
``rlff data synth throws`` / ``fit`` / ``generate`` / ``sim throw`` from outside the clone.
The sdist's files are what setuptools' own reading of MANIFEST.in gives (a build with
``python -m build --sdist`` needs setuptools 77, newer than the project venv's).
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


def _setuptools_config() -> dict:
    return tomllib.loads((REPO / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["setuptools"]


def test_every_package_data_pattern_matches_a_file():
    patterns = _setuptools_config()["package-data"]["rlff"]
    empty = [pattern for pattern in patterns if not list((REPO / "src" / "rlff").glob(pattern))]
    assert not empty, f"package-data patterns that match no file under src/rlff: {empty}"


def test_the_version_is_written_once_in_rlff():
    import rlff

    project = _project()
    assert "version" not in project and "version" in project.get("dynamic", []), (
        "pyproject.toml writes the version itself: it is rlff.__version__'s to say")
    assert _setuptools_config()["dynamic"]["version"] == {"attr": "rlff.__version__"}
    assert Version(rlff.__version__)  # a version pip accepts


def test_the_sdist_holds_what_a_test_run_and_the_readme_need(monkeypatch):
    from setuptools.command.egg_info import FileList

    manifest = REPO / "MANIFEST.in"
    assert manifest.is_file(), "no MANIFEST.in: the sdist holds tests/test_*.py without their conftest and data"
    monkeypatch.chdir(REPO)
    files = FileList()
    files.findall()
    for line in manifest.read_text(encoding="utf-8").splitlines():
        if line.strip() and not line.lstrip().startswith("#"):
            files.process_template_line(line)
    held = set(files.files)
    needed = {"tests/conftest.py", "scripts/setup.sh", "scripts/debian-packages.txt", ".ci/run"}
    for pattern in ("tests/*.py", "tests/data/*", "docs/*.md", "docs/figures/*", "scripts/setup.d/*.sh",
                    "benchmarks/*.py"):
        found = {path.relative_to(REPO).as_posix() for path in REPO.glob(pattern)}
        assert found, pattern
        needed |= found
    assert not needed - held, f"the sdist would lack {sorted(needed - held)}"
    caches = sorted(path for path in held if path.endswith((".pyc", ".nbi", ".nbc")))
    assert not caches, f"the sdist would hold compiled caches: {caches[:5]}"
