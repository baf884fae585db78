"""Labelling a cut throw: the basket it aimed at, where the ball was released and where it landed.

Basket distance, in order of precedence:

1. a manifest CSV with columns ``file``, ``distance`` (m) and, to tell the throws of one file
   apart, ``throw`` (1-based index in the file) or ``start`` and ``end`` (s from the first
   sample of the recording: the throw whose extension peak falls inside is meant); optionally
   ``subject``;
2. the file name: ``2.5m``, ``2_5m``, ``250cm`` as a separate part of the name
   (``user3_2.5m.bag``);
3. none: the throw's estimated landing distance, rounded to the nearest multiple of
   ``distance_step`` (0.25 m, the spacing of the thesis' baskets), stands for its basket. A
   continuous estimate would give every throw a basket of its own, and the cleaning steps and
   the model that compare or condition on baskets need several throws per basket; the estimate
   itself (from a 15-30 Hz hand velocity) is not finer than that anyway. The exact estimate
   stays in the ``landing`` metadata.

Release and landing: the ball leaves the hand when the hand is fastest during the extension
(an overhand throw releases close to full speed). From the hand's position and velocity there,
the ball flies ballistically (:func:`rlff.ballistics.crossing_distance`) in the vertical plane of
the hand's horizontal velocity; the landing distance is measured on the ground from below the
shoulder, as a basket's distance is from the thrower. A skeleton holds no floor, so the shoulder is
taken to be ``shoulder_height`` above it.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rlff.ballistics import crossing_distance
from rlff.capture.angles import ArmMotion
from rlff.capture.segment import ThrowCut
from rlff.errors import InputError


@dataclass(frozen=True)
class LandingSettings:
    """Assumptions of the landing estimate (m).

    ``distance_step``: a throw without a known basket gets its landing estimate rounded to the
    nearest multiple of this as its distance (0 keeps the estimate as it is).
    """

    shoulder_height: float = 1.4
    target_height: float = 0.0
    hit_radius: float = 0.15
    distance_step: float = 0.25


@dataclass(frozen=True)
class Release:
    """Estimated release of the ball.

    Attributes
    ----------
    index : int
        Sample of the arm's grid.
    time : float
        Time (s) on the recording's clock.
    height : float
        Height of the hand above the floor (m).
    forward : float
        Horizontal distance of the hand in front of the shoulder along the throw (m).
    speed_horizontal, speed_vertical : float
        Hand velocity components (m/s), vertical positive up.
    """

    index: int
    time: float
    height: float
    forward: float
    speed_horizontal: float
    speed_vertical: float


@dataclass(frozen=True)
class ManifestRow:
    file: str
    distance: float
    throw: int | None = None
    start: float | None = None
    end: float | None = None
    subject: str | None = None


def estimate_release(motion: ArmMotion, cut: ThrowCut, up: np.ndarray, settings: LandingSettings) -> Release:
    """The release: fastest hand sample from the extension's start to just after its end.

    Parameters
    ----------
    motion : ArmMotion
    cut : ThrowCut
    up : array of shape (3,)
        Unit vector up in the recording's frame.
    settings : LandingSettings
    """
    up = np.asarray(up, dtype=float) / np.linalg.norm(up)
    last = min(cut.stop, cut.extension_end + 2)
    window = slice(cut.extension_start, max(last, cut.extension_start + 1))
    speeds = np.linalg.norm(motion.hand_velocity[window], axis=1)
    index = window.start + int(np.argmax(speeds))
    velocity = motion.hand_velocity[index]
    vertical = float(velocity @ up)
    horizontal_vector = velocity - vertical * up
    speed_horizontal = float(np.linalg.norm(horizontal_vector))
    offset = motion.hand[index] - motion.shoulder[index]
    direction = horizontal_vector / speed_horizontal if speed_horizontal > 1e-9 else np.zeros(3)
    return Release(
        index=index,
        time=float(motion.time[index]),
        height=settings.shoulder_height + float(offset @ up),
        forward=float(offset @ direction),
        speed_horizontal=speed_horizontal,
        speed_vertical=vertical,
    )


def is_downward(release: Release, max_dip_deg: float = 30.0) -> bool:
    """True when the hand moves down steeper than ``max_dip_deg`` below horizontal at release.

    Such an extension is the arm straightening as it comes down to rest after a throw (seen in
    the MSR recordings), not a throw at a basket.
    """
    dip = np.degrees(np.arctan2(-release.speed_vertical, release.speed_horizontal))
    return bool(dip > max_dip_deg)


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
        when the step is 0; NaN stays NaN).
    source : str
        The ``distance_source`` metadata: ``landing estimate, rounded to 0.25 m`` (or
        ``landing estimate`` when not rounded).
    """
    step = settings.distance_step
    if step <= 0:
        return landing, "landing estimate"
    # rounded again: multiples of a step such as 0.1 are not exact in binary
    return float(np.round(np.round(landing / step) * step, 10)), f"landing estimate, rounded to {step:g} m"


_DISTANCE_IN_NAME = re.compile(r"(?:^|[_\-\s.])(\d+(?:[._,]\d+)?)(cm|m)(?=$|[_\-\s.])", re.IGNORECASE)


def distance_from_name(path: str | Path) -> float | None:
    """Basket distance (m) written in a file name (``2.5m``, ``2_5m``, ``250cm``), or None."""
    match = _DISTANCE_IN_NAME.search(Path(path).name)
    if match is None:
        return None
    value = float(re.sub(r"[_,]", ".", match.group(1)))
    return value / 100.0 if match.group(2).lower() == "cm" else value


def read_manifest(path: str | Path) -> list[ManifestRow]:
    """Read a manifest CSV (columns ``file``, ``distance``; optional ``throw``, ``start``, ``end``, ``subject``).

    Raises
    ------
    InputError
        The file is missing or unreadable, lacks ``file`` or ``distance``, or has a bad value.
    """
    import pandas as pd

    path = Path(path)
    if not path.is_file():
        raise InputError(f"manifest {path}: {'is a folder, not a file' if path.is_dir() else 'no such file'}")
    try:
        frame = pd.read_csv(path, dtype=str, keep_default_na=False)
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise InputError(f"manifest {path}: not a readable CSV ({str(exc).strip().splitlines()[-1]})") from None
    frame.columns = [str(c).strip().lower() for c in frame.columns]
    missing = [name for name in ("file", "distance") if name not in frame.columns]
    if missing:
        raise InputError(f"manifest {path}: no column {', '.join(map(repr, missing))} (columns: {', '.join(frame.columns)})")
    rows = []
    for number, record in enumerate(frame.to_dict("records"), start=2):

        def number_or_none(name: str, kind: type, record: dict = record, number: int = number):
            text = str(record.get(name, "")).strip()
            if not text:
                return None
            try:
                return kind(text)
            except ValueError:
                raise InputError(f"manifest {path}, line {number}: column {name!r} has a bad value {text!r}") from None

        distance = number_or_none("distance", float)
        if distance is None or not np.isfinite(distance) or distance <= 0:
            raise InputError(f"manifest {path}, line {number}: column 'distance' needs a positive number (m)")
        subject = str(record.get("subject", "")).strip() or None
        rows.append(
            ManifestRow(
                str(record["file"]).strip(), distance, number_or_none("throw", int),
                number_or_none("start", float), number_or_none("end", float), subject,
            )
        )
    return rows


def manifest_entry(rows: list[ManifestRow], source: str, throw_number: int, peak_time: float) -> ManifestRow | None:
    """The manifest row for a throw, or None.

    Parameters
    ----------
    rows : the manifest
    source : the recording's path; rows match it by full path, file name or stem
    throw_number : 1-based index of the throw in its recording
    peak_time : time (s from the recording's first sample) of the throw's extension peak
    """
    path = Path(source)
    names = {str(path), path.name, path.stem}
    fallback = None
    for row in rows:
        if row.file not in names and Path(row.file).name not in names:
            continue
        if row.throw is not None:
            if row.throw == throw_number:
                return row
        elif row.start is not None or row.end is not None:
            low = -np.inf if row.start is None else row.start
            high = np.inf if row.end is None else row.end
            if low <= peak_time <= high:
                return row
        else:
            fallback = row
    return fallback
