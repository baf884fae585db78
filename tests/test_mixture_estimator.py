"""GaussianMixture follows scikit-learn's estimator protocol: params, clone, grid search, checks."""

from __future__ import annotations

import numpy as np
import pytest
from sklearn.base import clone
from sklearn.model_selection import GridSearchCV, KFold
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import StandardScaler
from sklearn.utils.estimator_checks import check_estimator

from rlff.errors import InputError
from rlff.model.mixture import GaussianMixture


def two_clusters(seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return np.concatenate([rng.normal(-5.0, 1.0, (150, 2)), rng.normal(5.0, 1.0, (150, 2))])


def test_get_params_returns_the_init_arguments_unchanged():
    column_variance = np.array([0.1, 0.2])
    mixture = GaussianMixture(3, reg_covar=1e-4, column_variance=column_variance, random_state=7)
    params = mixture.get_params()
    assert list(params) == [
        "n_components", "reg_covar", "column_variance", "tol", "max_iter", "n_init", "init",
        "random_state", "weights_init", "means_init", "covariances_init",
    ]
    assert params["n_components"] == 3 and params["reg_covar"] == 1e-4 and params["random_state"] == 7
    assert params["column_variance"] is column_variance
    assert params == mixture.get_params(deep=False)


def test_set_params_changes_settings_and_validation_waits_for_fit():
    mixture = GaussianMixture()
    assert mixture.set_params(n_components=2, tol=1e-5) is mixture
    assert (mixture.n_components, mixture.tol) == (2, 1e-5)
    mixture.set_params(n_components=0)  # stored as given, like scikit-learn
    with pytest.raises(InputError, match="n_components must be an integer >= 1, got 0"):
        mixture.fit(two_clusters())


def test_set_params_refuses_an_unknown_name_and_lists_the_parameters():
    with pytest.raises(InputError, match=r"no parameter 'components' \(parameters: n_components, reg_covar"):
        GaussianMixture().set_params(components=2)


def test_clone_gives_an_unfitted_copy_with_the_same_settings():
    original = GaussianMixture(3, random_state=0, n_init=2)
    copy = clone(original)
    assert copy is not original and type(copy) is GaussianMixture
    assert copy.get_params() == original.get_params()
    X = two_clusters()
    original.fit(X)
    fitted_copy = clone(original)
    assert not hasattr(fitted_copy, "weights_")
    fitted_copy.fit(X)
    np.testing.assert_array_equal(fitted_copy.means_, original.means_)
    assert fitted_copy.lower_bound_ == original.lower_bound_


def test_repr_names_the_settings_that_differ_from_the_defaults():
    assert repr(GaussianMixture()) == "GaussianMixture()"
    assert repr(GaussianMixture(3, random_state=0, init="random")) == (
        "GaussianMixture(n_components=3, init='random', random_state=0)"
    )


def test_grid_search_over_n_components_ranks_by_score():
    X = two_clusters()
    search = GridSearchCV(GaussianMixture(random_state=0), {"n_components": [1, 2, 3]}, cv=KFold(5))
    search.fit(X)
    # The mean test score of each K is the mean of our score() on the held-out folds.
    for k, mean_score in zip([1, 2, 3], search.cv_results_["mean_test_score"], strict=True):
        by_hand = [
            GaussianMixture(k, random_state=0).fit(X[train]).score(X[test])
            for train, test in KFold(5).split(X)
        ]
        assert mean_score == pytest.approx(np.mean(by_hand), rel=1e-12)
    assert search.cv_results_["mean_test_score"][0] < search.cv_results_["mean_test_score"][1] - 1.0
    assert search.best_params_["n_components"] == int(
        [1, 2, 3][int(np.argmax(search.cv_results_["mean_test_score"]))]
    )
    assert isinstance(search.best_estimator_, GaussianMixture)
    assert search.best_estimator_.n_components == search.best_params_["n_components"]
    assert search.score(X) == pytest.approx(search.best_estimator_.score(X))


def test_grid_search_with_default_constructor():
    search = GridSearchCV(GaussianMixture(), {"n_components": [1, 2, 3]}).fit(two_clusters(1))
    assert search.best_params_["n_components"] in (2, 3)
    assert np.all(np.isfinite(search.cv_results_["mean_test_score"]))


def test_works_as_the_last_step_of_a_pipeline():
    X = two_clusters(2) * [1.0, 1000.0]
    pipeline = make_pipeline(StandardScaler(), GaussianMixture(2, random_state=0)).fit(X)
    labels = pipeline.predict(X)
    assert sorted(np.bincount(labels)) == [150, 150]
    assert np.isfinite(pipeline.score(X))


def test_n_features_in_is_set_and_checked():
    mixture = GaussianMixture(2, random_state=0).fit(two_clusters())
    assert mixture.n_features_in_ == 2
    with pytest.raises(InputError, match="X has 3 features, but GaussianMixture is expecting 2"):
        mixture.score(np.zeros((4, 3)))


@pytest.mark.parametrize(
    ("X", "message"),
    [
        (np.ones((5, 2)) + 1j, "Complex data not supported"),
        (np.array([[0.0, np.inf], [1.0, 2.0]]), r"non-finite value \(\+inf\) at row 0, column 1"),
        (np.array([[0.0, 1.0], [np.nan, 2.0]]), r"non-finite value \(NaN\) at row 1, column 0"),
        (np.zeros((3, 0)), r"no columns \(0 feature\(s\)"),
    ],
)
def test_bad_arrays_are_input_errors(X, message):
    with pytest.raises(InputError, match=message):
        GaussianMixture(1).fit(X)


def test_sparse_input_is_refused_with_a_hint():
    from scipy.sparse import csr_matrix

    with pytest.raises(InputError, match=r"sparse matrix: give a dense array"):
        GaussianMixture(1).fit(csr_matrix(np.eye(4)))


#: scikit-learn's own estimator checks that GaussianMixture fails on purpose.
EXPECTED_FAILED_CHECKS = {
    "check_estimators_unfitted": "raises rlff.errors.InputError (a ValueError), not scikit-learn's "
    "NotFittedError: rlff does not import scikit-learn at run time",
    "check_dtype_object": "an object array holding a dict is an InputError (ValueError), not a TypeError",
    "check_fit1d": "a 1-D array is read as one column (N,) -> (N, 1) on purpose",
    "check_fit2d_predict1d": "a 1-D array is read as one column (N,) -> (N, 1) on purpose",
}


@pytest.mark.filterwarnings("ignore:Estimator GaussianMixture does not inherit:UserWarning")
def test_passes_scikit_learns_estimator_checks():
    results = check_estimator(
        GaussianMixture(random_state=0), expected_failed_checks=EXPECTED_FAILED_CHECKS, on_fail=None,
        on_skip=None,
    )
    failed = {r["check_name"]: str(r["exception"])[:200] for r in results if r["status"] == "failed"}
    assert failed == {}
    ran = {r["check_name"] for r in results if r["status"] == "passed"}
    assert {"check_get_params_invariance", "check_set_params", "check_fit_idempotent",
            "check_n_features_in_after_fitting", "check_estimators_nan_inf"} <= ran
    assert len(ran) >= 35


def test_parameters_that_overflow_when_standardised_are_refused_but_a_zero_weight_is_not():
    eye = np.array([np.eye(2)] * 2)
    zero_weight = GaussianMixture.from_parameters(np.array([1.0, 0.0]), np.zeros((2, 2)), eye)
    assert zero_weight.score(np.zeros((3, 2))) == pytest.approx(-np.log(2 * np.pi))
    with pytest.raises(InputError, match="overflow on its standardised scale"):
        GaussianMixture.from_parameters(np.array([0.5, 0.5]), np.array([[0.0, 0.0], [1e200, 0.0]]), eye)
