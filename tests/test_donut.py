"""Donut densities, the exploration factor and the global DMM mode."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import minimize
from scipy.stats import multivariate_normal, norm

from alone import each_alone
from rlff.errors import InputError
from rlff.model.donut import dmm_mode, dmm_pdf, donut_pdf, donut_radii, exploration_factor
from rlff.model.mixture import GaussianMixture
from rlff.model.regression import Conditional, condition


def conditional_of(weights, means, covariances) -> Conditional:
    """A Conditional (N inputs) from explicit component weights (N, K), means (N, K, O), covs (K, O, O)."""
    weights = np.asarray(weights, float)
    means = np.asarray(means, float)
    covariances = np.asarray(covariances, float)
    mean = np.einsum("nk,nko->no", weights, means)
    spread = means - mean[:, None, :]
    covariance = np.einsum("nk,kop->nop", weights, covariances) + np.einsum("nk,nko,nkp->nop", weights, spread, spread)
    return Conditional(weights, means, covariances, mean, covariance)


def random_conditional(seed: int, n: int, k: int, o: int = 1) -> Conditional:
    rng = np.random.default_rng(seed)
    weights = rng.dirichlet(np.ones(k), size=n)
    means = rng.normal(0, 2, (n, k, o))
    factors = rng.normal(size=(k, o, o)) * rng.uniform(0.2, 1.5, (k, 1, 1))
    covariances = factors @ np.swapaxes(factors, 1, 2) + 0.05 * np.eye(o)
    return conditional_of(weights, means, covariances)


# -- exploration and radii ---------------------------------------------------------------------------


def test_exploration_factor_formula_scale_and_spectral_norm():
    variance = np.array([0.0, 1.0, 3.0])[:, None, None]
    np.testing.assert_allclose(exploration_factor(variance), [0.0, 0.5, 0.75])
    # the scale is in output units: variance 4 at scale 2 counts as variance 1 at scale 1
    np.testing.assert_allclose(exploration_factor(4 * variance, scale=2.0), [0.0, 0.5, 0.75])
    matrix = np.array([[[2.0, 1.0], [1.0, 2.0]]])  # eigenvalues 1 and 3
    assert exploration_factor(matrix)[0] == pytest.approx(0.75)
    with pytest.raises(InputError, match="scale"):
        exploration_factor(variance, scale=0.0)


@pytest.mark.parametrize("o", [2, 3, 4])
def test_the_spectral_norm_is_numpys_largest_eigenvalue_also_where_eigenvalues_coincide(o):
    """exploration_factor takes ||V|| from its own closed forms (2x2, 3x3) and Jacobi rotations:
    against np.linalg.eigvalsh on random covariances, the identity, zero, and matrices whose two
    largest eigenvalues coincide or nearly do (where the 3x3 formula's arccos loses digits)."""
    from rlff.model.donut import _largest_eigenvalues

    rng = np.random.default_rng(o)
    factors = rng.normal(size=(500, o, o))
    matrices = factors @ np.swapaxes(factors, 1, 2)
    axes = rng.normal(size=(100, o))
    axes /= np.linalg.norm(axes, axis=1)[:, None]
    outer = np.einsum("ni,nj->nij", axes, axes)
    matrices[:50] = 2 * np.eye(o) - outer[:50]  # the largest eigenvalue twice (o >= 3: o - 1 times)
    matrices[50:100] = 2 * np.eye(o) - outer[50:] + 1e-7 * outer[50:]
    matrices[100], matrices[101], matrices[102] = np.eye(o), 0.0, np.diag(np.arange(1.0, o + 1))
    largest = np.empty(len(matrices))
    _largest_eigenvalues(matrices, largest)
    np.testing.assert_allclose(largest, np.linalg.eigvalsh(matrices)[:, -1], rtol=1e-13, atol=1e-15)


@pytest.mark.parametrize("d", [1, 2, 3])
def test_radii_keep_the_covariance_and_bound_the_hole(d):
    eps = np.linspace(0, 1, 11)
    r_a2, r_b2 = donut_radii(eps, d)
    np.testing.assert_allclose(2 / r_a2 - 1 / r_b2, 1.0)
    assert r_a2[0] == pytest.approx(1.0) and r_b2[0] == pytest.approx(1.0)
    # eps = 1: gamma r_a^d = (gamma - 1) r_b^d, the two terms cancel at the mean
    assert 2 * r_a2[-1] ** (d / 2) == pytest.approx(r_b2[-1] ** (d / 2))
    assert np.all(np.diff(r_b2 / r_a2) > 0)


# -- densities ---------------------------------------------------------------------------------------


def test_donut_at_zero_exploration_is_the_gaussian_and_at_one_has_no_density_at_the_mean():
    y = np.linspace(-4, 6, 41)[:, None]
    np.testing.assert_allclose(donut_pdf(y, [1.0], [[2.0]], 0.0), norm(1.0, np.sqrt(2.0)).pdf(y[:, 0]), rtol=1e-12)
    assert donut_pdf(np.array([1.0]), np.array([1.0]), np.array([[2.0]]), 1.0) == pytest.approx(0.0, abs=1e-15)
    y2 = np.random.default_rng(0).normal(size=(30, 2))
    cov = np.array([[1.0, 0.3], [0.3, 0.5]])
    np.testing.assert_allclose(donut_pdf(y2, np.zeros(2), cov, 0.0), multivariate_normal(np.zeros(2), cov).pdf(y2), rtol=1e-12)


@settings(max_examples=30, deadline=None)
@given(eps=st.floats(0, 1), variance=st.floats(0.05, 20), gamma=st.floats(1.2, 5))
def test_donut_is_non_negative_and_integrates_to_one_in_1d(eps, variance, gamma):
    sd = np.sqrt(variance)
    y = np.linspace(-12 * sd, 12 * sd, 20001)[:, None]
    density = donut_pdf(y, np.zeros(1), np.array([[variance]]), eps, gamma=gamma)
    assert density.min() >= -1e-15
    assert np.trapezoid(density, y[:, 0]) == pytest.approx(1.0, abs=1e-6)
    # and it keeps the variance of its Gaussian
    assert np.trapezoid(density * y[:, 0] ** 2, y[:, 0]) == pytest.approx(variance, rel=1e-5)


@settings(max_examples=15, deadline=None)
@given(eps=st.floats(0, 1), a=st.floats(0.2, 3), b=st.floats(0.2, 3), rho=st.floats(-0.8, 0.8))
def test_donut_is_non_negative_and_integrates_to_one_in_2d(eps, a, b, rho):
    cov = np.array([[a * a, rho * a * b], [rho * a * b, b * b]])
    axis_x = np.linspace(-9 * a, 9 * a, 301)
    axis_y = np.linspace(-9 * b, 9 * b, 301)
    grid = np.stack(np.meshgrid(axis_x, axis_y, indexing="ij"), axis=-1)
    density = donut_pdf(grid, np.zeros(2), cov, eps)
    assert density.min() >= -1e-14 * density.max()  # rounding where the two terms cancel
    total = np.trapezoid(np.trapezoid(density, axis_y, axis=1), axis_x)
    assert total == pytest.approx(1.0, abs=1e-4)


@settings(max_examples=20, deadline=None)
@given(seed=st.integers(0, 10_000), k=st.integers(1, 4), eps=st.floats(0, 1))
def test_dmm_is_non_negative_and_integrates_to_one(seed, k, eps):
    conditional = random_conditional(seed, 3, k)
    y = np.linspace(-25, 25, 40001)
    density = dmm_pdf(conditional, np.broadcast_to(y[None, :, None], (3, y.size, 1)), eps)
    assert density.min() >= -1e-15
    np.testing.assert_allclose(np.trapezoid(density, y, axis=1), 1.0, atol=1e-6)


def test_dmm_in_two_outputs_integrates_to_one():
    conditional = random_conditional(4, 1, 3, o=2)
    axis = np.linspace(-14, 14, 401)
    grid = np.stack(np.meshgrid(axis, axis, indexing="ij"), axis=-1).reshape(1, -1, 2)
    for eps in (0.0, 0.6, 1.0):
        density = dmm_pdf(conditional, grid, eps).reshape(axis.size, axis.size)
        assert density.min() >= -1e-15
        assert np.trapezoid(np.trapezoid(density, axis, axis=1), axis) == pytest.approx(1.0, abs=1e-4)


def test_dmm_at_zero_exploration_is_the_gmr_density():
    mixture = GaussianMixture.from_parameters(
        np.array([0.4, 0.6]), np.array([[0.0, 1.0], [2.0, -1.0]]), np.array([[[1, 0.5], [0.5, 1]], [[2, -0.3], [-0.3, 0.5]]])
    )
    x = np.array([[0.5], [1.5]])
    conditional = condition(mixture, [0], [1], x)
    y = np.array([[0.3], [-0.7]])
    joint = np.exp(mixture.score_samples(np.column_stack([x, y])))
    marginal = sum(w * norm(m[0], np.sqrt(c[0, 0])).pdf(x[:, 0]) for w, m, c in
                   zip(mixture.weights_, mixture.means_, mixture.covariances_, strict=True))
    np.testing.assert_allclose(dmm_pdf(conditional, y, 0.0), joint / marginal, rtol=1e-10)


# -- the mode ----------------------------------------------------------------------------------------


def dense_maximum(conditional: Conditional, eps: np.ndarray, lo: float = -30, hi: float = 30, n: int = 20001):
    y = np.linspace(lo, hi, n)
    density = dmm_pdf(conditional, np.broadcast_to(y[None, :, None], (len(conditional), n, 1)), eps)
    return density.max(axis=1), y[density.argmax(axis=1)]


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 100_000), k=st.integers(1, 5), auto=st.booleans(), eps=st.floats(0, 1))
def test_mode_is_the_global_maximum_on_a_dense_grid(seed, k, auto, eps):
    conditional = random_conditional(seed, 25, k)
    mode = dmm_mode(conditional, "auto" if auto else eps)
    grid_max, _ = dense_maximum(conditional, mode.exploration)
    np.testing.assert_allclose(dmm_pdf(conditional, mode.output, mode.exploration), mode.pdf, rtol=1e-12)
    assert np.all(mode.pdf >= grid_max * (1 - 1e-6))
    np.testing.assert_array_equal(mode.pdf, mode.max_pdf)
    assert np.all(mode.density_traded == 0)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_mode_is_global_with_far_apart_components_of_very_unequal_weight(seed):
    """Components 400 units apart, weights from 1e-12 to 1: most donut terms are negligible at
    most points (the climb skips them) and many starts are left out; the mode must stay global."""
    rng = np.random.default_rng(seed)
    n, k = 5, 9
    weights = rng.dirichlet(np.ones(k), size=n) * 10.0 ** rng.uniform(-12, 0, (n, k))
    weights /= weights.sum(axis=1, keepdims=True)
    means = rng.uniform(-200, 200, (n, k, 1))
    covariances = rng.uniform(0.05, 3.0, (k, 1, 1))
    conditional = conditional_of(weights, means, covariances)
    for eps in ("auto", 0.0, 0.6, 1.0):
        mode = dmm_mode(conditional, eps)
        grid_max, _ = dense_maximum(conditional, mode.exploration, -215, 215, 100_001)
        assert np.all(mode.pdf >= grid_max * (1 - 1e-6))
        np.testing.assert_allclose(dmm_pdf(conditional, mode.output, mode.exploration), mode.pdf, rtol=1e-12)


def test_many_low_components_on_one_spot_outweigh_a_single_high_one():
    """Five components at 0, each lower than the one at 10, together higher: none may be left out."""
    weights = [[0.12] * 5 + [0.4]]
    means = [[[0.0]] * 5 + [[10.0]]]
    mode = dmm_mode(conditional_of(weights, means, [[[1.0]]] * 6), 0.0)
    assert mode.output[0, 0] == pytest.approx(0.0, abs=1e-6)
    assert mode.pdf[0] == pytest.approx(0.6 * norm.pdf(0.0) + 0.4 * norm.pdf(10.0), rel=1e-9)


def test_mode_is_the_global_maximum_in_two_outputs():
    conditional = random_conditional(11, 6, 3, o=2)
    mode = dmm_mode(conditional, 0.8)
    axis = np.linspace(-12, 12, 401)
    grid = np.stack(np.meshgrid(axis, axis, indexing="ij"), axis=-1).reshape(1, -1, 2)
    density = dmm_pdf(conditional, np.broadcast_to(grid, (6, grid.shape[1], 2)), mode.exploration)
    assert np.all(mode.pdf >= density.max(axis=1) * (1 - 1e-6))


@settings(max_examples=20, deadline=None)
@given(seed=st.integers(0, 10_000), o=st.integers(1, 2))
def test_zero_exploration_gives_the_gmr_mean_when_unimodal(seed, o):
    conditional = random_conditional(seed, 10, 1, o=o)
    mode = dmm_mode(conditional, 0.0)
    np.testing.assert_allclose(mode.output, conditional.mean, atol=1e-7)


def test_mode_never_below_bfgs_from_the_gmr_mean():
    conditional = random_conditional(5, 30, 3)
    mode = dmm_mode(conditional)
    for i in range(len(conditional)):
        single = Conditional(
            conditional.weights[i : i + 1], conditional.means[i : i + 1], conditional.covariances,
            conditional.mean[i : i + 1], conditional.covariance[i : i + 1],
        )
        eps = mode.exploration[i : i + 1]
        result = minimize(lambda y, s=single, e=eps: -dmm_pdf(s, y[None, :], e)[0], conditional.mean[i], method="BFGS")
        assert mode.pdf[i] >= -result.fun * (1 - 1e-9)


def test_symmetric_donut_breaks_the_tie_towards_the_larger_output():
    conditional = conditional_of([[1.0]], [[[2.0]]], [[[1.0]]])
    mode = dmm_mode(conditional, 1.0)
    assert mode.output[0, 0] > 2.0
    mirrored = dmm_pdf(conditional, 4.0 - mode.output, 1.0)
    assert mirrored[0] == pytest.approx(mode.pdf[0], rel=1e-9)


def test_continuity_keeps_one_side_of_the_donut_and_reports_the_cost():
    # Two components swap weight along the path; their donuts' outer rings are nearly equally high,
    # so the global mode jumps from one side to the other half way.
    n = 41
    share = np.linspace(0.45, 0.55, n)
    weights = np.column_stack([share, 1 - share])
    means = np.broadcast_to(np.array([[0.0], [0.5]]), (n, 2, 1)).copy()
    conditional = conditional_of(weights, means, [[[1.0]], [[1.0]]])
    plain = dmm_mode(conditional, 1.0)
    smooth = dmm_mode(conditional, 1.0, continuity=0.2)
    assert np.abs(np.diff(plain.output[:, 0])).max() > 1.0
    assert np.abs(np.diff(smooth.output[:, 0])).max() < 0.2
    assert np.all(smooth.density_traded <= 0.2) and smooth.density_traded.max() > 0
    np.testing.assert_allclose(smooth.pdf, smooth.max_pdf * (1 - smooth.density_traded), rtol=1e-12)


@pytest.mark.parametrize(
    "kwargs,message",
    [({"exploration": "high"}, "'auto' or a number"), ({"exploration": 1.5}, r"\[0, 1\]"),
     ({"exploration": np.ones(3)}, "shape"), ({"scale": -1.0}, "scale"), ({"continuity": 2.0}, "continuity")],
)
def test_bad_mode_options_are_named(kwargs, message):
    conditional = random_conditional(0, 2, 2)
    with pytest.raises(InputError, match=message):
        dmm_mode(conditional, **kwargs)


def test_each_compiled_kernel_has_one_version_whatever_the_memory_layout():
    """Another argument type or layout would compile (and cache) another version of a kernel,
    seconds each on first use: every entry point hands the kernels C-ordered float64 arrays."""
    from rlff.model import climb, regression

    mixture = GaussianMixture.from_parameters(
        np.array([0.3, 0.7]), np.array([[0.0, 0.0, 1.0], [2.0, 1.0, 3.0]]), np.array([np.eye(3), 2 * np.eye(3)])
    )
    X = np.asfortranarray(np.random.default_rng(0).normal(size=(40, 2)))
    for queries in (X, X[::2], X[:1], X.astype(np.float32), X.tolist()):
        conditional = condition(mixture, [0, 1], [2], queries)
        regression.predict(mixture, [0, 1], [2], queries)
        dmm_mode(conditional)
        dmm_mode(conditional, 0.5, tol=1e-6)
    transposed = Conditional(  # per-sample arrays in Fortran order, as a caller might build them
        np.asfortranarray(conditional.weights), np.asfortranarray(conditional.means), conditional.covariances,
        np.asfortranarray(conditional.mean), np.asfortranarray(conditional.covariance),
    )
    dmm_mode(transposed)
    for queries in (X[:, :1], np.asfortranarray(X[::3, :1]), X[:1, :1].tolist()):  # two outputs: the other kernel
        dmm_mode(condition(mixture, [0], [1, 2], queries))
        dmm_mode(condition(mixture, [0], [1, 2], queries), 0.7, continuity=True)
    assert len(regression._conditional_kernel.signatures) == 1
    assert len(climb._modes_1d_kernel.signatures) == 1
    assert len(climb._modes_nd_kernel.signatures) == 1


# -- several outputs: the compiled climb -----------------------------------------------------------


def bfgs_tops(conditional: Conditional, eps: np.ndarray, i: int) -> list[float]:
    """P_DMM at the ends of scipy BFGS runs for input i, started from the GMR mean and from
    every component mean (the thesis' method and its obvious extension)."""
    single = Conditional(
        conditional.weights[i : i + 1], conditional.means[i : i + 1], conditional.covariances,
        conditional.mean[i : i + 1], conditional.covariance[i : i + 1],
    )
    starts = [conditional.mean[i], *conditional.means[i]]
    tops = []
    for start in starts:
        result = minimize(lambda y, s=single, e=eps[i : i + 1]: -dmm_pdf(s, y[None, :], e)[0], start, method="BFGS")
        tops.append(-result.fun)
    return tops


@pytest.mark.slow
@pytest.mark.parametrize("o", [2, 3])
@pytest.mark.parametrize("seed", [21, 22])
def test_several_outputs_never_below_bfgs_from_the_gmr_mean_and_every_component_mean(seed, o):
    conditional = random_conditional(seed, 25, 4, o=o)
    for exploration in ("auto", 1.0):
        mode = dmm_mode(conditional, exploration)
        np.testing.assert_allclose(dmm_pdf(conditional, mode.output, mode.exploration), mode.pdf, rtol=1e-12)
        for i in range(len(conditional)):
            assert mode.pdf[i] >= max(bfgs_tops(conditional, mode.exploration, i)) * (1 - 1e-7), (exploration, i)


def test_a_top_that_rises_inside_a_followed_block_is_found_at_every_input():
    """Along a path the climb follows the tops from input to input and climbs every start afresh
    only at the ends of each block. Here a far component's weight rises from 3e-4 to 1 - 5e-5 along
    41 inputs: its top is a low one (not followed) at first and the highest from about input 18 on,
    inside the first block. The fresh climb at the block's end finds it, and following it back
    must give every input its global mode, as climbing each input alone does."""
    n = 41
    share = 1 / (1 + np.exp(-np.linspace(-8.0, 10.0, n)))
    weights = np.column_stack([1 - share, share])
    means = np.broadcast_to(np.array([[0.0, 0.0], [4.0, -3.0]]), (n, 2, 2)).copy()
    covariances = [np.array([[0.3, 0.05], [0.05, 0.2]]), np.array([[0.2, -0.04], [-0.04, 0.25]])]
    conditional = conditional_of(weights, means, covariances)
    eps = np.full(n, 0.3)
    mode = dmm_mode(conditional, eps)
    np.testing.assert_allclose(mode.max_pdf, each_alone(conditional, eps), rtol=1e-9)
    switch = int(np.argmax(mode.output[:, 0] > 2.0))
    assert 5 < switch < 31  # inside the first block: found by following back, not afresh
    np.testing.assert_allclose(mode.output[switch:], np.broadcast_to(mode.output[-1], (n - switch, 2)), atol=1e-4)


TWO, THREE = ("velocity", "shoulder"), ("velocity", "shoulder", "shoulder_velocity")


@pytest.mark.parametrize(
    ("outputs", "seed", "points", "distance"),
    [(TWO, 3, 600, 2.5), (THREE, 3, 600, 2.5), (TWO, 5, 150, 2.5), (THREE, 5, 150, 2.5), (THREE, 5, 600, 3.5)],
)
def test_followed_modes_along_a_whole_arm_path_are_those_of_each_input_alone(outputs, seed, points, distance):
    """A whole-arm model's DMM along a throw's phase points, followed, against every point
    climbed alone. Seed 3 at 600 points has tops born and gone within 14 points and one that the
    followed top jumps onto; seed 5 at 150 points a narrow component that leaves its followed
    top behind from one point to the next; seed 5 at 3.5 m a top, let go while low, whose
    component's weight then rises fast: it becomes the highest inside a block and moves by more
    than a climb follows from one point to the next, so that following it back from the fresh
    input that finds it needs fresh climbs on the way (without them 7 points kept a top 4x lower)."""
    from rlff.model import Model
    from wholearm_dataset import whole_arm_throws

    model = Model.fit(whole_arm_throws(seed=seed), outputs=outputs, seed=0)
    path = np.column_stack([np.linspace(0.8, 2.9, points), np.full(points, distance)])
    conditional = model.condition(path)
    mode = dmm_mode(conditional)
    np.testing.assert_allclose(dmm_pdf(conditional, mode.output, mode.exploration), mode.pdf, rtol=1e-12)
    assert np.all(mode.max_pdf >= each_alone(conditional, mode.exploration) * (1 - 1e-9))


def test_fresh_inputs_along_a_path_follow_how_fast_the_mixture_changes():
    """The inputs climbed afresh: the first and the last, one every ``_TRACK_CHANGE`` of change of
    the mixture (here a component mean moving 0.01 per input, then 0.25), at most
    ``_TRACK_LONGEST`` apart; every input where the inputs are not a path."""
    from rlff.model import climb

    n = 201
    step = np.where(np.arange(n) < 100, 0.01, 0.25)
    means = np.zeros((n, 2, 2))
    means[:, 0, 0] = np.cumsum(step)
    log_a, radii = np.zeros((n, 2)), np.ones(n)
    fresh = climb._fresh_inputs(means, log_a, radii, 2 * radii)
    assert fresh[0] == 0 and fresh[-1] == n - 1
    gaps = np.diff(fresh)
    slow, fast = gaps[fresh[1:] < 100], gaps[fresh[:-1] > 100]
    assert np.all(slow == climb._TRACK_LONGEST)  # 0.32 of change: the longest block
    per_block = climb._TRACK_CHANGE / 0.25  # inputs (up to the sums' rounding)
    assert np.all((fast[:-1] >= per_block) & (fast[:-1] <= per_block + 1))
    rng = np.random.default_rng(0)  # random queries: means and weights anywhere at each input
    scattered, jumping = rng.normal(0.0, 10.0, size=(n, 2, 2)), np.log(rng.uniform(1e-3, 1.0, size=(n, 2)))
    np.testing.assert_array_equal(climb._fresh_inputs(scattered, jumping, radii, 2 * radii), np.arange(n))
    np.testing.assert_array_equal(climb._fresh_inputs(means[:1], log_a[:1], radii[:1], radii[:1]), [0])


def test_continuity_with_two_outputs_keeps_the_mode_nearest_the_previous_point():
    """Two components of two outputs, far apart, swap weight along the path: the global mode
    jumps from one to the other half way. With continuity the path stays on the mode it is on,
    the one of near-equal density nearest the previous point."""
    n = 41
    share = np.linspace(0.46, 0.54, n)
    weights = np.column_stack([share, 1 - share])
    means = np.broadcast_to(np.array([[0.0, 0.0], [3.0, 1.5]]), (n, 2, 2)).copy()
    covariance = np.array([[0.3, 0.05], [0.05, 0.2]])
    conditional = conditional_of(weights, means, [covariance, covariance])
    plain = dmm_mode(conditional, 0.0)
    smooth = dmm_mode(conditional, 0.0, continuity=0.2)
    jumps = np.sqrt((np.diff(plain.output, axis=0) ** 2).sum(axis=1))
    assert jumps.max() > 3.0 and np.count_nonzero(jumps > 1e-6) == 1
    assert np.sqrt((np.diff(smooth.output, axis=0) ** 2).sum(axis=1)).max() < 1e-6
    np.testing.assert_allclose(smooth.output, np.broadcast_to(plain.output[-1], (n, 2)), atol=1e-5)
    assert np.all(smooth.density_traded <= 0.2) and smooth.density_traded[0] > 0.1
    np.testing.assert_allclose(smooth.pdf, smooth.max_pdf * (1 - smooth.density_traded), rtol=1e-12)
