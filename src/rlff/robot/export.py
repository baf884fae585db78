"""Writing a timed joint trajectory to files: JSON, CSV, and ROS 1 / ROS 2 bags.

Bags hold one ``trajectory_msgs/JointTrajectory`` message (the type the thesis' plug-in and the
FollowJointTrajectory action take) on the robot's trajectory topic (the robot file's ``[ros]
trajectory_topic``, :data:`DEFAULT_TOPIC` without one), written with rosbags' type stores
(ROS 1 Noetic, ROS 2 Humble), so a ROS 1 bag carries the standard MD5 sum of the type and plays
with ``rosbag play``. JSON and CSV read back with :func:`read_json` and :func:`read_csv`, bags
with :func:`read_bag`; each keeps the robot it was planned for (:func:`read_planned_for`).

ROS conventions: a message's ``header.stamp`` is zero unless asked otherwise, which tells a
FollowJointTrajectory controller to start the trajectory on receipt (a stamp in the past would
make it skip the points already due); the bag's record time is the time of writing.
"""

from __future__ import annotations

import json
import time as clock
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd
from rosbags.rosbag2 import Reader as Ros2Reader
from rosbags.rosbag2 import Writer as Ros2Writer
from rosbags.typesys import Stores, get_typestore

from rlff.csvtable import write_csv_columns
from rlff.errors import InputError
from rlff.fileio import atomic_path, write_text
from rlff.jsonfile import read_json_object
from rlff.kinds import is_ros1_bag, rlff_kind
from rlff.robot.description import RosNames
from rlff.robot.ros1_fields import FieldReader as Ros1Reader
from rlff.robot.ros1_fields import FieldWriter as Ros1Writer
from rlff.trajectory.joint import JointTrajectory
from rlff.trajectory.planner import MOVING

#: The topic a bag carries the trajectory on when no robot names one (``RosNames``' default: the
#: topic of the original Comau driver's topic mode).
DEFAULT_TOPIC = RosNames.trajectory_topic
#: The ROS 1 type of the trajectory messages and its standard MD5 sum.
TRAJECTORY_TYPE = "trajectory_msgs/msg/JointTrajectory"
JOINT_TRAJECTORY_MD5 = "65b4f94a94d1ed67169da35a02f33d3f"

JSON_FORMAT = "rlff-joint-trajectory"
#: The ``units`` of a trajectory JSON: the only ones rlff writes and reads.
UNITS = {"time": "s", "positions": "rad", "velocities": "rad/s", "accelerations": "rad/s^2"}
_QUANTITIES = ("position", "velocity", "acceleration")


def write_json(traj: JointTrajectory, path: Path, robot: dict[str, str] | None = None) -> None:
    """``{"format", "version", "units", "robot", "joint_names", "time" (T,),
    "positions"/"velocities"/"accelerations" (T, J), "release_time"}`` (``release_time`` in s,
    null for a trajectory that is no throw; ``robot`` the robot it was planned for,
    :func:`rlff.robot.planned_for.planned_for`, left out when None)."""
    document = {
        "format": JSON_FORMAT, "version": 1, "units": UNITS, **({"robot": dict(robot)} if robot else {}),
        "joint_names": list(traj.joint_names), "time": traj.time.tolist(),
        "positions": traj.positions.tolist(), "velocities": traj.velocities.tolist(),
        "accelerations": traj.accelerations.tolist(), "release_time": traj.release_time,
    }
    write_text(path, json.dumps(document) + "\n")


def read_json(path: Path) -> JointTrajectory:
    """The trajectory of a file written by :func:`write_json`; :class:`InputError` naming the fault."""
    document = read_json_object(path)
    if document.get("format") != JSON_FORMAT:
        kind = rlff_kind(path)
        raise InputError(f"{path} is {kind}, not a robot trajectory ({JSON_FORMAT})" if kind
                         else f"{path}: not an {JSON_FORMAT} file")
    fields = ("joint_names", "time", "positions", "velocities", "accelerations")
    missing = [name for name in fields if name not in document]
    if missing:
        raise InputError(f"{path}: missing field {missing[0]!r}")
    _require_units(path, document.get("units", UNITS))
    release = document.get("release_time")
    if release is not None and (isinstance(release, bool) or not isinstance(release, int | float)):
        raise InputError(f"{path}: field 'release_time' must be a number of seconds or null, got {release!r}")
    try:
        return JointTrajectory(tuple(document["joint_names"]), *(document[name] for name in fields[1:]),
                               release_time=release)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{path}: not a robot trajectory ({exc})") from None


def _require_units(path: Path, units: object) -> None:
    """Refuse a JSON's ``units`` other than :data:`UNITS`: its numbers would be read as rad and s
    whatever it says (``"positions": "deg"`` was)."""
    if units == UNITS:
        return
    written = ", ".join(f"{name} {unit}" for name, unit in UNITS.items())
    if not isinstance(units, dict):
        raise InputError(f"{path}: field 'units' must be {json.dumps(UNITS)}, got {units!r}")
    name = next(name for name in (*UNITS, *units) if units.get(name) != UNITS.get(name))
    said = (f"has {name!r}, which rlff does not know" if name not in UNITS
            else f"gives no unit for {name}" if name not in units else f"gives {name} in {units[name]!r}")
    raise InputError(f"{path}: field 'units' {said}; rlff reads a trajectory only in {written}: convert the "
                     "file's values (and its 'units') to those")


def write_csv(traj: JointTrajectory, path: Path, robot: dict[str, str] | None = None) -> None:
    """One row per point: ``time`` (s), then ``{joint}_position`` (rad), ``_velocity``, ``_acceleration``.

    A planned throw also gets a ``release_time`` column (s), and a trajectory planned for a
    ``robot`` (:func:`rlff.robot.planned_for.planned_for`) the columns of :data:`ROBOT_COLUMNS`,
    its name and digest; each the same on every row (the way per-trajectory metadata rides along
    in rlff's CSV files).
    """
    columns = {"time": traj.time}
    for index, name in enumerate(traj.joint_names):
        for quantity, values in zip(_QUANTITIES, (traj.positions, traj.velocities, traj.accelerations), strict=True):
            columns[f"{name}_{quantity}"] = values[:, index]
    if traj.release_time is not None:
        columns["release_time"] = np.full(len(traj), traj.release_time)
    if robot:
        for column, key in ROBOT_COLUMNS.items():
            columns[column] = [robot[key]] * len(traj)
    write_csv_columns(path, columns)


#: The CSV columns of the robot a trajectory was planned for, and the key of the record each holds.
ROBOT_COLUMNS = {"robot": "name", "robot_digest": "digest"}


def read_planned_for(path: Path, topic: str = DEFAULT_TOPIC) -> dict[str, str] | None:
    """The robot a trajectory file of :func:`write_json` or :func:`write_csv`, or a bag of
    :func:`write_ros1_bag` or :func:`write_ros2_bag` (its trajectory on ``topic``), was planned
    for, ``{"name", "digest"}`` (a bag's also ``"convention"``, the ``[ros.joints]`` map its
    positions are in, where it says); None for one that does not say (written before rlff
    recorded it, by hand or by another tool). :class:`InputError` naming the field for a record
    that is no such thing."""
    path = Path(path)
    if path.is_dir() or is_ros1_bag(path):
        return _bag_planned_for(path, *_from_bag(path, lambda reader, *_: _bag_record(reader, topic)))
    if path.suffix.lower() == ".json":
        record = read_json_object(path).get("robot")
        if record is None:
            return None
        if not (isinstance(record, dict) and all(isinstance(record.get(key), str) and record[key]
                                                 for key in ROBOT_COLUMNS.values())):
            raise InputError(f"{path}: field 'robot' must be the robot the trajectory was planned for, "
                             f'{{"name": ..., "digest": ...}} as rlff writes it, got {json.dumps(record)[:80]}')
        return {key: record[key] for key in ROBOT_COLUMNS.values()}
    header = pd.read_csv(path, nrows=0).columns
    if not any(column in header for column in ROBOT_COLUMNS):
        return None
    missing = [column for column in ROBOT_COLUMNS if column not in header]
    if missing:
        raise InputError(f"{path}: a column {missing[0]!r} is needed beside "
                         f"{' and '.join(repr(c) for c in ROBOT_COLUMNS if c not in missing)}: together they name the "
                         "robot the trajectory was planned for")
    table = pd.read_csv(path, usecols=list(ROBOT_COLUMNS), dtype=str, keep_default_na=False)
    record = {}
    for column, key in ROBOT_COLUMNS.items():
        values = table[column].unique()
        if len(values) != 1 or not values[0]:
            raise InputError(f"{path}: column {column!r} must hold the same {key} of the robot the trajectory was "
                             "planned for on every row")
        record[key] = str(values[0])
    return record


#: The keys of a bag's record of the robot its trajectory was planned for, and the key of the
#: record each holds: in a ROS 2 bag, its metadata's ``custom_data``; in a ROS 1 bag, fields of
#: the trajectory connection's header (:mod:`rlff.robot.ros1_fields`). Neither is played.
BAG_KEYS = {"rlff_robot": "name", "rlff_robot_digest": "digest"}
#: The key of the ``[ros.joints]`` map a bag's positions are written in
#: (:func:`rlff.robot.planned_for.controller_convention`), beside :data:`BAG_KEYS`; bags written
#: before 2026-12-07 lack it.
CONVENTION_KEY = "rlff_ros_joints"


def _bag_keys(robot: dict[str, str] | None) -> dict[str, str]:
    """The :data:`BAG_KEYS` entries of a record ``robot`` (none for None), and its
    :data:`CONVENTION_KEY` where it has a ``"convention"``."""
    if not robot:
        return {}
    keys = {key: robot[field] for key, field in BAG_KEYS.items()}
    return keys | ({CONVENTION_KEY: robot["convention"]} if "convention" in robot else {})


def _bag_record(reader, topic: str) -> tuple[dict, str]:
    """What the bag open in ``reader`` holds of :data:`BAG_KEYS` (its trajectory on ``topic``),
    and where it holds them, for a message."""
    if isinstance(reader, Ros2Reader):  # rosbags' copy of its metadata.yaml
        custom = reader.storage.metadata.custom or {}
        return {key: value for key, value in custom.items() if key in _RECORD_KEYS}, "metadata's custom_data"
    found = {}
    for connection in reader.connections:
        if connection.topic == topic:
            found |= {key: value for key, value in reader.fields[connection.id].items() if key in _RECORD_KEYS}
    return found, f"connection header of {topic}"


_RECORD_KEYS = (*BAG_KEYS, CONVENTION_KEY)


def _bag_planned_for(path: Path, found: dict, where: str) -> dict[str, str] | None:
    """The record of the bag ``path`` from the :data:`BAG_KEYS` (and :data:`CONVENTION_KEY`, as
    ``"convention"``, where it has one) it holds, ``found`` in its ``where``."""
    if not found:
        return None
    if (not all(key in found for key in BAG_KEYS)
            or not all(isinstance(value, str) and value for value in found.values())):
        held = ", ".join(f"{key}={found[key]!r}" for key in _RECORD_KEYS if key in found)
        raise InputError(f"{path}: the bag's {where} must hold {' and '.join(BAG_KEYS)}, the robot its trajectory "
                         f"was planned for, as rlff writes them; it holds {held}")
    record = {field: found[key] for key, field in BAG_KEYS.items()}
    return record | ({"convention": found[CONVENTION_KEY]} if CONVENTION_KEY in found else {})


def read_csv(path: Path) -> JointTrajectory:
    """The trajectory of a file written by :func:`write_csv`; :class:`InputError` naming the fault."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"{path}: no such file")
    try:
        table = pd.read_csv(path)
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise InputError(f"{path}: not a readable CSV ({str(exc).strip().splitlines()[-1]})") from None
    if not isinstance(table.index, pd.RangeIndex):  # pandas made the first fields the row labels
        raise InputError(f"{path}: the rows have more fields than the header's {len(table.columns)} columns")
    names = [column.removesuffix("_position") for column in table.columns if column.endswith("_position")]
    if "time" not in table or not names:
        raise InputError(f"{path}: expected a 'time' column and '<joint>_position' columns")
    missing = [f"{n}_{q}" for q in _QUANTITIES for n in names if f"{n}_{q}" not in table.columns]
    if missing:
        raise InputError(f"{path}: no column {missing[0]!r} (columns: {', '.join(table.columns)})")
    release = None
    if "release_time" in table:
        values = pd.to_numeric(table["release_time"], errors="coerce").to_numpy(float)
        if not (np.all(np.isfinite(values)) and np.all(values == values[0])):
            raise InputError(f"{path}: column 'release_time' must hold one number of seconds on every row")
        release = float(values[0])
    try:
        arrays = [table[[f"{n}_{q}" for n in names]].to_numpy(float) for q in _QUANTITIES]
        return JointTrajectory(tuple(names), table["time"].to_numpy(float), *arrays, release_time=release)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{path}: not a robot trajectory ({exc})") from None


#: Largest distance (s) of a file's ``release_time`` from one of its sample times: rlff writes the
#: sample's own time; a hand-written one may round it (controllers' periods are 0.0001 s or more).
RELEASE_TOLERANCE = 1e-6


def require_release(path: Path, traj: JointTrajectory) -> JointTrajectory:
    """``traj``, read from the file ``path``, with its ``release_time`` the sample time it names.

    rlff releases a planned throw at a sample, at the end of the throw
    (:func:`rlff.trajectory.planner.plan_throw`): every joint that moves there is at its fastest
    since the throw began (the arm's last rest before it), and braking follows; a throw released
    at rest ends there. A release between samples, where the arm rests with a motion still to come
    or none before, or where a joint has slowed down (braking) is refused: the simulation let go there.
    Run after the motion check, which says what else an edit broke (a time column stretched alone).
    """
    release = traj.release_time
    if release is None:
        return traj
    time, speed = traj.time, np.abs(traj.velocities)
    k = int(np.argmin(np.abs(time - release)))
    if abs(time[k] - release) > RELEASE_TOLERANCE:
        raise InputError(f"{path}: release_time {release:.10g} s is not one of the trajectory's sample times (the "
                         f"nearest: {time[k]:.10g} s); a throw is released at a sample")
    resting = np.all(speed <= MOVING, axis=1)
    if resting[k] and (np.all(resting[:k]) or not np.all(resting[k:])):
        raise InputError(f"{path}: release_time {release:.10g} s falls where the arm rests, "
                         f"{'before its motion' if np.all(resting[:k]) else 'between its moves'}: nothing is thrown "
                         "there; give the time of the throw's release")
    began = int(np.flatnonzero(resting[:k])[-1]) if np.any(resting[:k]) else 0
    peak = speed[began:k + 1].max(axis=0)
    slower = np.flatnonzero((speed[k] > MOVING) & (peak > speed[k] * (1 + 1e-9) + 1e-9))
    if slower.size:
        j = int(slower[0])
        fastest = began + int(np.argmax(speed[began:k + 1, j]))
        raise InputError(f"{path}: release_time {release:.10g} s falls where the arm slows down: "
                         f"{traj.joint_names[j]} moves at {speed[k, j]:.4g} rad/s there, after {peak[j]:.4g} rad/s at "
                         f"{time[fastest]:.10g} s; a throw is released at its fastest, before it brakes: give the time "
                         "of the throw's release")
    return replace(traj, release_time=float(time[k]))


def _message(traj: JointTrajectory, typestore, stamp_ns: int, ros1: bool):
    """The JointTrajectory message; ``stamp_ns`` is its ``header.stamp`` (0: start on receipt)."""
    types = typestore.types
    seconds, nanoseconds = divmod(int(stamp_ns), 1_000_000_000)
    stamp = types["builtin_interfaces/msg/Time"](sec=seconds, nanosec=nanoseconds)
    header = (types["std_msgs/msg/Header"](seq=0, stamp=stamp, frame_id="") if ros1
              else types["std_msgs/msg/Header"](stamp=stamp, frame_id=""))
    duration = types["builtin_interfaces/msg/Duration"]
    point = types["trajectory_msgs/msg/JointTrajectoryPoint"]
    whole = np.floor(traj.time).astype(int)
    nanos = np.rint((traj.time - whole) * 1e9).astype(int)
    carry = nanos >= 1_000_000_000
    whole, nanos = whole + carry, np.where(carry, nanos - 1_000_000_000, nanos)
    points = [point(positions=traj.positions[i].copy(), velocities=traj.velocities[i].copy(),
                    accelerations=traj.accelerations[i].copy(), effort=np.zeros(0),
                    time_from_start=duration(sec=int(whole[i]), nanosec=int(nanos[i])))
              for i in range(len(traj))]
    return types[TRAJECTORY_TYPE](header=header, joint_names=list(traj.joint_names), points=points)


def write_ros1_bag(traj: JointTrajectory, path: Path, topic: str = DEFAULT_TOPIC,
                   stamp_ns: int | None = None, header_stamp_ns: int = 0,
                   robot: dict[str, str] | None = None) -> None:
    """A ROS 1 bag with one JointTrajectory on ``topic``, recorded at ``stamp_ns`` (default: now).

    ``header_stamp_ns`` is the message's ``header.stamp`` (default 0: start on receipt). The
    ``robot`` the trajectory was planned for (:func:`rlff.robot.planned_for.planned_for`; left
    out when None) goes in the connection's header (:data:`BAG_KEYS`).
    """
    stamp_ns = clock.time_ns() if stamp_ns is None else stamp_ns
    typestore = get_typestore(Stores.ROS1_NOETIC)
    # rosbags refuses an existing file: it writes a fresh temporary one, renamed over ``path``
    with atomic_path(path) as temp:
        temp.unlink()
        with Ros1Writer(temp, _bag_keys(robot)) as writer:
            connection = writer.add_connection(topic, TRAJECTORY_TYPE, typestore=typestore)
            message = _message(traj, typestore, header_stamp_ns, ros1=True)
            writer.write(connection, stamp_ns, typestore.serialize_ros1(message, TRAJECTORY_TYPE))


#: What a ROS 2 bag folder holds: its metadata and its storage files (sqlite3 or MCAP).
_BAG_FILES = ("metadata.yaml", "*.db3", "*.mcap")


def check_bag_output(path: Path) -> None:
    """Refuse a ROS 2 bag output over a folder that is not a bag of robot trajectories.

    Such a bag (what :func:`write_ros2_bag` writes: JointTrajectory messages only, and nothing in
    its folder but the bag's own files) is replaced whole, as an existing output file is; any
    other folder (the user's files, a recording) is kept.

    Raises
    ------
    InputError
        Naming the folder and what to do.
    """
    path = Path(path)
    if path.is_dir() and not _trajectory_bag(path):
        raise InputError(f"{path}: a folder, and not a ROS 2 bag of robot trajectories (one rlff wrote is replaced "
                         "whole): refusing to replace it; give a new folder name for the bag")


def _trajectory_bag(path: Path) -> bool:
    """Whether the folder ``path`` holds a readable ROS 2 bag of JointTrajectory messages and nothing else."""
    if not all(child.is_file() and any(child.match(name) for name in _BAG_FILES) for child in path.iterdir()):
        return False
    try:
        with Ros2Reader(path) as reader:
            return bool(reader.connections) and all(c.msgtype == TRAJECTORY_TYPE for c in reader.connections)
    except Exception:  # noqa: BLE001 - rosbags and sqlite raise many types on what is no bag
        return False


def write_ros2_bag(traj: JointTrajectory, path: Path, topic: str = DEFAULT_TOPIC,
                   stamp_ns: int | None = None, header_stamp_ns: int = 0,
                   robot: dict[str, str] | None = None) -> None:
    """A ROS 2 bag (a folder, sqlite3 storage) with one JointTrajectory on ``topic``.

    Recorded at ``stamp_ns`` (default: now); ``header.stamp`` is ``header_stamp_ns`` (default 0);
    the ``robot`` it was planned for (as :func:`write_ros1_bag`) in the metadata's ``custom_data``.
    A bag of robot trajectories already at ``path`` is replaced whole once the new one is
    complete; any other folder there is refused (:func:`check_bag_output`).
    """
    stamp_ns = clock.time_ns() if stamp_ns is None else stamp_ns
    typestore = get_typestore(Stores.ROS2_HUMBLE)
    path = Path(path)
    check_bag_output(path)
    with atomic_path(path, folder=True) as temp, Ros2Writer(temp, version=8) as writer:
        connection = writer.add_connection(topic, TRAJECTORY_TYPE, typestore=typestore)
        message = _message(traj, typestore, header_stamp_ns, ros1=False)
        writer.write(connection, stamp_ns, typestore.serialize_cdr(message, TRAJECTORY_TYPE))
        for key, value in _bag_keys(robot).items():
            writer.set_custom_data(key, value)


def read_bag(path: Path, topic: str = DEFAULT_TOPIC) -> list[JointTrajectory]:
    """Every JointTrajectory on ``topic`` of a ROS 1 bag (a file) or a ROS 2 bag (a folder).

    Raises
    ------
    InputError
        No such bag, a damaged bag (whatever rosbags or the message decoder met), or a message
        that is not a valid trajectory.
    """
    return _from_bag(path, lambda reader, typestore, deserialize: _read_bag(reader, typestore, deserialize, topic))


def trajectory_topics(path: Path) -> list[str]:
    """The topics of a bag (as :func:`read_bag` takes it) that carry JointTrajectory messages.

    Raises
    ------
    InputError
        As :func:`read_bag`.
    """
    return _from_bag(path, lambda reader, *_: sorted({c.topic for c in reader.connections
                                                      if c.msgtype == TRAJECTORY_TYPE}))


def _from_bag(path: Path, read):
    """``read(reader, typestore, deserialize)`` with the bag at ``path`` open: a ROS 1 bag (a
    file) or a ROS 2 bag (a folder); any error on the way is an :class:`InputError` naming it."""
    path = Path(path)
    if not path.exists():
        raise InputError(f"{path}: no such file or folder")
    try:
        if path.is_dir():
            reader, typestore, deserialize = Ros2Reader(path), get_typestore(Stores.ROS2_HUMBLE), "deserialize_cdr"
        else:
            reader, typestore, deserialize = Ros1Reader(path), get_typestore(Stores.ROS1_NOETIC), "deserialize_ros1"
        with reader:
            return read(reader, typestore, deserialize)
    except InputError as exc:
        raise InputError(f"{path}: not a robot trajectory ({exc})") from None
    except Exception as exc:  # noqa: BLE001 - rosbags, sqlite and the decoders raise many types on damage
        raise InputError(f"{path}: not a readable trajectory bag ({type(exc).__name__}: {exc})") from None


def _read_bag(reader, typestore, deserialize: str, topic: str) -> list[JointTrajectory]:
    trajectories = []
    connections = [c for c in reader.connections if c.topic == topic]
    if not connections:  # rosbags reads every connection when given none
        return trajectories
    for connection, _, raw in reader.messages(connections=connections):
        msg = getattr(typestore, deserialize)(raw, connection.msgtype)
        time = [p.time_from_start.sec + p.time_from_start.nanosec * 1e-9 for p in msg.points]
        trajectories.append(JointTrajectory(
            tuple(msg.joint_names), time, [p.positions for p in msg.points],
            [p.velocities for p in msg.points], [p.accelerations for p in msg.points]))
    return trajectories
