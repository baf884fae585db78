"""Time along a path from its velocity profile: t(angle) = integral of d angle / velocity.

Near-zero velocity: the integral diverges where the velocity is zero (a throw starts and ends at
rest). Each segment between two samples is taken at constant acceleration in time, which gives
dt = 2 d angle / (v_i + v_{i+1}): exact for constant velocity and for uniform acceleration, and
finite when one end of the segment is at rest. Where both ends are (nearly) at rest the speed is
floored at ``min_speed`` (default 1 % of the peak speed) so that the time stays finite: a segment
that starts and ends at rest takes its length over that floor, as if crept through slowly.

A leaf module (it needs only :mod:`rlff.errors`): the model stage times the paths it generates
with it, the robot mapping and the motion planner below it time theirs, so it lives beneath them
all rather than in :mod:`rlff.trajectory`, which the model stage must not import.
"""

from __future__ import annotations

import numpy as np

from rlff.errors import InputError

#: A path whose peak speed (rad/s) is not above this never gets anywhere: refused.
_SLOWEST_PEAK = 1e-9


def first_reversal(angle: np.ndarray) -> int | None:
    """The first sample (from 1) of ``angle`` (shape (T,)) that does not go on in the direction of
    its first step (1 when that step is none), or None for a strictly monotonic path."""
    steps = np.diff(np.asarray(angle, dtype=float))
    if steps.size == 0:
        return None
    direction = np.sign(steps[0])
    if direction == 0:
        return 1
    reversed_at = np.flatnonzero(np.sign(steps) != direction)
    return int(reversed_at[0]) + 1 if reversed_at.size else None


def time_along_path(
    angle: np.ndarray, velocity: np.ndarray, min_speed: float | None = None
) -> np.ndarray:
    """Time (s) at each sample of a path given its angle (rad) and velocity (rad/s).

    Parameters
    ----------
    angle : array of shape (T,)
        Strictly monotonic joint angle (rad).
    velocity : array of shape (T,)
        Joint velocity (rad/s) at each angle, same sign as the direction of motion (or zero).
    min_speed : float, optional
        Floor on the mean speed of a segment (rad/s); default 1 % of the peak speed.

    Returns
    -------
    ndarray of shape (T,)
        Time since the first sample, starting at 0, strictly increasing.

    Raises
    ------
    InputError
        Non-finite values, fewer than 2 samples, a non-monotonic angle, or a velocity that moves
        against the direction of the path.
    """
    angle = np.asarray(angle, dtype=float)
    velocity = np.asarray(velocity, dtype=float)
    if angle.shape != velocity.shape or angle.ndim != 1:
        raise InputError(f"angle and velocity must be 1-D of one length, got {angle.shape} and {velocity.shape}")
    if angle.size < 2:
        raise InputError("a timed path needs at least 2 samples")
    for label, values in (("angle", angle), ("velocity", velocity)):
        if not np.all(np.isfinite(values)):
            bad = int(np.flatnonzero(~np.isfinite(values))[0])
            raise InputError(f"{label} at sample {bad} is {values[bad]} (NaN or inf)")
    if (bad := first_reversal(angle)) is not None:
        raise InputError(f"angle is not strictly monotonic at sample {bad}")
    direction = np.sign(angle[1] - angle[0])
    speed = velocity * direction
    if np.any(speed < -1e-12):
        bad = int(np.flatnonzero(speed < -1e-12)[0])
        raise InputError(f"velocity at sample {bad} ({velocity[bad]:g} rad/s) moves against the path")
    if not np.max(speed) > _SLOWEST_PEAK:
        raise InputError(f"velocity is (nearly) zero everywhere (peak {np.max(speed):.3g} rad/s): "
                         "the path would take forever")
    if min_speed is None:
        min_speed = 0.01 * float(np.max(speed))
    elif not min_speed > 0:
        raise InputError(f"min_speed must be positive, got {min_speed!r} rad/s")
    mean_speed = np.maximum(0.5 * (speed[:-1] + speed[1:]), min_speed)
    return np.concatenate([[0.0], np.cumsum(np.abs(np.diff(angle)) / mean_speed)])
