"""A kinematic simulated arm that follows joint trajectories like the thesis' plug-in.

The plug-in of thesis 3.1.4 re-published the received points at a fixed rate and interpolated
between each point and its predecessor so that the robot moved smoothly through every (position,
velocity) pair. This arm does the same at every tick: between two points each joint follows the
cubic Hermite polynomial through both points' positions and velocities, so the points are met
exactly. Being kinematic, the actual state is the commanded one. Time is whatever clock the
caller ticks with (s); a trajectory starts at the ``start`` time it is given.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.interpolate import CubicHermiteSpline

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
        self._spline: CubicHermiteSpline | None = None
        self._arrived = False  # a one-point trajectory at 0 s: reached at once, not yet reported
        self._start = 0.0
        self._duration = 0.0
        self.trajectory: JointTrajectory | None = None

    @property
    def moving(self) -> bool:
        """Whether a trajectory is being followed."""
        return self._spline is not None

    def follow(self, traj: JointTrajectory, start: float, now: float) -> JointTrajectory:
        """Follow ``traj`` from clock time ``start`` on; returns the full trajectory followed.

        Joints that ``traj`` leaves out hold their positions. If the first point is later than
        0 s, the arm goes there from where it is at ``now`` (a point at time 0 prepended);
        a first point at 0 s is taken as the pose to start from.
        """
        here = self.state(now).positions
        index = [self.joint_names.index(name) for name in traj.joint_names]
        positions = np.tile(here, (len(traj), 1))
        velocities = np.zeros_like(positions)
        positions[:, index] = traj.positions
        velocities[:, index] = traj.velocities
        time = traj.time
        if time[0] > 0:
            time = np.concatenate([[0.0], time])
            positions = np.vstack([here, positions])
            velocities = np.vstack([np.zeros_like(here), velocities])
        full = JointTrajectory(self.joint_names, time, positions, velocities)
        self._hold = positions[-1].copy()
        self._spline = CubicHermiteSpline(time, positions, velocities, axis=0) if len(time) > 1 else None
        self._arrived = self._spline is None
        self._start, self._duration = start, float(time[-1])
        self.trajectory = full
        return full

    def stop(self, now: float) -> None:
        """Halt where the arm is at ``now`` and hold that position."""
        self._hold = self.state(now).positions
        self._spline = None
        self._arrived = False
        self.trajectory = None

    def state(self, now: float) -> ArmState:
        """Where the arm is at clock time ``now``; a finished trajectory leaves it holding its end."""
        if self._spline is None:
            zeros = np.zeros_like(self._hold)
            return ArmState(self._hold.copy(), zeros, zeros.copy(), 0.0)
        elapsed = float(np.clip(now - self._start, 0.0, self._duration))
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
