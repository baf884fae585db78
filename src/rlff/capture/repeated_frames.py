"""A tracker that outputs each skeleton several times: a 30 Hz stream of 15 Hz skeletons.

Some trackers write a row per camera frame and a new skeleton only every second (or k-th) frame,
repeating the one before with a new time stamp in between. Taken as samples, the repeats are
frames where every joint stands still while the arm moves: the frozen-tracker rule leaves the
moving joints' repeats out, but the recording's usual spacing, and with it the window of the
velocity fit, comes from the stream's stamps, not from the skeletons': a throw of the same motion
peaked up to 23 % lower than the same skeletons at their own 15 Hz. So when the repeats are the
rule and not an accident (about 1 row in k repeats the row before in every joint, in motion as
at rest), every repeat is left out and the skeletons keep their own rate, their first stamps.

A joint that freezes now and then (a few stretches, a small share of the rows) is the frozen
tracker's, and a noise-free still whose rows repeat (a simulation at rest) repeats only at rest:
neither is taken for a repeating stream.

A ROS bag carries the same stream when the tracker node publishes its last skeleton on every
tick of a timer faster than the camera (each joint's transform again, with a new stamp): the
joints come one transform each, so :func:`repeated_track_samples` first gathers them into rows
by their stamps. A transform re-published with the same stamp is another matter, dropped by the
bag reader as a repeated stamp.

The frozen tracker's rule (:func:`frozen_samples`) is here too, for every reader: a joint whose
position repeats the frame before exactly for a moment while it moves, where the tracker held its
last pose of that joint alone.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

#: The least share of a recording's rows repeating the row before in every joint for the rows to
#: be a repeating stream: a 2x stream repeats 1/2 of its rows, a 3x stream 2/3.
REPEATED_SHARE = 1 / 3
#: The fewest stretches of repeats entered and left in motion, and their least share of the rows
#: where a joint moves on from the row before: in a repeating stream every new skeleton in motion
#: is followed by its repeats (share 1); a tracker that froze now and then, a few.
MOVING_RUNS = 3
MOVING_SHARE = 0.5
#: A joint's speed (m/s) above which a stretch of frames repeating its position exactly is a
#: frozen tracker: a moving joint cannot stop dead to the last digit. A recording without noise
#: coming smoothly to rest (a simulation) slows below it first.
FROZEN_ENTRY_SPEED = 0.5
#: The longest such stretch (s): longer, the tracker lost the joint, and the gap says so.
FROZEN_LONGEST = 0.5


def frozen_samples(joint: np.ndarray, time: np.ndarray) -> np.ndarray:
    """Samples (N,) where one joint's position, shape (N, 3), repeats the sample before exactly,
    in stretches of at most :data:`FROZEN_LONGEST` that it entered and left faster than
    :data:`FROZEN_ENTRY_SPEED` (the first sample of a stretch is kept: the tracker's last real
    pose); ``time`` (N,) increasing stamps (s). A frame of text, a transform of a bag."""
    frozen = np.zeros(len(time), dtype=bool)
    repeats = np.r_[False, np.all(joint[1:] == joint[:-1], axis=1), False]
    edges = np.diff(repeats.astype(np.int8))
    for index, end in zip(np.flatnonzero(edges == 1) + 1, np.flatnonzero(edges == -1) + 1, strict=True):
        held = index - 1  # the last real pose, repeated at rows index .. end - 1
        if 1 <= held and end < len(time) and time[end - 1] - time[held] <= FROZEN_LONGEST:
            # entered moving and left with a jump (the tracker catching up): a still joint whose
            # coordinates repeat (noise-free or rounded) neither enters nor leaves so
            entered = float(np.linalg.norm(joint[held] - joint[held - 1])) / max(time[held] - time[held - 1], 1e-9)
            left = float(np.linalg.norm(joint[end] - joint[end - 1])) / max(time[end] - time[end - 1], 1e-9)
            if min(entered, left) > FROZEN_ENTRY_SPEED:
                frozen[index:end] = True
    return frozen


def repeated_skeletons(frames: np.ndarray, time: np.ndarray, moving_speed: float) -> tuple[np.ndarray, int] | None:
    """The rows to keep of a stream that repeats each skeleton, and how many times it gives each.

    Parameters
    ----------
    frames : array of shape (N, J, 3)
        Joint positions (m); nan where a joint was not tracked (a nan repeats a nan).
    time : array of shape (N,)
        Increasing time stamps (s).
    moving_speed : float
        Speed (m/s) above which a joint moves from one row to the next (the frozen-tracker rule's).

    Returns
    -------
    (keep, times) or None
        ``keep`` of shape (N,): the first row of each skeleton, and in a longer run of one
        skeleton (a still) every ``times``-th row, the skeletons' own rate; ``times`` the number
        of rows each skeleton takes in motion. None when the rows are not a repeating stream.
    """
    count = len(time)
    if count < 3:
        return None
    steps = np.diff(frames, axis=0)  # (N - 1, J, 3)
    equal = (frames[1:] == frames[:-1]) | (np.isnan(frames[1:]) & np.isnan(frames[:-1]))
    same = np.r_[False, np.all(equal, axis=(1, 2))]  # (N,): a row that repeats the row before
    if same.sum() < REPEATED_SHARE * count:
        return None
    speed = np.linalg.norm(np.nan_to_num(steps), axis=2).max(axis=1) / np.diff(time)  # (N - 1,) fastest joint
    moves = np.r_[False, speed > moving_speed]  # (N,): a row whose joints moved on from the row before
    edges = np.diff(np.r_[0, same.astype(np.int8), 0])
    starts, stops = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)  # runs of repeats [start, stop)
    # a run entered and left in motion: its skeleton came on a jump, and the next one jumps on
    moving = [(start, stop) for start, stop in zip(starts, stops, strict=True)
              if start >= 2 and stop < count and moves[start - 1] and moves[stop]]
    if len(moving) < MOVING_RUNS or len(moving) < MOVING_SHARE * moves.sum():
        return None
    times = int(np.median([stop - start for start, stop in moving])) + 1
    keep = ~same
    for start, stop in zip(starts, stops, strict=True):
        copies = np.arange(start, stop)  # the skeleton of row start - 1, given again
        keep[copies[(copies - start + 1) % times == 0]] = True  # a still keeps the skeletons' rate
    return keep, times


def repeated_track_samples(
    times: Sequence[np.ndarray], positions: Sequence[np.ndarray], moving_speed: float,
) -> tuple[list[np.ndarray], np.ndarray, np.ndarray, int] | None:
    """:func:`repeated_skeletons` for joints stamped one by one (a tf stream: a frame per joint).

    The joints' samples are gathered into rows by their stamps: a row holds the stamps within a
    quarter of the usual spacing of the joint sampled most (a tracker stamps a skeleton's joints
    together, or microseconds apart), at its first stamp; a joint without a sample in a row (a
    joint the tracker dropped) is nan there.

    Parameters
    ----------
    times : sequence of J arrays of shape (T_j,)
        Each joint's increasing stamps (s).
    positions : sequence of J arrays of shape (T_j, 3)
        Each joint's positions (m).
    moving_speed : float
        Speed (m/s) above which a joint moves from one row to the next.

    Returns
    -------
    (keep, rows, kept_rows, times) or None
        ``keep``: per joint, a bool array of shape (T_j,), False for its samples in the rows left
        out; ``rows`` of shape (N,) the rows' stamps (s), ``kept_rows`` of shape (N,) the rows
        kept (:func:`repeated_skeletons`), and ``times`` the number of rows each skeleton takes in
        motion. None when the rows are not a repeating stream.
    """
    densest = max(times, key=len)
    if len(densest) < 3:
        return None
    tolerance = 0.25 * float(np.median(np.diff(densest)))
    stamps = np.concatenate(times)
    order = np.argsort(stamps, kind="stable")
    row = np.empty(stamps.size, dtype=int)  # each sample's row, in the order of ``stamps``
    row[order] = np.cumsum(np.r_[True, np.diff(stamps[order]) > tolerance]) - 1
    starts = np.r_[0, np.cumsum([len(time) for time in times])]
    row_of = [row[begin:end] for begin, end in zip(starts[:-1], starts[1:], strict=True)]  # per joint (T_j,)
    rows = np.full(row.max() + 1, np.inf)
    np.minimum.at(rows, row, stamps)  # a row's stamp: its first
    frames = np.full((rows.size, len(times), 3), np.nan)
    for joint, (rows_of_joint, position) in enumerate(zip(row_of, positions, strict=True)):
        frames[rows_of_joint, joint] = position
    found = repeated_skeletons(frames, rows, moving_speed)
    if found is None:
        return None
    keep_rows, count = found
    return [keep_rows[rows_of_joint] for rows_of_joint in row_of], rows, keep_rows, count
