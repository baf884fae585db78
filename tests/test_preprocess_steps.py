"""Each cleaning step on small hand-made trajectories, with exact expected outputs."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from rlff.dataset import Dataset, Trajectory
from rlff.errors import InputError
from rlff.preprocess import (
    balance,
    crop,
    cut_release,
    densify,
    find_spikes,
    largest_change,
    longest_monotonic,
    min_points,
    monotonic_run,
    reject_contexts,
    reject_shapes,
    rescale,
    spike_filter,
    stop_point,
)


def _throw(name, angle, velocity=None, distance=2.0, time=None, **extra) -> Trajectory:
    angle = np.asarray(angle, dtype=float)
    data = {"angle": angle, "distance": np.full(angle.size, distance),
            "velocity": np.asarray(velocity if velocity is not None else np.ones(angle.size), dtype=float)}
    if time is not None:
        data["time"] = np.asarray(time, dtype=float)
    data.update({k: np.asarray(v, dtype=float) for k, v in extra.items()})
    return Trajectory(name, data)


def _one(trajectory: Trajectory) -> Dataset:
    return Dataset([trajectory])


# -- 1. spike filter ---------------------------------------------------------------------------


def test_spike_filter_drops_a_one_sample_glitch_and_recomputes_velocity():
    time = [0.0, 0.1, 0.2, 0.3, 0.4]
    data = _one(_throw("a", [1.0, 1.1, 0.05, 1.3, 1.4], velocity=[9, 9, 9, 9, 9], time=time))
    out, report = spike_filter(data, threshold=2.0)
    np.testing.assert_array_equal(out["a"]["angle"], [1.0, 1.1, 1.3, 1.4])
    np.testing.assert_array_equal(out["a"]["time"], [0.0, 0.1, 0.3, 0.4])
    # numpy.gradient on the kept samples: one-sided at the ends, second order inside
    np.testing.assert_allclose(out["a"]["velocity"], [1.0, 1.0, 1.0, 1.0], atol=1e-12)
    (change,) = report.samples
    assert (change.trajectory, change.removed, change.added) == ("a", 1, 0)
    assert "glitch sample 2" in change.reason


def test_spike_filter_drops_a_two_sample_glitch_and_an_end_glitch():
    assert find_spikes(np.array([1.0, 1.1, 0.05, 0.1, 1.4, 1.5]), None, 0.5).tolist() == [2, 3]
    assert find_spikes(np.array([1.0, 1.1, 1.2, 1.3, 0.0]), None, 0.5).tolist() == [4]
    assert find_spikes(np.array([0.0, 1.1, 1.2, 1.3, 1.4]), None, 0.5).tolist() == [0]


def test_spike_filter_keeps_fast_motion_and_an_abrupt_stop():
    # full-speed extension, then a stop with a small recoil: no out-and-back, nothing removed
    angle = np.array([0.7, 0.72, 1.5, 2.5, 3.0, 2.95, 2.95])
    assert find_spikes(angle, np.arange(7) / 30.0, 2.0).size == 0
    # a deep glitch in the middle of a fast extension still goes, its good neighbour stays
    assert find_spikes(np.array([0.6, 0.84, 1.97, 0.05, 2.98, 3.1]), np.arange(6) / 20, 8.0).tolist() == [3]


def test_spike_filter_auto_threshold_is_k_robust_deviations():
    # steps 1, 2, 3 (per sample, no time column): changes of speed 1, 1 -> median 1
    data = _one(_throw("a", [0.0, 1.0, 3.0, 6.0]))
    out, report = spike_filter(data, k=3.0)
    assert report.params["threshold"] == pytest.approx(3.0 * 1.4826)
    assert out.equals(data)
    assert report.summary() == "no change"


# -- 2-5. segmentation -------------------------------------------------------------------------


def test_crop_between_global_minimum_and_maximum():
    data = Dataset([_throw("up", [1.5, 1.0, 0.7, 1.2, 2.8, 3.0, 2.9]), _throw("down", [3.0, 2.0, 1.0, 2.0])])
    out, report = crop(data)
    np.testing.assert_array_equal(out["up"]["angle"], [0.7, 1.2, 2.8, 3.0])
    np.testing.assert_array_equal(out["down"]["angle"], [3.0, 2.0, 1.0])
    assert [(c.trajectory, c.removed) for c in report.samples] == [("up", 3), ("down", 1)]


def test_crop_increasing_takes_the_extension_after_a_straight_arm_at_rest():
    # the arm hangs nearly straight (3.0) before the wind-up: the global maximum comes first, and
    # the global extremes would keep the wind-up (falling); the largest rise is the extension
    angle = [3.0, 2.9, 2.0, 1.0, 0.8, 1.5, 2.6, 2.9, 2.7]
    data = _one(_throw("rest-first", angle, velocity=np.arange(9.0)))
    old, _ = crop(data)
    np.testing.assert_array_equal(old["rest-first"]["angle"], [3.0, 2.9, 2.0, 1.0, 0.8])
    out, report = crop(data, direction="increasing")
    np.testing.assert_array_equal(out["rest-first"]["angle"], [0.8, 1.5, 2.6, 2.9])
    np.testing.assert_array_equal(out["rest-first"]["velocity"], [4.0, 5.0, 6.0, 7.0])
    (change,) = report.samples
    assert (change.removed, change.reason) == (5, "kept samples 4-7, the largest rise of angle")
    assert report.params == {"column": "angle", "direction": "increasing"}


def test_crop_increasing_is_the_largest_rise_not_the_global_minimum():
    # the global minimum (0.2) is followed by a rise of 0.2 only; the rise 0.5 -> 1.0 is larger
    assert largest_change(np.array([2.0, 0.5, 1.0, 0.2, 0.4]), "increasing") == (1, 2)
    assert largest_change(np.array([2.0, 0.5, 1.0, 0.2, 0.4]), "any") == (0, 3)
    # the largest fall, from the highest sample to the lowest after it
    assert largest_change(np.array([1.0, 3.0, 2.0, 0.5, 0.7]), "decreasing") == (1, 3)
    # first occurrences of tied extremes
    assert largest_change(np.array([1.0, 0.5, 0.5, 2.0, 2.0]), "increasing") == (1, 3)


def test_crop_and_longest_monotonic_remove_a_trajectory_without_a_rise_with_the_reason():
    data = Dataset([_throw("falls", [3.0, 2.0, 1.0]), _throw("flat", [2.0, 2.0]), _throw("up", [1.0, 2.0])])
    for step in (crop, longest_monotonic):
        out, report = step(data, direction="increasing")
        assert out.ids == ("up",)
        assert [r.trajectory for r in report.removed] == ["falls", "flat"]
        assert "is a single sample: no motion to keep" in report.removed[0].reason


@given(st.lists(st.floats(-10, 10, allow_nan=False), min_size=1, max_size=30))
def test_largest_change_matches_every_pair(values):
    values = np.array(values)
    first, last = largest_change(values, "increasing")
    assert first <= last
    rises = values[None, :] - values[:, None]  # rises[i, j] = values[j] - values[i]
    best = max(0.0, float(np.max(np.triu(rises))))
    assert values[last] - values[first] == best
    first, last = largest_change(values, "decreasing")
    assert values[first] - values[last] == max(0.0, float(np.max(np.triu(-rises))))


def test_longest_monotonic_run():
    angle = np.array([0.7, 0.8, 0.75, 1.0, 1.5, 2.0, 1.9])
    assert monotonic_run(angle) == (2, 5)
    assert monotonic_run(angle, "decreasing") == (1, 2)
    assert monotonic_run(np.array([1.0, 2.0, 2.0, 3.0, 4.0])) == (2, 4)  # equal values end a run
    assert monotonic_run(np.array([5.0])) == (0, 0)
    assert monotonic_run(np.array([3.0, 2.0, 1.0]), "increasing") == (0, 0)
    out, report = longest_monotonic(_one(_throw("a", angle)), direction="increasing")
    np.testing.assert_array_equal(out["a"]["angle"], [0.75, 1.0, 1.5, 2.0])
    assert report.samples[0].removed == 3


def test_min_points_removes_short_trajectories_with_the_reason():
    data = Dataset([_throw("short", [1.0, 2.0, 3.0]), _throw("long", [1.0, 2.0, 3.0, 4.0, 5.0])])
    out, report = min_points(data, min_points=4)
    assert out.ids == ("long",)
    assert [(r.trajectory, r.reason) for r in report.removed] == [("short", "3 samples, fewer than 4")]
    with pytest.raises(InputError, match="min_points 0"):
        min_points(data, min_points=0)


def test_crop_warns_when_the_throws_move_the_other_way_at_their_fastest():
    # flexion angles (0 straight) fall as the arm extends: the preset's crop kept their wind-up
    extension = [0.5, 1.0, 2.0, 2.5, 2.0]
    velocity = [0.5, 3.0, 8.0, 2.0, -1.0]
    normal = Dataset([_throw(f"t{i}", extension, velocity=velocity) for i in range(3)])
    assert crop(normal, direction="increasing")[1].warnings == []
    flexion = Dataset([_throw(f"t{i}", np.pi - np.array(extension), velocity=-np.array(velocity)) for i in range(3)])
    _, report = crop(flexion, direction="increasing")
    assert report.warnings[0].startswith("3 of 3 throws move their angle the other way at their fastest sample: it "
                                         "is kept where it rises, their wind-up")
    assert crop(flexion, direction="decreasing")[1].warnings == []


def test_balance_keeps_at_most_m_per_context_deterministically():
    data = Dataset([_throw(f"t{i}", [1.0, 2.0], distance=d) for i, d in enumerate([1, 1, 2, 1, 1, 2, 3])])
    out, report = balance(data, max_per_context=2)
    assert out.ids == ("t0", "t1", "t2", "t5", "t6")
    assert {r.trajectory for r in report.removed} == {"t3", "t4"}
    assert "context distance=1 has 4 trajectories, keeping 2" in report.removed[0].reason
    first, _ = balance(data, max_per_context=2, order="random", seed=3)
    again, _ = balance(data, max_per_context=2, order="random", seed=3)
    assert first.ids == again.ids
    assert list(first.ids) == sorted(first.ids, key=data.ids.index)  # dataset order kept


def test_balance_warns_of_subjects_it_leaves_out_whole():
    # the thesis preset's first-ten rule kept 3 of 10 simulated people, and said only "removed 300"
    data = Dataset([t.replace(meta={"subject": f"s{i // 2}"})
                    for i, t in enumerate(_throw(f"t{i}", [1.0, 2.0], distance=1) for i in range(6))])
    _, report = balance(data, max_per_context=2)
    assert report.warnings == ["every throw of 2 subjects (s1, s2) was left out: order 'first' keeps the first "
                               "of each basket in the data's order; order 'random' draws from every subject"]
    assert report.to_dict()["warnings"] == report.warnings
    _, kept_all = balance(data, max_per_context=6)
    assert kept_all.warnings == []


# -- 6-9. reshaping ----------------------------------------------------------------------------


def test_stop_point_is_ten_percent_beyond_at_rest():
    data = _one(_throw("a", [1.0, 2.0], velocity=[1.0, 4.0], time=[0.0, 0.5]))
    out, report = stop_point(data)
    np.testing.assert_allclose(out["a"]["angle"], [1.0, 2.0, 2.2])
    np.testing.assert_array_equal(out["a"]["velocity"], [1.0, 4.0, 0.0])
    np.testing.assert_array_equal(out["a"]["distance"], [2.0, 2.0, 2.0])
    # uniform deceleration from 4 rad/s over 0.2 rad: 0.1 s
    np.testing.assert_allclose(out["a"]["time"], [0.0, 0.5, 0.6])
    assert report.samples[0].added == 1


@pytest.mark.parametrize(
    ("mode", "expected_first", "expected_second"),
    [("scale", [1.25, 2.5], [1.25, 2.5]), ("stretch", [1.0, 2.5], [1.5, 2.5])],
)
def test_rescale_to_the_mean_final_angle(mode, expected_first, expected_second):
    data = Dataset([_throw("a", [1.0, 2.0], velocity=[2.0, 2.0]), _throw("b", [1.5, 3.0], velocity=[3.0, 3.0])])
    out, report = rescale(data, mode=mode)
    np.testing.assert_allclose(out["a"]["angle"], expected_first)
    np.testing.assert_allclose(out["b"]["angle"], expected_second)
    np.testing.assert_array_equal(out["a"]["velocity"], [2.0, 2.0])  # positions only, as the thesis
    assert report.params["end"] == 2.5
    scaled, _ = rescale(data, mode="scale", scale_velocity=True)
    np.testing.assert_allclose(scaled["b"]["velocity"], [2.5, 2.5])


@pytest.mark.parametrize("mode", ["scale", "stretch"])
def test_rescale_removes_a_throw_it_would_reverse_or_cannot_move(mode):
    # the mean end is 2.5: stretched, "beyond" (2.6 -> 2.7) would run backwards from 2.6 to 2.5
    # with its velocity still forward; scaled, "negative" would be flipped about 0
    data = Dataset([_throw("a", [1.0, 2.0]), _throw("b", [1.5, 3.1]), _throw("beyond", [2.6, 2.7]),
                    _throw("negative", [-1.0, -0.3]), _throw("still", [0.0, 0.0] if mode == "scale" else [2.0, 2.0])])
    out, report = rescale(data, mode=mode, max_factor=math.inf)  # factors far from 1: the next test
    removed = {r.trajectory: r.reason for r in report.removed}
    expected = {"scale": {"negative", "still"}, "stretch": {"beyond", "still"}}[mode]
    assert set(removed) == expected
    assert set(out.ids) == set(data.ids) - expected
    assert all(np.all(np.diff(t["angle"]) > 0) for t in out)
    assert "would reverse the motion" in removed["beyond" if mode == "stretch" else "negative"]
    assert "its last angle is" in removed["still"]


@pytest.mark.parametrize("mode", ["scale", "stretch"])
def test_rescale_removes_a_throw_cut_short_rather_than_make_up_its_shape(mode):
    # a real MSR throw whose extension the tracker ended at 1.38 rad was stretched 2.5 times into
    # a slow sweep; here one ends at 1.0 rad where the others end near 2.9, and without it the
    # common end is theirs
    throws = [_throw(f"t{k}", [0.7, 1.8, end]) for k, end in enumerate([2.8, 2.9, 3.0])]
    data = Dataset([*throws, _throw("cut", [0.33, 0.6, 1.0])])
    out, report = rescale(data, mode=mode)
    assert list(out.ids) == ["t0", "t1", "t2"]
    [removed] = report.removed
    assert removed.trajectory == "cut" and "would make up its shape: a throw cut short" in removed.reason
    assert "more than max_factor 2" in removed.reason
    assert report.params["end"] == pytest.approx(2.9)  # the kept throws' mean end
    np.testing.assert_allclose([t["angle"][-1] for t in out], 2.9)
    # judged against the median end: the shortest end is not the common end that every other
    # throw is then too far from
    lowest, _ = rescale(data, mode=mode, reference="min")
    assert list(lowest.ids) == ["t0", "t1", "t2"]
    np.testing.assert_allclose([t["angle"][-1] for t in lowest], 2.8)
    kept, kept_report = rescale(data, mode=mode, max_factor=math.inf)  # any factor: the thesis' rule
    assert kept.ids == data.ids and kept_report.removed == []
    with pytest.raises(InputError, match="max_factor 0.5: must be a number >= 1"):
        rescale(data, max_factor=0.5)


def test_densify_resamples_a_line_exactly_in_the_direction_of_motion():
    up = _throw("up", [0.0, 0.1, 0.2, 0.3], velocity=[1.0, 1.2, 1.4, 1.6], time=[0.0, 0.1, 0.2, 0.3])
    down = _throw("down", [0.3, 0.2, 0.1, 0.02], velocity=[-1.0, -1.2, -1.4, -1.56], time=[0, 1, 2, 2.8])
    out, report = densify(Dataset([up, down]), step=0.05)
    np.testing.assert_allclose(out["up"]["angle"], [0.0, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3], atol=1e-12)
    np.testing.assert_allclose(out["up"]["velocity"], 1.0 + 2.0 * out["up"]["angle"], atol=1e-12)
    np.testing.assert_allclose(out["up"]["time"], out["up"]["angle"], atol=1e-12)
    np.testing.assert_allclose(out["down"]["angle"], [0.3, 0.25, 0.2, 0.15, 0.1, 0.05, 0.02], atol=1e-12)
    np.testing.assert_allclose(out["down"]["velocity"], -1.6 + 2.0 * out["down"]["angle"], atol=1e-12)
    assert [(c.removed, c.added) for c in report.samples] == [(4, 7), (4, 7)]
    # 4 measured samples stand behind 7: the share BIC counts; a second densify multiplies it
    assert out["up"].meta["measured_share"] == pytest.approx(4 / 7)
    again, _ = densify(out, step=0.025)
    assert again["up"].meta["measured_share"] == pytest.approx(4 / 7 * 7 / 13)


def test_densify_anchors_limit_the_spline_overshoot():
    step = _one(_throw("a", [0.0, 1.0, 2.0, 3.0, 4.0], velocity=[0.0, 0.0, 1.0, 1.0, 1.0]))
    anchored, _ = densify(step, step=0.01)
    free, _ = densify(step, step=0.01, anchors=[])
    overshoot = lambda d: max(d["a"]["velocity"].max() - 1.0, -d["a"]["velocity"].min())  # noqa: E731
    assert overshoot(anchored) < 0.5 * overshoot(free)


def test_densify_removes_a_trajectory_that_turns_back():
    data = Dataset([_throw("ok", [0.0, 0.1, 0.2]), _throw("back", [0.0, 0.2, 0.1])])
    out, report = densify(data, step=0.1)
    assert out.ids == ("ok",)
    assert report.removed[0].trajectory == "back"
    assert "not strictly monotonic" in report.removed[0].reason


def test_cut_release_at_a_fixed_angle_or_at_the_velocity_peak():
    data = Dataset([_throw("a", [0.5, 0.8, 0.9, 1.0, 1.2], velocity=[1, 3, 5, 4, 2]),
                    _throw("late", [1.0, 1.1], velocity=[1, 2])])
    out, report = cut_release(data, mode="angle", angle=0.9)
    np.testing.assert_array_equal(out["a"]["angle"], [0.5, 0.8, 0.9])
    assert out["a"].meta["cut_angle"] == 0.9
    assert [r.trajectory for r in report.removed] == ["late"]
    out, _ = cut_release(data, mode="estimated")
    np.testing.assert_array_equal(out["a"]["velocity"], [1, 3, 5])
    np.testing.assert_array_equal(out["late"]["angle"], [1.0, 1.1])
    out, _ = cut_release(data, mode="estimated", after_peak=0.2)
    np.testing.assert_array_equal(out["a"]["velocity"], [1, 3, 5, 4])


def test_cut_release_warns_when_the_throws_were_cut_before():
    # the thesis preset run on its own output removed 2 more real throws and said nothing of why
    data = Dataset([_throw("a", [0.5, 0.8, 0.9, 1.0, 1.2], velocity=[1, 3, 5, 4, 2]),
                    _throw("b", [0.5, 0.8, 0.9, 1.0, 1.2], velocity=[1, 3, 5, 4, 2])])
    once, first = cut_release(data, mode="estimated")
    assert first.warnings == []
    _, again = cut_release(once, mode="estimated")
    assert again.warnings == ["2 of 2 throws were cut at their release before (their cut_angle): the data look "
                              "cleaned already, and cleaning them again removes and reshapes more; give the "
                              "demonstrations as imported or simulated"]


def test_cut_release_warns_when_no_throw_goes_beyond_the_fixed_angle():
    # angle = 52 (degrees by mistake) cut nothing and said nothing
    data = Dataset([_throw("a", [0.5, 0.8, 0.9, 1.0, 1.2], velocity=[1, 3, 5, 4, 2]),
                    _throw("b", [0.6, 0.9, 1.3], velocity=[1, 3, 2])])
    out, report = cut_release(data, mode="angle", angle=52)
    assert [len(t) for t in out] == [5, 3]
    assert report.warnings == ["no throw's angle goes beyond the cut angle 52 (the furthest is 1.3): nothing was cut; "
                               "angles are in rad (52 deg is 0.9076 rad)"]
    _, report = cut_release(data, mode="angle", angle=1.3)  # reached but not passed: still nothing cut
    assert report.warnings == ["no throw's angle goes beyond the cut angle 1.3 (the furthest is 1.3): nothing was cut; "
                               "angles are in rad"]
    _, report = cut_release(data, mode="angle", angle=1.1)  # one throw goes beyond it
    assert report.warnings == []
    # throws that extend towards smaller angles: beyond is below
    falling = Dataset([_throw("c", [2.0, 1.5, 1.0], velocity=[-1, -3, -2])])
    _, report = cut_release(falling, mode="angle", angle=0.5)
    assert report.warnings == ["no throw's angle goes beyond the cut angle 0.5 (the furthest is 1): nothing was cut; "
                               "angles are in rad"]


def test_cut_release_removes_a_trajectory_it_would_leave_with_one_sample():
    data = Dataset([_throw("a", [0.5, 0.8, 0.9], velocity=[5, 3, 1]), _throw("b", [0.5, 0.95, 1.0], velocity=[1, 3, 2])])
    for mode in ("estimated", "angle"):
        out, report = cut_release(data, mode=mode, angle=0.7)
        assert "a" not in out.ids and all(len(t) >= 2 for t in out)
        assert "leaves 1 sample, fewer than 2" in report.removed[0].reason


def test_cut_release_takes_the_middle_of_the_velocitys_top():
    # three samples within a tenth of the fastest, the fastest first: which of a camera's few
    # frames of the extension's fastest part is fastest is the tracker's noise
    data = Dataset([_throw("flat", [0.5, 0.8, 1.0, 1.2, 1.4, 1.6], velocity=[1, 3, 5.0, 4.8, 4.7, 2])])
    out, report = cut_release(data, mode="estimated", top=0.1)
    assert out["flat"].meta["cut_angle"] == 1.2  # the middle of 1.0 .. 1.4
    assert report.params["top"] == 0.1
    assert cut_release(data, mode="estimated")[0]["flat"].meta["cut_angle"] == 1.0  # default: the fastest
    assert cut_release(data, mode="estimated", top=0.03)[0]["flat"].meta["cut_angle"] == 1.0  # 4.8 < 4.85
    # a drop after the peak counts from the top's middle, by a share of the fastest speed
    assert cut_release(data, mode="estimated", top=0.1, after_peak=0.5)[0]["flat"].meta["cut_angle"] == 1.6
    # a trajectory that never moves forward is cut at its least backward sample, as without a top
    back = Dataset([_throw("back", [0.5, 0.8, 1.0], velocity=[-1, -0.5, -2])])
    assert cut_release(back, mode="estimated", top=0.1)[0]["back"].meta["cut_angle"] == 0.8
    with pytest.raises(InputError, match=r"top 1.0: the share of the peak speed"):
        cut_release(data, top=1.0)


# -- 10-11. rejection --------------------------------------------------------------------------


def _curves(levels: dict[float, list[float]]) -> Dataset:
    angle = np.linspace(0.7, 2.0, 8)
    return Dataset([
        _throw(f"d{d:g}-{i}", angle, velocity=np.full(8, level), distance=d)
        for d, group in levels.items() for i, level in enumerate(group)
    ])


def test_reject_contexts_finds_the_one_that_breaks_the_trend():
    data = _curves({1.0: [1.0], 2.0: [2.0], 3.0: [1.5], 4.0: [4.0], 5.0: [5.0]})
    out, report = reject_contexts(data, max_spread_ratio=0, min_trajectories=1)
    assert out.contexts == ((1.0,), (2.0,), (4.0,), (5.0,))
    (rejection,) = report.contexts
    assert rejection.context == {"distance": 3.0}
    assert rejection.trajectories == ("d3-0",)
    assert rejection.reason == (
        "breaks the increasing trend of velocity with distance: level 1.5, 50 % below the 3 its "
        "neighbours 2 and 4 suggest"
    )
    assert [r.trajectory for r in report.removed] == ["d3-0"]


def test_reject_contexts_finds_the_one_that_stands_apart():
    data = _curves({1.0: [0.9, 1.0, 1.1], 2.0: [1.9, 2.0, 2.1], 3.0: [2.9, 3.0, 3.1],
                    4.0: [3.9, 4.0, 4.1], 5.0: [3.0, 5.0, 7.0]})
    out, report = reject_contexts(data)
    assert out.contexts == ((1.0,), (2.0,), (3.0,), (4.0,))
    assert "scatter 8.0 times more" in report.contexts[0].reason


def test_reject_contexts_along_one_of_two_context_columns():
    angle = np.linspace(0.7, 2.0, 5)
    trajectories = [
        _throw(f"h{h:g}-d{d:g}", angle, velocity=np.full(5, level), distance=d, height=np.full(5, h))
        for h, levels in ((0.3, [1.0, 2.0, 1.5, 4.0]), (0.5, [1.0, 2.0, 3.0, 4.0]))
        for d, level in zip([1.0, 2.0, 3.0, 4.0], levels, strict=True)
    ]
    data = Dataset(trajectories, context=("distance", "height"))
    out, report = reject_contexts(data, max_spread_ratio=0, min_trajectories=1)
    assert [r.context for r in report.contexts] == [{"distance": 3.0, "height": 0.3}]
    assert len(out) == 7
    with pytest.raises(InputError, match="'speed' is not a context column"):
        reject_contexts(data, column="speed")


def test_reject_contexts_scatter_is_judged_subject_by_subject():
    # subject "b" throws twice as fast as "a"; only 3 m has both: scattered, unless each throw
    # is compared with its own subject's speed
    trajectories = []
    for d, subjects in ((1.0, "a"), (2.0, "a"), (3.0, "ab"), (4.0, "b"), (5.0, "b")):
        for subject in subjects:
            for k, noise in enumerate((0.99, 1.01)):
                level = noise * (2.0 if subject == "b" else 1.0)
                trajectory = _throw(f"{subject}-{d:g}-{k}", np.linspace(0.7, 2.0, 5), np.full(5, level), d)
                trajectories.append(trajectory.replace(meta={"subject": subject}))
    data = Dataset(trajectories)
    _, naive = reject_contexts(data, trend="none", by_subject=False)
    assert [r.context for r in naive.contexts] == [{"distance": 3.0}]
    # spread at 3 m: median distance 0.495 from the median 1.495; elsewhere 1 %
    assert "scatter 33.1 times more" in naive.contexts[0].reason
    fair, report = reject_contexts(data, trend="none")
    assert report.contexts == [] and fair.equals(data)


def test_reject_contexts_compares_subjects_with_themselves():
    # subject "fast" throws three times as fast as "slow"; at 3 m only "slow" threw: not a dip
    angle = np.linspace(0.7, 2.0, 5)
    trajectories = []
    for d in (1.0, 2.0, 3.0, 4.0, 5.0):
        for subject, factor in (("fast", 3.0), ("slow", 1.0)):
            if d == 3.0 and subject == "fast":
                continue
            for k in range(2):
                trajectory = _throw(f"{subject}-{d:g}-{k}", angle, velocity=np.full(5, factor * d), distance=d)
                trajectories.append(trajectory.replace(meta={"subject": subject}))
    data = Dataset(trajectories)
    naive, report = reject_contexts(data, by_subject=False, max_spread_ratio=0, z=0.0)
    assert [r.context for r in report.contexts] == [{"distance": 3.0}]
    fair, report = reject_contexts(data, max_spread_ratio=0)
    assert report.contexts == [] and fair.equals(data)


def test_reject_contexts_needs_a_significant_dip():
    # 3 m is 40 % low, but its throws scatter so much that it may be chance (z = 2)
    data = _curves({1.0: [1.0, 1.0, 1.0], 2.0: [2.0, 2.0, 2.0], 3.0: [0.5, 1.8, 4.0],
                    4.0: [4.0, 4.0, 4.0], 5.0: [5.0, 5.0, 5.0]})
    kept, report = reject_contexts(data, max_spread_ratio=0)
    assert report.contexts == []
    _, report = reject_contexts(data, max_spread_ratio=0, z=0.0)
    assert [r.context for r in report.contexts] == [{"distance": 3.0}]


def test_reject_contexts_judges_single_throws_only_in_bins():
    # one throw per (estimated, continuous) distance: nothing judged unless grouped into bins
    data = _curves({1.0: [1.0], 1.1: [1.1], 2.0: [2.0], 2.1: [2.1], 2.9: [1.4], 3.05: [1.6],
                    4.0: [4.0], 4.1: [4.1]})
    out, report = reject_contexts(data, max_spread_ratio=0)
    assert out.equals(data)
    assert report.notes[0].startswith("8 context(s) with fewer than 2 trajectories not judged")
    out, report = reject_contexts(data, max_spread_ratio=0, bin_width=1.0)
    assert [r.context for r in report.contexts] == [{"distance": 3.0}]
    assert report.contexts[0].trajectories == ("d2.9-0", "d3.05-0")
    assert out.contexts == ((1.0,), (1.1,), (2.0,), (2.1,), (4.0,), (4.1,))


def test_reject_contexts_needs_enough_contexts():
    data = _curves({1.0: [2.0, 2.0], 2.0: [1.0, 1.0]})
    out, report = reject_contexts(data)
    assert out.equals(data)
    assert report.notes == ["2 context(s), fewer than 3: nothing checked"]


def test_reject_shapes_removes_the_odd_one_of_a_context():
    angle = np.linspace(0.7, 2.0, 20)
    bell = np.sin(np.linspace(0, np.pi, 20))
    trajectories = [_throw(f"b{i}", angle, velocity=(1 + 0.02 * i) * bell + 0.01 * i, distance=2.0) for i in range(4)]
    trajectories.append(_throw("ramp", angle, velocity=np.linspace(0.0, 1.3, 20), distance=2.0))
    trajectories += [_throw(f"pair{i}", angle, velocity=bell, distance=3.0) for i in range(2)]
    out, report = reject_shapes(Dataset(trajectories))
    assert [r.trajectory for r in report.removed] == ["ramp"]
    assert "shape differs from its context's common shape" in report.removed[0].reason
    assert "1 context(s) with fewer than 3 trajectories not compared" in report.notes
    assert len(out) == 6


def test_reject_shapes_tells_a_distance_from_a_limit_just_below_it():
    """At a k that puts the limit a hair under the odd one's distance, the message still shows
    a distance above its limit (at 3 digits both read 0.205, "0.205 > 0.205")."""
    angle = np.linspace(0.7, 2.0, 20)
    bell = np.sin(np.linspace(0, np.pi, 20))
    trajectories = [_throw(f"b{i}", angle, velocity=(1 + 0.02 * i) * bell + 0.01 * i, distance=2.0) for i in range(4)]
    trajectories.append(_throw("ramp", angle, velocity=np.linspace(0.0, 1.3, 20), distance=2.0))
    dataset = Dataset(trajectories)
    removed_at, kept_at = 0.01, 1000.0  # bisect k to the edge of removing the ramp
    for _ in range(60):
        k = (removed_at + kept_at) / 2
        if reject_shapes(dataset, k=k)[1].removed:
            removed_at = k
        else:
            kept_at = k
    report = reject_shapes(dataset, k=removed_at)[1]
    distance, limit = re.search(r"distance (\S+) > (\S+)\)", report.removed[-1].reason).groups()
    assert float(distance) > float(limit), report.removed[-1].reason


# -- whole-arm columns through the steps --------------------------------------------------------


def test_spike_filter_recomputes_every_joints_velocity():
    time = [0.0, 0.1, 0.2, 0.3, 0.4]
    data = _one(_throw("a", [1.0, 1.1, 0.05, 1.3, 1.4], velocity=[9] * 5, time=time,
                       shoulder=[2.0, 2.05, 0.1, 2.15, 2.2], shoulder_velocity=[9] * 5,
                       wrist=[2.4, 2.6, 3.1, 3.0, 3.2], wrist_velocity=[9] * 5))
    out, report = spike_filter(data, threshold=2.0)
    np.testing.assert_array_equal(out["a"]["shoulder"], [2.0, 2.05, 2.15, 2.2])
    np.testing.assert_allclose(out["a"]["shoulder_velocity"], [0.5, 0.5, 0.5, 0.5], atol=1e-12)
    np.testing.assert_allclose(out["a"]["wrist_velocity"], [2.0, 2.0, 2.0, 2.0], atol=1e-12)
    assert report.notes == [
        "velocity, shoulder_velocity, wrist_velocity recomputed from angle, shoulder, wrist and time "
        "where samples were removed"
    ]


def test_stop_point_leaves_the_other_joints_at_rest():
    data = _one(_throw("a", [1.0, 2.0], velocity=[1.0, 4.0], time=[0.0, 0.5],
                       shoulder=[1.8, 2.1], shoulder_velocity=[0.5, 0.6]))
    out, _ = stop_point(data)
    np.testing.assert_array_equal(out["a"]["shoulder"], [1.8, 2.1, 2.1])
    np.testing.assert_array_equal(out["a"]["shoulder_velocity"], [0.5, 0.6, 0.0])


def test_densify_resamples_the_other_joints_along_the_angle():
    # every column linear in the angle: resampled exactly on the angle's grid, the context kept
    angle = np.array([0.8, 1.0, 1.3, 1.7, 2.0])
    arm = _throw("a", angle, velocity=2.0 * angle, time=angle / 4, shoulder=1.2 + 0.5 * angle,
                 shoulder_velocity=3.0 - angle, height=np.full(5, 0.6))
    out, _ = densify(Dataset([arm], context=("distance", "height")), step=0.1)
    grid = out["a"]["angle"]
    np.testing.assert_allclose(grid, np.arange(8, 21) / 10, atol=1e-12)
    np.testing.assert_allclose(out["a"]["shoulder"], 1.2 + 0.5 * grid, atol=1e-12)
    np.testing.assert_allclose(out["a"]["shoulder_velocity"], 3.0 - grid, atol=1e-12)
    np.testing.assert_array_equal(out["a"]["height"], np.full(grid.size, 0.6))


def _uncropped(name, end):
    """A throw with its rest, wind-up, extension and follow-through: it starts at rest at 2.6,
    flexes to 0.8, extends fast to 3.0 and falls back to ``end``, 10 Hz."""
    angle = np.array([2.6, 2.3, 1.9, 1.4, 1.0, 0.8, 1.1, 1.9, 2.6, 3.0, 2.8, end])
    time = np.arange(angle.size) * 0.1
    return _throw(name, angle, velocity=np.gradient(angle, time), time=time)


def test_cut_release_takes_the_throws_direction_from_their_extension_not_their_ends():
    # both end lower than they start: the first and last angle say "decreasing"; the extension,
    # the fastest part, goes up
    data = Dataset([_uncropped("low", 2.4), _uncropped("lower", 2.3)])
    out, report = cut_release(data, mode="estimated")
    assert report.params["throws"] == "increasing"
    assert [t.meta["cut_angle"] for t in out] == [1.9, 1.9]  # the fastest sample, 1.1 -> 1.9 -> 2.6
    # a throw that starts below the fixed angle is cut in its extension; one that starts beyond it
    # is removed with that reason
    wound = Dataset([_throw("wound", [1.0, 0.7, 1.5, 2.4, 3.0, 2.2, 0.6], velocity=[-3, -1, 8, 12, 9, -4, -6])])
    out, report = cut_release(wound, mode="angle", angle=2.0)
    np.testing.assert_array_equal(out["wound"]["angle"], [1.0, 0.7, 1.5])
    _, report = cut_release(data, mode="angle", angle=0.1)
    assert [r.reason for r in report.removed] == ["cut at angle 0.1: it starts beyond it, at 2.6 (angle increasing in "
                                               "the throws); crop it to its extension first (step crop)"] * 2


def test_cut_release_direction_is_the_datasets_majority_or_given():
    data = Dataset([_uncropped("a", 2.4), _uncropped("b", 2.4),
                    _throw("odd", [3.0, 2.0, 1.9], velocity=[-9, -10, -1], time=[0, 0.1, 0.2])])
    _, report = cut_release(data)
    assert report.params["throws"] == "increasing"
    assert "1 trajectory (odd) move angle the other way at their fastest sample" in report.notes[0]
    tie = Dataset([_uncropped("a", 2.4), _throw("odd", [3.0, 2.0, 1.9], velocity=[-9, -10, -1], time=[0, 0.1, 0.2])])
    cut, report = cut_release(tie)  # not an error: a step of a preset must not stop a run
    assert report.params["throws"] == "increasing" and any(
        "cannot tell which way angle moves in the throws (1 trajectories move it up at their fastest sample, 1 down): "
        "cut as increasing" in note for note in report.notes)
    assert cut_release(tie, direction="decreasing")[1].params["throws"] == "decreasing"


@pytest.mark.parametrize("rate", [60.0, 120.0])
def test_densify_counts_a_fast_camera_s_frames_as_the_measurements_a_30_hz_one_makes(rate):
    # one smooth extension of 0.3 s seen at 30 Hz and at a faster rate: the frames in between
    # repeat what their neighbours measured, so BIC must not see 2-4 times the evidence (the
    # same MSR throws resampled to 60-120 Hz got K = 8, one band a throw, where 15-30 Hz got 1-2)
    def seen_at(hz: float) -> Trajectory:
        time = np.arange(0.0, 0.3 + 1e-9, 1.0 / hz)
        progress = 0.5 - 0.5 * np.cos(np.pi * time / 0.3)
        return _throw(f"{hz:g}", 0.8 + 2.0 * progress, velocity=np.pi / 0.3 * np.sin(np.pi * time / 0.3), time=time)

    def measured(trajectory: Trajectory, **settings) -> float:
        out, _ = densify(_one(trajectory), step=0.01, **settings)
        return len(out[trajectory.id]) * out[trajectory.id].meta["measured_share"]

    slow, fast = seen_at(30.0), seen_at(rate)
    assert measured(slow) == pytest.approx(len(slow))  # a 30 Hz camera's frames all count
    assert measured(fast) == pytest.approx(measured(slow), rel=1e-9)
    # 0 counts every frame, as before the cap
    assert measured(fast, independent_rate=0) == pytest.approx(len(fast))
    with pytest.raises(InputError, match="independent_rate"):
        densify(_one(fast), independent_rate=-1.0)
