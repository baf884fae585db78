"""From joint positions to the elbow angle and its velocity on one uniform time grid.

The three joints of an arm are stamped separately (a tf stream publishes each on its own and may
drop some), so they are first interpolated to common, evenly spaced stamps over the time they
overlap. Stretches where any joint has no sample for longer than ``max_gap`` (tracking lost) are
marked invalid rather than bridged. The angle is the elbow's included angle (thesis figure 4.14:
the rotation of the upper arm onto the forearm), about 0.7 rad wound up and near pi with the arm
straight, so it increases during the extension. Velocities come from a Savitzky-Golay derivative
(a local polynomial fit), which smooths the tracker's jitter that raw finite differences amplify.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.signal import savgol_filter

from rlff.capture.skeleton import ArmTrack, JointTrack
from rlff.errors import InputError

#: Width (s) of the Savitzky-Golay window used for velocities.
DERIVATIVE_WINDOW_S = 0.2
#: A joint missing for longer than this (s) means tracking was lost there.
MAX_GAP_S = 0.25


@dataclass(frozen=True)
class ArmMotion:
    """One arm on a uniform time grid.

    Attributes
    ----------
    arm : ArmTrack
        Where it came from.
    time : array of shape (T,)
        Evenly spaced stamps (s), in the recording's clock.
    angle : array of shape (T,)
        Elbow included angle (rad).
    velocity : array of shape (T,)
        Its time derivative (rad/s), Savitzky-Golay.
    shoulder, hand : arrays of shape (T, 3)
        Positions (m).
    hand_velocity : array of shape (T, 3)
        Hand velocity (m/s), Savitzky-Golay.
    valid : bool array of shape (T,)
        False where a joint was missing for longer than ``max_gap`` (values there are
        interpolated across the gap and must not be trusted).
    """

    arm: ArmTrack
    time: np.ndarray
    angle: np.ndarray
    velocity: np.ndarray
    shoulder: np.ndarray
    hand: np.ndarray
    hand_velocity: np.ndarray
    valid: np.ndarray

    @property
    def rate_hz(self) -> float:
        """Sampling rate of the grid (Hz)."""
        return 1.0 / float(self.time[1] - self.time[0])

    def runs(self) -> list[slice]:
        """Slices of consecutive valid samples, in time order."""
        edges = np.diff(np.concatenate([[0], self.valid.astype(np.int8), [0]]))
        starts = np.flatnonzero(edges == 1)
        stops = np.flatnonzero(edges == -1)
        return [slice(int(a), int(b)) for a, b in zip(starts, stops, strict=True)]


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


def savgol_derivative(values: np.ndarray, dt: float, window_s: float = DERIVATIVE_WINDOW_S) -> np.ndarray:
    """First derivative of evenly sampled values by a Savitzky-Golay filter.

    Parameters
    ----------
    values : array of shape (T,) or (T, D)
        Samples along axis 0.
    dt : float
        Sample spacing (s).
    window_s : float
        Window width (s); rounded to an odd number of samples, at least 5.

    Returns
    -------
    ndarray of the shape of ``values``: the derivative per second. Series shorter than the
    window fall back to central differences.
    """
    values = np.asarray(values, dtype=float)
    window = max(5, int(round(window_s / dt)) | 1)
    if values.shape[0] < window:
        if values.shape[0] < 2:
            return np.zeros_like(values)
        return np.gradient(values, dt, axis=0)
    order = 2 if window == 5 else 3
    return savgol_filter(values, window, order, deriv=1, delta=dt, axis=0, mode="interp")


def _interpolate(track: JointTrack, grid: np.ndarray) -> np.ndarray:
    """Positions of shape (T, 3) at the grid stamps, linear between samples."""
    return np.column_stack([np.interp(grid, track.time, track.position[:, axis]) for axis in range(3)])


def _covered(track: JointTrack, grid: np.ndarray, max_gap: float) -> np.ndarray:
    """True where the grid stamp lies between two samples of the track at most ``max_gap`` apart."""
    after = np.clip(np.searchsorted(track.time, grid, side="left"), 1, len(track.time) - 1)
    span = track.time[after] - track.time[after - 1]
    exact = (np.abs(track.time[after] - grid) <= 1e-6) | (np.abs(track.time[after - 1] - grid) <= 1e-6)
    return exact | (span <= max_gap + 1e-9)


def align_arm(arm: ArmTrack, rate_hz: float | None = None, max_gap: float = MAX_GAP_S) -> ArmMotion:
    """Interpolate an arm's joints to common stamps and compute the angle and velocities.

    Parameters
    ----------
    arm : ArmTrack
    rate_hz : float, optional
        Grid rate (Hz); default the median sampling rate of the elbow track.
    max_gap : float
        Longest stretch (s) without a joint sample that is interpolated across.

    Raises
    ------
    InputError
        A joint with fewer than 2 samples, or joints that never overlap in time.
    """
    tracks = [arm.shoulder, arm.elbow, arm.forearm_end, arm.hand]
    for track in tracks:
        if len(track) < 2:
            raise InputError(f"{arm.label}: joint {track.name!r} has {len(track)} samples")
    begin = max(track.time[0] for track in tracks)
    end = min(track.time[-1] for track in tracks)
    if end <= begin:
        raise InputError(f"{arm.label}: the joints {', '.join(t.name for t in tracks)} never overlap in time")
    if rate_hz is None:
        step = float(np.median(np.diff(arm.elbow.time)))
    else:
        if rate_hz <= 0:
            raise InputError(f"rate {rate_hz!r} Hz: must be positive")
        step = 1.0 / rate_hz
    count = int(np.floor((end - begin) / step + 1e-6)) + 1
    grid = begin + step * np.arange(count)
    shoulder, elbow, fore_end, hand = (_interpolate(track, grid) for track in tracks)
    valid = np.logical_and.reduce([_covered(track, grid, max_gap) for track in tracks])
    angle = included_angle(shoulder, elbow, fore_end)
    return ArmMotion(
        arm=arm,
        time=grid,
        angle=angle,
        velocity=_piecewise_derivative(angle, valid, step),
        shoulder=shoulder,
        hand=hand,
        hand_velocity=_piecewise_derivative(hand, valid, step),
        valid=valid,
    )


def _piecewise_derivative(values: np.ndarray, valid: np.ndarray, dt: float) -> np.ndarray:
    """Savitzky-Golay derivative computed separately on each run of valid samples (0 elsewhere)."""
    result = np.zeros_like(values)
    edges = np.diff(np.concatenate([[0], valid.astype(np.int8), [0]]))
    for start, stop in zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1), strict=True):
        result[start:stop] = savgol_derivative(values[start:stop], dt)
    return result


def hand_excursion(motion: ArmMotion) -> float:
    """How far the hand moves around the shoulder (m): norm of its 5-95 percentile range.

    The throwing hand sweeps more than a metre; the other one stays near the body. Percentiles
    keep a few glitched samples from deciding.
    """
    relative = (motion.hand - motion.shoulder)[motion.valid]
    if len(relative) < 2:
        return 0.0
    return float(np.linalg.norm(np.percentile(relative, 95, axis=0) - np.percentile(relative, 5, axis=0)))


def throwing_arm(motions: list[ArmMotion]) -> ArmMotion:
    """The arm that throws: the one whose hand sweeps furthest around its shoulder.

    On the MSR Action3D high throws this separates the throwing arm (1.05-1.36 m) from the other
    (at most 0.71 m) in every recording, where the angle range or the peak angular velocity do not.
    """
    if not motions:
        raise InputError("no arm to choose the throwing arm from")
    return max(motions, key=hand_excursion)
