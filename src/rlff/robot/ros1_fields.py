"""Fields of rlff's own in a ROS 1 bag's connection headers, written and read through rosbags.

A ROS 1 bag (format 2.0) keeps, for every connection, the connection header of its publisher:
``name=value`` fields (``topic``, ``type``, ``md5sum``, ``message_definition``, ``callerid``,
``latching``). ``rosbag record`` stores whatever fields a publisher sent; ``rosbag play`` and
``rosbag info`` read the ones they know and leave the others. So a field there is the place of
a bag-level note about a connection's messages that no player sends anywhere: the trajectory's
topic, message and MD5 sum stay as they are, and no topic is added. (A topic of rlff's own would
hold ``rosbag play --wait-for-subscribers`` for ever: it waits for a subscriber on every topic
of the bag, and no controller subscribes to rlff's.)

rosbags writes and reads the fields it knows; :class:`FieldWriter` and :class:`FieldReader` add
the others at its seam for connection records (``write_connection``, ``read_connection``), in
the format's record layout: the record's header (length-prefixed), then the connection header
as its data (a length, then length-prefixed ``name=value`` fields).
"""

from __future__ import annotations

from io import BytesIO
from pathlib import Path

from rosbags.rosbag1 import Reader, Writer
from rosbags.rosbag1.reader import Header, RecordType


def _field(name: str, value: str) -> bytes:
    """One ``name=value`` field of a ROS connection header: its length (uint32 LE), then the bytes."""
    text = f"{name}={value}".encode()
    return len(text).to_bytes(4, "little") + text


class FieldWriter(Writer):
    """rosbags' ROS 1 bag writer, adding ``fields`` (name to value) to the header of every
    connection it writes (its chunk's copy and the index's)."""

    def __init__(self, path: str | Path, fields: dict[str, str]) -> None:
        super().__init__(path)
        self.fields = dict(fields)

    def write_connection(self, connection, bio) -> None:  # rosbags': a staticmethod called on the writer
        record = BytesIO()
        Writer.write_connection(connection, record)
        raw = record.getvalue()
        data = 4 + int.from_bytes(raw[:4], "little")  # past the record's header: the connection header's length
        extra = b"".join(_field(name, value) for name, value in self.fields.items())
        size = int.from_bytes(raw[data:data + 4], "little") + len(extra)
        bio.write(raw[:data] + size.to_bytes(4, "little") + raw[data + 4:] + extra)


class FieldReader(Reader):
    """rosbags' ROS 1 bag reader, keeping every field of each connection's header:
    ``fields[connection.id]`` maps a field's name to its value (decoded as UTF-8)."""

    def __init__(self, path: str | Path) -> None:
        super().__init__(path)
        self.fields: dict[int, dict[str, str]] = {}

    def read_connection(self):
        start = self.bio.tell()
        connection = super().read_connection()
        end = self.bio.tell()
        self.bio.seek(start)
        Header.read(self.bio, RecordType.CONNECTION)  # the record's own header: conn, topic
        header = Header.read(self.bio)
        self.fields[connection.id] = {name: value.decode("utf-8", errors="replace") for name, value in header.items()}
        self.bio.seek(end)
        return connection
