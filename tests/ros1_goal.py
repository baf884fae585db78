"""Send one raw FollowJointTrajectory goal, as any ROS client could, and print its result as JSON.

Used by tests/test_ros1_safety.py as a separate process (a rospy node lives once per process):
``python tests/ros1_goal.py GOAL.json [--cancel-after S]``, GOAL.json holding ``joint_names``,
``time`` (T,), ``positions`` (T, J) and optionally ``velocities`` (T, J) and ``stamp`` (s of ROS
time, 0: on receipt); the result's JSON also lists the joint names its feedback carried. It bypasses rlff's client and its checks, so the server's own are tested.
"""

from __future__ import annotations  # noqa: I001 - rlff.robot.ros1 first, see below

import argparse
import json
import sys

import rlff.robot.ros1  # noqa: F401 - Debian's ROS 1 before the ROS 2 wheels of the same names
import actionlib
import rospy
from control_msgs.msg import FollowJointTrajectoryAction, FollowJointTrajectoryGoal
from trajectory_msgs.msg import JointTrajectoryPoint

ACTION = "/comau_controller/follow_joint_trajectory"
STATES = {2: "preempted", 3: "succeeded", 4: "aborted", 5: "rejected", 8: "recalled", 9: "lost"}


def main() -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("goal")
    parser.add_argument("--cancel-after", type=float, default=None)
    args = parser.parse_args()
    spec = json.loads(open(args.goal).read())
    rospy.init_node("rlff_test_goal", anonymous=True, disable_signals=True)
    client = actionlib.SimpleActionClient(ACTION, FollowJointTrajectoryAction)
    if not client.wait_for_server(rospy.Duration(30)):
        print(json.dumps({"status": "no server"}))
        return 1
    goal = FollowJointTrajectoryGoal()
    goal.trajectory.joint_names = spec["joint_names"]
    goal.trajectory.header.stamp = rospy.Time.from_sec(spec.get("stamp", 0.0))
    velocities = spec.get("velocities") or [[0.0] * len(spec["joint_names"])] * len(spec["time"])
    goal.trajectory.points = [
        JointTrajectoryPoint(positions=p, velocities=v, time_from_start=rospy.Duration.from_sec(t))
        for t, p, v in zip(spec["time"], spec["positions"], velocities, strict=True)]
    feedback_names: list[list[str]] = []
    client.send_goal(goal, feedback_cb=lambda feedback: feedback_names.append(list(feedback.joint_names)))
    if args.cancel_after is not None:
        if client.wait_for_result(rospy.Duration.from_sec(args.cancel_after)):
            print(json.dumps({"status": "ended before the cancel"}))
            return 1
        cancelled = rospy.get_time()
        client.cancel_goal()
        client.wait_for_result(rospy.Duration(30))
        answered = rospy.get_time() - cancelled
    else:
        client.wait_for_result(rospy.Duration(120))
        answered = None
    result = client.get_result()
    print(json.dumps({"status": STATES.get(client.get_state(), str(client.get_state())),
                      "error_code": None if result is None else result.error_code,
                      "error_string": "" if result is None else result.error_string,
                      "cancel_answered_after": answered,
                      "feedback_joint_names": [list(n) for n in dict.fromkeys(map(tuple, feedback_names))]}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
