"""The arm's controller's joint names and zeros against rlff's: the robot file's ``[ros.joints]``.

rlff plans, checks and simulates in its own convention: the robot file's joints (``joint_1`` ..
``joint_6`` with the zeros and signs of the comments of ``rlff/robots/comau_smart5_six.toml``,
joint 2 at 0 = upper arm vertical). An arm's controller may name its joints otherwise (a UR's
``shoulder_lift_joint``) and count them from other zeros and the other way round. For each joint
the file lists, with the joint's own name ``q`` rlff's position (rad)::

    controller position (rad)          = offset + sign * q
    controller velocity, acceleration  = sign * rlff's

and a joint not listed keeps its name, offset 0 and sign +1. :class:`JointMap` turns a
trajectory or a joint state one way or the other; only the ROS boundary calls it (goals, joint
states, feedback, bags). Without a map (:attr:`JointMap.identity`) every conversion returns what
it was given, the very object, so that a robot file without ``[ros.joints]`` sends the bytes it
sent before.
"""

from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import TYPE_CHECKING

import numpy as np

from rlff.errors import InputError

if TYPE_CHECKING:  # rlff.trajectory imports the robot description, which holds a JointMap
    from rlff.trajectory.joint import JointTrajectory

#: What a ``[ros.joints.<joint>]`` table holds.
ENTRY_FIELDS = ("name", "offset", "sign")


@dataclass(frozen=True)
class ControllerJoint:
    """One joint as the controller knows it.

    Parameters
    ----------
    name : str
        The controller's name of the joint (e.g. ``shoulder_lift_joint``).
    offset : float
        The controller's position (rad) where rlff's is 0.
    sign : int
        +1 when the controller counts the joint the way rlff does, -1 when the other way round.
    """

    name: str
    offset: float = 0.0
    sign: int = 1

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name.strip():
            raise InputError(f"name must be the controller's joint name, a non-empty string, got {self.name!r}")
        if self.name != self.name.strip():
            raise InputError(f"name {self.name!r} begins or ends with a space; the controller's names have none")
        if isinstance(self.offset, bool) or not isinstance(self.offset, int | float) or not math.isfinite(self.offset):
            raise InputError(f"offset must be a finite number of radians, got {self.offset!r}")
        if isinstance(self.sign, bool) or self.sign not in (1, -1):
            raise InputError(f"sign must be 1 or -1 (the controller counts the joint as rlff does, or the other way "
                             f"round), got {self.sign!r}")
        object.__setattr__(self, "offset", float(self.offset))
        object.__setattr__(self, "sign", int(self.sign))

    @property
    def counts_as_rlff(self) -> bool:
        """Whether the controller counts the joint from rlff's zero and the same way (offset 0,
        sign 1), whatever its name."""
        return self.offset == 0.0 and self.sign == 1

    def is_identity(self, joint: str) -> bool:
        """Whether this entry, for rlff's ``joint``, changes nothing."""
        return self.name == joint and self.counts_as_rlff


@dataclass(frozen=True)
class JointMap:
    """rlff's joints to the controller's (the robot file's ``[ros.joints]``), and back.

    Parameters
    ----------
    joints : mapping of str to ControllerJoint
        By rlff's joint name (a joint of the robot file), the controller's name, offset (rad) and
        sign of that joint. Joints not in it are the controller's as they are.

    The map is checked against the robot's joints by :meth:`check_joints` (the robot file's
    reader does it): each key a joint, no two joints under one controller name.
    """

    joints: Mapping[str, ControllerJoint] = field(default_factory=dict)

    def __post_init__(self) -> None:
        object.__setattr__(self, "joints", MappingProxyType(dict(self.joints)))

    def __hash__(self) -> int:
        return hash(tuple(self.joints.items()))

    @property
    def identity(self) -> bool:
        """Whether the map changes nothing (no ``[ros.joints]``, or only entries that keep all)."""
        return all(self.keeps(joint) for joint in self.joints)

    def keeps(self, joint: str) -> bool:
        """Whether the controller has rlff's ``joint`` as rlff does: same name, zero and sense."""
        return self.joints.get(joint, ControllerJoint(joint)).is_identity(joint)

    def check_joints(self, names: Sequence[str]) -> None:
        """:class:`InputError` (its text to follow ``[ros.joints]``) for an entry of a joint not in
        ``names`` (rlff's joints), or two joints under one controller name."""
        from rlff.wording import nearest_hint

        for joint, entry in self.joints.items():
            if joint in names:
                continue
            listed = f"joints: {', '.join(names)}"
            if entry.name in names:  # written the other way round
                hint = f" ({listed}; the other way round: [ros.joints.{entry.name}] with name = {joint!r}?)"
            elif re.fullmatch(r"joint_\d+", joint):  # a joint_7 is no misspelt joint_6
                hint = f" ({listed})"
            else:
                hint = nearest_hint(joint, names, listed)
            raise InputError(f"[ros.joints.{joint}]: {joint} is not a joint of the robot{hint}; each table is named "
                             "after one of the file's [[joints]], its `name` the controller's")
        seen: dict[str, str] = {}
        for joint in names:
            name = self.controller_name(joint)
            if name in seen:
                other = seen[name]
                listed = [j for j in (other, joint) if j in self.joints]
                unmapped = [j for j in (other, joint) if j not in self.joints]
                if unmapped:
                    raise InputError(f"[ros.joints.{listed[0]}]: name {name!r} is the name of rlff's joint "
                                     f"{unmapped[0]}, which keeps it (it has no [ros.joints.{unmapped[0]}] table): "
                                     "two joints under one name; give that joint the controller's own name too")
                raise InputError(f"[ros.joints.{joint}]: name {name!r} is also [ros.joints.{other}]'s: each joint "
                                 "needs a controller name of its own")
            seen[name] = joint

    # -- names ------------------------------------------------------------------------------------------
    def controller_name(self, joint: str) -> str:
        """The controller's name of rlff's ``joint``."""
        entry = self.joints.get(joint)
        return joint if entry is None else entry.name

    def controller_names(self, joints: Sequence[str]) -> list[str]:
        """The controller's names of rlff's ``joints``, in their order."""
        return [self.controller_name(joint) for joint in joints]

    def rlff_name(self, name: str) -> str | None:
        """rlff's joint the controller calls ``name``; ``name`` itself for a joint the map does not
        rename; None for a name rlff's own joint gave up (``joint_2`` when the map calls rlff's
        joint_2 ``shoulder_lift_joint``), which is no joint of the arm's controller."""
        for joint, entry in self.joints.items():
            if entry.name == name:
                return joint
        return None if name in self.joints else name

    def counts_otherwise(self, joint: str) -> bool:
        """Whether the controller counts rlff's ``joint`` from another zero or the other way round."""
        entry = self.joints.get(joint)
        return entry is not None and not entry.counts_as_rlff

    def words(self, joints: Sequence[str]) -> str:
        """The map of rlff's ``joints`` in words, as ``rlff robot show`` prints it:
        ``joint_1 as shoulder_pan_joint, joint_2 as shoulder_lift_joint = -1.571 + joint_2, ...``."""
        parts = []
        for joint in joints:
            said = f"{joint} as {self.controller_name(joint)}"
            if self.counts_otherwise(joint):  # offset 0 here means sign -1
                entry = self.joints[joint]
                said += f" = {entry.offset:.6g} {'+' if entry.sign > 0 else '-'} {joint}" if entry.offset else f" = -{joint}"
            parts.append(said)
        return ", ".join(parts)

    def label(self, joint: str) -> str:
        """rlff's ``joint`` in words for a message: ``shoulder_lift_joint (joint_2)``, or
        ``joint_2`` when the controller calls it so too."""
        name = self.controller_name(joint)
        return joint if name == joint else f"{name} ({joint})"

    def offset_and_sign(self, joint: str) -> tuple[float, int]:
        """The controller's offset (rad) and sign of rlff's ``joint`` (0 and 1 for a joint the map
        leaves as it is)."""
        entry = self.joints.get(joint, ControllerJoint(joint))
        return entry.offset, entry.sign

    # -- values -----------------------------------------------------------------------------------------
    def _factors(self, joints: Sequence[str]) -> tuple[np.ndarray, np.ndarray]:
        """Offsets (J,) rad and signs (J,) of rlff's ``joints``."""
        pairs = [self.offset_and_sign(joint) for joint in joints]
        return (np.array([offset for offset, _ in pairs], dtype=float),
                np.array([sign for _, sign in pairs], dtype=float))

    def positions_to_controller(self, joints: Sequence[str], positions: np.ndarray) -> np.ndarray:
        """Positions (..., J) rad of rlff's ``joints`` in the controller's convention: offset + sign * q."""
        if self.identity:  # not 0.0 + q, which turns a -0.0 into 0.0
            return np.asarray(positions, dtype=float)
        offset, sign = self._factors(joints)
        return offset + sign * np.asarray(positions, dtype=float)

    def positions_from_controller(self, joints: Sequence[str], positions: np.ndarray) -> np.ndarray:
        """The controller's positions (..., J) rad of rlff's ``joints`` in rlff's: sign * (q_c - offset)."""
        if self.identity:
            return np.asarray(positions, dtype=float)
        offset, sign = self._factors(joints)
        return sign * (np.asarray(positions, dtype=float) - offset)

    def rates_to_controller(self, joints: Sequence[str], rates: np.ndarray) -> np.ndarray:
        """Velocities or accelerations (..., J) of rlff's ``joints`` either way: times the sign (its own inverse)."""
        if self.identity:
            return np.asarray(rates, dtype=float)
        return self._factors(joints)[1] * np.asarray(rates, dtype=float)

    rates_from_controller = rates_to_controller

    # -- trajectories -----------------------------------------------------------------------------------
    def to_controller(self, traj: JointTrajectory) -> JointTrajectory:
        """``traj`` (rlff's joints and convention) as the controller takes it: its names, positions
        offset + sign * q (rad), velocities and accelerations times the sign; times and release as
        they are. ``traj`` itself when the map changes nothing."""
        if self.identity:
            return traj
        joints = traj.joint_names
        return dataclasses.replace(
            traj, joint_names=tuple(self.controller_names(joints)),
            positions=self.positions_to_controller(joints, traj.positions),
            velocities=self.rates_to_controller(joints, traj.velocities),
            accelerations=self.rates_to_controller(joints, traj.accelerations))

    def from_controller(self, traj: JointTrajectory) -> JointTrajectory:
        """A trajectory in the controller's names and convention (a goal, a bag) in rlff's: the
        inverse of :meth:`to_controller`. ``traj`` itself when the map changes nothing.

        Raises
        ------
        InputError
            ``traj`` names a joint by a name rlff's joint gave up (:meth:`rlff_name` is None).
        """
        if self.identity:
            return traj
        joints = self.rlff_names(traj.joint_names)
        return dataclasses.replace(
            traj, joint_names=joints, positions=self.positions_from_controller(joints, traj.positions),
            velocities=self.rates_from_controller(joints, traj.velocities),
            accelerations=self.rates_from_controller(joints, traj.accelerations))

    def rlff_names(self, names: Sequence[str]) -> tuple[str, ...]:
        """rlff's joints the controller calls ``names``; :class:`InputError` for a name rlff's own
        joint gave up (see :meth:`rlff_name`)."""
        joints = tuple(self.rlff_name(name) for name in names)
        if None in joints:
            name = names[joints.index(None)]
            raise InputError(f"{name} is not a joint of the arm's controller: the robot file's [ros.joints.{name}] "
                             f"calls rlff's {name} {self.controller_name(name)}")
        return joints

    # -- joint states ------------------------------------------------------------------------------------
    def state_to_controller(self, joints: Sequence[str], positions: np.ndarray,
                            velocities: np.ndarray) -> tuple[list[str], np.ndarray, np.ndarray]:
        """A joint state of rlff's ``joints`` (positions (J,) rad, velocities (J,) rad/s) as the
        controller publishes it: (names, positions, velocities)."""
        return (self.controller_names(joints), self.positions_to_controller(joints, positions),
                self.rates_to_controller(joints, velocities))

    def state_from_controller(self, joints: Sequence[str], names: Sequence[str], positions: Sequence[float],
                              velocities: Sequence[float]) -> tuple[np.ndarray, np.ndarray | None]:
        """rlff's ``joints`` (J) of a JointState message's fields in rlff's convention: (positions
        (J,) rad, velocities (J,) rad/s, None when the message has not one per name).

        ``names`` are the controller's and must hold every one of ``joints`` (other devices'
        joints beside them are passed over); ``positions`` (and ``velocities`` when given) one
        value per name.
        """
        names = list(names)
        index = [names.index(self.controller_name(joint)) for joint in joints]
        velocities = np.asarray(velocities, dtype=float)
        return (self.positions_from_controller(joints, np.asarray(positions, dtype=float)[index]),
                self.rates_from_controller(joints, velocities[index]) if velocities.size == len(names) else None)
