"""What a robot file without a ``[ros]`` table leaves to rlff's defaults, said once where it matters."""

from __future__ import annotations

import pytest

from rlff.robot import load_robot
from rlff.robot.ros_defaults import bag_defaults_note, ros_defaults_note


@pytest.mark.parametrize("fmt", ["ros1-bag", "ros2-bag"])
def test_a_bag_of_a_robot_file_without_a_ros_table_names_the_topic_it_is_written_on(tmp_path, fmt):
    # rlff learn --out and rlff robot export each spelled this out; one helper says it for both
    from robotfiles import unnamed_arm

    plain = load_robot(unnamed_arm(tmp_path))
    note = bag_defaults_note(plain, fmt)
    assert note == ros_defaults_note(plain, "the bag is written", ("trajectory_topic",))
    assert note.startswith(f"{plain.source} has no [ros] table: the bag is written with rlff's defaults, the Comau "
                           f"driver's trajectory_topic {plain.ros.trajectory_topic}, ")


@pytest.mark.parametrize("fmt", ["json", "csv", "comau"])
def test_a_file_that_carries_no_ros_name_says_nothing(tmp_path, fmt):
    from robotfiles import unnamed_arm

    assert bag_defaults_note(load_robot(unnamed_arm(tmp_path)), fmt) is None


def test_a_robot_file_that_names_its_controller_says_nothing():
    assert bag_defaults_note(load_robot("comau_smart5_six"), "ros2-bag") is None
