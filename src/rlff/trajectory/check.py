"""The one motion check every trajectory passes before it leaves rlff.

Files, bags, the Comau program, live goals and the simulation all execute what passes
:func:`check_trajectory`, and nothing else. It asks what a real arm's controller needs:

- times start at 0 or later and strictly increase (:class:`JointTrajectory` ensures it);
- at every point, positions, velocities and accelerations are within the joint's limits, and a
  joint the trajectory moves is not on a position limit (within :data:`LIMIT_SLACK`): a real
  controller's software limit faults at the least overshoot past it (a joint held still on a
  limit, which the trajectory does not put there, is an :class:`OnLimitWarning`);
- positions and velocities agree: over a step of ``dt`` s, a motion whose acceleration stays
  within ``A`` moves ``dt (v0 + v1) / 2`` up to ``A dt^2 / 4`` (the trapezoid rule's error bound,
  ``|integral of (t - dt/2) a(t) dt| <= A dt^2 / 4``); a file whose time column was stretched,
  whose velocities were scaled, or whose positions outrun clipped velocities fails here;
- between the points, under the interpolation the controller uses, the path stays within the
  position, velocity and acceleration limits. rlff assumes ros_control's
  joint_trajectory_controller: a quintic polynomial through both points' positions,
  velocities and accelerations (what it uses when a point has accelerations, which every rlff
  export writes); each step is checked at :data:`SUBDIVISIONS` - 1 inner instants;
- it starts where the arm is (within ``position_tolerance``, at the arm's velocity) and ends
  at rest; with ``start_at_rest`` (every file, bag and program rlff writes for a robot, and every
  robot trajectory it reads) it also starts at rest: a controller starts a trajectory from the
  arm standing still, and a first point at speed asks for a step in velocity it cannot make.

A refusal is a :class:`MotionLimitError` naming the point (index and time), the joint, the
quantity, the value and the limit. The jerk limit is not checked here: it is a property of the
planner's profiles (see :mod:`rlff.trajectory.planner`), which no controller reads from a
trajectory file.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence

import numpy as np

from rlff.errors import InputError
from rlff.limits import apart
from rlff.trajectory.joint import JointTrajectory
from rlff.trajectory.limits import POSITION_MARGIN, JointLimits
from rlff.trajectory.motion_limits import motion_limits

#: Inner instants checked per step are ``k / SUBDIVISIONS`` of it, k = 1 .. SUBDIVISIONS - 1.
SUBDIVISIONS = 8
#: Relative slack on every limit: rounding in a file (17 digits) or a polynomial fit, no more.
LIMIT_SLACK = 1e-6
#: Defaults of :func:`check_trajectory`'s tolerances: start pose (rad), velocity at the start and
#: at the end (rad/s), acceleration at the end (rad/s^2).
POSITION_TOLERANCE = 1e-3
VELOCITY_TOLERANCE = 1e-3
ACCELERATION_TOLERANCE = 1e-2

_UNITS = {"position": "rad", "velocity": "rad/s", "acceleration": "rad/s^2"}


class MotionLimitError(InputError):
    """A trajectory a real arm cannot (or should not) execute; the message says where and why."""


class OnLimitWarning(UserWarning):
    """A trajectory that holds a joint still on a position limit: it does not move it there, so it
    is not refused, but a controller's software limit may fault on the arm resting there."""


def _first(excess: np.ndarray) -> tuple[int, int, int] | None:
    """(row, column, count) of the first True of a (N, J) array in row order, or None."""
    rows, columns = np.nonzero(excess)
    if rows.size == 0:
        return None
    return int(rows[0]), int(columns[0]), int(rows.size)


def _more(count: int, where: str = "beyond it") -> str:
    return f" ({count - 1} more values {where})" if count > 1 else ""


def _check_points(traj: JointTrajectory, values: dict[str, np.ndarray], lower: np.ndarray,
                  upper: np.ndarray, where, moving: np.ndarray) -> None:
    """Raise for the first value of ``values[quantity]`` (N, J, in time order) outside
    ``lower``..``upper``, or a position of a ``moving`` joint ((J,) bool) on its limit (within the
    slack) that the trajectory moved it to: a joint that starts on a limit (where the arm stands)
    may leave it, not come back."""
    for quantity, array in values.items():
        low, high = lower[quantity], upper[quantity]
        span = np.maximum(np.abs(low), np.abs(high))
        slack = LIMIT_SLACK * np.maximum(span, 1.0)
        outside = (array < low - slack) | (array > high + slack)
        if quantity == "position":
            # the arm at Comau's zeros has joint_3 on its upper limit 0: every move from there had been refused
            left = np.logical_or.accumulate(np.abs(array - traj.positions[0]) > slack, axis=0)
            outside |= ((array <= low + slack) | (array >= high - slack)) & moving & left
        found = _first(outside)
        if found is None:
            continue
        row, column, count = found
        value = array[row, column]
        limit = high[column] if abs(value - high[column]) < abs(value - low[column]) else low[column]
        unit = _UNITS[quantity]
        shown, edge = apart(value, limit)  # as many digits as tell them apart
        if abs(value - limit) > slack[column]:
            raise MotionLimitError(f"{where(row)}: {traj.joint_names[column]} {quantity} {shown} {unit} "
                                   f"beyond the limit {edge} {unit}{_more(count)}")
        raise MotionLimitError(f"{where(row)}: {traj.joint_names[column]} moves to its position limit: {shown} "
                               f"{unit} on the limit {edge} {unit}, where a controller's software limit faults at the "
                               f"least overshoot; plan the motion to stay inside it (rlff plans throws "
                               f"{POSITION_MARGIN:g} rad inside){_more(count, 'on or beyond a limit')}")


def _warn_held_on_limits(traj: JointTrajectory, lower: np.ndarray, upper: np.ndarray, moving: np.ndarray) -> None:
    """Warn (:class:`OnLimitWarning`) of the joints ``traj`` holds still on a position limit, ``lower``
    and ``upper`` (J,) rad: the trajectory does not move them there, but the arm rests on the limit."""
    slack = LIMIT_SLACK * np.maximum(np.maximum(np.abs(lower), np.abs(upper)), 1.0)
    position = traj.positions[0]
    for j in np.flatnonzero(~moving & ((np.abs(position - lower) <= slack) | (np.abs(position - upper) <= slack))):
        side = "lower" if abs(position[j] - lower[j]) <= slack[j] else "upper"
        warnings.warn(f"the trajectory holds {traj.joint_names[j]} on its {side} position limit "
                      f"({position[j]:.6g} rad), where a controller's software limit faults at the least overshoot; "
                      "move it inside its limit before the trajectory", OnLimitWarning, stacklevel=3)


def _moving(traj: JointTrajectory) -> np.ndarray:
    """Which joints ``traj`` moves, (J,) bool: any change of position, any velocity or acceleration."""
    return ((np.ptp(traj.positions, axis=0) > 0) | np.any(traj.velocities != 0, axis=0)
            | np.any(traj.accelerations != 0, axis=0))


def _quintic(traj: JointTrajectory, fractions: np.ndarray, moving: np.ndarray) -> tuple[np.ndarray, ...]:
    """Position, velocity, acceleration of the quintic through every step at ``fractions``.

    Returns three arrays of shape (T - 1, F, J): step, instant, joint. A joint that holds still
    (``moving``, (J,) bool, False: :func:`_moving`) is its own quintic: it is copied, not computed.
    """
    steps, joints = len(traj) - 1, len(traj.joint_names)
    position = np.broadcast_to(traj.positions[0], (steps, fractions.size, joints)).copy()
    velocity = np.zeros_like(position)
    acceleration = np.zeros_like(position)
    moving = np.flatnonzero(moving)
    if moving.size == 0:
        return position, velocity, acceleration
    h = np.diff(traj.time)[:, None]
    q, v, a = (array[:, moving] for array in (traj.positions, traj.velocities, traj.accelerations))
    p0, p1, v0, v1, a0, a1 = q[:-1], q[1:], v[:-1], v[1:], a[:-1], a[1:]
    dp = p1 - p0
    c3 = (20 * dp - (8 * v1 + 12 * v0) * h - (3 * a0 - a1) * h**2) / (2 * h**3)
    c4 = (-30 * dp + (14 * v1 + 16 * v0) * h + (3 * a0 - 2 * a1) * h**2) / (2 * h**4)
    c5 = (12 * dp - 6 * (v1 + v0) * h - (a0 - a1) * h**2) / (2 * h**5)
    t = fractions[None, :, None] * h[:, :, None]
    c2 = a0[:, None] / 2
    c3, c4, c5 = c3[:, None], c4[:, None], c5[:, None]
    position[:, :, moving] = p0[:, None] + t * (v0[:, None] + t * (c2 + t * (c3 + t * (c4 + t * c5))))
    velocity[:, :, moving] = v0[:, None] + t * (2 * c2 + t * (3 * c3 + t * (4 * c4 + t * 5 * c5)))
    acceleration[:, :, moving] = 2 * c2 + t * (6 * c3 + t * (12 * c4 + t * 20 * c5))
    return position, velocity, acceleration


#: Largest factor by which the positions' steps may differ from what the velocities say over the
#: time column's steps (the median over the steps of fast motion) before the time is taken to be
#: in another unit than seconds.
TIME_UNIT_FACTOR = 2.0


def _require_time_unit(traj: JointTrajectory, moved: np.ndarray, dt: np.ndarray) -> None:
    """Refuse a trajectory whose positions move :data:`TIME_UNIT_FACTOR` times more or less than its
    velocities say over its time steps (the median over every step where a joint moves one way at
    a tenth of its peak speed or more): a time column in milliseconds moves 1000 times less.

    The disagreement test before it allows A dt^2 / 4, which grows with the steps: a time column
    in milliseconds (steps of 2 s) passed it, and the controller's quintic then swung the arm
    0.25 rad off the file's path between samples, within every limit but not the file's motion.

    ``moved`` (T-1, J) rad and ``dt`` (T-1, 1) s are the steps' motion and durations.
    """
    v0, v1 = traj.velocities[:-1], traj.velocities[1:]
    peak = np.max(np.abs(traj.velocities), axis=0)
    fast = (v0 * v1 > 0) & (np.minimum(np.abs(v0), np.abs(v1)) >= 0.1 * peak) & (peak > 0)
    if not fast.any():
        return
    ratio = float(np.median(np.abs(moved[fast]) / (dt * 0.5 * np.abs(v0 + v1))[fast]))
    if 1 / TIME_UNIT_FACTOR <= ratio <= TIME_UNIT_FACTOR:
        return
    unit = next((f", as a time in {name} does" for name, scale in (("milliseconds", 1e-3), ("microseconds", 1e-6),
                                                                  ("nanoseconds", 1e-9))
                 if 0.5 * scale <= ratio <= 2 * scale), "")
    raise MotionLimitError(
        f"the positions move {ratio:.3g} times as far as the velocities say over the time column's steps (the median "
        f"of {int(fast.sum())} steps of fast motion){unit}: is the time in seconds, and are the velocities the "
        "positions' rates in rad/s?")


def violation_counts(traj: JointTrajectory, joints: Sequence[JointLimits]) -> dict[str, int]:
    """How many values of ``traj`` break each rule of :func:`check_trajectory` (0 everywhere: it passes
    the limits), for reports and benchmarks that count rather than refuse.

    Returns
    -------
    dict of str to int
        ``"position"``, ``"velocity"``, ``"acceleration"``: values beyond the limit at the points
        and at the inner instants of the quintic interpolation; ``"disagreement"``: steps whose
        time, positions and velocities disagree; ``"end moving"``: joints not at rest at the end
        (velocity above :data:`VELOCITY_TOLERANCE` or acceleration above
        :data:`ACCELERATION_TOLERANCE`).
    """
    limits = motion_limits(joints, traj.joint_names)
    values = {"position": [traj.positions], "velocity": [traj.velocities], "acceleration": [traj.accelerations]}
    counts = {"disagreement": 0}
    if len(traj) > 1:
        dt = np.diff(traj.time)[:, None]
        said = dt * 0.5 * (traj.velocities[:-1] + traj.velocities[1:])
        allowed = limits.acceleration * dt**2 / 4 * (1 + LIMIT_SLACK) + 1e-9
        counts["disagreement"] = int(np.count_nonzero(np.abs(np.diff(traj.positions, axis=0) - said) > allowed))
        inner = _quintic(traj, np.arange(1, SUBDIVISIONS) / SUBDIVISIONS, _moving(traj))
        for quantity, array in zip(values, inner, strict=True):
            values[quantity].append(array.reshape(-1, len(traj.joint_names)))
    bounds = {"position": (limits.lower, limits.upper), "velocity": (-limits.velocity, limits.velocity),
              "acceleration": (-limits.acceleration, limits.acceleration)}
    for quantity, arrays in values.items():
        low, high = bounds[quantity]
        slack = LIMIT_SLACK * np.maximum(np.maximum(np.abs(low), np.abs(high)), 1.0)
        counts[quantity] = int(sum(np.count_nonzero((a < low - slack) | (a > high + slack)) for a in arrays))
    counts["end moving"] = int(np.count_nonzero((np.abs(traj.velocities[-1]) > VELOCITY_TOLERANCE)
                                                | (np.abs(traj.accelerations[-1]) > ACCELERATION_TOLERANCE)))
    return counts


def check_start(
    traj: JointTrajectory,
    start: np.ndarray,
    start_velocity: np.ndarray | None = None,
    *,
    position_tolerance: float = POSITION_TOLERANCE,
    velocity_tolerance: float = VELOCITY_TOLERANCE,
    labels: Sequence[str] | None = None,
) -> None:
    """Raise :class:`MotionLimitError` unless ``traj`` starts where the arm is: the part of
    :func:`check_trajectory` given its ``start``, with its parameters. ``labels`` (J,) name the
    joints in the message (default ``traj``'s joint names: ``shoulder_lift_joint (joint_2)`` for a
    trajectory in a controller's convention)."""
    names = traj.joint_names
    start = np.asarray(start, dtype=float).reshape(-1)
    expected = np.zeros(len(names)) if start_velocity is None else np.asarray(start_velocity, float)
    if start.shape != (len(names),) or expected.shape != (len(names),):
        raise InputError(f"start must hold one value per joint {list(names)}, got shape {start.shape}")
    labels = names if labels is None else labels
    for label, value, arm, tolerance, unit in (
            ("position", traj.positions[0], start, position_tolerance, "rad"),
            ("velocity", traj.velocities[0], expected, velocity_tolerance, "rad/s")):
        off = np.abs(value - arm)
        if np.any(off > tolerance):
            j = int(np.argmax(off > tolerance))
            raise MotionLimitError(
                f"point 0 (t = {traj.time[0]:.6f} s): {labels[j]} {label} {value[j]:.6g} {unit} is not where the arm "
                f"is ({arm[j]:.6g} {unit}; {off[j]:.3g} {unit} off, tolerance {tolerance:g} {unit})")


def check_trajectory(
    traj: JointTrajectory,
    joints: Sequence[JointLimits],
    *,
    start: np.ndarray | None = None,
    start_velocity: np.ndarray | None = None,
    start_at_rest: bool = False,
    position_tolerance: float = POSITION_TOLERANCE,
    velocity_tolerance: float = VELOCITY_TOLERANCE,
    acceleration_tolerance: float = ACCELERATION_TOLERANCE,
) -> None:
    """Raise :class:`MotionLimitError` unless ``traj`` is safe for a real arm to execute.

    Parameters
    ----------
    traj : JointTrajectory
        T points of J joints; every joint name must be among ``joints``.
    joints : sequence of JointLimits
        The robot's joints: position (rad), velocity (rad/s) and acceleration (rad/s^2) limits.
    start : array of shape (J,), optional
        Where the arm is (rad, joints in ``traj`` order); the first point must be within
        ``position_tolerance`` of it. None: the first point is taken as where the arm is.
    start_velocity : array of shape (J,), optional
        The arm's velocity (rad/s) there; default at rest. Checked only with ``start``.
    start_at_rest : bool
        Require the first point at rest as well as the last (velocity within
        ``velocity_tolerance``, acceleration within ``acceleration_tolerance``): what a robot
        output is (an export, a robot trajectory read back). False for a controller's goal,
        which it starts from the arm's state, whatever that is.
    position_tolerance : float
        Largest distance (rad) of the first point from ``start``.
    velocity_tolerance : float
        Largest speed (rad/s) left at the end, and off ``start_velocity`` at the start.
    acceleration_tolerance : float
        Largest acceleration (rad/s^2) left at the end.

    Raises
    ------
    MotionLimitError
        The first fault found, naming the point (index and time), the joint, the quantity, the
        value and the limit.
    InputError
        A joint unknown to ``joints`` or one without acceleration and jerk limits.
    """
    limits = motion_limits(joints, traj.joint_names)
    names, time = traj.joint_names, traj.time

    def at_point(index: int) -> str:
        return f"point {index} (t = {time[index]:.6f} s)"

    if time[0] < 0:
        raise MotionLimitError(f"{at_point(0)}: time starts before 0")
    if start is not None:
        check_start(traj, start, start_velocity, position_tolerance=position_tolerance,
                    velocity_tolerance=velocity_tolerance)
    lower = {"position": limits.lower, "velocity": -limits.velocity, "acceleration": -limits.acceleration}
    upper = {"position": limits.upper, "velocity": limits.velocity, "acceleration": limits.acceleration}
    moving = _moving(traj)
    _check_points(traj, {"position": traj.positions, "velocity": traj.velocities,
                         "acceleration": traj.accelerations}, lower, upper, at_point, moving)
    if len(traj) > 1:
        dt = np.diff(time)[:, None]
        moved = np.diff(traj.positions, axis=0)
        said = dt * 0.5 * (traj.velocities[:-1] + traj.velocities[1:])
        allowed = limits.acceleration * dt**2 / 4 * (1 + LIMIT_SLACK) + 1e-9
        found = _first(np.abs(moved - said) > allowed)
        if found is not None:
            row, j, count = found
            mean = moved[row, j] / dt[row, 0]
            raise MotionLimitError(
                f"{at_point(row)} to point {row + 1}: {names[j]} moves {moved[row, j]:.6g} rad in "
                f"{dt[row, 0]:.6g} s (mean velocity {mean:.6g} rad/s) but its velocities say "
                f"{traj.velocities[row, j]:.6g} and {traj.velocities[row + 1, j]:.6g} rad/s: time, "
                f"positions and velocities disagree by more than the acceleration limit "
                f"{limits.acceleration[j]:.6g} rad/s^2 allows ({abs(moved[row, j] - said[row, j]):.3g} "
                f"rad against {allowed[row, j]:.3g} rad){_more(count)}")
        _require_time_unit(traj, moved, dt)
        fractions = np.arange(1, SUBDIVISIONS) / SUBDIVISIONS
        inner = [values.reshape(-1, len(names)) for values in _quintic(traj, fractions, moving)]

        def between(flat: int) -> str:
            step, share = divmod(flat, fractions.size)
            instant = time[step] + fractions[share] * (time[step + 1] - time[step])
            return (f"between points {step} and {step + 1} (t = {instant:.6f} s, quintic "
                    "interpolation)")

        _check_points(traj, dict(zip(("position", "velocity", "acceleration"), inner, strict=True)),
                      lower, upper, between, moving)
    _warn_held_on_limits(traj, limits.lower, limits.upper, moving)
    if start_at_rest:
        _require_rest(traj, 0, velocity_tolerance, acceleration_tolerance, at_point)
    _require_rest(traj, len(traj) - 1, velocity_tolerance, acceleration_tolerance, at_point)


def _require_rest(traj: JointTrajectory, point: int, velocity_tolerance: float, acceleration_tolerance: float,
                  at_point) -> None:
    """Raise :class:`MotionLimitError` unless every joint of ``traj`` is at rest at ``point`` (its
    first or its last): speed within ``velocity_tolerance`` (rad/s), acceleration within
    ``acceleration_tolerance`` (rad/s^2)."""
    first = point == 0
    for label, values, tolerance, unit in (("velocity", traj.velocities[point], velocity_tolerance, "rad/s"),
                                           ("acceleration", traj.accelerations[point], acceleration_tolerance,
                                            "rad/s^2")):
        if np.any(np.abs(values) > tolerance):
            j = int(np.argmax(np.abs(values) > tolerance))
            state = f"{traj.joint_names[j]} {label} {values[j]:.6g} {unit}, not at rest (tolerance {tolerance:g} {unit})"
            if not first:
                raise MotionLimitError(f"{at_point(point)}: the trajectory ends with {state}")
            raise MotionLimitError(
                f"{at_point(point)}: the trajectory starts with {state}: a controller starts a trajectory from the "
                "arm at rest, and cannot jump to a moving first point; give a trajectory that starts at rest (rlff "
                "robot export plans one from the generated path or attempts log), or add the motion from rest to "
                "its first point")
