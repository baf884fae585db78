"""Which ROS a process imports: Debian's ROS 1 packages or the ROS 2 wheels of the same names.

Both install message packages under the same names (std_msgs, trajectory_msgs, sensor_msgs,
geometry_msgs, control_msgs, ...): the ROS 2 wheels into site-packages, ROS 1 into the venv's
``ros1`` folder (:func:`ros1_folder`; ``python -m rlff.robot.ros1.install`` makes it, and
``scripts/setup.d/10-ros.sh`` runs that for a clone). :func:`prefer` puts one first on ``sys.path``
and forgets the other's message modules already imported, so that the next import of such a
package finds the one asked for. A process drives one ROS; a process that checks both (a test
worker) asks for the one it is about to use each time.
"""

from __future__ import annotations

import sys
from pathlib import Path


def ros1_folder() -> Path:
    """The venv's folder of links to Debian's ROS 1 packages (``<venv>/ros1``)."""
    return Path(sys.prefix) / "ros1"


def _shared_names(folder: Path) -> set[str]:
    """Message packages both ROS provide: those of the ROS 1 folder that are also on the path elsewhere."""
    names = {entry.name for entry in folder.iterdir() if entry.name.endswith("_msgs")}
    elsewhere = {name for name in names for entry in sys.path
                 if entry and entry != str(folder) and (Path(entry) / name).is_dir()}
    return elsewhere


def prefer(version: int) -> None:
    """Make ROS ``version`` (1 or 2) the one this process imports from now on."""
    folder = ros1_folder()
    if str(folder) not in sys.path or not folder.is_dir():
        return  # no ROS 1 folder: nothing to choose between
    sys.path.remove(str(folder))
    if version == 1:
        sys.path.insert(0, str(folder))
    else:
        sys.path.append(str(folder))
    shared = _shared_names(folder)
    for name, module in list(sys.modules.items()):
        if name.split(".")[0] not in shared:
            continue
        origin = str(getattr(module, "__file__", None) or next(iter(getattr(module, "__path__", [])), ""))
        from_ros1 = origin.startswith(str(folder))
        if from_ros1 != (version == 1):
            del sys.modules[name]
