"""ROS bags written from a known simulated motion give back that motion, its throws and its defects."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

sys.path.insert(0, str(Path(__file__).parent))
import bagfactory as bf  # noqa: E402
from rlff.capture import import_recordings  # noqa: E402
from rlff.capture.angles import align_arm  # noqa: E402
from rlff.capture.bag import read_bag  # noqa: E402
from rlff.capture.contact_sheet import contact_sheet  # noqa: E402
from rlff.capture.users import keep_consistent_user  # noqa: E402
from rlff.errors import InputError  # noqa: E402

#: Stated tolerances of the round trip (tracker noise 2 mm, 3 % dropped frames and joints).
ANGLE_TOL = 0.08  # rad, any sample (2 mm noise on 0.3 m limbs: about 0.015 rad rms)
ANGLE_RMS_TOL = 0.02  # rad
VELOCITY_TOL = 0.1  # of the throw's peak velocity, any sample
VELOCITY_RMS_TOL = 0.4  # rad/s
BOUNDARY_TOL = 0.12  # s: four frames at 30 Hz (99 % of 2400 simulated boundaries fall within 0.1 s)


@pytest.fixture(scope="module")
def simulation() -> bf.Simulation:
    return bf.standard_simulation(seed=3, n_throws=3)


@pytest.fixture(scope="module")
def jpegs() -> list[bytes]:
    return bf.jpeg_frames(6)


@pytest.fixture(scope="module")
def lz4_bag(tmp_path_factory, simulation, jpegs) -> Path:
    return bf.write_ros1_bag(tmp_path_factory.mktemp("bags") / "session_2.5m.bag", simulation, compression="lz4", images=jpegs)


def _check_against_truth(dataset, report, simulation: bf.Simulation) -> None:
    assert len(dataset) == len(simulation.throws)
    origin = report.files[0].clock_origin
    peaks = max(spec.peak_velocity for spec in simulation.throws)
    for trajectory, (start, end) in zip(dataset, simulation.moving_spans(), strict=True):
        begin = trajectory.meta["start_time"] + origin - simulation.t0
        assert begin == pytest.approx(start, abs=BOUNDARY_TOL)
        assert trajectory.meta["end_time"] + origin - simulation.t0 == pytest.approx(end, abs=BOUNDARY_TOL)
        t = begin + trajectory["time"]
        angle_error = trajectory["angle"] - simulation.angle(t)
        velocity_error = trajectory["velocity"] - simulation.velocity(t)
        assert np.max(np.abs(angle_error)) < ANGLE_TOL
        assert np.sqrt(np.mean(angle_error**2)) < ANGLE_RMS_TOL
        assert np.max(np.abs(velocity_error)) < VELOCITY_TOL * peaks
        assert np.sqrt(np.mean(velocity_error**2)) < VELOCITY_RMS_TOL


def test_a_bag_of_a_known_motion_gives_back_its_angle_velocity_and_throws(lz4_bag, simulation):
    dataset, report = import_recordings([lz4_bag], "bag")
    _check_against_truth(dataset, report, simulation)
    assert report.files[0].arm == "right" and report.files[0].user == "1"
    # the basket distance comes from the file name; the angle rises during the extension
    for trajectory in dataset:
        assert trajectory.meta["target"] == 2.5 and trajectory.meta["distance_source"] == "file name"
        assert np.all(trajectory["distance"] == 2.5)
        assert trajectory["velocity"].max() > 8.0
        assert isinstance(trajectory.meta["hit"], bool)


def test_bz2_chunks_and_the_ros1_tf_message_type_read_the_same(tmp_path, simulation):
    bag = bf.write_ros1_bag(tmp_path / "b.bag", simulation, compression="bz2", tf_type="tf/msg/tfMessage")
    dataset, report = import_recordings([bag], "bag")
    _check_against_truth(dataset, report, simulation)


def test_a_ros2_bag_reads_the_same(tmp_path, simulation, jpegs):
    bag = bf.write_ros2_bag(tmp_path / "ros2bag", simulation, images=jpegs)
    dataset, report = import_recordings([bag])
    assert report.files[0].format == "bag"
    _check_against_truth(dataset, report, simulation)
    path, notes = contact_sheet(report.files[0], tmp_path / "sheets")
    assert path.is_file() and notes == []


def test_a_ros2_bag_given_by_its_metadata_yaml_is_read_as_its_folder(tmp_path, simulation):
    # the bag's metadata.yaml was refused ("cannot tell the format"; with --format bag "not a ROS
    # bag"), though it is the file that makes the folder a bag
    bag = bf.write_ros2_bag(tmp_path / "ros2bag", simulation)
    folder, folder_report = import_recordings([bag])
    for format in (None, "bag"):
        dataset, report = import_recordings([bag / "metadata.yaml"], format)
        assert report.files[0].format == "bag" and [t.id for t in dataset] == [t.id for t in folder]
        assert [t.meta["source"] for t in dataset] == [t.meta["source"] for t in folder]
        assert [t["velocity"].tolist() for t in dataset] == [t["velocity"].tolist() for t in folder]
    assert len(read_bag(bag / "metadata.yaml").arms) == len(read_bag(bag).arms)
    with pytest.raises(InputError, match="the same recording given twice"):
        import_recordings([bag, bag / "metadata.yaml"])


def test_a_bag_given_from_inside_its_folder_keeps_the_folder_s_name(tmp_path, simulation, monkeypatch):
    # metadata.yaml (or ".") given inside the bag's folder: its parent "." has no name, and the
    # throws came out as "_t1" from source ".", the distance in the folder's name lost
    bag = bf.write_ros2_bag(tmp_path / "ros2bag_2.5m", simulation)
    folder, _ = import_recordings([bag])
    monkeypatch.chdir(bag)
    for given in ("metadata.yaml", "."):
        dataset, _ = import_recordings([given])
        assert [t.id for t in dataset] == [t.id for t in folder] and dataset[0].id.startswith("ros2bag_2")
        assert [t.meta["distance_source"] for t in dataset] == [t.meta["distance_source"] for t in folder]
        assert [float(t["distance"][0]) for t in dataset] == [2.5] * len(dataset)


@pytest.mark.parametrize("format", ["msr", "kinect-text", "csv", "thesis"])
def test_a_bag_read_as_a_text_format_is_said_to_be_a_bag(tmp_path, lz4_bag, format):
    # --format msr on a bag quoted its binary bytes as "a header line ('E\x00\x00...')"
    bag2 = bf.write_ros2_bag(tmp_path / "ros2bag", bf.standard_simulation(seed=3, n_throws=1))
    for path in (lz4_bag, bag2 / "ros2bag.db3", bag2 / "metadata.yaml"):
        with pytest.raises(InputError) as caught:
            import_recordings([path], format)
        assert str(caught.value) == (f"{path}: a ROS bag, which --format {format} does not read (it reads text): "
                                     "leave --format out, or give --format bag")


@pytest.mark.parametrize("name", ["renamed.txt", "renamed.csv", "renamed"])
def test_a_ros1_bag_without_its_suffix_is_said_to_be_one(tmp_path, lz4_bag, name):
    # read as text: "cannot tell the format", "not a readable CSV (Error tokenizing data ...)", or
    # its binary bytes quoted as "a header line"; with --format bag, "not a ROS bag"
    path = tmp_path / name
    path.write_bytes(lz4_bag.read_bytes())
    said = (f"{path} is a ROS 1 bag (it starts with #ROSBAG V2.0), not UTF-8 text: give it the suffix .bag, by "
            "which rlff reads ROS 1 bags")
    for format in (None, "csv", "msr", "kinect-text", "thesis"):
        with pytest.raises(InputError) as caught:
            import_recordings([path], format)
        assert str(caught.value) == said, format
    named = f"its name ends in {path.suffix}" if path.suffix else "its name has no suffix"
    with pytest.raises(InputError) as caught:
        import_recordings([path], "bag")
    assert str(caught.value) == (f"{path}: a ROS 1 bag by its first bytes (#ROSBAG V2.0), but {named}: give it the "
                                 "suffix .bag (renamed.bag), by which rlff reads ROS 1 bags")


def test_a_ros2_database_without_its_metadata_says_to_give_the_folder(tmp_path):
    # said "not a ROS bag (a ROS 1 bag ends in .bag, a ROS 2 bag is a folder)"; renamed, it was read as text
    bag = bf.write_ros2_bag(tmp_path / "ros2bag", bf.standard_simulation(seed=3, n_throws=1))
    alone = tmp_path / "alone.db3"
    alone.write_bytes((bag / "ros2bag.db3").read_bytes())
    with pytest.raises(InputError) as caught:
        import_recordings([alone])
    assert str(caught.value) == (f"{alone}: a ROS 2 bag's .db3 database without its metadata.yaml beside it: give "
                                 "rlff the bag's folder, the one that holds both")
    renamed = tmp_path / "alone.dat"
    renamed.write_bytes(alone.read_bytes())
    with pytest.raises(InputError, match=r"alone.dat is an SQLite database \(a ROS 2 bag's .db3\?\), not UTF-8 text: "
                                         r"give rlff data import the bag's folder, the one with its metadata.yaml$"):
        import_recordings([renamed])


def test_the_flickering_second_skeleton_is_dropped_and_reported(lz4_bag):
    recording = read_bag(lz4_bag)
    assert recording.users() == ["1", "2"]
    assert {arm.side for arm in recording.arms} == {"right", "left"}
    arms, notes, _ = keep_consistent_user(recording)
    assert {arm.user for arm in arms} == {"1"}
    assert len(notes) == 1 and "dropped tracked user 2" in notes[0] and "appearances" in notes[0]


def test_dropped_frames_are_interpolated_and_long_losses_marked(tmp_path):
    simulation = bf.standard_simulation(seed=5, n_throws=1, drop_frames=0.0, drop_joints=0.0, second_user=False, noise=0.0)
    bag = bf.write_ros1_bag(tmp_path / "gap.bag", simulation, compression=None)
    recording = read_bag(bag)
    arm = recording.arm("1", "right")
    # cut out 0.5 s of the elbow (tracking lost) and single hand samples (dropped)
    elbow_keep = ~((arm.elbow.time - simulation.t0 > 0.2) & (arm.elbow.time - simulation.t0 < 0.7))
    hand_keep = np.ones(len(arm.hand), dtype=bool)
    hand_keep[[40, 41, 60]] = False
    from rlff.capture.skeleton import ArmTrack, JointTrack

    holed = ArmTrack("1", "right", arm.shoulder, JointTrack("e", arm.elbow.time[elbow_keep], arm.elbow.position[elbow_keep]),
                     JointTrack("h", arm.hand.time[hand_keep], arm.hand.position[hand_keep]))
    motion = align_arm(holed)
    t = motion.time - simulation.t0
    assert not motion.valid[(t > 0.25) & (t < 0.65)].any()
    assert motion.valid[t > 0.75].all()
    error = np.abs(motion.angle - simulation.angle(t))
    nearest = np.abs(motion.time[:, None] - holed.hand.time[None, :]).min(axis=1)
    measured = (nearest < 1e-4) & motion.valid
    assert measured.sum() > 100
    assert np.max(error[measured]) < 1e-3  # noise-free: exact where every joint was sampled
    assert np.max(error[motion.valid]) < 0.05  # linear interpolation over two dropped hand samples


def test_image_messages_are_never_deserialised(lz4_bag, monkeypatch):
    from rosbags.typesys.store import Typestore

    decoded: set[str] = set()
    for method in ("deserialize_ros1", "deserialize_cdr"):
        original = getattr(Typestore, method)

        def spy(self, rawdata, typename, original=original):
            decoded.add(typename)
            return original(self, rawdata, typename)

        monkeypatch.setattr(Typestore, method, spy)
    assert len(read_bag(lz4_bag).arms) == 4
    assert "sensor_msgs/msg/CompressedImage" not in decoded


@pytest.mark.parametrize("batch", [1, 7, 512])
def test_the_batched_tf_decoder_agrees_with_the_bag_typestore(lz4_bag, monkeypatch, batch):
    """Dropped joints give messages of new and of equal lengths with other names: all decoded alike."""
    from rosbags.highlevel import AnyReader

    from rlff.capture import tf_decode

    monkeypatch.setattr(tf_decode, "BATCH", batch)

    def keep(child: str) -> bool:
        return "elbow" in child or "hand" in child

    with AnyReader([lz4_bag]) as reader:
        connections = [c for c in reader.connections if c.topic == "/tf"]
        fast = tf_decode.TfCollector(keep, reader.typestore.deserialize_ros1)
        generic = tf_decode.TfCollector(keep, reader.typestore.deserialize_ros1)
        for connection, time_ns, raw in reader.messages(connections=connections):
            assert connection.digest == tf_decode.TF_MD5
            fast.add(raw, connection.msgtype, connection.digest, time_ns)
            generic.add(raw, connection.msgtype, "", time_ns)  # no digest: the typestore decodes
    ours, theirs = fast.finish(), generic.finish()
    assert sorted(ours) == sorted(theirs) == sorted((f"{side}_{joint}_{user}", bf.PARENT) for side in ("left", "right")
                                                      for joint in ("elbow", "hand") for user in "12")
    for pair, (times, positions) in theirs.items():
        order, their_order = np.argsort(ours[pair][0], kind="stable"), np.argsort(times, kind="stable")
        np.testing.assert_array_equal(ours[pair][0][order], times[their_order])
        np.testing.assert_array_equal(ours[pair][1][order], positions[their_order])


def test_a_bag_damaged_at_the_end_is_read_up_to_the_damage_with_a_warning(tmp_path, lz4_bag, simulation):
    damaged = tmp_path / "damaged_2.5m.bag"
    data = lz4_bag.read_bytes()
    damaged.write_bytes(data[: int(len(data) * 0.8)])
    dataset, report = import_recordings([damaged], "bag")
    warnings = report.files[0].warnings
    assert any("no usable index" in w for w in warnings)
    assert any("damaged" in w and "read the messages up to the damage" in w for w in warnings)
    # the throws wholly before the damage are still there, exactly where they were
    assert 1 <= len(dataset) <= len(simulation.throws)
    first = dataset[0]
    origin = report.files[0].clock_origin
    truth = simulation.moving_spans()[0][0]
    assert first.meta["start_time"] + origin - simulation.t0 == pytest.approx(truth, abs=BOUNDARY_TOL)
    # the camera frames before the damage are there for the contact sheet too
    path, notes = contact_sheet(report.files[0], tmp_path / "sheets")
    assert path.is_file() and not any("no frame" in note or "undecodable" in note for note in notes)


def test_a_damaged_chunk_in_the_middle_of_an_indexed_bag_is_skipped_and_the_rest_read(tmp_path, simulation):
    # the first damage met while iterating ended the stream: every throw after one damaged chunk
    # of twenty was lost ("no throw found")
    from rosbags.rosbag1 import Reader

    bag = bf.write_ros1_bag(tmp_path / "chunked.bag", simulation, chunk_bytes=4096)
    with Reader(bag) as reader:
        infos = sorted(reader.chunk_infos, key=lambda info: info.pos)
    assert len(infos) >= 10
    middle = infos[len(infos) // 2]
    data = bytearray(bag.read_bytes())
    data[middle.pos + 100 : middle.pos + 300] = np.random.default_rng(0).integers(0, 256, 200, dtype=np.uint8).tobytes()
    damaged = tmp_path / "damaged.bag"
    damaged.write_bytes(bytes(data))
    whole, ours = read_bag(bag), read_bag(damaged)
    (warning,) = [w for w in ours.warnings if "the bag is damaged" in w]
    assert "; skipped its messages from t=" in warning and warning.endswith(" of recording (a damaged chunk) and read the rest")
    elbow, reference = ours.arm("1", "right").elbow, whole.arm("1", "right").elbow
    assert elbow.time[-1] == reference.time[-1]  # read on to the end
    lost = np.setdiff1d(reference.time, elbow.time)
    assert 0 < lost.size and lost.max() - lost.min() < 0.5  # one chunk's span, about a quarter second at 4 kB
    assert len(import_recordings([damaged], "bag")[0]) == len(simulation.throws)


def test_an_unindexed_bag_from_a_dead_recorder_is_scanned(tmp_path, lz4_bag, simulation):
    """A recorder killed before closing leaves index_pos = 0 in the header."""
    data = bytearray(lz4_bag.read_bytes())
    index = data.index(b"index_pos=") + len(b"index_pos=")
    data[index : index + 8] = bytes(8)
    bag = tmp_path / "active.bag"
    bag.write_bytes(bytes(data))
    dataset, report = import_recordings([bag], "bag")
    assert len(dataset) == len(simulation.throws)
    assert any("not indexed" in w for w in report.files[0].warnings)


@pytest.mark.parametrize(
    ("content", "message"),
    [
        (b"", "not a ROS 1 bag"),
        (b"#ROSBAG V2.0\n" + bytes(range(256)) * 4, "corrupt ROS 1 bag"),
        (b"hello, I am not a bag\n", "not a ROS 1 bag"),
    ],
)
def test_corrupt_bags_are_input_errors_naming_the_file(tmp_path, content, message):
    bag = tmp_path / "broken.bag"
    bag.write_bytes(content)
    with pytest.raises(InputError, match=message) as error:
        read_bag(bag)
    assert str(bag) in str(error.value)


def test_a_bag_truncated_right_after_its_header_has_no_tf(tmp_path, lz4_bag):
    bag = tmp_path / "stub.bag"
    bag.write_bytes(lz4_bag.read_bytes()[:4200])
    with pytest.raises(InputError, match=r"no message could be read on /tf"):
        read_bag(bag)


def test_a_bag_without_tf_lists_its_topics(tmp_path, simulation):
    bag = bf.write_ros1_bag(tmp_path / "notf.bag", simulation, tf_topic="/skeleton")
    with pytest.raises(InputError, match=r"notf.bag: no topic /tf in the bag; topics there: /skeleton \(tf2_msgs/msg/TFMessage\); "
                                         r"give --topic /skeleton$"):
        read_bag(bag)
    assert len(read_bag(bag, topic="/skeleton").arms) == 4


def test_a_bag_of_skeleton_markers_says_rlff_reads_the_skeleton_from_tf(tmp_path):
    simulation = bf.standard_simulation(seed=4, n_throws=1, second_user=False)
    bag = bf.write_marker_bag(tmp_path / "markers.bag", simulation)
    with pytest.raises(InputError) as error:
        read_bag(bag)
    assert str(error.value) == (f"{bag}: no topic /tf in the bag; topics there: /skeleton_markers "
                                "(visualization_msgs/msg/Marker); rlff reads a skeleton from tf (tf/tfMessage or "
                                "tf2_msgs/TFMessage, a frame per joint as openni_tracker and NiTE publish it), not from "
                                "the visualization markers that draw one (/skeleton_markers): record the tracker's /tf "
                                "in the bag")


def test_missing_frames_list_the_frames_there(lz4_bag):
    with pytest.raises(InputError) as error:
        read_bag(lz4_bag, frames=("r_shoulder_1", "r_elbow_1", "r_wrist_1"))
    text = str(error.value)
    assert "r_wrist_1" in text and "frames there:" in text
    for frame in ("head_1", "right_elbow_1", "left_hand_2", "torso_1"):
        assert frame in text


def test_a_transform_at_exactly_the_cameras_origin_is_a_joint_not_tracked_there(tmp_path, simulation):
    # NiTE gives a joint it has no confidence in at the origin: read as a position, the hand
    # jumped 2.6 m to the camera and back
    class HandLost(bf.Simulation):
        def frames(self):
            for index, (t, users) in enumerate(super().frames()):
                if 40 <= index < 43 and "right_hand" in users["1"]:
                    users["1"]["right_hand"] = np.zeros(3)
                yield t, users

    lost = HandLost(simulation.throws, simulation.starts, simulation.duration, seed=3, second_user=False)
    recording = read_bag(bf.write_ros1_bag(tmp_path / "lost.bag", lost, compression=None))
    hand = recording.arm("1", "right").hand
    assert not np.any(np.all(hand.position == 0.0, axis=1))
    (note,) = [note for note in recording.notes if "(0, 0, 0)" in note]
    assert note.startswith("lost.bag: frame right_hand_1: left out ") and "transforms at exactly (0, 0, 0), the camera's " \
        "origin (a joint the tracker did not detect)" in note


def _never_tracked(*joints: str) -> bf.Simulation:
    """One throw whose ``joints`` (NiTE frames of user 1) the tracker never detects: every one of
    their transforms at exactly (0, 0, 0)."""
    class NeverTracked(bf.Simulation):
        def frames(self):
            for t, users in super().frames():
                for joint in joints:
                    if joint in users["1"]:
                        users["1"][joint] = np.zeros(3)
                yield t, users

    base = bf.standard_simulation(seed=4, n_throws=1, second_user=False)
    return NeverTracked(base.throws, base.starts, base.duration, seed=4, second_user=False)


def test_a_hip_frame_never_tracked_is_read_as_absent_and_the_torso_taken_from_the_spine(tmp_path):
    # the torso's hip centre read the first stamp of the right hip's empty track: IndexError, an
    # "internal error" for the user
    simulation = _never_tracked("right_hip")
    bag = bf.write_ros1_bag(tmp_path / "hip.bag", simulation, compression=None)
    recording = read_bag(bag)
    arm = recording.arm("1", "right")
    assert arm.hip is not None and arm.hip.name == "torso_1"  # the torso frame, on the spine below the neck
    assert any(note.startswith("hip.bag: frame right_hip_1: every one of its ") and note.endswith(
        " transforms is at exactly (0, 0, 0), the camera's origin: a joint the tracker never detected, read as a frame "
        "the bag does not have") for note in recording.notes)
    (throw,), _ = import_recordings([bag], "bag")
    assert "shoulder" in throw.columns


def test_an_arm_frame_never_tracked_says_so_where_the_frames_are_listed(tmp_path):
    # the arm left out was a note ("no frame right_hand_1", as for a frame the bag lacks) where text
    # warns of a joint never tracked: the throwing arm went without a warning
    bag = bf.write_ros1_bag(tmp_path / "hand.bag", _never_tracked("right_hand"), compression=None)
    recording = read_bag(bag)  # the left arm stays
    notes = recording.notes
    assert recording.warnings == [f"{bag}: user 1, right arm left out: frame right_hand_1 is in the bag but was never "
                                  "tracked (not one transform a position)"]
    assert not any("right arm left out" in note for note in notes)
    assert any(note.startswith("hand.bag: frame right_hand_1: every one of its ") for note in notes)
    bag = bf.write_ros1_bag(tmp_path / "hands.bag", _never_tracked("right_hand", "left_hand"), compression=None)
    with pytest.raises(InputError, match=r"hands.bag: no tracked user has all of the frames .*; frames there: .*; never "
                                         r"tracked, every transform at exactly \(0, 0, 0\): left_hand_1, "
                                         r"right_hand_1$"):
        read_bag(bag)


@pytest.mark.parametrize(("frame_name", "frames"), [
    (lambda joint, user: f"kinect1/{joint}_{user}", "kinect1/right_shoulder_1,kinect1/right_elbow_1,kinect1/right_hand_1"),
    (lambda joint, user: joint, "right_shoulder,right_elbow,right_hand"),  # one user, no number
], ids=["prefix", "no user number"])
def test_the_torso_frames_are_named_as_the_arm_frames_are(tmp_path, frame_name, frames):
    # with --frames kinect1/right_shoulder_1,... the torso's frames (neck, hips) were looked for
    # without the prefix and ending, not found, and the shoulder measured against the vertical
    # instead of the torso (up to 0.38 rad apart)
    simulation = bf.standard_simulation(seed=4, n_throws=1, second_user=False)
    plain = bf.write_ros1_bag(tmp_path / "plain.bag", simulation, compression=None)
    named = bf.write_ros1_bag(tmp_path / "named.bag", simulation, compression=None, frame_name=frame_name)
    recording = read_bag(named, frames=frames.split(","))
    assert recording.arm("1", "right").neck is not None and recording.arm("1", "right").hip is not None
    (reference,), _ = import_recordings([plain], "bag")
    (throw,), report = import_recordings([named], "bag", frames=frames.split(","))
    np.testing.assert_array_equal(throw["shoulder"], reference["shoulder"])
    assert not any("torso" in note for note in report.notes)


@pytest.mark.parametrize(("frame_name", "frames"), [
    (lambda joint, user: f"kinect1/{joint}_{user}", "kinect1/right_shoulder_1,kinect1/right_elbow_1,kinect1/right_hand_1"),
    (lambda joint, user: joint, "right_shoulder,right_elbow,right_hand"),
], ids=["prefix", "no user number"])
def test_arm_frames_named_with_a_prefix_or_without_a_number_are_suggested_as_frames(tmp_path, frame_name, frames):
    simulation = bf.standard_simulation(seed=4, n_throws=1, second_user=False)
    named = bf.write_ros1_bag(tmp_path / "named.bag", simulation, compression=None, frame_name=frame_name)
    with pytest.raises(InputError, match=rf"named.bag: no tracked user .*; frames there: .*; give --frames {frames}$"):
        read_bag(named)


def test_a_bag_without_the_torso_frames_says_which_it_looked_for(tmp_path):
    class NoTorso(bf.Simulation):
        def frames(self):
            for t, users in super().frames():
                yield t, {user: {joint: p for joint, p in body.items() if joint not in ("neck", "torso", "left_hip",
                                                                                        "right_hip")}
                          for user, body in users.items()}

    base = bf.standard_simulation(seed=4, n_throws=1, second_user=False)
    simulation = NoTorso(base.throws, base.starts, base.duration, seed=4, second_user=False)
    bag = bf.write_ros1_bag(tmp_path / "arms.bag", simulation, compression=None,
                            frame_name=lambda joint, user: f"kinect1/{joint}_{user}")
    recording = read_bag(bag, frames=("kinect1/right_shoulder_1", "kinect1/right_elbow_1", "kinect1/right_hand_1"))
    assert "arms.bag: no torso frames matched: looked for kinect1/neck_N with kinect1/left_hip_N and " \
        "kinect1/right_hip_N, or with kinect1/torso_N" in recording.notes


def test_frames_of_another_name_and_user_are_configurable(lz4_bag):
    recording = read_bag(lz4_bag, frames=("left_shoulder_2", "left_elbow_2", "left_hand_2"))
    assert recording.users() == ["1", "2"]
    assert recording.arm("1", "left") is not None and recording.arm("2", "right") is not None


def test_contact_sheet_has_a_row_per_throw_of_camera_frames(tmp_path, lz4_bag, simulation, jpegs):
    _, report = import_recordings([lz4_bag], "bag")
    path, notes = contact_sheet(report.files[0], tmp_path / "sheets")
    assert notes == []
    with Image.open(path) as sheet:
        assert sheet.size == (3 * 240, len(simulation.throws) * (180 + 16))
        # each tile shows a camera frame (noise), not the grey placeholder of a missing one
        tile = np.asarray(sheet.convert("RGB"))[16 + 60 : 16 + 120, 60:180]
        assert tile.std() > 20


def test_undecodable_camera_frames_are_skipped_with_a_note(tmp_path, simulation):
    bag = bf.write_ros1_bag(tmp_path / "cam.bag", simulation, images=[b"\xff\xd8 not a jpeg"])
    _, report = import_recordings([bag], "bag")
    path, notes = contact_sheet(report.files[0], tmp_path / "sheets")
    assert path.is_file()
    assert len(notes) == 3 * len(simulation.throws)
    assert all("undecodable frame" in note and "skipped" in note for note in notes)


def test_a_bag_without_a_camera_gets_no_contact_sheet(tmp_path, simulation):
    bag = bf.write_ros1_bag(tmp_path / "nocam.bag", simulation)
    _, report = import_recordings([bag], "bag")
    path, notes = contact_sheet(report.files[0], tmp_path / "sheets")
    assert path is None and "no compressed camera stream" in notes[0]


def test_hit_or_miss_against_the_manifest_basket(tmp_path, lz4_bag):
    first, _ = import_recordings([lz4_bag], "bag")
    landing = [t.meta["landing"] for t in first]
    manifest = tmp_path / "m.csv"
    manifest.write_text(
        "file,throw,distance\n"
        f"{lz4_bag.name},1,{landing[0] + 0.1:.6f}\n{lz4_bag.name},2,{landing[1] + 0.5:.6f}\n"
    )
    dataset, _ = import_recordings([lz4_bag], "bag", manifest=manifest)
    assert [t.meta["hit"] for t in dataset[:2]] == [True, False]
    assert [t.meta["distance_source"] for t in dataset] == ["manifest", "manifest", "file name"]
    assert dataset[2].meta["target"] == 2.5


class Republished:
    """A tracker node that publishes its last skeleton on every tick of a timer ``times`` times faster
    than the camera: each skeleton's transforms again, with new stamps (or, with ``same_stamp``,
    the same message again)."""

    def __init__(self, simulation: bf.Simulation, times: int, same_stamp: bool = False):
        self.simulation, self.times, self.same_stamp = simulation, times, same_stamp
        self.t0 = simulation.t0

    def frames(self):
        tick = 1.0 / (self.times * self.simulation.rate_hz)
        for t, users in self.simulation.frames():
            for k in range(self.times):
                yield (t if self.same_stamp else t + k * tick), users


@pytest.mark.parametrize("ros", [1, 2])
def test_a_tracker_that_publishes_each_skeleton_twice_reads_as_the_skeletons_at_their_own_rate(tmp_path, ros):
    # the text readers' rule for 30 Hz streams of 15 Hz skeletons did not reach bags: the repeats
    # stayed, the angle stood still on every other sample and the throws were read at 30 Hz
    simulation = bf.standard_simulation(seed=5, n_throws=3, rate_hz=15.0)
    suffix = ".bag" if ros == 1 else ""
    write = bf.write_ros1_bag if ros == 1 else bf.write_ros2_bag
    own = write(tmp_path / f"own{suffix}", simulation)
    doubled = write(tmp_path / f"doubled{suffix}", Republished(simulation, 2))
    reference, reference_report = import_recordings([own])
    dataset, report = import_recordings([doubled])
    assert report.files[0].motion.rate_hz == pytest.approx(15.0)
    assert np.array_equal(report.files[0].motion.time, reference_report.files[0].motion.time)
    assert len(dataset) == len(reference) == 3
    for ours, theirs in zip(dataset, reference, strict=True):
        assert ours.meta["native_rate_hz"] == pytest.approx(15.0)
        assert np.array_equal(ours["angle"], theirs["angle"]) and np.array_equal(ours["velocity"], theirs["velocity"])
    (note,) = [note for note in report.notes if note.startswith(f"doubled{suffix}: user 1: ")]
    assert note.endswith(" skeletons repeat the one before in every joint, in motion too, with new stamps: the tracker "
                         "gives each skeleton 2 times (30 Hz of 15 Hz skeletons); the repeats left out, the skeletons "
                         "read at their own rate")
    assert not any("repeat the one before" in note for note in reference_report.notes)


def test_a_skeleton_published_again_with_the_same_stamp_is_read_once(tmp_path):
    # the other way a bag repeats a skeleton: the same transforms again under the same stamp
    simulation = bf.standard_simulation(seed=5, n_throws=3, rate_hz=15.0)
    own = bf.write_ros1_bag(tmp_path / "own.bag", simulation)
    again = bf.write_ros1_bag(tmp_path / "again.bag", Republished(simulation, 2, same_stamp=True))
    reference, _ = import_recordings([own])
    dataset, report = import_recordings([again])
    assert any(note.startswith("again.bag: frame right_elbow_1: dropped ") and note.endswith(
        " transforms repeating a time stamp") for note in report.notes), report.notes
    assert not any("repeat the one before" in note for note in report.notes)
    for ours, theirs in zip(dataset, reference, strict=True):
        assert np.array_equal(ours["angle"], theirs["angle"])


def test_joints_stamped_microseconds_apart_are_gathered_into_skeletons():
    # openni_tracker stamps each joint's transform as it sends it: a skeleton's stamps differ by
    # microseconds, and a joint the tracker dropped leaves its row without it
    from rlff.capture.repeated_frames import repeated_track_samples
    from rlff.capture.skeleton_text import FROZEN_ENTRY_SPEED

    simulation = bf.standard_simulation(seed=6, n_throws=2, rate_hz=15.0, second_user=False)
    skeletons = list(simulation.frames())
    joints = sorted({joint for _, users in skeletons for joint in users["1"]})
    times = {joint: [] for joint in joints}
    positions = {joint: [] for joint in joints}
    for t, users in skeletons:
        for copy in range(2):  # each skeleton again 1/30 s later, with new stamps
            for offset, joint in enumerate(joints):
                if joint in users["1"]:
                    times[joint].append(t + copy / 30.0 + 40e-6 * offset)
                    positions[joint].append(users["1"][joint])
    found = repeated_track_samples([np.array(times[j]) for j in joints], [np.array(positions[j]) for j in joints],
                                   FROZEN_ENTRY_SPEED)
    assert found is not None
    keep, rows, kept_rows, count = found
    assert count == 2 and rows.size == 2 * len(skeletons) and kept_rows.sum() == len(skeletons)
    for joint, kept in zip(joints, keep, strict=True):  # each joint keeps its first copy of each skeleton
        assert np.all(np.rint(np.array(times[joint])[kept] * 30.0) % 2 == 0), joint
        assert kept.sum() == len(times[joint]) // 2


def _edited(edit) -> bf.Simulation:
    """One throw of user 1 (no frame or joint dropped), each frame's body passed through
    ``edit(index, body, extension)``, ``extension`` the frame indices within the elbow's extension."""
    base = bf.standard_simulation(seed=4, n_throws=1, second_user=False, drop_frames=0.0, drop_joints=0.0)
    spec = base.throws[0]
    begin = base.starts[0] + spec.wind_up + spec.hold
    extension = np.flatnonzero((base.frame_times > begin) & (base.frame_times < begin + spec.extension))

    class Edited(bf.Simulation):
        def frames(self):
            for index, (t, users) in enumerate(super().frames()):
                edit(index, users["1"], extension)
                yield t, users

    return Edited(base.throws, base.starts, base.duration, seed=4, second_user=False, drop_frames=0.0, drop_joints=0.0)


@pytest.mark.parametrize(("value", "joint"), [(np.nan, "right_elbow"), (np.inf, "right_elbow"), (np.nan, "neck")])
def test_a_nan_or_inf_transform_is_a_joint_not_tracked_there(tmp_path, value, joint):
    # a nan or inf translation was read as a position: a throw's extension with one crashed the
    # import ("internal error: ValueError: zero-size array ..."), a neck's ("y must contain only
    # finite values"), and one outside a throw stayed in the track as a nan
    def spoil(index, body, extension):
        if index in (extension[len(extension) // 2], 10):
            body[joint] = np.array([value, 0.5, 1.0])

    bag = bf.write_ros1_bag(tmp_path / "nan.bag", _edited(spoil), compression=None)
    recording = read_bag(bag)
    arm = recording.arm("1", "right")
    track = arm.elbow if joint == "right_elbow" else arm.neck
    assert np.all(np.isfinite(track.position)) and len(track) == len(_edited(spoil).frame_times) - 2
    assert f"nan.bag: frame {joint}_1: left out 2 transforms with a nan or inf in its translation, taken as not tracked " \
           "there (as a nan in text)" in recording.notes
    (throw,), _ = import_recordings([bag], "bag")
    assert np.all(np.isfinite(throw["velocity"]))


def test_a_transform_far_beyond_what_a_camera_sees_is_a_joint_not_tracked_there(tmp_path):
    # an elbow at 1e30 m for 0.1 s at rest was read as a position: a spurious movement there, and
    # the real throw renumbered t2
    def spoil(index, body, extension):
        if 10 <= index < 13:
            body["right_elbow"] = np.array([1e30, 0.0, 0.0])

    _, reference = import_recordings([bf.write_ros1_bag(tmp_path / "own.bag", _edited(lambda *_: None), compression=None)])
    bag = bf.write_ros1_bag(tmp_path / "far.bag", _edited(spoil), compression=None)
    recording = read_bag(bag)
    assert np.abs(recording.arm("1", "right").elbow.position).max() < 10.0
    assert "far.bag: frame right_elbow_1: left out 3 transforms with a coordinate beyond 100 m of its parent frame, " \
           "farther than a depth camera sees: taken as not tracked there" in recording.notes
    (throw,), report = import_recordings([bag], "bag")
    assert throw.id == "far_t1" and not report.files[0].rejected
    assert report.files[0].throws[0].peak_velocity == pytest.approx(reference.files[0].throws[0].peak_velocity)


def test_a_frame_a_frozen_tracker_held_is_left_out_as_in_text(tmp_path):
    # the text readers' frozen-tracker rule did not reach bags: a joint re-published at its last
    # translation for 0.17 s mid-extension was read as a stop and a jump (an elbow's: the peak 23
    # rad/s for 15.7), both confidences high, with no note
    held = {}

    def freeze(index, body, extension):
        middle = extension[len(extension) // 2]
        if index == middle - 2:
            held["hand"] = body["right_hand"].copy()
        elif middle - 2 < index <= middle + 2:
            body["right_hand"] = held["hand"].copy()

    simulation = _edited(freeze)
    bag = bf.write_ros1_bag(tmp_path / "frozen.bag", simulation, compression=None)
    recording = read_bag(bag)
    assert "frozen.bag: frame right_hand_1: 4 transforms repeating its translation of the one before exactly while it " \
           "was moving (a frozen tracker): left out of its track, the motion bridged across" in recording.notes
    hand = recording.arm("1", "right").hand
    assert len(hand) == len(simulation.frame_times) - 4
    assert not np.any(np.all(np.diff(hand.position, axis=0) == 0.0, axis=1))
    _, report = import_recordings([bag], "bag")
    assert report.files[0].throws[0].peak_confidence == "low"
    assert any("its extension has a " in warning and " gap in the hand's samples" in warning
               for warning in report.files[0].warnings), report.files[0].warnings


def test_a_frame_published_under_two_parent_frames_is_an_error_naming_both(tmp_path):
    # two trackers publishing the same frame names were merged into one track, positions in two
    # frames a metre apart: 29 "glitch samples" removed and the landing 1.22 m for 1.81
    def names(frame):
        return bf.nite_frame, ("kinect1_depth_frame" if frame % 2 else "kinect2_depth_frame")

    bag = bf.write_ros1_bag(tmp_path / "two.bag", _edited(lambda *_: None), compression=None, names=names)
    with pytest.raises(InputError, match=r"^.*two.bag: frame left_elbow_1 is published relative to 2 parent frames "
                                         r"\(kinect1_depth_frame, kinect2_depth_frame\): two trackers publish frames of "
                                         r"the same names, and a track needs one parent; keep one tracker's "
                                         r"transforms in the bag \(rosbag filter\), or .* --frames$"):
        read_bag(bag)


@pytest.mark.parametrize("when", ["halves", "alternating"])
def test_a_frame_written_with_and_without_a_leading_slash_is_one_frame(tmp_path, when):
    # /right_elbow_1 and right_elbow_1 (one frame to tf2) overwrote each other: half the samples lost
    simulation = _edited(lambda *_: None)
    count = len(simulation.frame_times)

    def names(frame):
        slash = frame < count // 2 if when == "halves" else frame % 2 == 0
        return (lambda joint, user: f"/{joint}_{user}") if slash else bf.nite_frame, bf.PARENT

    reference = read_bag(bf.write_ros1_bag(tmp_path / "own.bag", simulation, compression=None))
    recording = read_bag(bf.write_ros1_bag(tmp_path / "slash.bag", simulation, compression=None, names=names))
    ours, theirs = recording.arm("1", "right"), reference.arm("1", "right")
    for joint in ("shoulder", "elbow", "hand"):
        assert len(getattr(ours, joint)) == count
        np.testing.assert_array_equal(getattr(ours, joint).position, getattr(theirs, joint).position)
    assert any(note.startswith("slash.bag: ") and note.endswith(
        " frames published both with and without a leading slash (/left_elbow_1 and left_elbow_1, ...), one frame each "
        "as tf2 reads them: their transforms read together") for note in recording.notes)


def test_one_parent_frame_written_with_and_without_a_leading_slash_is_one_parent(tmp_path):
    # the joints' common parent, /openni_depth_frame for some and openni_depth_frame for others,
    # was refused as "different parent frames"
    def names(frame):
        return bf.nite_frame, lambda joint: f"/{bf.PARENT}" if joint == "right_shoulder" else bf.PARENT

    simulation = _edited(lambda *_: None)
    recording = read_bag(bf.write_ros1_bag(tmp_path / "parent.bag", simulation, compression=None, names=names))
    assert len(recording.arm("1", "right").elbow) == len(simulation.frame_times)
