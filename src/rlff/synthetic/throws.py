"""Simulated human throwing demonstrations, as a depth camera and a skeleton tracker record them.

Each throw is an overhand throw seen through the elbow's included angle (rad, between upper arm
and forearm): the person rests, winds up (the elbow flexes to about 0.6-0.9 rad), extends the
elbow with a bell-shaped (minimum-jerk) velocity profile, releases the ball during the extension,
and stops abruptly near full extension (2.8-3.1 rad) with a small recoil. The recording follows
the thesis' plan (section 4.2: several subjects, four throws per basket, baskets from 1.0 to
4.0 m) and its faults (section 4.2.1): a camera rate of 15-30 Hz, measurement noise, dropped
frames and "second skeleton" glitches (a sample whose angle jumps near zero).

Arm geometry (vertical plane of the throw; x forward from the shoulder, z up from the floor):
the shoulder is at height ``shoulder_height`` (per subject, about 1.45 m); the upper arm, of length
:data:`UPPER_ARM` (0.30 m), is held still at elevation ``phi_u`` above the horizontal (per subject,
1.05-1.30 rad); the forearm with the hand, of length :data:`FOREARM` (0.35 m, elbow to ball),
rotates about the elbow. At included angle theta the forearm points at ``phi_u + pi - theta`` from
the horizontal, so extending the elbow (theta growing) swings the hand forward and up. At release
the ball leaves the hand with speed ``angular velocity x FOREARM``, perpendicular to the forearm,
and flies without drag (:func:`rlff.ballistics.crossing_distance`) down to the basket's rim at
height :data:`RIM_HEIGHT` (0.3 m). The throw hits when it crosses the rim height within
``hit_radius`` (0.15 m) of the basket's centre.

A subject aims: they pick the angular velocity that would land the ball in the basket, scaled by
their own bias (most people fall short) and a per-throw error. Their style (rest angle, wind-up
depth, full extension, timing, where in the extension they let go) is drawn once per subject.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from rlff.ballistics import crossing_distance
from rlff.dataset import Dataset
from rlff.errors import InputError
from rlff.limits import check_distance
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
from rlff.synthetic.whole_arm import whole_arm_demonstrations

__all__ = [
    "FOREARM", "MAX_ELBOW_SPEED", "RIM_HEIGHT", "THESIS_DISTANCES", "UPPER_ARM", "release_state",
    "simulate_throws", "whole_arm_demonstrations",
]

#: Forearm with hand, elbow to the ball's centre (m).
FOREARM = 0.35


@dataclass(frozen=True)
class _Style:
    """How one subject throws (drawn once per subject)."""

    name: str
    shoulder_height: float  # m
    upper_arm_elevation: float  # rad above the horizontal
    rest_angle: float  # rad, before the wind-up
    wound_angle: float  # rad, deepest flexion
    extended_angle: float  # rad, where the extension stops
    release_phase: float  # fraction of the extension's duration at which the ball leaves
    windup_duration: float  # s
    speed_factor: float  # multiplies the angular velocity the throw needs (< 1: falls short)


def release_state(
    upper_arm_elevation: float, shoulder_height: float, release_angle: np.ndarray | float,
    angular_velocity: np.ndarray | float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Ball position and velocity at release from the arm geometry of the module docstring.

    Parameters
    ----------
    upper_arm_elevation : float
        Upper arm elevation above the horizontal (rad).
    shoulder_height : float
        Shoulder height above the floor (m).
    release_angle : float or array of shape (N,)
        Elbow included angle at release (rad).
    angular_velocity : float or array of shape (N,)
        Elbow angular velocity at release (rad/s), positive while extending.

    Returns
    -------
    x, z, vx, vz : arrays of shape (N,)
        Release position (m) and velocity (m/s); x forward from the shoulder, z up.
    """
    forearm_direction = upper_arm_elevation + np.pi - np.asarray(release_angle, dtype=float)
    elbow_x = UPPER_ARM * np.cos(upper_arm_elevation)
    elbow_z = shoulder_height + UPPER_ARM * np.sin(upper_arm_elevation)
    x = elbow_x + FOREARM * np.cos(forearm_direction)
    z = elbow_z + FOREARM * np.sin(forearm_direction)
    speed = FOREARM * np.asarray(angular_velocity, dtype=float)
    # the forearm turns towards the front (its direction angle decreases as theta grows)
    return x, z, speed * np.sin(forearm_direction), -speed * np.cos(forearm_direction)


def _needed_angular_velocity(style: _Style, release_angle: float, landing: float) -> float:
    """Elbow angular velocity (rad/s) at release that lands the ball at ``landing`` (m).

    The ball's speed is the elbow's rate times :data:`FOREARM` (:func:`~rlff.synthetic.people.needed_speed`).
    """
    x0, z0, vx, vz = release_state(style.upper_arm_elevation, style.shoulder_height, release_angle, 1.0)
    speed = needed_speed(float(x0), float(z0), float(np.arctan2(vz, vx)), landing, RIM_HEIGHT)
    if speed is None:
        raise InputError(f"basket distance {landing} m cannot be reached by the simulated arm")
    if speed / FOREARM > MAX_ELBOW_SPEED:
        raise InputError(
            f"basket distance {landing} m needs {speed / FOREARM:.0f} rad/s at the elbow, beyond a "
            f"human throw ({MAX_ELBOW_SPEED:g} rad/s)"
        )
    return float(speed / FOREARM)


def _draw_style(rng: np.random.Generator, name: str, bias: float) -> _Style:
    return _Style(
        name=name,
        shoulder_height=rng.uniform(1.35, 1.55),
        upper_arm_elevation=rng.uniform(1.05, 1.30),
        rest_angle=rng.uniform(1.5, 2.1),
        wound_angle=rng.uniform(0.6, 0.9),
        extended_angle=rng.uniform(2.8, 3.1),
        release_phase=rng.uniform(0.45, 0.6),
        windup_duration=rng.uniform(0.3, 0.5),
        speed_factor=float(np.clip(1.0 - rng.normal(bias, 0.03), 0.7, 1.2)),
    )


def _angle_profile(
    rng: np.random.Generator, style: _Style, extension_duration: float
) -> tuple[Callable[[np.ndarray], np.ndarray], float, float, float]:
    """The throw's true elbow angle as a function of time, with its release time and duration.

    Returns ``(angle_of_time, release_time, release_angle, duration)``.
    """
    rest = rng.uniform(0.15, 0.4)
    hold = rng.uniform(0.03, 0.12)
    recoil = rng.uniform(0.02, 0.12)
    recoil_duration = 0.2
    after = rng.uniform(0.25, 0.5)
    t_windup = rest
    t_hold = t_windup + style.windup_duration
    t_extend = t_hold + hold
    t_stop = t_extend + extension_duration
    duration = t_stop + after
    span = style.extended_angle - style.wound_angle

    def angle(t: np.ndarray) -> np.ndarray:
        windup = np.clip((t - t_windup) / style.windup_duration, 0.0, 1.0)
        extend = np.clip((t - t_extend) / extension_duration, 0.0, 1.0)
        settle = np.clip((t - t_stop) / recoil_duration, 0.0, 1.0)
        value = style.rest_angle + (style.wound_angle - style.rest_angle) * 0.5 * (1 - np.cos(np.pi * windup))
        value = np.where(t >= t_hold, style.wound_angle + span * minimum_jerk(extend), value)
        # abrupt stop: the extension's velocity is cut at full extension, then a small recoil
        return value - recoil * np.sin(0.5 * np.pi * settle)

    release_time = t_extend + style.release_phase * extension_duration
    release_angle = style.wound_angle + span * float(minimum_jerk(np.asarray(style.release_phase)))
    return angle, release_time, release_angle, duration


def simulate_throws(
    seed: int = 0,
    *,
    subjects: int | Sequence[str] = 10,
    distances: Sequence[float] = THESIS_DISTANCES,
    throws_per_distance: int = 4,
    rate_hz: float = 30.0,
    noise: float = 0.03,
    dropped_frames: float = 0.03,
    glitches: float = 0.01,
    inconsistent_distance: float | None = None,
    inconsistent_factor: float = 0.8,
    bias: float = 0.05,
    throw_error: float = 0.04,
    all_short: bool = False,
    hit_radius: float = 0.15,
    raw: bool = True,
) -> Dataset:
    """Recorded throws of several subjects at several basket distances.

    Parameters
    ----------
    seed : int
        Random seed; the same seed gives the same dataset.
    subjects : int or sequence of str
        Number of subjects (named ``s01``, ``s02``, ...) or their names. Thesis: 10.
    distances : sequence of float
        Basket distances (m) from the shoulder, horizontally.
    throws_per_distance : int
        Throws of each subject at each basket (thesis: 4).
    rate_hz : float
        Camera frame rate, 15 to 30 Hz.
    noise : float
        Standard deviation of the angle's measurement noise (rad).
    dropped_frames : float
        Probability that a frame is missing (the first and last frames are kept).
    glitches : float
        Probability per frame that a tracking glitch starts there: one sample (sometimes two)
        whose angle jumps to 0-0.15 rad.
    inconsistent_distance : float, optional
        A basket distance whose throws are all made ``inconsistent_factor`` times too slow, so
        that its velocities break the monotone trend with distance (as 2.75 m in the thesis).
    inconsistent_factor : float
        Speed factor of the inconsistent distance's throws.
    bias : float
        Mean fraction of the needed speed a subject falls short by (per subject, sd 0.03).
    throw_error : float
        Relative standard deviation of a throw's speed around the subject's aim.
    all_short : bool
        Make every throw fall short of the basket by more than ``hit_radius`` (a set of failures
        only, for the learning-from-failure benchmark).
    hit_radius : float
        Half-width of the basket's opening (m): a hit lands within it.
    raw : bool
        False gives the true motion sampled at the camera rate, without noise, dropped frames or
        glitches.

    Returns
    -------
    Dataset
        Columns ``time`` (s, from the first frame), ``angle`` (rad), ``distance`` (m),
        ``velocity`` (rad/s, finite differences of the recorded angle over time, as a capture
        computes it); metadata ``subject``, ``source`` ("simulated"), ``target`` (m),
        ``landing`` (m), ``hit``, ``release_angle`` (rad), ``release_time`` (s, same clock as
        ``time``), ``glitches`` (count). Trajectory ids ``<subject>-d<distance>-<k>``.

    Raises
    ------
    InputError
        A rate outside 15-30 Hz, a probability outside [0, 0.5), a noise outside 0-0.5 rad, an
        empty plan, a distance given twice or the simulated arm cannot reach, or an
        ``inconsistent_distance`` that is none of ``distances``.
    """
    check_recording(rate_hz, noise=noise, dropped_frames=dropped_frames, glitches=glitches, bias=bias,
                    throw_error=throw_error)
    names = subject_names(subjects)
    if not names or not len(distances) or throws_per_distance < 1:
        raise InputError("no throws to simulate: give at least one subject, distance and throw")
    for distance in distances:
        check_distance("basket distance", distance)
    check_distinct("basket distances", distances, "m")
    check_inconsistent_distance(inconsistent_distance, distances)
    if not raw:
        noise = dropped_frames = glitches = 0.0
    rng = np.random.default_rng(seed)
    styles = [_draw_style(rng, name, bias) for name in names]
    throws = [
        _throw(rng, style, float(distance), k, rate_hz, noise, dropped_frames, glitches,
               inconsistent_factor if _same(distance, inconsistent_distance) else 1.0,
               throw_error, all_short, hit_radius)
        for style in styles for distance in distances for k in range(throws_per_distance)
    ]
    return throws_dataset(throws, ("time", "angle", "distance", "velocity"), ("distance",))


def check_inconsistent_distance(value: float | None, distances: Sequence[float], name: str = "inconsistent distance",
                                among: str = "the basket distances") -> None:
    """Refuse an inconsistent distance (m) that is none of ``distances`` (m): it slowed no throw,
    and nothing said so."""
    if value is not None and not any(_same(distance, value) for distance in distances):
        shown = ", ".join(f"{distance:g}" for distance in distances)
        raise InputError(f"{name} {value:g} m is not among {among} ({shown} m): it would slow no throw; give one of them")


def _same(distance: float, other: float | None) -> bool:
    return other is not None and abs(distance - other) < 1e-9


def _throw(
    rng: np.random.Generator, style: _Style, target: float, k: int, rate_hz: float, noise: float,
    dropped_frames: float, glitches: float, slowdown: float, throw_error: float, all_short: bool,
    hit_radius: float,
) -> Throw:
    """One recorded throw: its id, columns and metadata."""
    span = style.extended_angle - style.wound_angle
    release_angle = style.wound_angle + span * float(minimum_jerk(np.asarray(style.release_phase)))
    needed = _needed_angular_velocity(style, release_angle, target)
    error = 1.0 + rng.normal(0.0, throw_error)
    aimed = needed * style.speed_factor * error * slowdown
    if all_short:
        short_landing = target - hit_radius - 0.05 - abs(rng.normal(0.0, 0.1 * target))
        aimed = min(aimed, _needed_angular_velocity(style, release_angle, max(short_landing, 0.3)))
    # the extension lasts what makes the minimum-jerk speed at the release phase equal the aim
    extension_duration = span * float(minimum_jerk_speed(style.release_phase)) / aimed
    angle_of_time, release_time, release_angle, duration = _angle_profile(rng, style, extension_duration)
    time, angles, count = record(
        rng, lambda t: {"angle": angle_of_time(t)}, duration, rate_hz, noise, dropped_frames, glitches
    )
    angle = angles["angle"]
    x, z, vx, vz = release_state(style.upper_arm_elevation, style.shoulder_height, release_angle, aimed)
    landing = float(crossing_distance(x, z, vx, vz, RIM_HEIGHT))
    start = time[0]
    time = time - start
    velocity = np.gradient(angle, time)
    meta = throw_meta(style.name, target, landing, hit_radius, release_angle, float(release_time - start), count)
    data = {"time": time, "angle": angle, "distance": np.full(time.size, target), "velocity": velocity}
    return f"{style.name}-d{target:g}-{k + 1}", data, meta
