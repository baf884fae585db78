"""Issue 16's learning goals, measured as the demo and a user would run them (real model, real MuJoCo).

- ``rlff demo``'s whole-arm part: every demonstrated (1-4 m) and unseen (1.25-4.5 m) basket, at
  bearings 0-90 deg, hit within 10 attempts of the default method with binary feedback. The demo
  runs seed 0; this test runs seed 5 (the robot file's whole-arm mapping was tuned on seeds 0, 2
  and 3; nothing on 5).
- The MSR Action3D high throws (real shoulders and elbows, captured whole-arm): hits at 2.0, 3.0
  and 4.0 m within 10 attempts each, with joints 2 and 3 (and with joint 5 too at 4 m).
"""

from __future__ import annotations

import pytest

from rlff.learn import learn
from rlff.sim.gap import parse_gap

pytestmark = [pytest.mark.slow, pytest.mark.integration]


def test_every_demo_basket_around_the_robot_is_hit_within_10_attempts(tmp_path):
    from rlff.synthetic.throws import THESIS_DISTANCES
    from rlff.whole_arm_demo import BUDGET, baskets, run_whole_arm

    whole = run_whole_arm(tmp_path, baskets(THESIS_DISTANCES), seed=5)
    distances = {run.distance for run in whole.runs}
    assert {1.0, 2.0, 3.0, 4.0} <= distances and {1.25, 4.5} <= distances
    assert {run.bearing for run in whole.runs} >= {0.0, 30.0, 60.0, 90.0}
    missed = [(run.distance, run.bearing, run.refused or run.misses) for run in whole.runs if not run.hit]
    assert not missed
    assert max(run.attempts for run in whole.runs) <= BUDGET == 10


@pytest.mark.parametrize("seed, distance", [(6, 4.0), (5, 4.25)])
def test_an_arm_slower_than_its_robot_file_still_hits_at_the_edge_of_the_reach(tmp_path, seed, distance):
    # joints 2 and 3 reach these baskets only near their speed limits: an arm at 95 % of the
    # commanded speed fell short at the limit and missed 10 times until joint 5 joined wherever
    # joints 2 and 3 lack the speed headroom (whole_arm_demo.SPEED_HEADROOM)
    from rlff.whole_arm_demo import ARM_JOINTS, BUDGET, run_whole_arm

    run, = run_whole_arm(tmp_path, [(distance, 0.0)], seed=seed, gap=parse_gap("speed:0.95")).runs
    assert run.joints != ARM_JOINTS
    assert run.hit, run.misses
    assert run.attempts <= BUDGET


def test_the_first_whole_arm_throw_is_where_the_kinematics_aim_not_at_the_speed_limit(tmp_path):
    # the people of seed 1 at 4-4.5 m: joint 5 joins and the speed limit lies 1-3 windows above
    # the aim; with the one-joint prior's width (0.3) about the aim its tail beyond the limit
    # outweighed the aim's window, and the first throw went to the limit, up to 0.8 m long
    from rlff.whole_arm_demo import run_whole_arm

    whole = run_whole_arm(tmp_path, [(4.0, 0.0), (4.25, 30.0), (4.5, 60.0)], seed=1)
    first = [whole.learned[(run.distance, run.bearing)].history[0] for run in whole.runs]
    assert [attempt.info["log_factor"] for attempt in first] == [0.0, 0.0, 0.0]
    assert all(abs(attempt.miss) < 0.2 for attempt in first), [attempt.miss for attempt in first]


def test_each_whole_arm_basket_starts_where_the_one_before_it_hit(tmp_path):
    # an arm 5 % slower than its robot file: the hit lies above the aim, and the next basket (the
    # nearest in distance, the same joints) starts from the offset the last hit found
    from rlff.whole_arm_demo import run_whole_arm

    whole = run_whole_arm(tmp_path, [(4.0, 0.0), (4.25, 30.0)], seed=1, gap=parse_gap("speed:0.95"))
    first, second = (whole.learned[(run.distance, run.bearing)] for run in whole.runs)
    assert first.hit and first.history[-1].info["log_factor"] > 0  # above the aim: the arm is slower
    assert second.notes[0].startswith(f"carried from {tmp_path / 'attempts' / 'whole-arm' / '4m-0deg.jsonl'}")
    assert second.history[0].info["log_factor"] == pytest.approx(first.history[-1].info["log_factor"], abs=2e-4)
    assert second.hit and second.attempts == 1


@pytest.mark.parametrize("basket, joints", [
    (2.0, ("joint_2", "joint_3")),
    (3.0, ("joint_2", "joint_3")),
    (4.0, ("joint_2", "joint_3")),
    (4.0, ("joint_2", "joint_3", "joint_5")),
])
def test_the_msr_throws_teach_hits_at_2_3_and_4_m(msr_throws, basket, joints):
    result = learn(msr_throws, basket, budget=10, joints=joints, feedback="binary", seed=7)
    assert result.hit, result.misses
    assert result.attempts <= 10


@pytest.mark.parametrize("basket", [2.0, 3.0, 4.0])
def test_the_first_msr_throw_lands_where_the_kinematics_aim_it(msr_throws, basket):
    # the aim is taken on the throw the loop makes (the DMM's shape), not on the GMR mean's,
    # whose shoulder moves differently: that one sent the 2 m throw to 2.21 m
    result = learn(msr_throws, basket, budget=1, joints=("joint_2", "joint_3"), feedback="binary", seed=7)
    first = result.history[0]
    assert first.info["log_factor"] == 0.0  # the aim's own window
    assert abs(first.miss) < 0.05, first.miss
