"""Time along a path, t(angle) = integral of d angle / velocity, on analytic cases."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rlff.errors import InputError
from rlff.timing import time_along_path


def test_constant_velocity_gives_linear_time():
    angle = np.linspace(0.2, 1.7, 31)
    time = time_along_path(angle, np.full(31, 3.0))
    np.testing.assert_allclose(time, (angle - 0.2) / 3.0, rtol=0, atol=1e-15)


def test_negative_direction_constant_velocity():
    angle = np.linspace(2.0, 0.0, 11)
    time = time_along_path(angle, np.full(11, -0.5))
    np.testing.assert_allclose(time, np.linspace(0, 4.0, 11), atol=1e-14)


def test_uniform_acceleration_from_rest_is_exact():
    # angle(t) = a t^2 / 2 (parabolic in time), so velocity = sqrt(2 a angle) and t = sqrt(2 angle / a),
    # starting at zero velocity; the constant-acceleration segments make this exact.
    a = 4.0
    angle = np.linspace(0.0, 2.0, 41)
    time = time_along_path(angle, np.sqrt(2 * a * angle))
    np.testing.assert_allclose(time, np.sqrt(2 * angle / a), rtol=1e-12, atol=1e-15)


def test_parabolic_velocity_profile_matches_closed_form():
    # velocity(angle) = v0 + k angle^2, so t = atan(angle sqrt(k / v0)) / sqrt(k v0)
    v0, k = 0.5, 2.0
    angle = np.linspace(0.0, 1.5, 3001)
    time = time_along_path(angle, v0 + k * angle**2)
    expected = np.arctan(angle * np.sqrt(k / v0)) / np.sqrt(k * v0)
    np.testing.assert_allclose(time, expected, rtol=0, atol=2e-7)


def test_rest_at_both_ends_stays_finite_and_increasing():
    angle = np.linspace(0.0, 1.0, 50)
    velocity = np.sin(np.pi * angle) ** 2  # zero at both ends, flat there
    time = time_along_path(angle, velocity)
    assert np.all(np.isfinite(time))
    assert np.all(np.diff(time) > 0)


def test_segment_at_rest_on_both_ends_takes_its_length_over_the_floor():
    angle = np.array([0.0, 0.1, 0.2, 1.2])
    velocity = np.array([0.0, 0.0, 2.0, 2.0])
    time = time_along_path(angle, velocity, min_speed=0.5)
    np.testing.assert_allclose(time, [0.0, 0.2, 0.3, 0.8])


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(0.0, 10.0), min_size=2, max_size=40),
       st.lists(st.floats(1e-3, 1.0), min_size=2, max_size=40))
def test_time_is_finite_and_increasing_for_any_nonnegative_profile(speeds, steps):
    n = min(len(speeds), len(steps))
    velocity = np.array(speeds[:n])
    velocity[[0, -1]] = 0.0
    if velocity.max() < 1e-3:
        velocity[0] = 1.0
    angle = np.concatenate([[0.0], np.cumsum(steps[: n - 1])])
    time = time_along_path(angle, velocity)
    assert time[0] == 0 and np.all(np.isfinite(time)) and np.all(np.diff(time) > 0)


@pytest.mark.parametrize(
    ("angle", "velocity", "message"),
    [
        ([0.0, 0.5, 0.4, 1.0], [1, 1, 1, 1], "not strictly monotonic at sample 2"),
        ([0.0, 0.5, 0.5, 1.0], [1, 1, 1, 1], "not strictly monotonic at sample 2"),
        ([0.0, np.nan, 1.0], [1, 1, 1], "angle at sample 1 is nan"),
        ([0.0, 0.5, 1.0], [1, np.inf, 1], "velocity at sample 1 is inf"),
        ([0.0, 0.5, 1.0], [1, -1, 1], "moves against the path"),
        ([0.0, 0.5, 1.0], [0, 0, 0], "zero everywhere"),
        ([0.0, 0.5, 1.0], [0, 1e-12, 0], "zero everywhere"),
        ([0.0], [1.0], "at least 2 samples"),
    ],
)
def test_bad_paths_are_refused_with_the_reason(angle, velocity, message):
    with pytest.raises(InputError, match=message):
        time_along_path(np.array(angle), np.array(velocity, dtype=float))
