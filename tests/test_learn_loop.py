"""The learning loop against the real model and the real MuJoCo simulation (no stand-ins)."""

from __future__ import annotations

import numpy as np
import pytest

from rlff.dataset import Dataset, Trajectory
from rlff.errors import InputError
from rlff.learn import learn
from rlff.learn.attempt import Attempt
from rlff.learn.baselines import CmaSearch, SecantSearch
from rlff.learn.loop import _as_reported
from rlff.learn.method import Problem
from rlff.learn.strategies import SpeedCalibration, fastest_at_release, release_speed
from rlff.learn.windows import window_width

#: Distances the simulated humans aimed at; every throw falls short of its basket.
DEMO_DISTANCES = (1.0, 1.25, 1.5)


@pytest.fixture(scope="module")
def failed_demos() -> Dataset:
    from rlff.preprocess import Pipeline
    from rlff.synthetic.throws import simulate_throws

    raw = simulate_throws(3, subjects=3, distances=DEMO_DISTANCES, throws_per_distance=2, all_short=True)
    assert not any(t.meta["hit"] for t in raw)
    clean, _ = Pipeline.preset("thesis").run(raw)
    return clean


@pytest.mark.slow
@pytest.mark.parametrize("basket", [1.4, 1.9], ids=["inside", "outside"])
def test_calibrate_hits_from_all_short_demonstrations(failed_demos, basket):
    result = learn(failed_demos, basket, budget=8, feedback="distance", update="calibrate", seed=0)
    assert result.hit, result.misses
    # every miss is the landing's real distance from the centre, the hit's too (inside the window)
    assert [a.miss for a in result.history] == pytest.approx([a.landing - basket for a in result.history])
    assert 0 < abs(result.misses[-1]) < 0.5 * 0.35 - 0.033
    # the demonstrations' labels stop at 1.5 m: beyond them the query must leave their range
    if basket > max(DEMO_DISTANCES):
        assert result.history[-1].query > max(DEMO_DISTANCES) or result.attempts == 1


@pytest.mark.slow
def test_calibrate_hits_with_binary_feedback(failed_demos):
    result = learn(failed_demos, 1.9, budget=12, feedback="binary", update="calibrate", seed=0)
    assert result.hit, result.misses


@pytest.mark.slow
def test_a_resumed_run_continues_exactly_like_an_uninterrupted_one(failed_demos, tmp_path):
    log = tmp_path / "attempts.jsonl"
    kwargs = dict(feedback="binary", update="failure", seed=1)
    first = learn(failed_demos, 1.9, budget=2, log_path=log, **kwargs)
    assert first.attempts == 2 and not first.hit
    resumed = learn(failed_demos, 1.9, budget=3, log_path=log, **kwargs)
    straight = learn(failed_demos, 1.9, budget=3, **kwargs)
    assert resumed.resumed == 2 and resumed.attempts == 3
    assert [a.landing for a in resumed.history] == [a.landing for a in straight.history]
    np.testing.assert_array_equal(resumed.history[2].velocity, straight.history[2].velocity)


def test_a_resumed_run_tells_how_many_attempts_came_from_its_log_before_it_shows_them(failed_demos, tmp_path):
    # a caller that says which attempts come from the log (rlff learn's progress) had to read the
    # log itself to know, a second parse of it before the loop's own
    log = tmp_path / "attempts.jsonl"
    kwargs = dict(feedback="binary", update="failure", seed=1, log_path=log)
    told = []
    learn(failed_demos, 1.9, budget=1, resuming=lambda count: told.append(("resumed", count)), **kwargs)
    assert told == [("resumed", 0)]
    told.clear()
    result = learn(failed_demos, 1.9, budget=3, resuming=lambda count: told.append(("resumed", count)),
                   progress=lambda attempt: told.append(("attempt", attempt.index)), **kwargs)
    assert result.resumed == 1 and result.attempts == 3
    assert told == [("resumed", 1), ("attempt", 1), ("attempt", 2), ("attempt", 3)]


def test_binary_feedback_hides_landing_and_miss():
    attempt = Attempt(1, 2.0, 2.0, np.arange(3.0), np.ones(3), np.arange(3.0), False, 1.7, -0.3)
    assert np.isnan(_as_reported(attempt, "binary").miss)
    assert np.isnan(_as_reported(attempt, "binary").landing)
    assert _as_reported(attempt, "distance").miss == -0.3


def test_bad_method_feedback_and_basket_are_input_errors(failed_demos):
    with pytest.raises(InputError, match="hindsight.*needs distance feedback"):
        learn(failed_demos, 1.9, update="hindsight", feedback="binary")
    with pytest.raises(InputError, match="unknown update"):
        learn(failed_demos, 1.9, update="telepathy")
    with pytest.raises(InputError, match="out of reach"):
        learn(failed_demos, 6.0)
    # the hint names joint 3, whose throw needs the shoulder's columns, which these lack
    with pytest.raises(InputError, match=r"with joint_3 too: 4.59 m.*--joints joint_2,joint_3, which needs "
                                         r"shoulder and shoulder_velocity columns in the demonstrations"):
        learn(failed_demos, 3.0)


def test_a_basket_beyond_the_arm_s_reach_is_refused_with_the_reach_of_this_run_s_own_throws(failed_demos):
    # the arm's reach is at its best release; this run lets go where the demonstrations let go and
    # reaches less: the first refusal gives both, so the basket a user tries next is taken
    import re

    from rlff.learn.loop import learnable_basket
    from rlff.robot import load_robot, mapping_for
    from rlff.sim import Basket

    with pytest.raises(InputError) as refused:
        learn(failed_demos, 2.6)
    found = re.search(r"farthest basket with a 0\.35 m opening is at (\S+) m .*; this run's throws \(joint_2 let go "
                      r"where the demonstrations let go, -?\d\.\d\d to -?\d\.\d\d rad\) reach a basket at (\S+) m "
                      r"at most$", str(refused.value))
    assert found, refused.value
    best, own = float(found[1]), float(found[2])
    farthest = learnable_basket(failed_demos, mapping_for(load_robot("comau_smart5_six"), None), Basket(2.6))
    assert own == pytest.approx(farthest, abs=0.01) and own <= best < 2.6
    assert learn(failed_demos, own, budget=1, seed=0).attempts == 1


def test_a_basket_beyond_the_default_release_s_reach_is_thrown_at_letting_go_later(failed_demos, tmp_path):
    # these throws let go at the first quartile of the demonstrations' last angles reach 2.03 m;
    # a basket at 2.3 m was refused, though the arm reaches 2.44 m: the run lets go later, where
    # the last of the demonstrations let go (the release that reaches farthest), says so, and
    # keeps it in its log's header; so does a basket within 0.1 m of the default's edge
    from rlff.learn.carry import carried_offsets
    from rlff.learn.demos import RELEASE_QUANTILE, usable_demos
    from rlff.learn.log import read_log
    from rlff.learn.loop import RELEASE_ROOM, release_note, release_quantile, release_reaches
    from rlff.robot import load_robot, mapping_for
    from rlff.sim import Basket

    mapping = mapping_for(load_robot("comau_smart5_six"), None)
    usable, _ = usable_demos(failed_demos, mapping, 0.3)
    reaches = release_reaches(usable, mapping, Basket(2.3), 0.0)
    assert reaches[RELEASE_QUANTILE] < 2.1 and max(reaches.values()) == reaches[1.0] > 2.3
    edge = round(reaches[RELEASE_QUANTILE] - RELEASE_ROOM / 2, 2)  # within the default's reach, near its edge
    assert [release_quantile(usable, mapping, Basket(d)) for d in (2.3, edge, edge - RELEASE_ROOM)] == [
        1.0, 1.0, RELEASE_QUANTILE]
    last_angles = [t["angle"][-1] for t in usable]

    log = tmp_path / "far.jsonl"
    result = learn(failed_demos, 2.3, budget=6, seed=0, log_path=log)
    assert result.hit, result.misses
    assert any(note.startswith("the basket at 2.30 m is beyond the reach of throws let go where the demonstrations "
                               "let go (joint_2 at -0.57 rad") and "this run lets go later, where the last of the "
                               "demonstrations let go (-0.02 rad)" in note for note in result.notes), result.notes
    # the words the demo's report gives its learning runs are the run's own; none at the default
    assert release_note(usable, mapping, Basket(2.3)) in result.notes
    assert release_note(usable, mapping, Basket(1.9)) == ""
    assert release_note(usable, mapping, Basket(2.5)) == ""  # beyond every release: refused, no run
    for attempt in result.history:  # every throw lets go at the end of the later grid
        assert attempt.angle[-1] == pytest.approx(max(last_angles), abs=1e-6)
    header, _ = read_log(log)
    assert header["release_quantile"] == 1.0
    assert learn(failed_demos, 2.3, budget=6, seed=0, log_path=log).resumed == result.attempts
    near_edge = learn(failed_demos, edge, budget=1, seed=0)
    assert any(f"the basket at {edge:.2f} m is within 0.1 m of the edge of the reach of throws let go" in note
               for note in near_edge.notes), near_edge.notes

    near_log = tmp_path / "near.jsonl"
    near = learn(failed_demos, 1.9, budget=6, seed=0, log_path=near_log)
    assert "release_quantile" not in read_log(near_log)[0]  # the default writes none: older logs resume
    assert near.history[0].angle[-1] == pytest.approx(np.quantile(last_angles, RELEASE_QUANTILE), abs=1e-6)
    # a speed offset is relative to the start of throws let go at one release: not carried to another
    with pytest.raises(InputError, match=r"release_quantile = 0.25 \(the default\) there, 1.0 here\): the speed "
                                         r"offset is relative to the method's own start, which .* and where the "
                                         r"throws let go set"):
        carried_offsets([near_log], header)


def test_demonstrations_beyond_the_joint_range_are_refused():
    # joint_2 = -0.6 + 0.6 angle must stay below 2.71 rad: angle 6.5 rad is beyond it
    angle = np.linspace(4.0, 6.5, 20)
    demos = Dataset([
        Trajectory(f"d{i}", {"angle": angle, "distance": np.full(20, 1.0 + i),
                             "velocity": np.full(20, 5.0)}) for i in range(2)
    ])
    with pytest.raises(InputError, match="'d0' is beyond the robot's joint limits.*2 of 2 demonstrations are beyond them, which leaves"):
        learn(demos, 1.5)


def test_one_demonstration_beyond_the_joint_range_is_left_out_with_a_note(failed_demos):
    # one of the real MSR throws maps beyond joint_2's range with the whole arm; the others are
    # still a set to learn from, so that one is left out and named, not the run refused
    angle = np.linspace(4.0, 6.5, 20)
    odd = Trajectory("odd", {"time": np.linspace(0.0, 0.5, 20), "angle": angle, "distance": np.full(20, 1.25),
                             "velocity": np.full(20, 5.0)})
    result = learn(Dataset([*failed_demos, odd]), 1.4, budget=1, seed=0)
    assert result.attempts == 1
    count = len(failed_demos) + 1
    assert result.notes[0].startswith(f"left out 1 demonstration of {count} beyond the robot's joint "
                                      "limits: 'odd' (its path maps to joint_2 positions")
    assert result.notes[0].endswith(f"learning from the other {count - 1}")
    # the farthest basket learn takes is judged on the same demonstrations
    from rlff.learn.loop import learnable_basket
    from rlff.robot import load_robot, mapping_for
    from rlff.sim import Basket

    mapping = mapping_for(load_robot("comau_smart5_six"), None)
    assert learnable_basket(Dataset([*failed_demos, odd]), mapping, Basket(1.4)) == pytest.approx(
        learnable_basket(failed_demos, mapping, Basket(1.4)))


class TestSpeedCalibration:
    def test_a_short_landing_speeds_the_next_throw_up_and_two_landings_fix_the_law(self):
        calibration = SpeedCalibration(2.0, 0.14, reference=10.0)
        first, _ = calibration.best_speed()
        assert first == pytest.approx(10.0, rel=0.02)
        calibration.observe_landing(10.0, 1.6)
        second, _ = calibration.best_speed()
        # the prior's elasticity (1.6) gives the first step: (2.0 / 1.6) ** (1 / 1.6) = 1.15
        assert second == pytest.approx(10.0 * (2.0 / 1.6) ** (1 / 1.6), rel=0.05)
        # the true law: L = 1.6 (u / 10) ** 1.4; its second landing pins the elasticity down
        calibration.observe_landing(second, 1.6 * (second / 10.0) ** 1.4)
        third, p_hit = calibration.best_speed()
        assert third == pytest.approx(10.0 * (2.0 / 1.6) ** (1 / 1.4), rel=0.02)
        assert p_hit > 0.9

    def test_no_speed_beyond_the_robot_limit(self):
        calibration = SpeedCalibration(2.0, 0.14, reference=10.0, max_speed=10.5)
        calibration.observe_landing(10.0, 1.2)  # far short: the law wants much faster
        best, _ = calibration.best_speed()
        assert best <= 10.5


    def test_a_reference_far_below_the_limit_reaches_the_limit(self):
        # u0 = 0.3 rad/s with the limit at 11: the candidates and the law's offsets reach it
        calibration = SpeedCalibration(1.9, 0.14, reference=0.3, max_speed=11.0)
        calibration.observe_landing(0.3 * 20.0, 1.9 * 0.6)  # short at 20 u0: the hit is faster
        best, _ = calibration.best_speed()
        assert 0.3 * 20.0 < best <= 11.0

    def test_a_ball_that_came_down_behind_the_base_speeds_the_next_throw_up(self):
        calibration = SpeedCalibration(1.9, 0.14, reference=0.3, max_speed=11.0)
        first, _ = calibration.best_speed()
        calibration.observe_landing(first, -0.46)  # it hardly moved at its release
        second, _ = calibration.best_speed()
        # no farther than 0.14 m at the first speed: a law of slope 1.6 wants (1.9 / 0.14)^(1 / 1.6)
        assert second > 3.0 * first
        calibration.observe_landing(second, float("nan"))  # no landing: nothing learned
        assert calibration.best_speed()[0] == pytest.approx(second)


def make_problem(demos: Dataset, feedback: str) -> Problem:
    from rlff.learn.demos import angle_grid, learning_demos

    demos = learning_demos(demos)
    return Problem(demos=demos, target=1.9, feedback=feedback, tolerance=0.14,
                   angles=angle_grid(demos), components=2, seed=4)


def fake_attempt(index: int, proposal, landing: float) -> Attempt:
    return Attempt(index, 1.9, proposal.query, proposal.angle, proposal.velocity,
                   np.arange(proposal.angle.size, dtype=float), False, landing, landing - 1.9)


def test_secant_takes_the_ballistic_first_step_then_the_secant(failed_demos):
    secant = SecantSearch(make_problem(failed_demos, "distance"))
    first = secant.propose([])
    assert first.info["factor"] == 1.0
    history = [fake_attempt(1, first, 1.6)]
    second = secant.propose(history)
    assert second.info["factor"] == pytest.approx(np.sqrt(1.9 / 1.6))
    history.append(fake_attempt(2, second, 1.8))
    third = secant.propose(history)
    s1, s2 = 1.0, second.info["factor"]
    assert third.info["factor"] == pytest.approx(s2 - (-0.1) * (s2 - s1) / (-0.1 - (-0.3)))
    np.testing.assert_allclose(third.velocity, first.velocity * third.info["factor"])


def test_secant_whose_start_is_beyond_the_speed_limit_steps_from_the_throw_at_the_limit(failed_demos):
    # the demo's learning basket at 2.1 m: the GMR mean's speed lies beyond the joint's limit, the
    # throw at the limit lands long; the secant had stepped from its unthrown start and asked for
    # the limit again and again (+0.20 m three times, then the run stopped)
    from dataclasses import replace

    fastest = float(np.max(np.abs(SecantSearch(make_problem(failed_demos, "distance")).mean)))
    secant = SecantSearch(replace(make_problem(failed_demos, "distance"), max_speed=0.8 * fastest))
    first = secant.propose([])
    assert first.info["factor"] == pytest.approx(0.8)
    assert np.max(np.abs(first.velocity)) == pytest.approx(0.8 * fastest)
    second = secant.propose([fake_attempt(1, first, 2.1)])  # 0.2 m long
    assert second.info["factor"] == pytest.approx(0.8 * np.sqrt(1.9 / 2.1))
    assert np.max(np.abs(second.velocity)) < np.max(np.abs(first.velocity))


@pytest.mark.parametrize("name", ["gp-bo", "imitation", "random"])
def test_a_baseline_s_throw_beyond_the_speed_limit_logs_the_factor_thrown(failed_demos, name):
    # thrown at the limit, logged at the start asked for: GP-BO fitted its first throw where it was
    # not thrown, and a hit there carried an offset beyond the limit into the next basket
    from dataclasses import replace

    from rlff.learn.baselines import BASELINES

    fastest = float(np.max(np.abs(SecantSearch(make_problem(failed_demos, "distance")).mean)))
    method = BASELINES[name](replace(make_problem(failed_demos, "distance"), max_speed=0.8 * fastest))
    first = method.propose([])
    assert np.max(np.abs(first.velocity)) == pytest.approx(0.8 * fastest)
    assert first.info["log_factor"] <= round(np.log(0.8), 4) + 1e-12


def test_cma_rebuilt_from_the_history_proposes_what_the_original_would(failed_demos):
    problem = make_problem(failed_demos, "distance")
    original = CmaSearch(problem)
    history: list[Attempt] = []
    for index in range(1, 9):  # more than one generation (6 candidates each)
        proposal = original.propose(history)
        history.append(fake_attempt(index, proposal, 1.5 + 0.05 * index))
    rebuilt = CmaSearch(problem)
    assert rebuilt.propose(history).info["x"] == original.propose(history).info["x"]


def test_uncleaned_demonstrations_are_refused_naming_the_throw():
    angle = np.array([0.8, 0.7, 0.9, 1.2, 1.6, 1.8])  # a wind-up: the angle goes back first
    demos = Dataset([
        Trajectory(f"raw{i}", {"angle": angle, "distance": np.full(6, 1.0 + i),
                               "velocity": np.full(6, 5.0)}) for i in range(2)
    ])
    with pytest.raises(InputError, match="'raw0' is not one throw up to its release.*preset thesis"):
        learn(demos, 1.5)
    # it ended "(rlff data preprocess --preset thesis, or --preset)"
    with pytest.raises(InputError, match=r"\(rlff data preprocess --preset thesis, or --config STEPS\.toml; in Python "
                                         r"rlff\.preprocess\.Pipeline\.preset\('thesis'\)\.run\(demos\)\)$"):
        learn(demos, 1.5)


@pytest.fixture(scope="module")
def wide_demos() -> Dataset:
    """The demo's setting: throws at 1 to 4 m, most of them beyond the robot's reach (~2.2 m)."""
    from rlff.learn.benchmark import demonstrations

    return demonstrations(0, "wide")


def test_fastest_at_release_caps_the_path_at_its_release_speed():
    angles = np.linspace(0.0, 1.0, 20)  # the release part: the last 2 samples
    velocity = np.r_[np.linspace(1.0, 12.0, 18), 9.0, 9.5]
    capped = fastest_at_release(angles, velocity)
    np.testing.assert_allclose(capped, np.minimum(velocity, 9.25))
    assert release_speed(angles, capped) == pytest.approx((9.0 + 9.25) / 2)
    np.testing.assert_allclose(fastest_at_release(angles, -velocity), -capped)


@pytest.mark.slow
@pytest.mark.parametrize("feedback", ["binary", "distance"])
def test_calibrate_hits_from_demonstrations_mostly_beyond_the_reach(wide_demos, feedback):
    # human landings up to 4 m, the robot's at most ~2.3 m: the DMM's donut has a slow and a
    # fast side at 1.75 m, and the throw must not run faster before its release than at it
    result = learn(wide_demos, 1.75, budget=4, feedback=feedback, update="calibrate", seed=0)
    assert result.hit, result.misses
    assert all(a.clipped == 0 for a in result.history)
    first_gmr = learn(wide_demos, 1.75, budget=1, feedback="distance", update="imitation", seed=0)
    if feedback == "distance":
        # not the donut's fast side: the first throw lands as near as the GMR mean's, or well
        # inside the opening (both may be a centimetre from the centre)
        assert abs(result.history[0].miss) <= max(abs(first_gmr.history[0].miss), 0.35 / 4)


@pytest.mark.slow
def test_until_centred_refines_past_rim_hits_until_one_lands_near_the_centre(failed_demos):
    """With a quarter of the half-opening as the centre window, the binary run keeps throwing
    after hits near the rim (the method is told they missed) until one lands within it."""
    window = 0.25 * 0.35 / 2
    plain = learn(failed_demos, 1.4, budget=20, feedback="binary", update="calibrate", seed=0)
    centred = learn(failed_demos, 1.4, budget=20, feedback="binary", update="calibrate", seed=0,
                    until="centred", centre_share=0.25)
    assert plain.hit and plain.until == "hit"
    assert centred.until == "centred" and centred.centre_window == pytest.approx(window)
    assert centred.hit and centred.centred, centred.misses
    assert abs(centred.misses[-1]) <= window
    # every earlier attempt was a miss or a hit outside the window: the run went on after them
    assert all(not a.hit or abs(a.miss) > window for a in centred.history[:-1])
    # the search steps by the narrower window: every throw's log speed factor is a whole
    # number of centre windows (2 x window / 1.4 m over the elasticity 1.6) from the first's
    # (where the demonstrations' landings point)
    factors = np.array([a.info["log_factor"] for a in centred.history])
    steps = (factors - factors[0]) / window_width(1.4, window)
    np.testing.assert_allclose(steps, np.round(steps), atol=2e-3)
    with pytest.raises(InputError, match="until"):
        learn(failed_demos, 1.4, until="perfect")
    with pytest.raises(InputError, match=r"centre_share must be in \(0, 1\]"):
        learn(failed_demos, 1.4, until="centred", centre_share=0.0)


def test_an_attempt_the_robot_saturated_can_still_be_planned_from_its_log(tmp_path):
    # a proposal 20 % beyond the joint's limit on its last samples: the robot saturates them,
    # and the attempt logs the clipped velocities; re-planning it (rlff learn --out, robot
    # export of the log) gives the throw that was executed instead of refusing its time column
    from rlff.learn.loop import _execute, _simulator
    from rlff.learn.method import Proposal
    from rlff.learn.replay import plan_attempt
    from rlff.robot import load_robot, mapping_for
    from rlff.sim import Basket

    robot = load_robot("comau_smart5_six")
    mapping = mapping_for(robot, None)
    limit = mapping.max_human_speeds()["velocity"]
    angle = np.linspace(0.6, 1.8, 60)
    velocity = limit * np.minimum(1.2, np.linspace(0.3, 1.5, 60))
    basket = Basket(1.5, rim_height=0.3, opening=0.35)
    attempt = _execute(Proposal(angle, velocity), 1, basket, mapping, _simulator(robot, basket, 0.0), 0.0)
    assert attempt.clipped >= 10
    assert np.max(attempt.velocity) == pytest.approx(limit)
    executed = _execute(Proposal(angle, np.minimum(velocity, limit)), 1, basket, mapping,
                        _simulator(robot, basket, 0.0), 0.0)
    replanned = plan_attempt(attempt, mapping).trajectory
    assert replanned.release_time is not None
    release = np.searchsorted(replanned.time, replanned.release_time)
    driven = robot.index(mapping.joint)
    assert replanned.velocities[release, driven] == pytest.approx(mapping.velocity_scale * limit)
    assert attempt.landing == pytest.approx(executed.landing)  # saturating is asking for the limit


def test_cma_takes_the_largest_seed(failed_demos):
    from dataclasses import replace

    problem = replace(make_problem(failed_demos, "distance"), seed=2**32 - 1)
    assert CmaSearch(problem).propose([]).velocity.size  # numpy.random.seed refused 2**32


def test_a_throw_whose_run_up_would_pass_a_position_limit_is_slowed_to_the_fastest_that_fits(tmp_path):
    """A short swing to a fast release needs a wind-up; with joint_2's lower limit just behind the
    start the asked throw cannot be made, and the loop ended the run with the planner's error (a
    tester's UR file). It now throws the fastest of that shape that fits, counted as clipped."""
    import re
    from importlib import resources

    from rlff.learn.loop import _plan
    from rlff.robot import load_robot, mapping_for
    from rlff.robot.plan import plan_path
    from rlff.timing import time_along_path
    from rlff.trajectory.check import MotionLimitError, check_trajectory

    text = (resources.files("rlff") / "robots" / "comau_smart5_six.toml").read_text(encoding="utf-8")
    tight = tmp_path / "tight.toml"  # the start maps to joint_2 = -1.65 + 0.71 * 0.4 = -1.366 rad
    tight.write_text(re.sub(r'(name = "joint_2"\nlower = )-1\.48', r"\g<1>-1.40", text))
    robot = load_robot(tight)
    mapping = mapping_for(robot, None)
    angle = np.linspace(0.4, 0.7, 30)
    velocity = np.linspace(2.0, 10.0, 30)  # released at 2.5 rad/s after a 0.21 rad swing
    path = {"angle": angle, "velocity": velocity, "time": time_along_path(angle, velocity)}
    with pytest.raises(MotionLimitError, match="beyond its lower limit -1.4 rad"):
        plan_path(mapping, path, clip=True)
    points, trajectory, clipped = _plan(mapping, path, 0.0)
    check_trajectory(trajectory, robot.joints)
    assert trajectory.positions[:, 1].min() >= -1.40
    (change,) = clipped.changes
    assert (change.point, change.joint, change.quantity, change.before) == (29, "joint_2", "velocity", 2.5)
    assert 0.5 * 2.5 < change.after < 2.5 and points.velocities[-1, 1] == change.after
    faster = {**path, "velocity": velocity * change.after / 2.5 * 1.01}  # the largest that fits, to 1 %
    faster["time"] = time_along_path(angle, faster["velocity"])
    with pytest.raises(MotionLimitError):
        plan_path(mapping, faster, clip=True)
