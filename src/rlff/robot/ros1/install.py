"""Making Debian's ROS 1 reachable from a venv: its Python packages, and control_msgs built.

Run as ``python -m rlff.robot.ros1.install`` with the venv's Python, after installing Debian's
ROS 1 packages (:data:`DEBIAN_PACKAGES`: ``sudo apt install ...``); ``scripts/setup.d/10-ros.sh``
runs it for a clone. Three steps, safe to run again:

1. The venv must keep its own numpy and friends, so never all of ``/usr/lib/python3/dist-packages``
   is put on its path: only a folder of symlinks to the ROS packages rlff uses and what they
   import (:data:`PACKAGES`), ``<venv>/ros1`` (where :func:`rlff.robot.rospath.prefer` looks),
   appended LAST to the venv's ``sys.path`` by a ``rlff-ros1.pth`` file in its site-packages.
2. control_msgs, which Debian does not package, is built into that folder
   (:mod:`rlff.robot.ros1.msgs`).
3. A fresh interpreter of the venv imports rospy, actionlib and the FollowJointTrajectory action,
   and its numpy is still the venv's.
"""

from __future__ import annotations

import subprocess
import sys
import sysconfig
from pathlib import Path

from rlff.robot.rospath import ros1_folder

#: Where Debian installs ROS 1's Python packages.
DIST_PACKAGES = Path("/usr/lib/python3/dist-packages")
#: The Debian packages live ROS 1 needs (scripts/debian-packages.txt lists them for a clone).
DEBIAN_PACKAGES = (
    "ros-core", "python3-rospy", "python3-actionlib", "python3-actionlib-msgs",
    "python3-trajectory-msgs", "python3-sensor-msgs", "python3-std-msgs", "python3-genmsg",
    "python3-genpy", "python3-rosbag",
)
#: The Python packages of :data:`DIST_PACKAGES` linked into the venv's ROS 1 folder.
PACKAGES = (
    "rospy", "actionlib", "actionlib_msgs", "trajectory_msgs", "sensor_msgs", "geometry_msgs",
    "std_msgs", "rosgraph", "rosgraph_msgs", "roslib", "rospkg", "roscpp", "genmsg", "genpy",
    "catkin", "catkin_pkg", "yaml", "_yaml",
)
PTH_FILE = "rlff-ros1.pth"
#: The FollowJointTrajectory action's MD5 sum in ROS 1 (what every ROS 1 node agrees on).
ACTION_MD5 = "bc4f9b743838566551c0390c65f1a248"

_CHECK = f"""
import rlff.robot.ros1  # Debian's ROS 1 before the ROS 2 wheels' packages of the same names
import numpy, rospy, actionlib
from control_msgs.msg import FollowJointTrajectoryAction
assert "/usr/lib/python3" not in numpy.__file__, "numpy comes from " + numpy.__file__
assert FollowJointTrajectoryAction._md5sum == {ACTION_MD5!r}, FollowJointTrajectoryAction._md5sum
print(rospy.__file__)
"""


class NotInstallable(Exception):
    """ROS 1 cannot be made reachable here; the message says why and what to do."""


def apt_command() -> str:
    """The command that installs :data:`DEBIAN_PACKAGES`."""
    return "sudo apt install " + " ".join(DEBIAN_PACKAGES)


def link_packages(folder: Path, dist: Path = DIST_PACKAGES) -> None:
    """Link each of :data:`PACKAGES` in ``dist`` into ``folder`` (links already there replaced)."""
    absent = [name for name in PACKAGES if not (dist / name).exists()]
    if absent:
        raise NotInstallable(f"{', '.join(str(dist / name) for name in absent)} not found: install "
                             f"Debian's ROS 1 packages first ({apt_command()})")
    folder.mkdir(parents=True, exist_ok=True)
    for name in PACKAGES:
        link = folder / name
        if link.is_symlink():
            link.unlink()
        link.symlink_to(dist / name)


def install() -> list[str]:
    """Make ROS 1 reachable from this venv (the three steps above); returns what was done, a line
    a step. Raises :class:`NotInstallable` outside a venv or without Debian's packages."""
    if sys.prefix == sys.base_prefix:
        raise NotInstallable(f"{sys.executable} is not a virtual environment's Python: run this with "
                             "the Python of the venv rlff is installed in (e.g. .venv/bin/python -m "
                             "rlff.robot.ros1.install)")
    folder = ros1_folder()
    link_packages(folder)
    site = Path(sysconfig.get_paths()["purelib"])
    (site / PTH_FILE).write_text(f"{folder}\n", encoding="utf-8")
    done = [f"linked Debian's ROS 1 packages into {folder}, on the path by {site / PTH_FILE}"]
    # fresh interpreters: the folder is on their path through the .pth file just written
    _python(["-m", "rlff.robot.ros1.msgs", str(folder)], "building control_msgs")
    done.append(f"built control_msgs' FollowJointTrajectory messages into {folder / 'control_msgs'}")
    rospy = _python(["-c", _CHECK], "importing rospy, actionlib and control_msgs").strip()
    done.append(f"ROS 1 reachable from {sys.executable} (rospy from {rospy})")
    return done


def _python(args: list[str], what: str) -> str:
    """Run this venv's Python with ``args`` (``what`` it does); its stdout, or NotInstallable
    with the end of its stderr."""
    proc = subprocess.run([sys.executable, *args], capture_output=True, text=True, timeout=600)
    if proc.returncode != 0:
        raise NotInstallable(f"{what} in a fresh {sys.executable} failed (exit {proc.returncode}): "
                             f"{proc.stderr.strip()[-1500:]}")
    return proc.stdout


def main() -> int:
    try:
        done = install()
    except NotInstallable as exc:
        print(f"rlff.robot.ros1.install: {exc}", file=sys.stderr)
        return 1
    print("\n".join(done))
    return 0


if __name__ == "__main__":
    sys.exit(main())
