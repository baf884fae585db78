"""Gaps in a throw's extension: where its speed is bridged between samples instead of measured.

A throw's velocity is a local fit over the samples of its angle (:mod:`~rlff.capture.angles`);
where a joint that makes the angle (shoulder, elbow, wrist, hand) has no sample (a frozen tracker,
a blank or zero joint, a dropped row), the fits on either side see one side of the gap only. Two
rules say when that leaves the throw's speed unmeasured:

* a **long gap** anywhere in the extension, over 3 of the recording's usual spacings and 0.1 s
  (:func:`longest_gap`): the importer bridges the velocity across it with the derivative of the
  angle's interpolant and warns;
* a **lost sample at the peak** (:func:`gap_at_the_peak`): a shorter gap, one sample or more lost
  (over 1.75 of the recording's mean spacing while tracked: one lost makes 2) and over 0.1 s,
  inside or at the edge of the extension's fast part, where the angle rises at least half as
  fast as its fastest between two samples. At 15 Hz the MSR high throws extend in 2-3 samples,
  and one of them lost at the peak leaves the written peak at a median 0.54 of the whole throw's
  (``a06_s01_e03``: 7.8 rad/s instead of 14.7), one lost beside it 0.6 (8.8), since the fits of
  the samples around the gap lose their points on its side. The gap's own rise over its time is
  the least speed the elbow reached across it (mean value theorem), and is said with the warning.

Sparse sampling alone is no gap: the rules compare with the recording's own spacing, so 4-10 Hz
copies of the MSR throws thinned regularly have none, and neither does a 30 Hz recording that
lost a sample (0.067 s, under 0.1 s: its fit keeps 7 samples; the peak moves 3 % in the median).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rlff.capture.angles import ArmMotion
from rlff.capture.segment import ThrowCut
from rlff.capture.skeleton import JointTrack

#: A gap in a throw's extension longer than this many of the recording's usual spacings, and
#: than EXTENSION_GAP_S (s), leaves its speed unmeasured there: bridged and warned of (sparse
#: recordings, 4-10 Hz, have no such gap by being sparse alone).
EXTENSION_GAP_FACTOR = 3.0
#: No gap of a throw's extension is warned of unless longer than this (s): a shorter one leaves a
#: local fit enough samples at any rate (at 30 Hz two lost samples make 0.1 s, and the fits over
#: 0.25 s keep 5 of 7).
EXTENSION_GAP_S = 0.1
#: A gap longer than this many of the recording's mean spacings while tracked has lost a sample
#: (one lost makes 2, a regular copy's uneven rounding to the source's frames 1.5 at most).
LOST_SAMPLE_FACTOR = 1.75
#: The extension's fast part: where the angle rises at least this share of its fastest rise
#: between two samples.
FAST_SHARE = 0.5


@dataclass(frozen=True)
class ExtensionGap:
    """A stretch of a throw's extension without samples of a joint that makes the elbow angle.

    Attributes
    ----------
    length : float
        Its duration (s).
    start : float
        Its first instant (s, the recording's clock).
    joints : str
        The joints without samples across it, in words: ``the elbow's``, ``the shoulder's and
        hand's``, ``every joint's``.
    rise : float
        How much the elbow angle rises across it (rad).
    extension_rise : float
        How much it rises over the whole extension, wound up to straight (rad).
    """

    length: float
    start: float
    joints: str
    rise: float
    extension_rise: float

    @property
    def least_speed(self) -> float:
        """The least peak speed (rad/s) the elbow reached across the gap: its rise over its time."""
        return self.rise / self.length

    @property
    def bridged_share(self) -> float:
        """The share of the extension's rise that the gap bridges."""
        return self.rise / self.extension_rise if self.extension_rise > 0 else 0.0


def tracked_spacing(motion: ArmMotion) -> float:
    """Mean time (s) between the samples of ``motion`` within its runs (lost tracking left out).

    The mean, not the median: a regular copy of 15 Hz samples at 10 Hz alternates 1 and 2 source
    frames, and its median spacing may be either; its mean is 0.1 s.
    """
    runs = [run for run in motion.runs() if run.stop - run.start > 1]
    spacings = sum(run.stop - run.start - 1 for run in runs)
    if not spacings:
        return 0.0
    return float(sum(motion.time[run.stop - 1] - motion.time[run.start] for run in runs) / spacings)


def _tracks(motion: ArmMotion) -> list[tuple[str, JointTrack]]:
    """The joints that make the elbow angle, by name, in the order the warnings name them."""
    arm = motion.arm
    tracks = [("shoulder", arm.shoulder), ("elbow", arm.elbow), ("hand", arm.hand)]
    return tracks + [("wrist", arm.wrist)] if arm.wrist is not None else tracks


def _joint_gaps(motion: ArmMotion, begin: float, end: float) -> list[tuple[float, float, str]]:
    """Every spacing (s) between the samples of each joint that makes the angle, from the sample at or
    before ``begin`` to the one at or after ``end``: (spacing, its start, joint name)."""
    tracks = _tracks(motion)
    gaps = []
    for name, track in tracks:
        first = max(int(np.searchsorted(track.time, begin, side="right")) - 1, 0)
        last = int(np.searchsorted(track.time, end, side="left")) + 1
        times = track.time[first:last]
        gaps.extend((float(step), float(at), name) for step, at in zip(np.diff(times), times[:-1], strict=True))
    return gaps


def _joints_in_words(motion: ArmMotion, gaps: list[tuple[float, float, str]], length: float, start: float) -> str:
    """The joints whose samples skip the stretch (``length``, ``start``), to within a sample's jitter."""
    names = [name for name, _ in _tracks(motion)]
    skipping = {name for step, at, name in gaps if step > length - 0.01 and abs(at - start) < 0.01}
    alike = [name for name in names if name in skipping]
    if len(alike) == len(names):
        return "every joint's"
    possessive = [f"{name}'s" for name in alike]
    return "the " + (possessive[0] if len(alike) == 1 else f"{', '.join(possessive[:-1])} and {possessive[-1]}")


def _gap(motion: ArmMotion, cut: ThrowCut, gaps: list[tuple[float, float, str]], length: float,
         start: float) -> ExtensionGap:
    rise = float(np.interp(start + length, motion.time, motion.angle) - np.interp(start, motion.time, motion.angle))
    extension_rise = float(motion.angle[cut.extension_end] - motion.angle[cut.extension_start])
    return ExtensionGap(length, start, _joints_in_words(motion, gaps, length, start), rise, extension_rise)


def longest_gap(motion: ArmMotion, cut: ThrowCut) -> ExtensionGap | None:
    """The longest stretch without samples of any joint that makes the elbow angle during the
    throw's extension (``cut.extension_start`` to ``cut.extension_end``); None without samples."""
    gaps = _joint_gaps(motion, float(motion.time[cut.extension_start]), float(motion.time[cut.extension_end]))
    if not gaps:
        return None
    length, start, _ = max(gaps, key=lambda gap: gap[0])
    return _gap(motion, cut, gaps, length, start)


def fast_part(motion: ArmMotion, cut: ThrowCut) -> tuple[float, float]:
    """(from, to) (s, the recording's clock): the stretch of the extension between the first and the
    last two consecutive samples across which the angle rises at least ``FAST_SHARE`` of its
    fastest rise between two samples there."""
    time = motion.time[cut.extension_start:cut.extension_end + 1]
    rate = np.diff(motion.angle[cut.extension_start:cut.extension_end + 1]) / np.diff(time)  # (E - 1,) rad/s
    fast = np.flatnonzero(rate >= FAST_SHARE * rate.max())
    return float(time[fast[0]]), float(time[fast[-1] + 1])


def gap_at_the_peak(motion: ArmMotion, cut: ThrowCut, bridged_above: float) -> ExtensionGap | None:
    """The gap of a lost sample inside or at the edge of the extension's fast part, or None.

    Parameters
    ----------
    motion : ArmMotion
        The arm the throw was cut from.
    cut : ThrowCut
        The throw; its extension has at least two samples.
    bridged_above : float
        Gaps longer than this (s) are the long-gap rule's (bridged and warned of): not looked at.

    Returns
    -------
    ExtensionGap or None
        The gap, longer than ``LOST_SAMPLE_FACTOR`` x :func:`tracked_spacing` and ``EXTENSION_GAP_S``,
        that touches :func:`fast_part` and across which the angle rises most; None when there is none.
    """
    if cut.extension_end <= cut.extension_start:
        return None
    begin, end = fast_part(motion, cut)
    gaps = _joint_gaps(motion, float(motion.time[cut.extension_start]), float(motion.time[cut.extension_end]))
    least = max(LOST_SAMPLE_FACTOR * tracked_spacing(motion), EXTENSION_GAP_S)
    lost = [_gap(motion, cut, gaps, length, start) for length, start, _ in gaps
            if least < length <= bridged_above and start <= end + 1e-9 and start + length >= begin - 1e-9]
    return max(lost, key=lambda gap: gap.rise, default=None)
