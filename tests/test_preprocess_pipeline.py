"""The pipeline: configuration from lists, TOML files and presets, reports, and its invariants."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rlff.dataset import Dataset, Trajectory
from rlff.errors import InputError
from rlff.preprocess import STEPS, Pipeline, preset_names


def _dataset() -> Dataset:
    angle = np.array([1.5, 1.0, 0.7, 1.2, 0.05, 2.0, 2.6, 3.0, 2.9])
    time = np.arange(angle.size) / 30.0
    # the farther basket's throw a little faster; its velocity still about the angle's rate of
    # change over time (at 1 + d, 2-4 times it, it is refused as in other units)
    return Dataset([
        Trajectory(f"t{d:g}-{k}", {"time": time, "angle": angle, "distance": np.full(angle.size, d),
                                  "velocity": np.gradient(angle, time) * (1 + d / 10)})
        for d in (1.0, 2.0, 3.0) for k in range(2)
    ])


def test_pipeline_from_a_list_runs_steps_in_order_and_keeps_before_after():
    pipeline = Pipeline([("spike_filter", {"threshold": 20.0}), ("crop", {}), ("min_points", {"min_points": 4})])
    data = _dataset()
    out, report = pipeline.run(data)
    assert [s.step for s in report.steps] == ["spike_filter", "crop", "min_points"]
    assert report.steps[0].before is data
    assert report.steps[1].before is report.steps[0].after
    assert report.after is out
    np.testing.assert_array_equal(out["t1-0"]["angle"], [0.7, 1.2, 2.0, 2.6, 3.0])
    payload = report.to_dict()
    json.dumps(payload)
    assert payload["steps"][0]["sample_changes"][0] == {
        "trajectory": "t1-0", "removed": 1, "added": 0,
        "reason": "glitch sample 4: angle jumps out and back faster than 20/s",
    }
    assert payload["trajectories"] == {"before": 6, "after": 6}


def test_progress_is_called_once_per_enabled_step():
    calls = []
    pipeline = Pipeline.preset("thesis")
    pipeline.run(_dataset(), progress=lambda n, description=None: calls.append(description))
    assert calls == [s.name for s in pipeline.steps if s.enabled]


def test_toml_config_with_a_disabled_step(tmp_path):
    path = tmp_path / "steps.toml"
    path.write_text(
        '[[step]]\nname = "crop"\n\n'
        '[[step]]\nname = "stop_point"\nenabled = false\n\n'
        '[[step]]\nname = "densify"\nstep = 0.1\nanchors = [0.5]\n'
    )
    pipeline = Pipeline.from_toml(path)
    assert [(s.name, s.enabled) for s in pipeline.steps] == [("crop", True), ("stop_point", False), ("densify", True)]
    out, report = pipeline.run(_dataset())
    assert [s.step for s in report.steps] == ["crop", "densify"]
    assert report.steps[1].params["anchors"] == [0.5]
    assert report.source == str(path)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ('[[step]]\nname = "smooth"\n', r"steps.toml, step 1: unknown step 'smooth' \(known: spike_filter, crop"),
        ('[[step]]\nname = "crop"\n[[step]]\nname = "densify"\nstepsize = 0.1\n',
         r"steps.toml, step 2: step 'densify': unknown parameter 'stepsize' \(known: column, step, anchors, spline, independent_rate\)"),
        ('[[step]]\nname = "densify"\nstep = "fine"\n', r"step 'densify': parameter 'step' = 'fine' should be a finite float"),
        ('[[step]]\nname = "cut_release"\nmode = "guess"\n', r"parameter 'mode' = 'guess' should be 'estimated' or 'angle'"),
        ('[[step]]\nname = "min_points"\nmin_points = true\n', r"parameter 'min_points' = True should be int"),
        ('[[step]]\nname = "crop"\nenabled = "no"\n', r"step 1 'crop': 'enabled' must be true or false"),
        ('[[step]]\ncolumn = "angle"\n', r"step 1: no 'name'"),
        ('steps = 3\n', r"unknown key 'steps'"),
        ('[[step]\nname = "crop"\n', r"malformed TOML"),
    ],
)
def test_bad_toml_names_the_file_and_the_step(tmp_path, text, message):
    path = tmp_path / "steps.toml"
    path.write_text(text)
    with pytest.raises(InputError, match=message) as error:
        Pipeline.from_toml(path)
    assert str(path) in str(error.value)


def test_an_error_inside_a_step_names_the_step():
    data = Dataset([Trajectory("a", {"angle": [2.0, 2.5], "distance": [1.0, 1.0], "velocity": [0.0, 0.0]})])
    with pytest.raises(InputError, match=r"^steps.toml, step 'densify': densify step -0.1: must be"):
        Pipeline([("densify", {"step": -0.1})], source="steps.toml").run(data)


def test_a_missing_column_is_named_with_the_step():
    data = Dataset([Trajectory("a", {"angle": [0.7, 1.5, 2.5, 3.0, 2.9], "distance": [2.0] * 5})])
    with pytest.raises(InputError, match=r"step 'cut_release': no column 'velocity' in the data"):
        Pipeline.preset("thesis").run(data)


def test_a_context_column_a_step_judges_by_is_required_before_any_step():
    # the thesis preset ran its eight first steps on data without a distance and then said
    # "step 'reject_contexts': reject_contexts: 'distance' is not a context column"
    data = Dataset([Trajectory(t.id, {name: t[name] for name in t.columns if name != "distance"}, t.meta)
                    for t in _dataset()])
    steps = []
    with pytest.raises(InputError, match=re.escape(
            "preset 'thesis', step 'reject_contexts' judges the throws by their 'distance' (the basket distance each "
            "throw aimed at, m), a context column the data lacks (columns: time, angle, velocity; context: none)")):
        Pipeline.preset("thesis").run(data, progress=lambda *_, **named: steps.append(named))
    assert steps == []
    off = Pipeline([("crop", {}), ("reject_contexts", {})], source="mine.toml")
    with pytest.raises(InputError, match=r"^mine.toml, step 'reject_contexts' judges the throws by their 'distance'"):
        off.check(data)
    Pipeline([("crop", {})]).check(data)  # a pipeline that judges no context takes such data


def _converted(data: Dataset, **factors: float) -> Dataset:
    """``data`` with the columns named in ``factors`` multiplied by them (another unit)."""
    return Dataset([Trajectory(t.id, {name: t[name] * factors.get(name, 1.0) for name in t.columns}, t.meta)
                    for t in data], context=data.context)


@pytest.mark.parametrize("factors, message", [
    ({"angle": 180 / np.pi, "velocity": 180 / np.pi},
     "column 'angle' reaches 171.9, beyond two turns in radians: degrees? joint angles are in rad"),
    ({"distance": 100.0},
     "column 'distance' holds 100 to 300, outside the basket distances 0.3 to 20 m (centimetres? the distance is "
     "in metres)"),
    ({"velocity": 180 / np.pi},
     "column 'velocity' integrates over the throws' time column to a median 43.1 times their angle's change"),
])
def test_a_dataset_in_degrees_or_centimetres_is_refused_before_any_step(factors, message):
    # degrees went through the thesis preset into 57 times the samples, centimetres into a model
    # that refused every basket: refused as the command line refuses such a file
    with pytest.raises(InputError, match=r"^" + re.escape(message)):
        Pipeline.preset("thesis").run(_converted(_dataset(), **factors))


def test_a_step_that_drops_data_silently_is_caught(monkeypatch):
    from rlff.preprocess import StepReport, pipeline

    def careless(dataset, *, column: str = "angle"):
        return dataset.replace(list(dataset)[1:]), StepReport("crop", {}, dataset)

    monkeypatch.setitem(pipeline.STEPS, "crop", careless)
    with pytest.raises(RuntimeError, match=r"step 'crop' changed data without reporting it \(trajectories \['t1-0'\]"):
        Pipeline([("crop", {})]).run(_dataset())


def test_a_step_that_leaves_a_single_sample_is_caught(monkeypatch):
    from rlff.preprocess import StepReport, pipeline

    def careless(dataset, *, column: str = "angle"):
        report = StepReport("crop", {}, dataset)
        for trajectory in dataset:
            report.change_samples(trajectory.id, len(trajectory) - 1, 0, "kept the first sample")
        return dataset.replace(t.take(slice(0, 1)) for t in dataset), report

    monkeypatch.setitem(pipeline.STEPS, "crop", careless)
    with pytest.raises(RuntimeError, match=r"step 'crop' left trajectories \['t1-0', .* with fewer than 2 samples"):
        Pipeline([("crop", {})]).run(_dataset())


def test_a_throw_the_stretch_would_reverse_is_dropped_not_cut_to_one_sample():
    """A throw that starts beyond the mean final angle: stretched backwards, with its velocity
    forward, cut_release cut it to its first sample and `rlff fit` refused the file."""
    angle = np.array([0.7, 1.2, 2.0, 2.6, 2.9])
    late = np.array([3.10, 3.11, 3.12, 3.13])
    data = Dataset([Trajectory(name, {"angle": a, "distance": np.full(a.size, 2.0),
                                      "velocity": np.linspace(2.0, 6.0, a.size) * (1 - np.linspace(0, 0.5, a.size))})
                    for name, a in (("a", angle), ("b", angle + 0.05), ("late", late))])
    steps = [s for s in Pipeline.preset("thesis").steps if s.name in ("rescale", "densify", "cut_release")]
    cleaned, report = Pipeline(steps).run(data)
    assert cleaned.ids == ("a", "b")
    (removal,) = report.steps[0].removed
    assert removal.trajectory == "late" and "would reverse the motion" in removal.reason


def test_bad_list_and_preset_names():
    with pytest.raises(InputError, match="step 1: unknown step 'nope'"):
        Pipeline([("nope", {})])
    with pytest.raises(InputError, match=r"unknown preset 'paper' \(available: thesis\)"):
        Pipeline.preset("paper")
    assert "thesis" in preset_names()


@pytest.mark.parametrize("steps, message", [
    (["crop"], r"step 1: 'crop' is not a step: give a \(name, parameters\) pair such as \('crop', "),
    ([("crop",)], r"step 1: \('crop',\) is not a step"),
    ([("crop", None)], r"step 1: \('crop', None\) is not a step: .*\(no parameters: \{\}\)"),
    ([("crop", {}), 5], r"step 2: 5 is not a step"),
    ("crop", r"Pipeline takes a list of steps, e.g. \[\('crop', .*got str 'crop'"),
    (5, r"Pipeline takes a list of steps, .*got int 5"),
])
def test_a_step_list_of_the_wrong_form_is_refused_naming_the_position_and_the_form(steps, message):
    # until 2026-12-07: ValueError / TypeError / AttributeError from unpacking the steps
    with pytest.raises(InputError, match=message):
        Pipeline(steps)
    assert Pipeline([["crop", {}]]).steps[0].name == "crop"  # a list pair is a pair too


def test_thesis_preset_has_every_step_in_the_thesis_order():
    pipeline = Pipeline.preset("thesis")
    names = [s.name for s in pipeline.steps]
    assert set(names) == set(STEPS)
    assert names[:5] == ["spike_filter", "crop", "longest_monotonic", "min_points", "balance"]
    assert not next(s for s in pipeline.steps if s.name == "stop_point").enabled
    assert dict(next(s for s in pipeline.steps if s.name == "cut_release").params)["mode"] == "estimated"


# -- invariants (hypothesis) -------------------------------------------------------------------


@st.composite
def recordings(draw) -> Dataset:
    """Throw-like recordings: a wind-up and an extension with noise and occasional glitches."""
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    distances = draw(st.lists(st.sampled_from([1.0, 1.5, 2.0, 2.5, 3.0, 3.5]), min_size=1, max_size=5, unique=True))
    trajectories = []
    for d in distances:
        for k in range(draw(st.integers(1, 4))):
            n = int(rng.integers(3, 40))
            time = np.cumsum(rng.uniform(0.02, 0.07, n))
            phase = np.linspace(-1.0, 1.0, n)
            angle = 0.7 + 2.2 * np.clip(phase, 0, 1) ** 2 * (1 + 0.1 * d) + 0.5 * np.clip(-phase, 0, 1)
            angle = angle + rng.normal(0, draw(st.sampled_from([0.0, 0.01, 0.05])), n)
            if n > 6 and rng.random() < 0.3:
                angle[int(rng.integers(2, n - 2))] = 0.05
            trajectories.append(Trajectory(f"d{d:g}-{k}", {
                "time": time, "angle": angle, "distance": np.full(n, d),
                "velocity": np.gradient(angle, time)}))
    return Dataset(trajectories)


def _is_subsequence(part: np.ndarray, whole: np.ndarray) -> bool:
    position = 0
    for value in part:
        hits = np.flatnonzero(whole[position:] == value)
        if not hits.size:
            return False
        position += int(hits[0]) + 1
    return True


_SETTINGS = settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@_SETTINGS
@given(data=recordings())
def test_thesis_preset_never_invents_contexts_or_trajectories_and_accounts_for_all(data):
    out, report = Pipeline.preset("thesis").run(data)
    assert set(out.contexts) <= set(data.contexts)
    assert set(out.ids) <= set(data.ids)
    removed = {r.trajectory for step in report.steps for r in step.removed}
    assert set(data.ids) == set(out.ids) | removed
    assert out.columns == data.columns and out.context == data.context
    for trajectory in out:
        source = data[trajectory.id]
        # units kept: the same distance, angles within the recorded range (stretched at most to
        # the mean final angle), time within the recording, and time still increasing
        assert trajectory["distance"][0] == source["distance"][0]
        assert source["angle"].min() - 1e-9 <= trajectory["angle"].min()
        assert trajectory["angle"].max() <= max(t["angle"].max() for t in data) + 1e-9
        assert source["time"][0] - 1e-9 <= trajectory["time"][0]
        assert trajectory["time"][-1] <= source["time"][-1] + 1e-9
        assert np.all(np.diff(trajectory["time"]) > 0)
        assert np.all(np.diff(trajectory["angle"]) > 0)  # resampled in the direction of motion


_SELECTING = ["spike_filter", "crop", "longest_monotonic", "min_points", "balance", "cut_release",
              "reject_shapes", "reject_contexts"]


@_SETTINGS
@given(data=recordings(), steps=st.lists(st.sampled_from(_SELECTING), min_size=1, max_size=6))
def test_selecting_steps_keep_samples_in_their_order_and_values(data, steps):
    params = {"reject_contexts": {"trend": "increasing"}, "spike_filter": {"recompute_velocity": False}}
    out, _ = Pipeline([(name, params.get(name, {})) for name in steps]).run(data)
    assert set(out.contexts) <= set(data.contexts)
    for trajectory in out:
        source = data[trajectory.id]
        assert _is_subsequence(trajectory["time"], source["time"])
        for name in data.columns:
            kept = np.searchsorted(source["time"], trajectory["time"])
            np.testing.assert_array_equal(trajectory[name], source[name][kept])


_THROWS = Dataset([
    Trajectory(f"t{i}", {"angle": np.linspace(0.8, 2.9 + 0.01 * i, 8), "distance": [1.0 + i % 3] * 8,
                         "velocity": np.sin(np.linspace(0.2, 3.0, 8)) * (5.0 + i)})
    for i in range(9)
])


@pytest.mark.parametrize(
    ("step", "params", "message"),
    [
        ("spike_filter", {"k": -3}, r"k -3: must be positive"),
        ("spike_filter", {"k": 0}, r"k 0: must be positive"),
        ("spike_filter", {"threshold": -1.0}, r"threshold -1.0: must be \"auto\" or a speed of 0 or more"),
        ("spike_filter", {"max_width": 0}, r"max_width 0: must be at least 1"),
        ("balance", {"seed": -1}, r"seed -1: must be 0 or more"),
        ("stop_point", {"extension": -0.5}, r"extension -0.5: must be positive"),
        ("stop_point", {"extension": 0.0}, r"extension 0.0: must be positive"),
        ("reject_shapes", {"k": -1.0}, r"k -1.0: must be positive"),
        ("reject_shapes", {"k": 0.0}, r"k 0.0: must be positive"),
        ("reject_shapes", {"min_trajectories": 0}, r"min_trajectories 0: must be at least 1"),
        ("reject_shapes", {"points": 1}, r"points 1: must be at least 2"),
        ("reject_contexts", {"tolerance": -0.1}, r"tolerance -0.1: must be 0 or more"),
        ("reject_contexts", {"z": -2.0}, r"z -2.0: must be 0 or more"),
        ("reject_contexts", {"max_spread_ratio": 0.5}, r"max_spread_ratio 0.5: must be 0 \(off\) or at least 1"),
        ("reject_contexts", {"max_spread_ratio": -1.0}, r"max_spread_ratio -1.0: must be 0 \(off\) or at least 1"),
        ("reject_contexts", {"min_contexts": 0}, r"min_contexts 0: must be at least 1"),
        ("reject_contexts", {"min_trajectories": 0}, r"min_trajectories 0: must be at least 1"),
        ("reject_contexts", {"bin_width": -0.25}, r"bin_width -0.25: must be 0 \(off\) or positive"),
    ],
)
def test_an_impossible_parameter_value_is_refused_in_one_line(step, params, message):
    with pytest.raises(InputError, match=rf"^steps.toml, step '{step}': {message}") as error:
        Pipeline([(step, params)], source="steps.toml").run(_THROWS)
    assert "\n" not in str(error.value)


@pytest.mark.parametrize(
    ("step", "params"),
    [("spike_filter", {"threshold": 0.0}), ("reject_contexts", {"max_spread_ratio": 0.0, "tolerance": 0.0,
                                                                  "z": 0.0, "bin_width": 0.0}),
     ("reject_contexts", {"max_spread_ratio": 1.0}), ("balance", {"seed": 0}), ("stop_point", {"extension": 0.01})],
)
def test_the_edges_of_the_valid_ranges_are_accepted(step, params):
    Pipeline([(step, params)]).run(_THROWS)


def test_a_pipeline_given_no_dataset_says_what_it_takes():
    frame = _dataset().to_array(["angle", "distance", "velocity"])
    with pytest.raises(InputError, match=r"^Pipeline\.run takes a Dataset \(rlff\.formats\.read_dataset reads one from "
                                         r"a file\), got ndarray$"):
        Pipeline.preset("thesis").run(frame)
