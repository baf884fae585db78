"""What the simulated controller commands at every step: a reference the joints can follow.

The trajectory's points are interpolated at the simulation step with cubic Hermite splines (the
thesis' controller plug-in also re-published the points at a fixed rate and interpolated between
them). Where the interpolated path would leave a position limit or move faster than a joint's
speed limit (a clipped trajectory whose positions outrun its velocities, or a spline overshooting
between points) the reference saturates like a real controller's interpolator: it is clamped to
the position range and rate-limited to the speed limit, and it then arrives late at the end.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from scipy.interpolate import CubicHermiteSpline

from rlff.errors import InputError
from rlff.sim.arm import Arm
from rlff.trajectory.joint import JointTrajectory

#: Deceleration (rad/s^2) the simulated arm is sure to reach when it stops after a trajectory
#: (its servos brake harder: about 300 rad/s^2 for joint 2 at the torque limit).
BRAKING = 100.0


class Reference(NamedTuple):
    """Joint positions (rad) and velocities (rad/s) to follow, each of shape (N, J), one row per
    simulation step from the trajectory's first time; ``saturated`` tells whether a limit bent it.
    """

    positions: np.ndarray
    velocities: np.ndarray
    saturated: bool


def servo_reference(trajectory: JointTrajectory, arm: Arm, timestep: float) -> Reference:
    """The reference of ``trajectory`` (T >= 2 points, joints in ``arm`` order) at ``timestep`` s."""
    time = trajectory.time
    steps = int(np.ceil((time[-1] - time[0]) / timestep - 1e-9)) + 1
    clock = np.minimum(time[0] + timestep * np.arange(steps), time[-1])
    spline = CubicHermiteSpline(time, trajectory.positions, trajectory.velocities, axis=0)
    positions, velocities = spline(clock), spline(clock, 1)
    lower = np.array([joint.lower for joint in arm.joints])
    upper = np.array([joint.upper for joint in arm.joints])
    largest_step = np.array([joint.max_velocity for joint in arm.joints]) * timestep
    clamped = np.clip(positions, lower, upper)
    if np.array_equal(clamped, positions) and np.all(np.abs(velocities) * timestep <= largest_step):
        return Reference(positions, velocities, False)
    # rate-limit the clamped path step by step (a recursion: each step starts where the last ended)
    limited = [clamped[0]]
    k = 0
    while k < steps - 1 or not np.array_equal(limited[-1], clamped[-1]):
        k = min(k + 1, steps - 1)
        limited.append(limited[-1] + np.clip(clamped[k] - limited[-1], -largest_step, largest_step))
    positions = np.array(limited)
    velocities = np.vstack([np.diff(positions, axis=0) / timestep, np.zeros((1, positions.shape[1]))])
    return Reference(positions, velocities, True)


def require_room_to_stop(trajectory: JointTrajectory, arm: Arm) -> None:
    """Raise :class:`InputError` if a joint still moving at the end of ``trajectory`` (joints in
    ``arm`` order) cannot stop, braking at :data:`BRAKING`, before its position limit."""
    end_positions, end_velocities = trajectory.positions[-1], trajectory.velocities[-1]
    for joint, position, velocity in zip(arm.joints, end_positions, end_velocities, strict=True):
        stop = position + np.sign(velocity) * velocity**2 / (2.0 * BRAKING)
        if not joint.lower <= stop <= joint.upper:
            limit = joint.upper if velocity > 0 else joint.lower
            raise InputError(
                f"trajectory ends with {joint.name} at {position:.4g} rad moving at {velocity:.4g} rad/s: "
                f"stopping needs {abs(stop - position):.3g} rad but its limit {limit:.4g} rad is "
                f"{abs(limit - position):.3g} rad away"
            )
