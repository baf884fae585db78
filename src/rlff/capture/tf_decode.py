"""Collecting the translations of some tf frames from a stream of serialised tf messages.

ROS 1 messages with the standard tf definition (``geometry_msgs/TransformStamped[]
transforms``, shared by ``tf/tfMessage`` and ``tf2_msgs/TFMessage``) are decoded here rather
than with the generic rosbags deserialiser, which converts each message to CDR and builds five
Python objects per transform: that made /tf extraction several times slower than reading the bag.

A skeleton tracker publishes the same frames in the same order at every tick, so the messages
come in a few byte layouts. The first message of each length is parsed with :mod:`struct` and
its layout recorded (where the length fields and frame names are, where the wanted stamps and
translations are). Later messages of that length are queued and decoded in batches with numpy:
one gather per batch, a byte-for-byte check of every length field and frame name against the
layout, and views of the stamps and translations. A message that fails the check is parsed on
its own. Other definitions and ROS 2 (CDR) messages go through the bag's typestore.
"""

from __future__ import annotations

import struct
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from rosbags.serde import SerdeError

#: MD5 of the ROS 1 tf definition; rosbags checks each connection's digest against the
#: definition stored in the bag, so a match means exactly the layout decoded here.
TF_MD5 = "94810edda583a504dfda3829e70d7eec"
_UINT32 = struct.Struct("<I")
_HEADER = struct.Struct("<IIII")  # seq, stamp sec, stamp nanosec, length of frame_id
_VECTOR = struct.Struct("<3d")
#: Messages decoded together (a few hundred kB at most: memory stays flat).
BATCH = 512
#: What decoding a damaged message raises: struct and the bounds checks here, rosbags' decoder.
_DAMAGE = (ValueError, IndexError, struct.error, SerdeError)


@dataclass
class _Layout:
    """Byte layout of a ROS 1 tf message.

    ``at`` holds the offsets of the F fixed bytes (length fields and frame names), then 8 per
    wanted transform (stamp sec and nanosec), then 24 per wanted transform (its translation).
    """

    at: np.ndarray
    fixed: np.ndarray
    names: list[tuple[str, str]]


class TfCollector:
    """Translations and stamps of the tf frames that ``keep`` accepts.

    Parameters
    ----------
    keep : callable
        ``keep(child_frame_id) -> bool``; called once per distinct name is enough (cache it).
    deserialize : callable
        ``deserialize(raw, msgtype)`` of the bag's typestore, for messages not decoded here.
    """

    def __init__(self, keep: Callable[[str], bool], deserialize: Callable[[bytes | memoryview, str], Any]):
        self.keep = keep
        self.deserialize = deserialize
        self._layouts: dict[int, _Layout] = {}
        self._pending: dict[int, tuple[list[bytes], list[int]]] = {}
        self._times: dict[tuple[str, str], list[np.ndarray]] = {}
        self._positions: dict[tuple[str, str], list[np.ndarray]] = {}
        #: Messages skipped because they could not be decoded (damaged bytes).
        self.skipped = 0

    def add(self, raw: bytes | memoryview, msgtype: str, digest: str, time_ns: int) -> None:
        """Take one serialised tf message received at ``time_ns`` (bag time, ns); a message that
        cannot be decoded is skipped and counted in :attr:`skipped`."""
        try:
            self._add(raw, msgtype, digest, time_ns)
        except _DAMAGE:
            self.skipped += 1

    def _add(self, raw: bytes | memoryview, msgtype: str, digest: str, time_ns: int) -> None:
        if digest != TF_MD5:
            decoded = self.deserialize(raw, msgtype)
            for t in decoded.transforms:
                if self.keep(t.child_frame_id):
                    stamp = t.header.stamp
                    translation = t.transform.translation
                    self._store(t.child_frame_id, t.header.frame_id, stamp.sec, stamp.nanosec, time_ns,
                                (translation.x, translation.y, translation.z))
            return
        data = bytes(raw)
        if len(data) not in self._layouts:
            self._layouts[len(data)] = self._parse(data, time_ns)
            return
        datas, times = self._pending.setdefault(len(data), ([], []))
        datas.append(data)
        times.append(time_ns)
        if len(datas) >= BATCH:
            self._flush(len(data))

    def finish(self) -> dict[tuple[str, str], tuple[np.ndarray, np.ndarray]]:
        """Per (child frame, parent frame) as the messages name them: (stamps (T,) in s,
        translations (T, 3) in m), unsorted; a child published under two parents (two trackers,
        or a name written with and without a leading slash) has an entry for each."""
        for length in list(self._pending):
            self._flush(length)
        return {pair: (np.concatenate(self._times[pair]), np.concatenate(self._positions[pair])) for pair in self._times}

    def _store(self, child: str, parent: str, sec: int, nanosec: int, time_ns: int, xyz: tuple[float, float, float]) -> None:
        self._times.setdefault((child, parent), []).append(np.array([sec + nanosec * 1e-9 or time_ns * 1e-9]))
        self._positions.setdefault((child, parent), []).append(np.array([xyz]))

    def _parse(self, data: bytes, time_ns: int) -> _Layout:
        """Decode one message with struct, store its wanted transforms, return its layout."""
        (count,) = _UINT32.unpack_from(data, 0)
        offset = 4
        fixed = [np.arange(4)]
        stamps, translations, names = [], [], []
        for _ in range(count):
            _, sec, nanosec, length = _HEADER.unpack_from(data, offset)
            parent_at = offset + 16
            if parent_at + length + 4 > len(data):  # a damaged length: never index past the message
                raise ValueError(f"tf message of {len(data)} bytes: a frame name of {length} bytes at byte {parent_at}")
            fixed.append(np.arange(offset + 12, parent_at + length))
            stamp_at = offset + 4
            offset = parent_at + length
            (child_length,) = _UINT32.unpack_from(data, offset)
            if offset + 4 + child_length > len(data):
                raise ValueError(f"tf message of {len(data)} bytes: a frame name of {child_length} bytes at byte {offset + 4}")
            fixed.append(np.arange(offset, offset + 4 + child_length))
            child = data[offset + 4 : offset + 4 + child_length].decode()
            offset += 4 + child_length
            if self.keep(child):
                parent = data[parent_at : parent_at + length].decode()
                self._store(child, parent, sec, nanosec, time_ns, _VECTOR.unpack_from(data, offset))
                names.append((child, parent))
                stamps.append(np.arange(stamp_at, stamp_at + 8))
                translations.append(np.arange(offset, offset + 24))
            offset += 56  # translation (3 x float64) and rotation (4 x float64)
        fixed_at = np.concatenate(fixed)
        at = np.concatenate([fixed_at, *stamps, *translations]).astype(np.intp)
        return _Layout(at, np.frombuffer(data, dtype=np.uint8)[fixed_at], names)

    def _flush(self, length: int) -> None:
        """Decode the queued messages of one length together."""
        datas, times = self._pending.pop(length, ([], []))
        if not datas:
            return
        layout = self._layouts[length]
        rows = np.frombuffer(b"".join(datas), dtype=np.uint8).reshape(len(datas), length)[:, layout.at]
        fixed = layout.fixed.size
        matches = np.all(rows[:, :fixed] == layout.fixed, axis=1)
        for index in np.flatnonzero(~matches):
            try:
                self._parse(datas[index], times[index])
            except _DAMAGE:
                self.skipped += 1
        wanted = len(layout.names)
        if not wanted or not matches.any():
            return
        good = rows[matches]
        stamps = np.ascontiguousarray(good[:, fixed : fixed + 8 * wanted]).view("<u4").reshape(-1, wanted, 2)
        positions = np.ascontiguousarray(good[:, fixed + 8 * wanted :]).view("<f8").reshape(-1, wanted, 3)
        seconds = stamps[..., 0] + stamps[..., 1] * 1e-9
        received = np.asarray(times, dtype=np.int64)[matches] * 1e-9
        seconds = np.where(seconds == 0, received[:, None], seconds)
        for index, pair in enumerate(layout.names):
            self._times.setdefault(pair, []).append(seconds[:, index])
            self._positions.setdefault(pair, []).append(positions[:, index])
