"""Sparse, irregular copies of real and simulated throwing recordings, made at test time.

Real skeleton trackers do not always deliver their nominal rate: during fast motion some Kinect v1
recordings hold samples at 4-8 Hz, irregularly, with frame numbers still counting at 30 Hz. This
module makes such recordings from data whose throws are known:

* :func:`msr_frames` reads an MSR Action3D file (15 Hz) from ``../shared/data`` as frames of
  shape (N, 20, 3) in the Kinect SDK v1 joint order (arm B, the throwing arm, at the right arm's
  indices 8-11);
* :func:`thinned_indices` decimates a 15 Hz (or any rate) recording to a lower rate by keeping the
  frame nearest to each wanted instant: regular (a phase, then every ``1/rate``) or irregular
  (intervals drawn from U(0.5, 1.5) / rate, and now and then an interval dropped). Frames are
  kept, never interpolated: the copy holds only samples the tracker really gave;
* :func:`write_kinect_text` and :func:`write_joint_csv` write the frames as Kinect text (frame
  numbers at 30 Hz) and as a CSV with a ``time`` column (camera frame, y up);
* :func:`session` simulates a person facing the camera who makes overhand throws, throws
  released forward and down, slow lobs, two-handed throws, and lets the arm drop to rest (which
  is not a throw), with the truth of each.

The shared data is never copied into the repository: tests and ``benchmarks/capture_rates.py``
write these copies into temporary folders.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

#: Kinect SDK v1 joint index (0-based) for each MSR Action3D line (0-based) of the arms.
_MSR_TO_KINECT = {1: 8, 8: 9, 10: 10, 12: 11, 0: 4, 7: 5, 9: 6, 11: 7}
#: Rates (Hz) and spacings the acceptance of issue 14 names.
RATES = (10.0, 8.0, 6.0, 5.0, 4.0)
SPACINGS = ("regular", "irregular")
KINECT_FRAME_RATE = 30.0


def msr_frames(path: str | Path) -> np.ndarray:
    """Frames of shape (N, 20, 3) of an MSR Action3D skeleton file, in the Kinect v1 joint order.

    The arm joints are moved to their Kinect indices (MSR arm B to the right arm, 8-11; arm A to
    the left, 4-7); the other joints fill the remaining slots in their MSR order.
    """
    values = np.loadtxt(path)[:, :3].reshape(-1, 20, 3)
    frames = np.empty_like(values)
    free = [index for index in range(20) if index not in _MSR_TO_KINECT.values()]
    others = [index for index in range(20) if index not in _MSR_TO_KINECT]
    for msr, kinect in _MSR_TO_KINECT.items():
        frames[:, kinect] = values[:, msr]
    frames[:, free] = values[:, others]
    return frames


def thinned_indices(
    count: int, source_rate: float, rate: float, spacing: str, phase: float, rng: np.random.Generator, drop: float = 0.1
) -> np.ndarray:
    """Indices of the frames kept when a ``source_rate`` recording of ``count`` frames is thinned.

    Parameters
    ----------
    count : number of frames of the source
    source_rate : its rate (Hz)
    rate : the wanted mean rate (Hz)
    spacing : ``"regular"`` (every ``1 / rate`` from ``phase / rate``) or ``"irregular"`` (from
        ``phase / rate``, intervals drawn from U(0.5, 1.5) / rate; with probability ``drop`` an
        interval is dropped, so the gap is two intervals long, never more)
    phase : fraction of an interval, in [0, 1)
    rng : random generator of the irregular intervals

    Returns
    -------
    ndarray of int, increasing: the frame nearest to each wanted instant, each frame at most once.
    """
    duration = (count - 1) / source_rate
    if spacing == "regular":
        wanted = np.arange(phase / rate, duration + 1e-9, 1.0 / rate)
    elif spacing == "irregular":
        intervals = rng.uniform(0.5, 1.5, int(3 * duration * rate) + 10) / rate
        times = phase / rate + np.concatenate([[0.0], np.cumsum(intervals)])
        kept = rng.random(times.size) >= drop
        kept[0] = True
        kept[1:] |= ~kept[:-1]  # a dropped interval is never followed by another: gaps of at most two
        wanted = times[kept & (times <= duration + 1e-9)]
    else:
        raise ValueError(f"spacing {spacing!r}: regular or irregular")
    return np.unique(np.clip(np.rint(wanted * source_rate).astype(int), 0, count - 1))


def write_kinect_text(path: Path, frames: np.ndarray, frame_numbers: np.ndarray) -> Path:
    """Write frames of shape (N, 20, 3) as Kinect SDK v1 text: frame number, then 20 x (x y z)."""
    rows = np.column_stack([np.asarray(frame_numbers, dtype=float), frames.reshape(len(frames), 60)])
    np.savetxt(path, rows, fmt=["%d", *["%.6f"] * 60])
    return path


def write_joint_csv(path: Path, frames: np.ndarray, time: np.ndarray) -> Path:
    """Write the arm joints of frames of shape (N, 20, 3) (Kinect order) as a joint CSV with ``time`` (s)."""
    import pandas as pd

    columns = {"time": np.asarray(time, dtype=float)}
    for side, first in (("right", 8), ("left", 4)):
        for offset, joint in enumerate(("shoulder", "elbow", "wrist", "hand")):
            for axis, name in enumerate("xyz"):
                columns[f"{side}_{joint}_{name}"] = frames[:, first + offset, axis]
    pd.DataFrame(columns).to_csv(path, index=False, float_format="%.6f")
    return path


# -- simulated sessions ----------------------------------------------------------------------------

UPPER_ARM = 0.30
FOREARM = 0.28
#: The person stands 2.5 m in front of the camera, facing it (-z), y up, right shoulder at +x.
_SHOULDERS = {"right": np.array([0.18, 0.35, 2.5]), "left": np.array([-0.18, 0.35, 2.5])}
_FORWARD = np.array([0.0, 0.0, -1.0])
_UP = np.array([0.0, 1.0, 0.0])


@dataclass(frozen=True)
class Movement:
    """One movement of a simulated session (angles in rad, times in s).

    ``kind`` is ``"overhand"``, ``"forward-down"`` (released forward and steeply down),
    ``"lob"`` (a slow extension), ``"two-handed"`` (both arms) or ``"to-rest"`` (the upper arm
    hangs and the forearm, raised forward, is lowered: the elbow extends fast, the hand moves down
    and back; not a throw).
    """

    kind: str
    start: float
    extension: float
    wound: float = 0.7
    straight: float = 3.0

    @property
    def is_throw(self) -> bool:
        return self.kind != "to-rest"

    @property
    def peak_time(self) -> float:
        """Middle of the extension (s), where the elbow extends fastest."""
        return self.start + _WIND_UP + _HOLD + self.extension / 2


_WIND_UP, _HOLD, _FOLLOW, _REST_ANGLE = 0.5, 0.1, 0.4, 2.7
#: Elevation (rad, from the forward horizontal, positive up) of the upper arm during each kind.
_ELEVATION = {"overhand": np.radians(55), "forward-down": np.radians(-22), "lob": np.radians(35), "two-handed": np.radians(50)}


def _smooth(s: np.ndarray) -> np.ndarray:
    s = np.clip(s, 0.0, 1.0)
    return s**3 * (10 - 15 * s + 6 * s**2)


def session(seed: int, rate: float = 30.0, noise: float = 0.003) -> tuple[np.ndarray, np.ndarray, list[Movement]]:
    """A simulated session of six movements facing a camera: frames (N, 20, 3) in Kinect order, times (N,), truth.

    The movements, in a shuffled order with 1.2-1.8 s of rest between them: an overhand throw, a
    throw released forward and down (about 40 deg below horizontal where the elbow extends
    fastest), a slow lob (0.65-0.8 s extension), a two-handed throw, another overhand throw, and
    the forearm lowered to rest.
    """
    rng = np.random.default_rng(seed)
    kinds = ["overhand", "forward-down", "lob", "two-handed", "overhand", "to-rest"]
    order = rng.permutation(len(kinds))
    movements, t = [], 1.0
    for index in order:
        kind = kinds[index]
        extension = float(rng.uniform(0.65, 0.8)) if kind == "lob" else float(rng.uniform(0.25, 0.4))
        wound = float(rng.uniform(1.4, 1.7)) if kind == "to-rest" else float(rng.uniform(0.6, 0.9))
        movements.append(Movement(kind, t, extension, wound, float(rng.uniform(2.85, 3.05))))
        t += _WIND_UP + _HOLD + extension + _FOLLOW + float(rng.uniform(1.2, 1.8))
    time = np.arange(0.0, t + 0.5, 1.0 / rate)
    frames = np.zeros((time.size, 20, 3))
    frames[:] = np.array([0.0, 0.0, 2.5])
    for side in ("right", "left"):
        shoulder, elbow, hand = _arm(time, movements, side)
        first = 8 if side == "right" else 4
        frames[:, first], frames[:, first + 1], frames[:, first + 3] = shoulder, elbow, hand
        frames[:, first + 2] = elbow + 0.9 * (hand - elbow)
    frames += rng.normal(0.0, noise, frames.shape)
    return frames, time, movements


def _arm(time: np.ndarray, movements: list[Movement], side: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Shoulder, elbow and hand (T, 3) of one arm moving in its vertical plane along the facing direction."""
    elevation = np.full(time.size, -np.pi / 2)  # hanging
    angle = np.full(time.size, _REST_ANGLE)
    for movement in movements:
        if side == "left" and movement.kind != "two-handed":
            continue
        begin = movement.start
        hold = begin + _WIND_UP + _HOLD
        extended, settled = hold + movement.extension, hold + movement.extension + _FOLLOW
        inside = (time >= begin) & (time < settled + 0.3)
        if movement.kind == "to-rest":
            # the upper arm hangs; the forearm, raised forward, is lowered to rest: the elbow extends,
            # the hand moves down and back toward the body
            lift = _smooth((time - begin) / _WIND_UP)
            drop = _smooth((time - hold) / movement.extension)
            elevation[inside] = (-np.pi / 2 - np.radians(8) * drop)[inside]
            value = _REST_ANGLE + (movement.wound - _REST_ANGLE) * lift + (movement.straight - movement.wound) * drop
            angle[inside] = value[inside]
            continue
        target = _ELEVATION[movement.kind]
        raise_ = _smooth((time - begin) / _WIND_UP)
        lower = _smooth((time - extended) / (_FOLLOW + 0.3))
        elevation[inside] = (-np.pi / 2 + (target + np.pi / 2) * (raise_ - lower))[inside]
        flex = _smooth((time - begin) / _WIND_UP)
        extend = _smooth((time - hold) / movement.extension)
        relax = _smooth((time - extended) / _FOLLOW)
        value = _REST_ANGLE + (movement.wound - _REST_ANGLE) * flex + (movement.straight - movement.wound) * extend
        value = value + (_REST_ANGLE - movement.straight) * relax
        angle[inside] = value[inside]
    upper = np.cos(elevation)[:, None] * _FORWARD + np.sin(elevation)[:, None] * _UP
    # the forearm folds up and back from the upper arm by pi - angle, in the same vertical plane
    fold = elevation + (np.pi - angle)
    fore = np.cos(fold)[:, None] * _FORWARD + np.sin(fold)[:, None] * _UP
    shoulder = np.tile(_SHOULDERS[side], (time.size, 1))
    elbow = shoulder + UPPER_ARM * upper
    return shoulder, elbow, elbow + FOREARM * fore


# -- found again -----------------------------------------------------------------------------------


@dataclass(frozen=True)
class Copy:
    """One thinned copy of a recording and what the import made of it."""

    source: str
    format: str
    rate: float
    spacing: str
    phase: float
    found: bool
    landing_ratio: float | None
    why: str


def write_copy(folder: Path, name: str, frames: np.ndarray, time: np.ndarray, format: str) -> Path:
    """Write frames (N, 20, 3) at times (N,) (s) as ``kinect-text`` (frame numbers at 30 Hz) or ``csv``."""
    if format == "kinect-text":
        return write_kinect_text(folder / f"{name}.txt", frames, np.rint(time * KINECT_FRAME_RATE).astype(int))
    return write_joint_csv(folder / f"{name}.csv", frames, time)


def import_copy(path: Path, format: str):
    """Import one copy (CSV copies are in the camera frame: ``up="y"``); returns the file's report."""
    from rlff.capture import import_recordings

    _, report = import_recordings([path], format, up="y" if format == "csv" else None)
    return report.files[0]


def compare(reference, copy, max_release_shift: float = 0.35) -> tuple[bool, float | None, str]:
    """Is the reference's throw found again in the copy: same arm, same count, each release within 0.35 s?

    Returns (found, ratio of the copy's landing estimate to the reference's for the first throw, why not).
    """
    if copy.arm != reference.arm:
        return False, None, f"arm {copy.arm} instead of {reference.arm}"
    if len(copy.throws) != len(reference.throws):
        return False, None, f"{len(copy.throws)} throws instead of {len(reference.throws)}"
    for ours, theirs in zip(copy.throws, reference.throws, strict=True):
        # both on the recording's clock: a thinned copy may start later than the original
        ours_at, theirs_at = ours.release + copy.clock_origin, theirs.release + reference.clock_origin
        if abs(ours_at - theirs_at) > max_release_shift:
            return False, None, f"release at {ours_at:.2f} s instead of {theirs_at:.2f} s"
    ratio = None
    if copy.throws and copy.throws[0].landing and reference.throws[0].landing:
        ratio = copy.throws[0].landing / reference.throws[0].landing
    return True, ratio, ""


def thinned_copies(
    source: Path, folder: Path, formats=("kinect-text", "csv"), rates=RATES, spacings=SPACINGS, phases=(0.0, 0.25, 0.5, 0.75)
) -> tuple[dict, list[Copy]]:
    """Thin one MSR file at every rate, spacing and phase, import each copy and compare it with the 15 Hz copy.

    Returns the 15 Hz reports per format and one :class:`Copy` per thinned copy.
    """
    frames = msr_frames(source)
    time = np.arange(len(frames)) / 15.0
    references, copies = {}, []
    seed = int.from_bytes(source.name.encode()[:8], "little") % 2**32
    for format in formats:
        reference = import_copy(write_copy(folder, f"{source.stem}_15", frames, time, format), format)
        references[format] = reference
        for rate in rates:
            for spacing in spacings:
                for phase in phases:
                    rng = np.random.default_rng([seed, int(rate * 10), int(phase * 100)])
                    kept = thinned_indices(len(frames), 15.0, rate, spacing, phase, rng)
                    name = f"{source.stem}_{rate:g}_{spacing}_{phase:g}"
                    report = import_copy(write_copy(folder, name, frames[kept], time[kept], format), format)
                    found, ratio, why = compare(reference, report)
                    copies.append(Copy(source.name, format, rate, spacing, phase, found, ratio, why))
    return references, copies
