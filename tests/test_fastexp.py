"""The vectorised exp of the compiled kernels against NumPy's exp."""

from __future__ import annotations

import numpy as np
import pytest

from rlff.model.fastexp import LOWEST, exp_relative


def run(values: np.ndarray, top: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    out, total = values.copy(), np.full(values.shape, 0.25)
    exp_relative(out, top, total)
    return out, total


def test_within_two_ulp_of_numpy_over_the_whole_range():
    rng = np.random.default_rng(0)
    x = np.concatenate([
        -rng.uniform(0, -LOWEST, 200_000),  # everywhere
        -rng.uniform(0, 1e-3, 1000),  # near 0, where the polynomial alone works
        -np.arange(0, 708) * np.log(2) + rng.uniform(-1e-9, 1e-9, 708),  # around the range-reduction seams
        [0.0, -0.0, LOWEST, -5e-324],
    ])
    x = np.minimum(x, 0.0)
    out, total = run(x, np.zeros_like(x))
    expected = np.exp(x)
    ulps = np.abs(out - expected) / np.spacing(expected)
    assert ulps.max() <= 2, f"worst {ulps.max()} ulp at x = {x[ulps.argmax()]!r}"
    np.testing.assert_array_equal(total, 0.25 + out)


def test_relative_to_a_top_and_clamped_at_the_lowest_exponent():
    values = np.array([3.0, 1.0, -1e6, 2.0, np.float64(-1e300)])
    top = np.array([3.0, 2.0, 0.0, 2.0, 0.0])
    out, _ = run(values, top)
    np.testing.assert_allclose(out[[0, 1, 3]], [1.0, np.exp(-1.0), 1.0], rtol=1e-15)
    # arguments below LOWEST are raised to it: still a normal number, never 0, inf or NaN
    assert out[2] == out[4] == pytest.approx(np.exp(LOWEST), rel=1e-15)


def test_all_lengths_of_the_vector_loop_and_its_remainder():
    for size in range(0, 19):
        x = -np.linspace(0, 30, size)
        out, _ = run(x, np.zeros(size))
        np.testing.assert_allclose(out, np.exp(x), rtol=5e-16)
