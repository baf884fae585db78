"""Gaussian Mixture Regression: exact values, closed forms, Monte Carlo and gmr cross-checks."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rlff.errors import InputError
from rlff.model.mixture import GaussianMixture
from rlff.model.regression import condition, predict


def mixture_of(weights, means, covariances) -> GaussianMixture:
    return GaussianMixture.from_parameters(np.asarray(weights, float), np.asarray(means, float), np.asarray(covariances, float))


def random_mixture(seed: int, k: int, d: int) -> GaussianMixture:
    rng = np.random.default_rng(seed)
    factors = rng.normal(size=(k, d, d))
    covariances = factors @ np.swapaxes(factors, 1, 2) + 0.3 * np.eye(d)
    weights = rng.dirichlet(np.ones(k))
    return mixture_of(weights, rng.normal(0, 2, (k, d)), covariances)


def test_two_unit_gaussians_at_zero():
    mixture = mixture_of([0.5, 0.5], [[0, 1], [1, 2]], [np.eye(2), np.eye(2)])
    result = condition(mixture, [0], [1], np.array([[0.0]]))
    assert result.mean[0, 0] == pytest.approx(1.37754067, abs=1e-8)
    # h = (1, e^-1/2) / (1 + e^-1/2): closed form of the weights
    np.testing.assert_allclose(result.weights[0], np.array([1, np.exp(-0.5)]) / (1 + np.exp(-0.5)), rtol=1e-12)


def test_mean_and_total_variance_of_two_components():
    mixture = mixture_of([0.5, 0.5], [[0, 0], [0, 2]], [np.diag([1, 0.5])] * 2)
    result = condition(mixture, [0], [1], np.array([[0.0]]))
    assert result.mean[0, 0] == pytest.approx(1.0, abs=1e-12)
    assert result.covariance[0, 0, 0] == pytest.approx(1.5, abs=1e-12)
    assert result.variance.shape == (1, 1)
    np.testing.assert_allclose(result.covariances[:, 0, 0], [0.5, 0.5])


def test_one_component_is_the_gaussian_conditional_for_several_inputs_and_outputs():
    mixture = random_mixture(3, 1, 5)
    mu, sigma = mixture.means_[0], mixture.covariances_[0]
    inputs, outputs = [4, 0, 2], [3, 1]
    X = np.random.default_rng(0).normal(size=(7, 3))
    result = condition(mixture, inputs, outputs, X)
    gain = sigma[np.ix_(outputs, inputs)] @ np.linalg.inv(sigma[np.ix_(inputs, inputs)])
    expected_mean = mu[outputs] + (X - mu[inputs]) @ gain.T
    expected_cov = sigma[np.ix_(outputs, outputs)] - gain @ sigma[np.ix_(inputs, outputs)]
    np.testing.assert_allclose(result.mean, expected_mean, atol=1e-10)
    np.testing.assert_allclose(result.covariance, np.broadcast_to(expected_cov, (7, 2, 2)), atol=1e-10)
    assert result.means.shape == (7, 1, 2) and result.weights.shape == (7, 1)


def test_weights_stay_finite_fifty_deviations_away():
    mixture = mixture_of([0.3, 0.7], [[0, 0], [1, 5]], [np.eye(2), np.diag([0.5, 1.0])])
    result = condition(mixture, [0], [1], np.array([[50.0], [-50.0], [1e3]]))
    assert np.all(np.isfinite(result.weights)) and np.all(np.isfinite(result.mean))
    np.testing.assert_allclose(result.weights.sum(axis=1), 1.0)
    # far away the component that is wider along x (variance 1 against 0.5) takes all the weight
    assert result.weights[0, 0] == pytest.approx(1.0)


@pytest.mark.parametrize("k", [1, 3, 6])
def test_same_means_as_gmr(k):
    from gmr import GMM

    mixture = random_mixture(k, k, 4)
    reference = GMM(k, priors=mixture.weights_, means=mixture.means_, covariances=mixture.covariances_)
    X = np.random.default_rng(k).normal(0, 2, (500, 2))
    ours = condition(mixture, [0, 2], [1, 3], X).mean
    np.testing.assert_allclose(ours, reference.predict([0, 2], X), rtol=1e-9, atol=1e-9)


def test_monte_carlo_conditional_matches_gmr():
    mixture = mixture_of([0.4, 0.6], [[0, 0], [1.5, 3]], [[[1, 0.6], [0.6, 1]], [[0.5, -0.2], [-0.2, 0.4]]])
    mixture.random_state = 0
    samples, _ = mixture.sample(3_000_000)
    for x0 in (0.0, 1.0, 2.0):
        near = samples[np.abs(samples[:, 0] - x0) < 0.01, 1]
        result = condition(mixture, [0], [1], np.array([[x0]]))
        se = near.std() / np.sqrt(near.size)
        assert near.mean() == pytest.approx(result.mean[0, 0], abs=5 * se)
        assert near.var() == pytest.approx(result.covariance[0, 0, 0], rel=0.05)


@settings(max_examples=20, deadline=None)
@given(seed=st.integers(0, 10_000), k=st.integers(1, 4))
def test_total_expectation_and_variance_over_sampled_inputs(seed, k):
    """E[y] = E_x[m(x)] and Var[y] = E_x[V(x)] + Var_x[m(x)] over samples of the joint."""
    mixture = random_mixture(seed, k, 2)
    mixture.random_state = seed
    samples, _ = mixture.sample(200_000)
    result = condition(mixture, [0], [1], samples[:, :1])
    y = samples[:, 1]
    se = y.std() / np.sqrt(y.size)
    assert result.mean[:, 0].mean() == pytest.approx(y.mean(), abs=6 * se)
    total = result.covariance[:, 0, 0].mean() + result.mean[:, 0].var()
    assert total == pytest.approx(y.var(), rel=0.03)


@settings(max_examples=20, deadline=None)
@given(seed=st.integers(0, 10_000), k=st.integers(1, 5), o=st.integers(1, 2))
def test_batch_equals_one_by_one_and_weights_are_a_distribution(seed, k, o):
    mixture = random_mixture(seed, k, 2 + o)
    X = np.random.default_rng(seed).normal(0, 3, (20, 2))
    outputs = list(range(2, 2 + o))
    batch = condition(mixture, [0, 1], outputs, X)
    for i in (0, 7, 19):
        single = condition(mixture, [0, 1], outputs, X[i : i + 1])
        np.testing.assert_allclose(single.mean[0], batch.mean[i], rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(single.covariance[0], batch.covariance[i], rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(batch.weights.sum(axis=1), 1.0)
    assert np.all(np.linalg.eigvalsh(batch.covariance) > 0)


def reference_gmr(mixture, inputs, outputs, X):
    """Thesis eq. 2.3-2.6 written out component by component with SciPy's Gaussian."""
    from scipy.stats import multivariate_normal

    log_h, component_means, component_covs = [], [], []
    for w, mu, cov in zip(mixture.weights_, mixture.means_, mixture.covariances_, strict=True):
        s_ii, s_oi = cov[np.ix_(inputs, inputs)], cov[np.ix_(outputs, inputs)]
        gain = s_oi @ np.linalg.inv(s_ii)
        log_h.append(np.log(w) + multivariate_normal(mu[inputs], s_ii).logpdf(X))
        component_means.append(mu[outputs] + (X - mu[inputs]) @ gain.T)
        component_covs.append(cov[np.ix_(outputs, outputs)] - gain @ s_oi.T)
    log_h = np.array(log_h)
    h = np.exp(log_h - log_h.max(axis=0))
    h /= h.sum(axis=0)
    m = np.array(component_means)  # (K, N, O)
    mean = np.einsum("kn,kno->no", h, m)
    spread = m - mean
    covariance = np.einsum("kn,kop->nop", h, np.array(component_covs)) + np.einsum("kn,kno,knp->nop", h, spread, spread)
    return h.T, m.transpose(1, 0, 2), mean, covariance


@pytest.mark.parametrize("n_in,n_out,k", [(1, 1, 2), (2, 1, 5), (3, 2, 4), (4, 3, 3)])
def test_matches_the_formulas_written_out_over_several_blocks(n_in, n_out, k):
    mixture = random_mixture(n_in * 10 + k, k, n_in + n_out)
    inputs, outputs = list(range(n_in)), list(range(n_in, n_in + n_out))
    X = np.random.default_rng(k).normal(0, 3, (1300, n_in))  # 1300: more than two blocks of samples
    weights, means, mean, covariance = reference_gmr(mixture, inputs, outputs, X)
    result = condition(mixture, inputs, outputs, X)
    np.testing.assert_allclose(result.weights, weights, rtol=1e-9, atol=1e-14)
    np.testing.assert_allclose(result.means, means, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(result.mean, mean, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(result.covariance, covariance, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(result.covariance, np.swapaxes(result.covariance, 1, 2), rtol=0, atol=0)
    # predict gives the same mean and total covariance without the per-component arrays
    predicted_mean, predicted_covariance = predict(mixture, inputs, outputs, X)
    np.testing.assert_array_equal(predicted_mean, result.mean)
    np.testing.assert_array_equal(predicted_covariance, result.covariance)


@pytest.mark.parametrize(
    "inputs,outputs,X,message",
    [
        ([0], [0], np.zeros((1, 1)), "share a column"),
        ([0], [5], np.zeros((1, 1)), "out of range"),
        ([], [1], np.zeros((1, 0)), "at least one column"),
        ([0], [1], np.zeros((3, 2)), "shape"),
        ([0], [1], np.array([[np.nan]]), "NaN or inf"),
    ],
)
def test_bad_conditioning_is_named(inputs, outputs, X, message):
    mixture = mixture_of([1.0], [[0, 0]], [np.eye(2)])
    with pytest.raises(InputError, match=message):
        condition(mixture, inputs, outputs, X)


def test_an_unfitted_mixture_and_column_names_are_refused_in_one_line():
    # until 2026-12-07: AttributeError 'weights_' and ValueError from int("a")
    X = np.zeros((3, 2))
    with pytest.raises(InputError, match=r"this GaussianMixture is not fitted yet \(no weights_, means_, "
                                         r"covariances_\): call fit first"):
        condition(GaussianMixture(2), [0, 1], [2], X)
    fitted = mixture_of([1.0], [[0, 0, 0]], [np.eye(3)])
    for function in (condition, predict):
        with pytest.raises(InputError, match=r"inputs \['a', 'b'\] must be column positions \(integers from 0 to 2\)"):
            function(fitted, ["a", "b"], [2], X)
    with pytest.raises(InputError, match=r"outputs \[1.5\] must be column positions"):
        condition(fitted, [0], [1.5], X[:, :1])
    assert condition(fitted, np.array([0, 1]), range(2, 3), X).mean.shape == (3, 1)


def test_a_wrong_shape_is_reported_as_given():
    mixture = mixture_of([1.0], [[0, 0, 0]], [np.eye(3)])
    with pytest.raises(InputError, match=r"X must have shape \(n, 2\) \(or \(2,\) for one row\), got \(5,\)$"):
        condition(mixture, [0, 1], [2], np.zeros(5))
    with pytest.raises(InputError, match=r"X must have shape \(n, 1\) \(or \(n,\)\), got \(5, 2\)$"):
        predict(mixture, [0], [2], np.zeros((5, 2)))
