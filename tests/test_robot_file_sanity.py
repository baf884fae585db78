"""Robot files that would make a real arm move wrongly: joints out of controller order, degrees."""

from __future__ import annotations

import itertools
import math
import re
import warnings
from importlib import resources

import numpy as np
import pytest

from rlff.cli import main
from rlff.errors import InputError
from rlff.robot import load_robot
from rlff.robot.description import Robot, RobotFileWarning

COMAU = (resources.files("rlff") / "robots" / "comau_smart5_six.toml").read_text(encoding="utf-8")
#: The built-in file cut into its head (up to the first [[joints]]), its six tables and the rest.
_FIRST, _AFTER = COMAU.index("[[joints]]"), COMAU.index("[geometry]")
HEAD, TABLES, TAIL = COMAU[:_FIRST], COMAU[_FIRST:_AFTER].split("\n\n[[joints]]"), COMAU[_AFTER:]
TABLES = [TABLES[0]] + ["[[joints]]" + table for table in TABLES[1:]]


def comau_file(path, order=range(6), edit=lambda table: table):
    """The built-in Comau file with its [[joints]] tables in ``order`` (0-based), each passed
    through ``edit``; written to ``path``."""
    path.write_text(HEAD + "\n\n".join(edit(TABLES[k]).rstrip("\n") for k in order) + "\n\n" + TAIL)
    return path


def in_degrees(table):
    """A [[joints]] table with every limit written in degrees (deg, deg/s, deg/s^2, deg/s^3)."""
    return re.sub(r"^(lower|upper|max_\w+) = (\S+)$",
                  lambda m: f"{m[1]} = {round(math.degrees(float(m[2])), 1)}", table, flags=re.M)


def seven_joint_file(path, names):
    """A seven-joint arm whose joints have names of their own, listed in the order ``names``."""
    tables = [f'[[joints]]\nname = "{name}"\nlower = -2.0\nupper = 2.0\nmax_velocity = 2.0\n'
              f"max_acceleration = 8.0\nmax_jerk = 80.0\n" for name in names]
    path.write_text('name = "seven"\n' + "\n".join(tables))
    return path


def test_the_comau_file_cut_and_joined_again_is_the_built_in_robot(tmp_path):
    assert load_robot(comau_file(tmp_path / "same.toml")).joints == load_robot().joints


@pytest.mark.parametrize("order", [(1, 0, 2, 3, 4, 5), (0, 1, 2, 3, 5, 4), (5, 0, 1, 2, 3, 4)])
def test_joints_out_of_controller_order_are_refused_naming_the_file(tmp_path, order):
    path = comau_file(tmp_path / "reordered.toml", order)
    with pytest.raises(InputError, match=r"reordered\.toml: joint_\d is listed as joint \d; .*"
                                         r"list the \[\[joints\]\] tables in controller order, joint_1 first"):
        load_robot(path)


def test_the_command_line_refuses_a_reordered_file_in_one_line(tmp_path, capsys):
    path = comau_file(tmp_path / "reordered.toml", (1, 0, 2, 3, 4, 5))
    assert main(["robot", "show", "--robot", str(path)]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "reordered.toml: joint_2 is listed as joint 1" in err


def test_a_robot_built_in_code_is_held_to_the_same_order():
    joints = load_robot().joints
    with pytest.raises(InputError, match="mine: joint_2 is listed as joint 1"):
        Robot("mine", (joints[1], joints[0], *joints[2:]), source="mine")


def test_a_file_in_degrees_is_refused(tmp_path):
    path = comau_file(tmp_path / "degrees.toml", edit=in_degrees)
    with pytest.raises(InputError, match=r"degrees\.toml: joint 1 \(joint_1\): lower -170 rad is more than "
                                         r"eight turns .*rlff reads radians .*is this file in degrees\?"):
        load_robot(path)


def test_a_speed_in_degrees_is_refused_even_with_positions_in_radians(tmp_path):
    path = comau_file(tmp_path / "speed.toml",
                      edit=lambda table: table.replace("max_velocity = 2.792", "max_velocity = 160.0"))
    with pytest.raises(InputError, match=r"speed\.toml: joint 2 \(joint_2\): max_velocity 160 rad/s is faster "
                                         r"than any arm's joint .*is this file in degrees\?"):
        load_robot(path)


@pytest.mark.parametrize("limit", [2 * math.pi, 47.12, 8 * 2 * math.pi])
def test_a_joint_of_several_turns_loads(tmp_path, limit):
    """A UR joint turns ±2π, the Comau's joint 6 ±47.12 rad; eight turns is the bound itself."""
    path = comau_file(tmp_path / "turns.toml",
                      edit=lambda table: table.replace("lower = -3.67", f"lower = {-limit!r}")
                                              .replace("upper = 3.67", f"upper = {limit!r}"))
    assert load_robot(path).joint("joint_4").upper == limit


@pytest.mark.parametrize("names", [("a1", "a2", "a3", "a4", "a5", "a6", "a7"),
                                   ("a3", "a1", "a2", "a4", "a5", "a6", "a7"),
                                   ("a7", "a2", "a1", "a6", "a4", "a3", "a5")])
def test_a_seven_joint_arm_with_names_of_its_own_keeps_its_file_order(tmp_path, names):
    assert load_robot(seven_joint_file(tmp_path / "seven.toml", names)).joint_names == names


def test_every_order_of_joints_named_otherwise_loads(tmp_path):
    names = ("shoulder_pan", "shoulder_lift", "elbow", "wrist_1")
    for order in itertools.permutations(names):
        robot = load_robot(seven_joint_file(tmp_path / "four.toml", order))
        assert robot.joint_names == order
        np.testing.assert_array_equal(robot.limits()[0], -2.0)


def in_millimetres(text):
    """A robot file with its [geometry] lengths written in millimetres."""
    head, _, geometry = text.partition("[geometry]")
    geometry, separator, rest = geometry.partition("\n[")
    geometry = re.sub(r"^(\w+) = ([-\d.]+)", lambda m: f"{m[1]} = {float(m[2]) * 1000:g}", geometry, flags=re.M)
    return head + "[geometry]" + geometry + separator + rest


def test_a_geometry_in_millimetres_is_refused(tmp_path, capsys):
    # it loaded, and `sim reach` put the farthest basket 845,754 m away
    path = tmp_path / "mm.toml"
    path.write_text(in_millimetres(COMAU))
    with pytest.raises(InputError, match=r"mm\.toml: \[geometry\] shoulder_height 450 m is longer than any arm's "
                                         r"link \(5 m; .*\); rlff reads metres: is this file in millimetres\?"):
        load_robot(path)
    assert main(["sim", "reach", "--robot", str(path)]) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert "is this file in millimetres?" in line


@pytest.mark.parametrize(("key", "value", "refused"), [
    ("upper_arm", 5.01, True), ("forearm", 492.2, True), ("elbow_offset", -5.5, True), ("flange", 99.6, True),
    ("upper_arm", 4.68, False), ("shoulder_forward", -4.9, False), ("forearm", 5.0, False),
])
def test_no_geometry_length_is_longer_than_the_largest_arm_s(key, value, refused):
    from rlff.robot.description import Geometry

    lengths = dict(shoulder_height=0.45, shoulder_forward=0.15, upper_arm=0.59, elbow_offset=0.13, forearm=0.647,
                   flange=0.095)
    lengths[key] = value
    if refused:
        with pytest.raises(InputError, match=rf"^\[geometry\] {key} {value:g} m is longer than any arm's link"):
            Geometry(**lengths)
    else:
        assert getattr(Geometry(**lengths), key) == value


@pytest.mark.parametrize("command", [
    ["robot", "show"],
    ["robot", "urdf", "-o", "{tmp}/arm.urdf"],
    ["robot", "export", "{tmp}/throw.json", "-f", "json", "-o", "{tmp}/out.json"],
    ["sim", "reach", "--joints", "joint_2,joint_3"],
    ["sim", "throw", "{tmp}/throw.json", "--basket", "2"],
], ids=["robot-show", "robot-urdf", "robot-export", "sim-reach", "sim-throw"])
def test_a_start_pose_outside_its_limits_is_refused_by_every_command_alike(tmp_path, capsys, command):
    # robot show and learn --joints refused it; sim throw of a robot trajectory and sim reach --joints took it
    text = COMAU.replace("[whole_arm.start_pose]\njoint_1 = 0.0\njoint_2 = -0.36",
                         "[whole_arm.start_pose]\njoint_1 = 0.0\njoint_2 = -9.0")
    assert text != COMAU
    path = tmp_path / "mine.toml"
    path.write_text(text)
    (tmp_path / "throw.json").write_text("{}")
    argv = [part.format(tmp=tmp_path) for part in command]
    assert main([*argv, "--robot", str(path)]) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert line == f"rlff: error: {path}: [whole_arm.start_pose]: joint_2 -9 rad is outside its limits [-1.48, 2.71] rad"


def test_a_throwing_start_pose_outside_its_limits_is_refused_when_the_file_is_read(tmp_path):
    path = tmp_path / "mine.toml"
    path.write_text(COMAU.replace("[throwing.start_pose]\njoint_1 = 0.0", "[throwing.start_pose]\njoint_1 = 3.5"))
    with pytest.raises(InputError) as refused:
        load_robot(path)
    assert str(refused.value) == f"{path}: [throwing.start_pose]: joint_1 3.5 rad is outside its limits [-2.967, 2.967] rad"
    path.write_text(COMAU.replace("[throwing.start_pose]\njoint_1 = 0.0", "[throwing.start_pose]\njoint_1 = 'up'"))
    with pytest.raises(InputError, match=r"mine.toml: \[throwing.start_pose\]: field 'joint_1' must be a finite number"):
        load_robot(path)


@pytest.mark.parametrize("joint", ["joint_1", "joint_4", "joint_6"])
def test_a_throw_driven_by_a_joint_outside_the_throwing_plane_is_refused_when_the_file_is_read(tmp_path, capsys,
                                                                                              joint):
    # robot show and robot export took [throwing] joint = "joint_1"; sim throw refused it after planning, learn
    # and sim reach in other words, none naming the file or the table
    text = COMAU.replace('[throwing]\njoint = "joint_2"', f'[throwing]\njoint = "{joint}"')
    text = text.replace(f"[throwing.start_pose]\n{joint} = ", "[throwing.start_pose]\njoint_2 = 0.0\n# was: ")
    path = tmp_path / "mine.toml"
    path.write_text(text)
    expected = (f"{path}: [throwing]: {joint} does not throw in the arm's vertical plane: a throw drives joint_2, "
                "joint_3 or joint_5 (joint_1 turns the arm to the basket's bearing, joint_4 and joint_6 roll the "
                "forearm and the flange)")
    with pytest.raises(InputError) as refused:
        load_robot(path)
    assert str(refused.value) == expected
    for command in (["robot", "show"], ["sim", "reach"], ["robot", "urdf", "-o", str(tmp_path / "arm.urdf")]):
        assert main([*command, "--robot", str(path)]) == 2
        assert capsys.readouterr().err.strip().splitlines() == [f"rlff: error: {expected}"]


@pytest.mark.parametrize("joint", ["joint_3", "joint_5"])
def test_a_throw_driven_by_another_joint_of_the_plane_loads(tmp_path, joint):
    pose = "[throwing.start_pose]\njoint_1 = 0.0\njoint_3 = -1.373\njoint_4 = 0.0\njoint_5 = -0.198\n"
    assert pose in COMAU
    text = COMAU.replace('[throwing]\njoint = "joint_2"', f'[throwing]\njoint = "{joint}"')
    text = text.replace(pose, pose.replace(f"{joint} = ", "joint_2 = 0.0\n# was: "))
    path = tmp_path / "mine.toml"
    path.write_text(text)
    from rlff.robot.mapping import RobotMapping

    robot = load_robot(path)
    assert RobotMapping.for_robot(robot).joint == joint and robot.name == "comau_smart5_six"


def test_a_whole_arm_joint_outside_the_throwing_plane_is_refused_when_the_file_is_read(tmp_path):
    path = tmp_path / "mine.toml"
    path.write_text(COMAU.replace("[whole_arm.joints.joint_5]", "[whole_arm.joints.joint_4]"))
    with pytest.raises(InputError) as refused:
        load_robot(path)
    assert str(refused.value).startswith(f"{path}: [whole_arm.joints.joint_4]: joint_4 does not throw in the arm's "
                                         "vertical plane: a throw drives joint_2, joint_3 or joint_5")


def test_a_mapping_built_in_code_is_held_to_the_throwing_plane_in_the_same_words():
    from rlff.robot.description import Joint
    from rlff.robot.mapping import ArmMapping, JointMap, RobotMapping

    robot = load_robot()
    pose = {name: 0.0 for name in robot.joint_names if name != "joint_1"}
    with pytest.raises(InputError, match=r"^built-in robot comau_smart5_six: \[throwing\]: joint_1 does not throw in "
                                         r"the arm's vertical plane: a throw drives joint_2, joint_3 or joint_5 "):
        RobotMapping(robot, "joint_1", pose)
    with pytest.raises(InputError, match=r"^built-in robot comau_smart5_six: \[whole_arm.joints.joint_6\]: joint_6 "
                                         r"does not throw"):
        ArmMapping(robot, (JointMap("joint_3", "angle", 0.0, 1.0), JointMap("joint_6", "wrist", 0.0, 1.0)),
                   {name: 0.0 for name in robot.joint_names}, 1.0)
    # a joint with a name of its own is not read by rlff's convention, and is not held to it
    own = Robot("own", (Joint("a1", -1.0, 1.0, 1.0), Joint("a2", -1.0, 1.0, 1.0)))
    assert RobotMapping(own, "a1", {"a2": 0.0}).joint == "a1"


def ur_like(joint_2=lambda table: table):
    """A UR5e-like file (the Comau's tables, every joint ±2π, 3.14 rad/s, 12 rad/s^2, 120 rad/s^3),
    joint_2's table passed through ``joint_2``."""
    def edit(table):
        table = re.sub(r"^lower = .*$", "lower = -6.283", table, flags=re.M)
        table = re.sub(r"^upper = .*$", "upper = 6.283", table, flags=re.M)
        table = re.sub(r"^max_velocity = .*$", "max_velocity = 3.14", table, flags=re.M)
        table = re.sub(r"^max_acceleration = .*$", "max_acceleration = 12.0", table, flags=re.M)
        table = re.sub(r"^max_jerk = .*$", "max_jerk = 120.0", table, flags=re.M)
        return joint_2(table) if 'name = "joint_2"' in table else table
    return edit


def _loaded_quietly(path):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        return load_robot(path)


def test_the_shipped_file_and_a_ur_like_one_load_without_a_warning(tmp_path):
    assert _loaded_quietly("comau_smart5_six").warnings == ()
    assert _loaded_quietly(comau_file(tmp_path / "ur.toml", edit=ur_like())).warnings == ()


def test_accelerations_in_degrees_are_warned_of(tmp_path):
    # 687.5 (12 rad/s^2 in degrees) loaded silently and the plans used it: full speed in 4.6 ms
    path = comau_file(tmp_path / "acc.toml", edit=lambda table: re.sub(
        r"^max_acceleration = (.*)$", lambda m: f"max_acceleration = {math.degrees(float(m[1])):.1f}", table,
        flags=re.M))
    with pytest.warns(RobotFileWarning) as caught:
        robot = load_robot(path)
    assert [str(w.message) for w in caught] == list(robot.warnings) == [
        f"{path}: joint 1 (joint_1): max_acceleration 573 rad/s^2 takes it from rest to its full speed 2.443 rad/s in "
        "4.3 ms (and 5 more joints); published arm limits take 0.1 s or more (Franka's quickest joints 0.13 s): is "
        "max_acceleration in degrees? rlff reads rad/s^2"]


def test_a_speed_far_below_the_other_joints_is_blamed_not_the_acceleration_beside_it(tmp_path):
    # 1e-9 rad/s beside 12 rad/s^2 asked whether the acceleration was in degrees (tester H)
    path = comau_file(tmp_path / "slow.toml", edit=ur_like(lambda table: table.replace("3.14", "1e-09")))
    with pytest.warns(RobotFileWarning) as caught:
        load_robot(path)
    assert [str(w.message) for w in caught] == [
        f"{path}: joint 2 (joint_2): max_velocity 1e-09 rad/s is 3.14e+09 times below that of the next slowest joint, "
        "joint_1 (3.14 rad/s), and its max_acceleration 12 rad/s^2 reaches it in 8.3e-08 ms; an arm's joints differ "
        "by a few times at most: is max_velocity right? rlff reads rad/s"]


def test_one_joint_s_speed_in_degrees_is_warned_of(tmp_path, cli):
    # 45 deg/s passed the 50 rad/s bound: sim reach said 227 m
    path = comau_file(tmp_path / "speed.toml", edit=ur_like(lambda table: table.replace("3.14", "45.0")))
    with pytest.warns(RobotFileWarning, match=r"speed\.toml: joint 2 \(joint_2\): max_velocity 45 rad/s is 14\.3 times "
                                              r"that of the next fastest joint, joint_1 \(3\.14 rad/s\); .*is it in "
                                              r"degrees per second\? rlff reads rad/s$"):
        load_robot(path)
    reach = cli("sim", "reach", "--robot", str(path))  # a process of its own: pytest would catch the warning
    assert reach.code == 0 and "joint 2 (joint_2): max_velocity 45 rad/s is 14.3 times" in reach.stderr
    # one `warning:` line, as rlff's other warnings, not Python's two-line form with a source line
    (said,) = [line for line in reach.stderr.splitlines() if "max_velocity 45 rad/s" in line]
    assert said.startswith("warning: ") and "RobotFileWarning" not in reach.stderr


def test_a_bending_joint_s_limits_in_degrees_are_warned_of_and_a_roll_joint_s_are_not(tmp_path):
    # ±45 on joint_2 passed the eight turns bound
    degrees = ur_like(lambda table: table.replace("-6.283", "-45.0").replace("= 6.283", "= 45.0"))
    with pytest.warns(RobotFileWarning, match=r"pos\.toml: joint 2 \(joint_2\): limits -45 to 45 rad reach 7\.2 turns "
                                              r"from 0; joint_2 bends the arm, .*is it in degrees\? rlff reads rad$"):
        load_robot(comau_file(tmp_path / "pos.toml", edit=degrees))
    # the Comau's joint 6 turns ±7.5 turns, and any roll joint may
    roll = comau_file(tmp_path / "roll.toml", edit=lambda table: table.replace("lower = -3.67", "lower = -45.0")
                      .replace("upper = 3.67", "upper = 45.0"))
    assert _loaded_quietly(roll).joint("joint_4").upper == 45.0


def test_geometry_with_a_controller_s_own_joint_names_is_refused(tmp_path):
    # a UR's names with [geometry]: the angles were placed on rlff's chain by position, and the
    # floor check judged another pose than the arm's (UR shoulder_lift 0 = upper arm horizontal)
    names = ("shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint", "wrist_1_joint", "wrist_2_joint",
             "wrist_3_joint")
    text = COMAU
    for k, name in enumerate(names, start=1):
        text = text.replace(f'"joint_{k}"', f'"{name}"')
    text = text[:text.index("[throwing]")] if "[throwing]" in text else text
    path = tmp_path / "ur.toml"
    path.write_text(text)
    with pytest.raises(InputError, match=r"ur.toml: \[geometry\] describes rlff's chain, joints joint_1 to joint_6 "
                                         r".*this file's joints are shoulder_pan_joint, .*leave \[geometry\] out"):
        load_robot(path)
    head, _, rest = text.partition("[geometry]")
    path.write_text(head + rest[rest.index("\n[", 1):] if "\n[" in rest[1:] else head)
    assert load_robot(path).joint_names == names  # without [geometry]: its names, no kinematics


def test_a_speed_no_joint_reaches_within_its_range_is_warned_of(tmp_path):
    # a slow arm's joint_2 at 18 "rad/s" (18 deg/s), the other joints' speeds 1.5 times the
    # Comau's: no joint stands out from the others, only the acceleration over the range tells
    # (11 rad/s^2 over 4.19 rad reaches 6.8 rad/s at most)
    def slow_arm_in_deg_per_s(table):
        table = re.sub(r"^max_velocity = (\S+)$", lambda m: f"max_velocity = {float(m[1]) * 1.5:g}", table, flags=re.M)
        return table.replace("max_velocity = 4.188", "max_velocity = 18")  # joint_2: 2.792 x 1.5
    path = comau_file(tmp_path / "slow.toml", edit=slow_arm_in_deg_per_s)
    with pytest.warns(RobotFileWarning, match=r"slow\.toml: joint 2 \(joint_2\): max_velocity 18 rad/s is 2\.6\d* times "
                                              r"the most its max_acceleration 11 rad/s\^2 reaches within its 4\.19 rad "
                                              r"range \(6\.\d+ rad/s\): is it in degrees per second\?"):
        load_robot(path)
    # the built-in file's speeds are all within reach of its accelerations
    with warnings.catch_warnings():
        warnings.simplefilter("error", RobotFileWarning)
        load_robot()
