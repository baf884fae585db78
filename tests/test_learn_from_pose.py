"""An executor of one's own: the throw the loop hands it starts at the throw's first pose, the arm
is where the last throw braked it; :func:`rlff.learn.plan_from_pose` plans the same throw from
there. Real model, real planner, real MuJoCo."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from rlff.dataset import Dataset
from rlff.errors import InputError
from rlff.learn import learn, plan_from_pose
from rlff.robot import load_robot
from rlff.sim import Basket, simulate_throw

BASKET = 1.4  # m


@pytest.fixture(scope="module")
def demos() -> Dataset:
    from rlff.preprocess import Pipeline
    from rlff.synthetic.throws import simulate_throws

    raw = simulate_throws(3, subjects=3, distances=(1.0, 1.25, 1.5), throws_per_distance=2, all_short=True)
    clean, _ = Pipeline.preset("thesis").run(raw)
    return clean


class Arm:
    """The caller's arm, in MuJoCo: it sends each throw planned from where the last one left it
    (``plan_from_pose``, as the docs say), and keeps what it was handed and what it sent."""

    def __init__(self) -> None:
        self.robot = load_robot("comau_smart5_six")
        self.pose = None  # unknown before the first throw: it waits at the first throw's start
        self.handed, self.sent = [], []

    def __call__(self, trajectory):
        pose = trajectory.positions[0] if self.pose is None else self.pose
        sent = plan_from_pose(trajectory, self.robot, pose)
        self.handed.append(trajectory)
        self.sent.append(sent)
        self.pose = sent.positions[-1]  # braked to rest after the release
        return simulate_throw(sent, Basket(BASKET))


@pytest.fixture(scope="module")
def run(demos):
    arm = Arm()
    result = learn(demos, BASKET, budget=3, feedback="distance", update="secant", executor=arm)
    assert result.attempts >= 2, result.misses  # a second throw, from where the first braked
    return result, arm


def release_state(trajectory) -> tuple[np.ndarray, np.ndarray]:
    """Positions and velocities (J,) at the trajectory's release."""
    at = int(np.argmin(np.abs(trajectory.time - trajectory.release_time)))
    return trajectory.positions[at], trajectory.velocities[at]


def test_the_throw_handed_to_an_executor_starts_where_the_last_one_did_not_end(run):
    # why an executor must plan from the arm's pose: the loop's plan starts at rest at its own
    # first pose, the arm waits where the last throw braked it (about a radian away on joint_2)
    _, arm = run
    joint = arm.robot.index("joint_2")
    assert abs(arm.handed[1].positions[0, joint] - arm.handed[0].positions[-1, joint]) > 0.5


def test_each_throw_sent_starts_at_the_arm_at_rest_and_lets_go_as_the_loop_planned(run):
    result, arm = run
    for number, (handed, sent) in enumerate(zip(arm.handed, arm.sent, strict=True)):
        where = arm.handed[0].positions[0] if number == 0 else arm.sent[number - 1].positions[-1]
        np.testing.assert_array_equal(sent.positions[0], where)
        np.testing.assert_array_equal(sent.velocities[0], 0.0)
        for planned, made in zip(release_state(handed), release_state(sent), strict=True):
            np.testing.assert_allclose(made, planned, rtol=0, atol=1e-12)
        # the ball flies as from the loop's own plan (what the log keeps and replays); the
        # simulated arm follows a goal sampled at 10 ms a little otherwise than one at 2 ms (1 cm
        # here), where a throw planned again as if its braking were its release fell at the base
        assert result.history[number].landing == pytest.approx(simulate_throw(handed, Basket(BASKET)).landing_x,
                                                               abs=0.02)


def test_from_the_throws_own_start_at_the_loops_period_it_is_the_loops_plan(run):
    _, arm = run
    handed = arm.handed[1]
    again = plan_from_pose(handed, "comau_smart5_six", handed.positions[0], period=0.002)
    np.testing.assert_array_equal(again.time, handed.time)
    np.testing.assert_array_equal(again.positions, handed.positions)
    assert again.release_time == handed.release_time


@pytest.mark.parametrize(("change", "words"), [
    (lambda t, pose: (t, pose[:5]), r"the arm's pose must be 6 finite angles \(rad\), one per joint of"),
    (lambda t, pose: (t, pose + np.r_[0, 4.0, 0, 0, 0, 0]), r"planned from the arm's pose: .*joint_2"),
    (lambda t, pose: (type(t)(t.joint_names, t.time, t.positions, t.velocities), pose),
     r"takes the planned throw learn hands its executor"),
    # a joint the throw leaves out, beyond its limit (accepted until 2026-12-07)
    (lambda t, pose: (t.select(["joint_2"]), pose + np.r_[9.0, 0, 0, 0, 0, 0]),
     r"planned from the arm's pose: joint_1 starts at 9 rad, already beyond its upper limit 2\.967 rad"),
    # a release_time during the braking: planned as if released there (at half the speed) until 2026-12-07
    (lambda t, pose: (replace(t, release_time=float(t.time[np.searchsorted(t.time, t.release_time + 0.1)])), pose),
     r"release_time .* falls where the arm slows down: joint_2 moves at"),
])
def test_what_cannot_be_planned_from_a_pose_is_refused_naming_it(run, change, words):
    _, arm = run
    trajectory, pose = change(arm.handed[1], arm.sent[0].positions[-1])
    with pytest.raises(InputError, match=words):
        plan_from_pose(trajectory, arm.robot, pose)


def test_a_robot_executor_says_the_attempt_of_a_server_that_is_not_there(run):
    # "no action server at /comau_controller/follow_joint_trajectory" came without "attempt N:",
    # where a goal that failed and every other robot failure of the run name it
    from rlff.errors import RlffError
    from rlff.learn.robot import RobotExecutor

    class NoServer(RlffError):
        pass

    class Unreachable:
        def arm_state(self, robot):
            return handed.positions[0], np.zeros(len(robot.joint_names))

        def send_goal(self, robot, goal, pose):
            raise NoServer("no action server at /comau_controller/follow_joint_trajectory (is it running?)")

    _, arm = run
    handed = arm.handed[0]
    executor = RobotExecutor(Unreachable(), arm.robot, outcome=lambda attempt, release: None)
    executor.resume(2)
    with pytest.raises(NoServer, match=r"^attempt 3: no action server at /comau_controller/follow_joint_trajectory"):
        executor(handed)
