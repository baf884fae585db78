"""Recordings in, a dataset of labelled single throws out: the whole capture stage in one call.

For every file: read the arm joints (:mod:`~rlff.capture.bag`,
:mod:`~rlff.capture.skeleton_text`), keep the consistent tracked user
(:mod:`~rlff.capture.users`), put each arm on a uniform grid and take the throwing one
(:mod:`~rlff.capture.angles`), cut the throws (:mod:`~rlff.capture.segment`) and label them
(:mod:`~rlff.capture.label`). Each throw becomes one trajectory with columns ``time`` (s from
the throw's start), ``angle`` (rad), ``velocity`` (rad/s) and ``distance`` (m). Cleaning
(glitches, cropping, cutting at the release) is left to :mod:`rlff.preprocess`.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from rlff.capture.angles import ArmMotion, align_arm, throwing_arm
from rlff.capture.bag import DEFAULT_FRAMES, DEFAULT_TOPIC, read_bag
from rlff.capture.label import (
    LandingSettings,
    ManifestRow,
    basket_from_landing,
    distance_from_name,
    estimate_release,
    is_downward,
    landing_distance,
    manifest_entry,
    read_manifest,
)
from rlff.capture.segment import SegmentSettings, ThrowCut, find_throws
from rlff.capture.skeleton import Recording
from rlff.capture.skeleton_text import axis_vector, read_joint_csv, read_kinect_text, read_msr_text
from rlff.capture.users import keep_consistent_user
from rlff.dataset import Dataset, Trajectory
from rlff.errors import InputError
from rlff.fileio import require_distinct

FORMATS = ("bag", "kinect-text", "msr", "csv", "thesis")
ARMS = ("auto", "right", "left")


@dataclass
class ThrowInfo:
    """Where one imported throw came from (times in s on the recording's own clock)."""

    id: str
    start: float
    end: float
    release: float
    peak_velocity: float
    angle_range: tuple[float, float]
    distance: float
    distance_source: str
    landing: float | None


@dataclass
class FileReport:
    """What the import did with one file."""

    source: str
    format: str
    arm: str | None = None
    user: str | None = None
    clock_origin: float = 0.0
    throws: list[ThrowInfo] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)


@dataclass
class ImportReport:
    """What the import did, file by file."""

    files: list[FileReport] = field(default_factory=list)

    @property
    def n_throws(self) -> int:
        return sum(len(report.throws) for report in self.files)

    @property
    def warnings(self) -> list[str]:
        return [warning for report in self.files for warning in report.warnings]

    @property
    def notes(self) -> list[str]:
        return [note for report in self.files for note in report.notes]

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-able summary."""
        return {"throws": self.n_throws, "files": [asdict(report) for report in self.files]}


def detect_format(path: str | Path) -> str:
    """Guess a recording's format from its name and first line.

    ``.bag`` files and ROS 2 bag folders are bags, ``*_skeleton3D.txt`` and 4-column text is MSR,
    61-column text is Kinect SDK v1, ``.csv`` is a joint CSV.
    """
    path = Path(path)
    if path.suffix == ".bag" or path.is_dir() or path.suffix in (".db3", ".mcap"):
        return "bag"
    if path.suffix.lower() == ".csv":
        return "csv"
    if path.is_file():
        with path.open(encoding="utf-8", errors="replace") as handle:
            for line in handle:
                fields = line.split("#", 1)[0].replace(",", " ").split()
                if fields:
                    if len(fields) == 4:
                        return "msr"
                    if len(fields) == 61:
                        return "kinect-text"
                    break
    raise InputError(f"{path}: cannot tell the format; give --format ({'|'.join(FORMATS)})")


def read_recording(
    path: Path,
    format: str,
    *,
    topic: str = DEFAULT_TOPIC,
    frames: Sequence[str] = DEFAULT_FRAMES,
    rate_hz: float | None = None,
    columns: Mapping[str, str] | None = None,
    up: str | None = None,
) -> Recording:
    """Read one recording in a skeleton format (not ``thesis``)."""
    if format == "bag":
        recording = read_bag(path, topic=topic, frames=frames)
    elif format == "kinect-text":
        recording = read_kinect_text(path, rate_hz)
    elif format == "msr":
        recording = read_msr_text(path, rate_hz)
    elif format == "csv":
        recording = read_joint_csv(path, columns, rate_hz, up or "z")
    else:
        raise InputError(f"{path}: unknown format {format!r} (formats: {', '.join(FORMATS)})")
    if up is not None:
        recording.up = axis_vector(up)
    return recording


def import_recordings(
    paths: Sequence[str | Path],
    format: str | None = None,
    *,
    manifest: str | Path | None = None,
    topic: str = DEFAULT_TOPIC,
    frames: Sequence[str] = DEFAULT_FRAMES,
    arm: str = "auto",
    rate_hz: float | None = None,
    progress: Callable[[str], None] | None = None,
    columns: Mapping[str, str] | None = None,
    up: str | None = None,
    segment: SegmentSettings | None = None,
    landing: LandingSettings | None = None,
) -> tuple[Dataset, ImportReport]:
    """Import skeleton recordings as a dataset of single, labelled throws.

    Parameters
    ----------
    paths : recordings (files, or ROS 2 bag folders)
    format : one of ``bag``, ``kinect-text``, ``msr``, ``csv``, ``thesis``; None or ``auto`` guesses
        it per file from the name and content
    manifest : CSV of basket distances (see :mod:`rlff.capture.label`)
    topic, frames : tf topic and (shoulder, elbow, hand) frames, for bags
    arm : ``auto`` (the arm whose hand sweeps furthest), ``right`` or ``left``
    rate_hz : frame rate of text formats without time stamps (Kinect 30, MSR 15, CSV 30 by default)
    progress : called with each file's path when it is done
    columns : column map of the CSV format (our name -> the file's)
    up : the up axis of the recordings' frame (``x``, ``-y``...); default per format
    segment, landing : settings of the throw finder and of the landing estimate

    Returns
    -------
    dataset : Dataset
        One trajectory per throw: ``time``, ``angle``, ``velocity``, ``distance`` (the basket's,
        or without one the landing estimate rounded to ``landing.distance_step``); metadata
        ``subject``, ``source``, ``target``/``hit`` (when the basket is known), ``landing``,
        ``distance_source``, ``release_time`` (s from the throw's start), ``start_time`` and
        ``end_time`` (s from the recording's first sample), ``arm``.
    report : ImportReport
        Per file: the throws, the arm and user kept, and notes and warnings.

    Raises
    ------
    InputError
        A file that cannot be read (named, with what is wrong), an unknown format or arm.
    """
    if format not in (None, "auto", *FORMATS):
        raise InputError(f"unknown format {format!r} (formats: {', '.join(FORMATS)})")
    if arm not in ARMS:
        raise InputError(f"unknown arm {arm!r} (arms: {', '.join(ARMS)})")
    if not paths:
        raise InputError("no recordings given")
    require_distinct(paths, "recording")
    rows = read_manifest(manifest) if manifest is not None else []
    landing = landing or LandingSettings()
    trajectories: list[Trajectory] = []
    report = ImportReport()
    used_ids: set[str] = set()
    for raw_path in paths:
        path = Path(raw_path)
        kind = detect_format(path) if format in (None, "auto") else format
        if kind == "thesis":
            file_report, found = _import_thesis(path, used_ids)
        else:
            recording = read_recording(path, kind, topic=topic, frames=frames, rate_hz=rate_hz, columns=columns, up=up)
            file_report, found = _import_recording(recording, kind, arm, rows, segment, landing, used_ids)
        trajectories.extend(found)
        report.files.append(file_report)
        if progress is not None:
            progress(str(path))
    return Dataset(trajectories), report


def _import_thesis(path: Path, used_ids: set[str]) -> tuple[FileReport, list[Trajectory]]:
    from rlff.formats import read_thesis_matrix

    dataset = read_thesis_matrix(path)
    found = []
    for trajectory in dataset:
        found.append(trajectory.replace(id=_unique_id(trajectory.id, used_ids)))
    return FileReport(str(path), "thesis", notes=[f"{path.name}: {len(found)} trajectories from the thesis matrix"]), found


def _unique_id(candidate: str, used: set[str]) -> str:
    name, suffix = candidate, 2
    while name in used:
        name = f"{candidate}-{suffix}"
        suffix += 1
    used.add(name)
    return name


def _subject(path: Path, row: ManifestRow | None) -> str:
    if row is not None and row.subject:
        return row.subject
    match = re.search(r"(?:^|_)(s\d+)(?:_|$)", path.stem)
    return match.group(1) if match else path.stem


def _import_recording(
    recording: Recording,
    kind: str,
    arm: str,
    rows: list[ManifestRow],
    segment: SegmentSettings | None,
    landing: LandingSettings,
    used_ids: set[str],
) -> tuple[FileReport, list[Trajectory]]:
    path = Path(recording.source)
    report = FileReport(str(path), kind, notes=list(recording.notes), warnings=list(recording.warnings))
    arms, user_notes = keep_consistent_user(recording)
    report.notes.extend(user_notes)
    if arm != "auto":
        arms = [track for track in arms if track.side == arm]
        if not arms:
            sides = sorted({track.side for track in recording.arms})
            raise InputError(f"{path}: no {arm} arm (arms there: {', '.join(sides)})")
    motions = [align_arm(track) for track in arms]
    motion = motions[0] if len(motions) == 1 else throwing_arm(motions)
    report.arm, report.user = motion.arm.side, motion.arm.user
    report.clock_origin = float(motion.time[0])
    if len(motions) > 1:
        report.notes.append(f"{path.name}: throwing arm: {motion.arm.side} (the hand that sweeps furthest)")
    lost = int(np.sum(~motion.valid))
    if lost:
        report.notes.append(f"{path.name}: {lost} samples ({lost / motion.rate_hz:.2f} s) without tracking are left out")
    cuts, segment_notes = find_throws(motion, segment)
    report.notes.extend(segment_notes)
    cuts = _throws_at_a_target(recording, motion, cuts, landing, report, one_per_file=kind == "msr")
    if not cuts:
        report.warnings.append(f"{path}: no throw found ({motion.arm.label})")
    trajectories = []
    for number, cut in enumerate(cuts, start=1):
        trajectory = _throw(recording, motion, cut, number, rows, landing, report, used_ids)
        if trajectory is not None:
            trajectories.append(trajectory)
    return report, trajectories


def _throws_at_a_target(
    recording: Recording,
    motion: ArmMotion,
    cuts: list[ThrowCut],
    landing: LandingSettings,
    report: FileReport,
    one_per_file: bool,
) -> list[ThrowCut]:
    """Leave out extensions that release steeply downward (the arm coming down to rest).

    With ``one_per_file`` (MSR Action3D: a file holds one performance of the action), keep only
    the throw with the fastest hand at release. Every throw left out gets a note.
    """
    path = Path(recording.source)
    releases = [estimate_release(motion, cut, recording.up, landing) for cut in cuts]
    kept = []
    for cut, release in zip(cuts, releases, strict=True):
        if is_downward(release):
            report.notes.append(
                f"{path.name}: extension at t={motion.time[cut.peak] - report.clock_origin:.2f} s left out: the hand moves "
                f"down at release ({release.speed_vertical:.1f} m/s), the arm coming down to rest"
            )
        else:
            kept.append((cut, release))
    if one_per_file and len(kept) > 1:
        best = max(kept, key=lambda item: np.hypot(item[1].speed_horizontal, item[1].speed_vertical))
        for cut, _ in kept:
            if cut is not best[0]:
                report.notes.append(
                    f"{path.name}: extension at t={motion.time[cut.peak] - report.clock_origin:.2f} s left out: "
                    "an MSR file holds one throw, the one with the fastest release is kept"
                )
        kept = [best]
    return [cut for cut, _ in kept]


def _throw(
    recording: Recording,
    motion: ArmMotion,
    cut: ThrowCut,
    number: int,
    rows: list[ManifestRow],
    landing: LandingSettings,
    report: FileReport,
    used_ids: set[str],
) -> Trajectory | None:
    path = Path(recording.source)
    origin = report.clock_origin
    window = slice(cut.start, cut.stop)
    time = motion.time[window]
    release = estimate_release(motion, cut, recording.up, landing)
    landed = landing_distance(release, landing)
    row = manifest_entry(rows, recording.source, number, float(motion.time[cut.peak] - origin)) if rows else None
    target: float | None = None
    if row is not None:
        target, source_of_distance = row.distance, "manifest"
    elif (named := distance_from_name(path)) is not None:
        target, source_of_distance = named, "file name"
    if target is None:
        distance, source_of_distance = basket_from_landing(landed, landing)
    else:
        distance = target
    if not np.isfinite(distance):
        report.warnings.append(
            f"{path}: throw {number} at t={time[0] - origin:.2f} s left out: no basket distance and the ball "
            f"never comes down to {landing.target_height} m from the estimated release"
        )
        return None
    identifier = _unique_id(f"{path.stem}_t{number}", used_ids)
    meta: dict[str, Any] = {
        "subject": _subject(path, row),
        "source": str(path),
        "distance_source": source_of_distance,
        "release_time": float(release.time - time[0]),
        "start_time": float(time[0] - origin),
        "end_time": float(time[-1] - origin),
        "arm": motion.arm.side,
    }
    if np.isfinite(landed):
        meta["landing"] = landed
    if target is not None:
        meta["target"] = float(target)
        if np.isfinite(landed):
            meta["hit"] = bool(abs(landed - target) <= landing.hit_radius)
    angle = motion.angle[window]
    velocity = motion.velocity[window]
    report.throws.append(
        ThrowInfo(
            identifier, float(time[0] - origin), float(time[-1] - origin), float(release.time - origin),
            float(velocity.max()), (float(angle.min()), float(angle.max())), float(distance),
            source_of_distance, float(landed) if np.isfinite(landed) else None,
        )
    )
    data = {
        "time": time - time[0],
        "angle": angle,
        "velocity": velocity,
        "distance": np.full(time.size, float(distance)),
    }
    return Trajectory(identifier, data, meta)
