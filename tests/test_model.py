"""Model: fitting named columns, the thesis synthetic set, model.json, generated paths."""

from __future__ import annotations

import json
import re
import warnings

import numpy as np
import pandas as pd
import pytest

from rlff.dataset import Dataset, Trajectory
from rlff.errors import InputError
from rlff.model import GeneratedPath, Model
from rlff.model.donut import dmm_pdf
from rlff.synthetic.thesis import thesis_dataset


@pytest.fixture(scope="module")
def thesis_model() -> Model:
    return Model.fit(thesis_dataset(), seed=0)


def test_thesis_set_follows_the_formula():
    data = thesis_dataset()
    assert len(data) == 11 and data.n_samples == 550
    angle = np.linspace(0, 10, 50)
    for z, trajectory in enumerate(data, start=1):
        np.testing.assert_array_equal(trajectory["angle"], angle)
        np.testing.assert_array_equal(trajectory["distance"], np.full(50, z))
        np.testing.assert_allclose(trajectory["velocity"], (1 + 0.1 * (z - 1)) * (-(angle**2) + 10 * angle) / 2)
        assert trajectory.meta["target"] == z
    steeper = thesis_dataset(factor_slope=0.3, n_trajectories=3, n_points=11)
    assert len(steeper) == 3 and len(steeper[0]) == 11
    np.testing.assert_allclose(steeper[2]["velocity"], 1.6 * (-(steeper[2]["angle"] ** 2) + 10 * steeper[2]["angle"]) / 2)


def test_thesis_paths_grow_with_distance_and_sit_on_the_global_maximum(thesis_model):
    paths = {d: thesis_model.generate({"distance": d}) for d in (4.5, 8.5, 12.5)}
    velocities = np.array([paths[d].velocity for d in (4.5, 8.5, 12.5)])
    assert np.all(np.diff(velocities, axis=0) > 0)  # at every angle, also the unseen 12.5
    grid = np.linspace(-10, 40, 5001)
    for distance, path in paths.items():
        assert path.angle.size == 100 and path.angle[0] == 0 and path.angle[-1] == 10
        conditional = thesis_model.condition(np.column_stack([path.angle, np.full(100, distance)]))
        density = dmm_pdf(conditional, np.broadcast_to(grid[None, :, None], (100, grid.size, 1)), path.exploration)
        assert np.all(path.pdf >= density.max(axis=1) * (1 - 1e-6))
        np.testing.assert_allclose(dmm_pdf(conditional, path.velocity[:, None], path.exploration), path.pdf, rtol=1e-12)
    assert any("12.5 is outside the fitted range" in warning for warning in paths[12.5].warnings)


def test_a_generated_path_prints_one_line_not_its_arrays(thesis_model):
    # the dataclass's repr printed its eleven arrays: kilobytes
    T = 5
    angle, time = np.linspace(0.6, 1.9, T), np.linspace(0.0, 0.45, T)
    outputs = np.column_stack([np.linspace(0.5, 7.43, T), np.full(T, 0.8), np.full(T, 1.5)])
    path = GeneratedPath(angle, outputs[:, 0], np.ones(T), np.zeros(T), outputs[:, 0], np.ones(T), time, outputs,
                         outputs, np.ones((T, 3)), np.zeros(T), output_names=("velocity", "shoulder", "shoulder_velocity"),
                         context={"distance": 1.4, "bearing": 30.0}, cautions=("extrapolated",))
    assert repr(path) == ("GeneratedPath(5 points, angle 0.6 to 1.9, 0.45 s, release velocity=7.43, shoulder=0.8, "
                          "shoulder_velocity=1.5, context distance=1.4, bearing=30, cautions=['extrapolated'])")
    generated = thesis_model.generate({"distance": 8.5})
    assert repr(generated).startswith("GeneratedPath(100 points, angle 0 to 10, ") and len(repr(generated)) < 150


def test_generate_refuses_angles_of_two_columns_or_in_degrees():
    model = Model.fit(Dataset([Trajectory(f"t{d}", {"angle": np.linspace(0.6, 1.9, 40), "velocity": np.linspace(1, 9, 40)
                                                    * d, "distance": np.full(40, d)}) for d in (1.0, 1.5, 2.0)]),
                      components=2)
    grid = np.linspace(0.6, 1.9, 20)
    with pytest.raises(InputError, match=r"^angle values to generate at of shape \(20, 2\): give one array of "
                                         r"shape \(T,\)$"):
        model.generate({"distance": 1.5}, np.column_stack([grid, grid]))
    with pytest.raises(InputError, match=r"^angle values to generate at reaches 108.9, beyond two turns in radians: "
                                         r"degrees\?"):
        model.generate({"distance": 1.5}, np.degrees(grid))
    assert model.generate({"distance": 1.5}, grid[:, None]).angle.shape == (20,)  # a column is one array


def test_generated_path_columns_and_time(thesis_model, tmp_path):
    path = thesis_model.generate({"distance": 2.5}, np.linspace(0, 10, 60))
    for name in ("angle", "velocity", "pdf", "exploration", "gmr_mean", "gmr_std", "time"):
        values = getattr(path, name)
        assert values.shape == (60,) and np.all(np.isfinite(values)), name
    assert path.time[0] == 0 and np.all(np.diff(path.time) > 0)
    assert np.all((path.exploration >= 0) & (path.exploration < 1))
    target = tmp_path / "traj.csv"
    path.write_csv(target)
    import pandas as pd

    frame = pd.read_csv(target)
    assert list(frame.columns[:7]) == ["angle", "velocity", "time", "pdf", "exploration", "gmr_mean", "gmr_std"]
    np.testing.assert_array_equal(frame["velocity"].to_numpy(), path.velocity)
    np.testing.assert_array_equal(frame["distance"].to_numpy(), np.full(60, 2.5))


def test_a_path_with_a_non_finite_value_is_not_written(thesis_model, tmp_path):
    # distance=1e300 gave NaN and inf, written with exit 0 (and printed as invalid JSON)
    import dataclasses

    path = thesis_model.generate({"distance": 2.5}, np.linspace(0, 10, 60))
    broken = dataclasses.replace(path, pdf=np.where(np.arange(60) == 3, np.nan, path.pdf))
    target = tmp_path / "traj.csv"
    with pytest.raises(InputError, match=r"the path generated at distance=2.5 \(.*traj.csv not written\): pdf holds nan at row 4"):
        broken.write_csv(target)
    assert not target.exists()


def test_zero_exploration_gives_the_gmr_mean_where_unimodal():
    model = Model.fit(thesis_dataset(), components=1)
    path = model.generate({"distance": 5.0}, exploration=0.0)
    np.testing.assert_allclose(path.velocity, path.gmr_mean, atol=1e-7)
    assert np.all(path.exploration == 0)


def test_time_is_finite_where_the_velocity_is_not_positive():
    # a model whose velocity is negative over most of the path, going forward in angle
    rng = np.random.default_rng(0)
    angle = rng.uniform(0, 1, 300)
    data = np.column_stack([angle, -1.0 + 0.5 * angle + rng.normal(0, 0.01, 300)])
    model = Model.fit(data, inputs=("angle",), outputs=("velocity",), components=1)
    path = model.generate({}, np.linspace(0, 1, 20), exploration=0.0)
    assert np.all(path.velocity < 0)
    assert np.all(np.isfinite(path.time)) and np.all(np.diff(path.time) > 0)
    assert any("<= 0" in note for note in path.notes)
    assert any("no forward velocity" in note for note in path.notes)
    backwards = model.generate({}, np.linspace(1, 0, 20), exploration=0.0)
    assert np.all(np.isfinite(backwards.time)) and not any("<= 0" in note for note in backwards.notes)


def test_predict_is_the_conditional_mean_and_covariance(thesis_model):
    model = thesis_model
    X = np.column_stack([np.linspace(0, 10, 7), np.full(7, 4.5)])
    mean, covariance = model.predict(X)
    conditional = model.condition(X)
    np.testing.assert_array_equal(mean, conditional.mean)
    np.testing.assert_array_equal(covariance, conditional.covariance)
    assert mean.shape == (7, 1) and covariance.shape == (7, 1, 1)


def test_save_and_load_give_the_same_model(thesis_model, tmp_path):
    target = tmp_path / "model.json"
    thesis_model.save(target)
    document = json.loads(target.read_text())
    assert document["format"] == "rlff-model" and document["version"] == 1
    assert document["columns"] == ["angle", "distance", "velocity"]
    assert np.shape(document["covariances"]) == (thesis_model.n_components, 3, 3)
    loaded = Model.load(target)
    np.testing.assert_array_equal(loaded.mixture.means_, thesis_model.mixture.means_)
    np.testing.assert_array_equal(loaded.mixture.covariances_, thesis_model.mixture.covariances_)
    assert loaded.input_range == thesis_model.input_range
    assert loaded.selection.table == thesis_model.selection.table
    a = thesis_model.generate({"distance": 3.0})
    b = loaded.generate({"distance": 3.0})
    np.testing.assert_array_equal(a.velocity, b.velocity)


def corrupt(document: dict, change) -> dict:
    copy = json.loads(json.dumps(document))
    change(copy)
    return copy


@pytest.mark.parametrize(
    "change,field",
    [
        (lambda d: d.update(format="other"), "format"),
        (lambda d: d.update(version=2), "version"),
        (lambda d: d.pop("weights"), "weights"),
        (lambda d: d.update(weights=[0.9] + d["weights"][1:]), "weights"),
        (lambda d: d["means"][0].pop(), "means"),
        (lambda d: d["covariances"][1][0].__setitem__(1, d["covariances"][1][0][1] + 1.0), "covariances[1]"),
        (lambda d: d["covariances"][0].__setitem__(0, [-1.0, 0.0, 0.0]), "covariances[0]"),
        (lambda d: d["means"][0].__setitem__(0, "x"), "means"),
        (lambda d: d.update(inputs=["angle"]), "columns"),
        (lambda d: d.update(outputs=["angle"]), "inputs"),
        (lambda d: d["scale"].update(std=[1.0, 0.0, 1.0]), "scale.std"),
        (lambda d: d.pop("input_range"), "input_range"),
        (lambda d: d["input_range"].update(angle=[5.0, 1.0]), "input_range.angle"),
        (lambda d: d.update(selection={"criterion": "xic", "table": []}), "selection"),
    ],
)
def test_corrupted_model_json_names_the_field(thesis_model, tmp_path, change, field):
    target = tmp_path / "model.json"
    target.write_text(json.dumps(corrupt(thesis_model.to_dict(), change)))
    with pytest.raises(InputError, match=f"field '{field}'".replace("[", r"\[").replace("]", r"\]")):
        Model.load(target)


def test_unreadable_model_files(tmp_path):
    with pytest.raises(InputError, match="no such file"):
        Model.load(tmp_path / "missing.json")
    broken = tmp_path / "broken.json"
    broken.write_text('{"format": "rlff-model", ')
    with pytest.raises(InputError, match="not valid JSON"):
        Model.load(broken)
    broken.write_text("[1, 2]")
    with pytest.raises(InputError, match="JSON object"):
        Model.load(broken)


def test_a_context_every_demonstration_shared_is_said_to_tell_nothing():
    # a manifest's rim height of 0.3 for every throw: asked for 1.0 the model gives the 0.3 throw,
    # and it said only "outside the fitted range [0.3, 0.3]: extrapolating"
    rng = np.random.default_rng(2)
    t, a = rng.uniform(0, 1, 500), rng.uniform(1, 2, 500)
    data = np.column_stack([t, a, np.full(500, 0.3), 2 * t + a + rng.normal(0, 0.05, 500)])
    with pytest.warns(UserWarning, match="column 'h' is constant"):
        model = Model.fit(data, columns=["t", "a", "h", "y"], inputs=("t", "a", "h"), outputs=("y",), components=2)
    path = model.generate({"a": 1.5, "h": 1.0}, np.linspace(0.1, 0.9, 9))
    assert list(path.warnings) == ["h = 1: every demonstration had h 0.3, so the model cannot tell one h from another and "
                             "gives the throw for 0.3"]
    assert not model.generate({"a": 1.5, "h": 0.3}, np.linspace(0.1, 0.9, 9)).warnings


def test_any_columns_several_contexts_and_outputs():
    rng = np.random.default_rng(1)
    n = 2000
    t, a, b = rng.uniform(0, 1, n), rng.uniform(1, 2, n), rng.uniform(-1, 1, n)
    y1 = 2 * t + a + rng.normal(0, 0.05, n)
    y2 = -t + 0.5 * b + rng.normal(0, 0.05, n)
    data = np.column_stack([y2, b, t, y1, a])
    model = Model.fit(
        data, columns=["y2", "b", "t", "y1", "a"], inputs=("t", "a", "b"), outputs=("y1", "y2"), components=2
    )
    assert model.columns == ("t", "a", "b", "y1", "y2")
    path = model.generate({"a": 1.5, "b": 0.2}, np.linspace(0.1, 0.9, 9), exploration=0.0)
    assert path.outputs.shape == (9, 2)
    grid = np.linspace(0.1, 0.9, 9)
    np.testing.assert_allclose(path.outputs[:, 0], 2 * grid + 1.5, atol=0.05)
    np.testing.assert_allclose(path.outputs[:, 1], -grid + 0.1, atol=0.05)
    frame = path.to_frame()
    for name in ("t", "y1", "y2", "velocity", "time", "gmr_mean_y2", "a", "b"):
        assert name in frame.columns
    # the hint is the middle of what was demonstrated (it was "b=2.5" for any context)
    with pytest.raises(InputError, match=r"missing context 'b': give b=\S+ "
                                         r"\(demonstrated: -0\.99\d* to 0\.99\d*\)$"):
        model.generate({"a": 1.5})
    # every missing one named at once (it named one per try)
    with pytest.raises(InputError, match=r"missing context 'a', 'b': give a=\S+ \(demonstrated: .*\) and b="):
        model.generate({})
    with pytest.raises(InputError, match="unknown context 'c'"):
        model.generate({"a": 1.5, "b": 0.0, "c": 1.0})


def test_a_distance_alone_is_the_context_of_a_model_of_one(thesis_model):
    # model.generate(2.0) had been a TypeError ('float' object is not iterable)
    np.testing.assert_array_equal(thesis_model.generate(2.5).velocity, thesis_model.generate({"distance": 2.5}).velocity)
    np.testing.assert_array_equal(thesis_model.generate(np.float64(2.5)).velocity,
                                  thesis_model.generate({"distance": 2.5}).velocity)
    with pytest.raises(InputError, match=r"^the context is a mapping of the model's context columns to their values, "
                                         r"e.g. \{'distance': [\d.]+\}, got list \[2.5, 3.0\] \(or the distance alone"):
        thesis_model.generate([2.5, 3.0])


@pytest.mark.parametrize("distance", [175.0, -2.0, 0.0])
def test_a_basket_distance_outside_what_rlff_takes_is_refused_as_the_cli_refuses_it(thesis_model, distance):
    # 175 (centimetres) was extrapolated into a path of -285 rad/s over 5 ms, a warning at most
    hint = r" \(centimetres\? the distance is in metres\)" if distance > 20 else ""
    with pytest.raises(InputError, match=rf"^context 'distance': {distance:g} m is outside the range 0.3 to 20 m{hint}$"):
        thesis_model.generate({"distance": distance})


def test_sample_weights_move_the_model():
    data = thesis_dataset()
    X = data.to_array(("angle", "distance", "velocity"))
    heavy = np.where(X[:, 1] >= 6, 20.0, 1.0)
    plain = Model.fit(data, components=2)
    weighted = Model.fit(data, components=2, sample_weight=heavy)
    assert weighted.fit_info["weighted"] and not plain.fit_info["weighted"]
    assert weighted.mixture.weights_ @ weighted.mixture.means_[:, 1] > plain.mixture.weights_ @ plain.mixture.means_[:, 1]


@pytest.mark.filterwarnings("ignore:column .* is constant")
def test_bad_fit_input_is_named():
    data = thesis_dataset()
    with pytest.raises(InputError, match="no column 'speed'"):
        Model.fit(data, outputs=("speed",))
    with pytest.raises(InputError, match="more than once"):
        Model.fit(data, inputs=("angle", "velocity"))
    with pytest.raises(InputError, match="components"):
        Model.fit(data, components="many")
    with pytest.raises(InputError, match="empty"):
        Model.fit(Dataset([]))
    with pytest.raises(InputError, match="name them"):
        Model.fit(np.zeros((10, 5)))
    one = Dataset([Trajectory("a", {"angle": [0.0], "distance": [1.0], "velocity": [0.0]})])
    with pytest.raises(InputError, match="at least 2 samples"):
        Model.fit(one)
    with pytest.raises(InputError, match="n_components = 20 is more than"):
        Model.fit(data[:1].replace([data[0].take(slice(0, 10))]), components=20)


@pytest.mark.parametrize("data, message", [
    ("clean.csv", r"data is the path 'clean.csv', not the samples: read it first, "
                  r"Model.fit\(rlff.formats.read_dataset\('clean.csv'\)\)"),
    (list(thesis_dataset()), r"data is a list of Trajectory: make a Dataset of them, Model.fit\(rlff.Dataset"),
    ({"angle": [1.0, 2.0]}, r"data must be a Dataset \(rlff.formats.read_dataset reads one from a file\), a pandas "
                            r"DataFrame or a numeric array of shape \(N, C\), got dict$"),
    ([object(), object()], r"data must be a Dataset .*, got list of object$"),
])
def test_fit_data_of_another_type_is_named_with_what_fit_takes(data, message):
    # until 2026-12-07 all said "data must be a numeric array"
    with pytest.raises(InputError, match=message):
        Model.fit(data)


def test_predict_names_the_shape_it_was_given(thesis_model):
    # a (3,) input was reported as (3, 1), the shape it had been turned into
    with pytest.raises(InputError, match=r"X must have shape \(n, 2\) \(or \(2,\) for one row\), got \(3,\)$"):
        thesis_model.predict([1.0, 2.0, 3.0])
    np.testing.assert_array_equal(thesis_model.predict([1.0, 2.0])[0], thesis_model.predict([[1.0, 2.0]])[0])


@pytest.mark.parametrize("column, factor, message", [
    ("angle", 180 / np.pi, "column 'angle' reaches 160.4, beyond two turns in radians: degrees?"),
    ("distance", 100.0, "column 'distance' holds 100 to 300, outside the basket distances 0.3 to 20 m (centimetres?"),
])
def test_a_fit_in_degrees_or_centimetres_is_refused_whatever_holds_the_samples(column, factor, message):
    # degrees had fitted a model releasing at 408 "rad/s", centimetres one that refused every
    # basket it was asked for in metres: refused as `rlff fit` refuses such a file
    data = baskets_dataset(baskets=np.array([1.0, 2.0, 3.0]))
    converted = data.replace(t.with_columns(**{column: t[column] * factor}) for t in data)
    frame = pd.DataFrame(converted.to_array(["velocity", "distance", "angle"]), columns=["velocity", "distance", "angle"])
    for given in (converted, frame, converted.to_array(["angle", "distance", "velocity"])):
        with pytest.raises(InputError, match=r"^" + re.escape(message)):
            Model.fit(given, components=2)



@pytest.mark.parametrize("timed, message", [
    (False, "column 'velocity' peaks at 647.2 in the median throw, faster than a person's joint turns"),
    (True, "column 'velocity' integrates over the throws' time column to a median 57.3 times their angle's change"),
])
def test_a_fit_in_degrees_per_second_is_refused_from_python_as_rlff_fit_refuses_it(timed, message):
    # Model.fit from Python checked distances and angles, not the velocity, which only the CLI's
    # reader checked: a frame of clean.csv in deg/s fitted without a word (until 2026-12-07)
    from rlff.timing import time_along_path

    data = baskets_dataset(baskets=np.array([1.0, 2.0, 3.0]))
    if timed:
        data = data.replace(t.with_columns(time=time_along_path(t["angle"], np.abs(t["velocity"]))) for t in data)
    converted = data.replace(t.with_columns(velocity=t["velocity"] * 180 / np.pi) for t in data)
    columns = ["angle", "distance", "velocity", *(["time"] if timed else [])]
    frame = pd.DataFrame(converted.to_array(columns), columns=columns)
    frame.insert(0, "trajectory", np.repeat([t.id for t in converted], [len(t) for t in converted]))
    for given in (converted, frame):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the frame's trajectory column is not read into the fit
            with pytest.raises(InputError, match=r"^" + re.escape(message)):
                Model.fit(given, components=2)
    Model.fit(data, components=1, n_init=1)  # in rad/s it fits

def test_a_fit_takes_distances_nearer_than_any_basket_a_throw_landed_at():
    # a learning method labels each throw with where it came down: 0.2 m is a throw that fell
    # near the base, no unit slip; 0 m and below is no landing in front of the arm
    data = baskets_dataset(baskets=np.array([1.0, 2.0, 3.0]))
    landed = data.replace(t.with_columns(distance=t["distance"] - 0.8) for t in data)
    assert Model.fit(landed, components=2).input_range["distance"] == pytest.approx((0.2, 2.2))
    behind = data.replace(t.with_columns(distance=t["distance"] - 1.0) for t in data)
    with pytest.raises(InputError, match=r"^column 'distance' holds 0 to 2, outside the basket distances"):
        Model.fit(behind, components=2)


def baskets_dataset(seed: int = 0, baskets: np.ndarray = np.arange(1.0, 3.01, 0.25)) -> Dataset:
    """Noisy throws at baskets 0.25 m apart, a dozen each: the context takes few values."""
    rng = np.random.default_rng(seed)
    trajectories = []
    for b, distance in enumerate(baskets):
        for t in range(12):
            angle = np.linspace(0.7, 2.8, 40)
            velocity = (1.0 + 0.4 * distance) * np.sin(angle) * 6 + rng.normal(0, 0.4, angle.size)
            columns = {"angle": angle, "distance": np.full(angle.size, distance), "velocity": velocity}
            trajectories.append(Trajectory(f"b{b}t{t}", columns))
    return Dataset(trajectories)


def test_context_resolution_keeps_every_component_off_a_single_basket():
    data = baskets_dataset(baskets=np.array([1.0, 1.25, 1.5]))  # 3 baskets, 6 components
    auto = Model.fit(data, components=6)
    assert auto.fit_info["context_resolution"] == {"distance": pytest.approx(0.25)}
    # every component is at least as wide in the distance as a basket's +-0.125 m
    assert np.all(auto.mixture.covariances_[:, 1, 1] >= 0.25**2 / 12)
    given = Model.fit(data, components=6, context_resolution=0.5)
    assert np.all(given.mixture.covariances_[:, 1, 1] >= 0.5**2 / 12)
    # without it, EM puts components on one basket each: no variance there, ln L without bound
    plain = Model.fit(data, components=6, context_resolution=None)
    assert plain.fit_info["context_resolution"] == {"distance": 0.0}
    assert np.min(plain.mixture.covariances_[:, 1, 1]) < 1e-3 * 0.25**2 / 12
    assert plain.fit_info["log_likelihood"] > auto.fit_info["log_likelihood"] + 100


def test_context_resolution_auto_follows_the_spacing_of_the_recorded_values():
    data = baskets_dataset()
    # one trajectory off the 0.25 m grid does not make the resolution fine (median gap)
    off_grid = data.replace([*data, data[0].replace(id="extra").with_columns(distance=np.full(len(data[0]), 1.8))])
    assert Model.fit(off_grid, components=2).fit_info["context_resolution"] == {"distance": pytest.approx(0.25)}
    # an array whose context changes from sample to sample is continuous: nothing added
    X = data.to_array(["angle", "distance", "velocity"])
    X[:, 1] += np.random.default_rng(1).uniform(-0.1, 0.1, len(X))
    assert Model.fit(X, components=2).fit_info["context_resolution"] == {"distance": 0.0}
    with pytest.raises(InputError, match="context_resolution"):
        Model.fit(data, components=2, context_resolution="fine")
    with pytest.raises(InputError, match="context_resolution"):
        Model.fit(data, components=2, context_resolution=-1.0)


def test_bic_counts_the_measured_samples_of_densified_throws():
    from rlff.preprocess import densify

    raw = baskets_dataset(baskets=np.array([1.0, 1.5, 2.0]))
    sparse = raw.replace(t.take(slice(None, None, 8)) for t in raw)  # 5 measured samples a throw
    dense, _ = densify(sparse, step=0.01)
    model = Model.fit(dense, max_components=4)  # the default counts what was measured
    shares = np.array([t.meta["measured_share"] for t in dense])
    expected = sum(len(t) * share for t, share in zip(dense, shares, strict=True))
    assert model.fit_info["effective_samples"] == pytest.approx(expected)
    assert expected == pytest.approx(sum(len(t) for t in sparse))  # the measured samples
    n, p = model.fit_info["n_samples"], model.mixture.n_parameters()
    scaled = model.fit_info["log_likelihood"] * expected / n
    assert model.fit_info["bic"] == pytest.approx(-2 * scaled + p * np.log(expected), rel=1e-12)
    plain = Model.fit(dense, max_components=4, effective_samples=None)  # the old count: every sample
    assert plain.fit_info["effective_samples"] is None
    p_plain = plain.mixture.n_parameters()
    assert plain.fit_info["bic"] == pytest.approx(-2 * plain.fit_info["log_likelihood"] + p_plain * np.log(n), rel=1e-12)
    # without densified trajectories nothing changes
    assert Model.fit(raw, components=2).fit_info["effective_samples"] is None
    with pytest.raises(InputError, match="effective_samples"):
        Model.fit(dense, components=2, effective_samples="some")


def test_a_chosen_k_says_when_it_is_the_largest_tried_or_the_data_hardly_decide_it():
    data = thesis_dataset()
    assert Model.fit(data, components=2).selection_notes() == []  # K given: nothing to say
    capped = Model.fit(data, max_components=2)
    assert capped.n_components == 2
    assert capped.selection_notes() == [
        "BIC chose K = 2, the largest tried: a larger K may fit better (raise max_components, "
        "rlff fit --max-components)"]
    few = Model.fit(data, max_components=3, effective_samples=5.0)
    notes = few.selection_notes()
    assert len(notes) == 1 and notes[0].startswith(
        f"BIC rests on 5 effective samples, fewer than the {few.mixture.n_parameters()} parameters")
    wide = Model.fit(data, max_components=10)
    assert wide.n_components < 10 and wide.selection_notes() == []


def test_a_larger_k_fitted_worse_than_a_smaller_one_is_said():
    # the thesis set: EM's three starts at K = 8 end below K = 7's ln L, which a mixture of 8
    # can always match; BIC's K = 7 then rests on K = 8's poorer fit as much as on its size
    model = Model.fit(thesis_dataset())
    table = {row["n_components"]: row["log_likelihood"] for row in model.selection.table}
    assert model.n_components == 7 and table[8] < table[7] - 0.25
    fall, = [note for note in model.selection_notes() if note.startswith("ln L falls")]
    assert fall.startswith(f"ln L falls from K = 7 to K = 8 ({table[7]:.2f} to {table[8]:.2f})")
    assert "EM's 3 starts found a poorer optimum there" in fall and "rlff fit --n-init" in fall
    # a fall below the chosen K cannot have changed the choice: nothing said
    assert not [note for note in Model.fit(thesis_dataset(), max_components=10).selection_notes()
                if note.startswith("ln L falls")]


def test_a_fall_in_ln_l_between_two_ks_that_lost_anyway_is_not_said():
    # MSR data: BIC chose K = 1 and ln L fell from K = 20 to 21, and the note said "K = 21 may
    # have lost to K = 1 for its fit": K = 20, fitted well, had lost to K = 1 by far
    from rlff.model.model import ComponentSelection, _fall_may_have_decided

    def row(k, bic, log_likelihood):
        return {"n_components": k, "bic": bic, "aic": bic, "log_likelihood": log_likelihood}

    table = [row(1, 100.0, -40.0), row(20, 400.0, -10.0), row(21, 430.0, -12.0)]
    assert not _fall_may_have_decided(ComponentSelection("bic", table), 1, table[2], table[1], 1.0)  # 426 > 100
    # below the chosen K's own ln L (the thesis set's K = 8 under K = 7): said
    close = [row(7, 100.0, -40.0), row(8, 120.0, -43.0)]
    assert _fall_may_have_decided(ComponentSelection("bic", close), 7, close[1], close[0], 1.0)
    # between two larger Ks, where the larger, fitted as well, would have won: said
    table = [row(2, 100.0, -40.0), row(3, 101.0, -30.0), row(4, 108.0, -36.0)]  # 108 - 12 = 96 < 100
    assert _fall_may_have_decided(ComponentSelection("bic", table), 2, table[2], table[1], 1.0)


def test_k_by_bic_stays_within_one_component_per_d_plus_1_samples():
    # until 2026-12-07 two samples got K = 2 (BIC -70.7), three K = 3 and a predicted variance of
    # 7e-7: one component per sample, each with a covariance held up by the regularisation alone
    from rlff.model.model import component_bound

    for rows in ([[0.1, 1.0, 2.0], [0.2, 1.0, 3.0]], [[0.1, 1.0, 2.0], [0.2, 1.0, 3.0], [0.3, 2.0, 2.5]]):
        with pytest.warns(UserWarning, match=rf"{len(rows)} samples over 3 columns, fewer than the 4 a covariance "
                                             "needs: the model's variances come from the regularisation alone"):
            model = Model.fit(rows)
        assert model.n_components == 1 and [row["n_components"] for row in model.selection.table] == [1]
    rng = np.random.default_rng(0)
    eleven = np.column_stack([rng.uniform(0.5, 2.5, 11), rng.choice([1.0, 2.0], 11), rng.normal(5.0, 1.0, 11)])
    assert [row["n_components"] for row in Model.fit(eleven).selection.table] == [1, 2]  # 11 // 4
    assert component_bound(11, None, 3) == 2 and component_bound(2215, 65.0, 3) == 16
    assert component_bound(3, None, 3) == 1 and component_bound(550, None, 3) == 137  # the thesis set: K = 7 stays


def test_on_tiny_data_the_notes_say_the_samples_are_too_few_not_to_raise_max_components():
    """Four samples: K stops at 1 (one component per D + 1 = 4 samples) whatever max_components
    says, and the samples, every one counted, are far fewer than the parameters."""
    tiny = Dataset([Trajectory(name, {"angle": np.array([1.0, 2.0]), "distance": np.full(2, distance),
                                      "velocity": np.array(velocity)})
                    for name, distance, velocity in (("a", 2.0, [3.0, 3.0]), ("b", 2.5, [4.0, 5.0]))])
    model = Model.fit(tiny, max_components=8)
    assert model.n_components == 1
    assert model.fit_info["effective_samples"] is None
    notes = model.selection_notes()
    assert not any("the largest tried" in note for note in notes)
    assert len(notes) == 1 and notes[0].startswith(
        f"BIC rests on 4 samples, fewer than the {model.mixture.n_parameters()} parameters of K = {model.n_components}")


def test_constant_column_warns_and_fits():
    data = Dataset([t.with_columns(distance=np.full(len(t), 2.5)) for t in thesis_dataset()[:1]])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        model = Model.fit(data, components=2)
    assert any("column 'distance' is constant" in str(w.message) for w in caught)
    path = model.generate({"distance": 2.5})
    assert np.all(np.isfinite(path.velocity))


def test_one_output_paths_are_those_before_the_multi_output_climb():
    """The reference holds, as hexadecimal floats, the paths the code before the compiled
    several-output climb (commit 649ba55) generated from the model stored beside it: the one-output
    case must not move. Bit for bit only on a machine like the one that wrote it: the compiled
    kernels and libm round differently on other CPUs (on an AMD EPYC: densities and exploration
    1e-14 apart, the continuity's climbs, which stop at a tolerance, up to 2e-9), so the check is
    to rounding, far below any change of the method (a mode moved by a climb's step is 1e-4 off)."""
    from pathlib import Path

    data = Path(__file__).parent / "data"
    model = Model.load(data / "thesis_model_k_bic.json")
    reference = json.loads((data / "thesis_paths_before_multi_output.json").read_text())
    tolerance = {"velocity": 1e-8, "pdf": 1e-12, "exploration": 1e-12}
    for distance in (3.0, 8.5, 12.5):
        for continuity in (False, True):
            path = model.generate({"distance": distance}, np.linspace(0, 10, 40), continuity=continuity)
            expected = reference[f"distance={distance:g} continuity={continuity}"]
            for name, rtol in tolerance.items():
                np.testing.assert_allclose(getattr(path, name), [float.fromhex(v) for v in expected[name]],
                                           rtol=rtol, atol=0, err_msg=f"{distance} {continuity} {name}")


def _throws(peaks: list[tuple[float, float]]) -> Dataset:
    """Three throws per (distance m, peak velocity rad/s): one velocity profile scaled."""
    angle = np.linspace(0.5, 2.4, 40)
    profile = np.sin(0.5 * np.pi * (angle - 0.5) / 1.9 + 0.2)
    return Dataset([Trajectory(f"t{i}_{k}", {"angle": angle, "velocity": (peak + 0.1 * k) * profile,
                                              "distance": np.full(angle.size, distance)})
                    for i, (distance, peak) in enumerate(peaks) for k in range(3)], context=("distance",))


@pytest.mark.parametrize("peaks, turned_back", [
    ([(1.0, 5.0), (1.5, 7.0), (2.0, 6.0)], True),  # the farthest throws were slower: the slope turns
    ([(1.0, 5.0), (1.5, 6.0), (2.0, 7.0)], False),
])
def test_a_distance_past_the_data_whose_throw_turns_back_says_so(peaks, turned_back):
    model = Model.fit(_throws(peaks), inputs=("angle", "distance"), outputs=("velocity",), components=3, seed=0)
    warnings = model.generate({"distance": 2.6}).warnings  # -q kept them no more than a note
    assert "distance = 2.6 is outside the fitted range [1, 2]: extrapolating" in warnings
    reversal = [warning for warning in warnings if "turns back" in warning]
    if turned_back:
        # it said "the velocity generated ... peaks at" the GMR mean's peak, not the generated one's
        assert reversal == [next(w for w in warnings if w.startswith("the regression's (GMR mean) velocity for "
                                                                     "distance 2.6 peaks at"))]
        assert "below the" in reversal[0] and "for 2 (the fitted range's top)" in reversal[0]
        assert "would land shorter than the one for 2; ask within [1, 2]" in reversal[0]
    else:
        assert not reversal
    assert not model.generate({"distance": 1.7}).warnings  # within the range


def test_a_path_past_the_data_and_an_impossible_joint_angle_are_warned(tmp_path):
    # a grid of -5..10 rad and a wrist of 3.43 rad (straight is pi) came out without a word
    angle = np.linspace(0.6, 2.8, 30)
    trajectories = [Trajectory(f"t{d}_{k}", {"angle": angle, "velocity": (4 + d + 0.1 * k) * np.sin(angle),
                                             "wrist": np.full(angle.size, 2.2 + 0.4 * d + 0.01 * k),
                                             "wrist_velocity": np.zeros(angle.size),
                                             "distance": np.full(angle.size, float(d))})
                    for d in (1, 2) for k in range(3)]
    model = Model.fit(Dataset(trajectories, context=("distance",)), inputs=("angle", "distance"),
                      outputs=("velocity", "wrist"), components=1, seed=0)
    inside = model.generate({"distance": 1.5})
    assert not inside.warnings
    far = model.generate({"distance": 5.0}, np.linspace(-1.0, 4.0, 20))
    assert "angle values -1 to 4 leave the fitted range [0.6, 2.8]: extrapolating" in far.warnings
    (wrist,) = [w for w in far.warnings if w.startswith("wrist goes")]
    assert far.outputs[:, 1].max() > np.pi + 0.05 and "outside 0 to pi" in wrist
    # the elbow's own grid beyond pi or below 0 had only "extrapolating" (until 2026-12-07)
    (elbow,) = [w for w in far.warnings if w.startswith("angle goes")]
    assert elbow.startswith("angle goes -1 to 4 rad, outside 0 to pi (the angle between two limbs): no arm takes")


def test_a_step_between_modes_is_said_where_it_is(thesis_model):
    # a 2.7 rad/s step between neighbouring points came out without a word (density_traded 7e-8)
    from rlff.learn.benchmark import demonstrations
    from rlff.learn.scenarios import Scenario

    people = Model.fit(demonstrations(0, Scenario("wide", landings="exact")), inputs=("angle", "distance"),
                       outputs=("velocity",), components="auto", seed=0)
    said = 0
    for model, distance in [(thesis_model, 2.0), (thesis_model, 7.0), (people, 1.5), (people, 2.5)]:
        path = model.generate({"distance": distance}, continuity=True)
        steps = np.abs(np.diff(path.velocity))
        notes = [note for note in path.notes if note.startswith("velocity steps by")]
        if steps.max() > 0.1 * np.ptp(path.velocity):
            i = int(np.argmax(steps))
            assert len(notes) == 1 and f"between angle {path.angle[i]:.4g} and {path.angle[i + 1]:.4g}" in notes[0]
            said += 1
        else:
            assert not notes
    assert said == 2  # the simulated people's DMM changes mode along the path, the thesis set's does not


def test_a_grid_is_held_to_what_its_climbs_would_hold(thesis_model):
    # a 1,000,000-point path of a K = 8, 5-output model grew past 3.3 GB over hours
    from rlff.limits import MAX_GENERATE_BYTES
    from rlff.model.climb import starts_per_input

    per_point = 8 * starts_per_input(thesis_model.n_components, 1) * 3
    assert MAX_GENERATE_BYTES // per_point > 2_000_000  # one output: the grid's own limit binds
    angle = np.linspace(0.5, 2.5, 30)
    arm = Model.fit(Dataset([Trajectory(f"t{d}_{k}", {"angle": angle, "velocity": (d + 0.1 * k) * np.sin(angle),
                                                      "wrist": np.full(30, 2.0 + 0.1 * d + 0.01 * k),
                                                      "wrist_velocity": np.full(30, 0.1 * k),
                                                      "shoulder": np.full(30, 1.0 + 0.1 * d - 0.01 * k),
                                                      "shoulder_velocity": np.full(30, 0.2 * k),
                                                      "distance": np.full(30, float(d))})
                             for d in (1, 2) for k in range(4)], context=("distance",)),
                    inputs=("angle", "distance"), components=2, seed=0,
                    outputs=("velocity", "shoulder", "shoulder_velocity", "wrist", "wrist_velocity"))
    most = MAX_GENERATE_BYTES // (8 * starts_per_input(2, 5) * 7)
    with pytest.raises(InputError, match=rf"with this model \(2 components, 5 outputs: about .* kB a point\): "
                                         rf"{most + 1:,} is more than the {most:,} allowed"):
        arm.generate({"distance": 1.5}, np.linspace(0.5, 2.5, most + 1))


def test_a_given_k_with_more_parameters_than_samples_is_said_too():
    # K = 4 over (angle, distance, velocity): 4 x (3 + 6) + 3 = 39 parameters against 20 samples
    model = Model.fit(thesis_dataset(), components=4, effective_samples=20.0)
    assert model.mixture.n_parameters() == 39
    assert model.selection_notes() == [
        "the given K = 4 has 39 parameters, more than the 20 effective samples BIC counts: its components "
        "fit the noise of a few samples (fewer components, or leave K to BIC: components=\"auto\", rlff fit -k auto)"]
