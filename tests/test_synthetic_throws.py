"""Simulated human throws: the recording plan, the motion, the faults and the ballistic outcomes."""

from __future__ import annotations

import numpy as np
import pytest

from rlff.ballistics import crossing_distance
from rlff.errors import InputError
from rlff.synthetic.throws import (
    FOREARM,
    RIM_HEIGHT,
    THESIS_DISTANCES,
    release_state,
    simulate_throws,
)


@pytest.fixture(scope="module")
def demos():
    return simulate_throws(3, subjects=4)


def test_same_seed_same_throws_other_seed_other_throws():
    first = simulate_throws(7, subjects=2, distances=(2.0, 3.0))
    assert first.equals(simulate_throws(7, subjects=2, distances=(2.0, 3.0)))
    assert not first.equals(simulate_throws(8, subjects=2, distances=(2.0, 3.0)))


def test_recording_plan_follows_the_thesis(demos):
    assert len(demos) == 4 * len(THESIS_DISTANCES) * 4
    assert demos.contexts == tuple((d,) for d in THESIS_DISTANCES)
    assert demos.columns == ("time", "angle", "distance", "velocity")
    assert {t.meta["subject"] for t in demos} == {"s01", "s02", "s03", "s04"}
    for trajectory in demos:
        assert trajectory.meta["target"] == trajectory["distance"][0]


def test_clean_throw_winds_up_extends_and_stops():
    clean = simulate_throws(0, subjects=3, distances=(1.0, 2.5, 4.0), raw=False)
    for trajectory in clean:
        angle, velocity, time = trajectory["angle"], trajectory["velocity"], trajectory["time"]
        assert 0.6 <= angle.min() <= 0.9, "wound up"
        assert 2.7 <= angle.max() <= 3.1, "nearly straight at the end of the extension"
        assert np.argmin(angle) < np.argmax(angle), "wind-up first, then extension"
        assert 4.0 < velocity.max() < 22.0
        # the extension is the bell: the peak lies between the deepest flexion and full extension
        assert np.argmin(angle) < np.argmax(velocity) < np.argmax(angle)
        # release during the extension
        release = trajectory.meta["release_time"]
        assert time[np.argmin(angle)] < release < time[np.argmax(angle)]
        # abrupt stop: from fast to (nearly) still within three frames after full extension
        top = np.argmax(angle)
        assert abs(velocity[min(top + 3, velocity.size - 1)]) < 0.25 * velocity.max()
        assert np.all(np.diff(time) > 0)


def test_velocity_is_the_finite_difference_of_the_recorded_angle(demos):
    for trajectory in demos[:20]:
        np.testing.assert_allclose(trajectory["velocity"], np.gradient(trajectory["angle"], trajectory["time"]))


def test_faster_throws_for_farther_baskets():
    clean = simulate_throws(1, subjects=3, raw=False, throw_error=0.0)
    peaks = [np.median([t["velocity"].max() for t in group]) for group in clean.by_context().values()]
    assert np.all(np.diff(peaks) > 0)


def test_outcome_follows_the_ballistic_model():
    clean = simulate_throws(2, subjects=2, distances=(1.5, 3.0), raw=False)
    for trajectory in clean:
        # rebuild the release from the recorded motion: angle and angular velocity at release
        time = trajectory["time"]
        release = trajectory.meta["release_time"]
        angle = np.interp(release, time, trajectory["angle"])
        assert angle == pytest.approx(trajectory.meta["release_angle"], abs=0.08)
        assert trajectory.meta["hit"] == (abs(trajectory.meta["landing"] - trajectory.meta["target"]) <= 0.15)
    # the landing is monotone in the release speed for a given arm: faster throws land farther
    x, z, vx, vz = release_state(1.2, 1.45, 1.9, np.array([6.0, 9.0, 12.0]))
    landing = crossing_distance(x, z, vx, vz, RIM_HEIGHT)
    assert np.all(np.diff(landing) > 0)
    assert np.hypot(vx, vz) == pytest.approx(FOREARM * np.array([6.0, 9.0, 12.0]))


def test_subjects_tend_to_fall_short_and_many_throws_miss(demos):
    miss = np.array([t.meta["landing"] - t.meta["target"] for t in demos])
    hits = np.array([t.meta["hit"] for t in demos])
    assert np.mean(miss) < 0
    assert 0.05 < hits.mean() < 0.7


def test_all_short_makes_every_throw_a_short_miss():
    failures = simulate_throws(4, subjects=3, all_short=True)
    assert not any(t.meta["hit"] for t in failures)
    assert all(t.meta["landing"] < t.meta["target"] - 0.15 for t in failures)


def test_inconsistent_distance_is_slower_than_its_neighbours():
    demos = simulate_throws(5, subjects=3, inconsistent_distance=2.75, raw=False)
    peak = {c[0]: np.median([t["velocity"].max() for t in g]) for c, g in demos.by_context().items()}
    assert peak[2.75] < peak[2.5] < peak[3.0]


def test_glitches_jump_near_zero_and_are_counted():
    demos = simulate_throws(6, subjects=3, glitches=0.03, dropped_frames=0.0, noise=0.0)
    assert sum(t.meta["glitches"] for t in demos) > 10
    for trajectory in demos:
        low = np.flatnonzero(trajectory["angle"] < 0.3)
        runs = np.count_nonzero(np.diff(low) > 1) + 1 if low.size else 0
        assert runs == trajectory.meta["glitches"]


def test_dropped_frames_leave_gaps_at_the_camera_rate():
    demos = simulate_throws(7, subjects=2, rate_hz=15, dropped_frames=0.2, glitches=0.0)
    steps = np.concatenate([np.diff(t["time"]) for t in demos])
    frame = 1 / 15
    assert np.allclose(steps / frame, np.round(steps / frame))
    assert np.mean(steps > 1.5 * frame) > 0.1


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [({"rate_hz": 60}, "15 to 30 Hz"), ({"noise": -1.0}, "noise"), ({"subjects": 0}, "no throws"),
     ({"distances": (15.0,)}, "beyond a human throw"), ({"distances": (30.0,)}, "outside the range 0.3 to 20 m"),
     ({"distances": (-1.0,)}, "outside the range"), ({"distances": (1e308,)}, "outside the range"),
     # nan passed every comparison: 2 samples a throw, or a non-finite angle blamed on a trajectory
     ({"dropped_frames": np.nan}, "dropped_frames nan: a probability per frame"),
     ({"glitches": np.nan}, "glitches nan: a probability per frame"),
     ({"noise": np.nan}, "noise nan: the angle noise is a standard deviation in rad"),
     ({"noise": 1e9}, r"noise 1e\+09: the angle noise is a standard deviation in rad, from 0 to 0.5"),
     ({"bias": np.nan}, "bias nan: out of range"),
     ({"distances": (1.0, 2.0, 1.0)}, "basket distances: 1 m is given twice"),
     ({"inconsistent_distance": 9.0}, r"inconsistent distance 9 m is not among the basket distances \(1, 1.5,")],
)
def test_bad_settings_are_input_errors(kwargs, message):
    with pytest.raises(InputError, match=message):
        simulate_throws(0, **kwargs)
