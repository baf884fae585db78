"""From joint positions to the arm's joint angles and their velocities, on the recording's own samples.

The stamps are the elbow's own samples (over the time all joints overlap); the other joints are
interpolated to them, which is exact when the format stamps all joints together (text, CSV) and
fills single dropped samples of a tf stream. Nothing is resampled onto a grid here: a sparse,
irregular recording (a Kinect that delivers 4-8 Hz during fast motion) keeps its samples, and every
threshold downstream is a time or an angle, never a number of samples.

* Lost tracking: a joint without a sample for longer than ``max_gap`` (0.5 s) *and* longer than
  ``gap_factor`` (3) times the recording's usual spacing. At 4 Hz a 0.4 s gap is the normal
  spacing, at 30 Hz a 0.6 s one is lost tracking. The recording is split there.
* Glitches: a sample that leaves two neighbours which agree with each other (a reflection, a
  swapped joint) is removed, one sample at a time: the angle or the hand departs by more than
  ``GLITCH_ANGLE`` / ``GLITCH_DISTANCE`` from the line between its neighbours, the neighbours differ
  by less than half of that, and they are at most ``GLITCH_SPAN`` apart (a real movement does
  not go out and back that far so quickly). Where the neighbours are at most ``QUICK_SPAN``
  apart (20 Hz or denser), a sample that jumps that far off their line, outside their range,
  is a glitch even in the middle of an extension. A median filter would do the same at 30 Hz,
  but its width in time grows as the sampling thins, and at 5 Hz it flattens the throw itself.
* The angle is the elbow's included angle (thesis figure 4.14): about 0.7 rad wound up, near pi
  straight, so it increases during the extension.
* The shoulder's elevation is the angle between the upper arm (shoulder -> elbow) and the torso's
  downward axis (neck -> hip centre): 0 with the arm hanging along the torso, pi/2 horizontal, pi
  straight up. Where the format has no torso points, the downward vertical (against the
  recording's up) stands in: the same for a person standing upright, off by their lean otherwise.
* The wrist's angle, where the format has a hand point beside the wrist, is the included angle
  between forearm (wrist -> elbow) and hand (wrist -> hand): about pi straight.
* Glitches of the shoulder's or the wrist's angle (a torso point or the hand jumping away while
  the elbow is fine) are found by the same rule on that joint's own series, after the elbow's
  glitches went, and bridged by a line between the neighbours: the sample stays, since the
  elbow's angle there is good.
* Velocities: a local polynomial fit in time (cubic when the window holds 6 samples or more,
  quadratic from 3), which smooths the tracker's jitter; where the window holds fewer than 3
  samples the chord to the neighbours (a 3-point derivative on the uneven spacing) stands in. The
  window spans 4 usual spacings, but never less than 0.25 s nor more than 0.35 s: at 30 Hz and
  15 Hz it is the Savitzky-Golay filter rlff used before (7 samples cubic, 5 quadratic), and at
  4-8 Hz it stays 0.35 s instead of growing to 0.7-1.3 s. Hand-written because scipy's
  Savitzky-Golay filter needs even spacing.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from rlff.capture.skeleton import ArmTrack, JointTrack
from rlff.errors import InputError

#: Shortest torso (neck to hip centre, m) whose axis is used; a tracker's torso is about 0.5 m.
MIN_TORSO = 0.1
#: Up when a caller gives none (z, as in a ROS frame); only used without torso points.
_DEFAULT_UP = np.array([0.0, 0.0, 1.0])
#: Width (s) of the local fit used for velocities: 4 usual spacings, within these bounds.
DERIVATIVE_WINDOW_S = (0.25, 0.35)
#: A gap is lost tracking when longer than this (s) ...
MAX_GAP_S = 0.5
#: ... and longer than this many times the recording's median spacing.
GAP_FACTOR = 3.0
#: A glitch departs by more than this from its neighbours (angle, rad; hand, m) ...
GLITCH_ANGLE = 0.25
GLITCH_DISTANCE = 0.15
#: ... whose own distance in time is at most this (s) ...
GLITCH_SPAN = 0.25
#: ... or, when the neighbours are at most this far apart (s), whatever they do.
QUICK_SPAN = 0.1
#: Times nearer than this share of the median sample spacing are one: a sample at the edge of a fit
#: window is in it, and a walk of the throw finder that lasts a setting lasts it. Far above the
#: stamps' rounding (float64 keeps epoch seconds, 1.7e9 s, to 2.4e-7 s; 2 steps at 15 Hz span the
#: 0.133 s half-window exactly), so that velocities and cuts do not depend on the clock's origin.
TIME_TOLERANCE = 0.01


@dataclass(frozen=True)
class ArmMotion:
    """One arm on the recording's own (possibly uneven) samples.

    Attributes
    ----------
    arm : ArmTrack
        Where it came from.
    time : array of shape (T,)
        Stamps (s), increasing, in the recording's clock.
    angle : array of shape (T,)
        Elbow included angle (rad).
    velocity : array of shape (T,)
        Its time derivative (rad/s): local fit in time, computed within each run.
    shoulder, hand : arrays of shape (T, 3)
        Positions (m).
    joints : mapping of str to array of shape (T,)
        The other joint angles (rad) by dataset column: ``shoulder`` (elevation against the torso)
        always, ``wrist`` where the arm has a wrist and a hand point.
    joint_velocities : mapping of str to array of shape (T,)
        Their time derivatives (rad/s), by the same local fit as ``velocity``.
    torso : str
        What the shoulder's elevation is measured against: ``"neck -> hip centre"`` or
        ``"vertical"`` (no torso points in the recording).
    joint_glitches : mapping of str to int
        Samples of each other joint's angle bridged as glitches.
    valid : bool array of shape (T,)
        False where a joint other than the elbow has no sample within a lost-tracking gap
        (values there are interpolated across it and must not be trusted).
    lost_gap : float
        The spacing (s) beyond which a gap between samples is lost tracking.
    glitches : array of shape (G,)
        Times (s) of the samples removed as glitches.
    """

    arm: ArmTrack
    time: np.ndarray
    angle: np.ndarray
    velocity: np.ndarray
    shoulder: np.ndarray
    hand: np.ndarray
    valid: np.ndarray
    lost_gap: float
    glitches: np.ndarray
    joints: Mapping[str, np.ndarray] = field(default_factory=dict)
    joint_velocities: Mapping[str, np.ndarray] = field(default_factory=dict)
    torso: str = "vertical"
    joint_glitches: Mapping[str, int] = field(default_factory=dict)

    @property
    def rate_hz(self) -> float:
        """Usual sampling rate (Hz): 1 / the median spacing."""
        return 1.0 / median_spacing(self.time)

    def runs(self) -> list[slice]:
        """Slices of consecutive valid samples without a lost-tracking gap between them, in time order."""
        gap = np.r_[True, np.diff(self.time) > self.lost_gap, True]  # before sample i, i = 0..T
        valid = np.r_[False, self.valid, False]
        starts = np.flatnonzero(valid[1:-1] & (~valid[:-2] | gap[:-1]))
        stops = np.flatnonzero(valid[1:-1] & (~valid[2:] | gap[1:])) + 1
        return [slice(int(a), int(b)) for a, b in zip(starts, stops, strict=True)]

    def lost_spans(self) -> list[tuple[float, float]]:
        """(from, to) times (s) of every stretch without tracking between two runs."""
        runs = self.runs()
        return [(float(self.time[a.stop - 1]), float(self.time[b.start])) for a, b in zip(runs, runs[1:], strict=False)]


def included_angle(shoulder: np.ndarray, elbow: np.ndarray, hand: np.ndarray) -> np.ndarray:
    """Elbow included angle (rad) between elbow->shoulder and elbow->hand.

    Parameters
    ----------
    shoulder, elbow, hand : arrays of shape (T, 3)
        Joint positions (m).

    Returns
    -------
    ndarray of shape (T,)
        In [0, pi]: 0 folded, pi straight. Computed with atan2(|u x v|, u . v), which stays
        accurate near 0 and pi where arccos of the cosine loses digits.
    """
    upper = np.asarray(shoulder, dtype=float) - np.asarray(elbow, dtype=float)
    fore = np.asarray(hand, dtype=float) - np.asarray(elbow, dtype=float)
    return np.arctan2(np.linalg.norm(np.cross(upper, fore), axis=-1), np.einsum("...i,...i->...", upper, fore))


def median_spacing(time: np.ndarray) -> float:
    """The usual time (s) between samples at ``time`` (T,): the median of its differences, which a
    few dropped or doubled frames do not move; 0 for fewer than 2 samples."""
    return float(np.median(np.diff(time))) if len(time) > 1 else 0.0


def derivative_window(time: np.ndarray) -> float:
    """Width (s) of the velocity fit for samples at ``time``: 4 median spacings, within ``DERIVATIVE_WINDOW_S``."""
    low, high = DERIVATIVE_WINDOW_S
    return float(np.clip(4 * median_spacing(time), low, high))


def time_tolerance(time: np.ndarray) -> float:
    """How near (s) two times of samples at ``time`` (T,) are one: :data:`TIME_TOLERANCE` of their median spacing."""
    return TIME_TOLERANCE * median_spacing(time)


def _windows(time: np.ndarray, window_s: float) -> tuple[np.ndarray, np.ndarray]:
    """First and one-past-last sample index, each (T,), of every sample's fit window of
    ``window_s`` s; near the ends the window keeps its width and slides inwards (one-sided, like
    Savitzky-Golay's "interp")."""
    centre = np.clip(time, time[0] + window_s / 2, time[-1] - window_s / 2) if time[-1] - time[0] > window_s else time
    slack = time_tolerance(time)
    low = np.searchsorted(time, centre - window_s / 2 - slack, side="left")
    high = np.searchsorted(time, centre + window_s / 2 + slack, side="right")
    return low, high


def fewest_in_window(time: np.ndarray, window_s: float) -> int:
    """The fewest samples any fit window of :func:`local_derivative` holds on ``time`` (T,)."""
    if len(time) < 2:
        return len(time)
    low, high = _windows(np.asarray(time, dtype=float), window_s)
    return int((high - low).min())


def local_derivative(time: np.ndarray, values: np.ndarray, window_s: float, cubic_from: int = 5) -> np.ndarray:
    """First derivative of unevenly sampled values by a local polynomial fit in time.

    Parameters
    ----------
    time : array of shape (T,)
        Increasing stamps (s).
    values : array of shape (T,) or (T, D)
        Samples along axis 0.
    window_s : float
        Width (s) of the fit around each sample.
    cubic_from : int
        Fewest samples in a window for the cubic fit (at least 4). 5 (the default) fits a cubic
        at 15 Hz too: a quadratic's slope at the middle of its window is the straight line's,
        which flattens a throw's peak speed (MSR's 15 Hz throws peaked at 8.4 rad/s, the same
        motion at 30-120 Hz at 14.5-15; with the cubic 12.7). A larger value smooths more.

    Returns
    -------
    ndarray of the shape of ``values``: the derivative per second. Each sample gets the slope
    at its own time of a least-squares polynomial through the samples within ``window_s / 2``
    (near the ends, of the first or last ``window_s``):
    cubic with ``cubic_from`` or more samples, quadratic with 3 or more; with fewer (sparse sampling) the
    3-point derivative on the uneven spacing (the chords to both neighbours, weighted), and at
    the ends the chord to the one neighbour.
    """
    time = np.asarray(time, dtype=float)
    values = np.asarray(values, dtype=float)
    flat = values.reshape(len(time), -1)
    if len(time) < 2:
        return np.zeros_like(values)
    result = np.gradient(flat, time, axis=0, edge_order=1)
    low, high = _windows(time, window_s)
    counts = high - low
    width = int(counts.max())
    if width >= 3:
        offsets = np.arange(width)
        index = np.minimum(low[:, None] + offsets, len(time) - 1)
        inside = offsets[None, :] < counts[:, None]
        dt = np.where(inside, time[index] - time[:, None], 0.0)
        scale = window_s / 2
        cubic_from = max(int(cubic_from), 4)
        for degree, fits in ((3, counts >= cubic_from), (2, (counts >= 3) & (counts < cubic_from))):
            if not fits.any():
                continue
            powers = (dt[fits] / scale)[..., None] ** np.arange(degree + 1)  # (F, W, degree + 1)
            powers = powers * inside[fits][..., None]
            gram = np.einsum("fwi,fwj->fij", powers, powers)
            moments = np.einsum("fwi,fwd->fid", powers, flat[index[fits]] * inside[fits][..., None])
            coefficients = np.linalg.solve(gram, moments)  # (F, degree + 1, D)
            result[fits] = coefficients[:, 1, :] / scale
    return result.reshape(values.shape)


def positions_at(track: JointTrack, stamps: np.ndarray) -> np.ndarray:
    """The track's positions of shape (T, 3) at the stamps of shape (T,), linear between samples."""
    return np.column_stack([np.interp(stamps, track.time, track.position[:, axis]) for axis in range(3)])


def _covered(track: JointTrack, stamps: np.ndarray, lost_gap: float) -> np.ndarray:
    """True where the stamp lies on a sample of the track or between two at most ``lost_gap`` apart."""
    after = np.clip(np.searchsorted(track.time, stamps, side="left"), 1, len(track.time) - 1)
    span = track.time[after] - track.time[after - 1]
    exact = (np.abs(track.time[after] - stamps) <= 1e-6) | (np.abs(track.time[after - 1] - stamps) <= 1e-6)
    return exact | (span <= lost_gap + 1e-9)


def lost_tracking_gap(time: np.ndarray, max_gap: float = MAX_GAP_S, gap_factor: float = GAP_FACTOR) -> float:
    """Spacing (s) beyond which a gap between samples at ``time`` is lost tracking.

    The larger of ``max_gap`` and ``gap_factor`` x the median spacing: a gap must be long in
    absolute terms and against the recording's usual spacing.
    """
    return max(max_gap, gap_factor * median_spacing(time))


def _glitches(time: np.ndarray, angle: np.ndarray, hand: np.ndarray | None) -> np.ndarray:
    """Boolean mask of shape (T,): samples that leave their neighbours and come back (one at a time).

    Two cases, both within a short time: the neighbours (at most ``GLITCH_SPAN`` apart) agree
    with each other and the sample leaves them; or the neighbours are at most ``QUICK_SPAN``
    apart (dense sampling, where even the fastest throw moves smoothly from one sample to the
    next) and the sample jumps away from the line between them, as a spike in the middle of
    an extension does.
    """
    if len(time) < 3:
        return np.zeros(len(time), dtype=bool)
    before, after = time[1:-1] - time[:-2], time[2:] - time[1:-1]
    share = (before / (before + after))[:, None]
    span = time[2:] - time[:-2]

    def leaves(series: np.ndarray, limit: float, outside_range: bool) -> np.ndarray:
        """How far (in units of ``limit``) each inner sample leaves its neighbours; 0 when it does not."""
        series = series.reshape(len(time), -1)
        line = series[:-2] + share * (series[2:] - series[:-2])
        departure = np.linalg.norm(series[1:-1] - line, axis=1)
        neighbours = np.linalg.norm(series[2:] - series[:-2], axis=1)
        agreeing = (span <= GLITCH_SPAN) & (departure > limit) & (neighbours < departure / 2)
        jump = departure
        if outside_range:  # an angle: how far outside the range of its two neighbours
            low, high = np.minimum(series[:-2], series[2:]), np.maximum(series[:-2], series[2:])
            jump = np.maximum(low - series[1:-1], series[1:-1] - high).max(axis=1)
        quick = (span <= QUICK_SPAN) & (jump > limit)
        return np.where(agreeing | quick, departure / limit, 0.0)

    score = leaves(angle, GLITCH_ANGLE, True)
    if hand is not None:
        score = np.maximum(score, leaves(hand, GLITCH_DISTANCE, False))
    # a glitch also puts its neighbours off their lines: only the sample that leaves most is one
    padded = np.r_[0.0, score, 0.0]
    inner = (score > 0) & (score >= padded[:-2]) & (score > padded[2:])
    return np.r_[False, inner, False]


def elevation(shoulder: np.ndarray, elbow: np.ndarray, down: np.ndarray) -> np.ndarray:
    """Shoulder elevation (rad): the angle between the upper arm and the torso's downward axis.

    Parameters
    ----------
    shoulder, elbow : arrays of shape (T, 3)
        Joint positions (m).
    down : array of shape (T, 3) or (3,)
        The torso's downward direction (neck -> hip centre, any length), or the vertical.

    Returns
    -------
    ndarray of shape (T,)
        In [0, pi]: 0 hanging along the torso, pi/2 horizontal (for an upright torso), pi straight up.
    """
    upper = np.asarray(elbow, dtype=float) - np.asarray(shoulder, dtype=float)
    down = np.broadcast_to(np.asarray(down, dtype=float), upper.shape)
    return np.arctan2(np.linalg.norm(np.cross(upper, down), axis=-1), np.einsum("...i,...i->...", upper, down))


def _bridge_glitches(time: np.ndarray, values: np.ndarray) -> tuple[np.ndarray, int]:
    """A joint angle's glitches (the rule of :func:`_glitches` on the angle alone) replaced by
    the line between their neighbours, one at a time until none is left; and their number."""
    values = values.copy()
    count = 0
    for _ in range(values.size):
        glitch = np.flatnonzero(_glitches(time, values, None))
        if not glitch.size:
            break
        for index in glitch:
            share = (time[index] - time[index - 1]) / (time[index + 1] - time[index - 1])
            values[index] = values[index - 1] + share * (values[index + 1] - values[index - 1])
        count += glitch.size
    return values, count


def align_arm(
    arm: ArmTrack, max_gap: float = MAX_GAP_S, gap_factor: float = GAP_FACTOR, up: np.ndarray = _DEFAULT_UP
) -> ArmMotion:
    """The arm's joints at the elbow's own stamps, without glitches, with their angles and velocities.

    Parameters
    ----------
    arm : ArmTrack
    max_gap, gap_factor : float
        A gap (s) is lost tracking when longer than both ``max_gap`` and ``gap_factor`` x the
        median spacing of the elbow's samples.
    up : array of shape (3,)
        The recording's up direction: the shoulder's elevation is measured against its opposite
        when the arm has no torso points (neck and hip centre, at least ``MIN_TORSO`` apart).

    Raises
    ------
    InputError
        A joint with fewer than 2 samples, or joints that never overlap in time.
    """
    tracks = [arm.shoulder, arm.elbow, arm.forearm_end, arm.hand]
    for track in tracks:
        if len(track) < 2:
            raise InputError(f"{arm.label}: joint {track.name!r} has {len(track)} samples")
    torso = [arm.neck, arm.hip] if arm.neck is not None and arm.hip is not None else []
    torso = [track for track in torso if len(track) >= 2]
    if len(torso) < 2 or max(t.time[0] for t in torso) >= min(t.time[-1] for t in torso):
        torso = []  # no torso tracked alongside the arm: the vertical stands in
    begin = max(track.time[0] for track in tracks)
    end = min(track.time[-1] for track in tracks)
    if end <= begin:
        raise InputError(f"{arm.label}: the joints {', '.join(t.name for t in tracks)} never overlap in time")
    elbow_time = arm.elbow.time
    stamps = elbow_time[(elbow_time >= begin - 1e-9) & (elbow_time <= end + 1e-9)]
    if stamps.size < 2:
        raise InputError(f"{arm.label}: fewer than 2 elbow samples while all joints are tracked")
    lost_gap = lost_tracking_gap(stamps, max_gap, gap_factor)
    shoulder, elbow, fore_end, hand = (positions_at(track, stamps) for track in tracks)
    valid = np.logical_and.reduce([_covered(track, stamps, lost_gap) for track in tracks])
    angle = included_angle(shoulder, elbow, fore_end)
    glitch = _glitches(stamps, angle, hand)
    keep = ~glitch
    glitch_times = stamps[glitch]
    # the other joints, on the same stamps: the shoulder against the torso (or the vertical), the
    # wrist between forearm and hand where the arm has both points
    down = positions_at(torso[1], stamps) - positions_at(torso[0], stamps) if torso else None
    if down is not None and np.median(np.linalg.norm(down, axis=1)) < MIN_TORSO:
        torso, down = [], None  # neck and hip in one place: not a torso
    if down is None:
        down = -np.asarray(up, dtype=float)
    joints = {"shoulder": elevation(shoulder, elbow, down)}
    if arm.wrist is not None:
        joints["wrist"] = included_angle(elbow, fore_end, hand)
    stamps, angle, shoulder, hand, valid = stamps[keep], angle[keep], shoulder[keep], hand[keep], valid[keep]
    joints = {name: values[keep] for name, values in joints.items()}
    motion = ArmMotion(arm, stamps, angle, np.zeros_like(angle), shoulder, hand, valid, lost_gap, elbow_time[:0])
    velocity = np.zeros_like(angle)
    window = derivative_window(stamps)
    bridged = {name: 0 for name in joints}
    rates = {name: np.zeros_like(values) for name, values in joints.items()}
    for run in motion.runs():
        velocity[run] = local_derivative(stamps[run], angle[run], window)
        for name in joints:
            joints[name][run], found = _bridge_glitches(stamps[run], joints[name][run])
            bridged[name] += found
            rates[name][run] = local_derivative(stamps[run], joints[name][run], window)
    return ArmMotion(
        arm, stamps, angle, velocity, shoulder, hand, valid, lost_gap, glitch_times, joints, rates,
        "neck -> hip centre" if torso else "vertical", bridged,
    )


def sweep(relative: np.ndarray) -> float:
    """How far positions of shape (T, 3) range (m): norm of their 5-95 percentile range, 0 below 2.

    Percentiles keep a few glitched samples from deciding.
    """
    if len(relative) < 2:
        return 0.0
    return float(np.linalg.norm(np.percentile(relative, 95, axis=0) - np.percentile(relative, 5, axis=0)))


def hand_excursion(motion: ArmMotion) -> float:
    """How far the hand moves around the shoulder (m): the :func:`sweep` of hand - shoulder.

    The throwing hand sweeps more than a metre; the other one stays near the body.
    """
    return sweep((motion.hand - motion.shoulder)[motion.valid])


def throwing_arm(motions: list[ArmMotion]) -> ArmMotion:
    """The arm that throws: the one whose hand sweeps furthest around its shoulder.

    On the MSR Action3D high throws this separates the throwing arm (1.05-1.36 m) from the other
    (at most 0.71 m) in every recording, where the angle range or the peak angular velocity do not.
    """
    if not motions:
        raise InputError("no arm to choose the throwing arm from")
    return max(motions, key=hand_excursion)
