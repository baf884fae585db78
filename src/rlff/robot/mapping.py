"""Human to robot (thesis 4.4): the learned human joints drive robot joints.

:class:`RobotMapping` (the robot file's ``[throwing]`` table): the learned human angle drives
one robot joint. The driven joint's position is ``angle_offset + angle_scale * angle`` and its
velocity ``velocity_scale * velocity``; every other joint stays at its start pose. The robot's
timing follows from the mapped path (t = integral of dq / qdot), i.e. the human timing stretched
by ``angle_scale / velocity_scale``.

:class:`ArmMapping` (the ``[whole_arm]`` table): several human joints (elbow ``angle``,
``shoulder``, ``wrist``) drive several robot joints on one time base: each robot position is
``offset + scale * human position``, each robot velocity ``scale * human velocity / time_scale``,
the robot's time the human's times ``time_scale``.

Both offer the path protocol the learning loop and the CLI use (:meth:`ArmMapping.path_to_robot`,
``path_from_robot``, ``max_human_speeds``, ``driven_joints``, ``human_columns``); the basket's
bearing turns the ``bearing_joint`` (joint 1) to face it. A point beyond a position or velocity
limit is an error unless clipping is asked for, and then every changed value is reported.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np

from rlff.dataset import JOINT_COLUMNS as HUMAN_JOINT_COLUMNS
from rlff.dataset import velocity_column
from rlff.errors import InputError
from rlff.limits import apart, as_names
from rlff.robot.description import Robot, number_field, require_start_pose, require_throwing_joint
from rlff.timing import time_along_path
from rlff.trajectory.joint import JointTrajectory
from rlff.trajectory.limits import (
    ClipReport,
    LimitChange,
    clip_to_limits,
    onto_limits,
    require_within_limits,
)

#: A throw in human units (thesis 4.2): columns of equal length T, always ``angle`` (rad, the
#: elbow, the phase) and ``velocity`` (rad/s), plus ``shoulder``/``shoulder_velocity`` and
#: ``wrist``/``wrist_velocity`` for the joints driven, optionally ``time`` (s).
HumanPath = Mapping[str, np.ndarray]


#: The robot joint that turns the arm to the basket's bearing when a robot file does not say.
DEFAULT_BEARING_JOINT = "joint_1"
#: How far inside its nearer limit, as a share of its range, the driven joint of a simulated arm
#: waits for its first goal where its range leaves 0 out (:meth:`RobotMapping.waiting_position`).
WAITING_MARGIN = 0.05


def scaled_speed(path: HumanPath, factor: float) -> dict[str, np.ndarray]:
    """``path`` with every velocity column (``velocity``, ``*_velocity``) times ``factor`` and a
    ``time`` column, if any, divided by it: the same throw along the same positions, sped up or
    slowed down as a whole, every joint by one time scale (its release keeps its direction)."""
    scaled = {name: np.asarray(values, dtype=float) * factor if name == "velocity" or name.endswith("_velocity")
              else values for name, values in path.items()}
    if scaled.get("time") is not None:
        scaled["time"] = np.asarray(scaled["time"], dtype=float) / factor
    return scaled


@dataclass(frozen=True)
class RobotMapping:
    """How a human joint angle (rad) and velocity (rad/s) become a robot joint trajectory.

    Parameters
    ----------
    robot : Robot
    joint : str
        The robot joint the learned angle drives (default ``joint_2``).
    start_pose : mapping of joint name to position (rad)
        Fixed positions of every other joint of ``robot``.
    angle_offset, angle_scale : float
        Driven joint position (rad) = ``angle_offset + angle_scale * angle``.
    velocity_scale : float
        Driven joint velocity (rad/s) = ``velocity_scale * velocity``; same sign as
        ``angle_scale``.
    """

    robot: Robot
    joint: str = "joint_2"
    start_pose: Mapping[str, float] = field(default_factory=dict)
    angle_offset: float = 0.0
    angle_scale: float = 1.0
    velocity_scale: float = 1.0

    def __post_init__(self) -> None:
        self.robot.joint(self.joint)
        require_throwing_joint(self.joint, f"{self.robot.source}: [throwing]")
        for name in self.start_pose:
            self.robot.joint(name)
        missing = [n for n in self.robot.joint_names if n != self.joint and n not in self.start_pose]
        if missing:
            raise InputError(f"{self.robot.source}: [throwing.start_pose] misses joints {missing}")
        if self.angle_scale == 0 or self.velocity_scale == 0:
            raise InputError("angle_scale and velocity_scale must be non-zero")
        if np.sign(self.angle_scale) != np.sign(self.velocity_scale):
            raise InputError("angle_scale and velocity_scale must have the same sign "
                             f"(got {self.angle_scale} and {self.velocity_scale})")
        pose = {name: float(self.start_pose[name]) for name in self.robot.joint_names if name != self.joint}
        require_start_pose(self.robot.joints, pose, f"{self.robot.source}: [throwing.start_pose]")
        object.__setattr__(self, "start_pose", MappingProxyType(pose))

    @classmethod
    def for_robot(cls, robot: Robot, **overrides: object) -> RobotMapping:
        """The mapping of the robot file's ``[throwing]`` table, with keyword ``overrides``."""
        table = dict(robot.throwing)
        if not table:
            also = (": a URDF states the joints and their position and speed limits only, and a robot file "
                    "with urdf = \"...\" adds the rest (docs/robot.md)" if robot.source.endswith(".urdf") else "")
            raise InputError(f"{robot.source} has no [throwing] table, which maps a generated throw to the "
                             f"robot and says how it rests{also}")
        table.update(overrides)
        where = f"{robot.source}: [throwing]"
        if "joint" not in table:
            raise InputError(f"{where}: missing field 'joint'")
        pose = table.get("start_pose")
        if not isinstance(pose, Mapping):
            raise InputError(f"{where}: missing table 'start_pose'")
        with _naming(where, robot.source):
            return cls(robot, str(table["joint"]),
                       {name: number_field(pose, name, f"{where}.start_pose") for name in pose},
                       *(number_field(table, key, where) for key in ("angle_offset", "angle_scale", "velocity_scale")))

    def pose(self, driven: float = 0.0) -> np.ndarray:
        """Positions (J,) (rad) of every joint: the start pose, the driven joint at ``driven``."""
        return np.array([driven if name == self.joint else self.start_pose[name]
                         for name in self.robot.joint_names])

    def waiting_position(self) -> float:
        """Where (rad) the driven joint of a simulated arm waits for its first goal (``rlff robot
        serve``): 0, or where its range leaves 0 out, :data:`WAITING_MARGIN` of the range inside
        the nearer limit (a goal may start there, and a goal's first move is not into the limit)."""
        joint = self.robot.joint(self.joint)
        if joint.lower <= 0.0 <= joint.upper:
            return 0.0
        margin = WAITING_MARGIN * (joint.upper - joint.lower)
        return joint.lower + margin if joint.lower > 0.0 else joint.upper - margin

    @property
    def time_scale(self) -> float:
        """Robot time per human time: ``angle_scale / velocity_scale``."""
        return self.angle_scale / self.velocity_scale

    def to_robot(
        self,
        angle: np.ndarray,
        velocity: np.ndarray,
        time: np.ndarray | None = None,
        clip: bool = False,
    ) -> tuple[JointTrajectory, ClipReport]:
        """The robot trajectory of a human (angle, velocity) path, checked against the limits.

        Parameters
        ----------
        angle : array of shape (T,)
            Human joint angle (rad), strictly monotonic.
        velocity : array of shape (T,)
            Human joint velocity (rad/s), in the direction of motion or zero.
        time : array of shape (T,), optional
            Human time (s); default: from the path, ``time_along_path(angle, velocity)``.
        clip : bool
            Clip positions and velocities into the limits instead of raising; the timing is
            kept (a clipped joint saturates, as a controller would) and a joint beyond a
            position limit is held just inside it, with velocity 0
            (:func:`rlff.trajectory.limits.clip_to_limits`). A velocity against the direction of the path (a
            model's dip below 0 at a stop) is set to 0 first (an error without ``clip``).

        Returns
        -------
        JointTrajectory
            T points of every joint of the robot (controller order), time starting at 0;
            accelerations from the velocities over time.
        ClipReport
            What was clipped (empty unless ``clip`` and a value was beyond a limit).

        Raises
        ------
        InputError
            NaN, a non-monotonic angle, a bad time, or (without ``clip``) a point beyond a limit
            or a velocity against the path.
        """
        angle = np.asarray(angle, dtype=float)
        velocity = np.array(velocity, dtype=float)
        backward = _backward_samples(angle, velocity, clip)
        original_velocity = velocity.copy()
        velocity[backward] = 0.0
        human_time = _human_time(angle, velocity, time)
        robot_time = (human_time - human_time[0]) * self.time_scale
        driven = self.robot.index(self.joint)
        count, joints = angle.size, len(self.robot.joints)
        positions = np.tile(self.pose(), (count, 1))
        velocities = np.zeros((count, joints))
        positions[:, driven] = self.angle_offset + self.angle_scale * angle
        velocities[:, driven] = self.velocity_scale * velocity
        traj = onto_limits(JointTrajectory(self.robot.joint_names, robot_time, positions, velocities,
                                           _accelerations(robot_time, velocities)), self.robot.joints)
        if not clip:
            require_within_limits(traj, self.robot.joints)
            return traj, ClipReport()
        clipped, report = clip_to_limits(traj, self.robot.joints)
        stopped = [LimitChange(int(i), self.joint, "velocity", float(self.velocity_scale * before), 0.0)
                   for i, before in zip(backward, original_velocity[backward], strict=True)]
        report = ClipReport(tuple(sorted(report.changes + tuple(stopped),
                                         key=lambda c: (c.point, c.joint, c.quantity))))
        if not report:
            return traj, report
        return (JointTrajectory(clipped.joint_names, clipped.time, clipped.positions,
                                clipped.velocities, _accelerations(clipped.time, clipped.velocities)),
                report)

    def from_robot(self, traj: JointTrajectory) -> tuple[np.ndarray, np.ndarray]:
        """The human (angle (rad), velocity (rad/s)) of a robot trajectory, each of shape (T,).

        The inverse of :meth:`to_robot` on the driven joint; the learning loop records the
        robot's attempts in the human units of the demonstrations with it.
        """
        column = traj.joint_index(self.joint)
        angle = (traj.positions[:, column] - self.angle_offset) / self.angle_scale
        velocity = traj.velocities[:, column] / self.velocity_scale
        return angle, velocity

    # the path protocol shared with ArmMapping

    @property
    def driven_joints(self) -> tuple[str, ...]:
        """The robot joint the path drives: ``(joint,)``."""
        return (self.joint,)

    @property
    def human_columns(self) -> tuple[str, ...]:
        """The human position column that drives it: ``("angle",)``."""
        return ("angle",)

    @property
    def bearing_joint(self) -> str | None:
        """The joint that turns the arm to the basket's bearing (the ``[whole_arm]`` table's, or
        joint_1), None when the robot has no such joint or it is the driven one."""
        name = str(self.robot.whole_arm.get("bearing_joint", DEFAULT_BEARING_JOINT))
        return name if name in self.robot.joint_names and name != self.joint else None

    def path_to_robot(self, path: HumanPath, *, bearing: float = 0.0,
                      clip: bool = False) -> tuple[JointTrajectory, ClipReport]:
        """:meth:`to_robot` of ``path["angle"]``, ``path["velocity"]`` (and ``path["time"]``),
        with the bearing joint turned ``bearing`` degrees from its start pose (see
        :meth:`ArmMapping.path_to_robot`; at bearing 0 exactly :meth:`to_robot`)."""
        _require_columns(path, ("angle", "velocity"))
        traj, report = self.to_robot(path["angle"], path["velocity"], path.get("time"), clip=clip)
        return _turned(traj, self.robot, self.bearing_joint, bearing), report

    def path_from_robot(self, traj: JointTrajectory) -> dict[str, np.ndarray]:
        """The human columns ``angle``, ``velocity`` and ``time`` (s, from the robot's time) of a
        robot trajectory; arrays of shape (T,)."""
        angle, velocity = self.from_robot(traj)
        return {"angle": angle, "velocity": velocity, "time": traj.time / self.time_scale}

    def max_human_speeds(self) -> dict[str, float]:
        """The driven joint's speed limit in human units: ``{"velocity": rad/s}``."""
        return {"velocity": self.robot.joint(self.joint).max_velocity / abs(self.velocity_scale)}


@dataclass(frozen=True)
class JointMap:
    """One robot joint following one human joint.

    Parameters
    ----------
    joint : str
        The robot joint.
    human : str
        The human position column it follows (``angle``, ``shoulder`` or ``wrist``).
    offset, scale : float
        Robot position (rad) = ``offset + scale * human position`` (rad); ``scale`` non-zero.
    """

    joint: str
    human: str
    offset: float
    scale: float


@dataclass(frozen=True)
class ArmMapping:
    """How a whole-arm human path becomes one coordinated robot joint trajectory.

    Parameters
    ----------
    robot : Robot
    joints : sequence of JointMap
        The driven robot joints, the one following ``angle`` (the elbow, the phase) first.
    start_pose : mapping of joint name to position (rad)
        Positions of the joints not driven (required), and where the arm rests before a throw
        (:meth:`pose`; a driven joint without one rests at 0); the bearing joint's is its
        position at bearing 0.
    time_scale : float
        Robot time per human time (s/s), one for all joints, so they stay coordinated.
    bearing_joint : str or None
        The robot joint turned to the basket's bearing (deg, counter-clockwise from above).
    """

    robot: Robot
    joints: tuple[JointMap, ...]
    start_pose: Mapping[str, float]
    time_scale: float
    bearing_joint: str | None = DEFAULT_BEARING_JOINT

    def __post_init__(self) -> None:
        where = f"{self.robot.source}: [whole_arm]"
        joints = tuple(self.joints)
        if not joints or joints[0].human != "angle":
            raise InputError(f"{where}: the driven joints must include the one following the elbow "
                             f"(human = \"angle\"), first; got {[(j.joint, j.human) for j in joints]}")
        names = [j.joint for j in joints]
        humans = [j.human for j in joints]
        for item in joints:
            self.robot.joint(item.joint)
            require_throwing_joint(item.joint, f"{self.robot.source}: [whole_arm.joints.{item.joint}]")
            if item.human not in HUMAN_JOINT_COLUMNS:
                raise InputError(f"{where}.joints.{item.joint}: human must be one of "
                                 f"{', '.join(HUMAN_JOINT_COLUMNS)}, got {item.human!r}")
            if item.scale == 0 or not np.isfinite(item.scale) or not np.isfinite(item.offset):
                raise InputError(f"{where}.joints.{item.joint}: scale must be non-zero and finite, "
                                 f"offset finite (got {item.scale}, {item.offset})")
        if len(set(names)) != len(names) or len(set(humans)) != len(humans):
            raise InputError(f"{where}: each robot joint and each human joint may be driven once, got "
                             f"{[(j.joint, j.human) for j in joints]}")
        if not (np.isfinite(self.time_scale) and self.time_scale > 0):
            raise InputError(f"{where}: time_scale must be a positive number, got {self.time_scale}")
        if self.bearing_joint is not None:
            self.robot.joint(self.bearing_joint)
            if self.bearing_joint in names:
                raise InputError(f"{where}: bearing_joint {self.bearing_joint} cannot also be driven")
        missing = [n for n in self.robot.joint_names if n not in names and n not in self.start_pose]
        if missing:
            raise InputError(f"{where}.start_pose misses joints {missing}")
        for name in self.start_pose:
            self.robot.joint(name)
        pose = {name: float(value) for name, value in self.start_pose.items()}
        require_start_pose(self.robot.joints, pose, f"{self.robot.source}: [whole_arm.start_pose]")
        object.__setattr__(self, "joints", joints)
        object.__setattr__(self, "start_pose", MappingProxyType(pose))
        object.__setattr__(self, "time_scale", float(self.time_scale))

    @classmethod
    def for_robot(cls, robot: Robot, joints: Sequence[str] = ("joint_2", "joint_3")) -> ArmMapping:
        """The mapping of the robot file's ``[whole_arm]`` table for the robot ``joints`` driven.

        Parameters
        ----------
        robot : Robot
        joints : sequence of str
            A subset of the table's ``[whole_arm.joints]`` that includes the one following the
            elbow (``human = "angle"``); each other joint of the table stays at its start pose.

        Raises
        ------
        InputError
            No ``[whole_arm]`` table, a joint not in it, a missing or bad field (all named).
        """
        table = robot.whole_arm
        where = f"{robot.source}: [whole_arm]"
        if not table:
            raise InputError(f"{robot.source} has no [whole_arm] table: it maps one joint only "
                             "(drop joints, --joints)")
        entries = table.get("joints")
        pose = table.get("start_pose")
        if not isinstance(entries, Mapping) or not entries:
            raise InputError(f"{where}: missing tables [whole_arm.joints.<joint>]")
        if not isinstance(pose, Mapping):
            raise InputError(f"{where}: missing table 'start_pose'")
        asked = [str(name) for name in as_names(joints)]
        twice = sorted({name for name in asked if asked.count(name) > 1})
        if twice:  # it was blamed on the robot file's table ("each robot joint ... may be driven once")
            raise InputError(f"{' and '.join(twice)} given twice in joints {','.join(asked)} (--joints): give "
                             f"each joint once ({','.join(dict.fromkeys(asked))})")
        unknown = [name for name in asked if name not in entries]
        if unknown:
            raise InputError(f"joints {unknown} are not in {where}.joints (mapped: {', '.join(entries)})")
        maps = []
        for name in asked:
            entry = entries[name]
            here = f"{where}.joints.{name}"
            if not isinstance(entry, Mapping) or not isinstance(entry.get("human"), str):
                raise InputError(f"{here}: needs human = \"angle\" | \"shoulder\" | \"wrist\", offset and scale")
            maps.append(JointMap(name, entry["human"], number_field(entry, "offset", here),
                                 number_field(entry, "scale", here)))
        if "angle" not in [m.human for m in maps]:
            elbow = [name for name, entry in entries.items() if isinstance(entry, Mapping) and entry.get("human") == "angle"]
            raise InputError(f"joints {asked} must include the one following the elbow (the phase): "
                             f"{', '.join(elbow) or 'none in ' + where}")
        maps.sort(key=lambda m: m.human != "angle")
        bearing = table.get("bearing_joint", DEFAULT_BEARING_JOINT)
        if bearing is not None and not isinstance(bearing, str):
            raise InputError(f"{where}: bearing_joint must be a joint name, got {bearing!r}")
        start = {name: number_field(pose, name, f"{where}.start_pose") for name in pose}
        # an undriven joint of the table rests at its start pose
        with _naming(where, robot.source):
            return cls(robot, tuple(maps), start, number_field(table, "time_scale", where), bearing or None)

    @property
    def driven_joints(self) -> tuple[str, ...]:
        """The robot joints driven, in the order of :attr:`human_columns`."""
        return tuple(m.joint for m in self.joints)

    @property
    def human_columns(self) -> tuple[str, ...]:
        """The human position columns that drive them, ``angle`` first."""
        return tuple(m.human for m in self.joints)

    def pose(self) -> np.ndarray:
        """Positions (J,) (rad) of every joint at the start pose: where the arm rests before a
        throw, the ``start`` the approach is planned from (a driven joint without one at 0)."""
        return np.array([self.start_pose.get(name, 0.0) for name in self.robot.joint_names])

    def path_to_robot(self, path: HumanPath, *, bearing: float = 0.0,
                      clip: bool = False) -> tuple[JointTrajectory, ClipReport]:
        """The coordinated robot trajectory of a whole-arm human path, checked against the limits.

        Parameters
        ----------
        path : HumanPath
            Columns of shape (T,): ``angle`` (rad, the phase: strictly monotonic), ``velocity``
            (rad/s), and the position and velocity column of every other human joint of
            :attr:`human_columns`; optional ``time`` (s; default: from angle and velocity,
            :func:`rlff.timing.time_along_path`).
        bearing : float
            The basket's bearing (deg, counter-clockwise seen from above): the bearing joint
            stands at its start pose plus this angle through the whole throw.
        clip : bool
            Clip positions and velocities into the limits instead of raising (each change
            reported); an elbow velocity against the path is set to 0 first.

        Returns
        -------
        JointTrajectory
            T points of every robot joint (controller order), time from 0 (human time times
            :attr:`time_scale`); accelerations from the velocities over time.
        ClipReport
            What was clipped (empty unless ``clip``).

        Raises
        ------
        InputError
            A missing column (named), NaN, a non-monotonic angle, a bad time, a bearing the
            bearing joint cannot turn to, or (without ``clip``) a value beyond a limit.
        """
        velocities_of = tuple(velocity_column(c) for c in self.human_columns)
        needed = tuple(c for pair in zip(self.human_columns, velocities_of, strict=True) for c in pair)
        _require_columns(path, needed, f"driving {', '.join(self.driven_joints)} needs {', '.join(needed)}: "
                                       "a whole-arm model's path")
        angle = np.asarray(path["angle"], dtype=float)
        human = {c: np.asarray(path[c], dtype=float) for c in (*self.human_columns, *velocities_of)}
        for name, column in human.items():
            if column.shape != angle.shape:
                raise InputError(f"path column {name!r} has shape {column.shape}, angle {angle.shape}")
            if not np.all(np.isfinite(column)):
                raise InputError(f"path column {name!r} holds NaN or inf")
        velocity = human["velocity"].copy()
        backward = _backward_samples(angle, velocity, clip)
        velocity[backward] = 0.0
        human["velocity"] = velocity
        human_time = _human_time(angle, velocity, path.get("time"))
        robot_time = (human_time - human_time[0]) * self.time_scale
        positions = np.tile(self.pose(), (angle.size, 1))
        velocities = np.zeros_like(positions)
        for item, speed in zip(self.joints, velocities_of, strict=True):
            column = self.robot.index(item.joint)
            positions[:, column] = item.offset + item.scale * human[item.human]
            velocities[:, column] = item.scale * human[speed] / self.time_scale
        traj = JointTrajectory(self.robot.joint_names, robot_time, positions, velocities,
                               _accelerations(robot_time, velocities))
        traj = onto_limits(_turned(traj, self.robot, self.bearing_joint, bearing), self.robot.joints)
        if not clip:
            require_within_limits(traj, self.robot.joints)
            return traj, ClipReport()
        clipped, report = clip_to_limits(traj, self.robot.joints)
        elbow = self.joints[0]
        stopped = [LimitChange(int(i), elbow.joint, "velocity", float(elbow.scale * before / self.time_scale), 0.0)
                   for i, before in zip(backward, np.asarray(path["velocity"], dtype=float)[backward], strict=True)]
        report = ClipReport(tuple(sorted(report.changes + tuple(stopped), key=lambda c: (c.point, c.joint, c.quantity))))
        if not report:
            return traj, report
        return (JointTrajectory(clipped.joint_names, clipped.time, clipped.positions, clipped.velocities,
                                _accelerations(clipped.time, clipped.velocities)), report)

    def path_from_robot(self, traj: JointTrajectory) -> dict[str, np.ndarray]:
        """The human columns (positions, velocities, ``time`` in s) of a robot trajectory: the
        inverse of :meth:`path_to_robot` on the driven joints; arrays of shape (T,)."""
        path = {}
        for item in self.joints:
            column = traj.joint_index(item.joint)
            path[item.human] = (traj.positions[:, column] - item.offset) / item.scale
            path[velocity_column(item.human)] = traj.velocities[:, column] * self.time_scale / item.scale
        path["time"] = traj.time / self.time_scale
        return path

    def max_human_speeds(self) -> dict[str, float]:
        """Each driven joint's speed limit in human units (rad/s), by velocity column."""
        return {velocity_column(m.human): self.robot.joint(m.joint).max_velocity * self.time_scale / abs(m.scale)
                for m in self.joints}


def mapping_for(robot: Robot, joints: Sequence[str] | None = None) -> RobotMapping | ArmMapping:
    """The mapping for the robot ``joints`` driven: None or the ``[throwing]`` table's one joint
    alone gives the one-joint :class:`RobotMapping` exactly as before; several joints the
    :class:`ArmMapping` of the ``[whole_arm]`` table.

    Raises
    ------
    InputError
        Joints the robot file does not map (named), see :meth:`ArmMapping.for_robot`.
    """
    if joints is None:
        return RobotMapping.for_robot(robot)
    joints = tuple(str(name) for name in as_names(joints))
    if not joints:
        raise InputError("joints (--joints) names no joint (e.g. joint_2,joint_3)")
    if len(joints) == 1 and joints[0] == robot.throwing.get("joint"):
        return RobotMapping.for_robot(robot)
    return ArmMapping.for_robot(robot, joints)


@contextmanager
def _naming(where: str, source: str) -> Iterator[None]:
    """Prefix ``where`` (the robot file and its table) to an :class:`InputError` that does not
    name the file already (a mapping's own checks name no file)."""
    try:
        yield
    except InputError as exc:
        if str(exc).startswith(source):
            raise
        raise InputError(f"{where}: {exc}") from None


def _require_columns(path: HumanPath, columns: Sequence[str], why: str = "") -> None:
    """:class:`InputError` naming the columns of ``columns`` that ``path`` lacks (and ``why``)."""
    missing = [name for name in columns if name not in path]
    if missing:
        because = f"; {why}" if why else ""
        raise InputError(f"the path lacks the columns {', '.join(missing)} (it has {', '.join(path)}){because}")


def bearing_at_release(traj: JointTrajectory, robot: Robot) -> tuple[float, str] | None:
    """The bearing (deg) a robot trajectory throws at, and the joint it is read from: how far the
    bearing joint (joint_1, or the ``[whole_arm]`` table's) stands at the release (the last point
    without one) from its pose in the ``[throwing]`` table's start pose, the inverse of what
    ``path_to_robot`` does with a bearing. None when the trajectory has no such joint.
    """
    mapping = mapping_for(robot)
    joint = mapping.bearing_joint
    if joint is None or joint not in traj.joint_names:
        return None
    when = traj.time[-1] if traj.release_time is None else traj.release_time
    position = float(np.interp(when, traj.time, traj.positions[:, traj.joint_index(joint)]))
    return round(math.degrees(position - mapping.start_pose[joint]), 6), joint


def start_facing(robot: Robot) -> tuple[float, str] | None:
    """Where the arm faces at the ``[throwing]`` start pose, the line a bearing of 0 points along
    (bearings count from it, :func:`bearing_at_release`): (deg from the robot base's x axis, the
    bearing joint); None where that is the x axis itself, or the robot has no bearing joint or
    ``[throwing]`` table."""
    if not robot.throwing:
        return None
    mapping = mapping_for(robot)
    joint = mapping.bearing_joint
    if joint is None or not mapping.start_pose.get(joint, 0.0):
        return None
    return math.degrees(mapping.start_pose[joint]), joint


def bearing_range(robot: Robot) -> tuple[str, float, float] | None:
    """The bearings (deg) the robot can face: ``(joint, lowest, highest)``, how far its bearing
    joint (joint_1, or the ``[whole_arm]`` table's) may turn from its ``[throwing]`` start pose
    within its limits; None when it has no such joint."""
    mapping = mapping_for(robot)
    joint = mapping.bearing_joint
    if joint is None:
        return None
    limits, start = robot.joint(joint), mapping.start_pose[joint]
    return joint, math.degrees(limits.lower - start), math.degrees(limits.upper - start)


def require_bearing(mapping: RobotMapping | ArmMapping, bearing: float) -> None:
    """Raise :class:`InputError` when ``mapping``'s arm cannot face ``bearing`` (deg): what
    ``path_to_robot`` refuses every throw at that bearing for, said before the first (``rlff
    learn`` then opens no attempts log)."""
    joint = mapping.bearing_joint
    _require_turn(mapping.robot, joint, mapping.start_pose.get(joint, 0.0), bearing)


def _turned(traj: JointTrajectory, robot: Robot, joint: str | None, bearing: float) -> JointTrajectory:
    """``traj`` with ``joint`` turned ``bearing`` degrees from where it stands (unchanged at 0).

    Raises
    ------
    InputError
        See :func:`_require_turn`.
    """
    column = None if joint is None else traj.joint_index(joint)
    _require_turn(robot, joint, 0.0 if column is None else traj.positions[0, column], bearing)
    if bearing == 0:
        return traj
    positions = np.array(traj.positions)
    positions[:, column] += np.radians(bearing)
    return JointTrajectory(traj.joint_names, traj.time, positions, traj.velocities, traj.accelerations,
                           traj.release_time)


def _require_turn(robot: Robot, joint: str | None, start: float, bearing: float) -> None:
    """Raise :class:`InputError` for a non-finite bearing, a bearing without a joint to turn, or one
    that turns ``joint`` from ``start`` (rad) beyond its limits."""
    if not np.isfinite(bearing):
        raise InputError(f"bearing must be a finite number of degrees, got {bearing}")
    if bearing == 0:
        return
    if joint is None:
        raise InputError(f"robot {robot.name} has no joint to turn to a bearing of {bearing:g} deg")
    limits = robot.joint(joint)
    turned = start + np.radians(bearing)
    if not limits.lower <= turned <= limits.upper:
        # as many digits as tell each number from the limit it passes: 170 deg turns joint_1 to
        # 2.96706 rad, past 2.967 rad, and read "2.967 rad, beyond its limits [-2.967, 2.967] rad"
        passed = limits.upper if turned > limits.upper else limits.lower
        ends = (limits.lower, limits.upper)
        rad = [apart(turned, end, 4)[1] for end in ends]
        deg = [apart(bearing, math.degrees(end - start))[1] for end in ends]
        raise InputError(f"bearing {apart(bearing, math.degrees(passed - start))[0]} deg turns {joint} to "
                         f"{apart(turned, passed, 4)[0]} rad, beyond its limits [{rad[0]}, {rad[1]}] rad "
                         f"(bearings {deg[0]} to {deg[1]} deg)")


def _backward_samples(angle: np.ndarray, velocity: np.ndarray, clip: bool) -> np.ndarray:
    """Samples whose phase velocity points against the path; an error without ``clip``."""
    direction = np.sign(angle[-1] - angle[0]) if angle.ndim == 1 and angle.size > 1 else 0.0
    backward = np.flatnonzero(velocity * direction < 0) if velocity.shape == angle.shape else np.array([], int)
    if direction and velocity.shape == angle.shape and np.all(np.isfinite(velocity)) and not np.any(velocity * direction > 0):
        raise InputError(f"velocity never moves along the path ({velocity.min():g} to {velocity.max():g} rad/s "
                         f"while the angle runs {angle[0]:g} -> {angle[-1]:g} rad): there is no throw to plan "
                         "(a model gives this where its demonstrations move backward or rest at that context; "
                         "rlff generate notes it)")
    if backward.size and not clip:
        i = int(backward[0])
        raise InputError(f"velocity at sample {i} ({velocity[i]:g} rad/s) moves against the path "
                         f"({backward.size} samples do); clipping sets them to 0 (--clip)")
    return backward


def _human_time(angle: np.ndarray, velocity: np.ndarray, time: np.ndarray | None) -> np.ndarray:
    """The human time (s) of a path, shape (T,): ``time``, checked, or from angle and velocity."""
    if time is None:
        return time_along_path(angle, velocity)
    human_time = np.asarray(time, dtype=float)
    time_along_path(angle, velocity)  # same checks of the path: finite, monotonic
    if human_time.shape != angle.shape or not np.all(np.isfinite(human_time)):
        raise InputError(f"time must be finite with the shape of angle {angle.shape}")
    if np.any(np.diff(human_time) <= 0):
        bad = int(np.flatnonzero(np.diff(human_time) <= 0)[0]) + 1
        raise InputError(f"time is not strictly increasing at sample {bad}")
    return human_time


def _accelerations(time: np.ndarray, velocities: np.ndarray) -> np.ndarray:
    """Accelerations (rad/s^2), shape (T, J): differences of velocity over time (T >= 2)."""
    return np.gradient(velocities, time, axis=0)
