"""Skeleton tracks from ROS 1 and ROS 2 bags: the /tf transforms of the arm joints.

A skeleton tracker (openni_tracker, NiTE2tf) publishes every joint as a tf frame named
``{joint}_{user}``, e.g. ``right_elbow_1``, relative to the camera frame. This module reads the
/tf connections of a bag with rosbags, in one streaming pass (one chunk in memory at a time),
decoding only those connections (``tf/tfMessage`` or ``tf2_msgs/TFMessage``) with the message
definitions stored in the bag; camera images in the same bag are never deserialised.

Arm frames are matched by name without the user number, so every tracked user is found
(``right_elbow_1``, ``right_elbow_2``...) and both arms when the bag has the other side's
frames (``right`` swapped for ``left`` in the names).

A ROS 1 bag whose end is damaged (the recorder died, the copy was cut short) has no usable
index; rosbags refuses it, so its chunks are then scanned from the start and read up to the
damage, with a warning.
"""

from __future__ import annotations

import os
import re
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from io import BytesIO
from pathlib import Path
from typing import Any

import numpy as np

from rlff.capture.skeleton import ArmTrack, JointTrack, Recording
from rlff.capture.tf_decode import TfCollector
from rlff.errors import InputError

#: Default frames of the throwing arm (NiTE / openni_tracker names, user 1).
DEFAULT_FRAMES = ("right_shoulder_1", "right_elbow_1", "right_hand_1")
DEFAULT_TOPIC = "/tf"
#: Message types of /tf in ROS 1 (tf) and ROS 1/2 (tf2), as rosbags names them.
TF_TYPES = ("tf2_msgs/msg/TFMessage", "tf/msg/tfMessage")
IMAGE_TYPES = ("sensor_msgs/msg/CompressedImage",)
#: Up in a ROS camera-link frame (x forward, y left, z up: REP 103).
ROS_UP = np.array([0.0, 0.0, 1.0])


@dataclass(frozen=True)
class Message:
    """One message of a bag, still serialised."""

    topic: str
    msgtype: str
    time_ns: int
    raw: bytes | memoryview
    digest: str = ""


@dataclass
class _BagStream:
    """Messages of some topics, a way to decode them, the topics there are, and what went wrong."""

    topics: dict[str, str]
    messages: Iterator[Message]
    deserialize: Callable[[bytes | memoryview, str], Any]
    warnings: list[str] = field(default_factory=list)


def read_bag(
    path: str | Path,
    *,
    topic: str = DEFAULT_TOPIC,
    frames: Sequence[str] = DEFAULT_FRAMES,
) -> Recording:
    """Read the arm joints of every tracked user from a bag's /tf.

    Parameters
    ----------
    path : path of a ROS 1 ``.bag`` file or a ROS 2 bag folder (or a file inside it)
    topic : the tf topic
    frames : (shoulder, elbow, hand) frame names; a trailing number is the tracker's user id
        and matches any user.

    Returns
    -------
    Recording
        Positions (m) in the joints' common parent frame, z up; times are the transforms'
        header stamps (s), or the bag's receive time where a stamp is zero.

    Raises
    ------
    InputError
        Not a bag, a bag without ``topic`` (the topics there are listed), a topic that is not
        tf, the frames missing (the frames there are listed), joints relative to different parent
        frames, or a bag so damaged that no /tf message could be read.
    """
    path = Path(path)
    if len(frames) != 3:
        raise InputError(f"frames: expected shoulder, elbow and hand frame names, got {list(frames)}")
    names = [name.lstrip("/") for name in frames]
    stems = [re.sub(r"\d+$", "", name) for name in names]
    sides = _sides(stems)
    pattern = re.compile(
        "^(?:" + "|".join(re.escape(stem) for side in sides.values() for stem in side) + r")(\d*)$"
    )
    wanted: dict[str, bool] = {}

    def keep(child: str) -> bool:
        decision = wanted.get(child)
        if decision is None:
            decision = wanted[child] = pattern.match(child.lstrip("/")) is not None
        return decision

    count = 0
    with _open_stream(path, [topic], TF_TYPES) as stream:
        collector = TfCollector(keep, stream.deserialize)
        for message in stream.messages:
            count += 1
            collector.add(message.raw, message.msgtype, message.digest, message.time_ns)
        collected = collector.finish()
        warnings = stream.warnings
    if count == 0:
        raise InputError(f"{path}: no message could be read on {topic}" + (f" ({warnings[0]})" if warnings else ""))
    notes: list[str] = []
    arms = _arm_tracks(path, collected, sides, notes)
    if not arms:
        present = sorted({name.lstrip("/") for name in wanted})
        raise InputError(
            f"{path}: no tracked user has all of the frames {', '.join(stem + 'N' for stem in stems)} on {topic} "
            f"(looked for {', '.join(names)}); frames there: {', '.join(present) if present else 'none'}"
        )
    preferred = re.search(r"(\d+)$", names[0])
    if preferred and not any(arm.user == preferred.group(1) for arm in arms):
        notes.append(f"{path}: no user {preferred.group(1)}; found users {', '.join(sorted({a.user for a in arms}))}")
    return Recording(str(path), arms, ROS_UP, notes, warnings)


def _sides(stems: list[str]) -> dict[str, list[str]]:
    """Frame-name stems of each arm: the given side, and the other when the names say which side."""
    for this, other in (("right", "left"), ("left", "right")):
        if all(this in stem for stem in stems):
            return {this: stems, other: [stem.replace(this, other) for stem in stems]}
    return {"right": stems}


def _arm_tracks(
    path: Path,
    collected: dict[str, tuple[str, np.ndarray, np.ndarray]],
    sides: dict[str, list[str]],
    notes: list[str],
) -> list[ArmTrack]:
    """Arm tracks for every (user, side) with all three frames, in user order."""
    users = sorted(
        {m.group(1) for name in collected if (m := re.search(r"(\d*)$", name.lstrip("/")))},
        key=lambda user: (len(user), user),
    )
    arms = []
    by_name = {name.lstrip("/"): value for name, value in collected.items()}
    for user in users:
        for side, stems in sides.items():
            frame_names = [stem + user for stem in stems]
            if not all(name in by_name for name in frame_names):
                continue
            parents = {by_name[name][0] for name in frame_names}
            if len(parents) > 1:
                raise InputError(
                    f"{path}: frames {', '.join(frame_names)} are relative to different parent frames "
                    f"({', '.join(sorted(parents))}); they need one common parent"
                )
            joints = [_joint_track(name, *by_name[name][1:], notes, path) for name in frame_names]
            arms.append(ArmTrack(user or "1", side, *joints))
    return arms


def _joint_track(name: str, time: np.ndarray, position: np.ndarray, notes: list[str], path: Path) -> JointTrack:
    """A joint track with its samples in time order and repeated stamps dropped (keeping the last)."""
    order = np.argsort(time, kind="stable")
    time, position = time[order], position[order]
    keep = np.ones(time.size, dtype=bool)
    keep[:-1] = np.diff(time) > 0
    if not keep.all():
        notes.append(f"{path.name}: frame {name}: dropped {int((~keep).sum())} transforms repeating a time stamp")
    return JointTrack(name, time[keep], position[keep])


# -- opening bags ---------------------------------------------------------------------------------


def _bag_path(path: Path) -> Path:
    """The path rosbags wants: a ROS 1 file, or the folder of a ROS 2 bag."""
    if not path.exists():
        raise InputError(f"{path}: no such file or folder")
    if path.is_file() and path.suffix in (".db3", ".mcap") and (path.parent / "metadata.yaml").is_file():
        return path.parent
    return path


@contextmanager
def _open_stream(path: Path, topics: Sequence[str], msgtypes: Sequence[str] | None) -> Iterator[_BagStream]:
    """Messages of ``topics`` (checked to be of one of ``msgtypes``) in time order.

    Reads through rosbags; a ROS 1 bag that rosbags cannot open (damaged index) is scanned instead.
    Errors while iterating end the iteration with a warning.
    """
    from rosbags.highlevel import AnyReader, AnyReaderError

    bag = _bag_path(path)
    if bag.is_file() and bag.suffix != ".bag":
        raise InputError(f"{path}: not a ROS bag (a ROS 1 bag ends in .bag, a ROS 2 bag is a folder)")
    try:
        reader = AnyReader([bag])
        reader.open()
    except (AnyReaderError, OSError, ValueError, KeyError, AssertionError) as exc:
        if bag.is_file():
            yield _scan_ros1(path, topics, msgtypes, reason=str(exc) or type(exc).__name__)
            return
        raise InputError(f"{path}: not a readable ROS 2 bag ({exc})") from None
    try:
        all_topics = {conn.topic: conn.msgtype for conn in reader.connections}
        _check_topics(path, all_topics, topics, msgtypes)
        connections = [conn for conn in reader.connections if conn.topic in topics]
        typestore = reader.typestore
        deserialize = typestore.deserialize_cdr if reader.is2 else typestore.deserialize_ros1
        warnings: list[str] = []

        def messages() -> Iterator[Message]:
            last = None
            try:
                for connection, time_ns, raw in reader.messages(connections=connections):
                    last = time_ns
                    yield Message(connection.topic, connection.msgtype, time_ns, raw, connection.digest if not reader.is2 else "")
            except Exception as exc:  # noqa: BLE001 - any decoding failure inside the bag is damage
                warnings.append(_damage_warning(path, f"{type(exc).__name__}: {exc}", last, reader.start_time))

        yield _BagStream(all_topics, messages(), deserialize, warnings)
    finally:
        reader.close()


def _check_topics(path: Path, all_topics: dict[str, str], topics: Sequence[str], msgtypes: Sequence[str] | None) -> None:
    for topic in topics:
        if topic not in all_topics:
            there = ", ".join(f"{name} ({kind})" for name, kind in sorted(all_topics.items())) or "none"
            raise InputError(f"{path}: no topic {topic} in the bag; topics there: {there}")
        if msgtypes is not None and all_topics[topic] not in msgtypes:
            raise InputError(
                f"{path}: topic {topic} carries {all_topics[topic]}, expected one of {', '.join(msgtypes)}"
            )


def _damage_warning(path: Path, reason: str, last_ns: int | None, first_ns: int | None) -> str:
    where = "before any message" if last_ns is None else f"after t={(last_ns - (first_ns or last_ns)) * 1e-9:.2f} s of recording"
    return f"{path}: the bag is damaged ({reason}); read the messages up to the damage, {where}"


def _scan_ros1(path: Path, topics: Sequence[str], msgtypes: Sequence[str] | None, reason: str) -> _BagStream:
    """Read a ROS 1 bag without its index: chunk by chunk from the start, up to the first damage.

    Written here because rosbags has no ROS 1 reindexer; the record layout is ROS 1's bag format
    2.0 (a header of ``name=value`` fields, then a data block; chunks hold connection and message
    records). Uses rosbags' record-header parser and decompressors.
    """
    from rosbags.rosbag1.reader import (
        Header,
        ReaderError,
        RecordType,
        decompressors,
        read_bytes,
        read_uint32,
    )
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore
    from rosbags.typesys.msg import normalize_msgtype

    size = os.path.getsize(path)
    handle = path.open("rb")
    magic = handle.readline()
    if magic != b"#ROSBAG V2.0\n":
        handle.close()
        raise InputError(f"{path}: not a ROS 1 bag of format 2.0 (file starts with {magic[:20]!r}; {reason})")
    typestore = get_typestore(Stores.EMPTY)
    connections: dict[int, tuple[str, str, str]] = {}
    warnings: list[str] = [f"{path}: the bag has no usable index ({reason}); scanning its chunks instead"]
    found_topics: dict[str, str] = {}

    def add_connection(conn_id: int, topic: str, data: bytes) -> None:
        fields = Header.read(BytesIO(len(data).to_bytes(4, "little") + data))
        msgtype = normalize_msgtype(fields.get_string("type"))
        if topic in topics and msgtype not in typestore.fielddefs:
            typestore.register(get_types_from_msg(fields.get_string("message_definition"), msgtype))
        connections[conn_id] = (topic, msgtype, fields.get_string("md5sum"))
        found_topics[topic] = msgtype

    def records(source) -> Iterator[tuple[Header, bytes]]:
        while True:
            if source.read(1) == b"":
                return
            source.seek(-1, os.SEEK_CUR)
            header = Header.read(source)
            yield header, read_bytes(source, read_uint32(source))

    def messages() -> Iterator[Message]:
        last = first = None
        position = handle.tell()
        try:
            for header, data in records(handle):
                op = header.get_uint8("op")
                if op == RecordType.CHUNK:
                    compression = header.get_string("compression")
                    if compression not in decompressors:
                        raise ReaderError(f"unknown chunk compression {compression!r}")
                    chunk = BytesIO(decompressors[compression](data))
                    batch = []
                    for inner, payload in records(chunk):
                        kind = inner.get_uint8("op")
                        if kind == RecordType.CONNECTION:
                            add_connection(inner.get_uint32("conn"), inner.get_string("topic"), payload)
                        elif kind == RecordType.MSGDATA:
                            topic, msgtype, digest = connections[inner.get_uint32("conn")]
                            if topic in topics:
                                batch.append(Message(topic, msgtype, inner.get_time("time"), payload, digest))
                    for message in batch:
                        first = message.time_ns if first is None else first
                        last = message.time_ns
                        yield message
                elif op == RecordType.CONNECTION:
                    add_connection(header.get_uint32("conn"), header.get_string("topic"), data)
                position = handle.tell()
        except Exception as exc:  # noqa: BLE001 - whatever breaks the scan is the damage
            warnings.append(
                _damage_warning(path, f"unreadable from byte {position} of {size}: {type(exc).__name__} {exc}", last, first)
            )
        finally:
            handle.close()
            missing = [topic for topic in topics if topic not in found_topics]
            if missing and not warnings[1:]:
                there = ", ".join(sorted(found_topics)) or "none"
                warnings.append(f"{path}: no topic {', '.join(missing)} in the readable part; topics there: {there}")

    try:
        header = Header.read(handle, RecordType.BAGHEADER)
        read_bytes(handle, read_uint32(handle))
    except (ReaderError, ValueError) as exc:
        handle.close()
        raise InputError(f"{path}: corrupt ROS 1 bag: its header is unreadable ({exc})") from None
    del header

    def typed_messages() -> Iterator[Message]:
        for message in messages():
            if msgtypes is not None and message.msgtype not in msgtypes:
                handle.close()
                raise InputError(
                    f"{path}: topic {message.topic} carries {message.msgtype}, expected one of {', '.join(msgtypes)}"
                )
            yield message

    return _BagStream(found_topics, typed_messages(), typestore.deserialize_ros1, warnings)


# -- camera frames ---------------------------------------------------------------------------------


def image_topics(path: str | Path) -> list[str]:
    """Topics of compressed camera images in a bag (empty when it has none or cannot be opened)."""
    from rosbags.highlevel import AnyReader, AnyReaderError

    try:
        with AnyReader([_bag_path(Path(path))]) as reader:
            return sorted({c.topic for c in reader.connections if c.msgtype in IMAGE_TYPES})
    except (AnyReaderError, OSError, ValueError, KeyError, AssertionError, InputError):
        return []


def images_near(path: str | Path, topic: str, times: Sequence[float]) -> tuple[list[tuple[float, bytes] | None], list[str]]:
    """The compressed image closest in time to each of ``times``.

    Parameters
    ----------
    path : the bag
    topic : a topic of ``sensor_msgs/CompressedImage``
    times : stamps (s, the clock of the /tf stamps)

    Returns
    -------
    frames : list, one per time: (stamp, encoded bytes) or None when the topic is empty
    warnings : problems met while reading
    """
    wanted = np.asarray(times, dtype=float)
    best: list[tuple[float, float, bytes] | None] = [None] * wanted.size
    with _open_stream(Path(path), [topic], IMAGE_TYPES) as stream:
        for message in stream.messages:
            image = stream.deserialize(message.raw, message.msgtype)
            stamp = image.header.stamp.sec + image.header.stamp.nanosec * 1e-9 or message.time_ns * 1e-9
            error = np.abs(wanted - stamp)
            for index in np.flatnonzero([b is None or e < b[0] for b, e in zip(best, error, strict=True)]):
                best[index] = (float(error[index]), stamp, bytes(image.data))
        warnings = list(stream.warnings)
    return [None if b is None else (b[1], b[2]) for b in best], warnings
