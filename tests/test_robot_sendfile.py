"""What ``rlff robot send`` reads: every export that makes sense over ROS, checked from the arm's pose."""

from __future__ import annotations

import re
import sys
from pathlib import Path

import numpy as np
import pytest
from rosbags.rosbag1 import Reader, Writer
from rosbags.typesys import Stores, get_typestore

sys.path.insert(0, str(Path(__file__).parent))
from rlff.errors import InputError  # noqa: E402
from rlff.robot import RobotMapping, load_robot  # noqa: E402
from rlff.robot.export import write_ros1_bag  # noqa: E402
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
