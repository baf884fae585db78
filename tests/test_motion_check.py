"""The one motion check: what it refuses, and that the message names point, joint, quantity, limit."""

from __future__ import annotations

import numpy as np
import pytest

from rlff.errors import InputError
from rlff.robot.description import load_robot
from rlff.robot.mapping import RobotMapping
from rlff.trajectory.check import MotionLimitError, check_trajectory, violation_counts
from rlff.trajectory.joint import JointTrajectory
from rlff.trajectory.planner import plan_throw

ROBOT = load_robot()
MAPPING = RobotMapping.for_robot(ROBOT)


@pytest.fixture(scope="module")
def planned() -> JointTrajectory:
    q = np.linspace(-1.3, -0.3, 30)
    positions = np.tile(MAPPING.pose(), (30, 1))
    positions[:, 1] = q
    velocities = np.zeros_like(positions)
    velocities[:, 1] = np.linspace(0.0, 2.4, 30)
    return plan_throw(JointTrajectory(ROBOT.joint_names, np.arange(30.0), positions, velocities), ROBOT.joints)


def altered(traj: JointTrajectory, *, time=None, positions=None, velocities=None, accelerations=None):
    return JointTrajectory(traj.joint_names, traj.time if time is None else time,
                           traj.positions if positions is None else positions,
                           traj.velocities if velocities is None else velocities,
                           traj.accelerations if accelerations is None else accelerations)


def test_a_planned_throw_passes(planned):
    check_trajectory(planned, ROBOT.joints, start=planned.positions[0])
    assert issubclass(MotionLimitError, InputError)


def test_a_stretched_time_column_is_refused(planned):
    with pytest.raises(MotionLimitError, match=r"point \d+ \(t = [\d.]+ s\) to point \d+: joint_2 moves .* "
                                               r"disagree by more than the acceleration limit 11 rad/s\^2"):
        check_trajectory(altered(planned, time=planned.time * 20), ROBOT.joints)


@pytest.mark.parametrize(("scale", "unit"), [(1e3, "milliseconds"), (1e6, "microseconds")])
def test_a_time_column_in_another_unit_is_refused_however_long_its_steps(planned, scale, unit):
    # x1000: steps of 2 s, where the disagreement the acceleration limit allows (A dt^2 / 4) is 11 rad:
    # a tester's file with its time in milliseconds passed, and the quintic swung off its path
    with pytest.raises(MotionLimitError, match=rf"the positions move {1 / scale:.3g} times as far as the velocities "
                                               rf"say over the time column's steps \(the median of \d+ steps of fast "
                                               rf"motion\), as a time in {unit} does: is the time in seconds"):
        check_trajectory(altered(planned, time=planned.time * scale), ROBOT.joints)


def test_scaled_velocities_with_the_time_kept_are_refused(planned):
    with pytest.raises(MotionLimitError, match="joint_2 moves .* but its velocities say .* disagree"):
        check_trajectory(altered(planned, velocities=planned.velocities * 0.8), ROBOT.joints)


def test_positions_outrunning_clipped_velocities_are_refused():
    """``--clip`` of old: velocities under the limit while the positions move at 9.5 rad/s."""
    time = np.arange(11) * 0.01
    positions = np.tile(MAPPING.pose(), (11, 1))
    positions[:, 1] = -1.0 + 9.5 * time
    velocities = np.zeros_like(positions)
    velocities[:, 1] = 2.792
    velocities[-1, 1] = 0.0
    with pytest.raises(MotionLimitError, match=r"point 0 \(t = 0.000000 s\) to point 1: joint_2 moves 0.095 rad "
                                               r"in 0.01 s \(mean velocity 9.5 rad/s\)"):
        check_trajectory(altered_from(time, positions, velocities), ROBOT.joints)


def altered_from(time, positions, velocities):
    return JointTrajectory(ROBOT.joint_names, time, positions, velocities)


def test_between_points_the_quintic_interpolation_is_checked():
    # two points at rest 0.088 rad apart: the quintic through them peaks at 5.77 * 0.088 / T^2 rad/s^2:
    # 5.6 in 0.3 s (fine for joint_2), 12.7 in 0.2 s, while the points agree (0.088 < 11 * 0.2^2 / 4)
    for duration, ok in ((0.3, True), (0.2, False)):
        positions = np.tile(MAPPING.pose(), (2, 1))
        positions[1, 1] += 0.088
        traj = altered_from([0.0, duration], positions, np.zeros_like(positions))
        if ok:
            check_trajectory(traj, ROBOT.joints)
            continue
        with pytest.raises(MotionLimitError, match=r"between points 0 and 1 \(t = [\d.]+ s, quintic interpolation\): "
                                                   r"joint_2 acceleration 12.\d+ rad/s\^2 beyond the limit 11 rad/s\^2"):
            check_trajectory(traj, ROBOT.joints)


def test_points_beyond_a_limit_are_named(planned):
    accelerations = planned.accelerations.copy()
    accelerations[5, 1] = 12.5
    with pytest.raises(MotionLimitError, match=r"point 5 \(t = 0.010000 s\): joint_2 acceleration 12.5 rad/s\^2 "
                                               r"beyond the limit 11 rad/s\^2"):
        check_trajectory(altered(planned, accelerations=accelerations), ROBOT.joints)
    positions = planned.positions.copy()
    positions[:, 2] = 0.01
    with pytest.raises(MotionLimitError, match=r"point 0 .*joint_3 position 0.01 rad beyond the limit 0 rad"):
        check_trajectory(altered(planned, positions=positions), ROBOT.joints)


def test_it_must_start_where_the_arm_is_and_end_at_rest(planned):
    with pytest.raises(MotionLimitError, match=r"point 0 \(t = 0.000000 s\): joint_2 position -1.3 rad is not "
                                               r"where the arm is \(-1.2 rad; 0.1 rad off, tolerance 0.001 rad\)"):
        check_trajectory(planned, ROBOT.joints, start=MAPPING.pose(-1.2))
    cut = planned.time <= planned.release_time
    moving = JointTrajectory(planned.joint_names, planned.time[cut], planned.positions[cut],
                             planned.velocities[cut], planned.accelerations[cut])
    with pytest.raises(MotionLimitError, match=r"the trajectory ends with joint_2 velocity 2.4 rad/s, not at rest"):
        check_trajectory(moving, ROBOT.joints)


def test_violation_counts_count_what_the_check_refuses(planned):
    assert violation_counts(planned, ROBOT.joints) == {
        "disagreement": 0, "position": 0, "velocity": 0, "acceleration": 0, "end moving": 0}
    slowed = violation_counts(altered(planned, velocities=planned.velocities * 0.8), ROBOT.joints)
    assert slowed["disagreement"] > 0 and slowed["end moving"] == 0
    cut = planned.time <= planned.release_time
    moving = JointTrajectory(planned.joint_names, planned.time[cut], planned.positions[cut],
                             planned.velocities[cut], planned.accelerations[cut])
    assert violation_counts(moving, ROBOT.joints)["end moving"] == 1


def test_a_joint_moving_alone_is_checked_between_points_like_any():
    """The quintic is computed for moving joints only: a held joint copies, a moving one is checked."""
    for column in (0, 3):
        positions = np.tile(MAPPING.pose(), (2, 1))
        positions[1, column] += 0.1
        traj = JointTrajectory(ROBOT.joint_names, [0.0, 0.2], positions, np.zeros_like(positions))
        counts = violation_counts(traj, ROBOT.joints)
        expected = 5.77 * 0.1 / 0.2**2 > ROBOT.joints[column].max_acceleration  # quintic peak 14.4 rad/s^2
        assert (counts["acceleration"] > 0) == expected
