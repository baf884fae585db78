"""What a send says of its goal around the motion check: a timeout too short for the motion, an
interrupt's outcome, an approach that cannot be planned (no ROS: the live cases are in
tests/test_ros1_live.py and tests/test_ros2_client.py)."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import numpy as np
import pytest

from rlff.errors import InputError
from rlff.robot import load_robot

ROBOT = load_robot()
NAMES = list(ROBOT.joint_names)
POSE = np.array([0.0, 0.5, -1.0, 0.0, 0.0, 0.0])


def test_a_timeout_shorter_than_the_motion_is_said_before_the_goal_goes_out():
    # --timeout 2 on a 3.03 s goal: the arm started and was braked 1.7 s in, without a word before
    from rlff.robot.send import short_timeout
    from rlff.trajectory.joint import JointTrajectory

    traj = JointTrajectory(NAMES, [0.0, 3.03], np.tile(POSE, (2, 1)), np.zeros((2, 6)))
    assert short_timeout(2.0, traj) == ("timeout (--timeout) 2 s is shorter than the motion (3.030 s): the goal will be "
                                        "cancelled mid-motion and the arm braked to rest (leave the timeout out to "
                                        "wait for the whole motion)")
    assert short_timeout(None, traj) is None and short_timeout(3.03, traj) is None


#: A child process (one ROS per process: rlff.robot.rospath) that calls the ROS ``argv[1]`` client's
#: entry points with timeouts that are no time, with whatever would start ROS made to fail, and
#: prints what each raised.
_NO_TIME_CHILD = """
import json, math, sys
import numpy as np
from rlff.robot import load_robot
from rlff.trajectory.joint import JointTrajectory

def started(*args, **kwargs):
    raise RuntimeError("ROS was started")

if sys.argv[1] == "1":
    import rlff.robot.ros1.client as client
    client._connect = started
    entries = {"arm_state": client.arm_state, "send_goal": client.send_goal,
               "publish_trajectory": client.publish_trajectory}
else:
    import rlff.robot.ros2.client as client
    unstarted = object.__new__(client.Connection)  # no node: a method that uses one fails
    client.Connection = started
    entries = {"arm_state": client.arm_state, "send_goal": client.send_goal,
               "Connection.arm_state": unstarted.arm_state, "Connection.send_goal": unstarted.send_goal}
robot = load_robot()
pose = np.array(json.loads(sys.argv[2]))
traj = JointTrajectory(robot.joint_names, [0.0, 3.03], np.tile(pose, (2, 1)), np.zeros((2, pose.size)))
said = {}
for name, call in entries.items():
    for timeout in (math.nan, math.inf, 0.0, -1.0):
        args = (robot, timeout) if name.endswith("arm_state") else (robot, traj, pose, timeout)
        try:
            call(*args)
        except Exception as exc:
            said[f"{name} {timeout:g}"] = f"{type(exc).__name__}: {exc}"
print(json.dumps(said))
"""


@pytest.mark.parametrize("ros", [1, 2])
def test_the_library_refuses_a_timeout_that_is_no_time_before_ros_starts(ros):
    # only `rlff robot send --timeout` was checked: send_goal(..., timeout=nan) went on to ROS
    from ros2rig import ros2_missing
    from rosrig import missing

    reason = missing() if ros == 1 else ros2_missing()
    if reason is not None:
        if os.environ.get("CI") == "true":
            pytest.fail(reason)
        pytest.skip(reason)
    child = subprocess.run([sys.executable, "-c", _NO_TIME_CHILD, str(ros), json.dumps(POSE.tolist())],
                           capture_output=True, text=True, timeout=120)
    assert child.returncode == 0, child.stderr
    said = json.loads(child.stdout)
    assert len(said) == (3 if ros == 1 else 4) * 4, said
    for call, message in said.items():
        timeout = call.split()[-1]
        assert message == (f"InputError: timeout {timeout}: give a finite number of seconds above 0, or leave "
                           "timeout out (10 s to connect, and the whole motion)"), call


def test_an_interrupt_that_stopped_the_wait_for_the_cancel_says_so_not_that_the_server_was_silent():
    # two quick Ctrl-Cs: the second stopped the wait 0.5 s in, and rlff said "no answer from the
    # server within 10 s" while the server had braked the arm and confirmed
    from rlff.robot.send import (
        CANCEL_NOT_AWAITED,
        CANCEL_UNCONFIRMED,
        GOAL_CANCELLED,
        interrupted_goal,
        mark_goal,
    )

    said = interrupted_goal(mark_goal(KeyboardInterrupt(), CANCEL_NOT_AWAITED))
    assert said == ("goal interrupted: the cancel went out, and a second interrupt stopped the wait for the server to "
                    "confirm it: the arm's state is unknown; check the arm (e-stop it if it moves)")
    assert "within 10 s" in interrupted_goal(mark_goal(KeyboardInterrupt(), CANCEL_UNCONFIRMED))
    assert interrupted_goal(mark_goal(KeyboardInterrupt(), GOAL_CANCELLED)) == "goal cancelled"
    assert interrupted_goal(KeyboardInterrupt()) is None


def test_an_approach_to_a_moving_start_is_refused_naming_the_joint_and_its_speed():
    # a file cut mid-motion: "the trajectory does not start at rest: no approach to its first point
    # is planned" named no joint, speed or way out
    from rlff.robot.sendfile import with_approach
    from rlff.trajectory.joint import JointTrajectory

    velocities = np.zeros((2, 6))
    velocities[0, 1] = 1.25
    positions = np.tile(POSE, (2, 1))
    positions[1, 1] += 0.05
    cut = JointTrajectory(NAMES, [0.0, 0.1], positions, velocities)
    with pytest.raises(InputError, match=r"^the trajectory does not start at rest \(joint_2 at 1\.25 rad/s at its first "
                                         r"point, t = 0\.000 s\): an approach ends at rest"):
        with_approach(ROBOT, cut, np.zeros(6), 0.01)
