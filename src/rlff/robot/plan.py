"""From a generated human path to the robot's timed trajectory: map, resample, check limits.

This is what every robot output (exports, the ROS client) runs first, so a trajectory beyond
the robot's limits is refused before anything is written or sent.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rlff.errors import InputError
from rlff.robot.description import DEFAULT_ROBOT, load_robot
from rlff.robot.mapping import RobotMapping
from rlff.trajectory.joint import JointTrajectory
from rlff.trajectory.limits import ClipReport, clip_to_limits, require_within_limits
from rlff.trajectory.path_csv import read_generated_path
from rlff.trajectory.resample import resample


@dataclass(frozen=True)
class RobotPlan:
    """The robot trajectory and what was clipped on the way.

    ``points`` is the mapped trajectory at the path's own samples; ``trajectory`` the one to
    execute (``points`` resampled at the controller period, or ``points`` itself);
    ``clipped_points`` and ``clipped_samples`` list the values clipped at each stage (the spline
    between two points inside the limits may still overshoot them).
    """

    points: JointTrajectory
    trajectory: JointTrajectory
    clipped_points: ClipReport
    clipped_samples: ClipReport

    def summary(self) -> str:
        """One line on what was clipped, or that nothing was."""
        if not (self.clipped_points or self.clipped_samples):
            return "within the limits, nothing clipped"
        return (f"path points: {self.clipped_points.summary()}; "
                f"resampled: {self.clipped_samples.summary()}")


def plan(
    mapping: RobotMapping,
    angle: np.ndarray,
    velocity: np.ndarray,
    time: np.ndarray | None = None,
    period: float | None = 0.002,
    clip: bool = False,
) -> RobotPlan:
    """Map a human path (angle (T,) rad, velocity (T,) rad/s, time (T,) s or None) to the robot.

    ``period`` (s) resamples at the controller period; None or 0 keeps the path's points.
    Without ``clip`` any value beyond a limit raises :class:`rlff.errors.InputError`.
    """
    points, clipped_points = mapping.to_robot(angle, velocity, time, clip=clip)
    if not period:
        return RobotPlan(points, points, clipped_points, ClipReport())
    samples = resample(points, period)
    if not clip:
        try:
            require_within_limits(samples, mapping.robot.joints)
        except InputError as exc:
            raise InputError(f"after resampling at {period * 1000:g} ms (points are the samples): {exc}") from None
        return RobotPlan(points, samples, clipped_points, ClipReport())
    samples, clipped_samples = clip_to_limits(samples, mapping.robot.joints)
    return RobotPlan(points, samples, clipped_points, clipped_samples)


def plan_file(
    path: str | Path,
    robot: str | Path = DEFAULT_ROBOT,
    period: float | None = 0.002,
    clip: bool = False,
) -> tuple[RobotPlan, RobotMapping]:
    """:func:`plan` for a generated trajectory CSV and a robot file (default mapping)."""
    mapping = RobotMapping.for_robot(load_robot(robot))
    generated = read_generated_path(path)
    return plan(mapping, generated.angle, generated.velocity, generated.time, period, clip), mapping
