"""Fuzzing the bag readers: damaged ROS 1 and ROS 2 bags load (up to the damage, with a warning)
or are an InputError naming the bag; nothing else escapes.

Skeleton bags come from tests/bagfactory.py (a short simulated throw, lz4 chunks and a camera
stream), trajectory bags from rlff.robot.export. See tests/fuzz.py for the damage.
"""

from __future__ import annotations

import shutil
import sys
import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

sys.path.insert(0, str(Path(__file__).parent))
import bagfactory as bf  # noqa: E402
from fuzz import FUZZ, check_reader, damaged_bytes, damaged_text, file_with  # noqa: E402

#: Bags take longer to read than small text files: fewer examples.
BAG_FUZZ = settings(FUZZ, max_examples=40)


def _short_session() -> bf.Simulation:
    return bf.standard_simulation(seed=4, n_throws=1, second_user=False)


@pytest.fixture(scope="module")
def skeleton_bag(tmp_path_factory) -> bytes:
    path = tmp_path_factory.mktemp("seed") / "session.bag"
    bf.write_ros1_bag(path, _short_session(), compression="lz4", images=bf.jpeg_frames(2), image_every=10)
    return path.read_bytes()


@pytest.fixture(scope="module")
def skeleton_bag2(tmp_path_factory) -> Path:
    return bf.write_ros2_bag(tmp_path_factory.mktemp("seed") / "session2", _short_session())


def _trajectory():
    from rlff.trajectory.joint import JointTrajectory

    time = np.linspace(0.0, 0.4, 5)
    positions = np.column_stack([np.sin(time), np.cos(time)])
    return JointTrajectory(("joint_1", "joint_2"), time, positions, np.gradient(positions, time, axis=0))


@pytest.fixture(scope="module")
def trajectory_bag(tmp_path_factory) -> bytes:
    from rlff.robot.export import write_ros1_bag

    path = tmp_path_factory.mktemp("seed") / "trajectory.bag"
    write_ros1_bag(_trajectory(), path, stamp_ns=1_700_000_000_000_000_000)
    return path.read_bytes()


@pytest.fixture(scope="module")
def trajectory_bag2(tmp_path_factory) -> Path:
    from rlff.robot.export import write_ros2_bag

    path = tmp_path_factory.mktemp("seed") / "trajectory2"
    write_ros2_bag(_trajectory(), path, stamp_ns=1_700_000_000_000_000_000)
    return path


def _read_skeleton(path: Path):
    from rlff.capture.bag import read_bag

    recording = read_bag(path)
    for arm in recording.arms:
        for joint in (arm.shoulder, arm.elbow, arm.hand):
            assert np.all(np.isfinite(joint.time)) and np.all(np.isfinite(joint.position))
    return recording


def _read_trajectories(path: Path):
    from rlff.robot.export import read_bag

    trajectories = read_bag(path)
    for trajectory in trajectories:
        assert np.all(np.isfinite(trajectory.positions)) and np.all(np.isfinite(trajectory.velocities))
    return trajectories


def test_seed_bags_read_back(skeleton_bag, skeleton_bag2, trajectory_bag, trajectory_bag2):
    with file_with(skeleton_bag, "session.bag") as path:
        assert _read_skeleton(path).arms
    assert _read_skeleton(skeleton_bag2).arms
    with file_with(trajectory_bag, "trajectory.bag") as path:
        (back,) = _read_trajectories(path)
        np.testing.assert_allclose(back.positions, _trajectory().positions)
    assert len(_read_trajectories(trajectory_bag2)) == 1


@BAG_FUZZ
@given(data=st.data())
def test_ros1_skeleton_bag(skeleton_bag, data):
    with file_with(data.draw(damaged_bytes(skeleton_bag)), "session.bag") as path:
        check_reader(_read_skeleton, path)


@pytest.fixture(scope="module")
def plain_skeleton_bag(tmp_path_factory) -> bytes:
    path = tmp_path_factory.mktemp("seed") / "plain.bag"
    bf.write_ros1_bag(path, _short_session(), compression=None)
    return path.read_bytes()


def _import_skeleton(path: Path):
    from rlff.capture import import_recordings

    dataset, report = import_recordings([path], "bag")
    for trajectory in dataset:
        assert np.all(np.isfinite(trajectory["angle"])) and np.all(np.isfinite(trajectory["velocity"]))
    return dataset


@BAG_FUZZ
@given(data=st.data())
def test_ros1_skeleton_bag_with_bad_translations(plain_skeleton_bag, data):
    """Translations of some arm and torso transforms set to nan, inf, 0 or far away: the import
    reads them as joints not tracked there (a nan in an extension once crashed it with an internal
    ValueError)."""
    import struct

    content = bytearray(plain_skeleton_bag)
    names = [f"{joint}_1".encode() for joint in ("right_shoulder", "right_elbow", "right_hand", "neck", "right_hip",
                                                 "left_hip", "torso", "left_elbow")]
    for _ in range(data.draw(st.integers(1, 12))):
        name = data.draw(st.sampled_from(names))
        at = -1
        for _ in range(data.draw(st.integers(1, 60))):
            at = content.find(name, at + 1)
            if at < 0:
                break
        if at < 0:
            continue
        value = data.draw(st.sampled_from((float("nan"), float("inf"), -float("inf"), 1e308, 1e30, 150.0, 0.0)))
        axis = data.draw(st.integers(0, 2))
        struct.pack_into("<d", content, at + len(name) + 8 * axis, value)
    with file_with(bytes(content), "session.bag") as path:
        check_reader(_import_skeleton, path)


@BAG_FUZZ
@given(data=st.data())
def test_ros1_trajectory_bag(trajectory_bag, data):
    with file_with(data.draw(damaged_bytes(trajectory_bag)), "trajectory.bag") as path:
        check_reader(_read_trajectories, path)


def _damaged_folder(seed: Path, data: st.DataObject) -> tempfile.TemporaryDirectory:
    """A copy of a ROS 2 bag folder with its metadata.yaml (as text) or its database damaged."""
    folder = tempfile.TemporaryDirectory(prefix="rlff-fuzz-")
    copy = Path(folder.name) / seed.name
    shutil.copytree(seed, copy)
    target = data.draw(st.sampled_from(sorted(p.name for p in copy.iterdir())))
    original = (copy / target).read_bytes()
    if target.endswith(".yaml"):
        damage = damaged_text(original.decode()) | damaged_bytes(original)
    else:
        damage = damaged_bytes(original)
    (copy / target).write_bytes(data.draw(damage))
    return folder


@pytest.mark.slow
@BAG_FUZZ
@given(data=st.data())
def test_ros2_skeleton_bag(skeleton_bag2, data):
    with _damaged_folder(skeleton_bag2, data) as folder:
        check_reader(_read_skeleton, Path(folder) / skeleton_bag2.name)


@pytest.mark.slow
@BAG_FUZZ
@given(data=st.data())
def test_ros2_trajectory_bag(trajectory_bag2, data):
    with _damaged_folder(trajectory_bag2, data) as folder:
        check_reader(_read_trajectories, Path(folder) / trajectory_bag2.name)


@pytest.mark.parametrize("occurrence", [0, 40])
def test_a_tf_message_with_a_damaged_length_is_skipped_not_allocated(tmp_path, occurrence):
    """A frame name's length field set to 2 GB: once read as a 16 GB index array (the machine ran
    out of memory); now the message is skipped with a warning and the rest of the bag is read.
    Occurrence 0 is the first message of its length (parsed with struct), 40 one decoded in a
    batch."""
    path = bf.write_ros1_bag(tmp_path / "s.bag", _short_session(), compression=None)
    content = bytearray(path.read_bytes())
    name = b"right_elbow_1"
    at = -1
    for _ in range(occurrence + 1):
        at = content.index(name, at + 1)
    assert content[at - 4 : at] == len(name).to_bytes(4, "little")
    content[at - 4 : at] = (2**31 - 1).to_bytes(4, "little")
    path.write_bytes(bytes(content))
    recording = _read_skeleton(path)
    assert recording.arms
    assert any("skipped 1 damaged /tf messages" in warning for warning in recording.warnings), recording.warnings


def test_a_ros2_bag_whose_metadata_has_a_wrong_type_is_an_input_error(skeleton_bag2, tmp_path):
    """rosbags raised a bare TypeError for a duration that is text (found by the fuzz)."""
    import re

    from rlff.errors import InputError

    copy = tmp_path / skeleton_bag2.name
    shutil.copytree(skeleton_bag2, copy)
    metadata = copy / "metadata.yaml"
    text, replaced = re.subn(r"nanoseconds: \d+", 'nanoseconds: "soon"', metadata.read_text(), count=1)
    assert replaced == 1
    metadata.write_text(text)
    with pytest.raises(InputError, match="not a readable ROS 2 bag") as caught:
        _read_skeleton(copy)
    assert str(copy) in str(caught.value)
