"""A ROS 2 arm driver that accepts a FollowJointTrajectory goal and then says nothing: no feedback,
no result (tests/test_ros2_client.py kills it after the acceptance, as a crashed driver).

Run as ``python ros2_mute_server.py P1,P2,...,P6`` (the pose, rad) with ROS_DOMAIN_ID set; it
publishes that pose on /joint_states at 20 Hz and prints ``accepted`` when a goal is accepted.
The test's own rclpy with the generated control_msgs type, independent of rlff's code.
"""

from __future__ import annotations

import sys
import time

import rclpy
from control_msgs.action import FollowJointTrajectory
from rclpy.action import ActionServer, CancelResponse, GoalResponse
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.executors import MultiThreadedExecutor
from sensor_msgs.msg import JointState

ACTION = "/comau_controller/follow_joint_trajectory"
NAMES = [f"joint_{i}" for i in range(1, 7)]


def main() -> None:
    pose = [float(value) for value in sys.argv[1].split(",")]
    rclpy.init()
    node = rclpy.create_node("test_mute_driver")
    group = ReentrantCallbackGroup()

    def execute(handle):
        print("accepted", flush=True)
        time.sleep(600)  # killed long before
        handle.abort()
        return FollowJointTrajectory.Result(error_code=-1, error_string="gave up")

    ActionServer(node, FollowJointTrajectory, ACTION, execute, goal_callback=lambda goal: GoalResponse.ACCEPT,
                 cancel_callback=lambda handle: CancelResponse.ACCEPT, callback_group=group)
    publisher = node.create_publisher(JointState, "/joint_states", 10)

    def publish() -> None:
        msg = JointState(name=NAMES, position=pose, velocity=[0.0] * 6)
        msg.header.stamp = node.get_clock().now().to_msg()
        publisher.publish(msg)

    node.create_timer(0.05, publish, callback_group=group)
    executor = MultiThreadedExecutor(num_threads=3)
    executor.add_node(node)
    print("serving", flush=True)
    executor.spin()


if __name__ == "__main__":
    main()
