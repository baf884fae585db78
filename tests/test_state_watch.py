"""StateWatch, the arm's state from joint states messages, fed by hand (no ROS): which messages
it takes, and which pairs of fresh messages it refuses as two publishers' (the live cases are in
tests/test_ros1_safety.py and tests/test_ros2_client.py)."""

from __future__ import annotations

import re
import threading
import time

import numpy as np
import pytest

from rlff.errors import InputError
from rlff.robot import load_robot
from rlff.robot.send import STATE_NOISE, STATE_SPAN, ArmStateError, StateWatch

ROBOT = load_robot()
NAMES = list(ROBOT.joint_names)
POSE = np.array([0.0, 0.5, -1.0, 0.0, 0.0, 0.0])
REST = [0.0] * 6
NOW = 1000.0  # s of ROS time: every message below is stamped within STATE_MAX_AGE of it
VMAX_2 = ROBOT.joint("joint_2").max_velocity  # 2.792 rad/s


def watch(info: str = "rostopic info") -> StateWatch:
    return StateWatch(ROBOT, lambda: NOW, info)


def taken(state: StateWatch, seconds: float = 0.05):
    return state.wait(time.monotonic() + seconds, seconds)


def moved(joint: int, by: float) -> list[float]:
    pose = POSE.copy()
    pose[joint] += by
    return pose.tolist()


def stream(state: StateWatch, pose=POSE, rate: float = 100.0, start: float = NOW, span: float = STATE_SPAN,
           velocity=REST) -> None:
    """Messages of one arm standing at ``pose``, ``rate`` per second over ``span`` s from ``start``."""
    for k in range(round(span * rate) + 1):
        state.offer(start + k / rate, NAMES, list(pose), velocity)


def test_one_fresh_message_is_not_enough_messages_0_1_s_apart_that_agree_are():
    state = watch()
    state.offer(NOW, NAMES, POSE.tolist(), REST)
    with pytest.raises(ArmStateError) as refused:
        taken(state)
    assert str(refused.value) == (
        "one fresh state on /joint_states within 0.05 s, and none 0.1 s after it: states 0.1 s apart that agree "
        "tell one arm's pose from two publishers'; have the arm's driver publish continuously")
    state.offer(NOW + 0.05, NAMES, POSE.tolist(), REST)
    with pytest.raises(ArmStateError, match=r"^2 fresh states on /joint_states within 0.05 s, their stamps within "
                                            r"0.05 s: states 0.1 s apart"):
        taken(state)
    state.offer(NOW + STATE_SPAN, NAMES, POSE.tolist(), REST)
    pose, velocity = taken(state)
    np.testing.assert_array_equal(pose, POSE)
    np.testing.assert_array_equal(velocity, REST)


def test_a_slow_driver_s_second_message_is_enough():
    # a driver at 2 Hz: its second message, 0.5 s after the first, is the state (the joint crept
    # 4 mrad: 0.008 rad/s, at rest as its velocity says)
    state = watch()
    state.offer(NOW, NAMES, POSE.tolist(), REST)
    state.offer(NOW + 0.5, NAMES, moved(1, 0.004), REST)
    pose, _ = taken(state)
    np.testing.assert_array_equal(pose, moved(1, 0.004))


@pytest.mark.parametrize("rate", [0.5, 0.05])
def test_positions_that_move_under_velocities_of_zero_are_a_moving_arm(rate):
    # a driver that fills velocities with zeros: joint_2 turning at 0.5 rad/s passed as at rest,
    # and a dry run said every check passed
    state = watch()
    for k in range(11):
        state.offer(NOW + 0.01 * k, NAMES, moved(1, rate * 0.01 * k), REST)
    with pytest.raises(ArmStateError, match=rf"^/joint_states reports joint_2 at 0 rad/s, but its position moved "
                                            rf"\+{rate * STATE_SPAN:.4g} rad in 0.100 s \({rate:.3g} rad/s\): the arm is "
                                            r"moving, or its driver's velocities are not its motion"):
        taken(state)


def test_the_last_pose_is_taken_when_the_joints_could_move_there():
    # joint_2 at its max velocity between messages 10 ms apart, and the noise allowance on top: one arm
    state = watch()
    step = VMAX_2 * 0.01 + 0.9 * STATE_NOISE
    for k in range(11):
        state.offer(NOW + 0.01 * k, NAMES, moved(1, -k * step), [0.0, -VMAX_2, 0.0, 0.0, 0.0, 0.0])
    pose, velocity = taken(state)
    np.testing.assert_array_equal(pose, moved(1, -10 * step))
    assert velocity[1] == -VMAX_2


def test_two_publishers_at_different_poses_are_refused_saying_what_jumped():
    state = watch("ros2 topic info")
    state.offer(NOW, NAMES, POSE.tolist(), REST)
    state.offer(NOW + 0.02, NAMES, moved(1, 0.8), REST)  # joint_2 0.8 rad further in 20 ms
    with pytest.raises(ArmStateError) as refused:
        taken(state)
    assert str(refused.value) == (
        "two fresh states on /joint_states disagree: joint_2 at 0.5 rad, then at 1.3 rad 0.02 s later by their "
        "stamps, 0.8 rad where its max velocity (2.792 rad/s) allows 0.0568: the arm's pose is unknown; two nodes "
        "likely publish the arm's joints on /joint_states (a simulator or a bag beside the arm's driver): "
        "`ros2 topic info /joint_states` lists them; stop all but the arm's driver")


def test_a_jump_just_beyond_the_joints_reach_is_refused_and_names_every_joint_that_jumped():
    state = watch()
    state.offer(NOW, NAMES, POSE.tolist(), REST)
    second = POSE.copy()
    second[1] += VMAX_2 * 0.02 + 1.1 * STATE_NOISE  # just beyond
    second[4] -= 0.3
    state.offer(NOW + 0.02, NAMES, second.tolist(), REST)
    with pytest.raises(ArmStateError) as refused:
        taken(state)
    said = str(refused.value)
    # the joint furthest beyond its reach is named with its numbers, the others after it
    assert re.search(r"disagree: joint_5 at 0 rad, then at -0.3 rad 0.02 s later by their stamps, 0.3 rad where "
                     r"its max velocity \(6.545 rad/s\) allows 0.132 \(and joint_2\): ", said), said
    assert "`rostopic info /joint_states` lists them" in said


def test_equal_stamps_at_different_poses_are_two_publishers():
    state = watch()
    state.offer(NOW, NAMES, POSE.tolist(), REST)
    state.offer(NOW, NAMES, moved(0, 0.01), REST)
    with pytest.raises(ArmStateError, match=r"joint_1 at 0 rad, then at 0.01 rad 0 s later by their stamps, "
                                            r"0.01 rad where its max velocity \(2.443 rad/s\) allows 0.001:"):
        taken(state)


def test_a_slower_second_publisher_is_seen_among_a_fast_driver_s_messages():
    # the driver at 100 Hz, a simulator at 10 Hz elsewhere, its first message 95 ms after the driver's
    state = watch()
    for k in range(11):
        state.offer(NOW + 0.01 * k, NAMES, POSE.tolist(), REST)
        if k == 9:
            state.offer(NOW + 0.095, NAMES, moved(1, -0.5), REST)
    with pytest.raises(ArmStateError, match=r"disagree: joint_2 at 0.5 rad, then at 0 rad 0.005 s later"):
        taken(state)


def test_a_refusal_is_final_whatever_comes_next():
    state = watch()
    state.offer(NOW, NAMES, POSE.tolist(), REST)
    state.offer(NOW + 0.01, NAMES, moved(1, 0.5), REST)
    stream(state, moved(1, 0.5), start=NOW + 0.02)  # the second publisher alone: agrees with itself
    with pytest.raises(ArmStateError, match="disagree"):
        taken(state)


def test_without_velocities_the_speed_is_the_change_over_the_span():
    state = watch()
    stream(state, velocity=[])
    pose, velocity = taken(state)
    np.testing.assert_array_equal(velocity, REST)
    # moving at 0.2 rad/s on joint_6
    state = watch()
    for k in range(11):
        state.offer(NOW + 0.01 * k, NAMES, moved(5, 0.002 * k), [])
    pose, velocity = taken(state)
    np.testing.assert_allclose(velocity, [0, 0, 0, 0, 0, 0.2], atol=1e-9)
    # a message of another publisher among them is refused, not averaged into a speed
    state = watch()
    state.offer(NOW, NAMES, POSE.tolist(), [])
    state.offer(NOW + 0.01, NAMES, POSE.tolist(), [])
    state.offer(NOW + 0.02, NAMES, moved(2, -0.4), [])
    with pytest.raises(ArmStateError, match="disagree: joint_3 at -1 rad, then at -1.4 rad 0.01 s later"):
        taken(state)


def test_without_velocities_too_short_a_span_says_so():
    state = watch()
    state.offer(NOW, NAMES, POSE.tolist(), [])
    with pytest.raises(ArmStateError, match=r"and whether it moves \(they carry no velocities\); have the arm's "
                                            r"driver publish continuously, with velocities$"):
        taken(state)


def test_stale_and_other_devices_messages_are_passed_over_not_compared():
    state = watch()
    state.offer(NOW - 5.0, NAMES, moved(1, 1.0), REST)  # stale, elsewhere: never the arm's pose
    state.offer(NOW, ["finger_joint"], [0.01], [0.0])  # a gripper's
    state.offer(NOW, NAMES, POSE.tolist(), REST)
    state.offer(NOW + 0.005, ["finger_joint"], [0.02], [0.0])
    state.offer(NOW + 0.1, NAMES, POSE.tolist(), REST)
    pose, _ = taken(state)
    np.testing.assert_array_equal(pose, POSE)


def test_one_arm_message_after_a_gripper_s_is_not_called_a_wrong_robot_file():
    # the grace for other devices' messages ends once one names every joint; its missing second is the error
    state = watch()
    state.offer(NOW, ["finger_joint"], [0.01], [0.0])
    state.offer(NOW, NAMES, POSE.tolist(), REST)
    with pytest.raises(ArmStateError, match="^one fresh state on /joint_states within"):
        taken(state)


def test_only_other_devices_messages_are_still_the_robot_file_s_fault():
    state = watch()
    state.offer(NOW, ["finger_joint"], [0.01], [0.0])
    state._partial = (time.monotonic() - 10.0, state._partial[1])  # its grace long over
    with pytest.raises(InputError, match="has no position of joint_1, .*, joint_6 \\(it names finger_joint\\)"):
        taken(state, 5.0)


def test_the_second_message_wakes_a_waiting_caller():
    state = watch()
    state.offer(NOW, NAMES, POSE.tolist(), REST)
    threading.Timer(0.2, lambda: state.offer(NOW + 0.1, NAMES, POSE.tolist(), REST)).start()
    started = time.monotonic()
    pose, _ = taken(state, 10.0)
    assert time.monotonic() - started < 5.0
    np.testing.assert_array_equal(pose, POSE)


def test_a_hold_keeps_comparing_and_takes_nothing_until_it_ends():
    # other publishers may not reach the subscription yet: a late one is still compared
    state = watch()
    state.hold(0.3)
    stream(state)
    state.offer(NOW + 0.11, NAMES, moved(1, 0.3), REST)  # the publisher heard late
    with pytest.raises(ArmStateError, match="disagree: joint_2 at 0.5 rad, then at 0.8 rad"):
        taken(state)
    # one arm alone: taken with its first message after the hold, even past the wait's deadline
    state = watch()
    state.hold(0.3)
    stream(state)
    threading.Timer(0.35, lambda: state.offer(NOW + 0.5, NAMES, POSE.tolist(), REST)).start()
    started = time.monotonic()
    np.testing.assert_array_equal(taken(state, 0.05)[0], POSE)
    assert 0.3 < time.monotonic() - started < 5.0


def test_a_hold_of_0_releases_the_state():
    state = watch()
    state.hold(60.0)
    stream(state)
    state.hold(0.0)  # every publisher heard
    state.offer(NOW + 0.11, NAMES, POSE.tolist(), REST)
    np.testing.assert_array_equal(taken(state)[0], POSE)

