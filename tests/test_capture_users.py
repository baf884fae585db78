"""Several tracked users: keep the thrower, join them when re-acquired, drop a reflection."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import bagfactory as bf  # noqa: E402
from rlff.capture.angles import align_arm  # noqa: E402
from rlff.capture.segment import find_throws  # noqa: E402
from rlff.capture.skeleton import ArmTrack, JointTrack, Recording  # noqa: E402
from rlff.capture.users import keep_consistent_user  # noqa: E402


def _arm(user: str, t: np.ndarray, positions: tuple[np.ndarray, ...]) -> ArmTrack:
    return ArmTrack(user, "right", *(JointTrack(name, t, p) for name, p in zip(("s", "e", "h"), positions, strict=True)))


def test_a_person_lost_and_found_again_under_a_new_id_is_joined_and_a_reflection_dropped():
    simulation = bf.standard_simulation(seed=9, n_throws=4, second_user=False)
    t = simulation.frame_times
    shoulder, elbow, hand = simulation.arm_positions(simulation.angle(t))
    # tracking lost for 0.6 s between the 2nd and 3rd throw; the tracker calls the person user 3 after
    gap_start = simulation.ends[1] + 0.3
    first, second = t < gap_start, t > gap_start + 0.6
    reflection = (t > 2.0) & (t < 2.6)
    mirror = np.array([1.0, -1.0, 1.0])
    recording = Recording(
        "session.bag",
        [
            _arm("1", t[first], (shoulder[first], elbow[first], hand[first])),
            _arm("2", t[reflection], tuple(p[reflection] * mirror + [1.5, 0.3, 0.0] for p in (shoulder, elbow, hand))),
            _arm("3", t[second], (shoulder[second], elbow[second], hand[second])),
        ],
        bf.UP,
    )
    arms, notes, _ = keep_consistent_user(recording)
    kept, joined = ("3", "1") if second.sum() > first.sum() else ("1", "3")  # the longer track is kept
    assert len(arms) == 1 and arms[0].user == kept
    assert len(arms[0].elbow) == first.sum() + second.sum()
    assert any(f"user {joined} is user {kept} found again" in note for note in notes)
    assert any("dropped tracked user 2" in note and "1 appearances" in note for note in notes)
    motion = align_arm(arms[0])
    assert len(motion.runs()) == 2  # the 0.6 s without tracking (over 0.5 s, and 18 x the spacing) is not bridged
    ((lost_from, lost_to),) = motion.lost_spans()
    assert lost_from < gap_start < gap_start + 0.6 < lost_to
    cuts, _ = find_throws(motion)
    assert len(cuts) == 4


def test_a_single_user_is_kept_as_it_is():
    t = np.arange(10) / 30.0
    arm = _arm("1", t, (np.zeros((10, 3)), np.ones((10, 3)), np.full((10, 3), 2.0)))
    recording = Recording("x.bag", [arm], bf.UP)
    assert keep_consistent_user(recording) == ([arm], [], [])
