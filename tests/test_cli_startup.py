"""The command line starts without loading the heavy libraries its commands use.

Every ``rlff`` call (and every CLI test) pays for what ``import rlff.cli`` loads, so the command
modules import the library inside their commands. These checks are structural (which modules are
loaded), not timings.
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

HEAVY = ("numpy", "numba", "scipy.interpolate", "pandas", "mujoco", "matplotlib", "rosbags", "sklearn")

# Runs in a fresh interpreter: which heavy modules are loaded after the import, then after --help.
_PROBE = f"""
import contextlib, io, json, sys
heavy = {HEAVY!r}
loaded = lambda: sorted(name for name in heavy if name in sys.modules)
import rlff.cli
after_import = loaded()
with contextlib.redirect_stdout(io.StringIO()) as out:
    code = rlff.cli.main(["--help"])
print(json.dumps({{"import": after_import, "help": loaded(), "code": code, "usage": "Usage" in out.getvalue()}}))
"""


def test_import_and_help_load_no_heavy_library():
    proc = subprocess.run([sys.executable, "-c", _PROBE], capture_output=True, text=True, timeout=120, check=True)
    result = json.loads(proc.stdout)
    assert result["code"] == 0 and result["usage"], proc.stdout
    assert result["import"] == [], f"`import rlff.cli` loads {result['import']}"
    assert result["help"] == [], f"`rlff --help` loads {result['help']}"


def test_cli_copies_of_library_constants_match():
    from rlff.cli import robot as robot_cli
    from rlff.robot.description import DEFAULT_ROBOT
    from rlff.robot.formats import FORMATS

    assert robot_cli.DEFAULT_ROBOT == DEFAULT_ROBOT
    assert robot_cli.FORMATS == FORMATS


@pytest.mark.parametrize("name", ["Geometry", "Joint", "Robot", "RobotMapping", "available_robots", "load_robot"])
def test_robot_package_exports_resolve_lazily(name):
    import importlib

    import rlff.robot

    module = importlib.import_module(rlff.robot._EXPORTS[name])
    assert getattr(rlff.robot, name) is getattr(module, name)
    assert name in rlff.robot.__all__


def test_robot_package_unknown_name_is_an_attribute_error():
    import rlff.robot

    with pytest.raises(AttributeError, match="no_such_name"):
        rlff.robot.no_such_name  # noqa: B018
