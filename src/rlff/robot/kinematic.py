"""A kinematic simulated arm that follows joint trajectories like the thesis' plug-in.

The plug-in of thesis 3.1.4 re-published the received points at a fixed rate and interpolated
between each point and its predecessor so that the robot moved smoothly through every point.
This arm does the same at every tick, with the interpolation of ros_control's
joint_trajectory_controller for points with accelerations (the one
:func:`rlff.trajectory.check.check_trajectory` checks): between two points each joint follows
the quintic polynomial through both points' positions, velocities and accelerations, so the
points are met exactly and acceleration is continuous (points without accelerations count as
accelerations of zero). Being kinematic, the actual state is the commanded one. Time is whatever
clock the caller ticks with (s); a trajectory starts at the ``start`` time it is given.

The arm follows what it is given and nothing else: whether a trajectory starts where the arm
is and stays within the limits is decided before, by :mod:`rlff.robot.controller`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.interpolate import PPoly

from rlff.errors import InputError
from rlff.trajectory.joint import JointTrajectory


@dataclass(frozen=True)
class ArmState:
    """Joint positions (rad), velocities (rad/s), accelerations (rad/s^2), each (J,), and
    ``elapsed`` time since the trajectory's start (s; 0 when idle or not started)."""

    positions: np.ndarray
    velocities: np.ndarray
    accelerations: np.ndarray
    elapsed: float


def quintic(traj: JointTrajectory) -> PPoly:
    """The piecewise quintic through every point's position, velocity and acceleration.

    Returns a :class:`scipy.interpolate.PPoly` of ``traj.time`` (s) with values of shape (J,)
    (rad; its derivatives rad/s, rad/s^2). The coefficients are the closed-form quintic Hermite
    ones: scipy's ``BPoly.from_derivatives`` builds the same polynomial but takes 0.6 s for a
    5,000-point goal, which the server cannot spend in a goal callback.
    """
    h = np.diff(traj.time)[:, None]
    p0, p1 = traj.positions[:-1], traj.positions[1:]
    v0, v1 = traj.velocities[:-1], traj.velocities[1:]
    a0, a1 = traj.accelerations[:-1], traj.accelerations[1:]
    dp = p1 - p0
    c3 = (20 * dp - (8 * v1 + 12 * v0) * h - (3 * a0 - a1) * h**2) / (2 * h**3)
    c4 = (-30 * dp + (14 * v1 + 16 * v0) * h + (3 * a0 - 2 * a1) * h**2) / (2 * h**4)
    c5 = (12 * dp - 6 * (v1 + v0) * h - (a0 - a1) * h**2) / (2 * h**5)
    return PPoly(np.stack([c5, c4, c3, a0 / 2, v0, p0]), traj.time)


class KinematicArm:
    """Joints that follow the trajectory they are given exactly, holding still otherwise.

    Parameters
    ----------
    joint_names : sequence of str, length J
    positions : array of shape (J,)
        Initial joint positions (rad).
    """

    def __init__(self, joint_names: tuple[str, ...], positions: np.ndarray) -> None:
        self.joint_names = tuple(joint_names)
        self._hold = np.array(positions, dtype=float)
        if self._hold.shape != (len(self.joint_names),):
            raise InputError(f"initial positions must have shape ({len(self.joint_names)},)")
        self._spline: PPoly | None = None
        self._arrived = False  # a one-point trajectory: reached at once, not yet reported
        self._start = 0.0
        self._duration = 0.0
        self.trajectory: JointTrajectory | None = None

    @property
    def moving(self) -> bool:
        """Whether a trajectory is being followed (it may not have started yet)."""
        return self._spline is not None

    def follow(self, traj: JointTrajectory, start: float) -> None:
        """Follow ``traj`` (every joint of the arm, in the arm's order) from clock time ``start`` on.

        Until ``start`` the arm stands at the first point; after the end it holds the last.
        """
        if traj.joint_names != self.joint_names:
            raise InputError(f"the arm follows trajectories of {list(self.joint_names)}, "
                             f"got {list(traj.joint_names)}")
        self._hold = traj.positions[-1].copy()
        self._spline = quintic(traj) if len(traj) > 1 else None
        self._arrived = self._spline is None
        self._start, self._duration = start - float(traj.time[0]), float(traj.time[-1])
        self.trajectory = traj

    def state(self, now: float) -> ArmState:
        """Where the arm is at clock time ``now``; a finished trajectory leaves it holding its end."""
        if self._spline is None:
            zeros = np.zeros_like(self._hold)
            return ArmState(self._hold.copy(), zeros, zeros.copy(), 0.0)
        elapsed = float(np.clip(now - self._start, self._spline.x[0], self._duration))
        return ArmState(self._spline(elapsed), self._spline(elapsed, 1), self._spline(elapsed, 2), elapsed)

    def finished(self, now: float) -> bool:
        """Whether the trajectory being followed has ended by ``now`` (then the arm holds its end)."""
        if self._spline is None:
            arrived, self._arrived = self._arrived, False
            return arrived
        if now - self._start < self._duration:
            return False
        self._hold = self._spline(self._duration)
        self._spline = None
        return True
