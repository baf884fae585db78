"""Simulated whole-arm people: the plan, the coordination, the kinematics, the misses, the faults."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.interpolate import CubicSpline

from rlff.ballistics import crossing_distance
from rlff.errors import InputError
from rlff.preprocess import spike_filter
from rlff.synthetic.throws import THESIS_DISTANCES, release_state, whole_arm_demonstrations
from rlff.synthetic.whole_arm import (
    FOREARM_ONLY,
    HAND,
    THESIS_BEARINGS,
    THESIS_HEIGHTS,
    UPPER_ARM,
    arm_release_state,
)


@pytest.fixture(scope="module")
def demos():
    return whole_arm_demonstrations(2)


@pytest.fixture(scope="module")
def clean():
    return whole_arm_demonstrations(
        5, subjects=3, distances=(1.0, 2.5, 4.0), bearings=(0.0,), heights=(0.3, 1.0),
        joints=("shoulder", "elbow", "wrist"), raw=False,
    )


def _extension(trajectory) -> slice:
    """From the deepest flexion (its last sample: the elbow waits there) to the full extension."""
    angle = trajectory["angle"]
    low = int(np.flatnonzero(angle == angle.min())[-1])
    return slice(low, low + int(np.argmax(angle[low:])) + 1)


def test_same_seed_same_throws_other_seed_other_throws():
    plan = {"subjects": 2, "distances": (2.0, 3.0), "bearings": (0.0, 60.0), "heights": (0.3,)}
    first = whole_arm_demonstrations(7, **plan)
    assert first.equals(whole_arm_demonstrations(7, **plan))
    assert not first.equals(whole_arm_demonstrations(8, **plan))


def test_plan_is_every_person_at_every_basket(demos):
    assert len(demos) == 4 * len(THESIS_DISTANCES) * len(THESIS_BEARINGS) * len(THESIS_HEIGHTS)
    assert demos.context == ("distance", "bearing", "height")
    assert demos.contexts == tuple(
        (d, b, h) for d in THESIS_DISTANCES for b in THESIS_BEARINGS for h in THESIS_HEIGHTS
    )
    assert demos.columns == (
        "time", "angle", "velocity", "shoulder", "shoulder_velocity", "distance", "bearing", "height"
    )
    for trajectory in demos:
        assert trajectory.meta["target"] == trajectory["distance"][0]
        assert trajectory.meta["source"] == "simulated"
        d, b, h = trajectory.context_value(demos.context)
        assert trajectory.id.startswith(f"{trajectory.meta['subject']}-d{d:g}-b{b:g}-h{h:g}-")


def test_joints_choose_the_columns_and_a_single_default_basket_adds_no_context():
    elbow = whole_arm_demonstrations(0, subjects=1, distances=(2.0,), bearings=(0.0,), heights=(0.3,),
                                     joints=("elbow",))
    assert elbow.columns == ("time", "angle", "velocity", "distance")
    assert elbow.context == ("distance",)
    three = whole_arm_demonstrations(0, subjects=1, distances=(2.0,), bearings=(30.0,), heights=(0.3,),
                                     joints=("wrist", "elbow", "shoulder"))
    assert three.columns == (
        "time", "angle", "velocity", "shoulder", "shoulder_velocity", "wrist", "wrist_velocity",
        "distance", "bearing",
    )


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"joints": ("shoulder", "wrist")}, "the elbow must throw"),
        ({"joints": ("hip", "elbow")}, "joint 'hip': not one of shoulder, elbow, wrist"),
        ({"heights": (2.0,)}, "basket height 2 m: out of range"),
        ({"bearings": (200.0,)}, "basket bearing 200 deg: out of range"),
        ({"rate_hz": 60.0}, "rate_hz 60"),
        ({"bearings": ()}, "no throws to simulate"),
        ({"bearings": (0.0, 30.0, 0.0)}, "basket bearings: 0 deg is given twice"),
        ({"heights": (0.3, 0.3)}, "basket heights: 0.3 m is given twice"),
        ({"noise": np.nan}, "noise nan: the angle noise"),
    ],
)
def test_bad_plans_are_errors_naming_the_value(options, message):
    with pytest.raises(InputError, match=message):
        whole_arm_demonstrations(0, subjects=1, distances=(2.0,), **options)


def test_the_chain_with_a_still_shoulder_and_a_straight_wrist_is_the_one_joint_arm():
    elevation, height = 1.15, 1.45  # upper arm above the horizontal (rad), shoulder height (m)
    elbow, rate = np.array([1.2, 1.8, 2.4]), np.array([5.0, 9.0, 14.0])
    expected = release_state(elevation, height, elbow, rate)
    got = arm_release_state(height, elevation + np.pi / 2, elbow, np.pi, 0.0, rate, 0.0)
    for a, b in zip(got, expected, strict=True):
        np.testing.assert_allclose(a, b, atol=1e-12)
    assert FOREARM_ONLY + HAND == pytest.approx(0.35)


def test_the_chain_velocity_is_the_derivative_of_its_position():
    t = np.linspace(0.0, 0.3, 3001)
    shoulder, elbow, wrist = 2.7 - 1.5 * t**2, 0.8 + 8.0 * t**2, 2.3 + 3.0 * t**2
    rates = -3.0 * t, 16.0 * t, 6.0 * t
    x, z, vx, vz = arm_release_state(1.5, shoulder, elbow, wrist, *rates)
    np.testing.assert_allclose(np.gradient(x, t)[1:-1], vx[1:-1], atol=1e-4)
    np.testing.assert_allclose(np.gradient(z, t)[1:-1], vz[1:-1], atol=1e-4)
    # straight arm held horizontal forward: the hand is the arm's length ahead of the shoulder
    x, z, _, _ = arm_release_state(1.5, np.pi / 2, np.pi, np.pi, 0.0, 0.0, 0.0)
    assert (float(x), float(z)) == pytest.approx((UPPER_ARM + FOREARM_ONLY + HAND, 1.5))


def test_proximal_to_distal_the_shoulder_leads_the_elbow_and_the_wrist_follows(clean):
    for trajectory in clean:
        time, shoulder = trajectory["time"], trajectory["shoulder"]
        extension = _extension(trajectory)
        t = time[extension]
        # the wind-up raises the arm from hanging to about horizontal, the throw raises it further
        # (as in the MSR high throws)
        assert shoulder[0] < 0.7 and 1.2 < shoulder[extension.start] < 1.7
        assert np.all(np.diff(trajectory["angle"][extension]) > 0), "the elbow's angle is the phase"
        shoulder_peak = t[np.argmax(trajectory["shoulder_velocity"][extension])]
        elbow_peak = t[np.argmax(trajectory["velocity"][extension])]
        wrist_peak = t[np.argmax(trajectory["wrist_velocity"][extension])]
        assert shoulder_peak < elbow_peak
        # the hand straightens with the elbow's fastest extension (in the recordings too)
        assert shoulder_peak <= wrist_peak and abs(wrist_peak - elbow_peak) <= 0.1 + 1e-9
        # the shoulder started its swing before the elbow started extending
        moving = np.flatnonzero(trajectory["shoulder_velocity"] > 0.05)
        assert time[moving[moving > extension.start - 3][0]] <= time[extension.start]
        release = trajectory.meta["release_time"]
        assert np.interp(release, time, shoulder) > np.pi / 2, "the arm above the horizontal at release"
        assert t[0] < release < t[-1]


def test_velocities_are_finite_differences_of_the_recorded_angles(demos):
    for trajectory in demos[:30]:
        for joint, velocity in (("angle", "velocity"), ("shoulder", "shoulder_velocity")):
            np.testing.assert_allclose(trajectory[velocity], np.gradient(trajectory[joint], trajectory["time"]))


def test_landing_follows_the_arm_and_the_ballistics():
    # the landing rebuilt from the recorded motion (30 Hz, true angles) matches the label to a cm
    clean = whole_arm_demonstrations(
        9, subjects=2, distances=(1.5, 3.0), bearings=(0.0,), heights=(0.3, 1.0),
        joints=("shoulder", "elbow", "wrist"), raw=False,
    )
    errors = []
    for trajectory in clean:
        time, release = trajectory["time"], trajectory.meta["release_time"]
        # the recorded angles through a spline: positions and rates at the release
        splines = [CubicSpline(time, trajectory[name]) for name in ("shoulder", "angle", "wrist")]
        state = [float(f(release)) for f in splines] + [float(f(release, 1)) for f in splines]
        assert state[1] == pytest.approx(trajectory.meta["release_angle"], abs=0.05)
        # the subject's shoulder height is not recorded: solve it from the landing's label
        heights = np.linspace(1.3, 1.6, 301)
        x, z, vx, vz = arm_release_state(heights, *state)
        landings = crossing_distance(x, z, vx, vz, trajectory["height"][0])
        errors.append(float(np.min(np.abs(landings - trajectory.meta["landing"]))))
        assert trajectory.meta["hit"] == (abs(trajectory.meta["landing"] - trajectory.meta["target"]) <= 0.15)
    assert max(errors) < 0.01


def test_farther_and_higher_baskets_are_thrown_faster():
    exact = whole_arm_demonstrations(
        5, subjects=3, distances=(1.0, 2.5, 4.0), bearings=(0.0,), heights=(0.3, 1.0), raw=False,
        throw_error=0.0, release_jitter=0.0, shape_scatter=0.0,
    )
    peaks = {
        context: np.median([t["velocity"].max() for t in group]) for context, group in exact.by_context().items()
    }
    for height in (0.3, 1.0):
        assert peaks[(1.0, height)] < peaks[(2.5, height)] < peaks[(4.0, height)]
    for distance in (1.0, 2.5, 4.0):
        assert peaks[(distance, 0.3)] < peaks[(distance, 1.0)]


def test_the_bearing_labels_the_throw_but_does_not_change_the_motion():
    plan = {"subjects": 2, "distances": (1.5, 3.5), "heights": (0.6,)}
    ahead = whole_arm_demonstrations(4, bearings=(0.0,), **plan)
    left = whole_arm_demonstrations(4, bearings=(60.0,), **plan)
    assert "bearing" not in ahead.columns and set(left[0]["bearing"]) == {60.0}
    for a, b in zip(ahead, left, strict=True):
        for name in ahead.columns:
            np.testing.assert_array_equal(a[name], b[name])
        assert a.meta == b.meta


def test_people_miss_as_people_do(demos):
    miss = np.array([t.meta["landing"] - t.meta["target"] for t in demos])
    assert np.all(np.isfinite(miss))
    assert 0.7 < np.mean(miss < 0) < 0.97, "mostly short, some long"
    assert 0.15 < np.mean([t.meta["hit"] for t in demos]) < 0.7
    # each person has their own bias
    by_subject = {}
    for trajectory, m in zip(demos, miss / np.array([t.meta["target"] for t in demos]), strict=True):
        by_subject.setdefault(trajectory.meta["subject"], []).append(m)
    means = sorted(np.mean(v) for v in by_subject.values())
    assert means[-1] - means[0] > 0.02


def test_all_short_misses_every_basket_short():
    failures = whole_arm_demonstrations(1, subjects=2, distances=(1.0, 2.5, 4.0), all_short=True)
    assert not any(t.meta["hit"] for t in failures)
    assert all(t.meta["landing"] < t.meta["target"] - 0.15 for t in failures)


def test_a_glitch_disturbs_every_joint_and_the_spike_filter_removes_it_from_all():
    seen = 0
    for seed in range(12):
        plan = {"subjects": 1, "distances": (2.5,), "bearings": (0.0,), "heights": (0.3,),
                "joints": ("shoulder", "elbow", "wrist"), "noise": 0.0, "dropped_frames": 0.0}
        faulty = whole_arm_demonstrations(seed, glitches=0.08, **plan)
        truth = whole_arm_demonstrations(seed, glitches=0.0, **plan)[0]
        if not faulty[0].meta["glitches"]:
            continue
        seen += 1
        different = {name: faulty[0][name] != truth[name] for name in ("angle", "shoulder", "wrist")}
        np.testing.assert_array_equal(different["angle"], different["shoulder"])
        np.testing.assert_array_equal(different["angle"], different["wrist"])
        cleaned, _ = spike_filter(faulty)
        kept = np.isin(truth["time"], cleaned[0]["time"])
        assert not np.any(kept & different["angle"]), "every glitch frame removed"
        for joint, velocity in (("shoulder", "shoulder_velocity"), ("wrist", "wrist_velocity")):
            np.testing.assert_array_equal(cleaned[0][joint], truth[joint][kept])
            np.testing.assert_allclose(cleaned[0][velocity], np.gradient(cleaned[0][joint], cleaned[0]["time"]))
    assert seen >= 3


@pytest.mark.parametrize("extension", ["csv", "parquet", "npz"])
def test_whole_arm_demonstrations_round_trip_through_every_dataset_format(tmp_path, extension):
    from rlff.formats import read_dataset, write_dataset

    dataset = whole_arm_demonstrations(0, subjects=1, distances=(1.0, 2.0), joints=("shoulder", "elbow", "wrist"))
    write_dataset(dataset, tmp_path / f"arm.{extension}")
    back = read_dataset(tmp_path / f"arm.{extension}")
    assert back.equals(dataset) and back.context == ("distance", "bearing", "height")
