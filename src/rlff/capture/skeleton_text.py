"""Skeleton recordings as text: Kinect SDK v1 joint text, MSR Action3D text, CSV of joint positions.

Kinect SDK v1 text
    One line per frame: the frame number, then 20 joints x (x y z) in the Kinect's joint order
    (0-based: 4-7 shoulder, elbow, wrist, hand left; 8-11 shoulder, elbow, wrist, hand right;
    the torso: 2 shoulder centre, 0 hip centre).
    Time is frame number / frame rate (default 30 Hz), so dropped frames keep their place.
MSR Action3D
    20 lines ``x y z confidence`` per frame, no time stamps: time is frame index / 15 Hz. Arm B
    (lines 2, 9, 11, 13) is reported as the right arm, arm A (lines 1, 8, 10, 12) as the left;
    the torso is line 3 (neck) to line 7 (hip centre).
CSV
    One row per frame with columns ``{side}_{joint}_{axis}`` (e.g. ``right_elbow_x``; joints
    shoulder, elbow, hand and optionally wrist), optionally the torso's ``neck_{axis}`` and
    ``hip_{axis}`` (hip centre), and an optional ``time`` column (s), or any other names through
    a column map.

Frames whose arm joints are all zero (the tracker lost the user) are dropped, a single joint at
exactly (0, 0, 0) (a joint not detected) or with a coordinate beyond
:data:`~rlff.capture.skeleton.FARTHEST` (100 m, no camera's: as in a bag; unless most joints are,
a recording in millimetres) is left out of its track in that frame, and so are repeats
of the frame number (Kinect) or time stamp (CSV) of the row before; each reader says how many in
its notes. A time stamp (or frame number) a little below one before it, by less than a quarter
of the median step, is clock jitter (a host clock stamping frames as they arrive): the rows are put
in time order, with a note. Further below (two recordings appended, a clock reset, rows out of
order) it is an error naming its line: such rows are never re-sorted.
"""

from __future__ import annotations

import math
import re
import shlex
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import NamedTuple

import numpy as np

from rlff.capture.angles import median_spacing
from rlff.capture.repeated_frames import FROZEN_ENTRY_SPEED, frozen_samples, repeated_skeletons
from rlff.capture.skeleton import FARTHEST, SIDES, ArmTrack, JointTrack, Recording
from rlff.csvlines import data_row_line, header_separator
from rlff.errors import InputError
from rlff.fileio import require_file
from rlff.limits import FRAME_RATE_RANGE, check_frame_rate, is_number
from rlff.wording import bad_cell, did_you_mean, nearest_hint, plural

#: Up direction of the Kinect's camera frame (x left, y up, z away from the camera).
KINECT_UP = np.array([0.0, 1.0, 0.0])
#: Kinect SDK v1 joint indices (0-based) of each side: shoulder, elbow, wrist, hand.
KINECT_ARMS = {"right": (8, 9, 10, 11), "left": (4, 5, 6, 7)}
#: MSR Action3D joint indices (0-based lines within a frame): arm B is the throwing arm of a06.
MSR_ARMS = {"right": (1, 8, 10, 12), "left": (0, 7, 9, 11)}
#: Torso joints (0-based), top then bottom: Kinect SDK v1 shoulder centre and hip centre, MSR
#: neck and hip centre.
KINECT_TORSO = (2, 0)
MSR_TORSO = (2, 6)
#: Torso points of the CSV format (columns ``{name}_{axis}``), top then bottom.
CSV_TORSO = ("neck", "hip")
KINECT_RATE_HZ = 30.0
MSR_RATE_HZ = 15.0
_JOINTS = ("shoulder", "elbow", "wrist", "hand")
_AXES = ("x", "y", "z")
#: Every column name the CSV reader looks for (each read as it is, or through a column map).
CSV_NAMES = ("time", *(f"{side}_{joint}_{axis}" for side in SIDES for joint in _JOINTS for axis in _AXES),
             *(f"{point}_{axis}" for point in CSV_TORSO for axis in _AXES))


#: Numbers in a row of Kinect SDK v1 text as rlff reads it (a frame number, 20 joints x (x y z)),
#: and as exporters that add each joint's tracking state write it: what that is, what to drop.
KINECT_WIDTH = 61
KINECT_WITH_STATE = 81
WITH_STATE_IS = ("a frame number and 20 joints x 4 values (x y z and a tracking state, as some Kinect SDK v1 "
                 "exporters write them)")
WITH_STATE_DROP = "each joint's 4th value (rlff reads x y z)"
#: Numbers in a row of Kinect v2 joint text (25 joints), which the Kinect text reader does not
#: take, and what they are; :data:`KINECT_V2_ROUTE` is the way to import such a file.
KINECT_V2_WIDTHS = {76: "a frame number and 25 joints x (x y z)",
                    101: "a frame number and 25 joints x 4 values (x y z and a tracking state)"}
KINECT_V2_ROUTE = ("which rlff does not read (its Kinect text is Kinect SDK v1's, 20 joints): "
                   "write the arm's joints as a CSV with a header row naming them (Kinect v2's joints 8-11, from 0, "
                   "are the right shoulder, elbow, wrist and hand, 4-7 the left's) and import that with --format csv "
                   "--columns ... --up y (docs/capture.md, \"A CSV of joint positions\")")


def _numeric_rows(
    path: Path, expected: int, what: str, frame_of: Callable[[int, list[float]], str]
) -> tuple[np.ndarray, np.ndarray]:
    """Whitespace- or comma-separated numbers, ``expected`` per line; blank and # lines skipped,
    a UTF-8 byte order mark read past.

    ``frame_of(row, values)`` names the frame of the ``row``-th numeric line (0-based) in messages.
    Returns the values, shape (N, expected), and the file line of each row, shape (N,); raises
    InputError naming the first bad line (a header line, or a row of another known width, with
    what to drop).
    """
    require_file(path)
    rows, lines = [], []
    with path.open(encoding="utf-8-sig", errors="replace") as handle:
        for number, line in enumerate(handle, start=1):
            text = line.split("#", 1)[0].replace(",", " ").strip()
            if not text:
                continue
            fields = text.split()
            if not rows and not any(is_number(value) for value in fields):
                raise InputError(f"{path}, line {number}: a header line ({text[:60]!r}), where rlff reads numbers "
                                 f"only ({what}): drop the line")
            if len(fields) != expected:
                raise InputError(f"{path}, line {number}: {len(fields)} columns, expected {expected} ({what})"
                                 + (_kinect_width(len(fields)) if expected == KINECT_WIDTH else ""))
            try:
                row = [float(value) for value in fields]
            except ValueError:
                raise InputError(f"{path}, line {number}: non-numeric value in {text[:60]!r}") from None
            # nan is a joint the tracker did not give (the readers drop the frame where rlff reads
            # that joint); inf is no tracker's
            bad = next((index for index, value in enumerate(row) if math.isinf(value)), None)
            if bad is not None:
                raise InputError(
                    f"{path}, line {number} ({frame_of(len(rows), row)}): value {bad + 1} is "
                    f"{fields[bad]!r}, not a finite number"
                )
            rows.append(row)
            lines.append(number)
    if not rows:
        raise InputError(f"{path}: no frames ({what})")
    return np.asarray(rows), np.asarray(lines)


class RowLayout(NamedTuple):
    """A layout of Kinect text rows that rlff knows but does not read (:func:`kinect_row_layout`).

    Attributes
    ----------
    holds : str
        What a row holds, in words.
    drop : str or None
        What to drop from every row to make it Kinect SDK v1 text as rlff reads it; None for
        Kinect v2 text, which no dropping makes one (:data:`KINECT_V2_ROUTE` imports it).
    """

    holds: str
    drop: str | None


def kinect_row_layout(width: int) -> RowLayout | None:
    """The layout of a text row of ``width`` numbers where Kinect SDK v1 text has
    :data:`KINECT_WIDTH`: a tracking state after each joint's x y z (:data:`KINECT_WITH_STATE`),
    Kinect v2's 25 joints (:data:`KINECT_V2_WIDTHS`); None for a width rlff does not know."""
    if width == KINECT_WITH_STATE:
        return RowLayout(WITH_STATE_IS, WITH_STATE_DROP)
    if width in KINECT_V2_WIDTHS:
        return RowLayout(KINECT_V2_WIDTHS[width], None)
    return None


def _kinect_width(width: int) -> str:
    """What a row of ``width`` numbers in a Kinect text file is and what to do, when rlff knows
    the layout (:func:`kinect_row_layout`), after ``"; "``; else ``""``."""
    layout = kinect_row_layout(width)
    if layout is None:
        return ""
    if layout.drop is not None:
        return f"; {width} are {layout.holds}: drop {layout.drop}"
    return f"; {width} look like Kinect v2 joint text ({layout.holds}), {KINECT_V2_ROUTE}"


#: A stamp below the latest one before it by less than this share of the median step between
#: stamps is clock jitter (a host clock stamping frames as they arrive): the rows are put in time
#: order. A larger step back is two recordings appended, a clock reset or rows out of order.
JITTER_SHARE = 0.25


def _forward_rows(
    stamps: np.ndarray, line_of: Callable[[int], int], what: str, notes: list[str], path: Path, unit: str = "",
) -> np.ndarray:
    """Rows to keep, in the order of their ``what`` (time, frame number) ``stamps`` of shape (N,):
    row indices of shape (M,), M <= N. Stamps below one before them by less than
    :data:`JITTER_SHARE` of the median step forward are put in order, and a repeat of the stamp
    before is dropped, each with a note.

    ``line_of(row)`` is a row's file line; ``unit`` follows a stamp's value in the note (`` s``).
    Raises InputError at the first stamp further below one before it (two recordings appended, a
    clock reset, rows out of order).
    """
    behind = np.maximum.accumulate(stamps)[:-1] - stamps[1:]  # (N - 1,): > 0 where a stamp goes back
    ahead = -behind[behind < 0]
    jitter = JITTER_SHARE * float(np.median(ahead)) if ahead.size else 0.0
    far = (behind > 0) & (behind >= jitter)
    if far.any():
        row = int(np.flatnonzero(far)[0]) + 1
        raise InputError(
            f"{path}, line {line_of(row)}: {what} {stamps[row]:g} after {stamps[row - 1]:g} goes back "
            f"(two recordings appended, or rows out of order?): split the file at this line, or sort "
            f"its rows by {what}"
        )
    order = np.argsort(stamps, kind="stable")
    if np.any(behind > 0):
        back = np.flatnonzero(behind > 0)
        notes.append(
            f"{path.name}: {plural(back.size, what)} went back, by at most {behind.max():.3g}{unit}, under "
            f"{JITTER_SHARE:.0%} of the median step (clock jitter; the first on line {line_of(int(back[0]) + 1)}): "
            f"the rows put in {what} order"
        )
    repeat = np.r_[False, np.diff(stamps[order]) == 0]
    if repeat.any():
        notes.append(
            f"{path.name}: dropped {plural(int(repeat.sum()), 'repeated ' + what)} (kept the first; the first "
            f"repeat is on line {line_of(int(order[np.flatnonzero(repeat)[0]]))})"
        )
    return order[~repeat]


def _span(time: np.ndarray) -> tuple[float, float] | None:
    """(first, last) of a file's frame times (N,) (s), before any frame is dropped; None without frames."""
    return (float(time[0]), float(time[-1])) if len(time) else None


def _untracked(frames: np.ndarray, time: np.ndarray, read_joints: list[int], where: np.ndarray,
               notes: list[str], path: Path, what: str, why: str = "") -> None:
    """Set to nan, in place, the joints of ``frames`` (N, J, 3) that ``where`` (N, len(read_joints))
    marks as not tracked in a frame, with a note of how many frames, ``what`` they hold, ``why``
    that is no position and the first one's time (``time`` (N,), s); nothing when ``where`` marks
    none."""
    if not where.any():
        return
    rows = where.any(axis=1)
    notes.append(f"{path.name}: {plural(int(rows.sum()), 'frame')} {what} ({why}the first at "
                 f"t={time[int(np.flatnonzero(rows)[0])]:.2f} s): taken as not tracked there, left out of that "
                 "joint's track")
    marked = np.zeros(frames.shape[:2], dtype=bool)
    marked[:, read_joints] = where
    frames[marked] = np.nan


def _clean_frames(
    frames: np.ndarray, time: np.ndarray, arm_joints: list[int], notes: list[str], path: Path,
    read_joints: list[int] | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Drop frames whose arm joints are all at zero (the tracker lost the user); note the frames
    with a nan in a joint that is read, and set to nan a joint at exactly (0, 0, 0) (the sensor's
    origin: how trackers such as OpenPose write a joint they did not detect), a joint with a
    coordinate beyond :data:`~rlff.capture.skeleton.FARTHEST` (as a bag reader leaves out such a
    transform; unless most joints are, a recording in millimetres, which the import's upper-arm
    check refuses naming the unit), and a joint a frozen
    tracker repeated (:func:`~rlff.capture.repeated_frames.frozen_samples`; :func:`_track` leaves
    them all out of that joint's track). A stream that gives each skeleton several times keeps
    each skeleton once (:func:`repeated_skeletons`).

    Parameters
    ----------
    frames : array of shape (N, J, 3); nan where the tracker gave no value
    time : array of shape (N,)
    arm_joints : joint indices whose loss means the frame is useless
    read_joints : every joint index the readers use (arms and torso; default ``arm_joints``): a
        nan in another joint (the head, the feet) is no loss
    """
    read_joints = arm_joints if read_joints is None else read_joints
    lost = np.all(frames[:, arm_joints, :] == 0.0, axis=(1, 2))
    if lost.any():
        notes.append(f"{path.name}: dropped {int(lost.sum())} frames with all arm joints at zero (tracking lost)")
    blank = ~np.all(np.isfinite(frames[:, read_joints, :]), axis=2)  # (N, read joints)
    if blank.any():
        rows, first = int(blank.any(axis=1).sum()), int(np.flatnonzero(blank.any(axis=1))[0])
        notes.append(f"{path.name}: {plural(rows, 'frame')} with a nan or blank value in a joint rlff reads (the "
                     f"first at t={time[first]:.2f} s): left out of that joint's track (tracking lost there)")
    if (~lost).sum() < 2:
        raise InputError(f"{path}: fewer than 2 frames with a tracked arm")
    frames, time = frames[~lost].copy(), time[~lost]
    read = frames[:, read_joints, :]  # (N, R, 3), a copy
    at_origin = np.all(read == 0.0, axis=2)  # (N, R): a joint the tracker did not detect
    _untracked(frames, time, read_joints, at_origin, notes, path,
               "with a joint at exactly (0, 0, 0), the sensor's origin",
               "how trackers such as OpenPose write a joint they did not detect; ")
    far = np.any(np.abs(read) > FARTHEST, axis=2)  # (N, R): a coordinate no camera sees (1e30)
    given = np.all(np.isfinite(read), axis=2) & ~at_origin
    # most joints that far: a recording in another unit (millimetres), which the import's upper-arm
    # check names; a few: a tracker's bad arithmetic
    if far.sum() <= 0.5 * given.sum():
        _untracked(frames, time, read_joints, far, notes, path,
                   f"with a joint's coordinate beyond {FARTHEST:g} m, farther than a depth camera sees")
    repeating = repeated_skeletons(frames[:, read_joints, :], time, FROZEN_ENTRY_SPEED)
    if repeating is not None:
        keep, times = repeating
        notes.append(f"{path.name}: {int((~keep).sum())} of {len(time)} frames repeat the frame before in every joint, "
                     f"in motion too: the tracker gives each skeleton {times} times ({1 / median_spacing(time):.3g} Hz "
                     f"of {1 / median_spacing(time[keep]):.3g} Hz skeletons); the repeats left out, the skeletons read at "
                     "their own rate")
        frames, time = frames[keep], time[keep]
    held = np.zeros(frames.shape[:2], dtype=bool)  # (N, J): a joint the tracker froze in that frame
    for joint in read_joints:
        held[:, joint] = frozen_samples(frames[:, joint, :], time)
    if held.any():
        rows = held.any(axis=1)
        first = int(np.flatnonzero(rows)[0])
        notes.append(f"{path.name}: {plural(int(rows.sum()), 'frame')} where a joint repeats its value of the frame "
                     f"before exactly while it was moving (a frozen tracker; the first at t={time[first]:.2f} s): "
                     "left out of that joint's track, the motion bridged across")
        frames[held] = np.nan
    return frames, time


def _track(name: str, time: np.ndarray, positions: np.ndarray) -> JointTrack:
    """The joint's track of its frames with a value, positions (N, 3) at ``time`` (N,): a nan (a
    frame the tracker did not give the joint) is left out, as a bag leaves out a missing frame."""
    given = np.all(np.isfinite(positions), axis=1)
    return JointTrack(name, time[given], positions[given])


def _arms(
    frames: np.ndarray, time: np.ndarray, layout: Mapping[str, tuple[int, ...]], torso: tuple[int, int],
) -> list[ArmTrack]:
    """Arm tracks from frames of shape (N, J, 3) sharing one time base of shape (N,), with the
    torso's top and bottom joints ``torso``; each track named as in messages: ``right elbow
    (joint 10)``, the joint's 1-based place in the frame."""
    neck, hip = (_track(f"{name} (joint {index + 1})", time, frames[:, index, :])
                 for name, index in zip(("neck", "hip centre"), torso, strict=True))
    arms = []
    for side, indices in layout.items():
        joints = {
            joint: _track(f"{side} {joint} (joint {index + 1})", time, frames[:, index, :])
            for joint, index in zip(_JOINTS, indices, strict=True)
        }
        arms.append(ArmTrack("1", side, joints["shoulder"], joints["elbow"], joints["hand"], joints["wrist"], neck, hip))
    return arms


def read_kinect_text(path: str | Path, rate_hz: float | None = None) -> Recording:
    """Read a Kinect SDK v1 joint text file.

    Parameters
    ----------
    path : path of the file
    rate_hz : float, optional
        Frame rate (default 30 Hz); time = frame number / rate.

    Raises
    ------
    InputError
        A line without 61 columns, a non-numeric or non-finite value, a frame number that goes
        back, or no tracked frame.
    """
    path = Path(path)
    rate = KINECT_RATE_HZ if rate_hz is None else check_frame_rate(rate_hz)
    values, lines = _numeric_rows(
        path, KINECT_WIDTH, "frame number then 20 joints x (x y z)", lambda row, values: f"frame number {values[0]:g}"
    )
    notes: list[str] = []
    if np.isnan(values[:, 0]).any():
        raise InputError(f"{path}, line {int(lines[np.flatnonzero(np.isnan(values[:, 0]))[0]])}: the frame number is "
                         "'nan', not a number")
    values = values[_forward_rows(values[:, 0], lambda row: int(lines[row]), "frame number", notes, path)]
    frames = values[:, 1:].reshape(-1, 20, 3)
    arm_joints = [i for indices in KINECT_ARMS.values() for i in indices]
    span = _span(values[:, 0] / rate)
    frames, time = _clean_frames(frames, values[:, 0] / rate, arm_joints, notes, path, [*arm_joints, *KINECT_TORSO])
    return Recording(str(path), _arms(frames, time, KINECT_ARMS, KINECT_TORSO), KINECT_UP, notes,
                     assumed_rate=rate, frames_span=span)


def read_msr_text(path: str | Path, rate_hz: float | None = None) -> Recording:
    """Read an MSR Action3D skeleton file (20 lines ``x y z confidence`` per frame).

    Parameters
    ----------
    path : path of the file
    rate_hz : float, optional
        Frame rate (default 15 Hz); time = frame index / rate.

    Raises
    ------
    InputError
        A line without 4 columns, a non-numeric or non-finite value, a line count that is not a
        multiple of 20, or no tracked frame.
    """
    path = Path(path)
    rate = MSR_RATE_HZ if rate_hz is None else check_frame_rate(rate_hz)
    values, _ = _numeric_rows(
        path, 4, "x y z confidence", lambda row, values: f"frame {row // 20 + 1}, joint {row % 20 + 1}"
    )
    if len(values) % 20:
        raise InputError(
            f"{path}: {len(values)} joint lines, not a multiple of 20 (20 joints per frame); "
            f"the last frame is missing {20 - len(values) % 20} joints"
        )
    frames = values[:, :3].reshape(-1, 20, 3)
    notes: list[str] = []
    arm_joints = [i for indices in MSR_ARMS.values() for i in indices]
    time = np.arange(len(frames)) / rate
    span = _span(time)
    frames, time = _clean_frames(frames, time, arm_joints, notes, path, [*arm_joints, *MSR_TORSO])
    return Recording(str(path), _arms(frames, time, MSR_ARMS, MSR_TORSO), KINECT_UP, notes, assumed_rate=rate,
                     frames_span=span)


def read_joint_csv(
    path: str | Path,
    columns: Mapping[str, str] | None = None,
    rate_hz: float | None = None,
    up: str = "z",
    arm: str = "auto",
) -> Recording:
    """Read a CSV of joint positions, one row per frame.

    A file with ``;`` or tab between its header's names is read with that separator, and a
    decimal comma or point. Without a time column, frames are ``rate_hz`` apart, 30 Hz with a
    warning when not given; with one, ``rate_hz`` is ignored (a note says so). An arm, wrist or
    torso with some of its columns and not all (a misspelt header, a column the export lost) is
    left out with a warning naming the columns it lacks.

    Parameters
    ----------
    path : path of the file
    columns : mapping of str to str, optional
        Our name -> the file's column name, for any of ``time``,
        ``{side}_{joint}_{axis}`` (side right/left, joint shoulder/elbow/wrist/hand, axis x/y/z)
        and the torso's ``neck_{axis}`` and ``hip_{axis}``. Names not mapped are looked up as
        they are.
    rate_hz : float, optional
        Frame rate when the file has no ``time`` column (default 30 Hz, with a warning).
    up : {"x", "y", "z", "-x", "-y", "-z"}
        Axis pointing up in the file's frame.
    arm : {"auto", "right", "left"}
        The side whose throws will be cut: that arm lacking some of its columns is an error, not
        a warning.

    Raises
    ------
    InputError
        No arm with all of shoulder, elbow and hand x/y/z columns (the message lists what is
        missing and the columns that are there), the ``arm`` asked for with some of its columns
        and not all (the message names those it lacks), a header without rows, a column map entry whose
        name is not one of ours or whose column the file does not have (with the nearest), a
        non-numeric value, or a time stamp below the one before.
    """
    import pandas as pd

    path = Path(path)
    require_file(path)
    notes: list[str] = []
    warnings: list[str] = []
    separator = header_separator(path)
    _require_header(path, separator)
    if separator != ",":
        shown = "tab" if separator == "\t" else repr(separator)
        notes.append(f"{path.name}: columns separated by {shown} (decimal comma or point)")
    try:
        frame = pd.read_csv(path, sep=separator, decimal="." if separator == "," else ",", skipinitialspace=True)
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise InputError(f"{path}: not a readable CSV ({str(exc).strip().splitlines()[-1]})") from None
    if frame.empty:
        raise InputError(f"{path}: no frames (a header and no rows below it)")
    frame.columns = [str(name).strip() for name in frame.columns]  # "time, right_shoulder_x, ..." as Excel writes
    mapping = dict(columns or {})
    _check_column_map(mapping, [str(name) for name in frame.columns], path)

    def column(name: str) -> str | None:
        real = mapping.get(name, name)
        return real if real in frame.columns else None

    read: dict[str, tuple[np.ndarray, np.ndarray]] = {}  # a column's numbers and blank cells, read once

    def numeric(name: str, finite: bool = True) -> np.ndarray:
        """The column's numbers; a cell that is no number is an error, and a blank or nan one too
        unless ``finite`` is False (then nan: a joint the tracker did not give)."""
        if name not in read:
            column = frame[name]
            blank = column.isna().to_numpy()  # pandas reads empty cells, nan, NA, n/a as missing
            if not pd.api.types.is_numeric_dtype(column):  # text among the numbers (dtype object, or str
                # under pandas 3): "nan" spelt otherwise (NAN, " nan") is blank too
                blank = blank | column.astype(str).str.strip().str.lower().isin(["", "nan"]).to_numpy()
            read[name] = (pd.to_numeric(column, errors="coerce").to_numpy(dtype=float), blank)
        values, blank = read[name]
        bad = ~np.isfinite(values) & (True if finite else ~blank)
        if bad.any():
            row = int(np.flatnonzero(bad)[0])
            raise InputError(f"{path}, line {data_row_line(path, row, separator)}: column {name!r} has {bad_cell(frame[name].iloc[row])}")
        return values

    found: dict[str, dict[str, str]] = {}
    missing: dict[str, list[str]] = {}
    for side in SIDES:
        names = {f"{joint}_{axis}": column(f"{side}_{joint}_{axis}") for joint in _JOINTS for axis in _AXES}
        need = [f"{side}_{joint}_{axis}" for joint in ("shoulder", "elbow", "hand") for axis in _AXES]
        absent = [name for name in need if names[name.split("_", 1)[1]] is None]
        if absent:
            missing[side] = absent
        else:
            found[side] = {key: value for key, value in names.items() if value is not None}
    if not found:
        wanted = "; ".join(f"{side}: {', '.join(names)}" for side, names in missing.items())
        raise InputError(
            f"{path}: no arm with shoulder, elbow and hand x/y/z columns (missing {wanted}); "
            f"columns present: {', '.join(map(str, frame.columns))}; map the file's names to rlff's with --columns "
            "(e.g. --columns right_elbow_x=ElbowRight.X, docs/capture.md)"
        )
    # some of a group's columns and not all is a misspelt header or a column the export lost: said,
    # else the other arm's throws would be imported in its place without a word
    unread = [name for name in frame.columns if name not in {column(ours) for ours in CSV_NAMES}]
    for side, absent in missing.items():
        if any(column(f"{side}_{joint}_{axis}") is not None for joint in _JOINTS for axis in _AXES):
            lacks = f"{path}: the {side} arm lacks {_lacking(absent, unread)}"
            if side == arm:
                raise InputError(lacks + _add_or_map(absent))
            warnings.append(f"{lacks}: left out, its throws not imported{_add_or_map(absent)}")
    for side in found:
        absent = [f"{side}_wrist_{axis}" for axis in _AXES if column(f"{side}_wrist_{axis}") is None]
        if 0 < len(absent) < len(_AXES):
            warnings.append(f"{path}: the {side} wrist lacks {_lacking(absent, unread)}: the arm read without its "
                            f"wrist{_add_or_map(absent)}")
    absent = [f"{point}_{axis}" for point in CSV_TORSO for axis in _AXES if column(f"{point}_{axis}") is None]
    if 0 < len(absent) < len(CSV_TORSO) * len(_AXES):
        warnings.append(f"{path}: the torso lacks {_lacking(absent, unread)}: left out, the shoulder's elevation "
                        f"measured against the vertical{_add_or_map(absent)}")
    rate = None if rate_hz is None else check_frame_rate(rate_hz)
    time_column = column("time")
    if time_column is not None:
        time = numeric(time_column)
        if rate is not None:
            notes.append(f"{path.name}: --rate {rate:g} Hz is ignored: the time column {time_column!r} gives the time")
    else:
        time = np.arange(len(frame)) / (KINECT_RATE_HZ if rate is None else rate)
        timelike = [str(name) for name in frame.columns if any(word in str(name).lower() for word in ("time", "stamp"))]
        # quoted as a shell needs it: a pasted --columns time=Time (s) breaks at the space
        hint = (f" (the file has a column {timelike[0]!r}: map it with --columns {shlex.quote('time=' + timelike[0])})"
                if timelike else "")
        if rate is None:
            warnings.append(
                f"{path}: no time column: frames taken as {KINECT_RATE_HZ:g} Hz; give --rate or map the time "
                f"column{hint}"
            )
        elif timelike:
            notes.append(f"{path.name}: no time column: frames taken as {rate:g} Hz (--rate){hint}")
    # rows out of order first: the steps between shuffled rows are no frame rate
    keep = _forward_rows(time, lambda row: data_row_line(path, row, separator), "time stamp", notes, path, " s")
    if time_column is not None:
        _check_time_unit(time[keep], time_column, path)
    torso = {}
    for point in CSV_TORSO:
        names = [column(f"{point}_{axis}") for axis in _AXES]
        if all(name is not None for name in names):
            torso[point] = dict(zip((f"{point}_{axis}" for axis in _AXES), names, strict=True))
    # a blank or nan cell is a joint the tracker did not give: mostly blank, the arm or torso is
    # not tracked and is left out; else the rows where it is blank are lost tracking
    for group, label in ((found, "arm"), (torso, "torso")):
        for name in list(group):
            cells = np.column_stack([numeric(column_name, finite=False)[keep] for column_name in group[name].values()])
            share = float(np.mean(~np.all(np.isfinite(cells), axis=1)))
            if share > 0.5 and (label == "torso" or len(found) > 1):
                what = f"the {name} arm" if label == "arm" else f"the torso's {name} point"
                # an arm left out may be the throwing one: a warning; a torso point only changes
                # what the shoulder's elevation is measured against
                (warnings if label == "arm" else notes).append(
                    f"{path}: {what} is blank or nan in {share:.0%} of the rows: left out")
                del group[name]
    sides = list(found)
    joints_by_side = {
        side: [joint for joint in _JOINTS if f"{joint}_x" in found[side] and f"{joint}_y" in found[side] and f"{joint}_z" in found[side]]
        for side in sides
    }
    slots = [(side, joint) for side in sides for joint in joints_by_side[side]]
    arm_slots = list(range(len(slots)))
    if len(torso) == len(CSV_TORSO):
        for point in CSV_TORSO:
            found[point] = torso[point]
            slots.append((point, point))
    frames = np.stack(
        [np.column_stack([numeric(found[side][f"{joint}_{axis}"], finite=False) for axis in _AXES])
         for side, joint in slots],
        axis=1,
    )[keep]
    time = time[keep]
    span = _span(time)
    frames, time = _clean_frames(frames, time, arm_slots, notes, path, list(range(len(slots))))
    neck, hip = (
        (_track(point, time, frames[:, slots.index((point, point)), :]) for point in CSV_TORSO)
        if (CSV_TORSO[0], CSV_TORSO[0]) in slots else (None, None)
    )
    arms = []
    for side in sides:
        tracks = {
            joint: _track(f"{side}_{joint}", time, frames[:, slots.index((side, joint)), :])
            for joint in joints_by_side[side]
        }
        arms.append(ArmTrack("1", side, tracks["shoulder"], tracks["elbow"], tracks["hand"], tracks.get("wrist"), neck, hip))
    assumed = None if time_column is not None else (KINECT_RATE_HZ if rate is None else rate)
    return Recording(str(path), arms, axis_vector(up), notes, warnings, assumed_rate=assumed, frames_span=span)


def _check_time_unit(time: np.ndarray, name: str, path: Path) -> None:
    """Refuse a time column whose median step puts the frame rate outside :data:`FRAME_RATE_RANGE`
    (a column in milliseconds, or in microseconds), naming the unit it looks like; ``time`` of
    shape (N,) is the column's stamps in order, without repeats (:func:`_forward_rows`)."""
    steps = np.diff(time)
    if steps.size == 0:
        return  # one row, or all repeats: the rows' own checks say so
    spacing = float(np.median(steps))
    low, high = FRAME_RATE_RANGE
    if abs(spacing - 1.0) < 1e-6 and np.allclose(steps, np.round(steps), rtol=0, atol=1e-6):
        # 1 Hz is a rate, but whole steps of 1 count frames
        raise InputError(f"{path}: the time column {name!r} steps by 1 per frame in whole numbers: a frame number? "
                         "rlff reads seconds: divide it by the frame rate, or rename the column and give --rate")
    if low <= 1.0 / spacing <= high:
        return
    looks = ""
    for unit, per_second in (("milliseconds", 1e3), ("microseconds", 1e6), ("nanoseconds", 1e9)):
        if low <= per_second / spacing <= high:
            looks = f": it looks like {unit} (divide the column by {per_second:,.0f})"
            break
    raise InputError(f"{path}: the time column {name!r} steps by {spacing:.6g} per frame (median), "
                     f"{1.0 / spacing:.3g} frames per second, outside {low:g}-{high:g} Hz; rlff reads seconds{looks}")


def _require_header(path: Path, separator: str) -> None:
    """:class:`InputError` when the CSV's first line holds numbers only: a file without a header
    row of names, whose first row of numbers had been read as its column names and listed as
    "columns present" (a Kinect text file given as --format csv)."""
    with path.open(encoding="utf-8-sig", errors="replace") as handle:
        first = next((line.strip() for line in handle if line.strip()), "")
    cells = first.replace(separator, " ").split()
    decimal = "." if separator == "," else ","
    if not cells or not all(is_number(cell.replace(decimal, ".")) for cell in cells):
        return
    shown = first if len(first) <= 40 else f"{first[:40]}..."
    spaced = len(cells) > 1 and separator not in first
    raise InputError(
        f"{path}: no header row of names: the first line holds numbers ({shown!r}), where a CSV of joint positions "
        "names its columns, separated by ',', ';' or a tab (time, right_shoulder_x, ... or the file's own names mapped "
        "with --columns; docs/capture.md, \"A CSV of joint positions\"); add that line"
        + (f", and put ',' between the columns (the line has {len(cells)} numbers separated by spaces)" if spaced else "")
    )


def _check_column_map(mapping: Mapping[str, str], present: list[str], path: Path) -> None:
    """InputError at the first entry of a CSV's column ``mapping`` (our name -> the file's column)
    whose name is not one of ours or whose column is not among ``present``, with the nearest one;
    then at the first column of the file that two of our names would read (:func:`_read_twice`)."""
    ours = list(CSV_NAMES)
    where = f"{path}: column map (--columns)"
    for name, column in mapping.items():
        if name not in ours:
            raise InputError(
                f"{where}: unknown name {name!r}"
                + nearest_hint(name, ours, "names: time, {side}_{joint}_{axis}, neck_{axis}, hip_{axis}")
            )
        if column not in present:
            raise InputError(f"{where}: {name}={column}: no column {column!r} in the file{_missing_column(column, present)}")
    twice = _read_twice(mapping, ours, present)
    if twice is not None:
        column, names = twice
        given = " and ".join(f"{name}={column}" if name in mapping else f"{name} (its own column, not mapped)"
                             for name in names)
        raise InputError(
            f"{where}: the file's column {column!r} is given for two names, {given}: one point read as two joints "
            "makes the segment between them 0 m long (a wrist angle of 0 on every row); give each name a column of "
            "its own, or leave one out (the wrist's and the torso's columns are optional: a file whose arm ends at "
            "the wrist maps the wrist's columns to the hand's names alone)"
        )


def _read_twice(mapping: Mapping[str, str], ours: list[str], present: list[str]) -> tuple[str, list[str]] | None:
    """The first column of the file (among ``present``) that two of ``ours`` would read, each
    through ``mapping`` or under its own name, with those two names; None when each has its own."""
    readers: dict[str, list[str]] = {}
    for name in ours:
        column = mapping.get(name, name)
        if column in present:
            readers.setdefault(column, []).append(name)
    return next(((column, names[:2]) for column, names in readers.items() if len(names) > 1), None)


def _lacking(names: list[str], unread: list[str]) -> str:
    """Our column ``names`` a file lacks, in words, each with the nearest of its ``unread``
    columns (those no name of ours reads) where one is close: ``right_elbow_x (did you mean
    'right_elbo_x'?)``."""
    return ", ".join(name + did_you_mean(name, unread) for name in names)


def _add_or_map(absent: list[str]) -> str:
    """What to do about the ``absent`` columns, after ``"; "``."""
    return (f"; add or rename the {'column' if len(absent) == 1 else 'columns'}, or map the file's with --columns "
            "(docs/capture.md, \"A CSV of joint positions\")")


def _axis_of(name: str) -> tuple[str, str]:
    """A column name split into its joint and its axis (``"HandRight.X"``: ``("HandRight.", "x")``;
    ``("Timestamp", "")`` when it does not end in x, y or z after something else)."""
    if len(name) > 1 and name[-1].lower() in _AXES:
        return name[:-1], name[-1].lower()
    return name, ""


def _missing_column(column: str, present: list[str]) -> str:
    """What to say of a mapped ``column`` the file does not have: the same name in another case;
    where the file has that joint's other axes, those (another axis is no fix for a missing one);
    else the nearest name of the same axis and side (the other arm's joint is no fix either: a file
    that has no column of that side says so), or every column."""
    same = [name for name in present if name.lower() == column.lower()]
    if same:
        return f" (did you mean {same[0]!r}?)"
    joint, axis = _axis_of(column)
    if axis:
        others = [name for name in present if _axis_of(name)[1] and _axis_of(name)[0].lower() == joint.lower()]
        if others:
            return f"; its columns for {joint.rstrip('._-: ') or joint}: {', '.join(others)}"
    side = _side_of(column)
    if side is not None and not any(_side_of(name) == side for name in present):
        return (f"; the file has no column of the {side} side (it may hold one arm: leave the {side}_... names out "
                f"of --columns; columns: {', '.join(present)})")
    choices = [name for name in present if not (axis and _axis_of(name)[1] not in ("", axis))
               and (side is None or _side_of(name) in (None, side))]
    return nearest_hint(column, choices, f"columns: {', '.join(present)}")


#: A side in a column name: the word (``ShoulderLeft``, ``left_shoulder``), or its letter as a part
#: of its own (``L_Shoulder``, ``l_shoulder``, ``Shoulder_L``) or before a capital (``LShoulder``).
_SIDE_IN_NAME = re.compile(r"(?i:(left|right))|(?:^|[^A-Za-z])([LRlr])(?=$|[^A-Za-z])|^([LR])(?=[A-Z][a-z])")


def _side_of(name: str) -> str | None:
    """The side (``left``, ``right``) a column's name says it is of, or None."""
    joint = _axis_of(name)[0].rstrip("._-: ") if _axis_of(name)[1] else name
    match = _SIDE_IN_NAME.search(joint)
    if match is None:
        return None
    letter = (match.group(1) or match.group(2) or match.group(3))[0].lower()
    return "left" if letter == "l" else "right"


def axis_vector(axis: str) -> np.ndarray:
    """Unit vector of shape (3,) for an axis name such as ``"z"`` or ``"-y"``."""
    text = axis.strip().lower()
    sign = -1.0 if text.startswith("-") else 1.0
    name = text.lstrip("+-")
    if name not in _AXES:
        raise InputError(f"up axis {axis!r}: expected one of x, y, z, -x, -y, -z")
    vector = np.zeros(3)
    vector[_AXES.index(name)] = sign
    return vector


