"""Exports: JSON and CSV read back exactly; ROS 1 and ROS 2 bags read back with rosbags."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from rosbags.rosbag1 import Reader as Ros1Reader
from rosbags.rosbag2 import Reader as Ros2Reader
from rosbags.typesys import Stores, get_typestore

from rlff.errors import InputError
from rlff.robot.export import (
    JOINT_TRAJECTORY_MD5,
    read_bag,
    read_csv,
    read_json,
    require_release,
    trajectory_topics,
    write_csv,
    write_json,
    write_ros1_bag,
    write_ros2_bag,
)
from rlff.trajectory import JointTrajectory


@pytest.fixture
def traj() -> JointTrajectory:
    rng = np.random.default_rng(7)
    time = np.array([0.0, 0.002, 0.5, 1.0 - 1e-10, 1.25, 3.000000001])
    return JointTrajectory(("joint_1", "joint_2", "joint_3"), time, rng.normal(size=(6, 3)),
                           rng.normal(size=(6, 3)), rng.normal(size=(6, 3)))


def assert_same(back: JointTrajectory, traj: JointTrajectory, time_atol: float = 0.0) -> None:
    assert back.joint_names == traj.joint_names
    np.testing.assert_allclose(back.time, traj.time, rtol=0, atol=time_atol)
    for name in ("positions", "velocities", "accelerations"):
        np.testing.assert_array_equal(getattr(back, name), getattr(traj, name))


def test_json_and_csv_read_back_exactly(traj, tmp_path):
    write_json(traj, tmp_path / "t.json")
    assert_same(read_json(tmp_path / "t.json"), traj)
    write_csv(traj, tmp_path / "t.csv")
    assert (tmp_path / "t.csv").read_text().splitlines()[0].startswith(
        "time,joint_1_position,joint_1_velocity,joint_1_acceleration,joint_2_position")
    assert_same(read_csv(tmp_path / "t.csv"), traj)


def test_ros1_bag_reads_back_with_the_standard_checksum(traj, tmp_path):
    path = tmp_path / "t.bag"
    write_ros1_bag(traj, path, stamp_ns=1_700_000_000_123_456_789)
    with Ros1Reader(path) as reader:
        (connection,) = reader.connections
        assert connection.topic == "/comau/joint_trajectory"  # the default [ros] trajectory_topic
        assert connection.msgtype == "trajectory_msgs/msg/JointTrajectory"
        assert connection.digest == JOINT_TRAJECTORY_MD5 == "65b4f94a94d1ed67169da35a02f33d3f"
        assert [stamp for _, stamp, _ in reader.messages()] == [1_700_000_000_123_456_789]
    (back,) = read_bag(path)
    assert_same(back, traj, time_atol=1e-9)  # time_from_start is whole nanoseconds


def test_ros2_bag_reads_back(traj, tmp_path):
    path = tmp_path / "bag2"
    write_ros2_bag(traj, path, stamp_ns=5)
    # its database is named after the bag, not after a temporary folder a user would clean up
    assert sorted(p.name for p in path.iterdir()) == ["bag2.db3", "metadata.yaml"]
    assert [p.name for p in tmp_path.iterdir()] == ["bag2"]
    with Ros2Reader(path) as reader:
        (connection,) = reader.connections
        assert (connection.topic, connection.msgtype) == ("/comau/joint_trajectory",
                                                          "trajectory_msgs/msg/JointTrajectory")
    (back,) = read_bag(path)
    assert_same(back, traj, time_atol=1e-9)
    write_ros2_bag(traj, path, stamp_ns=7)  # a bag of trajectories is replaced whole, as a file is
    with Ros2Reader(path) as reader:
        assert [stamp for _, stamp, _ in reader.messages()] == [7]
    assert sorted(p.name for p in tmp_path.rglob("*")) == ["bag2", "bag2.db3", "metadata.yaml"]
    (path / "notes.txt").write_text("mine\n")  # no longer only a bag: kept
    with pytest.raises(InputError, match="bag2: a folder, and not a ROS 2 bag of robot trajectories"):
        write_ros2_bag(traj, path, stamp_ns=9)
    assert (path / "notes.txt").read_text() == "mine\n"


@pytest.mark.parametrize("writer, name", [(write_ros1_bag, "t.bag"), (write_ros2_bag, "bag2")])
def test_a_bag_is_read_on_its_topic_only(traj, tmp_path, writer, name):
    """A bag written on another topic (another robot file's [ros] trajectory_topic) holds nothing
    on the default one; before, rosbags read every connection when none matched."""
    writer(traj, tmp_path / name, topic="/arm/joint_trajectory", stamp_ns=1)
    assert read_bag(tmp_path / name) == []
    (back,) = read_bag(tmp_path / name, "/arm/joint_trajectory")
    assert_same(back, traj, time_atol=1e-9)
    assert trajectory_topics(tmp_path / name) == ["/arm/joint_trajectory"]


def test_nanosecond_rounding_carries_into_seconds(tmp_path):
    traj = JointTrajectory(("j",), [0.0, 1.9999999999], [[0.0], [1.0]], [[0.0], [0.0]])
    write_ros1_bag(traj, tmp_path / "t.bag", stamp_ns=1)
    (back,) = read_bag(tmp_path / "t.bag")
    assert back.time[-1] == 2.0


@pytest.mark.ros
def test_ros1_checksum_is_the_one_of_ros_itself():
    """Debian's generated trajectory_msgs class carries the same MD5 (needs the ROS packages).

    Asked in a child: the ROS 2 wheels' trajectory_msgs comes first in this process, and putting
    ROS 1's first here (rlff.robot.ros1 does) would hide it from the ROS 2 tests of this worker.
    """
    probe = subprocess.run([sys.executable, "-c", "import rlff.robot.ros1, trajectory_msgs.msg as m; "
                            "print(m.JointTrajectory._md5sum)"], capture_output=True, text=True, timeout=120)
    if probe.returncode and os.environ.get("CI") != "true":  # in CI the ROS packages must be there
        pytest.skip(f"Debian's ROS 1 trajectory_msgs is not reachable: {probe.stderr.strip()[-200:]}")
    assert probe.stdout.strip() == JOINT_TRAJECTORY_MD5, probe.stderr


def test_foreign_json_is_refused(tmp_path):
    (tmp_path / "x.json").write_text('{"format": "other"}')
    with pytest.raises(InputError, match="not an rlff-joint-trajectory file"):
        read_json(tmp_path / "x.json")


def _header_stamps(path) -> list[tuple[int, int]]:
    from rosbags.typesys import Stores, get_typestore

    ros1 = not path.is_dir()
    typestore = get_typestore(Stores.ROS1_NOETIC if ros1 else Stores.ROS2_HUMBLE)
    stamps = []
    with (Ros1Reader(path) if ros1 else Ros2Reader(path)) as reader:
        for connection, _, raw in reader.messages():
            message = (typestore.deserialize_ros1 if ros1 else typestore.deserialize_cdr)(raw, connection.msgtype)
            stamps.append((message.header.stamp.sec, message.header.stamp.nanosec))
    return stamps


@pytest.mark.parametrize("writer, name", [(write_ros1_bag, "t.bag"), (write_ros2_bag, "bag2")])
def test_bags_stamp_the_header_zero_unless_asked(traj, tmp_path, writer, name):
    """ROS convention: header.stamp 0 = start on receipt; the bag's record time stays the given one."""
    writer(traj, tmp_path / name, stamp_ns=1_700_000_000_000_000_000)
    assert _header_stamps(tmp_path / name) == [(0, 0)]
    writer(traj, tmp_path / f"asked-{name}", stamp_ns=7, header_stamp_ns=2_000_000_003)
    assert _header_stamps(tmp_path / f"asked-{name}") == [(2, 3)]


def released(traj: JointTrajectory, at: int) -> JointTrajectory:
    """``traj`` released at its point ``at``, every joint at its fastest there (as a planned throw)."""
    velocities = traj.velocities.copy()
    velocities[at] = np.abs(velocities).max(axis=0) + 1.0
    return JointTrajectory(traj.joint_names, traj.time, traj.positions, velocities, traj.accelerations,
                           release_time=traj.time[at])


def test_json_carries_the_release_time(traj, tmp_path):
    thrown = released(traj, 2)
    write_json(thrown, tmp_path / "t.json")
    assert read_json(tmp_path / "t.json").release_time == 0.5
    write_json(traj, tmp_path / "none.json")
    assert read_json(tmp_path / "none.json").release_time is None


@pytest.mark.parametrize(("write", "read", "suffix"), [(write_json, read_json, "json"), (write_csv, read_csv, "csv")])
def test_a_release_time_the_throw_is_not_released_at_is_refused(tmp_path, write, read, suffix):
    """An edited release_time between two samples, or in the braking (0.9 s of a throw released at
    0.634 s), was taken and sim throw let go there (tester H). A release at a sample where every
    moving joint is at its fastest since the arm last rested is taken (rounded: the sample's own
    time), and so is one at rest where the motion ends: a throw released at rest ends there."""
    speeds = {"throw": [0.0, 1.0, 2.0, 3.0, 2.0, 1.0, 0.0], "twice": [0.0, 1.0, 0.0, 1.0, 2.0, 1.0, 0.0]}

    def read_back(kind: str, release: float) -> JointTrajectory:
        time = np.array([0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6])
        velocities = np.stack([speeds[kind], np.zeros(7)], axis=1)
        path = tmp_path / f"{kind}.{suffix}"
        write(JointTrajectory(("joint_1", "joint_2"), time, np.cumsum(velocities, axis=0) * 0.1, velocities,
                              release_time=0.3), path)
        text = path.read_text()  # the edit: 0.3 on the line of the release time, or in its column
        path.write_text(text.replace('"release_time": 0.3}', f'"release_time": {release!r}}}') if suffix == "json"
                        else "\n".join(line.rsplit(",", 1)[0] + f",{release!r}" if number else line
                                       for number, line in enumerate(text.splitlines())) + "\n")
        return require_release(path, read(path))

    assert read_back("throw", 0.3 + 4e-7).release_time == 0.3
    assert read_back("throw", 0.6).release_time == 0.6
    assert read_back("twice", 0.4).release_time == 0.4
    for kind, release, said in [
            ("throw", 0.35, "release_time 0.35 s is not one of the trajectory's sample times (the nearest: "
                            "0.3 s); a throw is released at a sample"),
            ("throw", 0.5, "release_time 0.5 s falls where the arm slows down: joint_1 moves at 1 rad/s there, "
                           "after 3 rad/s at 0.3 s; a throw is released at its fastest, before it brakes: give the "
                           "time of the throw's release"),
            ("throw", 0.0, "release_time 0 s falls where the arm rests, before its motion: nothing is thrown there"),
            ("twice", 0.2, "release_time 0.2 s falls where the arm rests, between its moves: nothing is thrown")]:
        with pytest.raises(InputError, match=re.escape(f"{kind}.{suffix}: {said}")):
            read_back(kind, release)


@pytest.mark.parametrize(("units", "said"), [
    ({"positions": "deg"}, "gives positions in 'deg'"),
    ({"time": None}, "gives no unit for time"),
    ({"angles": "rad"}, "has 'angles', which rlff does not know"),
])
def test_json_units_other_than_rlff_s_are_refused(traj, tmp_path, units, said):
    """A JSON saying "positions": "deg" was read as radians without a word (tester H)."""
    write_json(traj, tmp_path / "t.json")
    document = json.loads((tmp_path / "t.json").read_text())
    document["units"] = {name: unit for name, unit in (document["units"] | units).items() if unit is not None}
    (tmp_path / "edited.json").write_text(json.dumps(document))
    with pytest.raises(InputError, match=re.escape(
            f"{tmp_path / 'edited.json'}: field 'units' {said}; rlff reads a trajectory only in time s, positions rad, "
            "velocities rad/s, accelerations rad/s^2: convert the file's values (and its 'units') to those")):
        read_json(tmp_path / "edited.json")
    document["units"] = "SI"
    (tmp_path / "edited.json").write_text(json.dumps(document))
    with pytest.raises(InputError, match="edited.json: field 'units' must be "):
        read_json(tmp_path / "edited.json")
    del document["units"]  # none said: rlff's
    (tmp_path / "edited.json").write_text(json.dumps(document))
    assert_same(read_json(tmp_path / "edited.json"), traj)


def test_csv_carries_the_release_time(traj, tmp_path):
    thrown = released(traj, 4)
    write_csv(thrown, tmp_path / "t.csv")
    back = read_csv(tmp_path / "t.csv")
    assert back.release_time == 1.25
    assert_same(back, thrown)
    table = (tmp_path / "t.csv").read_text().splitlines()
    table[2] = table[2].rsplit(",", 1)[0] + ",2.0"
    (tmp_path / "bad.csv").write_text("\n".join(table) + "\n")
    with pytest.raises(InputError, match="bad.csv: column 'release_time' must hold one number"):
        read_csv(tmp_path / "bad.csv")


def test_a_file_beyond_the_robot_s_limits_says_which_robot_checked_it(tmp_path):
    # a trajectory exported for a faster arm, thrown without its --robot: the Comau's limit was
    # named, not the Comau, so the user could not tell the robot was the wrong one
    from rlff.robot import load_robot
    from rlff.robot.plan import load_for_robot

    comau = load_robot()
    time = np.linspace(0.0, 1.0, 11)
    positions = np.zeros((11, 6))
    positions[:, 1] = -1.0 + 3.0 * time  # joint_2 at 3 rad/s: within a 3.6 rad/s arm's limit, beyond the Comau's
    positions[:, 2], positions[:, 4] = -1.373, -0.198
    velocities = np.gradient(positions, time, axis=0)
    path = tmp_path / "fast.json"
    write_json(JointTrajectory(comau.joint_names, time, positions, velocities), path)
    with pytest.raises(InputError, match=r"fast.json: .*joint_2 velocity 3 rad/s beyond the limit 2.792 rad/s.*"
                                         r"checked against built-in robot comau_smart5_six.*--robot"):
        load_for_robot(path, comau)


def test_the_robot_a_trajectory_was_planned_for_reads_back(traj, tmp_path):
    """JSON and CSV keep the record; a digest of digits alone keeps its leading zeros."""
    from rlff.robot.export import read_planned_for

    record = {"name": "slow_arm", "digest": "0012345678901234"}
    for write, name in ((write_json, "t.json"), (write_csv, "t.csv")):
        write(traj, tmp_path / name, robot=record)
        assert read_planned_for(tmp_path / name) == record
        assert_same((read_json if name.endswith("json") else read_csv)(tmp_path / name), traj)
        write(traj, tmp_path / name)  # a trajectory of no robot, as written before the record
        assert read_planned_for(tmp_path / name) is None
    document = json.loads((tmp_path / "t.json").read_text()) | {"robot": "slow_arm"}
    (tmp_path / "t.json").write_text(json.dumps(document))
    with pytest.raises(InputError, match=r"t.json: field 'robot' must be the robot the trajectory was planned for"):
        read_planned_for(tmp_path / "t.json")


def test_a_bag_keeps_the_robot_its_trajectory_was_planned_for_beside_an_unchanged_trajectory(traj, tmp_path):
    """Bags kept no record, so a bag of one arm was sent to another checked against the limits
    given alone. A ROS 2 bag keeps it in its metadata's custom_data, a ROS 1 bag in the header of
    the trajectory's connection: no topic is added (`rosbag play --wait-for-subscribers` would
    wait for a subscriber to it for ever), and the trajectory's topic, type, MD5 and message are
    those of a bag without it."""
    from rlff.robot.export import read_planned_for

    record = {"name": "slow_arm", "digest": "0012345678901234"}
    for write, name, reader in ((write_ros1_bag, "t.bag", Ros1Reader), (write_ros2_bag, "bag2", Ros2Reader)):
        write(traj, tmp_path / name, stamp_ns=1, robot=record)
        write(traj, tmp_path / f"plain_{name}", stamp_ns=1)  # a bag of no robot, as written before the record
        assert read_planned_for(tmp_path / name) == record
        assert read_planned_for(tmp_path / f"plain_{name}") is None
        (back,) = read_bag(tmp_path / name)
        assert_same(back, traj, time_atol=1e-9)
        with reader(tmp_path / name) as recorded, reader(tmp_path / f"plain_{name}") as plain:
            assert ([(c.topic, c.msgtype, c.digest) for c in recorded.connections]
                    == [(c.topic, c.msgtype, c.digest) for c in plain.connections]
                    == [("/comau/joint_trajectory", "trajectory_msgs/msg/JointTrajectory", plain.connections[0].digest)])
            assert list(recorded.messages()) [0][1:] == list(plain.messages())[0][1:]
    with Ros1Reader(tmp_path / "t.bag") as reader:
        assert reader.connections[0].digest == JOINT_TRAJECTORY_MD5
    assert "custom_data:\n    rlff_robot: slow_arm\n    rlff_robot_digest: '0012345678901234'" in (
        tmp_path / "bag2" / "metadata.yaml").read_text()


@pytest.mark.parametrize("fmt", ["ros1-bag", "ros2-bag"])
def test_a_bag_s_record_of_half_a_robot_is_refused(traj, tmp_path, fmt):
    """A name without its digest (a bag edited, or written by another tool) says nothing sure."""
    from rosbags.rosbag2 import Writer as Ros2Writer

    from rlff.robot.export import read_planned_for
    from rlff.robot.ros1_fields import FieldWriter

    out = tmp_path / ("t.bag" if fmt == "ros1-bag" else "bag2")
    if fmt == "ros1-bag":
        with FieldWriter(out, {"rlff_robot": "slow_arm"}) as writer:
            writer.add_connection("/comau/joint_trajectory", "trajectory_msgs/msg/JointTrajectory",
                                  typestore=get_typestore(Stores.ROS1_NOETIC))
        where = "connection header of /comau/joint_trajectory"
    else:
        with Ros2Writer(out, version=8) as writer:
            writer.add_connection("/comau/joint_trajectory", "trajectory_msgs/msg/JointTrajectory",
                                  typestore=get_typestore(Stores.ROS2_HUMBLE))
            writer.set_custom_data("rlff_robot", "slow_arm")
        where = "metadata's custom_data"
    with pytest.raises(InputError, match="^" + re.escape(
            f"{out}: the bag's {where} must hold rlff_robot and rlff_robot_digest, the robot its trajectory was "
            "planned for, as rlff writes them; it holds rlff_robot='slow_arm'") + "$"):
        read_planned_for(out)


@pytest.mark.ros
def test_rosbag_of_ros_itself_reads_the_record_in_the_connection_header(traj, tmp_path):
    """Debian's rosbag (the Python of the ROS 1 tools, which rosbag play and info run on) reads the
    bag, its message, and the record among the fields of the connection's header."""
    import shutil

    tool = shutil.which("rosbag")
    if tool is None and os.environ.get("CI") != "true":  # in CI the ROS packages must be there
        pytest.skip("Debian's rosbag is not installed (scripts/setup.sh --test installs it)")
    interpreter = Path(tool).read_text().splitlines()[0].removeprefix("#!").split()  # the tools' Python
    path = tmp_path / "t.bag"
    write_ros1_bag(traj, path, robot={"name": "slow_arm", "digest": "0012345678901234"})
    script = ("import rosbag, sys\n"
              "bag = rosbag.Bag(sys.argv[1])\n"
              "(connection,) = bag._connections.values()\n"
              "fields = {name: value.decode() for name, value in connection.header.items()}\n"
              "print(connection.topic, fields['md5sum'], fields['rlff_robot'], fields['rlff_robot_digest'])\n"
              "for topic, message, _ in bag.read_messages():\n"
              "    print(topic, ','.join(message.joint_names), len(message.points))\n")
    probe = subprocess.run([*interpreter, "-c", script, str(path)], capture_output=True, text=True, timeout=120)
    assert probe.stdout.splitlines() == [
        f"/comau/joint_trajectory {JOINT_TRAJECTORY_MD5} slow_arm 0012345678901234",
        f"/comau/joint_trajectory joint_1,joint_2,joint_3 {len(traj)}"], probe.stderr


def test_the_record_is_the_robot_s_limits_and_geometry():
    from dataclasses import replace

    from rlff.robot import load_robot
    from rlff.robot.planned_for import planned_for

    comau = load_robot()
    assert planned_for(comau) == planned_for(replace(comau, source="elsewhere.toml", throwing={}))
    faster = replace(comau, joints=(comau.joints[0], replace(comau.joints[1], max_velocity=3.0), *comau.joints[2:]))
    assert planned_for(faster)["digest"] != planned_for(comau)["digest"]
