"""Human to robot (thesis 4.4): the learned human angle drives one robot joint.

The driven joint's position is ``angle_offset + angle_scale * angle`` and its velocity
``velocity_scale * velocity``; every other joint stays at its start pose. The robot's timing
follows from the mapped path (t = integral of dq / qdot), i.e. the human timing stretched by
``angle_scale / velocity_scale``. A point beyond a position or velocity limit is an error unless
clipping is asked for, and then every changed value is reported.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np

from rlff.errors import InputError
from rlff.robot.description import Robot, number_field
from rlff.trajectory.joint import JointTrajectory
from rlff.trajectory.limits import ClipReport, LimitChange, clip_to_limits, require_within_limits
from rlff.trajectory.timing import time_along_path


@dataclass(frozen=True)
class RobotMapping:
    """How a human joint angle (rad) and velocity (rad/s) become a robot joint trajectory.

    Parameters
    ----------
    robot : Robot
    joint : str
        The robot joint the learned angle drives (default ``joint_2``).
    start_pose : mapping of joint name to position (rad)
        Fixed positions of every other joint of ``robot``.
    angle_offset, angle_scale : float
        Driven joint position (rad) = ``angle_offset + angle_scale * angle``.
    velocity_scale : float
        Driven joint velocity (rad/s) = ``velocity_scale * velocity``; same sign as
        ``angle_scale``.
    """

    robot: Robot
    joint: str = "joint_2"
    start_pose: Mapping[str, float] = field(default_factory=dict)
    angle_offset: float = 0.0
    angle_scale: float = 1.0
    velocity_scale: float = 1.0

    def __post_init__(self) -> None:
        self.robot.joint(self.joint)
        for name in self.start_pose:
            self.robot.joint(name)
        missing = [n for n in self.robot.joint_names if n != self.joint and n not in self.start_pose]
        if missing:
            raise InputError(f"{self.robot.source}: [throwing.start_pose] misses joints {missing}")
        if self.angle_scale == 0 or self.velocity_scale == 0:
            raise InputError("angle_scale and velocity_scale must be non-zero")
        if np.sign(self.angle_scale) != np.sign(self.velocity_scale):
            raise InputError("angle_scale and velocity_scale must have the same sign "
                             f"(got {self.angle_scale} and {self.velocity_scale})")
        pose = {name: float(self.start_pose[name]) for name in self.robot.joint_names if name != self.joint}
        for name, value in pose.items():
            joint = self.robot.joint(name)
            if not joint.lower <= value <= joint.upper:
                raise InputError(f"start pose of {name} ({value} rad) is outside its limits "
                                 f"[{joint.lower}, {joint.upper}] rad")
        object.__setattr__(self, "start_pose", MappingProxyType(pose))

    @classmethod
    def for_robot(cls, robot: Robot, **overrides: object) -> RobotMapping:
        """The mapping of the robot file's ``[throwing]`` table, with keyword ``overrides``."""
        table = dict(robot.throwing)
        table.update(overrides)
        where = f"{robot.source}: [throwing]"
        if "joint" not in table:
            raise InputError(f"{where}: missing field 'joint'")
        pose = table.get("start_pose")
        if not isinstance(pose, Mapping):
            raise InputError(f"{where}: missing table 'start_pose'")
        return cls(robot, str(table["joint"]),
                   {name: number_field(pose, name, f"{where}.start_pose") for name in pose},
                   *(number_field(table, key, where) for key in ("angle_offset", "angle_scale", "velocity_scale")))

    def pose(self, driven: float = 0.0) -> np.ndarray:
        """Positions (J,) (rad) of every joint: the start pose, the driven joint at ``driven``."""
        return np.array([driven if name == self.joint else self.start_pose[name]
                         for name in self.robot.joint_names])

    @property
    def time_scale(self) -> float:
        """Robot time per human time: ``angle_scale / velocity_scale``."""
        return self.angle_scale / self.velocity_scale

    def to_robot(
        self,
        angle: np.ndarray,
        velocity: np.ndarray,
        time: np.ndarray | None = None,
        clip: bool = False,
    ) -> tuple[JointTrajectory, ClipReport]:
        """The robot trajectory of a human (angle, velocity) path, checked against the limits.

        Parameters
        ----------
        angle : array of shape (T,)
            Human joint angle (rad), strictly monotonic.
        velocity : array of shape (T,)
            Human joint velocity (rad/s), in the direction of motion or zero.
        time : array of shape (T,), optional
            Human time (s); default: from the path, ``time_along_path(angle, velocity)``.
        clip : bool
            Clip positions and velocities into the limits instead of raising; the timing is
            kept (a clipped joint saturates, as a controller would) and a joint held at a
            position limit gets velocity 0. A velocity against the direction of the path (a
            model's dip below 0 at a stop) is set to 0 first (an error without ``clip``).

        Returns
        -------
        JointTrajectory
            T points of every joint of the robot (controller order), time starting at 0;
            accelerations from the velocities over time.
        ClipReport
            What was clipped (empty unless ``clip`` and a value was beyond a limit).

        Raises
        ------
        InputError
            NaN, a non-monotonic angle, a bad time, or (without ``clip``) a point beyond a limit
            or a velocity against the path.
        """
        angle = np.asarray(angle, dtype=float)
        velocity = np.array(velocity, dtype=float)
        backward = self._backward(angle, velocity, clip)
        original_velocity = velocity.copy()
        velocity[backward] = 0.0
        if time is None:
            human_time = time_along_path(angle, velocity)
        else:
            human_time = np.asarray(time, dtype=float)
            time_along_path(angle, velocity)  # same checks of the path: finite, monotonic
            if human_time.shape != angle.shape or not np.all(np.isfinite(human_time)):
                raise InputError(f"time must be finite with the shape of angle {angle.shape}")
            if np.any(np.diff(human_time) <= 0):
                bad = int(np.flatnonzero(np.diff(human_time) <= 0)[0]) + 1
                raise InputError(f"time is not strictly increasing at sample {bad}")
        robot_time = (human_time - human_time[0]) * self.time_scale
        driven = self.robot.index(self.joint)
        count, joints = angle.size, len(self.robot.joints)
        positions = np.tile(self.pose(), (count, 1))
        velocities = np.zeros((count, joints))
        positions[:, driven] = self.angle_offset + self.angle_scale * angle
        velocities[:, driven] = self.velocity_scale * velocity
        traj = JointTrajectory(self.robot.joint_names, robot_time, positions, velocities,
                               _accelerations(robot_time, velocities))
        if not clip:
            require_within_limits(traj, self.robot.joints)
            return traj, ClipReport()
        clipped, report = clip_to_limits(traj, self.robot.joints)
        stopped = [LimitChange(int(i), self.joint, "velocity", float(self.velocity_scale * before), 0.0)
                   for i, before in zip(backward, original_velocity[backward], strict=True)]
        report = ClipReport(tuple(sorted(report.changes + tuple(stopped),
                                         key=lambda c: (c.point, c.joint, c.quantity))))
        if not report:
            return traj, report
        return (JointTrajectory(clipped.joint_names, clipped.time, clipped.positions,
                                clipped.velocities, _accelerations(clipped.time, clipped.velocities)),
                report)

    def _backward(self, angle: np.ndarray, velocity: np.ndarray, clip: bool) -> np.ndarray:
        """Samples whose velocity points against the path (a model's dip below 0 at a stop).

        Without ``clip`` they are an error; with it they are set to 0 (the joint at rest there)
        and reported.
        """
        direction = np.sign(angle[-1] - angle[0]) if angle.ndim == 1 and angle.size > 1 else 0.0
        backward = np.flatnonzero(velocity * direction < 0) if velocity.shape == angle.shape else np.array([], int)
        if backward.size and not clip:
            i = int(backward[0])
            raise InputError(f"velocity at sample {i} ({velocity[i]:g} rad/s) moves against the path "
                             f"({backward.size} samples do); clipping sets them to 0 (--clip)")
        return backward

    def from_robot(self, traj: JointTrajectory) -> tuple[np.ndarray, np.ndarray]:
        """The human (angle (rad), velocity (rad/s)) of a robot trajectory, each of shape (T,).

        The inverse of :meth:`to_robot` on the driven joint; the learning loop records the
        robot's attempts in the human units of the demonstrations with it.
        """
        column = traj.joint_index(self.joint)
        angle = (traj.positions[:, column] - self.angle_offset) / self.angle_scale
        velocity = traj.velocities[:, column] / self.velocity_scale
        return angle, velocity


def _accelerations(time: np.ndarray, velocities: np.ndarray) -> np.ndarray:
    """Accelerations (rad/s^2), shape (T, J): differences of velocity over time (T >= 2)."""
    return np.gradient(velocities, time, axis=0)
