"""Resampling at a controller period: the grid, exactness on polynomial paths, consistency."""

from __future__ import annotations

import numpy as np
import pytest

from rlff.errors import InputError
from rlff.trajectory import JointTrajectory, resample, time_along_path
from rlff.trajectory.resample import sample_times


def test_grid_is_regular_and_ends_at_the_duration():
    np.testing.assert_allclose(sample_times(0.025, 0.01), [0.0, 0.01, 0.02, 0.025])
    np.testing.assert_allclose(sample_times(0.03, 0.01), [0.0, 0.01, 0.02, 0.03])
    assert sample_times(1.0, 0.002).size == 501


@pytest.mark.parametrize("period", [0.002, 0.010])
def test_cubic_path_is_reproduced_exactly(period):
    # q(t) = t^3 - t^2 + 0.5 t on [0, 1.3], knots at 7 uneven times
    knots = np.array([0.0, 0.1, 0.35, 0.6, 0.9, 1.1, 1.3])
    q = lambda t: t**3 - t**2 + 0.5 * t  # noqa: E731
    dq = lambda t: 3 * t**2 - 2 * t + 0.5  # noqa: E731
    traj = JointTrajectory(("j",), knots, q(knots)[:, None], dq(knots)[:, None])
    fine = resample(traj, period)
    assert fine.time[0] == 0 and fine.time[-1] == 1.3
    np.testing.assert_allclose(np.diff(fine.time[:-1]), period, atol=1e-12)
    np.testing.assert_allclose(fine.positions[:, 0], q(fine.time), atol=1e-12)
    np.testing.assert_allclose(fine.velocities[:, 0], dq(fine.time), atol=1e-12)
    np.testing.assert_allclose(fine.accelerations[:, 0], 6 * fine.time - 2, atol=1e-9)


def test_resampled_quantities_are_consistent_with_each_other():
    angle = np.linspace(0.0, 1.5, 40)
    velocity = 3 * np.sin(np.pi * angle / 1.5) ** 2 + 0.1
    time = time_along_path(angle, velocity)
    traj = JointTrajectory(("a", "b"), time, np.c_[angle, 2 * angle], np.c_[velocity, 2 * velocity])
    fine = resample(traj, 0.002)
    # Within a step the path is one cubic, for which these quadrature rules are exact:
    # dq = dt (v0 + v1) / 2 + dt^2 (a0 - a1) / 12 and dv = dt (a0 + a1) / 2. Acceleration jumps
    # at the original points, so steps across one are left out.
    dt = np.diff(fine.time)[:, None]
    q, v, a = fine.positions, fine.velocities, fine.accelerations
    smooth = np.searchsorted(time, fine.time[:-1], side="right") == np.searchsorted(time, fine.time[1:], side="left")
    assert smooth.sum() > 0.9 * smooth.size
    np.testing.assert_allclose(np.diff(q, axis=0)[smooth],
                               (dt * (v[:-1] + v[1:]) / 2 + dt**2 * (a[:-1] - a[1:]) / 12)[smooth], atol=1e-12)
    np.testing.assert_allclose(np.diff(v, axis=0)[smooth], (dt * (a[:-1] + a[1:]) / 2)[smooth], atol=1e-10)
    # the original points are passed through
    np.testing.assert_allclose(np.interp(time, fine.time, fine.positions[:, 0]), angle, atol=1e-5)
    assert fine.positions[-1, 0] == pytest.approx(1.5)


def test_bad_period_is_refused():
    traj = JointTrajectory(("j",), [0.0, 1.0], [[0.0], [1.0]], [[1.0], [1.0]])
    with pytest.raises(InputError, match="period must be positive"):
        resample(traj, 0.0)
