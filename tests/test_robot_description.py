"""Robot files: the built-in Comau Smart5 SiX, other files, and clear errors on bad ones."""

from __future__ import annotations

import re

import numpy as np
import pytest

from rlff.errors import InputError
from rlff.robot import available_robots, load_robot
from rlff.robot.description import Joint

COMAU_LIMITS = {  # rad, rad, rad/s (the numbers), rad/s^2, rad/s^3 (conservative choices)
    "joint_1": (-2.967, 2.967, 2.443, 10.0, 100.0),
    "joint_2": (-1.48, 2.71, 2.792, 11.0, 110.0),
    "joint_3": (-2.967, 0.0, 2.967, 12.0, 120.0),
    "joint_4": (-3.67, 3.67, 7.854, 30.0, 300.0),
    "joint_5": (-2.27, 2.27, 6.545, 26.0, 260.0),
    "joint_6": (-47.12, 47.12, 9.6, 38.0, 380.0),
}

MINIMAL = """
name = "two_link"
[[joints]]
name = "a"
lower = -1.0
upper = 1.0
max_velocity = 2.0
max_acceleration = 8.0
max_jerk = 80.0
[[joints]]
name = "b"
lower = -0.5
upper = 0.5
max_velocity = 1.0
max_acceleration = 4.0
max_jerk = 40.0
"""


def test_builtin_comau_has_the_limits_and_geometry():
    robot = load_robot()
    assert robot.name == "comau_smart5_six" and "comau_smart5_six" in available_robots()
    assert robot.joint_names == tuple(COMAU_LIMITS)
    for joint in robot.joints:
        assert (joint.lower, joint.upper, joint.max_velocity, joint.max_acceleration,
                joint.max_jerk) == COMAU_LIMITS[joint.name]
    g = robot.geometry
    assert (g.shoulder_height, g.shoulder_forward, g.upper_arm, g.elbow_offset, g.forearm, g.flange) == (
        0.45, 0.15, 0.59, 0.13, 0.647, 0.095)
    lower, upper, vmax = robot.limits(["joint_2", "joint_3"])
    np.testing.assert_array_equal(lower, [-1.48, -2.967])
    np.testing.assert_array_equal(vmax, [2.792, 2.967])


def test_another_robot_is_another_file(tmp_path):
    path = tmp_path / "two_link.toml"
    path.write_text(MINIMAL)
    robot = load_robot(path)
    assert robot.joint_names == ("a", "b") and robot.geometry is None and robot.source == str(path)
    assert robot.joint("b") == Joint("b", -0.5, 0.5, 1.0, 4.0, 40.0)
    assert load_robot(str(path)).joints == robot.joints


def test_a_robot_file_saved_with_a_byte_order_mark_is_read(tmp_path):
    """Notepad saves UTF-8 with a byte-order mark: the file was refused as "not valid TOML: Invalid
    statement (at line 1, column 1)", though CSVs and manifests with one are read."""
    path = tmp_path / "two_link.toml"
    path.write_bytes(b"\xef\xbb\xbf" + MINIMAL.encode("utf-8"))
    robot = load_robot(path)
    assert robot.joint_names == ("a", "b") and robot.joint("b") == Joint("b", -0.5, 0.5, 1.0, 4.0, 40.0)


@pytest.mark.parametrize("field", ["lower", "upper", "max_velocity", "max_acceleration", "max_jerk"])
def test_missing_limit_names_the_file_joint_and_field(tmp_path, field):
    path = tmp_path / "broken.toml"
    path.write_text(MINIMAL.replace(f"{field} = ", f"# {field} = ", 2).replace(f"# {field} = ", f"{field} = ", 1))
    with pytest.raises(InputError, match=rf"broken.toml: joint 2 \(b\): missing field '{field}'"):
        load_robot(path)


def test_bad_values_are_refused(tmp_path):
    path = tmp_path / "r.toml"
    path.write_text(MINIMAL.replace("upper = 1.0", "upper = -2.0"))
    with pytest.raises(InputError, match=r"r.toml: joint 1 \(a\): lower limit -1.0 is not below upper -2.0"):
        load_robot(path)
    path.write_text(MINIMAL.replace("max_velocity = 2.0", 'max_velocity = "fast"'))
    with pytest.raises(InputError, match="'max_velocity' must be a finite number"):
        load_robot(path)
    path.write_text(MINIMAL.replace("max_jerk = 80.0", "max_jerk = -1.0"))
    with pytest.raises(InputError, match=r"r.toml: joint 1 \(a\): max_jerk must be positive and finite, got -1.0"):
        load_robot(path)
    path.write_text(MINIMAL.replace('name = "b"', 'name = "a"'))
    with pytest.raises(InputError, match=r"r.toml: joint 2 \(a\): joint 1 has that name too"):
        load_robot(path)
    path.write_text("name = 'x'\n[[joints]\n")
    with pytest.raises(InputError, match="not valid TOML"):
        load_robot(path)


def test_unknown_robot_and_joint_are_named():
    with pytest.raises(InputError, match="unknown robot 'kuka'.*comau_smart5_six"):
        load_robot("kuka")
    with pytest.raises(InputError, match="cannot read robot file"):
        load_robot("/nonexistent/robot.toml")
    with pytest.raises(InputError, match="unknown joint 'joint_7'.*joint_1, joint_2"):
        load_robot().joint("joint_7")


def _builtin_text() -> str:
    from importlib import resources

    return (resources.files("rlff") / "robots" / "comau_smart5_six.toml").read_text(encoding="utf-8")


@pytest.mark.parametrize(("edit", "message"), [
    (("[comau_program]", "[comau_progam]"), r"unknown field 'comau_progam' \(did you mean 'comau_program'\?\)"),
    (("position_slot = 3", "position_slott = 2"),
     r"\[comau_program\]: unknown field 'position_slott' \(did you mean 'position_slot'\?\)"),
    (("max_velocity = 2.792", "max_velocity = 2.792\nmax_velcoity = 9.0"),
     r"joint 2 \(joint_2\): unknown field 'max_velcoity' \(did you mean 'max_velocity'\?\)"),
    (("velocity_scale = 0.25", "velocity_scale = 0.25\nspeed = 2"), r"\[throwing\]: unknown field 'speed' \(known: "),
    (("scale = 0.851", "scale = 0.851\nsclae = 1"), r"\[whole_arm.joints.joint_2\]: unknown field 'sclae'"),
    (("[throwing.start_pose]\njoint_1 = 0.0", "[throwing.start_pose]\njoint_7 = 0.0\njoint_1 = 0.0"),
     r"\[throwing.start_pose\] names 'joint_7', not a joint of the robot"),
    (("upper_arm = 0.59", "upper_arm = -0.59"), r"\[geometry\] upper_arm is a length and must be positive \(m\), got -0.59"),
    (("flange = 0.095", "flange = -0.01"), r"\[geometry\] flange is a length and must be zero or more"),
], ids=["table", "comau-key", "joint-key", "throwing-key", "whole-arm-key", "start-pose-joint", "negative-arm",
        "negative-flange"])
def test_a_misspelt_key_or_an_impossible_length_is_refused_by_name(tmp_path, edit, message):
    """A key no table holds would be ignored and its default used (a Comau program's slot, a
    joint's speed limit): the file is refused, naming it and the nearest known key."""
    text = _builtin_text()
    assert edit[0] in text
    path = tmp_path / "mine.toml"
    path.write_text(text.replace(edit[0], edit[1], 1))
    with pytest.raises(InputError, match=rf"mine.toml: .*{message}"):
        load_robot(path)


@pytest.mark.parametrize(("edit", "message"), [
    # the misspelt key stood where the field it misses belongs: "missing field 'max_velocity'" named the wrong fault
    (("max_velocity = 2.792", "max_velocty = 2.792"),
     r"joint 2 \(joint_2\): unknown field 'max_velocty' \(did you mean 'max_velocity'\?\)"),
    (("max_jerk = 110.0", "max_jrek = 110.0"), r"joint 2 \(joint_2\): unknown field 'max_jrek' \(did you mean 'max_jerk'\?\)"),
    (('name = "joint_2"', 'nmae = "joint_2"'), r"joint 2: unknown field 'nmae' \(did you mean 'name'\?\)"),
    (("upper_arm = 0.59", "upper_ram = 0.59"), r"\[geometry\]: unknown field 'upper_ram' \(did you mean 'upper_arm'\?\)"),
    (("angle_scale = ", "angle_scael = "), r"\[throwing\]: unknown field 'angle_scael' \(did you mean 'angle_scale'\?\)"),
], ids=["joint-limit", "joint-jerk", "joint-name", "geometry", "throwing"])
def test_a_misspelt_key_is_named_before_the_field_it_misses(tmp_path, edit, message):
    text = _builtin_text()
    assert edit[0] in text
    path = tmp_path / "mine.toml"
    path.write_text(text.replace(edit[0], edit[1], 1))
    with pytest.raises(InputError) as refused:
        load_robot(path)
    assert re.fullmatch(rf"{re.escape(str(path))}: {message}", str(refused.value)), str(refused.value)


@pytest.mark.parametrize(("edit", "message"), [
    # inf was "more than eight turns ... is this file in degrees?"
    (("upper = 2.71", "upper = inf"), "field 'upper' must be a finite number, got inf"),
    (("lower = -1.48", "lower = -inf"), "field 'lower' must be a finite number, got -inf"),
    (("max_velocity = 2.792", "max_velocity = inf"), "field 'max_velocity' must be a finite number, got inf"),
    (("upper = 2.71", "upper = nan"), "field 'upper' must be a finite number, got nan"),
], ids=["upper-inf", "lower-inf", "speed-inf", "upper-nan"])
def test_a_limit_that_is_no_finite_number_is_named_so(tmp_path, edit, message):
    path = tmp_path / "mine.toml"
    path.write_text(_builtin_text().replace(edit[0], edit[1], 1))
    with pytest.raises(InputError) as refused:
        load_robot(path)
    assert str(refused.value) == f"{path}: joint 2 (joint_2): {message}"


def test_a_mapping_error_names_the_file_and_its_table(tmp_path):
    path = tmp_path / "mine.toml"
    path.write_text(_builtin_text().replace('joint = "joint_2"', 'joint = "joint2"', 1))
    with pytest.raises(InputError, match=r"mine.toml: \[throwing\]: unknown joint 'joint2'"):
        from rlff.robot.mapping import RobotMapping

        RobotMapping.for_robot(load_robot(path))


def test_a_geometry_built_in_code_is_held_to_the_same_lengths():
    from rlff.robot.description import Geometry

    with pytest.raises(InputError, match=r"\[geometry\] forearm is a length and must be positive \(m\), got 0"):
        Geometry(shoulder_height=0.45, shoulder_forward=0.15, upper_arm=0.59, elbow_offset=0.13, forearm=0.0,
                 flange=0.095)
    Geometry(shoulder_height=0.0, shoulder_forward=-0.1, upper_arm=0.59, elbow_offset=-0.13, forearm=0.6, flange=0.0)


def test_the_ros_names_default_to_the_comau_driver_s_and_the_shipped_file_states_them(tmp_path):
    from rlff.robot.description import RosNames

    path = tmp_path / "two_link.toml"
    path.write_text(MINIMAL)  # a robot file from before [ros]: nothing changes for it
    plain = load_robot(path)
    assert (plain.ros.action, plain.ros.joint_states, plain.ros.trajectory_topic) == (
        "/comau_controller/follow_joint_trajectory", "/joint_states", "/comau/joint_trajectory")
    assert plain.ros_origin("action") == f"rlff's default; {path} has no [ros] action"
    shipped = load_robot()
    assert shipped.ros == plain.ros == RosNames()  # the shipped table writes the defaults out
    assert shipped.ros_origin("joint_states") == "the [ros] joint_states of built-in robot comau_smart5_six"


def test_a_ros_table_names_the_arm_s_controller(tmp_path):
    path = tmp_path / "ur.toml"
    path.write_text(MINIMAL + '[ros]\naction = "/scaled_joint_trajectory_controller/follow_joint_trajectory"\n'
                              'joint_states = "/arm/joint_states"\n')
    robot = load_robot(path)
    assert robot.ros.action == "/scaled_joint_trajectory_controller/follow_joint_trajectory"
    assert robot.ros.joint_states == "/arm/joint_states"
    assert robot.ros.trajectory_topic == "/comau/joint_trajectory"  # not given: the default
    assert robot.ros_origin("action") == f"the [ros] action of {path}"
    assert robot.ros_origin("trajectory_topic") == f"rlff's default; {path} has no [ros] trajectory_topic"
    for name in ("/a", "/_hidden/A9_z", "/arm__two/x_"):
        path.write_text(MINIMAL + f'[ros]\ntrajectory_topic = "{name}"\n')
        assert load_robot(path).ros.trajectory_topic == name


@pytest.mark.parametrize(("value", "fault"), [
    ('"arm/joint_states"', "is relative: each node would resolve it in its own namespace"),
    ('"~/joint_states"', "is relative: each node would resolve it in its own namespace"),
    ('""', "is empty"),
    ('"/"', "ends with '/'"),
    ('"/arm/"', "ends with '/'"),
    ('"/arm//joint_states"', r"has an empty segment \('//'\)"),
    ('"/arm/2nd_joint_states"', r"has a segment starting with a digit \('2nd_joint_states'\)"),
    ('"/arm-1/joint_states"', "has the character '-'"),
    ('"/arm/joint states"', "has the character ' '"),
    ('"/bras/états"', "has the character 'é'"),
    ("3", "is not a string"),
    (f'"/{"a" * 200}"', "is longer than 200 characters"),
], ids=["relative", "private", "empty", "root", "trailing-slash", "double-slash", "digit", "dash", "space",
        "non-ascii", "number", "too-long"])
def test_a_bad_ros_name_is_refused_naming_the_file_the_key_and_a_good_one(tmp_path, value, fault):
    path = tmp_path / "mine.toml"
    path.write_text(MINIMAL + f"[ros]\njoint_states = {value}\n")
    with pytest.raises(InputError) as refused:
        load_robot(path)
    assert re.fullmatch(rf"{re.escape(str(path))}: \[ros\] joint_states .* {fault}; give an absolute ROS name, '/' and "
                        r"segments of letters, digits and '_' \(none starting with a digit\), e.g. '/arm/joint_states'",
                        str(refused.value)), str(refused.value)


def test_an_unknown_key_in_the_ros_table_is_refused_by_name(tmp_path):
    path = tmp_path / "mine.toml"
    path.write_text(MINIMAL + '[ros]\nacton = "/arm/follow_joint_trajectory"\n')
    with pytest.raises(InputError, match=r"mine.toml: \[ros\]: unknown field 'acton' \(did you mean 'action'\?\)"):
        load_robot(path)
    path.write_text(MINIMAL + '[ros]\nstated = ["action"]\n')  # the dataclass' own field is no key of the file
    with pytest.raises(InputError, match=r"\[ros\]: unknown field 'stated' \(known: action, joint_states, "
                                         r"trajectory_topic, joints\)"):
        load_robot(path)
    path.write_text('ros = "/arm"\n' + MINIMAL)
    with pytest.raises(InputError, match=r"mine.toml: \[ros\] must be a table, got '/arm'"):
        load_robot(path)


def test_ros_names_given_in_code_are_checked_and_named_as_the_robot_s():
    from rlff.robot.description import Robot, RosNames

    robot = Robot("x", (Joint("a", -1.0, 1.0, 1.0),), ros=RosNames(action="/arm/follow_joint_trajectory"))
    assert robot.ros_origin("action") == "the [ros] action of <memory>"
    assert robot.ros_origin("joint_states") == "rlff's default; <memory> has no [ros] joint_states"
    with pytest.raises(InputError, match=r"^\[ros\] trajectory_topic '/arm/' ends with '/'; give an absolute ROS "
                                         r"name, .* e.g. '/arm/joint_trajectory'$"):
        RosNames(trajectory_topic="/arm/")


def test_the_throwing_joint_in_the_throwing_start_pose_is_warned_of_as_unused(tmp_path):
    from rlff.robot.description import RobotFileWarning

    path = tmp_path / "mine.toml"
    path.write_text(_builtin_text().replace("[throwing.start_pose]\njoint_1 = 0.0",
                                            "[throwing.start_pose]\njoint_2 = 0.3\njoint_1 = 0.0", 1))
    with pytest.warns(RobotFileWarning, match=r"mine.toml: \[throwing.start_pose\] gives joint_2, the throwing joint: "
                                              r"its start is the throw's first angle, and joint_2 = 0.3 is not used"):
        robot = load_robot(path)
    assert robot.warnings[-1].endswith("joint_2 = 0.3 is not used")
    assert not any("start_pose" in said for said in load_robot().warnings)  # the built-in's whole_arm names its own
