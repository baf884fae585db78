"""The one motion planner between the model and every consumer (exports, send, serve, sim).

A throw leaves rlff as three jerk-limited phases, each planned by ruckig (Berscheid & Kröger
2021: time-optimal state-to-state motion under per-joint velocity, acceleration and jerk limits,
in closed form, in microseconds):

1. approach: from ``start`` (the arm's pose, at rest) to the throw's first pose, at rest, at
   :data:`APPROACH_SPEED` of the limits (slow enough to be seen coming and stopped);
2. the throw: from the first pose at rest to the release, reaching exactly the release
   position and velocity the model asked (its last point), with zero acceleration there, never
   faster than the release speed of each joint (it accelerates into the release, or reaches the
   release speed early and holds it: the servos are settled when the ball goes); a path too short to reach the release
   speed from rest within the limits is preceded by a wind-up (the arm backs up first), refused
   like any motion that would leave a position limit;
3. braking: from the release to rest, within the position limits; a throw with no room to brake
   is refused, naming the joint and the numbers.

Why not keep the model's own timing between the first pose and the release: the model gives a
velocity at each sampled angle, and timing that (t = integral of dq / v) gives accelerations
and jerks that no arm follows (35 rad/s^2 and 16,000 rad/s^3 for a nominal throw, issue 12). What
the ball's flight depends on is the release state alone, which is kept exactly. toppra
(time-optimal path parametrisation) keeps the model's sampled path but bounds only velocity and
acceleration: its profiles switch acceleration instantly (unbounded jerk), so it is the peer of
``benchmarks/motion.py``, not the planner.

Every phase lasts a whole number of controller periods (ruckig's discrete durations) and is
sampled at every period with the positions, velocities and accelerations of ruckig's profile:
the samples are evenly spaced and the release falls on the controller's clock.

The controller's quintic interpolation between two samples is the profile itself except in a
step where the profile's jerk jumps (a corner of its acceleration): there the quintic, smooth
through the step, overshoots the profile by up to ``jerk * period / 24`` in acceleration and
``jerk * period**2 / 90`` in velocity (:data:`ACCELERATION_OVERSHOOT`,
:data:`VELOCITY_OVERSHOOT`). The profiles use :data:`MARGIN` of the velocity and acceleration
limits and a jerk low enough that both overshoots fit in what the margin leaves
(:func:`planning_jerk`): a robot file's ``max_jerk`` far above ``max_acceleration / period``
asks for acceleration changes within one controller period, which no quintic through the
samples follows, so such a jerk is planned lower.
"""

from __future__ import annotations

from collections.abc import Sequence
from itertools import chain

import numpy as np

from rlff.errors import InputError
from rlff.limits import apart
from rlff.trajectory.check import MotionLimitError, violation_counts
from rlff.trajectory.joint import JointTrajectory
from rlff.trajectory.limits import POSITION_MARGIN, JointLimits
from rlff.trajectory.motion_limits import MotionLimits, motion_limits

#: Controller period (s) a plan is sampled at unless told otherwise.
DEFAULT_PERIOD = 0.002
#: Speed (rad/s) above which a joint of a throw moves: a joint released at this speed or slower is
#: released at rest, and its cap is its peak in the throw instead (:func:`plan_throw`).
MOVING = 1e-6
#: Share of the velocity and acceleration limits the profiles use; the rest absorbs the quintic's
#: overshoot at the profiles' corners (:func:`planning_jerk`).
MARGIN = 0.99
#: Share of each joint's velocity, acceleration and jerk limits the approach uses (the move from
#: the arm's pose to the throw's first pose, before anything is thrown). The throw and the
#: braking need the limits themselves; the approach does not, and an arm that crosses the cell at
#: full speed to get to its start gives the people beside it no time to see it coming. A
#: quarter: the built-in Comau's shoulder moves 1.5 rad to its start in 2.5 s at up to 0.69 rad/s
#: instead of 0.9 s at 2.76. Motion planners for shared cells scale further down by default
#: (MoveIt: a tenth); ``--approach-speed`` sets it per run.
APPROACH_SPEED = 0.25
#: Largest overshoot (rad/s^2) of the quintic through the samples of a jerk-limited profile over
#: the profile's acceleration, per rad/s^3 of jerk and s of period, wherever its corners fall in
#: the step: 1/24, for an acceleration plateau 2/3 of a step long starting 1/6 into it (one corner
#: alone: 1/32).
ACCELERATION_OVERSHOOT = 1 / 24
#: The same for the velocity (rad/s), per rad/s^3 of jerk and s^2 of period: 0.0105 at most
#: (an acceleration bump of 0.4 jerk * period ending in the step), rounded up to 1/90.
VELOCITY_OVERSHOOT = 1 / 90


def _vector(values, size: int, label: str) -> np.ndarray:
    array = np.asarray(values, dtype=float).reshape(-1)
    if array.shape != (size,):
        raise InputError(f"{label} must hold one value per joint ({size}), got shape {np.shape(values)}")
    if not np.all(np.isfinite(array)):
        raise InputError(f"{label} holds NaN or inf: {array.tolist()}")
    return array


def _period(period: float | None) -> float:
    period = DEFAULT_PERIOD if period is None else period
    if not (np.isfinite(period) and period > 0):
        raise InputError(f"the controller period must be positive, got {period!r} s")
    return float(period)


#: The slowest approach asked for: a hundredth of the limits (a 1.5 rad move of the Comau's
#: shoulder in 55 s). Below it ruckig's time-optimal profile of a long move fails to compute,
#: and no one waits for it.
SLOWEST_APPROACH = 0.01


def check_approach_speed(share: float) -> float:
    """``share`` checked: a share of the limits, :data:`SLOWEST_APPROACH` <= share <= 1
    (:class:`InputError` otherwise)."""
    if not (np.isfinite(share) and SLOWEST_APPROACH <= share <= 1):
        raise InputError(f"the approach speed is a share of the joints' limits, from {SLOWEST_APPROACH:g} to 1 "
                         f"(0.25: a quarter), not {share:.10g}")
    return float(share)


def planning_jerk(limits: MotionLimits, period: float) -> np.ndarray:
    """The jerk (rad/s^3, shape (J,)) the profiles use at a controller ``period`` (s).

    The robot file's ``max_jerk``, lowered where the quintic's overshoot at a corner
    (:data:`ACCELERATION_OVERSHOOT` ``* jerk * period`` and :data:`VELOCITY_OVERSHOOT`
    ``* jerk * period**2``) would exceed the ``1 - MARGIN`` of the acceleration or velocity limit
    the profiles leave free. The built-in Comau's jerks are below both caps at 2-20 ms periods.
    """
    spare = 1 - MARGIN
    return np.minimum(limits.jerk, spare * np.minimum(
        limits.acceleration / (ACCELERATION_OVERSHOOT * period),
        limits.velocity / (VELOCITY_OVERSHOOT * period**2)))


def _jerk_text(limits: MotionLimits, period: float, j: int) -> str:
    """``max_jerk`` of joint ``j`` for a message, with the jerk planned if lower (:func:`planning_jerk`)."""
    used = planning_jerk(limits, period)[j]
    text = f"max_jerk {limits.jerk[j]:g} rad/s^3"
    return text if used == limits.jerk[j] else f"{text}, planned with {used:.4g} at a {period:g} s period"


def _ruckig(limits: MotionLimits, position, velocity, acceleration, target_position,
            target_velocity, max_velocity: np.ndarray | None, period: float, share: float = 1.0,
            target_acceleration: np.ndarray | None = None) -> JointTrajectory:
    """Sample ruckig's time-optimal profile between two states at ``period`` s, within ``share``
    of the velocity, acceleration and jerk limits (a target velocity or acceleration above that
    share is reached); ``target_acceleration`` None: 0 on arrival.

    Joints already at their target and at rest stay out of ruckig (they hold still whatever the
    others do): fewer degrees of freedom to solve and to sample.
    """
    from ruckig import (
        ControlInterface,
        DurationDiscretization,
        InputParameter,
        Result,
        Ruckig,
        Trajectory,
    )

    if target_acceleration is None:
        target_acceleration = np.zeros_like(position)
    held = (velocity == 0) & (acceleration == 0) & (target_velocity == 0) & (target_acceleration == 0)
    if target_position is not None:
        held &= target_position == position
    moving = np.flatnonzero(~held)
    if moving.size == 0:
        zero = np.zeros((1, position.size))
        return JointTrajectory(limits.names, np.zeros(1), position[None], zero, zero)
    size = moving.size
    request = InputParameter(size)
    request.current_position = position[moving].tolist()
    request.current_velocity = velocity[moving].tolist()
    request.current_acceleration = acceleration[moving].tolist()
    request.target_velocity = target_velocity[moving].tolist()
    request.target_acceleration = target_acceleration[moving].tolist()
    if target_position is None:
        request.control_interface = ControlInterface.Velocity
        request.target_position = position[moving].tolist()
    else:
        request.target_position = target_position[moving].tolist()
    speed = share * MARGIN * limits.velocity
    if max_velocity is not None:
        speed = np.minimum(speed, max_velocity)
    request.max_velocity = np.maximum(speed, np.abs(target_velocity))[moving].tolist()
    request.max_acceleration = np.maximum(share * MARGIN * limits.acceleration,
                                          np.abs(target_acceleration))[moving].tolist()
    request.max_jerk = (share * planning_jerk(limits, period)[moving]).tolist()
    # a whole number of periods: every sample (a phase's end, the release) falls on the
    # controller's clock, and the last step is no shorter than the others
    request.duration_discretization = DurationDiscretization.Discrete
    profile = Trajectory(size)
    try:
        result = Ruckig(size, period).calculate(request, profile)
    except ValueError:  # a code the binding does not name (-101 for limits far too low for the move)
        result = Result.Error
    if result not in (Result.Working, Result.Finished):
        arrival = "" if not np.any(target_acceleration) else f", {target_acceleration.tolist()} rad/s^2"
        raise InputError(f"ruckig cannot plan the motion from {position.tolist()} rad at "
                         f"{velocity.tolist()} rad/s to {request.target_position} rad at "
                         f"{target_velocity.tolist()} rad/s{arrival} ({result.name})")
    steps = round(profile.duration / period)
    time = np.arange(steps + 1) * period
    # (N, 3, size): position, velocity, acceleration; flattened by chain, far faster than
    # numpy's conversion of nested lists
    flat = chain.from_iterable(chain.from_iterable(profile.at_time(t) for t in time.tolist()))
    sampled = np.fromiter(flat, float, count=time.size * 3 * size).reshape(time.size, 3, size)
    states = np.zeros((time.size, 3, position.size))
    states[:, 0] = position
    states[:, :, moving] = sampled
    # the arrival is the target state by definition: drop ruckig's last-bit rounding (1e-16)
    states[-1, 1], states[-1, 2] = target_velocity, target_acceleration
    if target_position is not None:
        states[-1, 0] = target_position
    return JointTrajectory(limits.names, time, states[:, 0], states[:, 1], states[:, 2])


def _require_inside(traj: JointTrajectory, limits: MotionLimits, period: float, what: str,
                    room_from=None, margin: float = 0.0, stops: bool = False) -> None:
    """Raise :class:`MotionLimitError` if ``traj`` leaves a position or speed limit during ``what``.

    A profile leaves the speed limit only from a state that no jerk-limited motion can keep
    inside it (close to the limit and still accelerating towards it). Where the motion turns or
    stops it must also stay ``margin`` (rad) inside a position limit (:data:`POSITION_MARGIN`
    for a throw), unless the positions asked for (its first, and its last unless it ``stops``
    wherever braking ends) are closer: those are checked against the limits themselves.
    """
    speed = np.abs(traj.velocities) > limits.velocity * (1 + 1e-9)
    if np.any(speed):
        row, j = (int(index[0]) for index in np.nonzero(speed))
        peak = float(np.max(np.abs(traj.velocities[:, j])))
        raise MotionLimitError(
            f"{what}: {limits.names[j]} would reach {peak:.6g} rad/s (t = {traj.time[row]:.4f} s), beyond its "
            f"limit {limits.velocity[j]:.6g} rad/s: from {traj.velocities[0, j]:.6g} rad/s accelerating at "
            f"{traj.accelerations[0, j]:.6g} rad/s^2, {_jerk_text(limits, period, j)} cannot turn the "
            "acceleration round in time")
    asked = traj.positions[:1] if stops else traj.positions[[0, -1]]
    for j, name in enumerate(limits.names):
        q = traj.positions[:, j]
        for beyond, limit, side in ((q > limits.upper[j], limits.upper[j], "upper"),
                                    (q < limits.lower[j], limits.lower[j], "lower")):
            if np.any(beyond) and beyond[0] and room_from is None:  # the arm (or the state given) is already there
                raise MotionLimitError(
                    f"{what}: {name} starts at {q[0]:.6g} rad, already beyond its {side} limit {limit:.6g} rad "
                    "in the robot file: move the arm inside its limits, or check the robot file's limits "
                    "against the arm's")
            inward = -1.0 if side == "upper" else 1.0
            kept = limit + inward * margin  # the closest the motion may come, unless asked closer
            kept = max(kept, asked[:, j].max()) if side == "upper" else min(kept, asked[:, j].min())
            extreme = float(q.max() if side == "upper" else q.min())
            if not (np.any(beyond) or (extreme - kept) * -inward > 0):
                continue
            shown, edge = apart(extreme, limit)  # as many digits as tell them apart
            how = (f"beyond its {side} limit {edge} rad" if np.any(beyond) else
                   f"{abs(limit - extreme):.3g} rad inside its {side} limit {edge} rad, within the {margin:g} rad a "
                   "throw keeps clear of a position limit (a controller's software limit faults at the least "
                   "overshoot past it)")
            where = q[0] if room_from is None else room_from[j]
            needs, room = (apart(abs(extreme - where), abs(limit - where), digits=4) if np.any(beyond)
                           else (f"{abs(extreme - where):.4g}", f"{abs(limit - where):.4g}"))
            clear = "" if np.any(beyond) else f", {max(abs(limit - where) - margin, 0.0):.4g} rad less the margin"
            raise MotionLimitError(
                f"{what}: {name} would reach {shown} rad, {how} (it needs {needs} rad from {where:.6g} rad, moving "
                f"at {traj.velocities[0, j]:.6g} rad/s, with max_acceleration {limits.acceleration[j]:g} rad/s^2 and "
                f"{_jerk_text(limits, period, j)}; the limit is {room} rad away{clear})")


def _require_interpolated_speed(traj: JointTrajectory, joints: Sequence[JointLimits], limits: MotionLimits,
                                target_velocity: np.ndarray, period: float, what: str) -> None:
    """Raise :class:`MotionLimitError` if the controller's quintic between the samples of ``traj``
    (one phase, ending at ``target_velocity``) leaves a speed limit.

    With :func:`planning_jerk` it can only where the profile levels off at a target speed above
    :data:`MARGIN` of the limit (a release at the speed limit, reached early and held): the
    overshoot there, up to :data:`VELOCITY_OVERSHOOT` ``* jerk * period**2``, has no room left.
    """
    share = np.abs(target_velocity) / limits.velocity
    if np.all(share <= MARGIN) or violation_counts(traj, joints)["velocity"] == 0:
        return
    j = int(np.argmax(share))
    jerk = planning_jerk(limits, period)[j]
    raise MotionLimitError(
        f"{what}: {limits.names[j]} reaches its target speed {abs(target_velocity[j]):.6g} rad/s, "
        f"{100 * share[j]:.4g} % of its limit {limits.velocity[j]:.6g} rad/s, "
        f"early and holds it; the controller's quintic between the {period:g} s samples overshoots "
        f"where the profile levels off (by up to {VELOCITY_OVERSHOOT * jerk * period**2:.3g} rad/s with "
        f"{_jerk_text(limits, period, j)}) and leaves the limit: aim below the speed limit, or lower "
        "max_jerk or the period")


def plan_transition(
    position: np.ndarray,
    velocity: np.ndarray,
    acceleration: np.ndarray,
    target_position: np.ndarray | None,
    target_velocity: np.ndarray,
    joints: Sequence[JointLimits],
    *,
    period: float | None = DEFAULT_PERIOD,
    max_velocity: np.ndarray | None = None,
    share: float = 1.0,
    target_acceleration: np.ndarray | None = None,
) -> JointTrajectory:
    """The time-optimal jerk-limited motion from one state to another (ruckig).

    Parameters
    ----------
    position, velocity, acceleration : array of shape (J,)
        The current state: rad, rad/s, rad/s^2, joints in the order of ``joints``.
    target_position : array of shape (J,) or None
        Where to arrive (rad); None: only the velocity is targeted (e.g. braking to rest).
    target_velocity : array of shape (J,)
        Velocity (rad/s) on arrival.
    joints : sequence of JointLimits
        The J joints moved, with their position, velocity, acceleration and jerk limits.
    period : float, optional
        Sampling period (s) of the result; default :data:`DEFAULT_PERIOD`.
    max_velocity : array of shape (J,), optional
        A lower speed cap (rad/s) than the joints' limits for this motion.
    share : float
        Share (0 < share <= 1) of the velocity, acceleration and jerk limits the motion uses
        (:data:`APPROACH_SPEED` for an approach); 1: the limits themselves.
    target_acceleration : array of shape (J,), optional
        Acceleration (rad/s^2) on arrival (a goal's first point that is already accelerating);
        default 0.

    Returns
    -------
    JointTrajectory
        From time 0 (the current state) to the arrival, sampled every ``period`` s and at the
        end; a single point when already there.

    Raises
    ------
    MotionLimitError
        The motion would leave a position limit (e.g. no room to brake); the message names the
        joint, the position reached, the limit and the distances.
    InputError
        Bad shapes or values, a joint without acceleration or jerk limits.
    """
    limits = motion_limits(joints)
    size = len(limits.names)
    state = [_vector(values, size, label) for values, label in (
        (position, "position"), (velocity, "velocity"), (acceleration, "acceleration"))]
    target = None if target_position is None else _vector(target_position, size, "target position")
    target_velocity = _vector(target_velocity, size, "target velocity")
    if target_acceleration is not None:
        target_acceleration = _vector(target_acceleration, size, "target acceleration")
    if max_velocity is not None:
        max_velocity = np.minimum(_vector(max_velocity, size, "max_velocity"), MARGIN * limits.velocity)
    period = _period(period)
    traj = _ruckig(limits, *state, target, target_velocity, max_velocity, period, check_approach_speed(share),
                   target_acceleration)
    what = "the transition" if target is not None else "braking to rest"
    _require_inside(traj, limits, period, what)
    _require_interpolated_speed(traj, joints, limits, target_velocity, period, what)
    return traj


def plan_stop(
    position: np.ndarray,
    velocity: np.ndarray,
    acceleration: np.ndarray,
    joints: Sequence[JointLimits],
    *,
    period: float | None = DEFAULT_PERIOD,
) -> JointTrajectory:
    """Brake to rest from a moving state within the acceleration and jerk limits (ruckig).

    The shortest such stop; its arguments and result are those of :func:`plan_transition`
    (a :class:`MotionLimitError` when a joint has no room to stop before its position limit).
    """
    zero = np.zeros(np.size(position))
    return plan_transition(position, velocity, acceleration, None, zero, joints, period=period)


def _fits_at_default_period(phase, period: float) -> bool:
    """Whether ``phase`` (a period (s) -> the phase planned and kept inside the limits, raising
    :class:`MotionLimitError` otherwise), refused at ``period``, fits at :data:`DEFAULT_PERIOD`."""
    if period <= DEFAULT_PERIOD:
        return False
    try:
        phase(DEFAULT_PERIOD)
    except MotionLimitError:
        return False
    return True


def _period_blame(period: float) -> str:
    """What to say of a phase refused at ``period`` (s) that fits at :data:`DEFAULT_PERIOD`."""
    return (f"the {period:g} s controller period leaves no room, not the throw: at that period the profile "
            "changes its acceleration more slowly (its jerk planned lower, so the quintic between samples that far "
            f"apart stays within the limits) and lasts whole periods; the same throw plans at {DEFAULT_PERIOD:g} s: "
            f"give a shorter --period ({DEFAULT_PERIOD:g} for a file, 0.01 for a live goal)")


def _join(phases: Sequence[JointTrajectory]) -> tuple[JointTrajectory, list[float]]:
    """One trajectory of consecutive phases (each from time 0, the next starting where the last
    ended) and the time each phase ends."""
    times, positions, velocities, accelerations, ends = [], [], [], [], []
    offset = 0.0
    for number, phase in enumerate(phases):
        skip = 0 if number == 0 else 1  # a phase's first point is the last one's end
        times.append(phase.time[skip:] + offset)
        positions.append(phase.positions[skip:])
        velocities.append(phase.velocities[skip:])
        accelerations.append(phase.accelerations[skip:])
        offset += phase.duration
        ends.append(offset)
    joined = JointTrajectory(phases[0].joint_names, np.concatenate(times), np.concatenate(positions),
                             np.concatenate(velocities), np.concatenate(accelerations))
    return joined, ends


def plan_throw(
    throw: JointTrajectory,
    joints: Sequence[JointLimits],
    *,
    start: np.ndarray | None = None,
    period: float | None = None,
    approach_speed: float = APPROACH_SPEED,
) -> JointTrajectory:
    """Plan a throw for a real arm: approach, the throw up to its release, braking to rest.

    Parameters
    ----------
    throw : JointTrajectory
        The model's throw mapped to the robot: T >= 2 points of J joints; its first point is the
        throw's start pose, its last the release (position (rad) and velocity (rad/s) kept
        exactly). Its times, accelerations and inner velocities are not used: each joint moves
        no faster than its release speed (a joint released at rest: than its peak in ``throw``).
    joints : sequence of JointLimits
        The robot's joints (a superset of ``throw``'s, any order) with all four limits.
    start : array of shape (J,), optional
        Where the arm is, at rest (rad, joints in ``throw`` order); default the throw's first pose.
    period : float, optional
        Controller period (s) of the samples; default :data:`DEFAULT_PERIOD`.
    approach_speed : float
        Share of the limits the approach from ``start`` uses (:data:`APPROACH_SPEED`).

    Returns
    -------
    JointTrajectory
        Joints in ``throw``'s order, from ``start`` at rest to rest after the release, sampled
        every ``period`` s and at each phase's end; ``release_time`` is the release's time.

    Raises
    ------
    MotionLimitError
        The throw leaves a position limit, its release is faster than a speed limit, or there
        is no room to brake after the release (joint and numbers in the message).
    """
    if len(throw) < 2:
        raise InputError(f"a throw needs at least 2 points (its start and its release), got {len(throw)}")
    limits = motion_limits(joints, throw.joint_names)
    moved = [joint for name in throw.joint_names for joint in joints if joint.name == name]
    period, approach_speed = _period(period), check_approach_speed(approach_speed)
    first, release, release_velocity = throw.positions[0], throw.positions[-1], throw.velocities[-1]
    for index, where in ((0, "the throw's start"), (len(throw) - 1, "the release")):
        q = throw.positions[index]
        outside = (q < limits.lower) | (q > limits.upper)
        if np.any(outside):
            j = int(np.argmax(outside))
            raise MotionLimitError(f"{where} (point {index}): {limits.names[j]} position {q[j]:.6g} rad "
                                   f"outside its limits {limits.lower[j]:.6g}..{limits.upper[j]:.6g} rad")
    too_fast = np.abs(release_velocity) > limits.velocity
    if np.any(too_fast):
        j = int(np.argmax(too_fast))
        raise MotionLimitError(f"the release (point {len(throw) - 1}): {limits.names[j]} velocity "
                               f"{release_velocity[j]:.6g} rad/s beyond the limit {limits.velocity[j]:.6g} rad/s")
    start = first if start is None else _vector(start, len(limits.names), "start")
    rest = np.zeros(len(limits.names))
    phases = []
    if np.any(np.abs(start - first) > 0):
        phases.append(plan_transition(start, rest, rest, first, rest, moved, period=period, share=approach_speed))
    # never faster than the release (a joint released at rest: than its peak in the model): the
    # throw accelerates into the release, or cruises at the release speed when it got there early
    release_speed, peak = np.abs(release_velocity), np.max(np.abs(throw.velocities), axis=0)
    cap = np.where(release_speed > MOVING, release_speed, np.where(peak > MOVING, peak, limits.velocity))
    cap = np.minimum(cap, MARGIN * limits.velocity)
    def throw_at(step: float) -> JointTrajectory:
        traj = _ruckig(limits, first, rest, rest, release, release_velocity, cap, step)
        # from rest inside the limits, the throw leaves them only in a wind-up
        _require_inside(traj, limits, step, "the throw (start to release)", margin=POSITION_MARGIN)
        return traj

    def brake_at(step: float) -> JointTrajectory:
        traj = _ruckig(limits, release, release_velocity, rest, None, rest, None, step)
        _require_inside(traj, limits, step, "no room to brake after the release", room_from=release,
                        margin=POSITION_MARGIN, stops=True)
        return traj

    try:
        throwing = throw_at(period)
    except MotionLimitError as exc:
        raise MotionLimitError(f"{exc}: " + (_period_blame(period) if _fits_at_default_period(throw_at, period) else
                               "the path from the start to the release is too short to reach the release speed from "
                               "rest, so the arm backs up first; a slower release, or a throw further from that limit "
                               "(the robot file's [throwing] angle_offset), leaves room; clipping the throw's points "
                               "does not")) from None
    _require_interpolated_speed(throwing, moved, limits, release_velocity, period, "the throw (start to release)")
    phases.append(throwing)
    try:
        braking = brake_at(period)
    except MotionLimitError as exc:  # what would give the room: the release is the throw's own, or the period
        raise MotionLimitError(f"{exc}: " + (_period_blame(period) if _fits_at_default_period(brake_at, period) else
                               "a slower release, or one further from that limit (the robot file's [throwing] "
                               "angle_offset), leaves room; clipping the throw's points does not")) from None
    phases.append(braking)
    joined, ends = _join(phases)
    return JointTrajectory(joined.joint_names, joined.time, joined.positions, joined.velocities,
                           joined.accelerations, release_time=ends[-2])
