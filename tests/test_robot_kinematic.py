"""The kinematic arm the controller drives, and the goal checks run before anything moves."""

from __future__ import annotations

import numpy as np
import pytest

from rlff.errors import InputError
from rlff.robot import load_robot
from rlff.robot.goal import InvalidJoints, check_goal
from rlff.robot.kinematic import KinematicArm
from rlff.trajectory import JointTrajectory
from rlff.trajectory.check import MotionLimitError

NAMES = ("a", "b")


def test_follows_the_points_exactly_and_holds_the_end():
    arm = KinematicArm(NAMES, np.array([0.0, 0.0]))
    traj = JointTrajectory(NAMES, [0.0, 1.0, 2.0], [[0.0, 1.0], [1.0, 1.0], [3.0, 1.0]],
                           [[0.0, 0.0], [2.0, 0.0], [0.0, 0.0]], [[2.0, 0.0], [2.0, 0.0], [0.0, 0.0]])
    arm.follow(traj, start=10.0)
    assert arm.moving
    for t, expected in zip([0.0, 1.0, 2.0], traj.positions, strict=True):
        np.testing.assert_allclose(arm.state(10.0 + t).positions, expected, atol=1e-12)
    np.testing.assert_allclose(arm.state(11.0).velocities, [2.0, 0.0])
    np.testing.assert_allclose(arm.state(11.0).accelerations, [2.0, 0.0])
    # between points: the quintic through (0, 0, v=0, a=2) and (1, 1, v=2, a=2) is t^2
    np.testing.assert_allclose(arm.state(10.5).positions[0], 0.25)
    np.testing.assert_allclose(arm.state(10.5).accelerations[0], 2.0)
    assert not arm.finished(11.9)
    assert arm.finished(12.1) and not arm.moving
    np.testing.assert_allclose(arm.state(50.0).positions, [3.0, 1.0])
    np.testing.assert_array_equal(arm.state(50.0).velocities, [0.0, 0.0])


def test_before_its_start_the_arm_stands_at_the_first_point():
    arm = KinematicArm(NAMES, np.array([0.5, -0.5]))
    arm.follow(JointTrajectory(NAMES, [0.0, 1.0], [[0.5, -0.5], [0.5, 1.5]], [[0.0, 0.0], [0.0, 0.0]]), start=2.0)
    np.testing.assert_allclose(arm.state(1.0).positions, [0.5, -0.5])
    np.testing.assert_allclose(arm.state(2.5).positions, [0.5, 0.5])  # halfway, by symmetry
    assert not arm.finished(2.9) and arm.finished(3.0)


def test_a_single_point_is_reached_at_once():
    arm = KinematicArm(NAMES, np.zeros(2))
    arm.follow(JointTrajectory(NAMES, [0.0], [[0.3, 0.4]], [[0.0, 0.0]]), start=1.0)
    np.testing.assert_allclose(arm.state(1.0).positions, [0.3, 0.4])
    assert arm.finished(1.0) and not arm.finished(1.1)


def test_the_arm_follows_only_trajectories_of_all_its_joints():
    arm = KinematicArm(NAMES, np.zeros(2))
    with pytest.raises(InputError, match="follows trajectories of \\['a', 'b'\\], got \\['b'\\]"):
        arm.follow(JointTrajectory(("b",), [0.0], [[0.0]], [[0.0]]), start=0.0)


def test_goal_checks_split_joints_from_other_problems():
    robot = load_robot()
    pose = np.array([0.0])  # joint_2's
    ok = JointTrajectory(("joint_2",), [0.0, 1.0], [[0.0], [0.5]], [[0.0], [0.0]])
    check_goal(robot, ok, pose)
    with pytest.raises(InvalidJoints, match="unknown joints \\['elbow'\\]"):
        check_goal(robot, JointTrajectory(("elbow",), [0.0], [[0.0]], [[0.0]]))
    with pytest.raises(MotionLimitError, match="point 1 .*: joint_2 velocity 3 rad/s beyond the limit 2.792 rad/s"):
        check_goal(robot, JointTrajectory(("joint_2",), [0.0, 1.0, 2.0], [[0.0], [1.0], [2.0]],
                                          [[0.0], [3.0], [0.0]]))
    away = np.array([0.3])
    with pytest.raises(MotionLimitError, match="joint_2 position 0 rad is not where the arm is \\(0.3 rad"):
        check_goal(robot, ok, away)
    # every point inside the limits, but the spline still rises after 2.7 rad (at 1 rad/s)
    # and overshoots the upper limit 2.71 rad before coming back
    overshoot = JointTrajectory(("joint_2",), [0.0, 1.0, 2.0], [[2.5], [2.7], [2.5]], [[0.0], [1.0], [0.0]])
    with pytest.raises(InputError, match=r"between points 1 and 2 \(t = [\d.]+ s, quintic interpolation\): "
                                         r"joint_2 position 2.8\d* rad beyond the limit 2.71 rad"):
        check_goal(robot, overshoot)
