"""The kinematic arm the ROS server drives, and the goal checks run before anything moves."""

from __future__ import annotations

import numpy as np
import pytest

from rlff.errors import InputError
from rlff.robot import load_robot
from rlff.robot.goal import InvalidJoints, check_goal
from rlff.robot.kinematic import KinematicArm
from rlff.trajectory import JointTrajectory

NAMES = ("a", "b")


def test_follows_the_points_exactly_and_holds_the_end():
    arm = KinematicArm(NAMES, np.array([0.0, 0.0]))
    traj = JointTrajectory(NAMES, [0.0, 1.0, 2.0], [[0.0, 1.0], [1.0, 1.0], [3.0, 1.0]],
                           [[0.0, 0.0], [2.0, 0.0], [0.0, 0.0]])
    arm.follow(traj, start=10.0, now=10.0)
    assert arm.moving
    for t, expected in zip([0.0, 1.0, 2.0], traj.positions, strict=True):
        np.testing.assert_allclose(arm.state(10.0 + t).positions, expected, atol=1e-12)
    np.testing.assert_allclose(arm.state(11.0).velocities, [2.0, 0.0])
    # between points: the cubic Hermite through (0, 0, v=0) and (1, 1, v=2) is t^2
    np.testing.assert_allclose(arm.state(10.5).positions[0], 0.25)
    assert not arm.finished(11.9)
    assert arm.finished(12.1) and not arm.moving
    np.testing.assert_allclose(arm.state(50.0).positions, [3.0, 1.0])
    np.testing.assert_array_equal(arm.state(50.0).velocities, [0.0, 0.0])


def test_a_late_first_point_is_reached_from_where_the_arm_is():
    arm = KinematicArm(NAMES, np.array([0.5, -0.5]))
    full = arm.follow(JointTrajectory(("b",), [1.0], [[1.5]], [[0.0]]), start=0.0, now=0.0)
    np.testing.assert_allclose(full.positions, [[0.5, -0.5], [0.5, 1.5]])  # 'a' holds
    np.testing.assert_allclose(arm.state(0.5).positions, [0.5, 0.5])  # halfway, by symmetry


def test_a_single_point_at_zero_is_reached_at_once():
    arm = KinematicArm(NAMES, np.zeros(2))
    arm.follow(JointTrajectory(NAMES, [0.0], [[0.3, 0.4]], [[0.0, 0.0]]), start=1.0, now=1.0)
    np.testing.assert_allclose(arm.state(1.0).positions, [0.3, 0.4])
    assert arm.finished(1.0) and not arm.finished(1.1)


def test_stop_holds_where_the_arm_is():
    arm = KinematicArm(NAMES, np.zeros(2))
    arm.follow(JointTrajectory(NAMES, [0.0, 2.0], [[0.0, 0.0], [2.0, 2.0]], [[1.0, 1.0], [1.0, 1.0]]), 0.0, 0.0)
    arm.stop(0.5)
    assert not arm.moving
    np.testing.assert_allclose(arm.state(5.0).positions, [0.5, 0.5])


def test_goal_checks_split_joints_from_other_problems():
    robot = load_robot()
    ok = JointTrajectory(("joint_2",), [0.0, 1.0], [[0.0], [1.0]], [[0.0], [0.0]])
    check_goal(robot, ok)
    with pytest.raises(InvalidJoints, match="unknown joints \\['elbow'\\]"):
        check_goal(robot, JointTrajectory(("elbow",), [0.0], [[0.0]], [[0.0]]))
    with pytest.raises(InputError, match="joint_2 velocity 3 rad/s beyond the limit 2.792"):
        check_goal(robot, JointTrajectory(("joint_2",), [0.0, 1.0], [[0.0], [1.0]], [[0.0], [3.0]]))
    # every point inside the limits, but the spline still rises after 2.7 rad (at 1 rad/s)
    # and overshoots the upper limit 2.71 rad before coming back
    overshoot = JointTrajectory(("joint_2",), [0.0, 1.0, 2.0], [[2.5], [2.7], [2.5]], [[0.0], [1.0], [0.0]])
    with pytest.raises(InputError, match=r"between points 1 and 2 \(t = [\d.]+ s, quintic interpolation\): "
                                         r"joint_2 position 2.8\d* rad beyond the limit 2.71 rad"):
        check_goal(robot, overshoot)
