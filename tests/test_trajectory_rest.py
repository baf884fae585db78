"""Every robot output starts at rest as well as ending there (``check_trajectory(start_at_rest=True)``)."""

from __future__ import annotations

import numpy as np
import pytest

from rlff.robot.description import load_robot
from rlff.robot.mapping import RobotMapping
from rlff.trajectory.check import MotionLimitError, check_trajectory
from rlff.trajectory.joint import JointTrajectory
from rlff.trajectory.planner import plan_throw

ROBOT = load_robot()
MAPPING = RobotMapping.for_robot(ROBOT)


@pytest.fixture(scope="module")
def planned() -> JointTrajectory:
    positions = np.tile(MAPPING.pose(), (30, 1))
    positions[:, 1] = np.linspace(-1.3, -0.3, 30)
    velocities = np.zeros_like(positions)
    velocities[:, 1] = np.linspace(0.0, 2.4, 30)
    return plan_throw(JointTrajectory(ROBOT.joint_names, np.arange(30.0), positions, velocities), ROBOT.joints)


def from_point(traj: JointTrajectory, first: int) -> JointTrajectory:
    """``traj`` from its point ``first`` on, time from 0 there."""
    return JointTrajectory(traj.joint_names, traj.time[first:] - traj.time[first], traj.positions[first:],
                           traj.velocities[first:], traj.accelerations[first:])


def test_a_planned_throw_starts_at_rest(planned):
    check_trajectory(planned, ROBOT.joints, start_at_rest=True)


def test_a_trajectory_that_starts_moving_or_accelerating_is_refused(planned):
    # one period into the throw joint_2 moves at 2.2e-4 rad/s, within the velocity tolerance, but
    # accelerates at 0.22 rad/s^2: a step in acceleration no controller makes from rest
    accelerating = from_point(planned, 1)
    assert abs(accelerating.velocities[0, 1]) < 1e-3 < 1e-2 < abs(accelerating.accelerations[0, 1])
    check_trajectory(accelerating, ROBOT.joints)  # a controller's goal may start from a moving arm
    with pytest.raises(MotionLimitError, match=r"^point 0 \(t = 0.000000 s\): the trajectory starts with joint_2 "
                                               r"acceleration 0.22 rad/s\^2, not at rest \(tolerance 0.01 rad/s\^2\)"):
        check_trajectory(accelerating, ROBOT.joints, start_at_rest=True)
    moving = from_point(planned, int(np.argmax(planned.velocities[:, 1])))
    with pytest.raises(MotionLimitError, match=r"the trajectory starts with joint_2 velocity 2.4 rad/s, not at rest "
                                               r"\(tolerance 0.001 rad/s\): a controller starts a trajectory from "
                                               r"the arm at rest"):
        check_trajectory(moving, ROBOT.joints, start_at_rest=True)
