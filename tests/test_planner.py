"""The motion planner (ruckig): transitions, stops and planned throws stay within every limit."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rlff.errors import InputError
from rlff.robot.description import Joint, load_robot
from rlff.robot.export import require_release
from rlff.robot.mapping import RobotMapping
from rlff.trajectory.check import MotionLimitError, check_trajectory
from rlff.trajectory.joint import JointTrajectory
from rlff.trajectory.planner import APPROACH_SPEED, MARGIN, plan_stop, plan_throw, plan_transition

ROBOT = load_robot()
MAPPING = RobotMapping.for_robot(ROBOT)
J2 = ROBOT.joint("joint_2")


def finite_jerk(traj: JointTrajectory) -> np.ndarray:
    """Largest |jerk| (rad/s^3) per joint from the sampled accelerations."""
    return np.max(np.abs(np.diff(traj.accelerations, axis=0) / np.diff(traj.time)[:, None]), axis=0)


def mapped_throw(first: float, release: float, release_speed: float, points: int = 40) -> JointTrajectory:
    """A robot throw of joint_2 from ``first`` to ``release`` (rad) ending at ``release_speed``."""
    q = np.linspace(first, release, points)
    speed = release_speed * np.sin(np.linspace(0.0, np.pi / 2, points))
    positions = np.tile(MAPPING.pose(), (points, 1))
    positions[:, 1] = q
    velocities = np.zeros_like(positions)
    velocities[:, 1] = speed * np.sign(release - first)
    return JointTrajectory(ROBOT.joint_names, np.arange(points) * 0.01, positions, velocities)


def test_a_throw_keeps_its_release_and_ends_at_rest_within_every_limit():
    throw = mapped_throw(-1.3, -0.3, 2.25)
    planned = plan_throw(throw, ROBOT.joints)
    release = int(np.flatnonzero(planned.time == planned.release_time)[0])
    np.testing.assert_allclose(planned.positions[release], throw.positions[-1], atol=1e-9)
    np.testing.assert_allclose(planned.velocities[release], throw.velocities[-1], atol=1e-9)
    np.testing.assert_array_equal(planned.velocities[-1], 0.0)
    check_trajectory(planned, ROBOT.joints, start=throw.positions[0])
    assert np.max(np.abs(planned.accelerations[:, 1])) <= J2.max_acceleration
    assert finite_jerk(planned)[1] <= J2.max_jerk * (1 + 1e-9)
    assert np.all(np.diff(planned.time) <= 0.002 + 1e-12)
    # never faster than the release speed of the joint
    assert np.max(np.abs(planned.velocities[:, 1])) <= 2.25 + 1e-9


def test_a_throw_from_elsewhere_approaches_its_start_first():
    throw = mapped_throw(-1.3, -0.3, 2.0)
    start = MAPPING.pose(0.5)
    planned = plan_throw(throw, ROBOT.joints, start=start, period=0.01)
    np.testing.assert_array_equal(planned.positions[0], start)
    check_trajectory(planned, ROBOT.joints, start=start)
    # the approach passes the throw's start at rest, then throws
    at_first = np.flatnonzero(np.all(np.abs(planned.positions - throw.positions[0]) < 1e-12, axis=1))
    assert at_first.size and np.all(planned.velocities[at_first[0]] == 0)
    with pytest.raises(MotionLimitError, match="point 0 .*joint_2 position 0.5 rad is not where the arm is"):
        check_trajectory(planned, ROBOT.joints, start=MAPPING.pose(-1.3))


@pytest.mark.parametrize("share", [APPROACH_SPEED, 0.1, 1.0])
def test_the_approach_keeps_to_its_share_of_the_limits_and_the_throw_to_the_limits(share):
    throw = mapped_throw(-1.3, -0.3, 2.6)
    start = MAPPING.pose(0.5)  # 1.8 rad from the throw's start: long enough to cruise
    planned = plan_throw(throw, ROBOT.joints, start=start, period=0.002, approach_speed=share)
    arrived = int(np.flatnonzero(np.all(np.abs(planned.positions - throw.positions[0]) < 1e-12, axis=1))[0])
    approach = planned.velocities[:arrived + 1, 1], planned.accelerations[:arrived + 1, 1]
    assert np.abs(approach[0]).max() <= share * J2.max_velocity * (1 + 1e-9)
    assert np.abs(approach[0]).max() >= 0.95 * share * MARGIN * J2.max_velocity  # it uses its share
    assert np.abs(approach[1]).max() <= share * J2.max_acceleration * (1 + 1e-9)
    # the throw itself is not slowed: it still releases at 2.6 rad/s, 93 % of joint_2's limit
    release = int(np.flatnonzero(planned.time == planned.release_time)[0])
    assert planned.velocities[release, 1] == pytest.approx(2.6)


def test_the_approach_is_slow_by_default():
    throw = mapped_throw(-1.3, -0.3, 2.0)
    start = MAPPING.pose(0.5)
    default, full = (plan_throw(throw, ROBOT.joints, start=start, **extra) for extra in ({}, {"approach_speed": 1.0}))
    assert default.release_time > full.release_time + 1.0  # 1.8 rad at a quarter of the speed


@pytest.mark.parametrize("share", [0.0, 1e-6, -0.25, 1.5, float("nan")])
def test_an_approach_share_outside_0_to_1_is_refused(share):
    throw = mapped_throw(-1.3, -0.3, 2.0)
    with pytest.raises(InputError, match="approach speed is a share of the joints. limits, from 0.01 to 1"):
        plan_throw(throw, ROBOT.joints, start=MAPPING.pose(0.5), approach_speed=share)


def test_a_path_too_short_for_its_release_speed_winds_up_first():
    throw = mapped_throw(-0.5, -0.45, 2.0)  # 0.05 rad cannot take joint_2 from rest to 2 rad/s
    planned = plan_throw(throw, ROBOT.joints)
    release = int(np.flatnonzero(planned.time == planned.release_time)[0])
    assert planned.positions[:release, 1].min() < -0.5 - 0.1  # backs up before it throws
    np.testing.assert_allclose(planned.velocities[release, 1], 2.0, atol=1e-12)
    check_trajectory(planned, ROBOT.joints, start=throw.positions[0])


def test_no_room_to_wind_up_is_refused_with_what_gives_room():
    """The refusal gave no next step (tester H), where the braking one does; --clip gives no room."""
    throw = mapped_throw(J2.lower + 0.01, J2.lower + 0.04, 2.0)
    with pytest.raises(MotionLimitError, match=r"^the throw \(start to release\): joint_2 would reach -1\.\d+ rad, beyond "
                                               r"its lower limit -1\.48 rad .*the limit is 0\.01 rad away\): the path "
                                               r"from the start to the release is too short to reach the release speed "
                                               r"from rest, so the arm backs up first; a slower release, or a throw "
                                               r"further from that limit \(the robot file's \[throwing\] angle_offset\), "
                                               r"leaves room; clipping the throw's points does not$"):
        plan_throw(throw, ROBOT.joints)


def test_no_room_to_brake_is_refused_with_the_joint_and_numbers():
    throw = mapped_throw(1.5, J2.upper - 0.01, 2.7)
    with pytest.raises(MotionLimitError, match=r"no room to brake after the release: joint_2 would reach "
                                               r"3\.1\d* rad, beyond its upper limit 2\.71 rad .*moving at 2\.7 rad/s.*the limit is 0\.01 rad away\): "
                                               r"a slower release, or one further from that limit \(the robot file's "
                                               r"\[throwing\] angle_offset\), leaves room; clipping the throw's points "
                                               r"does not$"):
        plan_throw(throw, ROBOT.joints)


def test_a_release_beyond_a_limit_is_refused():
    with pytest.raises(MotionLimitError, match="the release .*joint_2 velocity 3 rad/s beyond the limit 2.792"):
        plan_throw(mapped_throw(-1.3, -0.3, 3.0), ROBOT.joints)
    with pytest.raises(MotionLimitError, match="the release .*joint_2 position 2.8 rad outside its limits"):
        plan_throw(mapped_throw(1.0, 2.8, 1.0), ROBOT.joints)


def test_an_arm_already_beyond_a_limit_is_named_so():
    # it said the transition "would reach 0 rad, beyond its upper limit -0.05 rad (it needs 0 rad
    # from 0 rad ...)": the arm was there already, and the robot file's limit excluded it
    start = MAPPING.pose(0.0)
    start[1] = J2.upper + 0.2
    with pytest.raises(MotionLimitError, match=r"the transition: joint_2 starts at 2\.91 rad, already beyond its "
                                               r"upper limit 2\.71 rad in the robot file: move the arm inside"):
        plan_transition(start, np.zeros(6), np.zeros(6), MAPPING.pose(0.0), np.zeros(6), ROBOT.joints)


def test_stop_brakes_within_the_acceleration_and_jerk_limits():
    position, velocity = MAPPING.pose(0.0), np.zeros(6)
    velocity[1] = 2.5
    stop = plan_stop(position, velocity, np.zeros(6), ROBOT.joints, period=0.01)
    assert np.all(stop.velocities[-1] == 0) and np.all(np.diff(stop.positions[:, 1]) >= 0)
    assert np.max(np.abs(stop.accelerations[:, 1])) <= J2.max_acceleration
    # braking from 2.5 rad/s at <= 11 rad/s^2 takes at least 2.5 / 11 s and 2.5^2 / 22 rad
    assert stop.duration >= 2.5 / 11 and stop.positions[-1, 1] >= 2.5**2 / 22
    check_trajectory(stop, ROBOT.joints, start=position, start_velocity=velocity)
    near = MAPPING.pose(J2.upper - 0.05)
    with pytest.raises(MotionLimitError, match="braking to rest: joint_2 would reach .* beyond its upper limit 2.71"):
        plan_stop(near, velocity, np.zeros(6), ROBOT.joints)


def test_transition_reaches_the_target_state():
    joints = ROBOT.joints
    target = MAPPING.pose(-1.0)
    motion = plan_transition(MAPPING.pose(0.0), np.zeros(6), np.zeros(6), target, np.zeros(6), joints,
                             period=0.002)
    np.testing.assert_allclose(motion.positions[-1], target, atol=1e-12)
    check_trajectory(motion, joints, start=MAPPING.pose(0.0))
    same = plan_transition(target, np.zeros(6), np.zeros(6), target, np.zeros(6), joints)
    assert len(same) == 1


def test_a_joint_without_acceleration_limits_is_refused_by_name():
    joints = [Joint("a", -1.0, 1.0, 1.0)]
    with pytest.raises(Exception, match="joint a has no max_acceleration"):
        plan_stop([0.0], [0.5], [0.0], joints)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(first=st.floats(-1.4, 1.0), travel=st.floats(0.05, 1.5), speed=st.just(0.0) | st.floats(0.05, 2.79),
       start=st.floats(-1.4, 2.6), period=st.sampled_from([0.002, 0.004, 0.01]))
def test_planned_throws_pass_the_check(first, travel, speed, start, period):
    throw = mapped_throw(first, min(first + travel, J2.upper - 0.001), speed, points=12)
    arm = MAPPING.pose(start)
    try:
        planned = plan_throw(throw, ROBOT.joints, start=arm, period=period)
    except MotionLimitError as exc:  # only for want of room: to brake, or to wind up
        release, travel = throw.positions[-1, 1], throw.positions[-1, 1] - throw.positions[0, 1]
        needed = speed**2 / (2 * J2.max_acceleration) + 0.2  # + what the jerk limit adds, generously
        if "no room to brake" in str(exc):
            assert J2.upper - release < needed
        else:  # the path is too short to reach the release speed: winding up passes the lower limit
            assert "the throw (start to release): joint_2 would reach" in str(exc) and "lower limit" in str(exc)
            assert travel + throw.positions[0, 1] - J2.lower < needed
        return
    check_trajectory(planned, ROBOT.joints, start=arm)
    assert require_release(Path("planned.json"), planned).release_time == planned.release_time  # read back as it is
    release = int(np.flatnonzero(planned.time == planned.release_time)[0])
    np.testing.assert_allclose(planned.velocities[release], throw.velocities[-1], atol=1e-9)
    np.testing.assert_allclose(planned.positions[release], throw.positions[-1], atol=1e-9)
    assert finite_jerk(planned)[1] <= J2.max_jerk * (1 + 1e-6)


@pytest.mark.parametrize(("first", "release", "speed"), [(-1.3, -0.3, 2.25), (-1.0, 0.4, 1.0), (0.2, -0.6, 2.7)])
def test_the_throw_is_no_faster_than_toppras_time_optimum_and_jerk_costs_little(first, release, speed):
    """Cross-check with toppra: the time-optimal motion along the same path from rest to the same
    release, under the same velocity and acceleration limits but no jerk limit, is a lower bound
    of the planned throw's duration; the jerk limit adds at most max_acceleration / max_jerk."""
    import toppra
    import toppra.algorithm
    import toppra.constraint

    toppra.setup_logging("ERROR")
    planned = plan_throw(mapped_throw(first, release, speed), ROBOT.joints)
    throw_duration = planned.release_time  # no approach: the arm starts at the throw's first pose
    acceleration = MARGIN * J2.max_acceleration
    path = toppra.SplineInterpolator([0.0, 1.0], [[first], [release]])
    constraints = [toppra.constraint.JointVelocityConstraint(np.array([[-speed, speed]])),
                   toppra.constraint.JointAccelerationConstraint(np.array([[-acceleration, acceleration]]))]
    optimum = toppra.algorithm.TOPPRA(constraints, path, gridpoints=np.linspace(0.0, 1.0, 801),
                                      parametrizer="ParametrizeConstAccel")
    bound = optimum.compute_trajectory(0.0, speed / abs(release - first)).duration
    assert bound - 0.002 <= throw_duration <= bound + J2.max_acceleration / J2.max_jerk + 0.002


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(position=st.floats(-1.4, 2.6), speed=st.floats(-0.99, 0.99), acceleration=st.floats(-0.9, 0.9),
       target=st.one_of(st.none(), st.floats(-1.4, 2.6)), period=st.sampled_from([0.002, 0.01]))
def test_stops_and_transitions_from_any_state_pass_the_check(position, speed, acceleration, target, period):
    """What the live server's cancel, preemption and approach ask of the planner: from any state
    within the limits, brake (or go to a pose) within them, or refuse for want of room."""
    state = MAPPING.pose(position)
    velocity, accel = np.zeros(6), np.zeros(6)
    velocity[1], accel[1] = speed * J2.max_velocity, acceleration * J2.max_acceleration
    # still accelerating towards the speed limit, the jerk limit lets the speed grow by a^2 / 2j first
    overshoot = velocity[1] + accel[1] * abs(accel[1]) / (2 * J2.max_jerk)
    try:
        if target is None:
            motion = plan_stop(state, velocity, accel, ROBOT.joints, period=period)
        else:
            motion = plan_transition(state, velocity, accel, MAPPING.pose(target), np.zeros(6), ROBOT.joints,
                                     period=period)
            np.testing.assert_allclose(motion.positions[-1], MAPPING.pose(target), atol=1e-12)
    except MotionLimitError as exc:
        if "rad/s (t = " in str(exc):  # beyond the speed limit: only from a state that must overshoot
            assert abs(overshoot) > 0.99 * J2.max_velocity and "cannot turn the acceleration round" in str(exc)
        else:
            assert "beyond its" in str(exc) and "limit" in str(exc) and "joint_2" in str(exc)
        return
    assert abs(overshoot) <= J2.max_velocity * 1.001
    check_trajectory(motion, ROBOT.joints, start=state, start_velocity=velocity)
    assert np.all(motion.velocities[-1] == 0)
    assert len(motion) == 1 or finite_jerk(motion)[1] <= J2.max_jerk * (1 + 1e-6)
