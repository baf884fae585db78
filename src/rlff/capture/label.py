"""Labelling a cut throw: the basket it aimed at, where the ball was released and where it landed.

Basket distance, in order of precedence:

1. a manifest CSV with columns ``file``, ``distance`` (m) and, to tell the throws of one file
   apart, ``throw`` (1-based index in the file) or ``start`` and ``end`` (s from the first
   sample of the recording: the throw whose extension peak falls inside is meant); optionally
   ``subject``;
2. the file name: ``2.5m``, ``2_5m``, ``250cm``, ``2500mm`` as a separate part of the name
   (``user3_2.5m.bag``);
3. none: the throw's estimated landing distance, rounded to the nearest multiple of
   ``distance_step`` (0.25 m, the spacing of the thesis' baskets) within the range of baskets
   (an estimate of 0.32 m to 0.5 m: no basket stands at 0.25 m), stands for its basket. A
   continuous estimate would give every throw a basket of its own, and the cleaning steps and
   the model that compare or condition on baskets need several throws per basket; the estimate
   itself (from a 15-30 Hz hand velocity) is not finer than that anyway. The exact estimate
   stays in the ``landing`` metadata.

Release and landing: the ball leaves the hand around where the elbow extends fastest (an overhand
throw releases close to full speed), the middle of the stretch of ``SegmentSettings.steepest_window``
(0.28 s) over which the elbow angle rises most (:attr:`ThrowCut.fastest`). By default the release
velocity is the hand's mean velocity over that stretch, from the hand's positions at both ends of
it (interpolated between samples). Measured over a fixed time, it is the same quantity at 30 Hz and
at 4 Hz; the fastest single sample, or a derivative whose width follows the sampling, would change
with the rate. Its price: over 0.28 s of a 0.25-0.4 s extension the hand's mean speed is half its
peak or less, so the landing it gives is short of where a ball let go at the peak comes down (0.30
of it on simulated minimum-jerk throws) and follows it loosely (correlation 0.16-0.41).

``LandingSettings.release_window`` (``rlff data import --release-window``) keeps the direction of
that chord, steady and parallel to the hand's path at the peak of an arc swept symmetrically about
it, and takes the speed from the hand's chord over the given time about the stretch's middle. With
0.1 s the landing is 0.64 of the true one at 15 Hz, 0.73 at 30 Hz and 0.77 at 120 Hz, following it
with correlations of 0.79-0.90; it is not the default because the estimates then change more with
the frame rate than issue 14 allows a 4-10 Hz copy of a recording (15 %), and real recordings'
baskets spread over more bins (docs/capture.md).

When the samples around the stretch are further apart than half of it, the release is only roughly
placed and is marked ``low`` confidence. From the hand's position and velocity there, the ball
flies ballistically (:func:`rlff.ballistics.crossing_distance`) in the vertical plane of the hand's
horizontal velocity; the landing distance is measured on the ground from below the shoulder, as a
basket's distance is from the thrower. A skeleton holds no floor, so the shoulder is taken to be
``shoulder_height`` above it.

Direction: a throw sends the hand forward, toward the sensor (the frame of a Kinect or of a tf
skeleton tracker is the camera's) or, when the frame is not the camera's, along the torso's
facing direction (from the two shoulders). A release whose hand moves down and back is no throw
at a basket: it is the arm coming down to rest; so is one moving down steeper than 75 deg below
the forward horizontal (the arm dropping nearly straight down). A release moving forward and
down is a throw (the former rule, any dip over 30 deg, rejected them; over a sparse stretch the
hand's chord also points lower than the release itself). Without a known forward direction, a
release dipping more than 30 deg below horizontal is still taken as the arm coming down to rest.
"""

from __future__ import annotations

import math
import os
import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rlff.ballistics import crossing_distance
from rlff.capture.angles import ArmMotion
from rlff.capture.segment import ThrowCut
from rlff.csvlines import data_row_lines, header_separator
from rlff.dataset import BEARING_RANGE, HEIGHT_RANGE
from rlff.errors import InputError
from rlff.limits import DISTANCE_RANGE, check_distance
from rlff.wording import did_you_mean, plural


@dataclass(frozen=True)
class LandingSettings:
    """Assumptions of the landing estimate (lengths in m, times in s).

    ``distance_step``: a throw without a known basket gets its landing estimate rounded to the
    nearest multiple of this as its distance (0 keeps the estimate as it is).
    ``release_window``: the time (s) about the release over which the hand's chord gives the
    release speed, its direction still the whole stretch of fastest extension's; None (the
    default) takes both from that stretch (module docstring: what each gives).
    """

    shoulder_height: float = 1.4
    target_height: float = 0.0
    hit_radius: float = 0.15
    distance_step: float = 0.25
    release_window: float | None = None

    def __post_init__(self) -> None:
        window = self.release_window
        if window is not None and not (math.isfinite(window) and 0 < window <= 1):
            raise InputError(f"release window {window!r}: give a time in seconds above 0 and at most 1 "
                             "(0.1 measures the hand's speed about the release, docs/capture.md)")


@dataclass(frozen=True)
class Release:
    """Estimated release of the ball.

    Attributes
    ----------
    index : int
        The sample of the arm's motion nearest to the release.
    time : float
        Time (s) on the recording's clock: the middle of the stretch of fastest extension.
    height : float
        Height of the hand above the floor (m).
    forward : float
        Horizontal distance of the hand in front of the shoulder along the throw (m).
    speed_horizontal, speed_vertical : float
        Hand velocity components (m/s), vertical positive up.
    speed_forward : float or None
        Horizontal velocity along the thrower's forward direction (m/s); None when that
        direction is unknown.
    confidence : str
        ``high``, or ``low`` when samples around the release are further apart than half the
        release window (sparse tracking).
    """

    index: int
    time: float
    height: float
    forward: float
    speed_horizontal: float
    speed_vertical: float
    speed_forward: float | None = None
    confidence: str = "high"


@dataclass(frozen=True)
class ManifestRow:
    file: str
    distance: float
    throw: int | None = None
    start: float | None = None
    end: float | None = None
    subject: str | None = None
    line: int = 0
    manifest: str = ""
    bearing: float | None = None
    height: float | None = None

    @property
    def where(self) -> str:
        """``manifest PATH, line N`` for messages."""
        return f"manifest {self.manifest}, line {self.line}"

    @property
    def has_span(self) -> bool:
        """The row names its throw by a time span (``start`` and/or ``end``), not by number."""
        return self.throw is None and (self.start is not None or self.end is not None)

    def spans(self, time: float) -> bool:
        """Whether ``time`` (s from the recording's first frame) lies within ``start``-``end``
        (either open when not given)."""
        low = -np.inf if self.start is None else self.start
        high = np.inf if self.end is None else self.end
        return bool(low <= time <= high)

    @property
    def folders(self) -> tuple[str, ...]:
        """The folder part of ``file`` (``..`` left out), empty when it names a file alone."""
        return tuple(part for part in Path(self.file).parent.parts if part != "..")

    def matches(self, source: str | Path) -> bool:
        """Whether the row names the recording ``source``: by file name or stem, and when ``file``
        has a folder part (``d1/x.bag``), only a recording whose path ends in those folders."""
        path = Path(source)
        if Path(self.file).name not in (path.name, path.stem):
            return False
        folders = self.folders
        parents = Path(os.path.abspath(path)).parent.parts
        return not folders or parents[len(parents) - len(folders):] == folders


def estimate_release(
    motion: ArmMotion, cut: ThrowCut, up: np.ndarray, settings: LandingSettings, facing: np.ndarray | None = None
) -> Release:
    """The release: where the elbow extends fastest, the hand's velocity there.

    The velocity is the hand's chord over the stretch of fastest extension (``cut.fastest``); with
    ``settings.release_window`` its speed is the chord's over that time about the stretch's middle
    (module docstring: what each gives).

    Parameters
    ----------
    motion : ArmMotion
    cut : ThrowCut
    up : array of shape (3,)
        Unit vector up in the recording's frame.
    settings : LandingSettings
    facing : array of shape (3,), optional
        The thrower's forward direction (horizontal), for ``speed_forward``.
    """
    up = np.asarray(up, dtype=float) / np.linalg.norm(up)
    begin, end = cut.fastest
    width, middle = end - begin, (begin + end) / 2

    def at(series: np.ndarray, when: float) -> np.ndarray:
        return np.array([np.interp(when, motion.time, series[:, axis]) for axis in range(3)])

    velocity = (at(motion.hand, end) - at(motion.hand, begin)) / width
    mean_speed = float(np.linalg.norm(velocity))
    if settings.release_window is not None and mean_speed > 1e-9:
        span = min(settings.release_window, width)
        speed = float(np.linalg.norm(at(motion.hand, middle + span / 2) - at(motion.hand, middle - span / 2))) / span
        velocity = velocity * (speed / mean_speed)
    vertical = float(velocity @ up)
    horizontal_vector = velocity - vertical * up
    speed_horizontal = float(np.linalg.norm(horizontal_vector))
    offset = at(motion.hand, middle) - at(motion.shoulder, middle)
    direction = horizontal_vector / speed_horizontal if speed_horizontal > 1e-9 else np.zeros(3)
    spacing = np.diff(motion.time)
    around = (motion.time[1:] > begin) & (motion.time[:-1] < end)
    sparse = bool(around.any() and spacing[around].max() > width / 2)
    return Release(
        index=int(np.argmin(np.abs(motion.time - middle))),
        time=float(middle),
        height=settings.shoulder_height + float(offset @ up),
        forward=float(offset @ direction),
        speed_horizontal=speed_horizontal,
        speed_vertical=vertical,
        speed_forward=None if facing is None else float(horizontal_vector @ facing),
        confidence="low" if sparse else "high",
    )


def not_at_a_target(release: Release, max_dip_deg: float = 30.0, max_forward_dip_deg: float = 75.0) -> str | None:
    """Why a release is not a throw at a basket, or None when it is.

    With a known forward direction: the hand moving down and back (the arm coming down to rest
    after a throw), or moving down steeper than ``max_forward_dip_deg`` below the forward
    horizontal (the arm dropping nearly straight down). Without one: the hand moving down steeper
    than ``max_dip_deg`` below horizontal.
    """
    vertical, horizontal = release.speed_vertical, release.speed_horizontal
    if release.speed_forward is not None:
        forward = release.speed_forward
        dip = np.degrees(np.arctan2(-vertical, forward))
        if forward < 0 and vertical < 0:
            return f"the hand moves down ({vertical:.1f} m/s) and back ({forward:.1f} m/s) at release: the arm coming down to rest"
        if dip > max_forward_dip_deg:
            return (
                f"the hand moves down at {dip:.0f} deg below the forward horizontal at release ({vertical:.1f} m/s down, "
                f"{forward:.1f} m/s forward; a throw released forward goes at most {max_forward_dip_deg:g} deg down): "
                "the arm coming down to rest"
            )
        return None
    dip = np.degrees(np.arctan2(-vertical, horizontal))
    if dip > max_dip_deg:
        return (
            f"the hand moves down at {dip:.0f} deg below horizontal at release ({vertical:.1f} m/s; forward "
            "direction unknown): the arm coming down to rest"
        )
    return None


def landing_distance(release: Release, settings: LandingSettings) -> float:
    """Horizontal distance (m) from below the shoulder to where the ball comes down to the target height.

    NaN when the ball never reaches that height on its way down (released below it, going down).
    """
    return float(
        crossing_distance(release.forward, release.height, release.speed_horizontal, release.speed_vertical, settings.target_height)
    )


def basket_from_landing(landing: float, settings: LandingSettings) -> tuple[float, str]:
    """The distance (m) standing for the basket of a throw known only by its landing estimate.

    Returns
    -------
    distance : float
        ``landing`` rounded to the nearest multiple of ``settings.distance_step`` (as it is
        when the step is 0; NaN stays NaN); a landing within :data:`rlff.limits.DISTANCE_RANGE`
        to the nearest multiple within it (0.32 m to 0.5 m, not to 0.25 m, where no basket stands).
        A landing outside the range stands for no basket (the import leaves its throw out).
    source : str
        The ``distance_source`` metadata: ``landing estimate, rounded to 0.25 m`` (or
        ``landing estimate`` when not rounded).
    """
    step = settings.distance_step
    if step <= 0:
        return landing, "landing estimate"
    distance = np.round(landing / step) * step
    low, high = DISTANCE_RANGE
    if low <= landing <= high:
        # 1e-9: a bound on a multiple of the step stays one whichever way binary rounds the quotient
        distance = np.clip(distance, np.ceil(low / step - 1e-9) * step, np.floor(high / step + 1e-9) * step)
    # rounded again: multiples of a step such as 0.1 are not exact in binary
    return float(np.round(distance, 10)), f"landing estimate, rounded to {step:g} m"


_DISTANCE_IN_NAME = re.compile(r"(?:^|[_\-\s.])(\d+(?:[._,]\d+)?)(mm|cm|m)(?=$|[_\-\s.])", re.IGNORECASE)
#: Units of a distance in a file name, per metre.
_NAME_UNITS = {"m": 1.0, "cm": 100.0, "mm": 1000.0}


def distance_from_name(path: str | Path) -> float | None:
    """Basket distance (m) written in a file name (``2.5m``, ``2_5m``, ``250cm``, ``2500mm``; until
    2026-12-07 a name in millimetres was passed over and the throw labelled by its landing
    estimate), or None.

    Raises
    ------
    InputError
        The distance is outside :data:`rlff.limits.DISTANCE_RANGE` (naming the file).
    """
    match = _DISTANCE_IN_NAME.search(Path(path).name)
    if match is None:
        return None
    value = float(re.sub(r"[_,]", ".", match.group(1)))
    distance = value / _NAME_UNITS[match.group(2).lower()]
    if not DISTANCE_RANGE[0] <= distance <= DISTANCE_RANGE[1]:
        raise InputError(
            f"{path}: the basket distance in the file name ({distance:g} m) is outside "
            f"the range {DISTANCE_RANGE[0]:g} to {DISTANCE_RANGE[1]:g} m; rename the file or give its distance in a --manifest"
        )
    return distance


#: The columns of a manifest: ``file`` and ``distance``, then the optional ones.
MANIFEST_COLUMNS = ("file", "distance", "throw", "start", "end", "subject", "bearing", "height")
#: Measured outcomes, which rlff does not take from a manifest: a throw's landing is estimated
#: from the hand's release, and its hit judged against the basket from that.
_OUTCOME_COLUMNS = ("hit", "landing")


def read_manifest(path: str | Path) -> list[ManifestRow]:
    """Read a manifest CSV (columns ``file``, ``distance``; optional ``throw``, ``start``, ``end``,
    ``subject``, and the basket's ``bearing`` (deg, -180 to 180) and rim ``height`` (m)).

    Raises
    ------
    InputError
        The file is missing or unreadable, lacks ``file`` or ``distance``, has a column that is
        none of :data:`MANIFEST_COLUMNS` (a measured outcome, ``hit`` or ``landing``, said to
        be one), has a bad value, a throw number below 1, a ``start`` after its ``end``, or lists
        the same throw twice with different distances (the rows at fault are named).
    """
    import pandas as pd

    path = Path(path)
    if not path.is_file():
        raise InputError(f"manifest {path}: {'is a folder, not a file' if path.is_dir() else 'no such file'}")
    try:
        separator = header_separator(path)  # as spreadsheets write it: ";" with decimal commas, or tabs
        frame = pd.read_csv(path, sep=separator, dtype=str, keep_default_na=False, skipinitialspace=True)
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise InputError(f"manifest {path}: not a readable CSV ({str(exc).strip().splitlines()[-1]})") from None
    frame.columns = [str(c).strip().lower() for c in frame.columns]
    _require_row_widths(path, separator, len(frame.columns))
    missing = [name for name in ("file", "distance") if name not in frame.columns]
    if missing:
        raise InputError(f"manifest {path}: no column {', '.join(map(repr, missing))} (columns: {', '.join(frame.columns)})")
    # a column without a name or a value is a separator ending the header
    _require_known_columns(path, [name for name in frame.columns
                                  if not name.startswith("unnamed: ") or frame[name].str.strip().any()])
    rows = []
    lines = data_row_lines(path, separator)
    if len(lines) != len(frame):  # read otherwise than pandas read it: the lines as if none were blank
        lines = list(range(2, len(frame) + 2))
    for number, record in zip(lines, frame.to_dict("records"), strict=True):

        def number_or_none(name: str, kind: type, record: dict = record, number: int = number):
            text = str(record.get(name, "")).strip()
            if not text:
                return None
            written = text
            if separator != "," and kind is float:
                text = text.replace(",", ".")  # a decimal comma
            try:
                return kind(text)
            except ValueError:
                raise InputError(f"manifest {path}, line {number}: column {name!r} has a bad value {written!r}") from None

        distance = number_or_none("distance", float)
        if distance is None or not np.isfinite(distance) or distance <= 0:
            raise InputError(f"manifest {path}, line {number}: column 'distance' needs a positive number (m)")
        check_distance(f"manifest {path}, line {number}: column 'distance'", distance)
        subject = str(record.get("subject", "")).strip() or None
        bearing, height = number_or_none("bearing", float), number_or_none("height", float)
        for name, value, (low, high), unit in (("bearing", bearing, BEARING_RANGE, "deg"), ("height", height, HEIGHT_RANGE, "m")):
            if value is not None and not low <= value <= high:
                raise InputError(
                    f"manifest {path}, line {number}: column {name!r} {value:g}: out of range {low:g} to {high:g} {unit}"
                )
        row = ManifestRow(
            str(record["file"]).strip(), distance, number_or_none("throw", int),
            number_or_none("start", float), number_or_none("end", float), subject, number, str(path),
            bearing, height,
        )
        if not row.file:
            raise InputError(f"{row.where}: column 'file' is empty")
        if row.throw is not None and row.throw < 1:
            raise InputError(f"{row.where}: throw {row.throw} does not exist (throws are numbered from 1)")
        if row.start is not None and row.end is not None and row.start > row.end:
            raise InputError(f"{row.where}: start {row.start:g} s is after end {row.end:g} s")
        rows.append(row)
    _check_no_conflicts(rows)
    return rows


def _require_known_columns(path: Path, columns: Sequence[str]) -> None:
    """:class:`InputError` naming the manifest's ``columns`` (lower case) that are none of
    :data:`MANIFEST_COLUMNS`, each with the nearest where one is close: their values would be lost
    without a word."""
    unknown = [name for name in columns if name not in MANIFEST_COLUMNS]
    outcomes = [name for name in unknown if name in _OUTCOME_COLUMNS]  # said first, and apart
    at_fault = outcomes or unknown
    if not at_fault:
        return
    columns_word, it = ("columns", "them") if len(at_fault) > 1 else ("column", "it")
    if outcomes:
        raise InputError(
            f"manifest {path}: {columns_word} {', '.join(map(repr, outcomes))}: rlff reads no measured outcome from "
            "a manifest (a throw's landing is estimated from the hand's release, and its hit judged from that: "
            f"docs/capture.md, Labels); drop {it}"
        )
    named = ", ".join(f"{name!r}{did_you_mean(name, MANIFEST_COLUMNS)}" for name in unknown)
    raise InputError(
        f"manifest {path}: unknown {columns_word} {named}; a manifest's columns are {', '.join(MANIFEST_COLUMNS)}: "
        f"rename or drop {it}"
    )


def _check_no_conflicts(rows: list[ManifestRow]) -> None:
    """The same throw (same file name, same throw number or time span) listed with different
    distances, by rows that can name the same recording (``x.bag`` and ``d1/x.bag`` can,
    ``d1/x.bag`` and ``d2/x.bag`` cannot)."""
    seen: dict[tuple, list[ManifestRow]] = {}
    for row in rows:
        key = (Path(row.file).name, row.throw, row.start, row.end)
        earlier = seen.setdefault(key, [])
        clashing = [first for first in earlier if first.distance != row.distance and _same_folders(first, row)]
        earlier.append(row)
        if clashing:
            first = clashing[0]
            which = f"throw {row.throw}" if row.throw is not None else (
                "the same time span" if row.start is not None or row.end is not None else "the whole file"
            )
            raise InputError(
                f"{row.where}: {row.file} ({which}) is listed again with distance {row.distance:g} m; "
                f"line {first.line} gives {first.distance:g} m"
            )


def _same_folders(a: ManifestRow, b: ManifestRow) -> bool:
    """Whether two rows' folder parts can name the same recording: one ends the other."""
    short, long = sorted((a.folders, b.folders), key=len)
    return long[len(long) - len(short):] == short


def _require_row_widths(path: Path, separator: str, width: int) -> None:
    """:class:`InputError` at the first manifest row with more cells than its header: pandas would
    take the first column for an index and shift the others (a decimal comma in a comma file)."""
    import csv

    with open(path, newline="", encoding="utf-8-sig", errors="replace") as handle:
        for number, record in enumerate(csv.reader(handle, delimiter=separator, skipinitialspace=True), start=1):
            cells = list(record)
            while cells and not cells[-1].strip():
                cells.pop()  # a trailing separator is no cell
            if number > 1 and len(cells) > width:
                comma = ("; a decimal comma in a comma-separated file? write 1.5, quote \"1,5\", or separate the "
                         "columns with ';'" if separator == "," else "")
                raise InputError(f"manifest {path}, line {number}: {len(cells)} cells, but the header names {width} "
                                 f"columns{comma}")


def check_throw_numbers(rows: list[ManifestRow], source: str, count: int) -> None:
    """Raise when a manifest row names a throw of ``source`` beyond the ``count`` throws found there.

    Raises
    ------
    InputError
        Naming the row, the file and how many throws it has.
    """
    path = Path(source)
    for row in rows:
        if row.throw is not None and row.throw > count and row.matches(path):
            raise InputError(
                f"{row.where}: throw {row.throw} of {path.name} does not exist ({plural(count, 'throw')} found there)"
            )


def rows_without_a_throw(rows: list[ManifestRow], source: str, peak_times: list[float],
                         left_out: Sequence[tuple[float, str]] = ()) -> list[str]:
    """Warnings for the rows of ``source`` with a time span (``start``/``end``, s from the
    recording's first frame) that holds none of its throws' extension peaks (``peak_times``, s):
    such a row labels nothing, and its distance is not used. ``left_out``: (time, rule) of throws
    a rule left out, named where the span holds one."""
    name = Path(source).name
    found = ", ".join(f"{t:.2f}" for t in peak_times) or "none"
    warnings = []
    for row in rows:
        if row.has_span and row.matches(source) and not any(row.spans(t) for t in peak_times):
            span = f"{'start' if row.start is None else f'{row.start:g}'}-{'end' if row.end is None else f'{row.end:g}'} s"
            why = "".join(f"; the throw at t={t:.2f} s was left out ({rule})" for t, rule in left_out if row.spans(t))
            warnings.append(f"{row.where}: no throw of {name} peaks within {span} (its throws peak at t = {found} s"
                            f"{why}); the row is not used")
    return warnings


def manifest_entry(rows: list[ManifestRow], source: str, throw_number: int, peak_time: float) -> ManifestRow | None:
    """The manifest row for a throw, or None.

    Parameters
    ----------
    rows : the manifest
    source : the recording's path; rows match it as :meth:`ManifestRow.matches` says
    throw_number : 1-based index of the throw in its recording
    peak_time : time (s from the recording's first frame, the import's clock) of the throw's extension peak
    """
    fallback = None
    for row in rows:
        if not row.matches(source):
            continue
        if row.throw is not None:
            if row.throw == throw_number:
                return row
        elif row.has_span:
            if row.spans(peak_time):
                return row
        else:
            fallback = row
    return fallback
