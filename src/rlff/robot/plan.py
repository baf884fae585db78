"""From a generated human path, or a robot trajectory file, to the trajectory a robot executes.

Every robot output (exports, ``robot send``, ``sim throw``) gets its trajectory here, so nothing
reaches a file, a bag, a Comau program, a live goal or the simulation without the motion planner
(:func:`rlff.trajectory.planner.plan_throw`) and the one check
(:func:`rlff.trajectory.check.check_trajectory`):

- a generated path (CSV of ``angle``, ``velocity`` [, ``time``], and for a whole-arm throw the
  other joints' columns) is mapped to the robot (one joint, or several on one time base), planned
  (approach, the throw to its release with every driven joint's release kept, braking to rest)
  and checked; a path that is no throw to clip (a unit or scale slip far beyond a limit, a release
  at rest, stopped or held at a limit by clipping: :func:`require_a_throw`) is refused with
  ``clip`` too;
- a robot trajectory (what ``rlff robot export --format json|csv`` writes) is read and checked
  as it is: it must already be executable, throw (not every joint at rest at its release:
  :func:`_require_released_moving`), and be of the robot it is read for (:mod:`rlff.robot.planned_for`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from rlff.dataset import ARM_JOINT_COLUMNS, separator_hint, velocity_column
from rlff.errors import InputError
from rlff.kinds import (
    DATASET,
    GENERATED,
    ROBOT_TRAJECTORY,
    binary_kind,
    csv_kind,
    file_kind,
    header_names,
    is_ros1_bag,
)
from rlff.limits import apart, check_period, require_radians
from rlff.robot.comau import HEADER as COMAU_HEADER
from rlff.robot.description import Robot
from rlff.robot.links import require_above_base
from rlff.robot.mapping import ArmMapping, HumanPath, RobotMapping, mapping_for, scaled_speed
from rlff.robot.planned_for import checked_against, require_planned_for
from rlff.trajectory.check import check_trajectory
from rlff.trajectory.joint import JointTrajectory
from rlff.trajectory.limits import ClipReport, LimitChange
from rlff.trajectory.path_csv import read_generated_path
from rlff.trajectory.planner import APPROACH_SPEED, DEFAULT_PERIOD, MOVING, plan_throw
from rlff.wording import plural


@dataclass(frozen=True)
class RobotPlan:
    """The robot trajectory to execute and how it was made.

    ``points`` is the mapped throw at the path's own samples (the model's release is its last
    point); ``trajectory`` the planned, checked trajectory to execute; ``clipped_points`` the
    values of ``points`` clipped into the limits (only with ``clip``); ``notes`` what the
    user may want to know of how the file was read (a whole-arm path thrown with one joint: the
    README's chain does that, so it is a note, not a warning); ``slowed`` how ``clip`` slowed a
    throw of several joints as a whole (:func:`slowed_to_limits`), ``""`` when it did not.
    """

    points: JointTrajectory
    trajectory: JointTrajectory
    clipped_points: ClipReport
    notes: tuple[str, ...] = ()
    slowed: str = ""

    def __repr__(self) -> str:
        """A line, not the arrays: the planned points, duration, release and joints, how many mapped
        points it was planned from and how many values were clipped."""
        traj = self.trajectory
        release = f", release at {traj.release_time:.3f} s" if traj.release_time is not None else ""
        source = "a robot trajectory as it is" if self.points is traj else f"from {len(self.points)} mapped points"
        slowed = ", slowed as a whole" if self.slowed else ""
        return (f"RobotPlan({len(traj)} points, {traj.duration:.3f} s{release}, joints={list(traj.joint_names)}, "
                f"{source}, clipped={len(self.clipped_points.changes)}{slowed})")

    def summary(self) -> str:
        """One line: how the throw was slowed (``slowed``, :func:`slowed_to_limits`) or clipped, the
        release's own clipped values first, and the plan's duration and release."""
        traj = self.trajectory
        if self.points is traj:
            return f"a robot trajectory, checked as it is: {plural(len(traj), 'point')}, {traj.duration:.3f} s"
        clipped = self.clipped_points.summary() if self.clipped_points else "nothing clipped"
        last = len(self.points) - 1
        at_release = [change.describe().removeprefix(f"point {last}: ")
                      for change in self.clipped_points.changes if change.point == last]
        if at_release:  # what the ball's flight depends on: not left among the "... and 22 more"
            clipped += f", the release's among them ({'; '.join(at_release)})"
        release = f", release at {traj.release_time:.3f} s" if traj.release_time is not None else ""
        slowed = f"{self.slowed}; " if self.slowed else ""
        return f"planned {traj.duration:.3f} s to rest{release}; {slowed}{clipped}"


def _faults(report: ClipReport, last: int) -> tuple[list[LimitChange], list[LimitChange]]:
    """The changes of ``report`` that count, and among them the faults: every position beyond a
    limit, and the release's velocities (``last``: the release's point).

    Velocities elsewhere along the path are not executed (the planner times the throw within
    the limits, never faster than the release), so only the release's count. The velocity of a
    joint held at a clipped position (set to 0) is no fault of its own: its position is.
    """
    held = {(c.point, c.joint) for c in report.changes if c.quantity == "position"}
    changes = [c for c in report.changes if c.quantity == "position" or (c.point, c.joint) not in held]
    return changes, [change for change in changes if change.quantity == "position" or change.point == last]


def _require_unclipped(report: ClipReport, last: int, coordinated: bool = False) -> None:
    """Without ``clip``: refuse a path beyond a position limit or a release beyond a limit
    (:func:`_faults`; a slip, or a release at rest once clipped: :func:`require_a_throw` refuses
    those before).

    The message says what ``clip`` (``--clip``) does: for a ``coordinated`` throw (several joints) it
    slows the whole throw rather than clip a release (:func:`slowed_to_limits`).
    """
    changes, faults = _faults(report, last)
    if not faults:
        return
    shown = "; ".join(_fault(c, last) for c in faults[:3])
    more = f" (and {len(faults) - 3} more)" if len(faults) > 3 else ""
    others = len(changes) - len(faults)
    also = (f" (and reports {plural(others, 'velocity', 'velocities')} along the path beyond a limit too, "
            "which the planner does not execute)" if others else "")
    remedy = f"clip (--clip) clips {'it' if len(faults) == 1 else 'them'}"
    kinds = {"position" if change.quantity == "position" else "speed" for change in faults if change.limit is not None}
    if coordinated and kinds:
        remedy = "clip (--clip) " + " and ".join(
            words for kind, words in (("position", "holds the positions inside their limits"),
                                      ("speed", "slows the whole throw, every joint by one factor, until its "
                                                "release is within the speed limits")) if kind in kinds)
    raise InputError(f"{plural(len(faults), 'value')} the robot would not execute as asked: {shown}{more}; "
                     f"{remedy}{also}")


def require_a_throw(mapping: RobotMapping | ArmMapping, points: JointTrajectory, report: ClipReport) -> None:
    """Refuse, with or without ``clip``, a mapped path that is no throw to clip: a unit or scale slip
    (:func:`_require_no_slip`), or every driven joint at rest at the release, stopped or held at a
    position limit by clipping, or at rest in the path (:func:`_require_thrown`).

    ``points`` is the path mapped to the robot and clipped (T points, the release last), ``report``
    what the mapping clipped. ``clip`` is for a path marginally beyond a limit (a throw for a basket
    a little beyond reach); of these it made a throw at the limits, or none, written with exit 0.
    """
    _require_no_slip(mapping, report, len(points) - 1)
    _require_thrown(mapping, points, report)


#: A release speed more than this many times its limit, which in rad/s would be within it, is a
#: path in deg/s: a unit slip, not a speed to clip.
DEGREES_SLIP = 10.0

#: A release speed more than this many times its limit is a unit or scale slip, not a speed to
#: clip. Measured 2026-12-07 on the Comau with the model of the MSR a06 throws (thesis preset):
#: `rlff generate` throws for baskets at 1.5 to 10 m ask at most 1.55 times joint_2's limit at the
#: release with the one-joint mapping, and with the whole arm (--joints joint_2,joint_3[,joint_5])
#: 4.1 at 2.5 m, 5.3 at 4.5 m, 5.9 at 6 m; of the throws `rlff demo --small` clips (its table's, its
#: learning runs', whole arm too) the fastest asks 2.9. A path in deg/s asks 57 times what it
#: means, a robot file's velocity_scale of 25 for 0.25 a hundred times. 15: 2.5 times the largest
#: measured for a legitimate throw.
SLIP = 15.0

#: A position more than this (rad, a full turn) beyond its limit is a unit or scale slip (degrees
#: for radians, an angle_offset in degrees), not a path to clip: no throw winds up a turn too far.
POSITION_SLIP = 2 * np.pi


def _is_slip(change: LimitChange) -> bool:
    """Whether ``change``, a value beyond its limit, is too far beyond it to be a throw to clip
    (:data:`SLIP`, :data:`POSITION_SLIP`)."""
    if change.limit is None:
        return False
    if change.quantity == "position":
        return abs(change.before - change.limit) > POSITION_SLIP
    return abs(change.before) > SLIP * abs(change.limit)


def _slip_words(change: LimitChange) -> str:
    """One value :func:`_is_slip`, for a message: the value, and how far beyond which limit."""
    value = f"{change.before:.6g} {change.unit}"
    if change.quantity == "position":
        return (f"point {change.point}: {change.joint} position {value}, {abs(change.before - change.limit):.3g} rad "
                f"beyond the limit {change.limit:g} rad")
    return (f"point {change.point}: {change.joint} velocity {value} at the release, "
            f"{abs(change.before / change.limit):.0f} times the limit {abs(change.limit):g} rad/s")


def _mapping_words(mapping: RobotMapping | ArmMapping) -> str:
    """The robot file's table a path was mapped through, with its values, for a message."""
    if isinstance(mapping, ArmMapping):
        joints = ", ".join(f"{m.joint} offset {m.offset:g} scale {m.scale:g}" for m in mapping.joints)
        return f"{mapping.robot.source}'s [whole_arm] mapping ({joints}; time_scale {mapping.time_scale:g})"
    return (f"{mapping.robot.source}'s [throwing] mapping ({mapping.joint}: angle_offset {mapping.angle_offset:g}, "
            f"angle_scale {mapping.angle_scale:g}, velocity_scale {mapping.velocity_scale:g})")


def _require_no_slip(mapping: RobotMapping | ArmMapping, report: ClipReport, last: int) -> None:
    """Refuse a path with a release speed or a position far beyond its limit (:func:`_is_slip`): a
    slip in the path's units or in the robot file's mapping, of which clipping would make a throw
    at the limits. A release speed only a path in deg/s explains (:func:`_looks_like_degrees`) gets
    the unit named."""
    _, faults = _faults(report, last)
    degrees = next((change for change in faults if _looks_like_degrees(change)), None)
    if degrees is not None:  # the velocities along the path say nothing more
        shown = "; ".join(_fault(c, last) for c in faults[:3])
        more = f" (and {len(faults) - 3} more)" if len(faults) > 3 else ""
        raise InputError(f"{plural(len(faults), 'value')} the robot would not execute as asked: {shown}{more}; "
                         f"{_degrees_hint(degrees)}")
    slips = [change for change in faults if _is_slip(change)]
    if not slips:
        return
    shown = "; ".join(_slip_words(c) for c in slips[:3])
    more = f" (and {len(slips) - 3} more)" if len(slips) > 3 else ""
    # a release in deg/s that is still beyond its limit as rad/s (a throw a little too fast)
    fast = next((c for c in slips if c.quantity == "velocity" and np.radians(abs(c.before)) <= SLIP * abs(c.limit)), None)
    degrees = (f"; read as deg/s, {fast.before:.6g} is {np.radians(fast.before):.4g} rad/s" if fast is not None else "")
    raise InputError(f"{plural(len(slips), 'value')} far beyond the robot's limits, a unit or scale slip, not a throw "
                     f"to clip: {shown}{more}; check the path's units (rlff reads rad and rad/s, as rlff generate "
                     f"writes them{degrees}) and {_mapping_words(mapping)}, through which the path was mapped")


def _require_thrown(mapping: RobotMapping | ArmMapping, points: JointTrajectory, report: ClipReport) -> None:
    """Refuse a path that leaves every driven joint at rest at its release: the ball would not be
    thrown. One joint at rest while another moves there is still a throw. The message names why:
    a release moving against the path's direction, which stopping (0, as the mapping does) leaves
    at rest; a release beyond a position limit, where clipping holds the joint (until 2026-12-07
    ``clip`` exported that with exit 0, and ``rlff sim throw`` warned); or a path whose release
    is itself at rest."""
    last = len(points) - 1
    driven = [points.joint_index(joint) for joint in mapping.driven_joints]
    if np.any(points.velocities[last, driven] != 0):
        return
    # not a velocity set to 0 with its joint held at a clipped position
    stopped = [change for change in _faults(report, last)[1] if change.point == last and change.limit is None]
    if stopped:
        shown = "; ".join(f"{c.joint} velocity {c.before:.6g} {c.unit}" for c in stopped)
        raise InputError(f"the ball would not be thrown: the release ({shown}) moves against the path's direction, and "
                         "stopped (0 rad/s) it leaves every driven joint at rest there; a path from uncleaned "
                         "demonstrations? clean them (rlff data preprocess --preset thesis), then fit and generate again")
    held = [change for change in report.changes if change.point == last and change.quantity == "position"
            and change.joint in mapping.driven_joints]
    if held:
        shown = "; ".join(f"{c.joint} at {c.before:.6g} rad, beyond its limit {c.limit:g} rad" for c in held)
        raise InputError(f"the ball would not be thrown: the release ({shown}) is beyond a position limit, where "
                         "clipping would hold it at rest with every driven joint; throw for a nearer basket (rlff "
                         "sim reach says how far the arm throws), or give a robot file whose range covers the "
                         f"release (check {_mapping_words(mapping)}, through which the path was mapped)")
    raise InputError("the ball would not be thrown: the path's release (its last point) is at rest, every driven "
                     "joint's velocity 0 there; give a path that ends at its release, as rlff generate writes it "
                     "(its default grid ends at the demonstrations' release)")


def _require_released_moving(path: Path, trajectory: JointTrajectory) -> None:
    """Refuse a robot ``trajectory`` (read from the file ``path``) whose every joint is at rest at
    its release (none faster than :data:`rlff.trajectory.planner.MOVING`, the rest
    :func:`rlff.robot.export.require_release` reads; a velocity of 1e-9 rad/s left by rounding is
    no throw either): the ball would not be thrown. An rlff before 2026-12-07 exported such files
    with ``--clip`` of a path :func:`_require_thrown` now refuses, and they were exported and sent
    again as they were (``rlff sim throw`` warned)."""
    if trajectory.release_time is None:
        return
    release = int(np.argmin(np.abs(trajectory.time - trajectory.release_time)))
    if np.any(np.abs(trajectory.velocities[release]) > MOVING):
        return
    raise InputError(f"{path}: the ball would not be thrown: every joint is at rest at the release "
                     f"({trajectory.release_time:.6g} s); an rlff before 2026-12-07 exported such throws with --clip "
                     "(a release beyond a position limit, or one moving against the path's direction from uncleaned "
                     "demonstrations): export again from the generated path or attempts log, and this rlff refuses "
                     "it or says why")


def _looks_like_degrees(change) -> bool:
    """Whether ``change``, a velocity beyond its limit, is one only degrees read as radians explain:
    more than :data:`DEGREES_SLIP` times the limit, and within it once converted to rad/s."""
    if change.quantity != "velocity" or change.limit is None:
        return False
    speed, limit = abs(change.before), abs(change.limit)
    return speed > DEGREES_SLIP * limit and np.radians(speed) <= limit


def _degrees_hint(change) -> str:
    """What to do of a velocity :func:`_looks_like_degrees`: give the path in rad/s, not clip it."""
    return (f"the path's velocities look like deg/s, not rad/s ({abs(change.before / change.limit):.0f} times the "
            f"limit; as deg/s {abs(np.radians(change.before)):.4g} {change.unit}, within it): rlff reads rad and "
            "rad/s, as rlff generate writes them; give the velocities in rad/s (deg/s × π/180) rather than "
            "clip (--clip) them")


def _fault(change, last: int) -> str:
    """One value of a path the robot would not execute as asked, for a message: beyond a limit,
    or a velocity against the path's direction (which the mapping stops: 0, not a limit)."""
    release = " (the release)" if change.point == last else ""
    if change.limit is None:
        return (f"point {change.point}: {change.joint} velocity {change.before:.6g} {change.unit} moves it against the "
                f"path's direction{release}, which clip (--clip) stops (0 {change.unit})")
    value, limit = apart(change.before, change.limit)  # as many digits as tell them apart
    return (f"point {change.point}: {change.joint} {change.quantity} {value} {change.unit} beyond the "
            f"limit {limit} {change.unit}{release}")


#: Largest relative difference between a generated path's time steps and those its angle and
#: velocity give (the model writes them from the same formula: they agree to rounding).
TIME_AGREEMENT = 0.01


def _require_time_agrees(angle: np.ndarray, velocity: np.ndarray, time: np.ndarray) -> None:
    """Refuse a path whose ``time`` column disagrees with its angle and velocity.

    Where both ends of a step move at 10 % of the peak speed or more, the step takes
    ``2 |d angle| / (v_i + v_{i+1})`` (:func:`rlff.timing.time_along_path`); a time
    column stretched, or velocities scaled with the time kept, differ from it.
    """
    angle, velocity, time = (np.asarray(a, dtype=float) for a in (angle, velocity, time))
    if time.shape != angle.shape or angle.size < 2:
        return  # the mapping refuses these, naming them
    speed = np.maximum(np.sign(angle[-1] - angle[0]) * velocity, 0.0)
    if speed.max() <= 0:
        return  # nothing moves along the path: timed by |velocity|, and refused as backward by the mapping
    fast = np.minimum(speed[:-1], speed[1:]) >= 0.1 * speed.max()
    expected = 2 * np.abs(np.diff(angle)) / np.maximum(speed[:-1] + speed[1:], 1e-300)
    ratio = np.diff(time) / expected
    bad = np.flatnonzero(fast & (np.abs(ratio - 1) > TIME_AGREEMENT))
    if bad.size:
        i = int(bad[0])
        raise InputError(
            f"rows {i + 1} to {i + 2}: the time column takes {time[i + 1] - time[i]:.6g} s where angle and "
            f"velocity take {expected[i]:.6g} s (angle {angle[i]:.6g} -> {angle[i + 1]:.6g} rad at "
            f"{velocity[i]:.6g} and {velocity[i + 1]:.6g} rad/s; {ratio[i]:.3g} times as long, "
            f"{bad.size} steps disagree by more than {TIME_AGREEMENT:.0%}): time, angle and velocity "
            f"do not belong together{_time_hint(angle, speed, time, ratio[fast], bad)}")


def _time_hint(angle: np.ndarray, speed: np.ndarray, time: np.ndarray, ratios: np.ndarray, bad: np.ndarray) -> str:
    """What likely parted a path's time column from its angle and velocity (:func:`_require_time_agrees`),
    as the end of its message, ``""`` when neither: a time in milliseconds (most of the steps that
    move, ``ratios``, about 1000 times as long), or a file rounded to fewer decimals than rlff writes
    (:func:`_shown_decimals`) whose rounding covers every step that disagrees (``bad``: indices of
    steps; ``speed`` (T,) the velocity along the path, rad/s)."""
    if np.mean(np.abs(ratios / 1000 - 1) <= 0.1) > 0.5:
        return "; is the time column in milliseconds? rlff reads seconds: divide it by 1000"
    shown = {name: _shown_decimals(column) for name, column in (("angle", angle), ("velocity", speed), ("time", time))}
    rounded = {name: decimals for name, decimals in shown.items() if decimals is not None}
    if not rounded:
        return ""
    # each value within half a unit of its last digit shown: a step's ends within one unit
    unit = {name: 10.0 ** -shown[name] if shown[name] is not None else 0.0 for name in shown}
    step, moved = np.diff(time)[bad], np.abs(np.diff(angle))[bad]
    total = (speed[:-1] + speed[1:])[bad]
    shortest = 2 * np.maximum(moved - unit["angle"], 0.0) / (total + unit["velocity"])
    longest = 2 * (moved + unit["angle"]) / np.maximum(total - unit["velocity"], 1e-300)
    slack = 1 + TIME_AGREEMENT
    if np.any(step + unit["time"] < shortest / slack) or np.any(step - unit["time"] > longest * slack):
        return ""
    counts = sorted(set(rounded.values()))
    to = (f"{counts[0]} decimals" if len(counts) == 1
          else ", ".join(f"{name} {decimals}" for name, decimals in rounded.items()) + " decimals")
    return (f"; the file looks rounded to {to} (a spreadsheet?), which explains the disagreement; rlff generate "
            "writes full precision: generate the path again, or keep full precision where it is saved")


def _shown_decimals(values: np.ndarray, most: int = 8) -> int | None:
    """The fewest decimals (0 to ``most``) every value of ``values`` is written with, or None for
    values of more (as rlff generate writes them: full precision)."""
    for decimals in range(most + 1):
        scaled = values * 10.0**decimals
        if np.all(np.abs(scaled - np.round(scaled)) <= 1e-6 * np.maximum(1.0, np.abs(scaled))):
            return decimals
    return None


def plan(
    mapping: RobotMapping,
    angle: np.ndarray,
    velocity: np.ndarray,
    time: np.ndarray | None = None,
    period: float | None = DEFAULT_PERIOD,
    clip: bool = False,
    start: np.ndarray | None = None,
    approach_speed: float = APPROACH_SPEED,
) -> RobotPlan:
    """Map a human path (angle (T,) rad, velocity (T,) rad/s, time (T,) s or None) and plan it.

    The one-joint form of :func:`plan_path`; its parameters and errors are those.
    """
    path = {"angle": angle, "velocity": velocity}
    if time is not None:
        path["time"] = time
    return plan_path(mapping, path, period=period, clip=clip, start=start, approach_speed=approach_speed)


def plan_path(
    mapping: RobotMapping | ArmMapping,
    path: HumanPath,
    *,
    bearing: float = 0.0,
    period: float | None = DEFAULT_PERIOD,
    clip: bool = False,
    start: np.ndarray | None = None,
    approach_speed: float = APPROACH_SPEED,
    throw: bool = False,
) -> RobotPlan:
    """Map a human path to the robot (one joint or the whole arm) and plan it.

    Parameters
    ----------
    mapping : RobotMapping or ArmMapping
    path : HumanPath
        The generated throw: columns (T,) ``angle`` (rad), ``velocity`` (rad/s), the other
        driven human joints' positions and velocities, optionally ``time`` (s); its last sample
        is the release.
    bearing : float
        The basket's bearing (deg): the throw's first pose has the bearing joint turned to it,
        so the approach from ``start`` turns the arm to face the basket.
    period : float
        Controller period (s) of the planned trajectory; must be positive.
    clip : bool
        Clip path positions and the release velocity into the limits (each change reported)
        instead of refusing them.
    start : array of shape (J,), optional
        Where the arm is (rad, the robot's joints in order); default the throw's first pose.
    approach_speed : float
        Share of the joints' limits the approach from ``start`` uses
        (:data:`rlff.trajectory.planner.APPROACH_SPEED`; 1: the limits themselves).
    throw : bool
        With ``clip`` too, refuse a path that is no throw to clip (:func:`require_a_throw`: a unit
        or scale slip, a release at rest, stopped or held at a limit by clipping), as without
        ``clip`` always: what a file's path gets (:func:`load_for_robot`). The learning loop's
        proposals saturate instead.

    Raises
    ------
    InputError
        A bad path, a ``time`` that disagrees with its angle and velocity, a value beyond a limit
        (without ``clip``), a slip or a release at rest (without ``clip``, or with ``throw``), or a plan that fails the check (:class:`rlff.trajectory.check.MotionLimitError`,
        e.g. no room to brake, or a link below the plane the base stands on:
        :func:`rlff.robot.links.require_above_base`).
    """
    check_period(period)
    for column in mapping.human_columns:
        if column in path:
            require_radians(path[column], f"the path's {column}")
    if path.get("time") is not None and "angle" in path and "velocity" in path:
        _require_time_agrees(path["angle"], path["velocity"], path["time"])
    points, report = mapping.path_to_robot(path, bearing=bearing, clip=True)
    if throw or not clip:
        require_a_throw(mapping, points, report)
    if not clip:
        _require_unclipped(report, len(points) - 1, isinstance(mapping, ArmMapping) and len(mapping.joints) > 1)
    joints = mapping.robot.joints
    trajectory = plan_throw(points, joints, start=start, period=period, approach_speed=approach_speed)
    check_trajectory(trajectory, joints, start=points.positions[0] if start is None else start, start_at_rest=True)
    require_above_base(mapping.robot, trajectory, "the planned throw")
    return RobotPlan(points, trajectory, report if clip else ClipReport())


def slowed_to_limits(mapping: RobotMapping | ArmMapping, path: HumanPath) -> tuple[HumanPath, str]:
    """``path`` with every velocity column times one factor, the largest that brings each driven
    joint's release within its speed limit, and what was done (one phrase; ``""`` and ``path``
    itself when every release is within its limit, or more than :data:`SLIP` times it, or ``mapping``
    drives one joint).

    What ``--clip`` does to a throw of several joints: clipped each on its own, their release
    velocities no longer point where the model's did (a tester's throw with joints 2, 3 and 5
    went out with joint_2 at 0.38 of its speed, joint_3 at 0.61 and joint_5 unchanged, and came
    down 1 m beyond its 0.75 m basket). Slowed as a whole, as the learning loop scales a throw
    (docs/learn.md, ``scale_speed``), the release keeps its direction and the positions along the
    path stay; a ``time`` column takes 1 / factor as long.
    """
    if not isinstance(mapping, ArmMapping) or len(mapping.joints) < 2:
        return path, ""
    shares = {column: abs(float(np.asarray(path[column])[-1])) / limit
              for column, limit in mapping.max_human_speeds().items() if column in path}
    column = max(shares, key=shares.get, default=None)
    if column is None or not 1.0 < shares[column] <= SLIP:  # beyond SLIP a slip, which plan_path(throw=True) refuses
        return path, ""
    factor = 1.0 / shares[column]
    fastest = next(m for m in mapping.joints if velocity_column(m.human) == column)
    limit = mapping.robot.joint(fastest.joint).max_velocity
    return scaled_speed(path, factor), (f"the whole throw slowed to {factor:.3g} of its speed, one factor for every joint so that its release "
                    f"keeps the model's direction ({fastest.joint}'s release {limit / factor:.4g} rad/s at its limit "
                    f"{limit:.4g} rad/s)")


def is_comau_program(path: Path) -> bool:
    """Whether ``path`` is a file that starts as a Comau program does (:data:`rlff.robot.comau.HEADER`)."""
    if not path.is_file():
        return False
    with open(path, "rb") as stream:
        return stream.read(len(COMAU_HEADER)).decode("utf-8", errors="replace") == COMAU_HEADER


def robot_file_kind(path: Path) -> str:
    """Which kind ``path`` is, :data:`GENERATED` or :data:`ROBOT_TRAJECTORY`: a JSON by its suffix, a
    CSV by its header (:func:`rlff.kinds.csv_kind`); :class:`InputError` in one line for any other
    file (demonstrations said to be, with what to make of them)."""
    if path.is_dir():
        raise InputError(f"{path} is a folder (a ROS 2 bag?): give a generated path CSV or a robot "
                         "trajectory JSON/CSV that `rlff robot export` wrote")
    if not path.is_file():
        raise InputError(f"{path}: no such file")
    if path.suffix.lower() == ".json":
        return ROBOT_TRAJECTORY
    if is_ros1_bag(path):  # not read as a CSV whose column is its magic line
        raise InputError(f"{path} is a ROS 1 bag: give a generated path CSV or a robot trajectory JSON/CSV "
                         "that `rlff robot export` wrote (`rlff robot send` takes the bag itself)")
    if is_comau_program(path):  # not read as a CSV whose column is its header line
        raise InputError(f"{path} is a Comau program (`rlff robot export -f comau` writes it), which runs on the "
                         "Comau controller and rlff does not read back: give the robot trajectory JSON/CSV it was "
                         "exported from, or the generated path it was planned from")
    header = header_names(path)
    if not header:  # no UTF-8 text (a gzip, UTF-16: with what to do first), or blank
        remedy = binary_kind(path)
        said = f"{remedy}; then" if remedy else f"{file_kind(path)}:"
        raise InputError(f"{path} is {said} give a generated path CSV or a robot trajectory JSON/CSV that "
                         "`rlff robot export` wrote")
    kind = csv_kind(header)
    if kind == DATASET:  # it was blamed on its time column, or its velocities
        raise InputError(f"{path} is demonstrations (a dataset, its throws by the trajectory column), not a generated "
                         f"path: fit a model to them (rlff fit {path} -o model.json), generate a throw (rlff generate "
                         "model.json -c distance=D -o path.csv) and give that")
    if kind is not None:
        return kind
    with open(path, "rb") as handle:
        opening = handle.read(64).lstrip()[:1]
    if opening in (b"{", b"["):
        raise InputError(f"{path}: holds JSON, not CSV: a robot trajectory JSON needs the .json suffix")
    raise InputError(f"{path}: neither a generated path (angle, velocity[, time]) nor a robot trajectory "
                     f"(time, <joint>_position, ...); columns: {_brief_columns(header)}{separator_hint(path)}")


def _brief_columns(header: Sequence[object], shown: int = 8, width: int = 40) -> str:
    """A CSV header's first ``shown`` column names, each cut to ``width`` characters, for an
    error of one line (the header of a file of another kind can be a whole file long)."""
    names = [str(name) if len(str(name)) <= width else str(name)[:width] + "..." for name in header[:shown]]
    more = f" and {len(header) - shown} more" if len(header) > shown else ""
    return ", ".join(names) + more


def load_for_robot(
    path: str | Path,
    robot: Robot,
    period: float | None = DEFAULT_PERIOD,
    clip: bool = False,
    start: np.ndarray | None = None,
    *,
    joints: Sequence[str] | None = None,
    bearing: float | None = None,
    approach_speed: float = APPROACH_SPEED,
) -> tuple[str, RobotPlan]:
    """The checked trajectory of a generated path or robot trajectory file for ``robot``.

    Returns the kind (:data:`GENERATED` or :data:`ROBOT_TRAJECTORY`) and the plan; for a robot
    trajectory, ``points`` and ``trajectory`` are the file's trajectory and ``period``, ``clip``,
    ``joints`` and ``bearing`` do not apply (a file beyond a limit is refused, not changed; the
    commands refuse them given for one: :func:`require_planned`).
    ``start`` (J,) is where the arm is (rad, ``robot``'s joints in order) to plan a generated
    throw from, with an approach at ``approach_speed`` of the limits (:func:`plan_path`); default the
    throw's first pose (a robot trajectory is checked on its own).
    ``joints`` are the robot joints a generated path drives (:func:`rlff.robot.mapping.mapping_for`;
    None: the one-joint mapping), ``bearing`` the basket's bearing (deg; None: the file's
    ``bearing`` column, else 0). With ``clip``, a path of several joints whose release is beyond a
    speed limit is first slowed as a whole (:func:`slowed_to_limits`), not clipped joint by joint;
    a path that is no throw to clip (:func:`require_a_throw`) is refused with ``clip`` too.
    """
    from rlff.robot.export import read_csv, read_json, read_planned_for, require_release

    path = Path(path)
    kind = robot_file_kind(path)
    if kind == GENERATED:
        generated = read_generated_path(path)
        mapping = mapping_for(robot, joints)
        where = "--bearing" if bearing is not None else "the path's bearing column"
        bearing = generated.context.get("bearing", 0.0) if bearing is None else bearing
        unused = [name for name in generated.joints if name in ARM_JOINT_COLUMNS]
        # a whole-arm path thrown with one joint: its other joints' columns would go unseen
        hint = (f"{path.name} holds {', '.join(unused)} columns (a whole-arm path), thrown with one joint: give "
                "joints (--joints, e.g. joint_2,joint_3, as rlff generate --joints wrote it) to drive them too"
                if joints is None and unused else None)
        human, slowed = slowed_to_limits(mapping, generated.to_path()) if clip else (generated.to_path(), "")
        try:
            planned = plan_path(mapping, human, bearing=bearing, period=period, clip=clip, start=start,
                                approach_speed=approach_speed, throw=True)
        except InputError as exc:
            said = f"{exc} ({where})" if str(exc).startswith("bearing ") else str(exc)
            raise type(exc)(f"{path}: {said}") from None
        return kind, replace(planned, notes=(hint,) if hint else (), slowed=slowed)
    trajectory = read_json(path) if path.suffix.lower() == ".json" else read_csv(path)
    own = require_planned_for(path, read_planned_for(path), robot)
    try:
        check_trajectory(trajectory, robot.joints, start_at_rest=True)
        require_above_base(robot, trajectory, "the trajectory")
    except InputError as exc:  # a file that keeps no robot may be another arm's, failing on this one's limits
        raise type(exc)(f"{path}: {exc}{'' if own else checked_against(robot)}") from None
    trajectory = require_release(path, trajectory)
    _require_released_moving(path, trajectory)
    return kind, RobotPlan(trajectory, trajectory, ClipReport())


def require_planned(path: str | Path, planned: RobotPlan, options: Sequence[str]) -> None:
    """Refuse ``options`` (``--bearing``, ``--period``, ...: given by the user) that shape a plan
    when ``planned`` is a robot trajectory, taken as it is: they would change nothing."""
    if not options or planned.points is not planned.trajectory:
        return
    they, them = ("it", "it") if len(options) == 1 else ("they", "them")
    raise InputError(f"{', '.join(options)}: {path} is a robot trajectory, which is checked and taken as it is, "
                     f"not planned again, so {they} would change nothing; leave {them} out, or give {them} with "
                     "the generated path (rlff generate) or attempts log (rlff learn --log) it was planned from")
