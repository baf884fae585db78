"""The transport-independent FollowJointTrajectory controller: goals, approaches, cancels, preemptions.

The arm is ticked at 100 Hz like ``rlff robot serve``; velocities and accelerations are the
first and second divided differences of the ticked positions. For the arm's C2 motion (quintic
pieces) a first divided difference is the velocity and a second one (times 2) the acceleration
at some instant between its ticks, so neither can exceed a limit unless the motion itself does;
the one allowance, DISCRETISATION, is the motion check's relative slack for rounding.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from rlff.errors import InputError
from rlff.robot import RobotMapping, load_robot
from rlff.robot.controller import (
    GoalRejected,
    ResultCode,
    TrajectoryController,
    check_rate,
    release_time,
)
from rlff.robot.plan import load_for_robot
from rlff.trajectory.check import LIMIT_SLACK
from rlff.trajectory.joint import JointTrajectory
from rlff.trajectory.planner import plan_stop, plan_transition

TICK = 0.01  # s, the server's default rate
DISCRETISATION = 1 + LIMIT_SLACK
ROBOT = load_robot()
NAMES = ROBOT.joint_names
VMAX = np.array([ROBOT.joint(n).max_velocity for n in NAMES])
AMAX = np.array([ROBOT.joint(n).max_acceleration for n in NAMES])
JMAX = np.array([ROBOT.joint(n).max_jerk for n in NAMES])
DRIVEN = 1  # joint_2


@pytest.fixture
def controller() -> TrajectoryController:
    return TrajectoryController(ROBOT, RobotMapping.for_robot(ROBOT).pose(0.0))


def _run(controller: TrajectoryController, start: float, stop: float, events=None):
    """Tick from ``start`` to ``stop``: (times (N,), positions (N, J), outcomes). ``events`` maps a
    tick index to a call made before that tick."""
    times = start + TICK * np.arange(round((stop - start) / TICK) + 1)
    positions, outcomes = [], []
    for index, now in enumerate(times):
        if events and index in events:
            outcomes += events[index](now)
        state, ended = controller.update(now)
        positions.append(state.positions)
        outcomes += ended
    return times, np.array(positions), outcomes


def _peaks(times: np.ndarray, positions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Largest |velocity| and |acceleration| (J,) of the ticked motion, from divided differences."""
    velocity = np.diff(positions, axis=0) / np.diff(times)[:, None]
    acceleration = 2 * np.diff(velocity, axis=0) / (times[2:] - times[:-2])[:, None]
    return np.abs(velocity).max(axis=0), np.abs(acceleration).max(axis=0)


def _within_limits(times: np.ndarray, positions: np.ndarray) -> None:
    velocity, acceleration = _peaks(times, positions)
    assert np.all(velocity <= VMAX * DISCRETISATION), (velocity, VMAX)
    assert np.all(acceleration <= AMAX * DISCRETISATION), (acceleration, AMAX)


def _goal(time, positions, velocities=None) -> JointTrajectory:
    positions = np.atleast_2d(positions)
    velocities = np.zeros_like(positions) if velocities is None else np.atleast_2d(velocities)
    return JointTrajectory(NAMES, time, positions, velocities)


def _swing(here: np.ndarray, to: float, duration: float, points: int = 40) -> JointTrajectory:
    """joint_2 from its pose to ``to`` (rad) in ``duration`` s along a cosine, at rest at both ends."""
    s = np.linspace(0.0, 1.0, points)
    positions = np.tile(here, (points, 1))
    velocities = np.zeros_like(positions)
    positions[:, DRIVEN] = here[DRIVEN] + (to - here[DRIVEN]) * (1 - np.cos(np.pi * s)) / 2
    velocities[:, DRIVEN] = (to - here[DRIVEN]) * np.pi * np.sin(np.pi * s) / (2 * duration)
    return JointTrajectory(NAMES, s * duration, positions, velocities)


def test_a_first_point_at_zero_away_from_the_arm_is_refused_and_nothing_moves(controller):
    here = controller.state(0.0).positions
    away = here.copy()
    away[DRIVEN] -= 0.613
    with pytest.raises(GoalRejected) as refused:
        controller.submit("g", _goal([0.0, 1.0], [away, away]), now=0.0)
    assert refused.value.code == ResultCode.PATH_TOLERANCE_VIOLATED
    message = str(refused.value)
    assert "joint_2 position -0.613 rad, the arm's 0 rad (0.613 rad apart, tolerance 0.001 rad)" in message
    times, positions, outcomes = _run(controller, 0.0, 1.0)
    assert np.ptp(positions, axis=0).max() == 0.0 and outcomes == []


def test_a_one_point_goal_1_rad_away_is_approached_within_the_limits(controller):
    here = controller.state(0.0).positions
    target = here.copy()
    target[DRIVEN] += 1.0
    executed, preempted = controller.submit("g", _goal([0.01], target), now=0.0)
    assert preempted == []
    # the fastest motion within the limits: no less than 1 rad at full speed, plus speeding up
    assert executed.duration > 1.0 / VMAX[DRIVEN] + VMAX[DRIVEN] / AMAX[DRIVEN] * 0.9
    times, positions, outcomes = _run(controller, 0.0, executed.duration + 0.5)
    _within_limits(times, positions)
    np.testing.assert_allclose(positions[-1], target, atol=1e-9)
    assert [(o.goal, o.status, o.code) for o in outcomes] == [("g", "succeeded", ResultCode.SUCCESSFUL)]


def test_an_arm_at_rest_waits_to_reach_the_first_point_at_its_time(controller):
    here = controller.state(0.0).positions
    target = here.copy()
    target[DRIVEN] += 0.1
    executed, _ = controller.submit("g", _goal([3.0], target), now=0.0)
    assert executed.duration < 3.0  # the limits allow it sooner
    np.testing.assert_allclose(controller.state(2.99 - executed.duration).positions, here)
    np.testing.assert_allclose(controller.state(3.0).positions, target, atol=1e-12)


def test_a_first_point_within_the_tolerance_becomes_the_arm_state(controller):
    here = controller.state(0.0).positions
    near = here.copy()
    near[DRIVEN] += 0.0008
    goal = _swing(near, near[DRIVEN] + 0.5, 1.5)
    executed, _ = controller.submit("g", goal, now=0.0)
    np.testing.assert_array_equal(executed.positions[0], here)  # no step of 0.8 mrad in one tick
    times, positions, _ = _run(controller, 0.0, 2.0)
    _within_limits(times, positions)
    np.testing.assert_allclose(positions[-1], goal.positions[-1])


def test_cancel_brakes_within_the_limits_and_reports_once_at_rest(controller):
    here = controller.state(0.0).positions
    executed, _ = controller.submit("g", _swing(here, 2.0, 1.6), now=0.0)
    cancel = {60: lambda now: controller.cancel("g", now)}  # 0.6 s in, near full speed
    times, positions, outcomes = _run(controller, 0.0, 2.0, cancel)
    _within_limits(times, positions)
    moving = np.abs(np.diff(positions[:, DRIVEN])) / TICK
    assert moving[58] > 1.5  # it was moving fast when cancelled
    [outcome] = outcomes
    assert (outcome.goal, outcome.status) == ("g", "cancelled")
    assert "cancelled after 0.600 s of 1.600 s; braked to rest from" in outcome.text
    braked = float(outcome.text.split(" in ")[-1].removesuffix(" s"))
    assert 0.1 < braked < 1.0
    after = times > 0.6 + braked + TICK
    assert np.ptp(positions[after], axis=0).max() == 0.0  # standing still, short of the end
    assert positions[-1, DRIVEN] < executed.positions[-1, DRIVEN] - 0.2
    assert controller.active_goal is None


def test_the_brake_is_jerk_limited(controller):
    here = controller.state(0.0).positions
    controller.submit("g", _swing(here, 2.0, 1.6), now=0.0)
    _run(controller, 0.0, 0.6)
    controller.cancel("g", 0.6)
    # the arm's own jerk, from its accelerations every ms while it brakes
    accelerations, outcomes = [], []
    for now in 0.6 + 0.001 * np.arange(1, 1001):
        state, ended = controller.update(now)
        accelerations.append(state.accelerations)
        outcomes += ended
    assert [outcome.status for outcome in outcomes] == ["cancelled"]
    jerk = np.abs(np.diff(accelerations, axis=0)) / 0.001
    assert jerk[:, DRIVEN].max() > 0.9 * JMAX[DRIVEN]  # braking hard
    assert np.all(jerk.max(axis=0) <= JMAX * DISCRETISATION)


def test_a_newer_goal_preempts_from_the_moving_arm(controller):
    here = controller.state(0.0).positions
    controller.submit("old", _swing(here, 2.0, 1.6), now=0.0)
    back = here.copy()
    back[DRIVEN] = -0.3
    newer = {60: lambda now: controller.submit("new", _goal([0.5], back), now)[1]}
    times, positions, outcomes = _run(controller, 0.0, 4.0, newer)
    _within_limits(times, positions)
    assert [(o.goal, o.status) for o in outcomes] == [("old", "preempted"), ("new", "succeeded")]
    assert outcomes[0].text.startswith("preempted by a newer goal after 0.600 s of 1.600 s")
    assert outcomes[0].code == ResultCode.SUCCESSFUL  # FollowJointTrajectory has no preemption code
    np.testing.assert_allclose(positions[-1], back, atol=1e-9)


def test_a_goal_from_zero_while_the_arm_moves_is_refused_and_the_old_one_goes_on(controller):
    here = controller.state(0.0).positions
    old = _swing(here, 1.0, 1.6)
    controller.submit("old", old, now=0.0)
    state = controller.state(0.8)
    with pytest.raises(GoalRejected, match="joint_2 velocity 0 rad/s, the arm's 0.98") as refused:
        controller.submit("new", _goal([0.0, 1.0], [state.positions, state.positions]), now=0.8)
    assert refused.value.code == ResultCode.PATH_TOLERANCE_VIOLATED
    assert controller.active_goal == "old"
    _, positions, outcomes = _run(controller, 0.8, 2.0)
    np.testing.assert_allclose(positions[-1], old.positions[-1])
    assert [(o.goal, o.status) for o in outcomes] == [("old", "succeeded")]


def test_a_cancel_during_a_brake_is_ignored_and_a_goal_takes_the_brake_over(controller):
    here = controller.state(0.0).positions
    controller.submit("g", _swing(here, 2.0, 1.6), now=0.0)
    _run(controller, 0.0, 0.6)
    assert controller.cancel("g", 0.6) == []
    assert controller.cancel("g", 0.61) == []  # already braking
    target = here.copy()
    target[DRIVEN] = 0.2
    _, ended = controller.submit("h", _goal([0.1], target), now=0.65)
    assert [(o.goal, o.status) for o in ended] == [("g", "cancelled")]
    assert ended[0].text.endswith("the brake was taken over by a newer goal")


def _sent_from(here: np.ndarray, tmp_path) -> JointTrajectory:
    """A goal as ``rlff robot send`` makes it: a throw planned from the arm's pose read at rest
    (``here``), its first point at time_from_start 0 that pose."""
    path = tmp_path / "throw.csv"
    mapping = RobotMapping.for_robot(ROBOT)
    pd.DataFrame({"angle": (np.linspace(-0.8, 1.6, 30) - mapping.angle_offset) / mapping.angle_scale,
                  "velocity": (0.2 + 2.0 * np.sin(np.linspace(0, np.pi, 30))) / mapping.velocity_scale}).to_csv(
                      path, index=False)
    return load_for_robot(path, ROBOT, 0.01, start=here)[1].trajectory


def test_a_goal_from_another_pose_to_an_idle_arm_is_not_told_the_arm_moved(controller, tmp_path):
    # it had said "the arm has moved since; send it again" as a fact, to an arm that never moved,
    # where sending it again gets the same refusal
    away = controller.state(0.0).positions.copy()
    away[1] += 0.3
    with pytest.raises(GoalRejected) as wrong:
        controller.submit("wrong", _sent_from(away, tmp_path), now=0.0)
    assert "misses only if the arm moved since: read it again and send; otherwise the goal's first point is not " \
        "where the arm is)" in str(wrong.value)
    assert "the arm has moved since" not in str(wrong.value)


def test_a_send_overlapping_another_is_told_to_wait_for_the_arm_to_rest(controller, tmp_path):
    """Two overlapping `rlff robot send` to one server, each planned from the pose read at rest: the
    second was refused with "start the goal later than 0 s", which a send user cannot do. It is
    told the other goal moved the arm, and to wait until the arm rests; a raw goal's hint stays."""
    here = controller.state(0.0).positions
    first, second = _sent_from(here, tmp_path), _sent_from(here, tmp_path)
    controller.submit("first", first, now=0.0, start=0.0)
    with pytest.raises(GoalRejected) as refused:
        controller.submit("second", second, now=0.8, start=0.8)
    assert refused.value.code == ResultCode.PATH_TOLERANCE_VIOLATED
    message = str(refused.value)
    assert message.startswith("the goal's first point (time_from_start 0) is not the arm's state: joint_2 ")
    assert (": another goal is under way, the arm moving at " in message and message.endswith(
        " rad/s, and moved the arm after this goal's start was read; wait until the arm rests and send the goal "
        "again from its state then (rlff robot send reads it anew), or, to preempt it, start the goal later "
        "than 0 s to have the controller approach its first point"))
    assert controller.active_goal == "first"
    _, _, outcomes = _run(controller, 0.8, 0.8 + first.duration)
    assert [(o.goal, o.status) for o in outcomes] == [("first", "succeeded")]
    with pytest.raises(GoalRejected) as late:  # the arm at rest where the first goal left it, not where read
        controller.submit("second", second, now=0.8 + first.duration)
    assert str(late.value).endswith(
        "; start the goal later than 0 s to have the controller approach its first point (a goal planned from the "
        "arm's state read before, as rlff robot send plans it, misses only if the arm moved since: read it again and "
        "send; otherwise the goal's first point is not where the arm is)")

    rest = controller.state(5.0).positions  # read anew: a goal from there is taken
    controller.submit("second", _goal([0.0, 1.0], [rest, rest]), now=5.0)


def test_the_release_of_a_planned_throw_survives_the_goal_and_its_approach(controller, tmp_path):
    here = controller.state(0.0).positions
    path = tmp_path / "throw.csv"
    mapping = RobotMapping.for_robot(ROBOT)
    q = np.linspace(-0.8, 1.6, 30)
    speed = 0.2 + 2.0 * np.sin(np.linspace(0, np.pi, 30))
    pd.DataFrame({"angle": (q - mapping.angle_offset) / mapping.angle_scale,
                  "velocity": speed / mapping.velocity_scale}).to_csv(path, index=False)
    planned = load_for_robot(path, ROBOT, 0.01, start=here)[1].trajectory
    assert planned.release_time is not None
    # what a FollowJointTrajectory goal carries: the points, no release; here starting 0.5 s later
    sent = JointTrajectory(NAMES, planned.time + 0.5, planned.positions, planned.velocities,
                           planned.accelerations)
    executed, _ = controller.submit("g", sent, now=0.0)
    assert executed.release_time == pytest.approx(planned.release_time, abs=1e-9)  # no approach needed
    assert release_time(_goal([0.0, 1.0], [here, here])) is None  # a goal that never moves has none


def _jerk_after(controller: TrajectoryController, start: float, stop: float) -> np.ndarray:
    """Largest |jerk| (J,) of the arm from ``start`` to ``stop`` (s): differences of its
    accelerations every ms (the quintic's, up to 1.9x max_jerk at a profile's corner)."""
    accelerations = [controller.state(now).accelerations for now in np.arange(start, stop, 0.001)]
    return np.abs(np.diff(accelerations, axis=0)).max(axis=0) / 0.001


def _accelerating_goal(controller: TrajectoryController, start: float) -> JointTrajectory:
    """joint_2 from the arm's pose at rest but already accelerating at 5 rad/s^2, 0.4 rad on, its
    first point at ``start`` s."""
    here = controller.state(0.0).positions
    rest, push = np.zeros(len(NAMES)), np.zeros(len(NAMES))
    push[DRIVEN] = 5.0
    target = here.copy()
    target[DRIVEN] += 0.4
    motion = plan_transition(here, rest, push, target, rest, ROBOT.joints, period=0.01)
    return JointTrajectory(NAMES, motion.time + start, motion.positions, motion.velocities, motion.accelerations)


def test_the_approach_meets_a_goal_accelerating_at_its_first_point_without_a_jerk(controller):
    # a throw of joint_2 as the planner makes it (from rest up to 2.25 rad/s, then braking to
    # rest), sent from just after its peak acceleration with that point 0.5 s after receipt
    here = controller.state(0.0).positions
    rest, release, fast = np.zeros(len(NAMES)), here.copy(), np.zeros(len(NAMES))
    release[DRIVEN], fast[DRIVEN] = here[DRIVEN] + 1.0, 2.25
    throw = plan_transition(here, rest, rest, release, fast, ROBOT.joints)
    brake = plan_stop(release, fast, rest, ROBOT.joints)
    peak = int(np.argmax(throw.accelerations[:, DRIVEN])) + 3
    assert throw.accelerations[peak, DRIVEN] > 0.9 * AMAX[DRIVEN]
    time = np.concatenate([throw.time[peak:] - throw.time[peak], throw.duration - throw.time[peak] + brake.time[1:]])
    goal = JointTrajectory(NAMES, time + 0.5, *(np.vstack([a[peak:], b[1:]]) for a, b in (
        (throw.positions, brake.positions), (throw.velocities, brake.velocities),
        (throw.accelerations, brake.accelerations))))
    executed, _ = controller.submit("g", goal, now=0.0)
    assert np.all(_jerk_after(controller, 0.0, executed.duration + 0.6) <= 3 * JMAX)  # 120x before the fix
    times, positions, outcomes = _run(controller, 0.0, executed.duration + 0.6)
    _within_limits(times, positions)
    assert [(o.goal, o.status) for o in outcomes] == [("g", "succeeded")]


def test_a_goal_from_zero_accelerating_where_the_arm_is_at_rest_is_refused_and_approached_later(controller):
    with pytest.raises(GoalRejected) as refused:
        controller.submit("g", _accelerating_goal(controller, 0.0), now=0.0)
    assert refused.value.code == ResultCode.PATH_TOLERANCE_VIOLATED
    assert ("joint_2 acceleration 5 rad/s^2, the arm's 0 rad/s^2 (5 rad/s^2 apart, its max_jerk 110 rad/s^3 "
            "changes it by 0.22 rad/s^2 in the controller's 0.002 s period); start the goal later than 0 s"
            in str(refused.value))
    assert controller.idle
    executed, _ = controller.submit("g", _accelerating_goal(controller, 0.5), now=0.0)
    assert np.all(_jerk_after(controller, 0.0, executed.duration + 0.6) <= 3 * JMAX)


@pytest.mark.parametrize(("goal", "code", "message"), [
    (JointTrajectory(("elbow",), [0.0], [[0.0]], [[0.0]]), ResultCode.INVALID_JOINTS, "unknown joints"),
    (JointTrajectory(("joint_2",), [0.5, 1.0], [[0.0], [3.5]], [[0.0], [0.0]]), ResultCode.INVALID_GOAL,
     "point 1 .*: joint_2 position 3.5 rad beyond the limit 2.71 rad"),
    (JointTrajectory(("joint_2",), [0.5, 2.0], [[0.0], [0.5]], [[0.0], [0.5]]), ResultCode.INVALID_GOAL,
     "ends with joint_2 velocity 0.5 rad/s, not at rest"),
])
def test_goals_beyond_the_robot_are_refused_with_their_codes(controller, goal, code, message):
    with pytest.raises(GoalRejected, match=message) as refused:
        controller.submit("g", goal, now=0.0)
    assert refused.value.code == code


def test_a_goal_leaving_out_a_moving_joint_is_refused(controller):
    here = controller.state(0.0).positions
    controller.submit("old", _swing(here, 1.0, 1.6), now=0.0)
    partial = JointTrajectory(("joint_1",), [0.5], [[0.2]], [[0.0]])
    with pytest.raises(GoalRejected, match="leaves out joint_2, which is moving at 0.98"):
        controller.submit("new", partial, now=0.8)


def test_a_goal_that_ended_before_its_receipt_is_old(controller):
    here = controller.state(0.0).positions
    with pytest.raises(GoalRejected, match="ended at 11.000 s, before its receipt at 20.000 s") as refused:
        controller.submit("g", _goal([0.0, 1.0], [here, here]), now=20.0, start=10.0)
    assert refused.value.code == ResultCode.OLD_HEADER_TIMESTAMP


@pytest.mark.parametrize("rate", [0.0, -5.0, float("nan"), float("inf")])
def test_a_rate_must_be_a_positive_number(rate):
    with pytest.raises(InputError, match=r"rate \(--rate\) must be a positive number of ticks per second"):
        check_rate(rate)


def test_a_goal_cancelled_while_the_arm_waits_for_its_start_never_moves_the_arm(controller):
    """A goal whose first point comes later is waited for at rest; cancelled then, it ends at once
    and the arm stays where it is (it once went on to execute the cancelled goal's motion)."""
    here = controller.state(0.0).positions
    there = here.copy()
    there[DRIVEN] += 0.3
    controller.submit("g", _goal([1.0, 2.0], [here, there]), now=0.0)
    [outcome] = controller.cancel("g", 0.3)
    assert (outcome.goal, outcome.status) == ("g", "cancelled") and "the arm was at rest" in outcome.text
    assert controller.active_goal is None
    _, positions, outcomes = _run(controller, 0.3, 3.0)
    assert outcomes == []
    np.testing.assert_array_equal(positions, np.tile(here, (len(positions), 1)))


def test_a_stop_brakes_the_goal_within_the_limits_ends_it_aborted_and_refuses_new_goals(controller):
    here = controller.state(0.0).positions
    executed, _ = controller.submit("g", _swing(here, 2.0, 1.6), now=0.0)
    stop = {60: lambda now: controller.stop(now, "SIGTERM")}  # 0.6 s in, near full speed
    times, positions, outcomes = _run(controller, 0.0, 2.0, stop)
    _within_limits(times, positions)
    [outcome] = outcomes
    assert (outcome.goal, outcome.status, outcome.code) == ("g", "aborted", ResultCode.SUCCESSFUL)
    assert outcome.text.startswith("the server was stopped by SIGTERM after 0.600 s of 1.600 s; braked to rest "
                                   "from "), outcome.text
    speed, braked = (float(outcome.text.split(word)[-1].split(" ")[0]) for word in (" from ", " in "))
    assert speed > 1.5 and 0.1 < braked < 1.0  # it was moving fast
    assert np.ptp(positions[times > 0.6 + braked + TICK], axis=0).max() == 0.0  # standing still
    assert positions[-1, DRIVEN] < executed.positions[-1, DRIVEN] - 0.2  # short of the end
    assert controller.idle and controller.stop(2.0, "SIGINT") == []
    with pytest.raises(GoalRejected, match=r"^the server is stopping \(stopped by SIGTERM\): it takes no new goal$") \
            as refused:
        controller.submit("h", _goal([1.0], here), now=2.0)
    assert refused.value.code == ResultCode.INVALID_GOAL
    _, still, outcomes = _run(controller, 2.0, 3.0)
    assert outcomes == [] and np.ptp(still, axis=0).max() == 0.0


def test_a_stop_ends_a_goal_waiting_at_rest_at_once_and_leaves_a_cancel_s_brake_alone(controller):
    here = controller.state(0.0).positions
    there = here.copy()
    there[DRIVEN] += 0.3
    controller.submit("g", _goal([1.0, 2.0], [here, there]), now=0.0)
    [outcome] = controller.stop(0.3, "SIGINT")  # the arm waits at rest for the goal's start
    assert (outcome.goal, outcome.status) == ("g", "aborted")
    assert outcome.text.startswith("the server was stopped by SIGINT after 0.000 s of ")  # not started
    assert outcome.text.endswith("; the arm was at rest")
    _, positions, outcomes = _run(controller, 0.3, 3.0)
    assert outcomes == [] and np.ptp(positions, axis=0).max() == 0.0  # it never goes on to the goal
    assert controller.idle

    braking = TrajectoryController(ROBOT, here)
    braking.submit("c", _swing(here, 2.0, 1.6), now=0.0)
    assert braking.cancel("c", 0.6) == [] and braking.stop(0.61, "SIGTERM") == []
    _, _, outcomes = _run(braking, 0.61, 2.0)
    assert [(o.goal, o.status) for o in outcomes] == [("c", "cancelled")]
    assert outcomes[0].text.startswith("cancelled after 0.600 s")
