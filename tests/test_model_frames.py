"""pandas DataFrames are read by column name (Model, GaussianMixture, rlff.condition/predict);
numpy arrays keep their positional meaning."""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd
import pytest

import rlff
from rlff import GaussianMixture, Model
from rlff.errors import InputError
from rlff.synthetic.thesis import thesis_dataset

#: The issue's example: GMR velocity at angle 5 rad, basket 8.5 m, of a K = 3 thesis model.
ANGLE, DISTANCE = 5.0, 8.5


@pytest.fixture(scope="module")
def samples() -> pd.DataFrame:
    """The thesis set as a frame in another column order than the model's, plus a text column."""
    frame = pd.DataFrame(thesis_dataset().to_array(("velocity", "distance", "angle")), columns=["velocity", "distance", "angle"])
    frame["note"] = "synthetic"
    return frame


@pytest.fixture(scope="module")
def model(samples) -> Model:
    return Model.fit(samples, components=3)


def test_predict_takes_a_frames_columns_by_name_not_position(model):
    reordered = pd.DataFrame({"distance": [DISTANCE], "angle": [ANGLE]})
    by_name, _ = model.predict(reordered)
    in_model_order, _ = model.predict(np.array([[ANGLE, DISTANCE]]))
    positional, _ = model.predict(reordered.to_numpy())  # an array is positional: angle 8.5, distance 5
    np.testing.assert_array_equal(by_name, in_model_order)
    assert by_name[0, 0] == pytest.approx(21.26, abs=0.005)  # the right answer
    # what the frame gave before: the array read in the model's order, angle 8.5 and distance 5
    np.testing.assert_array_equal(positional, model.predict(np.array([[DISTANCE, ANGLE]]))[0])
    assert abs(positional[0, 0] - by_name[0, 0]) > 5.0


def test_condition_takes_the_inputs_among_other_columns(model, samples):
    frame = samples.iloc[::50]  # velocity, distance, angle, note: inputs picked by name
    conditional = model.condition(frame)
    expected = model.condition(frame[["angle", "distance"]].to_numpy())
    np.testing.assert_array_equal(conditional.mean, expected.mean)
    np.testing.assert_array_equal(conditional.weights, expected.weights)


@pytest.mark.parametrize(
    ("frame", "message"),
    [
        (pd.DataFrame({"dist": [1.0], "angle": [2.0]}), r"inputs: the DataFrame has no column 'distance' \(columns present: dist, angle\)"),
        (pd.DataFrame({"a": [1.0]}), r"no columns 'angle', 'distance' \(columns present: a\)"),
        (pd.DataFrame({"angle": ["x"], "distance": [1.0]}), r"column 'angle' is not numeric"),
        (pd.DataFrame({"angle": [1.0, np.inf], "distance": [1.0, 2.0]}), r"column 'angle' has a non-finite value \(inf\) at row 1"),
        (pd.DataFrame([[1.0, 2.0, 3.0]], columns=["angle", "angle", "distance"]), r"column 'angle' 2 times"),
        (pd.DataFrame({"angle": [], "distance": []}), r"has no rows"),
    ],
)
def test_a_frame_without_the_named_columns_is_refused(model, frame, message):
    with pytest.raises(InputError, match=message):
        model.predict(frame)


def test_fit_on_a_frame_equals_fit_on_the_dataset(samples, model):
    from_dataset = Model.fit(thesis_dataset(), components=3)
    np.testing.assert_array_equal(model.mixture.means_, from_dataset.mixture.means_)
    assert model.columns == ("angle", "distance", "velocity")
    assert model.input_range == from_dataset.input_range


def test_fit_on_a_frame_refuses_missing_columns_and_columns_argument(samples):
    with pytest.raises(InputError, match=r"data: the DataFrame has no column 'velocity' \(columns present: distance, angle, note\)"):
        Model.fit(samples.drop(columns="velocity"), components=2)
    with pytest.raises(InputError, match="a DataFrame names its own"):
        Model.fit(samples, columns=["velocity", "distance", "angle", "note"], components=2)


def test_load_is_a_classmethod_and_the_loaded_mixture_reads_frames_by_name(model, tmp_path):
    path = tmp_path / "model.json"
    model.save(path)
    for where in (path, str(path)):
        loaded = Model.load(where)
        assert isinstance(loaded, Model)
    frame = pd.DataFrame({"distance": [DISTANCE, 2.0], "angle": [ANGLE, 1.0]})
    np.testing.assert_array_equal(loaded.predict(frame)[0], model.predict(frame)[0])
    # the top-level functions take the frame's columns by the mixture's names too
    mean, _ = rlff.predict(loaded.mixture, [0, 1], [2], frame)
    np.testing.assert_array_equal(mean, model.predict(frame)[0])
    np.testing.assert_array_equal(rlff.condition(loaded.mixture, [0, 1], [2], frame).mean, mean)


def test_a_model_refuses_a_mixture_fitted_on_other_columns(samples):
    mixture = GaussianMixture(2, random_state=0).fit(samples[["velocity", "distance", "angle"]])
    with pytest.raises(InputError, match=r"fitted on columns \['velocity', 'distance', 'angle'\]"):
        Model(mixture, ("angle", "distance"), ("velocity",), {"angle": (0, 1), "distance": (0, 1)})


def test_gaussian_mixture_fitted_on_a_frame_keeps_and_uses_its_column_names(samples):
    frame = samples[["velocity", "distance", "angle"]]
    mixture = GaussianMixture(3, random_state=0).fit(frame)
    assert mixture.feature_names_in_.dtype == object
    assert mixture.feature_names_in_.tolist() == ["velocity", "distance", "angle"]
    reordered = samples[["angle", "note", "velocity", "distance"]]
    assert mixture.score(reordered) == mixture.score(frame) == mixture.score(frame.to_numpy())
    np.testing.assert_array_equal(mixture.predict_proba(reordered), mixture.predict_proba(frame))
    with pytest.raises(InputError, match=r"no column 'velocity' \(columns present: angle, distance\)"):
        mixture.score(samples[["angle", "distance"]])
    mixture.fit(frame.to_numpy())  # refitting on an array forgets the names
    assert not hasattr(mixture, "feature_names_in_")


def test_a_named_frame_needs_a_named_mixture_and_unnamed_frames_are_positional(samples):
    values = samples[["velocity", "distance", "angle"]].to_numpy()
    mixture = GaussianMixture(2, random_state=0).fit(values)
    with pytest.raises(InputError, match="the mixture has no column names"):
        mixture.score(samples[["velocity", "distance", "angle"]])
    with pytest.raises(InputError, match="the mixture has no column names"):
        rlff.predict(mixture, [2, 1], [0], samples[["angle", "distance"]])
    assert mixture.score(pd.DataFrame(values)) == mixture.score(values)  # integer labels: no names
    mean, _ = rlff.predict(mixture, [2, 1], [0], values[:, [2, 1]])
    assert mean.shape == (len(values), 1)


def test_a_read_only_array_from_a_frame_runs_the_one_compiled_kernel(model):
    from rlff.model import regression

    model.predict(np.array([[ANGLE, DISTANCE]]))
    versions = len(regression._conditional_kernel.signatures)
    values = pd.DataFrame({"angle": [ANGLE], "distance": [DISTANCE]}).to_numpy()
    values.flags.writeable = False  # what pandas' copy-on-write gives
    model.predict(values)
    assert len(regression._conditional_kernel.signatures) == versions


def test_a_frame_of_a_dataset_file_warns_that_its_throw_metadata_is_not_read(tmp_path, samples):
    # pd.read_csv("clean.csv") fitted without a word: effective samples None instead of 580.7,
    # BIC 65178 instead of 3817, no release (the throw generated past it)
    from rlff.dataset import Trajectory, write_csv

    data = rlff.Dataset([Trajectory(t.id, t.data, {"measured_share": 0.5, "cut_angle": 9.0})
                         for t in thesis_dataset()])
    write_csv(data, tmp_path / "clean.csv")
    frame = pd.read_csv(tmp_path / "clean.csv")
    with pytest.warns(UserWarning, match=r"the DataFrame's columns trajectory, measured_share, cut_angle are not "
                                         r"read: .*fit a Dataset, Model.fit\(rlff.formats.read_dataset\(path\)\)"):
        from_frame = Model.fit(frame, components=2)
    assert from_frame.fit_info["release"] is None  # what the warning says
    assert Model.fit(data, components=2).fit_info["release"]["value"] == 9.0
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        Model.fit(samples, components=2)  # plain samples lose nothing: no warning
