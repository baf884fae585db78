"""Installing live ROS into a venv the way a wheel's user does, and what ``missing()`` tells them.

The ROS 1 install runs for real in a fresh venv of its own (Debian's ROS 1 packages linked, the
control_msgs messages built, imported by a fresh interpreter), which sees the project's packages
and rlff through a ``.pth`` file but not the project venv's own ROS 1 folder.
"""

from __future__ import annotations

import os
import subprocess
import sys
import sysconfig
import venv
from pathlib import Path

import pytest

import rlff
from rlff.robot.ros1.install import DEBIAN_PACKAGES, DIST_PACKAGES

REPO = Path(__file__).resolve().parents[1]
_MISSING = "from rlff.robot import ros{version}; print(ros{version}.missing() or '')"


def _fresh_venv(root: Path) -> Path:
    """A venv at ``root`` with no ROS 1 folder that imports the project venv's packages and this
    rlff; returns its Python."""
    venv.EnvBuilder(with_pip=False).create(root)
    python = root / "bin" / "python"
    site = subprocess.run([str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                          capture_output=True, text=True, check=True).stdout.strip()
    project = [str(Path(rlff.__file__).resolve().parents[1]), sysconfig.get_paths()["purelib"]]
    (Path(site) / "a-project.pth").write_text("\n".join(project) + "\n")
    return python


def _run(python: Path, *args: str, env: dict | None = None) -> subprocess.CompletedProcess:
    clean = {key: value for key, value in os.environ.items() if key != "PYTHONPATH"}
    return subprocess.run([str(python), *args], capture_output=True, text=True, timeout=600,
                          env={**clean, **(env or {})})


@pytest.mark.ros
@pytest.mark.integration
@pytest.mark.slow
def test_ros1_install_makes_a_fresh_venv_reach_ros1_as_missing_says(tmp_path):
    if not (DIST_PACKAGES / "rospy").is_dir():
        reason = f"Debian's ROS 1 packages are not installed ({DIST_PACKAGES / 'rospy'} is absent)"
        pytest.fail(reason) if os.environ.get("CI") == "true" else pytest.skip(reason)
    python = _fresh_venv(tmp_path / "venv")
    before = _run(python, "-c", _MISSING.format(version=1))
    assert before.returncode == 0, before.stderr
    said = before.stdout.strip()
    assert said.startswith("ROS 1 is not reachable"), said
    assert "sudo apt install ros-core python3-rospy" in said and "`python -m rlff.robot.ros1.install`" in said, said

    installed = _run(python, "-m", "rlff.robot.ros1.install")
    assert installed.returncode == 0, installed.stderr
    assert "ROS 1 reachable from" in installed.stdout, installed.stdout
    after = _run(python, "-c", _MISSING.format(version=1) + "; import rospy; print(rospy.__file__)")
    assert after.returncode == 0, after.stderr
    assert after.stdout.splitlines() == ["", str(tmp_path / "venv" / "ros1" / "rospy" / "__init__.py")]

    again = _run(python, "-m", "rlff.robot.ros1.install")  # safe to run again
    assert again.returncode == 0, again.stderr


def test_ros1_install_outside_a_venv_is_refused_with_what_to_run():
    base = Path(sys.base_prefix) / "bin" / f"python{sys.version_info.major}.{sys.version_info.minor}"
    refused = _run(base, "-m", "rlff.robot.ros1.install", env={"PYTHONPATH": str(Path(rlff.__file__).parents[1])})
    assert refused.returncode == 1, refused.stderr
    assert "is not a virtual environment's Python" in refused.stderr, refused.stderr


def test_ros2_missing_names_the_extra_and_the_install_module(tmp_path):
    stub = tmp_path / "absent" / "rclpy"
    stub.mkdir(parents=True)
    (stub / "__init__.py").write_text('raise ModuleNotFoundError("No module named \'rclpy\'", name="rclpy")\n')
    path = os.pathsep.join([str(stub.parent), str(Path(rlff.__file__).parents[1])])
    said = _run(Path(sys.executable), "-c", _MISSING.format(version=2), env={"PYTHONPATH": path})
    assert said.returncode == 0, said.stderr
    line = said.stdout.strip()
    assert line.startswith("ROS 2 is not reachable"), line
    assert "`pip install 'rlff[ros2]'`" in line and "`python -m rlff.robot.ros2.install`" in line, line


def test_the_debian_packages_ros1_install_names_are_those_the_set_up_installs():
    listed = {line.split("#")[0].strip() for line in (REPO / "scripts" / "debian-packages.txt").read_text().splitlines()}
    assert set(DEBIAN_PACKAGES) <= listed, set(DEBIAN_PACKAGES) - listed
