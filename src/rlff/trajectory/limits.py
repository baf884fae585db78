"""Joint limits of a timed trajectory: find every violation, or clip and report each change.

A point beyond a position or velocity limit is an error unless the caller asks to clip; clipping
never happens silently: each changed value is listed with its point, joint, quantity and values.
A position is clipped to :data:`CLIP_CLEARANCE` inside its limit, not onto it: the joint held
there comes to rest there, and a controller's software limit trips at the limit itself.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Protocol

import numpy as np

from rlff.errors import InputError
from rlff.limits import apart
from rlff.trajectory.joint import JointTrajectory
from rlff.wording import plural


class JointLimits(Protocol):
    """What the limit checks and the planner read from a joint (``rlff.robot.Joint`` has these).

    Positions in rad, ``max_velocity`` in rad/s, ``max_acceleration`` in rad/s^2, ``max_jerk`` in
    rad/s^3, each a magnitude allowed in either direction. The last two may be None on a joint
    built in code; the planner and the motion check refuse such a joint by name.
    """

    name: str
    lower: float
    upper: float
    max_velocity: float
    max_acceleration: float | None
    max_jerk: float | None


@dataclass(frozen=True)
class LimitChange:
    """One value beyond a limit: where it is, what it was and what it is (or would be) clipped to.

    ``quantity`` is ``"position"`` (rad) or ``"velocity"`` (rad/s); ``point`` is the index of the
    trajectory point; ``limit`` the limit the value is beyond, in the same unit (None for a change
    that no limit asked for: a velocity against the path's direction, stopped).
    """

    point: int
    joint: str
    quantity: str
    before: float
    after: float
    limit: float | None = None

    @property
    def unit(self) -> str:
        return "rad" if self.quantity == "position" else "rad/s"

    def describe(self) -> str:
        """One line: ``point 3: joint_2 velocity 3.1 rad/s -> 2.792 rad/s``, and for a position
        clipped inside its limit ``point 9: joint_2 position 2.8 rad -> 2.7 rad (0.01 rad inside
        its limit 2.71 rad)``."""
        before, after = apart(self.before, self.after)
        line = f"point {self.point}: {self.joint} {self.quantity} {before} {self.unit} -> {after} {self.unit}"
        if self.limit is None or self.after == self.limit:
            return line
        return f"{line} ({abs(self.limit - self.after):.3g} {self.unit} inside its limit {self.limit:g} {self.unit})"


@dataclass(frozen=True)
class ClipReport:
    """Every value that was beyond a limit, in point order; empty when nothing was clipped."""

    changes: tuple[LimitChange, ...] = ()

    def __bool__(self) -> bool:
        return bool(self.changes)

    def __len__(self) -> int:
        return len(self.changes)

    def count(self, quantity: str) -> int:
        """Number of changed ``"position"`` or ``"velocity"`` values."""
        return sum(change.quantity == quantity for change in self.changes)

    def summary(self) -> str:
        """One line: how many values were clipped, or that none were."""
        if not self.changes:
            return "no point beyond the limits"
        points = len({change.point for change in self.changes})
        return (f"clipped {self.count('position')} positions and {self.count('velocity')} "
                f"velocities at {points} points")


def _limit_arrays(traj: JointTrajectory, joints: Sequence[JointLimits]) -> tuple[np.ndarray, ...]:
    by_name = {joint.name: joint for joint in joints}
    unknown = [name for name in traj.joint_names if name not in by_name]
    if unknown:
        raise InputError(f"unknown joint names {unknown} (the robot has {', '.join(by_name)})")
    ordered = [by_name[name] for name in traj.joint_names]
    lower = np.array([joint.lower for joint in ordered])
    upper = np.array([joint.upper for joint in ordered])
    vmax = np.array([joint.max_velocity for joint in ordered])
    return lower, upper, vmax


#: How far inside a position limit (rad) :func:`clip_to_limits` puts a position beyond it. A joint
#: clipped at a limit is held there, so it comes to rest there; exactly on the limit, a
#: controller's software limit trips at any overshoot (the simulated servo, brought to rest on
#: joint_2's limit by a clipped throw, stood 8.5 urad past it at the release), and the arm's
#: tracking error in a throw is up to 2 mrad in the simulation. 10 mrad: 14 mm at the Comau's reach.
CLIP_CLEARANCE = 0.01

#: How far inside a position limit (rad) a planned throw keeps where it turns or comes to rest
#: (the wind-up before the throw, the braking after the release;
#: :func:`rlff.trajectory.planner.plan_throw`), as the profiles keep 1 % inside the speed and
#: acceleration limits. Braked to a stop on the limit itself (a tester's arm stopped 4e-10 rad short
#: of 1.7 rad), a real arm's servo overshoots its command by micro-radians at rest (the simulated
#: one stood 8.5 urad past it) and its controller's software limit faults. 2 mrad is the simulated
#: arm's tracking error in a throw (:data:`CLIP_CLEARANCE` cites it), and a fifth of the clearance a
#: clipped position gets, so a clipped path still plans: 2.6 mm at the Comau's 1.3 m reach.
POSITION_MARGIN = 0.002

#: Relative excess over a limit that is rounding, not a request: a path logged in the human's
#: units and mapped back puts a release clipped at 3.14 rad/s at 3.1400000000000006.
ROUNDING = 1e-9


def onto_limits(traj: JointTrajectory, joints: Sequence[JointLimits]) -> JointTrajectory:
    """``traj`` with every position and velocity beyond a limit of ``joints`` by no more than
    :data:`ROUNDING` of it set to the limit (``traj`` itself when none is): the mapping's own
    rounding, which no check should count as beyond the limit, nor a clip report list."""
    lower, upper, vmax = _limit_arrays(traj, joints)
    values = []
    for quantity, low, high in ((traj.positions, lower, upper), (traj.velocities, -vmax, vmax)):
        clipped = np.clip(quantity, low, high)
        rounding = np.abs(quantity - clipped) <= ROUNDING * np.maximum(np.abs(clipped), 1.0)
        values.append(np.where(rounding, clipped, quantity))
    if all(np.array_equal(new, old) for new, old in zip(values, (traj.positions, traj.velocities), strict=True)):
        return traj
    return JointTrajectory(traj.joint_names, traj.time, values[0], values[1], traj.accelerations, traj.release_time)


def limit_changes(traj: JointTrajectory, joints: Sequence[JointLimits]) -> ClipReport:
    """Every position and velocity of ``traj`` beyond the limits of ``joints``.

    Parameters
    ----------
    traj : JointTrajectory
        T points of J joints; each of its joint names must be among ``joints``.
    joints : sequence of JointLimits
        Position limits ``lower``/``upper`` (rad) and speed limit ``max_velocity`` (rad/s).

    Returns
    -------
    ClipReport
        One :class:`LimitChange` per value beyond a limit, ``after`` being the clipped value.
    """
    lower, upper, vmax = _limit_arrays(traj, joints)
    clipped_q = np.clip(traj.positions, lower, upper)
    clipped_v = np.clip(traj.velocities, -vmax, vmax)
    changes = []
    for quantity, before, after in (("position", traj.positions, clipped_q),
                                    ("velocity", traj.velocities, clipped_v)):
        for point, column in zip(*np.nonzero(before != after), strict=True):
            limit = float(after[point, column])
            changes.append(LimitChange(int(point), traj.joint_names[column], quantity,
                                       float(before[point, column]), limit, limit))
    changes.sort(key=lambda change: (change.point, change.joint, change.quantity))
    return ClipReport(tuple(changes))


def require_within_limits(traj: JointTrajectory, joints: Sequence[JointLimits]) -> None:
    """Raise :class:`InputError` naming the first violations if any point is beyond a limit."""
    report = limit_changes(traj, joints)
    if report:
        shown = "; ".join(
            "point {}: {} {} {} {unit} beyond the limit {} {unit}".format(
                c.point, c.joint, c.quantity, *apart(c.before, c.after), unit=c.unit)
            for c in report.changes[:3])
        more = f" (and {len(report) - 3} more)" if len(report) > 3 else ""
        raise InputError(f"{plural(len(report), 'value')} beyond the robot's limits: {shown}{more}")


def clip_to_limits(
    traj: JointTrajectory, joints: Sequence[JointLimits]
) -> tuple[JointTrajectory, ClipReport]:
    """``traj`` with positions and velocities clipped into the limits, and what changed.

    A position beyond a limit is clipped to :data:`CLIP_CLEARANCE` inside it (a quarter of the
    joint's range, if that is less), where the joint is held: its velocity is set to 0 and that
    change is reported too. A velocity beyond its limit is clipped to the limit. Positions and
    velocities inside the limits are kept, and so are the accelerations: the result is a path
    to plan (:func:`rlff.trajectory.planner.plan_throw` keeps its first pose and its release and
    times the motion between within the limits), not a trajectory to execute as it is (a joint
    that reaches a clipped point at speed stops dead there, which
    :func:`rlff.trajectory.check.check_trajectory` refuses).
    """
    report = limit_changes(traj, joints)
    if not report:
        return traj, report
    lower, upper, vmax = _limit_arrays(traj, joints)
    inset = np.minimum(CLIP_CLEARANCE, (upper - lower) / 4)
    positions = traj.positions.copy()
    below, above = positions < lower, positions > upper
    positions[below] = np.broadcast_to(lower + inset, positions.shape)[below]
    positions[above] = np.broadcast_to(upper - inset, positions.shape)[above]
    velocities = np.clip(traj.velocities, -vmax, vmax)
    held = below | above
    velocities[held] = 0.0
    changes = [replace(change, after=float(positions[change.point, traj.joint_names.index(change.joint)]))
               for change in report.changes if change.quantity == "position"]
    for point, column in zip(*np.nonzero(velocities != traj.velocities), strict=True):
        limit = None if held[point, column] else float(np.sign(traj.velocities[point, column]) * vmax[column])
        changes.append(LimitChange(int(point), traj.joint_names[column], "velocity",
                                   float(traj.velocities[point, column]),
                                   float(velocities[point, column]), limit))
    changes.sort(key=lambda change: (change.point, change.joint, change.quantity))
    clipped = JointTrajectory(traj.joint_names, traj.time, positions, velocities,
                              traj.accelerations)
    return clipped, ClipReport(tuple(changes))
