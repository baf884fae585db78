"""A package rlff declares that this Python lacks is said by name with its ``pip install``, exit 1.

The missing package is real absence as the importer sees it: a ``mujoco`` package first on the
path whose import raises the ModuleNotFoundError Python raises for a module that is not there.
"""

from __future__ import annotations

import os

from generated_paths import generated_path
from rlff.cli.missing_package import declared_packages, missing_package_line

_ABSENT = 'raise ModuleNotFoundError("No module named {name!r}", name={name!r})\n'


def _without(tmp_path, name: str) -> dict[str, str]:
    """An environment whose Python finds no ``name`` (a package that raises as a missing one)."""
    stub = tmp_path / "absent" / name
    stub.mkdir(parents=True)
    (stub / "__init__.py").write_text(_ABSENT.format(name=name))
    return {"PYTHONPATH": os.pathsep.join([str(stub.parent), os.environ.get("PYTHONPATH", "")])}


def test_sim_throw_without_mujoco_names_the_package_and_its_install(cli, tmp_path):
    throw = generated_path(tmp_path / "traj.csv")
    result = cli("sim", "throw", str(throw), "--basket", "1.9", "--json", env=_without(tmp_path, "mujoco"))
    assert result.code == 1, result.stderr
    assert result.stdout == ""
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith("rlff: error: this command needs the Python package mujoco"), lines[0]
    assert "`pip install mujoco`" in lines[0]
    assert "internal error" not in lines[0] and "bug" not in lines[0]


def test_an_extras_package_names_the_extra():
    line = missing_package_line(ModuleNotFoundError("No module named 'distributed'", name="distributed"))
    assert line is not None and "`pip install 'rlff[cluster]'`" in line, line


def test_a_package_whose_import_name_differs_is_found_by_it():
    line = missing_package_line(ModuleNotFoundError("No module named 'sklearn'", name="sklearn.mixture"))
    assert line is not None and "`pip install scikit-learn`" in line, line
    assert declared_packages()["PIL"][0].lower() == "pillow"


def test_a_module_rlff_does_not_declare_is_still_a_bug():
    assert missing_package_line(ModuleNotFoundError("No module named 'nowhere'", name="nowhere")) is None
