"""The ROS 2 set-up: rclpy and the control_msgs interface import as they are, with the standard type.

The type hashes are those of control_msgs 6.8.0 (the Kilted-era release) built from its own
definition files with the same rosidl generators: equal hashes mean the same interface, which a
ros2_control controller's clients and servers match against.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import sysconfig
from pathlib import Path

import pytest

from ros2rig import require_ros2

pytestmark = [pytest.mark.ros2]

STANDARD_HASHES = {
    "control_msgs/action/FollowJointTrajectory":
        "RIHS01_ff29901b2693f5deb847e96084a1c2cdb26e70b7c847be21859b70a55fb29cf0",
    "control_msgs/msg/JointTolerance":
        "RIHS01_c254f9cece0f3b733017b6990fd46d1326e25242d6b8844398c97d9a88e7d648",
}

CHECK = """
from control_msgs.action import FollowJointTrajectory
import rclpy.action
fields = FollowJointTrajectory.Feedback.get_fields_and_field_types()
print(fields["index"], fields["multi_dof_index"])
"""


@pytest.fixture(scope="module", autouse=True)
def _installed():
    require_ros2()


def test_rclpy_and_the_action_import_with_no_environment():
    # no library path, and the wheels' bootstrapper marker set, as a Python started by anything
    env = {key: value for key, value in os.environ.items() if key not in ("LD_LIBRARY_PATH", "PYTHONPATH")}
    env["_ROS_WHEELS_BOOTSTRAP_COMPLETE"] = "1"
    done = subprocess.run([sys.executable, "-c", CHECK], env=env, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["int32", "int32"]  # control_msgs 6.x feedback
    site = Path(sysconfig.get_paths()["purelib"])
    assert not (site / "ros_wheels_bootstrapper.pth").exists()  # no re-exec of every Python


@pytest.mark.parametrize("type_name", sorted(STANDARD_HASHES))
def test_the_built_interface_has_the_standard_type_hash(type_name):
    package, kind, name = type_name.split("/")
    description = Path(sys.prefix) / "share" / package / kind / f"{name}.json"
    hashes = {entry["type_name"]: entry["hash_string"] for entry in json.loads(description.read_text())["type_hashes"]}
    assert hashes[type_name] == STANDARD_HASHES[type_name]


def test_a_process_that_looked_at_ros1_imports_ros2_messages_again():
    """One process, both ROS in turn (as a test worker does): each gets its own messages."""
    from rlff.robot import ros1, ros2

    if ros1.missing() is None:  # Debian's ROS 1 is installed: its trajectory_msgs is the one now
        import trajectory_msgs.msg

        assert hasattr(trajectory_msgs.msg.JointTrajectory, "_md5sum")
    assert ros2.missing() is None
    from sensor_msgs.msg import JointState
    from trajectory_msgs.msg import JointTrajectory

    assert hasattr(JointTrajectory, "get_fields_and_field_types") and not hasattr(JointTrajectory, "_md5sum")
    assert "header" in JointState.get_fields_and_field_types()
