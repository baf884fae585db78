"""Resampling a timed joint trajectory at a controller period (2 ms by default, 10 ms option).

Between two points each joint follows the cubic Hermite polynomial through both points'
positions and velocities (scipy's CubicHermiteSpline), so the resampled positions, velocities and
accelerations are one function and its first two derivatives: consistent with each other by
construction, and the original points are passed through exactly. A cubic Hermite reproduces any
polynomial path of degree <= 3, in particular the constant-acceleration segments that
:func:`rlff.timing.time_along_path` assumes.
"""

from __future__ import annotations

import numpy as np

from rlff.errors import InputError
from rlff.trajectory.joint import JointTrajectory

#: Controller periods the robot side offers (s): 2 ms (default) and 10 ms.
CONTROLLER_PERIODS = (0.002, 0.010)


def sample_times(duration: float, period: float) -> np.ndarray:
    """Times 0, period, 2 period, ... and the end ``duration`` (s), shape (N,).

    The last regular sample is dropped when it falls within 1e-6 period of ``duration``, so
    that no step is (nearly) empty.
    """
    if not (np.isfinite(period) and period > 0):
        raise InputError(f"the controller period must be positive, got {period!r} s")
    count = int(np.floor(duration / period * (1 + 1e-12)))
    grid = np.arange(count + 1) * period
    grid = grid[grid < duration - 1e-6 * period]
    return np.append(grid, duration)


def resample(traj: JointTrajectory, period: float = 0.002) -> JointTrajectory:
    """``traj`` at a fixed controller period, with consistent derivatives.

    Parameters
    ----------
    traj : JointTrajectory
        T >= 2 points; ``positions`` (rad) and ``velocities`` (rad/s) are interpolated.
    period : float
        Controller period (s), e.g. 0.002 or 0.010.

    Returns
    -------
    JointTrajectory
        N points at ``traj.time[0] + k * period`` and at the last time of ``traj``; positions,
        velocities and accelerations (rad/s^2) are the Hermite spline and its derivatives.
    """
    if len(traj) < 2:
        raise InputError("resampling needs a trajectory of at least 2 points")
    # imported here: scipy.interpolate costs ~0.5 s, which every CLI command importing this
    # module would pay even when it never resamples
    from scipy.interpolate import CubicHermiteSpline

    start = traj.time[0]
    spline = CubicHermiteSpline(traj.time, traj.positions, traj.velocities, axis=0)
    time = start + sample_times(traj.duration - start, period)
    time[-1] = traj.duration
    return JointTrajectory(traj.joint_names, time, spline(time), spline(time, 1), spline(time, 2))
