"""Interrupt rlff's ROS 1 client while it makes the goal message, before anything is published,
and print as JSON what the interrupt says became of the goal.

Used by tests/test_ros1_live.py as a separate process (a rospy node lives once per process):
``python tests/ros1_interrupted_before_sending.py``. A Ctrl-C there had been marked "the cancel
was not confirmed ... e-stop it" (and ``goal_sent`` true in ``robot send --json``) although no
goal had gone out.
"""

from __future__ import annotations  # noqa: I001 - rlff.robot.ros1 first, see tests/ros1_goal.py

import json

import rlff.robot.ros1  # noqa: F401 - Debian's ROS 1 before the ROS 2 wheels of the same names
import numpy as np

from rlff.errors import Interrupted
from rlff.robot import load_robot
from rlff.robot.ros1 import client
from rlff.robot.send import goal_fate
from rlff.trajectory.planner import plan_transition


def _interrupted(*args, **kwargs):
    raise Interrupted()  # Ctrl-C while the goal message is made


def main() -> None:
    robot = load_robot()
    pose, _ = client.arm_state(robot)
    rest = np.zeros_like(pose)
    target = pose.copy()
    target[1] += 0.1
    client.to_msg = _interrupted
    try:
        client.send_goal(robot, plan_transition(pose, rest, rest, target, rest, robot.joints), pose, timeout=20.0)
    except KeyboardInterrupt as exc:
        print(json.dumps({"interrupted": True, "fate": goal_fate(exc)}))
        return
    print(json.dumps({"interrupted": False}))


if __name__ == "__main__":
    main()
