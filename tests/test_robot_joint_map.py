"""The robot file's [ros.joints]: the controller's names, zeros and signs of rlff's joints.

Parsing and every refusal (one line naming the file and the table), the conversion's formula on
exact numbers, its round trip (a property), identity without a map, and [geometry] with a
UR-named controller (the restriction the map lifts).
"""

from __future__ import annotations

import math
import re
import warnings
from importlib import resources

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rlff.errors import InputError
from rlff.robot import load_robot
from rlff.robot.controller import (
    GoalRejected,
    ResultCode,
    TrajectoryController,
    goal_in_rlff,
    in_controller_words,
)
from rlff.robot.description import Joint, Robot, RobotFileWarning, RosNames
from rlff.robot.joint_map import ControllerJoint, JointMap
from rlff.robot.messages import arm_state_of, missing_joints
from rlff.trajectory.joint import JointTrajectory
from rosrig import UR_NAMES, ur_file

COMAU = (resources.files("rlff") / "robots" / "comau_smart5_six.toml").read_text(encoding="utf-8")


def test_a_ur_named_map_loads_with_geometry_and_is_read_as_written(tmp_path):
    robot = load_robot(ur_file(tmp_path / "ur.toml"))
    assert robot.geometry is not None and robot.joint_names == tuple(f"joint_{k}" for k in range(1, 7))
    joints = robot.ros.joints
    assert [joints.controller_name(name) for name in robot.joint_names] == list(UR_NAMES)
    assert joints.joints["joint_2"] == ControllerJoint("shoulder_lift_joint", -math.pi / 2, 1)
    assert joints.joints["joint_5"] == ControllerJoint("wrist_2_joint", 0.25, -1)
    assert joints.label("joint_2") == "shoulder_lift_joint (joint_2)" and not joints.identity
    assert robot.ros.action == RosNames.action  # [ros]'s own keys are as they were
    assert load_robot().ros.joints.identity and load_robot().ros.joints.joints == {}


def test_a_joint_not_listed_keeps_its_name_zero_and_sign(tmp_path):
    robot = load_robot(ur_file(tmp_path / "one.toml", '\n[ros.joints.joint_2]\nname = "lift"\n'))
    joints = robot.ros.joints
    assert [joints.controller_name(name) for name in robot.joint_names] == [
        "joint_1", "lift", "joint_3", "joint_4", "joint_5", "joint_6"]
    assert joints.label("joint_1") == "joint_1" and joints.joints["joint_2"] == ControllerJoint("lift", 0.0, 1)
    # a table without a name keeps the joint's
    robot = load_robot(ur_file(tmp_path / "zero.toml", "\n[ros.joints.joint_3]\noffset = 0.5\n"))
    assert robot.ros.joints.joints["joint_3"] == ControllerJoint("joint_3", 0.5, 1)


@pytest.mark.parametrize(("tables", "message"), [
    ('\n[ros.joints.joint_2]\nname = "lift"\nsign = 2\n',
     r"bad.toml: \[ros.joints.joint_2\]: sign must be 1 or -1 \(the controller counts the joint as rlff does, or "
     r"the other way round\), got 2$"),
    ('\n[ros.joints.joint_2]\nname = "lift"\nsign = true\n', r"\[ros.joints.joint_2\]: sign must be 1 or -1 .*got True$"),
    ('\n[ros.joints.joint_2]\nname = "lift"\noffset = "90deg"\n',
     r"bad.toml: \[ros.joints.joint_2\]: offset must be a finite number of radians, got '90deg'$"),
    ('\n[ros.joints.joint_2]\noffset = nan\n', r"\[ros.joints.joint_2\]: offset must be a finite number of radians, "
                                              r"got nan$"),
    ('\n[ros.joints.joint_2]\noffset = 90\n',
     r"bad.toml: \[ros.joints.joint_2\]: offset 90 rad is more than eight turns \(50.27 rad\); rlff reads radians: "
     r"is it in degrees\?$"),
    ('\n[ros.joints.joint_7]\nname = "wrist_4_joint"\n',
     r"bad.toml: \[ros.joints.joint_7\]: joint_7 is not a joint of the robot \(joints: joint_1, joint_2, joint_3, "
     r"joint_4, joint_5, joint_6\); each table is named after one of the file's \[\[joints\]\], its `name` the "
     r"controller's$"),
    ('\n[ros.joints.joint2]\nname = "lift"\n', r"\[ros.joints.joint2\]: joint2 is not a joint of the robot \(did you "
                                               r"mean 'joint_2'\?\)"),
    ('\n[ros.joints.shoulder_lift_joint]\nname = "joint_2"\n',
     r"\[ros.joints.shoulder_lift_joint\]: shoulder_lift_joint is not a joint of the robot \(joints: joint_1, .*; "
     r"the other way round: \[ros.joints.joint_2\] with name = 'shoulder_lift_joint'\?\); each table"),
    ('\n[ros.joints.joint_2]\nname = "lift"\nsing = -1\n',
     r"bad.toml: \[ros.joints.joint_2\]: unknown field 'sing' \(did you mean 'sign'\?\)$"),
    ('\n[ros.joints.joint_2]\nname = "lift"\n[ros.joints.joint_3]\nname = "lift"\n',
     r"bad.toml: \[ros.joints.joint_3\]: name 'lift' is also \[ros.joints.joint_2\]'s: each joint needs a "
     r"controller name of its own$"),
    ('\n[ros.joints.joint_2]\nname = "joint_3"\n',
     r"bad.toml: \[ros.joints.joint_2\]: name 'joint_3' is the name of rlff's joint joint_3, which keeps it \(it "
     r"has no \[ros.joints.joint_3\] table\): two joints under one name; give that joint the controller's own "
     r"name too$"),
    ('\n[ros.joints.joint_3]\nname = "joint_2"\n', r"\[ros.joints.joint_3\]: name 'joint_2' is the name of rlff's "
                                                  r"joint joint_2, which keeps it"),
    ('\n[ros.joints.joint_2]\nname = ""\n', r"\[ros.joints.joint_2\]: name must be the controller's joint name, a "
                                           r"non-empty string, got ''$"),
    ('\n[ros.joints.joint_2]\nname = 2\n', r"\[ros.joints.joint_2\]: name must be .*got 2$"),
    ('\n[ros.joints.joint_2]\nname = " lift"\n', r"\[ros.joints.joint_2\]: name ' lift' begins or ends with a space"),
    ('\n[ros.joints]\njoint_2 = "lift"\n', r"bad.toml: \[ros.joints.joint_2\] must be a table \(name, offset, sign\), "
                                          r"got 'lift'$"),
    ('\n[ros]\n', r"not valid TOML"),  # a second [ros] table: TOML's own error
])
def test_a_bad_joint_map_is_refused_in_one_line_naming_the_file_and_table(tmp_path, tables, message):
    path = ur_file(tmp_path / "bad.toml", tables)
    with pytest.raises(InputError, match=message) as caught:
        load_robot(path)
    assert "\n" not in str(caught.value)


def test_a_joints_key_that_is_no_table_is_refused(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(COMAU.replace('trajectory_topic = "/comau/joint_trajectory"',
                                  'trajectory_topic = "/comau/joint_trajectory"\njoints = "ur"'))
    with pytest.raises(InputError, match=r"bad.toml: \[ros\] joints must be \[ros.joints.<joint>\] tables \(name, "
                                         r"offset, sign\), got 'ur'$"):
        load_robot(path)


def test_a_swap_of_two_names_is_taken(tmp_path):
    # two joints trading names is one name each: odd, not ambiguous
    robot = load_robot(ur_file(tmp_path / "swap.toml", '\n[ros.joints.joint_4]\nname = "joint_6"\n'
                                                       '[ros.joints.joint_6]\nname = "joint_4"\n'))
    assert robot.ros.joints.rlff_name("joint_6") == "joint_4" and robot.ros.joints.rlff_name("joint_4") == "joint_6"


def test_an_offset_beyond_a_turn_is_warned_of_as_degrees(tmp_path):
    path = ur_file(tmp_path / "deg.toml", "\n[ros.joints.joint_2]\noffset = -45\n[ros.joints.joint_3]\noffset = 30\n")
    with pytest.warns(RobotFileWarning, match=r"deg.toml: \[ros.joints.joint_2\]: offset -45 rad is 7.2 turns \(and 1 "
                                              r"more\); a controller's zero is within a turn of rlff's: is it in "
                                              r"degrees\? rlff reads rad$"):
        robot = load_robot(path)
    assert robot.ros.joints.joints["joint_2"].offset == -45.0  # warned of, still loaded
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        load_robot(ur_file(tmp_path / "rad.toml"))  # the UR's quarter turns: nothing to say


def test_geometry_with_other_names_now_points_at_the_map(tmp_path):
    text = COMAU
    for k, name in enumerate(UR_NAMES, start=1):
        text = text.replace(f'"joint_{k}"', f'"{name}"')
    path = tmp_path / "ur_names.toml"
    path.write_text(text[:text.index("[throwing]")])
    with pytest.raises(InputError, match=r"ur_names.toml: \[geometry\] describes rlff's chain, .*and give the "
                                         r"controller's names, zeros and signs in \[ros.joints\] tables "
                                         r"\(docs/robot.md\), or leave \[geometry\] out"):
        load_robot(path)


def test_a_map_built_in_code_is_checked_against_the_robot_s_joints():
    joints = (Joint("a", -1, 1, 1, 5, 50), Joint("b", -1, 1, 1, 5, 50))
    with pytest.raises(InputError, match=r"<memory>: \[ros.joints.c\]: c is not a joint of the robot"):
        Robot("r", joints, ros=RosNames(joints=JointMap({"c": ControllerJoint("x")})))
    with pytest.raises(InputError, match=r"sign must be 1 or -1"):
        ControllerJoint("x", 0.0, 0)
    assert Robot("r", joints, ros=RosNames(joints=JointMap({"a": ControllerJoint("x", 0.1, -1)}))).ros.joints.label(
        "a") == "x (a)"
    assert hash(RosNames(joints=JointMap({"a": ControllerJoint("x")}))) == hash(
        RosNames(joints=JointMap({"a": ControllerJoint("x")})))


# -- the conversion -------------------------------------------------------------------------------------
def _traj() -> JointTrajectory:
    names = tuple(f"joint_{k}" for k in range(1, 7))
    positions = np.array([[0.0, 0.1, -1.0, 0.2, -0.3, 1.0], [0.5, 0.4, -0.5, 0.0, 0.3, -1.0]])
    return JointTrajectory(names, [0.0, 0.5], positions, positions * 2, positions * 3, release_time=0.5)


def test_to_the_controller_renames_offsets_and_signs_exactly(tmp_path):
    robot = load_robot(ur_file(tmp_path / "ur.toml"))
    traj = _traj()
    out = robot.ros.joints.to_controller(traj)
    assert out.joint_names == UR_NAMES and out.release_time == 0.5
    np.testing.assert_array_equal(out.time, traj.time)
    expected = traj.positions + [0.0, -math.pi / 2, math.pi / 2, 0.0, 0.0, 0.0]
    expected[:, 4] = 0.25 - traj.positions[:, 4]
    np.testing.assert_array_equal(out.positions, expected)
    sign = np.array([1, 1, 1, 1, -1, 1])
    np.testing.assert_array_equal(out.velocities, sign * traj.velocities)
    np.testing.assert_array_equal(out.accelerations, sign * traj.accelerations)
    # a trajectory of some joints, in any order, maps those
    some = traj.select(["joint_5", "joint_2"])
    np.testing.assert_array_equal(robot.ros.joints.to_controller(some).positions,
                                  expected[:, [4, 1]])
    assert robot.ros.joints.to_controller(some).joint_names == ("wrist_2_joint", "shoulder_lift_joint")


def test_without_a_map_every_conversion_is_the_identity():
    robot = load_robot()
    traj = _traj()
    assert robot.ros.joints.to_controller(traj) is traj and robot.ros.joints.from_controller(traj) is traj
    assert goal_in_rlff(robot, traj) is traj
    pose = np.array([-0.0, 0.1, -1.0, 0.2, -0.3, 1.0])
    names, positions, velocities = robot.ros.joints.state_to_controller(robot.joint_names, pose, pose)
    assert names == list(robot.joint_names)
    assert positions.tobytes() == pose.tobytes() and velocities.tobytes() == pose.tobytes()  # -0.0 stays


finite = st.floats(-40.0, 40.0, allow_nan=False)


@settings(max_examples=200, deadline=None)
@given(offsets=st.lists(st.floats(-6.0, 6.0, allow_nan=False), min_size=6, max_size=6),
       signs=st.lists(st.sampled_from([1, -1]), min_size=6, max_size=6),
       values=st.lists(finite, min_size=18, max_size=18))
def test_from_the_controller_undoes_to_the_controller(offsets, signs, values):
    joints = JointMap({f"joint_{k + 1}": ControllerJoint(UR_NAMES[k], offsets[k], signs[k]) for k in range(6)})
    q = np.array(values).reshape(3, 6)
    traj = JointTrajectory(tuple(f"joint_{k}" for k in range(1, 7)), [0.0, 0.1, 0.3], q, q / 2, q / 3)
    out = joints.to_controller(traj)
    back = joints.from_controller(out)
    assert back.joint_names == traj.joint_names and out.joint_names == UR_NAMES
    # (offset + s q - offset) s: q within the rounding of the sum
    np.testing.assert_allclose(back.positions, traj.positions, rtol=0, atol=1e-13)
    np.testing.assert_array_equal(back.velocities, traj.velocities)  # a sign flip is exact
    np.testing.assert_array_equal(back.accelerations, traj.accelerations)
    names, positions, velocities = joints.state_to_controller(traj.joint_names, q[0], q[1])
    pose, speed = joints.state_from_controller(traj.joint_names, names[::-1], positions[::-1], velocities[::-1])
    np.testing.assert_allclose(pose, q[0], rtol=0, atol=1e-13)
    np.testing.assert_array_equal(speed, q[1])


def test_a_joint_state_in_the_controller_s_names_is_read_into_rlff_s(tmp_path):
    robot = load_robot(ur_file(tmp_path / "ur.toml"))
    # a UR driver's message, the gripper's finger among the arm's joints, in its own order
    names = ["finger", *reversed(UR_NAMES)]
    controller = [0.02, 0.0, 0.25 - 0.1, 0.0, math.pi / 2 - 1.3, -math.pi / 2 + 0.2, 0.3]
    pose, velocity = arm_state_of(robot, "/joint_states", names, controller, [0.0] * 7)
    np.testing.assert_allclose(pose, [0.3, 0.2, -1.3, 0.0, 0.1, 0.0], rtol=0, atol=1e-15)
    pose, velocity = arm_state_of(robot, "/joint_states", names, controller, [])
    assert velocity is None
    # rlff's own names are not the controller's: the arm's joints are missing, said both ways
    assert missing_joints(robot, [f"joint_{k}" for k in range(1, 7)]) == [
        f"{name} (joint_{k})" for k, name in enumerate(UR_NAMES, start=1)]
    assert missing_joints(robot, names) == []


def test_a_goal_in_rlff_s_names_is_refused_by_a_mapped_controller(tmp_path):
    robot = load_robot(ur_file(tmp_path / "ur.toml"))
    with pytest.raises(GoalRejected, match=re.escape("unknown joints ['joint_2'] (the controller of robot "
                                                     "comau_smart5_six has shoulder_pan_joint, shoulder_lift_joint, "
                                                     "elbow_joint, wrist_1_joint, wrist_2_joint, wrist_3_joint)")) as e:
        goal_in_rlff(robot, _traj().select(["joint_2"]))
    assert e.value.code == ResultCode.INVALID_JOINTS
    goal = robot.ros.joints.to_controller(_traj())
    np.testing.assert_allclose(goal_in_rlff(robot, goal).positions, _traj().positions, atol=1e-15)


def test_a_mapped_controller_s_refusal_names_the_joints_as_its_client_does(tmp_path):
    """The controller words a goal beyond a limit in rlff's names and convention; the client of a
    UR-named controller reads the map of the joint it names beside it."""
    robot = load_robot(ur_file(tmp_path / "ur.toml"))
    controller = TrajectoryController(robot, np.zeros(6))
    beyond = np.zeros((2, 6))
    beyond[1, 1] = 3.0  # joint_2 at 3 rad, beyond its 2.71
    goal = robot.ros.joints.to_controller(JointTrajectory(_traj().joint_names, [1.0, 3.0], beyond, np.zeros((2, 6))))
    assert list(goal.joint_names) == list(UR_NAMES)
    with pytest.raises(GoalRejected) as e:
        controller.submit(None, goal_in_rlff(robot, goal), 0.0)
    assert e.value.code == ResultCode.INVALID_GOAL
    text = in_controller_words(robot, str(e.value))
    assert text.startswith(str(e.value)) and "joint_2 position 3 rad beyond the limit 2.71 rad" in text
    assert text.endswith("; in rlff's names and convention: joint_2 as shoulder_lift_joint = -1.5708 + joint_2")
    # a joint only renamed is named too; a text of no joint of the arm stays as it was
    assert in_controller_words(robot, "joint_4 moves") == "joint_4 moves; in rlff's names and convention: joint_4 as wrist_1_joint"
    assert in_controller_words(robot, "joint_20 and joint_7 are none") == "joint_20 and joint_7 are none"
    unmapped = load_robot("comau_smart5_six")
    assert in_controller_words(unmapped, str(e.value)) == str(e.value)


def test_a_goal_the_client_refuses_names_the_joints_both_ways(tmp_path):
    # the client's own check (before anything is sent) named rlff's joint only, where the
    # controller's refusal of the same goal gave the map too
    from rlff.robot.send import check_goal_for_arm

    robot = load_robot(ur_file(tmp_path / "ur.toml"))
    beyond = np.zeros((2, 6))
    beyond[1, 1] = 3.0  # joint_2 at 3 rad, beyond its 2.71
    goal = JointTrajectory(_traj().joint_names, [0.0, 3.0], beyond, np.zeros((2, 6)))
    with pytest.raises(InputError) as e:
        check_goal_for_arm(robot, goal, np.zeros(6), np.zeros(6))
    text = str(e.value)
    assert text.startswith(f"from the arm's pose on {robot.ros.joint_states}: ") and "joint_2 position 3 rad" in text
    assert text.endswith("; in rlff's names and convention: joint_2 as shoulder_lift_joint = -1.5708 + joint_2")
    with pytest.raises(InputError) as plain:
        check_goal_for_arm(load_robot(), goal, np.zeros(6), np.zeros(6))
    assert "in rlff's names" not in str(plain.value)


def test_the_arm_s_state_is_checked_in_rlff_s_convention_and_named_both_ways(tmp_path):
    from rlff.robot.send import ArmStateError, StateWatch, pose_line, require_at_rest

    robot = load_robot(ur_file(tmp_path / "ur.toml"))
    watch = StateWatch(robot, lambda: 10.0)
    # joint_2 at 2.9 rad in rlff's convention, beyond its 2.71: the controller says 2.9 - pi/2
    watch.offer(10.0, list(UR_NAMES), [0.0, 2.9 - math.pi / 2, math.pi / 2 - 1.0, 0.0, 0.25, 0.0], [0.0] * 6)
    with pytest.raises(ArmStateError, match=re.escape(
            "/joint_states reports shoulder_lift_joint (joint_2) at 2.9 rad (rlff's convention; the controller's "
            "1.3292 rad), beyond its upper limit 2.71 rad in the robot file (comau_smart5_six): move the arm inside "
            "its limits, or check the robot file's limits, its [ros.joints.joint_2] and the driver's joint offsets "
            "against the arm's")):
        watch.wait(0.0, 1.0)
    with pytest.raises(ArmStateError, match=re.escape("(0.5 rad/s on wrist_2_joint (joint_5))")):
        require_at_rest(robot, np.array([0.0, 0.0, 0.0, 0.0, -0.5, 0.0]))
    assert pose_line(robot, np.array([0.0, 0.0, -1.0, 0.0, 0.1, 0.0])) == (
        "arm's pose read (rad; the controller's = rlff's): shoulder_pan_joint 0 = joint_1 0, shoulder_lift_joint "
        "-1.571 = joint_2 0, elbow_joint 0.5708 = joint_3 -1, wrist_1_joint 0 = joint_4 0, wrist_2_joint 0.15 = "
        "joint_5 0.1, wrist_3_joint 0 = joint_6 0")
    # a controller's -0.0 (and the map's sign turning a 0 into one) reads 0, not -0
    assert " -0," not in pose_line(robot, np.array([-0.0, 0.0, -1.0, -0.0, 0.1, -0.0])) + ","
    assert pose_line(load_robot(), np.array([0.0, -0.0, 0.0, 0.0, 0.0, 0.0])).endswith("joint_2 0, joint_3 0, "
                                                                                        "joint_4 0, joint_5 0, joint_6 0")
    # without a map: the messages as they were
    with pytest.raises(ArmStateError, match=re.escape("the arm is moving (0.5 rad/s on joint_5): wait until it "
                                                      "rests, then send again")):
        require_at_rest(load_robot(), np.array([0.0, 0.0, 0.0, 0.0, -0.5, 0.0]))


def test_the_announced_approach_and_fastest_joint_are_in_the_controllers_names_and_turns(tmp_path):
    # what the operator reads before the arm moves must match the arm's pendant: its names, and
    # its direction of turning (joint_5 counts the other way round in this map)
    from rlff.robot.send import approach_line, fastest_joint_line

    robot = load_robot(ur_file(tmp_path / "ur.toml"))
    time = np.array([0.0, 0.5, 1.0, 1.5])
    positions = np.zeros((4, 6))
    positions[1:, 1] = 0.5  # joint_2 up by 0.5 rad, then still
    positions[1:, 4] = 0.2  # joint_5 by 0.2 rad
    velocities = np.zeros((4, 6))
    velocities[3, 1] = 1.0  # the throw after the approach: joint_2 at 1 rad/s
    traj = JointTrajectory(robot.joint_names, time, positions, velocities)
    assert approach_line(traj) == "approach first: joint_2 +28.6 deg, joint_5 +11.5 deg in 0.50 s, to the start of the throw"
    assert approach_line(traj, joints=robot.ros.joints) == (
        "approach first: shoulder_lift_joint (joint_2) +28.6 deg, wrist_2_joint (joint_5) -11.5 deg in 0.50 s, to the "
        "start of the throw")
    assert approach_line(traj, joints=load_robot().ros.joints) == approach_line(traj)  # no map: as before
    top = robot.joint("joint_2").max_velocity
    assert fastest_joint_line(robot, traj) == f"fastest: shoulder_lift_joint (joint_2) at {1 / top:.0%} of its {top:g} rad/s"
    assert fastest_joint_line(load_robot(), traj) == f"fastest: joint_2 at {1 / top:.0%} of its {top:g} rad/s"


#: Universal Robots' published Denavit-Hartenberg parameters of the UR5e (m, rad), joints 1-6.
UR5E_D = (0.1625, 0.0, 0.0, 0.1333, 0.0997, 0.0996)
UR5E_A = (0.0, -0.425, -0.3922, 0.0, 0.0, 0.0)
UR5E_ALPHA = (math.pi / 2, 0.0, 0.0, math.pi / 2, -math.pi / 2, 0.0)


def _ur5e_frame_origins(angles: np.ndarray) -> list[np.ndarray]:
    """The origins (3,) of DH frames 1-6 of a UR5e at its controller's ``angles`` (6,) rad, in its
    base frame: frame 2's is the elbow, frame 3's the wrist-1 joint at the forearm's end."""
    frame, origins = np.eye(4), []
    for theta, d, a, alpha in zip(angles, UR5E_D, UR5E_A, UR5E_ALPHA, strict=True):
        ct, st, ca, sa = math.cos(theta), math.sin(theta), math.cos(alpha), math.sin(alpha)
        frame = frame @ np.array([[ct, -st * ca, st * sa, a * ct], [st, ct * ca, -ct * sa, a * st],
                                  [0.0, sa, ca, d], [0.0, 0.0, 0.0, 1.0]])
        origins.append(frame[:3, 3].copy())
    return origins


def test_the_docs_ur_table_puts_the_elbow_and_forearm_where_the_ur5e_s_dh_parameters_do(tmp_path):
    # docs/robot.md's worked example (shoulder_lift -pi/2, elbow +pi/2, both sign 1), with rlff's
    # chain of the UR5e's upper arm and forearm: the elbow and the forearm's end agree with the
    # UR's own kinematics in the arm's plane, rlff's forward being the side the UR's upper arm
    # points to at shoulder_lift 0 (the UR base's -x). Joint 1 turns both alike.
    from rlff.robot.description import Geometry
    from rlff.robot.links import chain_points

    table = ('\n[ros.joints.joint_1]\nname = "shoulder_pan_joint"\n'
             '\n[ros.joints.joint_2]\nname = "shoulder_lift_joint"\noffset = -1.5707963267948966\n'
             '\n[ros.joints.joint_3]\nname = "elbow_joint"\noffset = 1.5707963267948966\n')
    joints = load_robot(ur_file(tmp_path / "ur.toml", table)).ros.joints
    ur_arm = Geometry(shoulder_height=UR5E_D[0], shoulder_forward=0.0, upper_arm=-UR5E_A[1], elbow_offset=0.0,
                      forearm=-UR5E_A[2], flange=0.0)
    ur_base_from_rlff = np.diag([-1.0, -1.0, 1.0])  # a half turn about the vertical
    rng = np.random.default_rng(3)
    for _ in range(20):
        pose = np.r_[rng.uniform(-2.5, 2.5), rng.uniform(-1.4, 2.6), rng.uniform(-2.9, 0.0), 0.0, 0.0, 0.0]
        ours = chain_points(ur_arm, pose[None, :])
        theirs = _ur5e_frame_origins(joints.positions_to_controller(tuple(f"joint_{k}" for k in range(1, 7)), pose))
        np.testing.assert_allclose(ur_base_from_rlff @ ours["elbow"][0], theirs[1], atol=1e-12)
        np.testing.assert_allclose(ur_base_from_rlff @ ours["wrist"][0], theirs[2], atol=1e-12)
