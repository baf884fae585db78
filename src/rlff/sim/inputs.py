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
from rlff.robot.description import Robot
from rlff.robot.export import read_csv as read_robot_csv
from rlff.robot.export import read_json as read_robot_json
from rlff.robot.mapping import RobotMapping
from rlff.robot.plan import RobotPlan, plan
from rlff.trajectory.joint import JointTrajectory
from rlff.trajectory.limits import ClipReport, require_within_limits
from rlff.trajectory.path_csv import read_generated_path
from rlff.trajectory.resample import resample


@dataclass(frozen=True)
class LoadedThrow:
    """A trajectory ready to execute, what kind of file it came from and what mapping did.

    ``plan.trajectory`` is the trajectory; ``plan`` also says what was clipped on the way.
    """

    plan: RobotPlan
    kind: str  # "generated path" or "robot trajectory"
    summary: str

    @property
    def trajectory(self) -> JointTrajectory:
        """The robot joint trajectory to execute."""
        return self.plan.trajectory


def load_throw(path: str | Path, robot: Robot, clip: bool = False, period: float | None = None) -> LoadedThrow:
    """Read ``path`` and turn it into ``robot``'s joint trajectory.

    Parameters
    ----------
    path : str or Path
        Generated path CSV, robot trajectory CSV, or robot trajectory JSON.
    robot : Robot
        The robot; its ``[throwing]`` table maps a generated path.
    clip : bool
        Clip a mapped path into the joint limits (and say what changed) instead of refusing it.
    period : float, optional
        Resample at this controller period (s), as ``rlff robot export`` does; default: keep the
        points (the simulation interpolates between them itself).

    Raises
    ------
    InputError
        Unreadable file, missing columns, or (without ``clip``) a point beyond a joint limit.
    """
    path = Path(path)
    if not path.is_file():
        raise InputError(f"{path}: no such file")
    if path.suffix.lower() == ".json":
        return _robot_trajectory(read_robot_json(path), robot, period)
    try:
        header = pd.read_csv(path, nrows=0).columns
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise InputError(f"{path}: not a readable CSV ({exc})") from None
    if "angle" in header:
        generated = read_generated_path(path)
        mapping = RobotMapping.for_robot(robot)
        planned = plan(mapping, generated.angle, generated.velocity, generated.time, period=period, clip=clip)
        return LoadedThrow(planned, "generated path",
                           f"mapped to {mapping.joint} of {robot.name}: {planned.summary()}")
    if any(str(column).endswith("_position") for column in header):
        return _robot_trajectory(read_robot_csv(path), robot, period)
    raise InputError(f"{path}: neither a generated path (angle, velocity[, time]) nor a robot trajectory "
                     f"(time, <joint>_position, ...); columns: {', '.join(map(str, header))}")


def _robot_trajectory(points: JointTrajectory, robot: Robot, period: float | None) -> LoadedThrow:
    """A robot trajectory as read, its joints in ``robot``'s order, resampled at ``period`` if
    given, and checked against the limits (never clipped: it is what a robot was sent)."""
    missing = [name for name in robot.joint_names if name not in points.joint_names]
    if missing:
        raise InputError(f"the robot trajectory has no positions for joints {missing} of {robot.name} "
                         f"(it has {list(points.joint_names)})")
    points = points.select(robot.joint_names)
    require_within_limits(points, robot.joints)
    samples = points
    if period:
        samples = resample(points, period)
        require_within_limits(samples, robot.joints)
    return LoadedThrow(RobotPlan(points, samples, ClipReport(), ClipReport()), "robot trajectory",
                       f"{len(points)} points of {len(points.joint_names)} joints")
