"""Planned throws turn and stop POSITION_MARGIN inside a position limit, and the check refuses a
joint moved onto a limit: a controller's software limit faults at the least overshoot past it."""

from __future__ import annotations

import re

import numpy as np
import pytest

from rlff.robot.description import load_robot
from rlff.robot.mapping import RobotMapping
from rlff.trajectory.check import MotionLimitError, OnLimitWarning, check_trajectory
from rlff.trajectory.joint import JointTrajectory
from rlff.trajectory.limits import POSITION_MARGIN
from rlff.trajectory.planner import plan_throw

ROBOT = load_robot()
MAPPING = RobotMapping.for_robot(ROBOT)
UPPER = ROBOT.joint("joint_2").upper  # 2.71 rad


def throw_to(release: float, speed: float = 1.5) -> JointTrajectory:
    """joint_2's throw from 1 rad below ``release`` (rad) to it at ``speed`` (rad/s), planned."""
    positions = np.tile(MAPPING.pose(), (2, 1))
    positions[:, 1] = [release - 1.0, release]
    velocities = np.zeros_like(positions)
    velocities[1, 1] = speed
    return plan_throw(JointTrajectory(ROBOT.joint_names, [0.0, 1.0], positions, velocities), ROBOT.joints)


@pytest.fixture(scope="module")
def braking() -> float:
    """How far (rad) joint_2 travels braking to rest from 1.5 rad/s: the same wherever it is released."""
    planned = throw_to(0.0)
    return float(planned.positions[:, 1].max())


def test_braking_stops_the_margin_inside_a_limit_or_is_refused(braking):
    # a tester's arm braked to rest 4e-10 rad short of its limit, where its controller faults
    for short in (4e-10, POSITION_MARGIN / 2):
        with pytest.raises(MotionLimitError, match=r"no room to brake after the release: joint_2 would reach "
                                                   rf"[\d.]+ rad, {short:.3g} rad inside its upper limit 2.71 rad, "
                                                   r"within the 0.002 rad a throw keeps clear of a position limit"):
            throw_to(UPPER - braking - short)
    planned = throw_to(UPPER - braking - 2 * POSITION_MARGIN)
    assert UPPER - planned.positions[:, 1].max() == pytest.approx(2 * POSITION_MARGIN, abs=1e-9)
    check_trajectory(planned, ROBOT.joints, start_at_rest=True)


def test_a_refusal_just_beyond_the_limit_shows_the_overshoot(braking):
    # "would reach 1.7 rad, beyond its upper limit 1.7 rad" told nothing
    with pytest.raises(MotionLimitError, match=re.escape("joint_2 would reach 2.71000004 rad, beyond its upper limit "
                                                         "2.71 rad")):
        throw_to(UPPER - braking + 4e-8)


def test_a_joint_moved_onto_a_limit_is_refused_and_one_held_there_warned_of(braking):
    planned = throw_to(UPPER - braking - 2 * POSITION_MARGIN)
    positions = planned.positions.copy()
    positions[:, 1] += UPPER - positions[:, 1].max() - 4e-10  # the braking ends 4e-10 rad short of the limit
    onto = JointTrajectory(planned.joint_names, planned.time, positions, planned.velocities, planned.accelerations)
    with pytest.raises(MotionLimitError, match=r"^point \d+ \(t = [\d.]+ s\): joint_2 moves to its position limit: "
                                               r"2\.70999\d* rad on the limit 2.71 rad, where a controller's software "
                                               r"limit faults at the least overshoot"):
        check_trajectory(onto, ROBOT.joints)
    # joint_3 held on its upper limit (0 rad) through a throw of joint_2: not moved there, so said, not refused
    held = planned.positions.copy()
    held[:, 2] = 0.0
    with pytest.warns(OnLimitWarning, match=r"the trajectory holds joint_3 on its upper position limit \(0 rad\)"):
        check_trajectory(JointTrajectory(planned.joint_names, planned.time, held, planned.velocities,
                                         planned.accelerations), ROBOT.joints)


def test_a_joint_that_starts_on_a_limit_may_leave_it_but_not_come_back():
    # the Comau at its zeros has joint_3 on its upper limit (0 rad): every move from there, an
    # approach to a throw's start as docs/robot.md shows it, had been refused as one onto the limit
    from rlff.trajectory.planner import plan_transition

    zeros = np.zeros(len(ROBOT.joint_names))
    target = zeros.copy()
    target[2] = -0.5
    away = plan_transition(zeros, zeros, zeros, target, zeros, ROBOT.joints)
    assert away.positions[0, 2] == 0.0 and away.positions[-1, 2] == pytest.approx(-0.5)
    check_trajectory(away, ROBOT.joints, start_at_rest=True)
    back = JointTrajectory(away.joint_names, np.concatenate([away.time, away.time[-1] + away.time[1:]]),
                           np.concatenate([away.positions, away.positions[::-1][1:]]),
                           np.concatenate([away.velocities, -away.velocities[::-1][1:]]),
                           np.concatenate([away.accelerations, away.accelerations[::-1][1:]]))
    with pytest.raises(MotionLimitError, match=r"joint_3 moves to its position limit: \S+ rad on the limit 0 rad"):
        check_trajectory(back, ROBOT.joints)
