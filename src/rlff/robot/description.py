"""Robot description as data: joints with limits, arm geometry, the names of the arm's controller
on the ROS graph, and the robot's extra tables.

A robot is a TOML file (see ``rlff/robots/comau_smart5_six.toml`` for the fields and the
kinematic convention); the Comau Smart5 SiX ships with rlff, another robot is another file.
"""

from __future__ import annotations

import math
import re
import tomllib
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from importlib import resources
from pathlib import Path
from types import MappingProxyType
from typing import Any

import numpy as np

from rlff.errors import InputError
from rlff.robot.joint_map import ENTRY_FIELDS, ControllerJoint, JointMap
from rlff.wording import nearest_hint

DEFAULT_ROBOT = "comau_smart5_six"

_GEOMETRY_FIELDS = ("shoulder_height", "shoulder_forward", "upper_arm", "elbow_offset",
                    "forearm", "flange")


#: The limits every joint of a robot file states (see :class:`Joint`).
LIMIT_FIELDS = ("lower", "upper", "max_velocity", "max_acceleration", "max_jerk")

#: What each table of a robot file may hold. A key outside them is refused by name: a misspelt
#: one (``[comau_progam]``, ``max_velcoity``) would otherwise be ignored and its default used,
#: so that a joint's value lands in a Comau program slot nobody asked for.
_FIELDS = {
    "": ("name", "description", "joints", "geometry", "throwing", "whole_arm", "comau_program", "ros"),
    "[[joints]]": ("name", *LIMIT_FIELDS),
    "[geometry]": _GEOMETRY_FIELDS,
    "[throwing]": ("joint", "angle_offset", "angle_scale", "velocity_scale", "start_pose"),
    "[whole_arm]": ("time_scale", "bearing_joint", "joints", "start_pose"),
    "[whole_arm.joints.<joint>]": ("human", "offset", "scale"),
    "[comau_program]": ("position_slot", "velocity_slot"),
    "[ros]": ("action", "joint_states", "trajectory_topic", "joints"),
    "[ros.joints.<joint>]": ENTRY_FIELDS,
}
#: The tables of a robot file besides ``[[joints]]``.
_TABLES = ("geometry", "throwing", "whole_arm", "comau_program", "ros")
#: Bounds (rad, rad/s) no revolute joint of an arm exceeds, so that a robot file written in
#: degrees is refused, not read as radians: eight turns either way (the Comau's joint 6 turns
#: ±7.5, ±47.12 rad) and 50 rad/s (about 2,900 deg/s; its fastest joint does 9.6 rad/s).
#: Accelerations and jerks have no such bound (see docs/robot.md).
MAX_POSITION, MAX_VELOCITY = 8 * 2 * math.pi, 50.0
#: What a robot file whose limits load may still hold of degrees (a joint or a field left in
#: them), each warned of as the file is read (:class:`RobotFileWarning`), not refused: no bound
#: here is a law of arms, and a robot file written for a test may cross one on purpose.
#:
#: * A joint that its ``max_acceleration`` takes from rest to its full speed in less than 50 ms.
#:   Arm makers who publish accelerations give 0.13 s and more (Franka's wrist joints, 2.61 rad/s
#:   at 20 rad/s^2; the Comau file's choices 0.25 s); an acceleration in deg/s^2 beside a speed in
#:   rad/s gives 57 times less (4.4 ms for the Comau's, 4.6 ms for a UR's 3.14 rad/s at 12 rad/s^2).
#:   Its ``max_velocity`` is blamed instead where that is more than :data:`MAX_SPEED_RATIO` times
#:   below every other joint's (``1e-9``).
#: * A joint more than 5 times as fast as every other: an arm's fastest joint is a wrist joint a
#:   little faster than the next (the Comau's 9.6 rad/s against 7.85); one joint in deg/s among
#:   joints in rad/s is 57 times its real speed.
#: * A joint whose ``max_velocity`` is more than :data:`MAX_UNREACHABLE` times what its
#:   ``max_acceleration`` can reach within its range (from rest at one end, accelerating over half
#:   of it and braking over the other, sqrt(acceleration x range)): a speed in deg/s on a slow arm
#:   (a tester's 18 "rad/s" beside 6 rad/s^2 over 2.8 rad, at most 4.1) passed the other checks,
#:   and ``rlff sim reach`` threw the ball 23 m from a 1.2 m arm. The Comau's joints could reach
#:   1.7-6 times their speed limits so.
#: * A joint that bends the arm (``joint_2``, ``joint_3``, ``joint_5`` of rlff's convention) with a
#:   limit beyond a turn either way (the most any arm has, a UR's ±2π); a roll joint may turn many
#:   (the Comau's joint 6 ±7.5 turns), so those and joints with names of their own are not looked at.
MIN_TIME_TO_SPEED, MAX_SPEED_RATIO, MAX_BEND, MAX_UNREACHABLE = 0.05, 5.0, 2 * math.pi + 1e-3, 2.0


class RobotFileWarning(UserWarning):
    """A robot file that loads but holds a limit no arm has (:data:`MIN_TIME_TO_SPEED`,
    :data:`MAX_SPEED_RATIO`, :data:`MAX_BEND`), or a URDF joint without position limits that rlff
    limits (:func:`rlff.robot.urdf.continuous_warning`): one line naming the file, the joint and
    the value."""


#: A joint name rlff reads as the controller's k-th joint (``joint_2`` is the shoulder).
_NUMBERED = re.compile(r"joint_(\d+)")
#: The joints a throw may drive: in rlff's kinematic convention (joints named ``joint_<k>``) these
#: swing the arm in its vertical plane, where the simulation, the reach and the learning loop
#: throw; ``joint_1`` turns that plane (to the basket's bearing), ``joint_4`` and ``joint_6`` roll
#: the forearm and the flange about their own axes.
THROWING_JOINTS = ("joint_2", "joint_3", "joint_5")
#: Link lengths that must be positive, and distances that cannot be negative (the offsets
#: ``shoulder_forward`` and ``elbow_offset`` are signed: see the robot file's convention).
_POSITIVE_LENGTHS, _DISTANCES = ("upper_arm", "forearm"), ("shoulder_height", "flange")
#: The longest ``[geometry]`` length (m), either sign, rlff takes, so that a file in millimetres
#: (``upper_arm = 425``) is refused, not read as an arm that throws 845 km: the largest industrial
#: arms reach about 4.7 m from the shoulder to the flange (FANUC's M-2000iA/900L, 4.68 m), so no
#: single link or offset of an arm is longer than 5 m (the Comau's longest is 0.647 m).
MAX_LENGTH = 5.0


@dataclass(frozen=True)
class Joint:
    """One revolute joint and its limits.

    Parameters
    ----------
    name : str
    lower, upper : float
        Position limits (rad), ``lower < upper``.
    max_velocity : float
        Speed limit (rad/s), either direction.
    max_acceleration : float, optional
        Acceleration limit (rad/s^2), either direction. A robot file must state it; a joint built
        in code without it can be checked for positions and speeds but not planned
        (:mod:`rlff.trajectory.planner` and :mod:`rlff.trajectory.check` refuse it by name).
    max_jerk : float, optional
        Jerk limit (rad/s^3), either direction; as ``max_acceleration``.
    """

    name: str
    lower: float
    upper: float
    max_velocity: float
    max_acceleration: float | None = None
    max_jerk: float | None = None

    def __post_init__(self) -> None:
        if not self.lower < self.upper:
            raise InputError(f"joint {self.name}: lower limit {self.lower} is not below upper {self.upper}")
        for field_name in ("max_velocity", "max_acceleration", "max_jerk"):
            value = getattr(self, field_name)
            if value is None and field_name != "max_velocity":
                continue
            if not (np.isfinite(value) and value > 0):
                raise InputError(f"joint {self.name}: {field_name} must be positive and finite, got {value}")


def joint_names(joints: Sequence[Joint]) -> tuple[str, ...]:
    """The names of ``joints``, in order."""
    return tuple(joint.name for joint in joints)


def find_joint(joints: Sequence[Joint], name: str, owner: str = "") -> Joint:
    """The joint called ``name`` among ``joints``.

    Raises
    ------
    InputError
        If there is none; the message lists the joints, after ``owner`` (e.g. ``" on robot X"``).
    """
    for joint in joints:
        if joint.name == name:
            return joint
    raise InputError(f"unknown joint {name!r}{owner} (joints: {', '.join(joint_names(joints))})")


@dataclass(frozen=True)
class Geometry:
    """Link lengths (m) of a 6-axis arm with an elbow offset; see the robot file for the frames.

    ``shoulder_height``/``shoulder_forward``: joint 2 axis above the base and forward of joint 1;
    ``upper_arm``: joint 2 to joint 3; ``elbow_offset``: joint 3 axis to the forearm axis;
    ``forearm``: along the forearm to the wrist centre; ``flange``: wrist centre to flange face.
    """

    shoulder_height: float
    shoulder_forward: float
    upper_arm: float
    elbow_offset: float
    forearm: float
    flange: float

    def __post_init__(self) -> None:
        for key in _GEOMETRY_FIELDS:
            value = getattr(self, key)
            if not math.isfinite(value):
                raise InputError(f"[geometry] {key} must be a finite number (m), got {value:g}")
            if key in _POSITIVE_LENGTHS + _DISTANCES and (value < 0 or (key in _POSITIVE_LENGTHS and value == 0)):
                bound = "positive" if key in _POSITIVE_LENGTHS else "zero or more"
                raise InputError(f"[geometry] {key} is a length and must be {bound} (m), got {value:g}")
            if abs(value) > MAX_LENGTH:
                raise InputError(f"[geometry] {key} {value:g} m is longer than any arm's link ({MAX_LENGTH:g} m; the "
                                 "largest industrial arms reach about 4.7 m); rlff reads metres: is this file in "
                                 "millimetres?")


#: A ROS graph name both ROS 1 and ROS 2 take as it is: absolute, then segments of letters,
#: digits and '_', none starting with a digit (ROS 2 refuses that; ROS 1 resolves a relative
#: name in each node's namespace, and ROS 2 has its own rules for '~' and '{}').
_GRAPH_NAME = re.compile(r"(/[A-Za-z_][A-Za-z0-9_]*)+")
#: Longest name taken: ROS 2 refuses a topic of more than 247 characters, and an action's own
#: topics and services add up to 20 (``/_action/cancel_goal``).
MAX_ROS_NAME = 200
#: An example of a good value of each ``[ros]`` key, for the messages.
_ROS_EXAMPLES = {"action": "/scaled_joint_trajectory_controller/follow_joint_trajectory",
                 "joint_states": "/arm/joint_states", "trajectory_topic": "/arm/joint_trajectory"}


def graph_name_fault(value: Any) -> str | None:
    """What keeps ``value`` from being a name of :data:`_GRAPH_NAME`, in words; None if nothing."""
    if not isinstance(value, str):
        return "is not a string"
    if not value:
        return "is empty"
    if _GRAPH_NAME.fullmatch(value) and len(value) <= MAX_ROS_NAME:
        return None
    if not value.startswith("/"):
        return "is relative: each node would resolve it in its own namespace"
    if value.endswith("/"):
        return "ends with '/'"
    if "//" in value:
        return "has an empty segment ('//')"
    if len(value) > MAX_ROS_NAME:
        return f"is longer than {MAX_ROS_NAME} characters"
    for segment in value[1:].split("/"):
        if segment[0].isdigit():
            return f"has a segment starting with a digit ({segment!r})"
    bad = next(char for char in value if not (char.isascii() and (char.isalnum() or char in "/_")))
    return f"has the character {bad!r}"


@dataclass(frozen=True)
class RosNames:
    """Where the arm's controller is on the ROS graph (ROS 1 and ROS 2): the robot file's ``[ros]``
    table, each name rlff's default unless the file gives it.

    Parameters
    ----------
    action : str
        The FollowJointTrajectory action of the arm's controller (``rlff robot send``, ``rlff learn
        --executor ros1|ros2``; ``rlff robot serve`` serves it). A UR arm under ros_control:
        ``/scaled_joint_trajectory_controller/follow_joint_trajectory``.
    joint_states : str
        The sensor_msgs/JointState topic the arm's driver publishes its state on (read before every
        goal; ``robot serve`` publishes it).
    trajectory_topic : str
        The trajectory_msgs/JointTrajectory topic of the original driver's topic mode: ``robot serve``
        listens on it, ``robot send --topic-mode`` publishes on it, and exported bags carry the
        trajectory on it.
    joints : JointMap
        The controller's names, zeros and signs of the robot's joints (the ``[ros.joints]`` tables;
        :mod:`rlff.robot.joint_map`): goals, joint states, feedback and bags go through it. Empty:
        the controller's joints are the robot file's.
    stated : frozenset of str
        The keys the robot file gives; for messages that say where a name comes from
        (:meth:`Robot.ros_origin`).

    Each name is absolute: '/' then segments of letters, digits and '_', none starting with a digit,
    no longer than :data:`MAX_ROS_NAME` (what ROS 1 and ROS 2 both take as it is); another is an
    :class:`InputError` naming the key and showing a good value.
    """

    action: str = "/comau_controller/follow_joint_trajectory"
    joint_states: str = "/joint_states"
    trajectory_topic: str = "/comau/joint_trajectory"
    joints: JointMap = field(default_factory=JointMap)
    stated: frozenset[str] = field(default=frozenset(), compare=False, repr=False)

    def __post_init__(self) -> None:
        for key in _ROS_EXAMPLES:
            value = getattr(self, key)
            fault = graph_name_fault(value)
            if fault is not None:
                raise InputError(f"[ros] {key} {value!r} {fault}; give an absolute ROS name, '/' and segments of "
                                 f"letters, digits and '_' (none starting with a digit), e.g. {_ROS_EXAMPLES[key]!r}")
        object.__setattr__(self, "stated", frozenset(self.stated))


@dataclass(frozen=True)
class Robot:
    """A robot arm: its joints in controller order, geometry and extra tables of its file.

    The joints' order is the controller's (the Comau program's slots, the URDF's and the MuJoCo
    scene's chain): a joint named ``joint_<k>`` must be the k-th, since rlff's geometry, reach
    and mappings take ``joint_2`` for the shoulder; joints named otherwise keep their order.

    ``throwing`` holds the default one-joint human-to-robot mapping (read by
    :meth:`rlff.robot.mapping.RobotMapping.for_robot`), ``whole_arm`` the mapping of several
    human joints to several robot joints (:meth:`rlff.robot.mapping.ArmMapping.for_robot`),
    ``comau_program`` the layout of the Comau text program; each may be empty. ``ros`` holds the
    names of the arm's controller on the ROS graph (:class:`RosNames`). ``source`` names the file it
    came from, ``warnings`` what in it is implausible (:func:`implausible_limits`), or limited by
    rlff (:func:`rlff.robot.urdf.continuous_warning`): one line each, each also issued as a
    :class:`RobotFileWarning` by :func:`load_robot`.
    """

    name: str
    joints: tuple[Joint, ...]
    geometry: Geometry | None = None
    throwing: Mapping[str, Any] = field(default_factory=dict)
    comau_program: Mapping[str, Any] = field(default_factory=dict)
    source: str = "<memory>"
    whole_arm: Mapping[str, Any] = field(default_factory=dict)
    ros: RosNames = field(default_factory=RosNames)
    warnings: tuple[str, ...] = field(default=(), compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "warnings", tuple(self.warnings))
        names = [joint.name for joint in self.joints]
        if not names or len(set(names)) != len(names):
            raise InputError(f"{self.source}: joint names must be unique and non-empty, got {names}")
        for position, name in enumerate(names, start=1):
            numbered = _NUMBERED.fullmatch(name)
            if numbered and int(numbered[1]) != position:
                raise InputError(f"{self.source}: {name} is listed as joint {position}; rlff takes joint_<k> to be "
                                 "the controller's k-th joint (joint_2 the shoulder): list the [[joints]] tables "
                                 "in controller order, joint_1 first")
        object.__setattr__(self, "throwing", MappingProxyType(dict(self.throwing)))
        object.__setattr__(self, "comau_program", MappingProxyType(dict(self.comau_program)))
        object.__setattr__(self, "whole_arm", MappingProxyType(dict(self.whole_arm)))
        try:
            self.ros.joints.check_joints(names)
        except InputError as exc:  # the map's own check names no file
            raise InputError(f"{self.source}: {exc}") from None

    @property
    def joint_names(self) -> tuple[str, ...]:
        return joint_names(self.joints)

    def ros_origin(self, key: str) -> str:
        """Where the ROS name ``key`` of :attr:`ros` comes from, for a message: ``the [ros] action
        of mine.toml``, or ``rlff's default; mine.toml has no [ros] action``."""
        if key in self.ros.stated or getattr(self.ros, key) != getattr(RosNames, key):  # given in code
            return f"the [ros] {key} of {self.source}"
        return f"rlff's default; {self.source} has no [ros] {key}"

    def joint(self, name: str) -> Joint:
        """The joint called ``name``; :class:`InputError` listing the joints if unknown."""
        return find_joint(self.joints, name, f" on robot {self.name}")

    def index(self, name: str) -> int:
        """Position of joint ``name`` in :attr:`joints`."""
        return self.joint_names.index(self.joint(name).name)

    def limits(self, names: Sequence[str] | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Arrays (J,) of lower and upper position limits (rad) and speed limits (rad/s)."""
        joints = self.joints if names is None else [self.joint(name) for name in names]
        return (np.array([j.lower for j in joints]), np.array([j.upper for j in joints]),
                np.array([j.max_velocity for j in joints]))


def require_throwing_joint(name: str, where: str) -> None:
    """:class:`InputError` naming ``where`` (the file and its table) if ``name``, a joint of rlff's
    convention (``joint_<k>``), is not among :data:`THROWING_JOINTS`; a joint with a name of its own
    is not held to it. Checked when the robot file is read and by the mappings built in code."""
    if _NUMBERED.fullmatch(name) and name not in THROWING_JOINTS:
        raise InputError(f"{where}: {name} does not throw in the arm's vertical plane: a throw drives "
                         f"{', '.join(THROWING_JOINTS[:-1])} or {THROWING_JOINTS[-1]} (joint_1 turns the arm to the "
                         "basket's bearing, joint_4 and joint_6 roll the forearm and the flange)")


def require_start_pose(joints: Sequence[Joint], pose: Mapping[str, float], where: str) -> None:
    """:class:`InputError` naming ``where`` (the file and its table) and the first joint of
    ``pose`` (joint name to rad) outside its limits: the one check of a start pose, made when the
    robot file is read (:func:`parse_robot`) and by the mappings built in code."""
    for name, value in pose.items():
        joint = find_joint(joints, name)
        if not joint.lower <= value <= joint.upper:
            raise InputError(f"{where}: {name} {value:g} rad is outside its limits [{joint.lower:g}, "
                             f"{joint.upper:g}] rad")


def number_field(table: Mapping[str, Any], key: str, where: str) -> float:
    """``table[key]`` as a finite float; :class:`InputError` naming ``where`` and ``key`` if not."""
    if key not in table:
        raise InputError(f"{where}: missing field {key!r}")
    value = table[key]
    if isinstance(value, bool) or not isinstance(value, int | float) or not np.isfinite(value):
        raise InputError(f"{where}: field {key!r} must be a finite number, got {value!r}")
    return float(value)


def _require_known(table: Mapping[str, Any], kind: str, where: str) -> None:
    """:class:`InputError` naming the first key of ``table`` that a ``kind`` table (a key of
    :data:`_FIELDS`) does not hold, with the nearest known key when one is close."""
    known = _FIELDS[kind]
    for key in table:
        if key not in known:
            raise InputError(f"{where}: unknown field {key!r}" + nearest_hint(str(key), known, f"known: {', '.join(known)}"))


def _require_known_keys(document: Mapping[str, Any], source: str, top: Sequence[str] = ()) -> None:
    """Refuse a key no table of a robot file holds (see :data:`_FIELDS`; ``top``: further keys of
    the file's top level, such as ``urdf`` before the URDF is merged). Run before any value is read,
    so that a misspelt key is named as such, not as the field it misses (``max_velocty``). Tables
    that are not tables are left to :func:`parse_robot`, which says so."""
    _require_known({key: value for key, value in document.items() if key not in top}, "", source)
    tables = document.get("joints")
    for number, table in enumerate(tables if isinstance(tables, list) else [], start=1):
        if isinstance(table, Mapping):
            named = f" ({table['name']})" if isinstance(table.get("name"), str) else ""
            _require_known(table, "[[joints]]", f"{source}: joint {number}{named}")
    for key in _TABLES:
        if isinstance(document.get(key), Mapping):
            _require_known(document[key], f"[{key}]", f"{source}: [{key}]")
    for table in ("whole_arm", "ros"):
        parent = document.get(table)
        entries = parent.get("joints") if isinstance(parent, Mapping) else None
        for joint, entry in entries.items() if isinstance(entries, Mapping) else ():
            if isinstance(entry, Mapping):
                _require_known(entry, f"[{table}.joints.<joint>]", f"{source}: [{table}.joints.{joint}]")


def _require_known_joints(document: Mapping[str, Any], joints: Sequence[str], source: str) -> None:
    """Refuse a start pose of a joint the robot does not have."""
    for key in ("throwing", "whole_arm"):
        pose = document.get(key, {}).get("start_pose", {})
        unknown = [name for name in pose if name not in joints] if isinstance(pose, Mapping) else []
        if unknown:
            raise InputError(f"{source}: [{key}.start_pose] names {unknown[0]!r}, not a joint of the robot "
                             f"(joints: {', '.join(joints)})")


def _require_radians(tables: Any, source: str) -> None:
    """Refuse a ``[[joints]]`` table whose position limit is beyond :data:`MAX_POSITION` or whose
    speed limit is beyond :data:`MAX_VELOCITY`: a file in degrees. Fields that are missing or not
    numbers are left to :func:`parse_robot`."""
    for number, table in enumerate(tables if isinstance(tables, list) else [], start=1):
        if not isinstance(table, Mapping):
            continue
        where = f"{source}: joint {number} ({table.get('name')})"
        for key, bound, unit, what in (("lower", MAX_POSITION, "rad", "more than eight turns"),
                                       ("upper", MAX_POSITION, "rad", "more than eight turns"),
                                       ("max_velocity", MAX_VELOCITY, "rad/s", "faster than any arm's joint")):
            value = table.get(key)
            # a value that is not a finite number (inf, nan) is named as such by parse_robot
            if isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value) \
                    and abs(value) > bound:
                raise InputError(f"{where}: {key} {value:g} {unit} is {what} ({bound:.4g} {unit}); rlff reads "
                                 "radians (rad, rad/s, rad/s^2, rad/s^3): is this file in degrees?")


def implausible_limits(joints: Sequence[Joint], source: str) -> tuple[str, ...]:
    """What in ``joints`` no arm has, as the warnings of :class:`Robot`: one line per kind (see
    :data:`MIN_TIME_TO_SPEED`), naming ``source``, the first joint at fault and the values, and
    how many other joints are at fault too."""
    def where(joint: Joint) -> str:
        return f"{source}: joint {joints.index(joint) + 1} ({joint.name})"

    def more(count: int) -> str:
        return f" (and {count - 1} more joint{'s' if count > 2 else ''})" if count > 1 else ""

    found = []
    quick = [joint for joint in joints
             if joint.max_acceleration and joint.max_velocity / joint.max_acceleration < MIN_TIME_TO_SPEED]
    if quick:
        joint = quick[0]
        in_ms = f"{1e3 * joint.max_velocity / joint.max_acceleration:.2g} ms"
        slowest = min((other for other in joints if other is not joint), key=lambda other: other.max_velocity,
                      default=None)
        if slowest is not None and joint.max_velocity * MAX_SPEED_RATIO < slowest.max_velocity:
            # the speed is the odd one (a max_velocity of 1e-9 blamed the acceleration beside it)
            found.append(f"{where(joint)}: max_velocity {joint.max_velocity:g} rad/s is "
                         f"{slowest.max_velocity / joint.max_velocity:.3g} times below that of the next slowest joint, "
                         f"{slowest.name} ({slowest.max_velocity:g} rad/s), and its max_acceleration "
                         f"{joint.max_acceleration:g} rad/s^2 reaches it in {in_ms}{more(len(quick))}; an arm's joints "
                         "differ by a few times at most: is max_velocity right? rlff reads rad/s")
        else:
            found.append(f"{where(joint)}: max_acceleration {joint.max_acceleration:g} rad/s^2 takes it from rest to its "
                         f"full speed {joint.max_velocity:g} rad/s in {in_ms}{more(len(quick))}; published arm limits take "
                         "0.1 s or more (Franka's quickest joints 0.13 s): is max_acceleration in degrees? rlff reads "
                         "rad/s^2")
    by_speed = sorted(joints, key=lambda joint: joint.max_velocity, reverse=True)
    fastest_apart = len(by_speed) > 1 and by_speed[0].max_velocity > MAX_SPEED_RATIO * by_speed[1].max_velocity
    if fastest_apart:
        fast, next_ = by_speed[:2]
        found.append(f"{where(fast)}: max_velocity {fast.max_velocity:g} rad/s is {fast.max_velocity / next_.max_velocity:.3g}"
                     f" times that of the next fastest joint, {next_.name} ({next_.max_velocity:g} rad/s); an arm's "
                     "joints differ by a few times at most: is it in degrees per second? rlff reads rad/s")
    # a joint already blamed for its speed (in deg/s among joints in rad/s) is said once
    unreachable = [joint for joint in joints if joint.max_acceleration
                   and joint.max_velocity > MAX_UNREACHABLE * within_range(joint)
                   and not (fastest_apart and joint is by_speed[0])]
    if unreachable:
        joint = unreachable[0]
        found.append(f"{where(joint)}: max_velocity {joint.max_velocity:g} rad/s is {joint.max_velocity / within_range(joint):.3g}"
                     f" times the most its max_acceleration {joint.max_acceleration:g} rad/s^2 reaches within its "
                     f"{joint.upper - joint.lower:.3g} rad range ({within_range(joint):.3g} rad/s){more(len(unreachable))}: "
                     "is it in degrees per second? rlff reads rad/s")
    bent = [joint for joint in joints if joint.name in THROWING_JOINTS and max(-joint.lower, joint.upper) > MAX_BEND]
    if bent:
        joint = bent[0]
        turns = max(-joint.lower, joint.upper) / (2 * math.pi)
        found.append(f"{where(joint)}: limits {joint.lower:g} to {joint.upper:g} rad reach {turns:.2g} turns from 0"
                     f"{more(len(bent))}; {joint.name} bends the arm, and no arm bends a joint more than a turn either "
                     "way (a UR's 2 pi is the most): is it in degrees? rlff reads rad")
    return tuple(found)


def within_range(joint: Joint) -> float:
    """The fastest (rad/s) ``joint`` can move and still stop within its range: from rest at one
    limit, at its ``max_acceleration`` over half the range and braking over the other half."""
    return math.sqrt(joint.max_acceleration * (joint.upper - joint.lower))


#: The joints of the chain ``[geometry]`` describes, in order, in rlff's kinematic convention
#: (the comments of ``rlff/robots/comau_smart5_six.toml``).
CHAIN_JOINTS = tuple(f"joint_{k}" for k in range(1, 7))


def require_chain_names(names: Sequence[str], source: str) -> None:
    """:class:`InputError` unless ``names`` are :data:`CHAIN_JOINTS`: ``[geometry]`` places
    rlff's chain, whose joints and zeros are its own (joint 2 at 0 = upper arm vertical, ...).
    A file of a controller's own names (a UR's ``shoulder_lift_joint``, 0 = upper arm
    horizontal) had its angles placed on that chain by position, and the floor check and the
    simulation judged another pose than the arm's. Such a controller is driven from a file of
    rlff's joints whose ``[ros.joints]`` give the controller's names, zeros and signs
    (:class:`rlff.robot.joint_map.JointMap`)."""
    if sorted(names) == sorted(CHAIN_JOINTS):  # their order is the controller order's check (Robot)
        return
    raise InputError(
        f"{source}: [geometry] describes rlff's chain, joints joint_1 to joint_6 with rlff's zeros and signs (joint_2 "
        "at 0 = upper arm vertical, positive tilts it forward; the comments of the built-in comau_smart5_six.toml), "
        f"and this file's joints are {', '.join(names)}: name them joint_1 to joint_6 with their angles in that "
        "convention, and give the controller's names, zeros and signs in [ros.joints] tables (docs/robot.md), or "
        "leave [geometry] out (then no floor check and no simulation)")


def parse_robot(document: Mapping[str, Any], source: str) -> Robot:
    """Build a :class:`Robot` from a parsed robot file; errors name ``source`` and the field."""
    _require_known_keys(document, source)
    name = document.get("name")
    if not isinstance(name, str) or not name:
        raise InputError(f"{source}: missing field 'name'")
    tables = document.get("joints")
    if not isinstance(tables, list) or not tables:
        raise InputError(f"{source}: missing [[joints]] tables")
    joints = []
    for number, table in enumerate(tables, start=1):
        if not isinstance(table, Mapping):
            raise InputError(f"{source}: joint {number} must be a [[joints]] table, got {table!r}")
        joint_name = table.get("name")
        where = f"{source}: joint {number}" + (f" ({joint_name})" if joint_name else "")
        if not isinstance(joint_name, str) or not joint_name:
            raise InputError(f"{where}: missing field 'name'")
        if joint_name in joint_names(joints):
            raise InputError(f"{where}: joint {joint_names(joints).index(joint_name) + 1} has that name too; "
                             "each joint needs its own name")
        joints.append(_checked_joint(where, name=joint_name,
                                     **{key: number_field(table, key, where) for key in LIMIT_FIELDS}))
    for key in _TABLES:
        if key in document and not isinstance(document[key], Mapping):
            raise InputError(f"{source}: [{key}] must be a table, got {document[key]!r}")
    _require_known_joints(document, joint_names(joints), source)
    driven = document.get("throwing", {}).get("joint")
    if isinstance(driven, str) and driven in joint_names(joints):  # an unknown one is named by the mapping
        require_throwing_joint(driven, f"{source}: [throwing]")
    entries = document.get("whole_arm", {}).get("joints")
    for entry in entries if isinstance(entries, Mapping) else ():
        if entry in joint_names(joints):
            require_throwing_joint(entry, f"{source}: [whole_arm.joints.{entry}]")
    for key in ("throwing", "whole_arm"):  # every command refuses such a file alike, whether it maps a throw or not
        pose = document.get(key, {}).get("start_pose")
        if isinstance(pose, Mapping):
            where = f"{source}: [{key}.start_pose]"
            require_start_pose(joints, {joint: number_field(pose, joint, where) for joint in pose}, where)
    geometry = None
    if "geometry" in document:
        require_chain_names(joint_names(joints), source)
        values = {key: number_field(document["geometry"], key, f"{source}: [geometry]") for key in _GEOMETRY_FIELDS}
        try:
            geometry = Geometry(**values)
        except InputError as exc:  # the geometry's own checks name no file
            raise InputError(f"{source}: {exc}") from None
    names = dict(document.get("ros", {}))
    joint_map = _joint_map(names.pop("joints"), source) if "joints" in names else JointMap()
    try:
        ros = RosNames(**names, joints=joint_map, stated=frozenset(document.get("ros", {})))
    except InputError as exc:  # the names' own checks name no file
        raise InputError(f"{source}: {exc}") from None
    return Robot(name, tuple(joints), geometry, document.get("throwing", {}),
                 document.get("comau_program", {}), source, document.get("whole_arm", {}), ros,
                 implausible_limits(joints, source) + implausible_offsets(joint_map, source)
                 + _driven_in_start_pose(document, source))


def _checked_joint(where: str, **fields: Any) -> Joint:
    """``Joint(**fields)``, its own checks (lower < upper, positive limits), which name no file,
    said of ``where`` (the file and the joint)."""
    try:
        return Joint(**fields)
    except InputError as exc:
        own = f"joint {fields['name']}: "
        raise InputError(f"{where}: {str(exc).removeprefix(own)}") from None


def _driven_in_start_pose(document: Mapping[str, Any], source: str) -> tuple[str, ...]:
    """A warning for a ``[throwing.start_pose]`` that names the throwing joint, whose start is the
    throw's own first angle: the entry is not used (a tester's ``joint_2 = 0.3`` went unseen).
    (``[whole_arm.start_pose]`` may name driven joints: a throw of fewer joints holds them there.)"""
    joint, pose = document.get("throwing", {}).get("joint"), document.get("throwing", {}).get("start_pose")
    if not (isinstance(pose, Mapping) and isinstance(joint, str) and joint in pose):
        return ()
    return (f"{source}: [throwing.start_pose] gives {joint}, the throwing joint: its start is the throw's first "
            f"angle, and {joint} = {pose[joint]!r} is not used",)


def _joint_map(tables: Any, source: str) -> JointMap:
    """The :class:`JointMap` of a robot file's ``[ros.joints]`` tables; :class:`InputError` naming
    the file and the table at fault (an offset beyond :data:`MAX_POSITION` is one in degrees). Its
    joints are checked against the file's by :class:`Robot`."""
    if not isinstance(tables, Mapping):
        raise InputError(f"{source}: [ros] joints must be [ros.joints.<joint>] tables (name, offset, sign), "
                         f"got {tables!r}")
    entries = {}
    for joint, table in tables.items():
        where = f"{source}: [ros.joints.{joint}]"
        if not isinstance(table, Mapping):
            raise InputError(f"{where} must be a table (name, offset, sign), got {table!r}")
        try:
            entries[joint] = ControllerJoint(**({"name": joint} | dict(table)))
        except InputError as exc:  # the entry's own checks name no file
            raise InputError(f"{where}: {exc}") from None
        offset = entries[joint].offset
        if abs(offset) > MAX_POSITION:
            raise InputError(f"{where}: offset {offset:g} rad is more than eight turns ({MAX_POSITION:.4g} rad); rlff "
                             "reads radians: is it in degrees?")
    return JointMap(entries)


def implausible_offsets(joint_map: JointMap, source: str) -> tuple[str, ...]:
    """A warning (one line, as :func:`implausible_limits`') for a ``[ros.joints]`` offset beyond a
    turn either way (:data:`MAX_BEND`): a controller's zero is within a turn of rlff's, so such an
    offset is likely in degrees (45 for a quarter turn's 0.785)."""
    far = [(joint, entry.offset) for joint, entry in joint_map.joints.items() if abs(entry.offset) > MAX_BEND]
    if not far:
        return ()
    joint, offset = far[0]
    more = f" (and {len(far) - 1} more)" if len(far) > 1 else ""
    return (f"{source}: [ros.joints.{joint}]: offset {offset:g} rad is {abs(offset) / (2 * math.pi):.2g} turns{more}; "
            "a controller's zero is within a turn of rlff's: is it in degrees? rlff reads rad",)


def available_robots() -> list[str]:
    """Names of the robot files that ship with rlff."""
    folder = resources.files("rlff") / "robots"
    return sorted(entry.name[:-5] for entry in folder.iterdir() if entry.name.endswith(".toml"))


def load_robot(path_or_name: str | Path = DEFAULT_ROBOT) -> Robot:
    """Read a robot file, or a built-in robot by name.

    Parameters
    ----------
    path_or_name : str or Path
        A TOML file, a URDF file (joints with position and speed limits only), or the name of a
        built-in robot (see :func:`available_robots`). A TOML file may take its joints from a
        URDF: its field ``urdf`` names the file (relative to the TOML's folder), its
        ``[[joints]]`` tables add to the URDF joints of the same name what a URDF cannot state
        (``max_acceleration``, ``max_jerk``; :func:`rlff.robot.urdf.merge_urdf`).

    Raises
    ------
    InputError
        Unknown robot, unreadable file, a missing or invalid field (named in the message), limits
        written in degrees (:data:`MAX_POSITION`, :data:`MAX_VELOCITY`), or ``joint_<k>`` not the
        k-th joint (:class:`Robot`).
    """
    text_name = str(path_or_name)
    is_file = isinstance(path_or_name, Path) or text_name.endswith((".toml", ".urdf")) or "/" in text_name
    if is_file and text_name.endswith(".urdf"):
        from rlff.robot.urdf import continuous_warning, urdf_joints

        # a URDF states no acceleration or jerk limits: such a robot is checked, not planned for
        name, tables, continuous = urdf_joints(path_or_name)
        joints = tuple(_checked_joint(f"{path_or_name}: joint {number} ({table['name']})", **table)
                       for number, table in enumerate(tables, start=1))
        return _warned(Robot(name, joints, source=str(path_or_name),
                             warnings=continuous_warning(path_or_name, continuous, "give lower and upper in a robot "
                                                         "file's [[joints]] tables beside urdf = ...")))
    if is_file:
        path = Path(path_or_name)
        try:  # utf-8-sig: a file saved by Notepad starts with a byte-order mark, which TOML does not allow
            text = path.read_text(encoding="utf-8-sig")
        except OSError as exc:
            raise InputError(f"cannot read robot file {path}: {exc.strerror}") from None
        except UnicodeDecodeError:
            raise InputError(f"cannot read robot file {path}: not a UTF-8 text file") from None
        source = str(path)
    else:
        if text_name not in available_robots():
            raise InputError(f"unknown robot {text_name!r} (built in: {', '.join(available_robots())}; or give a .toml file)")
        text = (resources.files("rlff") / "robots" / f"{text_name}.toml").read_text(encoding="utf-8")
        source = f"built-in robot {text_name}"
    try:
        document = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{source}: not valid TOML: {exc}") from None
    _require_known_keys(document, source, top=("urdf",) if is_file else ())  # a misspelt key first, by name
    # the values the file writes; a URDF's own are in SI by its specification, metres for a prismatic joint
    _require_radians(document.get("joints"), source)
    continuous: tuple[str, ...] = ()
    if is_file and "urdf" in document:
        from rlff.robot.urdf import merge_urdf

        document, continuous = merge_urdf(document, Path(path_or_name).parent, source)
    robot = parse_robot(document, source)
    return _warned(replace(robot, warnings=continuous + robot.warnings) if continuous else robot)


def _warned(robot: Robot) -> Robot:
    """``robot``, once each of its warnings is issued as a :class:`RobotFileWarning`."""
    for text in robot.warnings:
        warnings.warn(text, RobotFileWarning, stacklevel=3)
    return robot
