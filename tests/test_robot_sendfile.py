"""What ``rlff robot send`` reads: every export that makes sense over ROS, checked from the arm's pose."""

from __future__ import annotations

import re
import sys
import warnings
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from rosbags.rosbag1 import Reader, Writer
from rosbags.typesys import Stores, get_typestore

sys.path.insert(0, str(Path(__file__).parent))
from rlff.errors import InputError  # noqa: E402
from rlff.robot import RobotMapping, load_robot  # noqa: E402
from rlff.robot.export import write_ros1_bag, write_ros2_bag  # noqa: E402
from rlff.robot.formats import export_trajectory  # noqa: E402
from rlff.robot.plan import load_for_robot  # noqa: E402
from rlff.robot.sendfile import SENDABLE, load_for_sending  # noqa: E402
from rlff.trajectory.check import MotionLimitError  # noqa: E402
from rosrig import DRIVEN, human_csv  # noqa: E402

ROBOT = load_robot()


@pytest.fixture
def planned(tmp_path):
    path = human_csv(tmp_path / "throw.csv", np.linspace(-0.5, 1.2, 21), np.linspace(0.5, 2.0, 21))
    return path, load_for_robot(path, ROBOT, 0.01)[1].trajectory


@pytest.mark.parametrize("fmt", SENDABLE)
def test_every_sendable_export_reads_back_as_the_planned_trajectory(planned, tmp_path, fmt):
    _, trajectory = planned
    out = tmp_path / f"throw.{fmt}"
    export_trajectory(trajectory, RobotMapping.for_robot(ROBOT), fmt, out)
    start = trajectory.positions[0]
    kind, plan = load_for_sending(out, ROBOT, None, start=start)
    assert kind == {"json": "robot trajectory", "csv": "robot trajectory"}.get(fmt, fmt)
    np.testing.assert_allclose(plan.trajectory.positions, trajectory.positions)
    np.testing.assert_allclose(plan.trajectory.time, trajectory.time, atol=1e-9)


def test_an_export_is_refused_from_anywhere_but_its_start(planned, tmp_path):
    _, trajectory = planned
    out = tmp_path / "throw.json"
    export_trajectory(trajectory, RobotMapping.for_robot(ROBOT), "json", out)
    elsewhere = trajectory.positions[0].copy()
    elsewhere[DRIVEN] += 0.25
    with pytest.raises(MotionLimitError, match=r"throw.json: point 0 \(t = 0.000000 s\): joint_2 position .* is not "
                                               r"where the arm is .*0.25 rad off.*send the generated trajectory CSV"):
        load_for_sending(out, ROBOT, None, start=elsewhere)


def test_a_generated_throw_is_planned_from_the_arm(planned):
    path, _ = planned
    pose = load_for_robot(path, ROBOT, 0.01)[1].trajectory.positions[0].copy()
    pose[DRIVEN] += 0.4
    kind, plan = load_for_sending(path, ROBOT, 0.01, start=pose)
    assert kind == "generated path"
    np.testing.assert_allclose(plan.trajectory.positions[0], pose)


def test_files_that_are_no_trajectory_to_send_are_one_line(planned, tmp_path):
    _, trajectory = planned
    export_trajectory(trajectory, RobotMapping.for_robot(ROBOT), "comau", tmp_path / "throw.txt")
    (tmp_path / "folder").mkdir()
    once, twice = tmp_path / "once.bag", tmp_path / "twice.bag"
    write_ros1_bag(trajectory, once)
    with Reader(once) as reader, Writer(twice) as writer:  # the one message, recorded twice
        [(connection, _, raw)] = list(reader.messages())
        copy = writer.add_connection(connection.topic, connection.msgtype,
                                     typestore=get_typestore(Stores.ROS1_NOETIC))
        for stamp in (1, 2):
            writer.write(copy, stamp, raw)
    for path, message in ((tmp_path / "throw.txt", "a Comau program, which runs on the Comau controller"),
                          (tmp_path / "folder", "a folder, but not a ROS 2 bag (no metadata.yaml)"),
                          (twice, "holds 2 trajectories on /comau/joint_trajectory; send a bag with one"),
                          (tmp_path / "missing.csv", "no such file")):
        with pytest.raises(InputError, match=re.escape(message)) as refused:
            load_for_sending(path, ROBOT, 0.01)
        assert "\n" not in str(refused.value)


def test_an_export_away_from_the_arm_is_refused_or_approached_within_the_limits(planned, tmp_path):
    """Without --approach an export that starts away from the arm is refused; with it, a planned
    approach from the arm at rest comes first, and the whole passes the motion check from there."""
    from rlff.trajectory.check import check_trajectory

    _, trajectory = planned
    out = tmp_path / "throw.json"
    export_trajectory(trajectory, RobotMapping.for_robot(ROBOT), "json", out)
    arm = trajectory.positions[0].copy()
    arm[DRIVEN] += 0.6  # the arm rests 0.6 rad away from the first point
    with pytest.raises(InputError, match="--approach"):
        load_for_sending(out, ROBOT, 0.01, start=arm)
    _, plan = load_for_sending(out, ROBOT, 0.01, start=arm, approach=True)
    sent = plan.trajectory
    check_trajectory(sent, ROBOT.joints, start=arm)
    np.testing.assert_allclose(sent.positions[0], arm)
    approach = sent.duration - trajectory.duration
    assert approach > 0.1  # 0.6 rad cannot be crossed faster within the velocity limit
    np.testing.assert_allclose(sent.positions[-1], trajectory.positions[-1])
    assert sent.release_time == pytest.approx(trajectory.release_time + approach)
    # already there: nothing is prepended
    _, same = load_for_sending(out, ROBOT, 0.01, start=trajectory.positions[0], approach=True)
    assert same.trajectory.duration == pytest.approx(trajectory.duration)


@pytest.mark.parametrize("fmt", ["ros1-bag", "ros2-bag"])
def test_a_bag_carries_the_robot_file_s_trajectory_topic_and_is_read_back_from_it(planned, tmp_path, fmt):
    """`rlff robot export --robot arm.toml` writes the bag on the file's [ros] trajectory_topic (a
    real bag, read with rosbags); sending it reads it from there, and with a robot whose topic is
    another the bag is refused, naming both topics."""
    from rosbags.rosbag2 import Reader as Ros2Reader

    from rlff.cli import main
    from rosrig import robot_file

    path, trajectory = planned
    arm = robot_file(tmp_path, "arm.toml", lambda text: text.replace(
        'trajectory_topic = "/comau/joint_trajectory"', 'trajectory_topic = "/arm/joint_trajectory"'))
    out = tmp_path / ("throw.bag" if fmt == "ros1-bag" else "throw2")
    assert main(["robot", "export", str(path), "-f", fmt, "--robot", str(arm), "--period", "0.01",
                 "-o", str(out)]) == 0
    with (Reader(out) if fmt == "ros1-bag" else Ros2Reader(out)) as reader:
        assert [(c.topic, c.msgtype) for c in reader.connections] == [
            ("/arm/joint_trajectory", "trajectory_msgs/msg/JointTrajectory")]
    robot = load_robot(arm)
    kind, plan = load_for_sending(out, robot, None, start=trajectory.positions[0])
    assert kind == fmt
    np.testing.assert_allclose(plan.trajectory.positions, trajectory.positions)
    np.testing.assert_allclose(plan.trajectory.time, trajectory.time, atol=1e-9)
    with pytest.raises(InputError) as refused:
        load_for_sending(out, ROBOT, None, start=trajectory.positions[0])
    assert str(refused.value) == (
        f"{out}: holds no trajectory on /comau/joint_trajectory (the [ros] trajectory_topic of built-in robot "
        "comau_smart5_six), but JointTrajectory messages on /arm/joint_trajectory: export it again with this robot "
        "file, or send it with the robot file it was exported with")


def test_a_dry_run_names_the_joint_nearest_its_speed_limit(planned):
    from rlff.robot.send import fastest_joint_line

    _, trajectory = planned
    peak = np.abs(trajectory.velocities).max(axis=0) / [joint.max_velocity for joint in ROBOT.joints]
    top = ROBOT.joints[int(np.argmax(peak))]
    assert top.name == "joint_2"  # the throw's joint, planned up to its limit at the release
    assert fastest_joint_line(ROBOT, trajectory) == (f"fastest: joint_2 at {peak.max():.0%} of its "
                                                      f"{top.max_velocity:g} rad/s")


def _raw_messages(path: Path) -> list[bytes]:
    """The serialized messages of a ROS 1 bag (a file) or a ROS 2 bag (a folder), as stored."""
    from rosbags.rosbag2 import Reader as Ros2Reader

    with (Ros2Reader(path) if path.is_dir() else Reader(path)) as reader:
        return [raw for _, _, raw in reader.messages()]


@pytest.mark.parametrize("fmt", ["ros1-bag", "ros2-bag"])
def test_a_bag_of_a_mapped_robot_is_the_controller_s_and_reads_back_into_rlff_s(planned, tmp_path, fmt):
    """A robot file with [ros.joints]: the exported bag names the controller's joints with its
    positions (offset + sign * rlff's, velocities and accelerations times the sign); `robot send`
    reads it back into rlff's convention (within rounding); a robot file without the map finds
    none of its joints in it. JSON keeps rlff's names."""
    from rlff.cli import main
    from rlff.robot.export import read_bag, read_json, write_ros1_bag, write_ros2_bag
    from rosrig import UR_NAMES, ur_file

    path, trajectory = planned
    mapped = load_robot(ur_file(tmp_path / "ur.toml"))
    out = tmp_path / ("throw.bag" if fmt == "ros1-bag" else "throw2")
    assert main(["robot", "export", str(path), "-f", fmt, "--robot", mapped.source, "--period", "0.01",
                 "-o", str(out)]) == 0
    (stored,) = read_bag(out)
    assert stored.joint_names == UR_NAMES
    expected = mapped.ros.joints.to_controller(trajectory)
    np.testing.assert_array_equal(stored.positions, expected.positions)
    np.testing.assert_array_equal(stored.velocities, expected.velocities)
    np.testing.assert_array_equal(stored.accelerations, expected.accelerations)
    assert np.any(stored.positions[:, 1] != trajectory.positions[:, 1])  # the offset is there

    kind, plan = load_for_sending(out, mapped, None, start=trajectory.positions[0])
    assert kind == fmt and plan.trajectory.joint_names == trajectory.joint_names
    np.testing.assert_allclose(plan.trajectory.positions, trajectory.positions, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(plan.trajectory.velocities, trajectory.velocities)
    np.testing.assert_allclose(plan.trajectory.time, trajectory.time, atol=1e-9)
    with pytest.raises(InputError, match=r"unknown joints|not a joint|shoulder_pan_joint"):
        load_for_sending(out, ROBOT, None, start=trajectory.positions[0])
    # a bag of rlff's names sent with the mapped file: refused, saying why
    plain = tmp_path / ("plain.bag" if fmt == "ros1-bag" else "plain2")
    export_trajectory(trajectory, RobotMapping.for_robot(ROBOT), fmt, plain)
    with pytest.raises(InputError, match=re.escape(
            f"{plain}: joint_1 is not a joint of the arm's controller: the robot file's [ros.joints.joint_1] calls "
            "rlff's joint_1 shoulder_pan_joint; export it again with this robot file, or send it with the robot file "
            "it was exported with")):
        load_for_sending(plain, mapped, None, start=trajectory.positions[0])
    # without a map the bag's message is the writer's own, byte for byte (as before [ros.joints])
    direct = tmp_path / ("direct.bag" if fmt == "ros1-bag" else "direct2")
    (write_ros1_bag if fmt == "ros1-bag" else write_ros2_bag)(trajectory, direct)
    assert _raw_messages(plain) == _raw_messages(direct)
    # JSON stays in rlff's names and convention
    export_trajectory(trajectory, RobotMapping.for_robot(mapped), "json", tmp_path / "t.json")
    assert read_json(tmp_path / "t.json").joint_names == trajectory.joint_names


@pytest.mark.parametrize("fmt", ["ros1-bag", "ros2-bag"])
def test_a_bag_written_under_another_ros_joints_map_is_refused(planned, tmp_path, fmt):
    """A bag is in the controller's convention: exported, then joint_2's sign fixed in the robot
    file (as docs/robot.md says for a joint that moves the wrong way), it was read through the new
    map without a word (same limits, same digest) and threw the ball behind the arm (tester H,
    2026-12-07). The bag records the map; another map is refused, the same one read as before."""
    from rosrig import UR_MAP, ur_file

    path, trajectory = planned
    mapped = load_robot(ur_file(tmp_path / "ur.toml"))
    flipped_map = UR_MAP.replace('name = "shoulder_lift_joint"\noffset = -1.5707963267948966',
                                 'name = "shoulder_lift_joint"\noffset = -1.5707963267948966\nsign = -1')
    assert flipped_map != UR_MAP
    flipped = load_robot(ur_file(tmp_path / "ur_sign.toml", flipped_map))
    out = tmp_path / ("throw.bag" if fmt == "ros1-bag" else "throw2")
    export_trajectory(trajectory, RobotMapping.for_robot(mapped), fmt, out)
    kind, plan = load_for_sending(out, mapped, None, start=trajectory.positions[0])
    np.testing.assert_allclose(plan.trajectory.positions, trajectory.positions, rtol=0, atol=1e-12)
    with pytest.raises(InputError, match=re.escape(
            f"{out} was written with another [ros.joints] map (the controller's joint names, offsets and signs: "
            "digest ")) as refused:
        load_for_sending(out, flipped, None, start=trajectory.positions[0])
    assert "export it again with this robot file" in str(refused.value)


def test_a_bag_of_controller_names_the_robot_file_does_not_map_says_what_to_do(planned, tmp_path):
    """Exported with joint_2 renamed in [ros.joints], sent with a file without it: "unknown joint
    names ['shoulder_lift_joint']" alone, no word of the map nor of what to do (reviewer J)."""
    from rosrig import ur_file

    _, trajectory = planned
    mapped = load_robot(ur_file(tmp_path / "ur.toml"))
    out = tmp_path / "throw.bag"
    export_trajectory(trajectory, RobotMapping.for_robot(mapped), "ros1-bag", out)
    with pytest.raises(InputError) as refused:
        load_for_sending(out, ROBOT, None, start=trajectory.positions[0])
    assert str(refused.value).startswith(f"{out}: holds joints shoulder_pan_joint, shoulder_lift_joint, ")
    assert str(refused.value).endswith(
        "which built-in robot comau_smart5_six does not have (its controller's joint names: joint_1, joint_2, "
        "joint_3, joint_4, joint_5, joint_6): the bag was written with another [ros.joints] map; export it again "
        "with this robot file, or send it with the robot file it was exported with")


def test_a_ros2_bag_given_by_its_metadata_yaml_is_sent_as_its_folder(planned, tmp_path):
    # robot send of the bag's metadata.yaml read it as a generated path ("columns:
    # rosbag2_bagfile_information:"); data import takes it as its folder since 2026-12-07
    path, trajectory = planned
    out = tmp_path / "throw2"
    export_trajectory(trajectory, RobotMapping.for_robot(ROBOT), "ros2-bag", out)
    kind, plan = load_for_sending(out / "metadata.yaml", ROBOT, None, start=trajectory.positions[0])
    folder_kind, folder_plan = load_for_sending(out, ROBOT, None, start=trajectory.positions[0])
    assert kind == folder_kind == "ros2-bag"
    np.testing.assert_array_equal(plan.trajectory.positions, folder_plan.trajectory.positions)


def test_a_bag_that_does_not_say_its_map_is_read_through_the_robot_file_s_with_a_warning(planned, tmp_path):
    """A bag of rlff written before the map was recorded (the robot's name and digest alone) is
    read through the robot file's map, warned where that map changes a joint."""
    from rlff.robot.planned_for import UnrecordedRobotWarning, planned_for
    from rosrig import ur_file

    _, trajectory = planned
    mapped = load_robot(ur_file(tmp_path / "ur.toml"))
    old = tmp_path / "old.bag"
    write_ros1_bag(mapped.ros.joints.to_controller(trajectory), old, robot=planned_for(mapped))
    with pytest.warns(UnrecordedRobotWarning, match=r"does not say which \[ros.joints\] map its positions are in"):
        _, plan = load_for_sending(old, mapped, None, start=trajectory.positions[0])
    np.testing.assert_allclose(plan.trajectory.positions, trajectory.positions, rtol=0, atol=1e-12)
    plain = tmp_path / "plain.bag"  # the built-in robot has no map: nothing to warn of
    write_ros1_bag(trajectory, plain, robot=planned_for(ROBOT))
    with warnings.catch_warnings():
        warnings.simplefilter("error", UnrecordedRobotWarning)
        load_for_sending(plain, ROBOT, None, start=trajectory.positions[0])


def test_a_mapped_bag_away_from_the_arm_is_refused_in_the_controller_s_words(planned, tmp_path):
    """With [ros.joints], the joint whose start is not where the arm is was named as rlff's joint_2
    alone (tester H); it is named as the approach line names it, the controller's name and counting
    (the bag's and the arm's joint states'), rlff's name beside it."""
    from rosrig import ur_file

    _, trajectory = planned
    mapped = load_robot(ur_file(tmp_path / "ur.toml"))
    out = tmp_path / "throw.bag"
    export_trajectory(trajectory, RobotMapping.for_robot(mapped), "ros1-bag", out)
    arm = trajectory.positions[0].copy()
    arm[4] += 0.2  # wrist_2_joint counts joint_5 the other way, from 0.25 rad
    with pytest.raises(MotionLimitError, match=re.escape(
            f"{out}: point 0 (t = 0.000000 s): wrist_2_joint (joint_5) position {0.25 - arm[4] + 0.2:.6g} rad is not "
            f"where the arm is ({0.25 - arm[4]:.6g} rad; 0.2 rad off, tolerance 0.001 rad); send with approach (--approach)")):
        load_for_sending(out, mapped, None, start=arm)
    # without a map, rlff's names and values, as before
    plain = tmp_path / "plain.json"
    export_trajectory(trajectory, RobotMapping.for_robot(ROBOT), "json", plain)
    with pytest.raises(MotionLimitError, match=re.escape(
            f"{plain}: point 0 (t = 0.000000 s): joint_5 position {arm[4] - 0.2:.6g} rad is not where the arm is "
            f"({arm[4]:.6g} rad; 0.2 rad off")):
        load_for_sending(plain, ROBOT, None, start=arm)


@pytest.mark.parametrize("fmt", ["ros1-bag", "ros2-bag"])
def test_a_bag_sent_as_it_is_must_start_at_rest(planned, tmp_path, fmt):
    """A bag's first point was checked against the arm's position and velocity, never its
    acceleration (and without the arm's pose, before robot send connects, not at all): a
    hand-made bag whose first point accelerates went out as a goal, which every other robot
    output and read-back refuses (check_trajectory(start_at_rest=True))."""
    from rlff.robot.export import write_ros2_bag

    _, trajectory = planned
    write = write_ros1_bag if fmt == "ros1-bag" else write_ros2_bag
    accelerating = trajectory.accelerations.copy()
    accelerating[0, DRIVEN] = 2.5  # at the arm's pose, at rest, but already accelerating
    out = tmp_path / ("accelerating.bag" if fmt == "ros1-bag" else "accelerating")
    write(replace(trajectory, accelerations=accelerating), out)
    for start in (trajectory.positions[0], None):  # from the arm's pose, and before robot send connects
        with pytest.raises(MotionLimitError, match=re.escape(
                f"{out}: point 0 (t = 0.000000 s): the trajectory starts with joint_2 acceleration 2.5 rad/s^2, "
                "not at rest (tolerance 0.01 rad/s^2)")) as refused:
            load_for_sending(out, ROBOT, None, start=start)
        assert "--approach" not in str(refused.value)  # moving there first would not start it at rest


@pytest.mark.parametrize("fmt", ["ros1-bag", "ros2-bag"])
def test_a_bag_is_sent_only_to_the_robot_it_was_planned_for(planned, tmp_path, capsys, fmt):
    """A slow arm's bag sent with `robot send` and the built-in Comau's file was checked against
    the Comau's limits alone, and passed: bags kept no record of their robot, as JSON and CSV do.
    It is refused now, naming both robots, before any connection; sent with its own robot file
    it goes, and a bag that keeps no record (an older one, another tool's) is read with a warning."""
    from rlff.cli import main
    from rlff.robot.planned_for import UnrecordedRobotWarning
    from robotfiles import slow_arm

    slow = slow_arm(tmp_path)
    path = human_csv(tmp_path / "slow.csv", np.linspace(-0.5, 1.5, 21), np.full(21, 1.2))  # within its 1.6 rad/s
    out = tmp_path / ("slow.bag" if fmt == "ros1-bag" else "slow")
    assert main(["robot", "export", str(path), "--robot", str(slow), "-f", fmt, "--period", "0.01",
                 "-o", str(out)]) == 0
    capsys.readouterr()
    assert main(["robot", "send", str(out)]) == 2  # refused before rlff looks for a roscore
    said = " ".join(capsys.readouterr().err.split())
    assert re.search(rf"error: {re.escape(str(out))} was planned for another robot \(slow_arm, digest [0-9a-f]{{16}} "
                     r"in the file; comau_smart5_six, digest [0-9a-f]{16}, with built-in robot comau_smart5_six\): its "
                     r"limits and speeds are that robot's; give its robot file as robot \(--robot\)", said), said
    robot = load_robot(slow)
    trajectory = load_for_robot(path, robot, 0.01)[1].trajectory
    with warnings.catch_warnings():
        warnings.simplefilter("error", UnrecordedRobotWarning)
        _, plan = load_for_sending(out, robot, None, start=trajectory.positions[0])
    np.testing.assert_allclose(plan.trajectory.positions, trajectory.positions)
    # the Comau's throw, in a bag that keeps no record, sent with the slow arm's file: which one checked it is said
    _, comau_throw = planned
    unrecorded = tmp_path / ("unrecorded.bag" if fmt == "ros1-bag" else "unrecorded")
    (write_ros1_bag if fmt == "ros1-bag" else write_ros2_bag)(comau_throw, unrecorded)
    with pytest.warns(UnrecordedRobotWarning, match=re.escape(
            f"{unrecorded} does not say which robot it was planned for (written before rlff recorded it, by hand or "
            f"by another tool): checked and converted for slow_arm ({slow})")):
        with pytest.raises(MotionLimitError, match=re.escape(" beyond the limit 1.6 rad/s") + r".*" + re.escape(
                f"(checked against {slow}; a trajectory planned for another robot is checked with its file: robot (--robot))")):
            load_for_sending(unrecorded, robot, None, start=comau_throw.positions[0])
