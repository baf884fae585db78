"""Send several goals in a row through rlff's ROS 1 client in one process, then one the server
rejects at once, and print what became of each as JSON.

Used by tests/test_ros1_live.py as a separate process (a rospy node lives once per process):
``python tests/ros1_goals_in_a_row.py``. Each goal goes out with the send held for 0.3 s after
the goal is published, where actionlib's own thread may take the server's answer before the
sender has the goal's handle (about one goal in 25 unforced, "Got a transition callback on a goal
handle that we're not tracking"): a client that loses those answers loses the goals' acceptance,
and the rejected goal's end, which it then waits for until its timeout. The JSON also counts the
actionlib clients the goals were sent through.
"""

from __future__ import annotations  # noqa: I001 - rlff.robot.ros1 first, see tests/ros1_goal.py

import json
import time

import rlff.robot.ros1  # noqa: F401 - Debian's ROS 1 before the ROS 2 wheels of the same names
import actionlib
import numpy as np

from rlff.robot import load_robot
from rlff.robot.ros1.client import arm_state, send_goal
from rlff.trajectory.planner import plan_transition

DRIVEN = 1  # joint_2


def _held(send):
    def send_goal(self, *args, **kwargs):
        handle = send(self, *args, **kwargs)
        time.sleep(0.3)  # the goal is out, the server answers: the sender does not have the handle yet
        return handle
    return send_goal


def _counted(init):
    def __init__(self, *args, **kwargs):
        clients.append(self)
        init(self, *args, **kwargs)
    return __init__


clients: list = []
actionlib.ActionClient.send_goal = _held(actionlib.ActionClient.send_goal)
actionlib.ActionClient.__init__ = _counted(actionlib.ActionClient.__init__)


def main() -> None:
    robot = load_robot()
    pose, _ = arm_state(robot)
    rest = np.zeros_like(pose)
    results = []
    for step in (0.1, -0.1, 0.1):
        target = pose.copy()
        target[DRIVEN] += step
        accepted = []
        sent = send_goal(robot, plan_transition(pose, rest, rest, target, rest, robot.joints), pose, timeout=20.0,
                         on_accepted=lambda accepted=accepted: accepted.append(True))
        results.append({"status": sent.status, "accepted": bool(accepted)})
        pose = target
    away = pose.copy()
    away[DRIVEN] += 0.3  # not where the arm is: the server rejects the goal on receipt
    target = away.copy()
    target[DRIVEN] += 0.1
    rejected = send_goal(robot, plan_transition(away, rest, rest, target, rest, robot.joints), away, timeout=5.0)
    print(json.dumps({"goals": results, "rejected": rejected.status, "rejected_code": rejected.error_name,
                      "clients": len(clients)}))


if __name__ == "__main__":
    main()
