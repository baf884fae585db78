"""The trajectory a simulated throw executes, from a file.

Two kinds of files: a generated human path (CSV with ``angle``, ``velocity`` [, ``time``], as
the model writes it), mapped to the robot with the robot file's ``[throwing]`` mapping; or a
robot joint trajectory as ``rlff robot export`` writes it (JSON, or CSV with ``time`` and
``<joint>_position`` columns), taken as it is.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import pandas as pd

from rlff.errors import InputError
from rlff.fileio import require_file
from rlff.robot.description import Robot
from rlff.robot.export import read_csv as read_robot_csv
from rlff.robot.export import read_json as read_robot_json
from rlff.robot.mapping import RobotMapping
from rlff.robot.plan import plan
from rlff.trajectory.joint import JointTrajectory
from rlff.trajectory.path_csv import read_generated_path


@dataclass(frozen=True)
class LoadedThrow:
    """A trajectory ready to simulate, what kind of file it came from and what mapping did."""

    trajectory: JointTrajectory
    kind: str  # "generated path" or "robot trajectory"
    summary: str


def load_throw(path: str | Path, robot: Robot, clip: bool = False) -> LoadedThrow:
    """Read ``path`` and turn it into ``robot``'s joint trajectory.

    Parameters
    ----------
    path : str or Path
        Generated path CSV, robot trajectory CSV, or robot trajectory JSON.
    robot : Robot
        The robot; its ``[throwing]`` table maps a generated path.
    clip : bool
        Clip a mapped path into the joint limits (and say what changed) instead of refusing it.

    Raises
    ------
    InputError
        Unreadable file, missing columns, or (without ``clip``) a point beyond a joint limit.
    """
    path = Path(path)
    require_file(path)
    if path.suffix.lower() == ".json":
        trajectory = read_robot_json(path)
        return LoadedThrow(trajectory, "robot trajectory", f"{len(trajectory)} points of {len(trajectory.joint_names)} joints")
    try:
        header = pd.read_csv(path, nrows=0).columns
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise InputError(f"{path}: not a readable CSV ({exc})") from None
    if "angle" in header:
        generated = read_generated_path(path)
        mapping = RobotMapping.for_robot(robot)
        planned = plan(mapping, generated.angle, generated.velocity, generated.time, period=None, clip=clip)
        return LoadedThrow(planned.trajectory, "generated path",
                           f"mapped to {mapping.joint} of {robot.name}: {planned.summary()}")
    if any(str(column).endswith("_position") for column in header):
        trajectory = read_robot_csv(path)
        return LoadedThrow(trajectory, "robot trajectory", f"{len(trajectory)} points of {len(trajectory.joint_names)} joints")
    raise InputError(f"{path}: neither a generated path (angle, velocity[, time]) nor a robot trajectory "
                     f"(time, <joint>_position, ...); columns: {', '.join(map(str, header))}")
