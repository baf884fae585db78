"""Simulated whole-arm throwing demonstrations: shoulder, elbow (and wrist) together.

A person faces the basket and throws overhand in the vertical plane through their shoulder and
the basket (x forward, z up from the floor); the basket's bearing (deg, around the person) only
labels the throw, the arm's motion in its plane is the same. Three joint angles, as a skeleton
tracker gives them (:mod:`rlff.dataset`):

- ``shoulder``: the upper arm's elevation against the torso's downward axis (the person stands
  upright, so against the vertical): 0 hanging, pi/2 horizontal, pi straight up. The upper arm
  points at ``shoulder - pi/2`` above the horizontal, forward.
- ``angle``: the elbow's included angle theta; the forearm points at ``upper + pi - theta``.
- ``wrist``: the included angle w between forearm and hand; the hand, bent back, points at
  ``forearm + pi - w`` (straight at w = pi). Without the wrist joint the hand is held straight.

Segments: :data:`UPPER_ARM` 0.30 m, :data:`FOREARM_ONLY` 0.26 m (elbow to wrist) and
:data:`HAND` 0.09 m (wrist to the ball's centre): straight, the forearm with the hand is the
one-joint people's 0.35 m. The ball leaves with the velocity of the chain's end,
``sum_i L_i * dphi_i/dt * (-sin phi_i, cos phi_i)`` over the segments' directions phi_i.

The throw, with human coordination (proximal to distal) as the MSR Action3D high throws show it
(docs/capture.md, ``benchmarks/whole_arm_people.py``): at rest the arm hangs (shoulder 0.25-0.6
rad, elbow 2.3-2.9 rad); the wind-up raises the upper arm to 1.25-1.65 rad, flexes the elbow
(0.6-0.9 rad) and bends the hand back; the throw goes on raising the upper arm (by about 0.6-1.1
rad, more for farther baskets: above the horizontal at the release, still rising), the elbow
starts extending after the shoulder has started and peaks after it (minimum-jerk moves), the
wrist straightens with the elbow's fastest extension (at most a little before it, as the
recordings show); the elbow stops abruptly near full extension with a small recoil and the arm
comes down a little as it follows through. Every joint
of a throw moves on one clock: the throw's duration D scales all velocities at once, so the
person aims by D: the ball speed the parabola to the basket's rim needs (without drag, to the rim
``height``), times their bias (most people fall short) and a per-throw error; the release also
comes a little early or late from throw to throw. The landing is computed from the release that
actually happens. The recording is the one-joint people's (:mod:`rlff.synthetic.people`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from rlff.ballistics import crossing_distance
from rlff.dataset import BEARING_RANGE, HEIGHT_RANGE, Dataset, velocity_column
from rlff.errors import InputError
from rlff.limits import as_names, check_distance
from rlff.synthetic.people import (
    MAX_ELBOW_SPEED,
    RIM_HEIGHT,
    THESIS_DISTANCES,
    UPPER_ARM,
    Throw,
    check_distinct,
    check_recording,
    minimum_jerk,
    minimum_jerk_speed,
    needed_speed,
    record,
    subject_names,
    throw_meta,
    throws_dataset,
)

#: Forearm, elbow to wrist (m).
FOREARM_ONLY = 0.26
#: Hand, wrist to the ball's centre (m).
HAND = 0.09
#: The thesis' bearings of the basket lines (deg), chapter 5's basket all around the thrower.
THESIS_BEARINGS = (0.0, 30.0, 60.0, 90.0)
#: Rim heights (m): the default basket and two raised ones.
THESIS_HEIGHTS = (0.3, 0.6, 1.0)
#: Joints a whole-arm person may throw with; the elbow always.
ARM_JOINTS = ("shoulder", "elbow", "wrist")
#: Time of the elbow's recoil after the abrupt stop (s).
_SETTLE = 0.2
#: Time of the upper arm's follow-through after the extension stops (s): slower than its swing.
_FOLLOW = 0.5


@dataclass(frozen=True)
class _Style:
    """How one person throws (drawn once per person); angles in rad, times in s or fractions."""

    name: str
    shoulder_height: float  # m
    shoulder_rest: float
    shoulder_wound: float  # elevation after the wind-up
    shoulder_swing: float  # elevation gained during the throw, at a 2.5 m basket
    shoulder_after: float  # the shoulder's swing ends this fraction of the throw after the release
    rest_angle: float  # elbow
    wound_angle: float
    extended_angle: float
    elbow_start: float  # fraction of the throw's duration at which the elbow starts extending
    release_phase: float  # fraction of the elbow's extension at which the ball leaves
    wrist_rest: float
    wrist_cocked: float
    wrist_snapped: float
    wrist_delay: float  # the wrist's snap peaks this fraction of the throw before the elbow's speed
    wrist_span: float  # fraction of the throw the snap lasts
    windup_duration: float
    speed_factor: float  # multiplies the ball speed the throw needs (< 1: falls short)


def _draw_style(rng: np.random.Generator, name: str, bias: float) -> _Style:
    return _Style(
        name=name,
        shoulder_height=rng.uniform(1.35, 1.55),
        shoulder_rest=rng.uniform(0.25, 0.6),
        shoulder_wound=rng.uniform(1.25, 1.65),
        shoulder_swing=rng.uniform(0.75, 0.95),
        shoulder_after=rng.uniform(0.02, 0.15),
        rest_angle=rng.uniform(2.3, 2.9),  # the arm hangs nearly straight
        wound_angle=rng.uniform(0.6, 0.9),
        extended_angle=rng.uniform(2.8, 3.1),
        elbow_start=rng.uniform(0.15, 0.3),
        release_phase=rng.uniform(0.45, 0.55),
        wrist_rest=rng.uniform(2.9, 3.1),
        wrist_cocked=rng.uniform(2.2, 2.5),
        wrist_snapped=rng.uniform(2.95, 3.1),
        wrist_delay=rng.uniform(0.0, 0.08),
        wrist_span=rng.uniform(0.2, 0.3),
        windup_duration=rng.uniform(0.3, 0.5),
        speed_factor=float(np.clip(1.0 - rng.normal(bias, 0.03), 0.7, 1.2)),
    )


def arm_release_state(
    shoulder_height: float,
    shoulder: np.ndarray | float,
    elbow: np.ndarray | float,
    wrist: np.ndarray | float,
    shoulder_rate: np.ndarray | float,
    elbow_rate: np.ndarray | float,
    wrist_rate: np.ndarray | float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The ball's position and velocity at the hand from the arm's three joint angles and rates.

    Parameters
    ----------
    shoulder_height : float
        Shoulder height above the floor (m).
    shoulder, elbow, wrist : float or array of shape (N,)
        Shoulder elevation, elbow and wrist included angles (rad), as in the module docstring.
    shoulder_rate, elbow_rate, wrist_rate : float or array of shape (N,)
        Their rates (rad/s).

    Returns
    -------
    x, z, vx, vz : arrays of shape (N,)
        Position (m; x forward from the shoulder, z up from the floor) and velocity (m/s).
    """
    upper = np.asarray(shoulder, dtype=float) - 0.5 * np.pi
    forearm = upper + np.pi - np.asarray(elbow, dtype=float)
    hand = forearm + np.pi - np.asarray(wrist, dtype=float)
    upper_rate = np.asarray(shoulder_rate, dtype=float)
    forearm_rate = upper_rate - np.asarray(elbow_rate, dtype=float)
    hand_rate = forearm_rate - np.asarray(wrist_rate, dtype=float)
    segments = ((UPPER_ARM, upper, upper_rate), (FOREARM_ONLY, forearm, forearm_rate), (HAND, hand, hand_rate))
    x = sum(length * np.cos(phi) for length, phi, _ in segments)
    z = shoulder_height + sum(length * np.sin(phi) for length, phi, _ in segments)
    vx = -sum(length * rate * np.sin(phi) for length, phi, rate in segments)
    vz = sum(length * rate * np.cos(phi) for length, phi, rate in segments)
    return np.asarray(x), np.asarray(z), np.asarray(vx), np.asarray(vz)


@dataclass(frozen=True)
class _Throw:
    """One throw's motion, whatever its duration: the person's style, this throw's raise of the
    upper arm and its release, the joints that move."""

    style: _Style
    swing: float  # shoulder elevation gained during the throw (rad)
    release_phase: float  # fraction of the elbow's extension at the release
    joints: tuple[str, ...]  # the joints that move, among shoulder, elbow, wrist

    def phases(self, u: float) -> dict[str, tuple[float, float]]:
        """Each joint's progress through its throwing move at throw fraction ``u`` and the
        progress' rate (per unit of throw fraction): {joint: (fraction, rate)}."""
        s = self.style
        moves = {
            "shoulder": (0.0, self.shoulder_end),
            "angle": (s.elbow_start, 1.0),
            "wrist": self.wrist_move,
        }
        out = {}
        for name, (start, end) in moves.items():
            fraction = float(np.clip((u - start) / (end - start), 0.0, 1.0))
            out[name] = (float(minimum_jerk(np.asarray(fraction))), float(minimum_jerk_speed(fraction)) / (end - start))
        return out

    @property
    def wrist_move(self) -> tuple[float, float]:
        """Start and end of the wrist's snap as fractions of the throw's duration: centred on the
        elbow's fastest extension (the middle of its move) or a little before, as in the MSR
        recordings, where the hand is nearly straight at the release."""
        s = self.style
        peak = 0.5 * (s.elbow_start + 1.0) - s.wrist_delay
        return peak - 0.5 * s.wrist_span, peak + 0.5 * s.wrist_span

    @property
    def shoulder_end(self) -> float:
        """The end of the shoulder's swing as a fraction of the throw's duration."""
        return min(self.release_u + self.style.shoulder_after, 1.0)

    @property
    def release_u(self) -> float:
        """The release as a fraction of the throw's duration."""
        return self.style.elbow_start + self.release_phase * (1.0 - self.style.elbow_start)

    def spans(self) -> dict[str, float]:
        """How far each joint moves during the throw (rad)."""
        s = self.style
        return {
            "shoulder": self.swing,
            "angle": s.extended_angle - s.wound_angle,
            "wrist": (s.wrist_snapped - s.wrist_cocked) if "wrist" in self.joints else 0.0,
        }

    def starts(self) -> dict[str, float]:
        """Each joint's angle when the throw starts (rad)."""
        s = self.style
        wrist = s.wrist_cocked if "wrist" in self.joints else np.pi
        # a person who does not throw with the shoulder holds the upper arm raised, as at a release
        shoulder = s.shoulder_wound if "shoulder" in self.joints else s.shoulder_wound + s.shoulder_swing
        return {"shoulder": shoulder, "angle": s.wound_angle, "wrist": wrist}

    def release(self, duration: float) -> tuple[np.ndarray, ...]:
        """Ball position (m) and velocity (m/s) at the release of a throw lasting ``duration`` (s):
        ``x, z, vx, vz`` as :func:`arm_release_state`."""
        phases = self.phases(self.release_u)
        spans, starts = self.spans(), self.starts()
        angle = {name: starts[name] + spans[name] * phases[name][0] for name in spans}
        rate = {name: spans[name] * phases[name][1] / duration for name in spans}
        return arm_release_state(
            self.style.shoulder_height, angle["shoulder"], angle["angle"], angle["wrist"],
            rate["shoulder"], rate["angle"], rate["wrist"],
        )


def _positions(
    throw: _Throw, duration: float, timing: tuple[float, float, float, float]
) -> tuple[Callable[[np.ndarray], dict[str, np.ndarray]], float, float]:
    """The throw's true angles of the joints that move, as a function of time, with the release
    time and the time the extension stops (s).

    ``timing``: the rest before the wind-up, the hold after it (s), the elbow's recoil and the
    shoulder's follow-through (rad).
    """
    s = throw.style
    rest, hold, recoil, follow = timing
    t_windup = rest
    t_hold = t_windup + s.windup_duration
    t_throw = t_hold + hold
    t_stop = t_throw + duration
    spans, starts = throw.spans(), throw.starts()
    u_release = throw.release_u

    def windup(t: np.ndarray, lag: float) -> np.ndarray:
        """Cosine progress of a wind-up that starts ``lag`` of the wind-up late (proximal first)."""
        x = np.clip((t - t_windup - lag * s.windup_duration) / ((1.0 - lag) * s.windup_duration), 0.0, 1.0)
        return 0.5 * (1.0 - np.cos(np.pi * x))

    def progress(t: np.ndarray, start: float, end: float) -> np.ndarray:
        return minimum_jerk(np.clip((t - t_throw - start * duration) / ((end - start) * duration), 0.0, 1.0))

    def positions(t: np.ndarray) -> dict[str, np.ndarray]:
        through = np.sin(0.5 * np.pi * np.clip((t - t_stop) / _SETTLE, 0.0, 1.0))
        after = 0.5 * (1.0 - np.cos(np.pi * np.clip((t - t_stop) / _FOLLOW, 0.0, 1.0)))
        shoulder = s.shoulder_rest + (starts["shoulder"] - s.shoulder_rest) * windup(t, 0.0)
        shoulder = np.where(
            t >= t_hold, starts["shoulder"] + spans["shoulder"] * progress(t, 0.0, throw.shoulder_end) - follow * after,
            shoulder,
        )
        elbow = s.rest_angle + (starts["angle"] - s.rest_angle) * windup(t, 0.25)
        elbow = np.where(t >= t_hold, starts["angle"] + spans["angle"] * progress(t, s.elbow_start, 1.0), elbow)
        # abrupt stop: the extension's velocity is cut at full extension, then a small recoil
        out = {"angle": elbow - recoil * through}
        if "shoulder" in throw.joints:
            out["shoulder"] = shoulder
        if "wrist" in throw.joints:
            wrist = s.wrist_rest + (starts["wrist"] - s.wrist_rest) * windup(t, 0.4)
            out["wrist"] = np.where(t >= t_hold, starts["wrist"] + spans["wrist"] * progress(t, *throw.wrist_move), wrist)
        return out

    return positions, t_throw + u_release * duration, t_stop


def whole_arm_demonstrations(
    seed: int = 0,
    *,
    subjects: int | Sequence[str] = 4,
    distances: Sequence[float] = THESIS_DISTANCES,
    bearings: Sequence[float] = THESIS_BEARINGS,
    heights: Sequence[float] = THESIS_HEIGHTS,
    throws_per_basket: int = 1,
    joints: Sequence[str] = ("shoulder", "elbow"),
    rate_hz: float = 30.0,
    noise: float = 0.03,
    dropped_frames: float = 0.03,
    glitches: float = 0.01,
    bias: float = 0.05,
    throw_error: float = 0.04,
    release_jitter: float = 0.03,
    shape_scatter: float = 0.05,
    all_short: bool = False,
    hit_radius: float = 0.15,
    raw: bool = True,
) -> Dataset:
    """Recorded whole-arm throws of several people at baskets around them.

    Every person throws ``throws_per_basket`` times at every basket of the grid ``distances`` x
    ``bearings`` x ``heights`` (defaults: the thesis' ten distances on its four basket lines, at
    three rim heights: 120 baskets).

    Parameters
    ----------
    seed : int
        Random seed; the same seed gives the same dataset.
    subjects : int or sequence of str
        Number of people (``s01``, ``s02``, ...) or their names.
    distances : sequence of float
        Basket distances (m) from the shoulder, horizontally, along the bearing.
    bearings : sequence of float
        Basket bearings (deg, -180 to 180; 0 straight ahead, positive to the left).
    heights : sequence of float
        Rim heights (m, within :data:`rlff.dataset.HEIGHT_RANGE`, 0 to 1.5).
    throws_per_basket : int
        Throws of each person at each basket.
    joints : sequence of str
        The joints that throw, among ``shoulder``, ``elbow``, ``wrist``; the elbow always (its
        angle is the phase). Without the wrist the hand is held straight and not recorded; without
        the shoulder the upper arm is held raised (as at the release) and is not recorded.
    rate_hz, noise, dropped_frames, glitches : float
        The camera, as :func:`rlff.synthetic.throws.simulate_throws` (noise: of the elbow angle,
        rad; the wrist's is twice it).
    bias, throw_error : float
        Mean fraction of the needed ball speed a person falls short by (per person, sd 0.03) and
        the relative sd of a throw's speed around the person's aim.
    release_jitter : float
        Sd of the release's timing, as a fraction of the elbow's extension (early or late).
    shape_scatter : float
        Relative sd of a throw's shoulder swing around the person's (the joints' shape varies).
    all_short : bool
        Every throw falls short of its basket by more than ``hit_radius`` (failures only).
    hit_radius : float
        Half-width of the basket's opening (m).
    raw : bool
        False: the true motion at the camera rate, no noise, dropped frames or glitches.

    Returns
    -------
    Dataset
        Columns ``time`` (s), ``angle`` (rad, the elbow) and ``velocity`` (rad/s), ``shoulder``
        and ``shoulder_velocity`` and/or ``wrist`` and ``wrist_velocity`` for the joints thrown
        with, ``distance`` (m), and ``bearing`` (deg) and ``height`` (m) when the plan has more
        than one value of them or a value other than the default (0 deg, 0.3 m). Velocities are
        finite differences of the recorded angles over time, as a capture computes them.
        Context: the basket columns present. Metadata ``subject``, ``source`` ("simulated"),
        ``target`` (m), ``landing`` (m, along the bearing at the rim's height), ``hit``,
        ``release_angle`` (rad), ``release_time`` (s), ``glitches``. Ids
        ``<subject>-d<distance>-b<bearing>-h<height>-<k>``.

    Raises
    ------
    InputError
        An unknown joint or none but the elbow missing, a camera setting out of range, an empty
        plan, a bearing, height or distance out of range or given twice, or a basket the person
        cannot reach.
    """
    throwing = _check_joints(joints)
    check_recording(rate_hz, noise=noise, dropped_frames=dropped_frames, glitches=glitches, bias=bias,
                    throw_error=throw_error, release_jitter=release_jitter, shape_scatter=shape_scatter)
    names = subject_names(subjects)
    if not names or not len(distances) or not len(bearings) or not len(heights) or throws_per_basket < 1:
        raise InputError("no throws to simulate: give at least one subject, distance, bearing, height and throw")
    for distance in distances:
        check_distance("basket distance", distance)
    for bearing in bearings:
        if not BEARING_RANGE[0] <= bearing <= BEARING_RANGE[1]:
            raise InputError(f"basket bearing {bearing:g} deg: out of range {BEARING_RANGE[0]:g} to {BEARING_RANGE[1]:g}")
    for height in heights:
        if not HEIGHT_RANGE[0] <= height <= HEIGHT_RANGE[1]:
            raise InputError(f"basket height {height:g} m: out of range {HEIGHT_RANGE[0]:g} to {HEIGHT_RANGE[1]:g} m")
    for name, values, unit in (("basket distances", distances, "m"), ("basket bearings", bearings, "deg"),
                               ("basket heights", heights, "m")):
        check_distinct(name, values, unit)
    if not raw:
        noise = dropped_frames = glitches = 0.0
    rng = np.random.default_rng(seed)
    styles = [_draw_style(rng, name, bias) for name in names]
    scatter = (throw_error, release_jitter, shape_scatter)
    throws = [
        _throw(rng, style, (float(d), float(b), float(h)), k, throwing, (rate_hz, noise, dropped_frames, glitches),
               scatter, all_short, hit_radius)
        for style in styles for d in distances for b in bearings for h in heights
        for k in range(throws_per_basket)
    ]
    context = ["distance"]
    if len(set(bearings)) > 1 or bearings[0] != 0.0:
        context.append("bearing")
    if len(set(heights)) > 1 or heights[0] != RIM_HEIGHT:
        context.append("height")
    order = ["time", "angle", "velocity"]
    for joint in ("shoulder", "wrist"):
        if joint in throwing:
            order += [joint, velocity_column(joint)]
    order += context
    return throws_dataset(throws, order, tuple(context))


def _check_joints(joints: Sequence[str]) -> tuple[str, ...]:
    joints = as_names(joints)
    unknown = [j for j in joints if j not in ARM_JOINTS]
    if unknown:
        raise InputError(f"joint {unknown[0]!r}: not one of {', '.join(ARM_JOINTS)}")
    if "elbow" not in joints:
        raise InputError(f"joints {', '.join(joints) or 'none'}: the elbow must throw (its angle is the phase)")
    return tuple(j for j in ARM_JOINTS if j in joints)


def _throw(
    rng: np.random.Generator, style: _Style, basket: tuple[float, float, float], k: int,
    joints: tuple[str, ...], camera: tuple[float, float, float, float], scatter: tuple[float, float, float],
    all_short: bool, hit_radius: float,
) -> Throw:
    """One recorded throw: its id, columns and metadata."""
    target, bearing, height = basket
    throw_error, release_jitter, shape_scatter = scatter
    shoulder = "shoulder" in joints
    # farther baskets: a wider raise of the upper arm (a person without the shoulder holds it)
    swing = style.shoulder_swing * (0.75 + 0.1 * target) * (1.0 + rng.normal(0.0, shape_scatter)) if shoulder else 0.0
    planned = _Throw(style, swing, style.release_phase, joints)
    duration = _aim(planned, target, height) / (style.speed_factor * (1.0 + rng.normal(0.0, throw_error)))
    actual = _Throw(
        style, swing, float(np.clip(style.release_phase + rng.normal(0.0, release_jitter), 0.3, 0.75)), joints
    )
    if all_short:  # slow enough that the release that happens falls short
        short_landing = target - hit_radius - 0.05 - abs(rng.normal(0.0, 0.1 * target))
        duration = max(duration, _aim(actual, max(short_landing, 0.3), height))
    timing = (rng.uniform(0.15, 0.4), rng.uniform(0.03, 0.12), rng.uniform(0.02, 0.12),
              rng.uniform(0.05, 0.15) if shoulder else 0.0)
    positions, release_time, stop = _positions(actual, duration, timing)
    rate_hz, noise, dropped_frames, glitches = camera
    time, angles, count = record(
        rng, positions, stop + rng.uniform(0.25, 0.5), rate_hz, noise, dropped_frames, glitches
    )
    x, z, vx, vz = actual.release(duration)
    landing = float(crossing_distance(x, z, vx, vz, height))
    start = time[0]
    time = time - start
    data = {"time": time}
    for name, values in angles.items():
        data[name] = values
        data[velocity_column(name)] = np.gradient(values, time)
    data.update(distance=np.full(time.size, target), bearing=np.full(time.size, bearing),
                height=np.full(time.size, height))
    release_angle = float(positions(np.array([release_time]))["angle"][0])
    meta = throw_meta(style.name, target, landing, hit_radius, release_angle, float(release_time - start), count)
    return f"{style.name}-d{target:g}-b{bearing:g}-h{height:g}-{k + 1}", data, meta


def _aim(throw: _Throw, landing: float, height: float) -> float:
    """The throw's duration (s) that lands the ball at ``landing`` (m) over a rim ``height`` (m)."""
    x0, z0, vx, vz = throw.release(1.0)
    nominal = float(np.hypot(vx, vz))
    speed = needed_speed(float(x0), float(z0), float(np.arctan2(vz, vx)), landing, height)
    if speed is None:
        raise InputError(
            f"basket at {landing:g} m with its rim at {height:g} m cannot be reached by the simulated arm"
        )
    duration = nominal / speed
    elbow_rate = throw.spans()["angle"] * throw.phases(throw.release_u)["angle"][1] / duration
    if elbow_rate > MAX_ELBOW_SPEED:
        raise InputError(
            f"basket at {landing:g} m with its rim at {height:g} m needs {elbow_rate:.0f} rad/s at the "
            f"elbow, beyond a human throw ({MAX_ELBOW_SPEED:g} rad/s)"
        )
    return duration
