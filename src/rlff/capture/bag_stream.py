"""A bag as a stream of still-serialised messages of some topics, ROS 1 or ROS 2.

Opened with rosbags (``AnyReader``: one chunk in memory at a time, types from the definitions
stored in the bag). A ROS 1 bag whose end is damaged (the recorder died, the copy was cut short)
has no usable index and rosbags refuses it; its chunks are then scanned from the start and read up
to the damage, with a warning. Damage met while iterating an indexed ROS 1 bag (a chunk whose bytes
are damaged) skips to the next chunk's start with a warning saying which span was lost; damage in
a ROS 2 bag, or in the last chunks, ends the stream with a warning.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from io import BytesIO
from pathlib import Path
from typing import Any

from rlff.errors import InputError
from rlff.kinds import ROS1_BAG_MAGIC, is_ros1_bag, is_ros2_metadata


@dataclass(frozen=True)
class Message:
    """One message of a bag, still serialised; ``digest`` is the ROS 1 md5sum of its
    connection's definition ("" for ROS 2)."""

    topic: str
    msgtype: str
    time_ns: int
    raw: bytes | memoryview
    digest: str = ""


@dataclass
class BagStream:
    """Messages of some topics, a way to decode them, the topics there are, and what went wrong."""

    topics: dict[str, str]
    messages: Iterator[Message]
    deserialize: Callable[[bytes | memoryview, str], Any]
    warnings: list[str] = field(default_factory=list)


def bag_path(path: Path) -> Path:
    """The path rosbags wants: a ROS 1 file, or the folder of a ROS 2 bag (given as the folder, its
    database or its ``metadata.yaml``)."""
    if not path.exists():
        raise InputError(f"{path}: no such file or folder")
    if path.is_file() and (is_ros2_metadata(path)
                           or path.suffix in (".db3", ".mcap") and (path.parent / "metadata.yaml").is_file()):
        return path.parent
    return path


@contextmanager
def open_stream(path: Path, topics: Sequence[str], msgtypes: Sequence[str] | None) -> Iterator[BagStream]:
    """Messages of ``topics`` (checked to be of one of ``msgtypes``) in time order.

    Reads through rosbags; a ROS 1 bag that rosbags cannot open (damaged index) is scanned instead.
    An error while iterating a ROS 1 bag skips to the next chunk (:func:`_next_chunk`), with a
    warning naming the span lost; one with no chunk after it, or in a ROS 2 bag, ends the
    iteration with a warning.
    """
    from rosbags.highlevel import AnyReader, AnyReaderError

    bag = bag_path(path)
    if bag.is_file() and bag.suffix != ".bag":
        if is_ros1_bag(bag):  # rosbags tells a ROS 1 bag by its suffix alone
            named = f"its name ends in {bag.suffix}" if bag.suffix else "its name has no suffix"
            raise InputError(f"{path}: a ROS 1 bag by its first bytes (#ROSBAG V2.0), but {named}: give it the "
                             f"suffix .bag ({bag.with_suffix('.bag').name}), by which rlff reads ROS 1 bags")
        if bag.suffix in (".db3", ".mcap"):  # said "not a ROS bag", which it is, in part
            raise InputError(f"{path}: a ROS 2 bag's {bag.suffix} database without its metadata.yaml beside it: "
                             "give rlff the bag's folder, the one that holds both")
        raise InputError(f"{path}: not a ROS bag (a ROS 1 bag ends in .bag, a ROS 2 bag is a folder)")
    try:
        reader = AnyReader([bag])
        reader.open()
    # rosbags lets some damage through unwrapped: a ROS 2 metadata.yaml whose values have the
    # wrong types raises TypeError or AttributeError while it is parsed
    except (AnyReaderError, OSError, ValueError, KeyError, AssertionError, TypeError, AttributeError) as exc:
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
            if not connections:
                return  # rosbags reads every connection when given none
            start = last = lost = None  # where reading resumes, the last message read, where damage began (ns)
            reason = ""
            while True:
                try:
                    for connection, time_ns, raw in reader.messages(connections=connections, start=start):
                        if lost is not None:  # read on past the damage
                            warnings.append(_skip_warning(path, reason, lost, start, reader.start_time))
                            lost = None
                        last = time_ns
                        yield Message(connection.topic, connection.msgtype, time_ns, raw,
                                      connection.digest if not reader.is2 else "")
                    if lost is not None:
                        warnings.append(_damage_warning(path, reason, last, reader.start_time))
                    return
                except Exception as exc:  # noqa: BLE001 - any decoding failure inside the bag is damage
                    after = max(time for time in (last, start, reader.start_time - 1) if time is not None)
                    if lost is None:
                        lost, reason = after, f"{type(exc).__name__}: {exc}"
                    start = None if reader.is2 else _next_chunk(reader, after)
                    if start is None:
                        warnings.append(_damage_warning(path, reason, last, reader.start_time))
                        return

        yield BagStream(all_topics, messages(), deserialize, warnings)
    finally:
        reader.close()


class MissingTopic(InputError):
    """A topic asked for that the bag does not have; ``topics`` maps the bag's topics to their types,
    for a reader to say what it would have read instead."""

    def __init__(self, message: str, topics: dict[str, str]):
        super().__init__(message)
        self.topics = topics


def _check_topics(path: Path, all_topics: dict[str, str], topics: Sequence[str], msgtypes: Sequence[str] | None) -> None:
    for topic in topics:
        if topic not in all_topics:
            there = ", ".join(f"{name} ({kind})" for name, kind in sorted(all_topics.items())) or "none"
            raise MissingTopic(f"{path}: no topic {topic} in the bag; topics there: {there}", all_topics)
        if msgtypes is not None and all_topics[topic] not in msgtypes:
            raise InputError(
                f"{path}: topic {topic} carries {all_topics[topic]}, expected one of {', '.join(msgtypes)}"
            )


def _next_chunk(reader: Any, after_ns: int) -> int | None:
    """The first stamp (ns) after ``after_ns`` where a chunk of the ROS 1 bags of ``reader`` (a
    rosbags ``AnyReader``) begins, to read on from past a damaged chunk; None when none begins later."""
    starts = [info.start_time for bag in reader.readers for info in bag.chunk_infos if info.start_time > after_ns]
    return min(starts, default=None)


def _skip_warning(path: Path, reason: str, lost_ns: int, resumed_ns: int, first_ns: int) -> str:
    """The warning for messages skipped from ``lost_ns`` (the last read before the damage) to
    ``resumed_ns`` (the next chunk's start)."""
    return (f"{path}: the bag is damaged ({reason}); skipped its messages from t={(lost_ns - first_ns) * 1e-9:.2f} s "
            f"to t={(resumed_ns - first_ns) * 1e-9:.2f} s of recording (a damaged chunk) and read the rest")


def _damage_warning(path: Path, reason: str, last_ns: int | None, first_ns: int | None) -> str:
    where = "before any message" if last_ns is None else f"after t={(last_ns - (first_ns or last_ns)) * 1e-9:.2f} s of recording"
    return f"{path}: the bag is damaged ({reason}); read the messages up to the damage, {where}"


def _scan_ros1(path: Path, topics: Sequence[str], msgtypes: Sequence[str] | None, reason: str) -> BagStream:
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
    if magic != ROS1_BAG_MAGIC:
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

    return BagStream(found_topics, typed_messages(), typestore.deserialize_ros1, warnings)
