"""Recordings in, a dataset of labelled single throws out: the whole capture stage in one call.

For every file: read the arm joints (:mod:`~rlff.capture.bag`,
:mod:`~rlff.capture.skeleton_text`), keep the consistent tracked user
(:mod:`~rlff.capture.users`), compute each arm's angle on its own samples and take the throwing
one (:mod:`~rlff.capture.angles`), cut the throws (:mod:`~rlff.capture.segment`), leave out the
releases that are not at a target and label the others (:mod:`~rlff.capture.label`). Only the
finished throw is resampled, onto an even grid at its own median spacing (no coarser than
``OUTPUT_RATE_HZ``; a shape-preserving PCHIP curve between the samples), and its native rate and
largest gap go into its metadata. Each throw becomes one trajectory with columns ``time`` (s from
the throw's start), ``angle`` (rad), ``velocity`` (rad/s), the other joints the recordings carry
(``shoulder`` and ``shoulder_velocity``, ``wrist`` and ``wrist_velocity``, on the elbow's samples;
``joints=("elbow",)`` leaves them out) and ``distance`` (m). Cleaning (glitches, cropping,
cutting at the release) is left to :mod:`rlff.preprocess`.

Every candidate movement that is not taken is reported (:class:`FileReport.rejected`) with its time
from the file's start and the rule that stopped it; a file without a throw says which rule stopped
its best candidate.
"""

from __future__ import annotations

import csv
import os
import re
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
from scipy.interpolate import PchipInterpolator

from rlff.capture.angles import (
    MIN_TORSO,
    ArmMotion,
    align_arm,
    median_spacing,
    positions_at,
    throwing_arm,
)
from rlff.capture.bag import DEFAULT_FRAMES, DEFAULT_TOPIC, ROS_UP, read_bag
from rlff.capture.extension_gaps import (
    EXTENSION_GAP_FACTOR,
    EXTENSION_GAP_S,
    ExtensionGap,
    gap_at_the_peak,
    longest_gap,
    tracked_spacing,
)
from rlff.capture.label import (
    LandingSettings,
    ManifestRow,
    Release,
    basket_from_landing,
    check_throw_numbers,
    distance_from_name,
    estimate_release,
    landing_distance,
    manifest_entry,
    not_at_a_target,
    read_manifest,
    rows_without_a_throw,
)
from rlff.capture.manifest_match import (
    NO_ROW,
    Outcome,
    listing_warning,
    names_every_throw,
    rows_for_others,
    rows_of,
    unnamed_reason,
)
from rlff.capture.segment import Rejection, SegmentSettings, ThrowCut, find_throws
from rlff.capture.skeleton import ArmTrack, Recording
from rlff.capture.skeleton_text import (
    KINECT_UP,
    KINECT_V2_ROUTE,
    KINECT_WIDTH,
    axis_vector,
    kinect_row_layout,
    read_joint_csv,
    read_kinect_text,
    read_msr_text,
)
from rlff.capture.users import keep_consistent_user, upper_arm_lengths
from rlff.dataset import DEFAULT_CONTEXT, Dataset, Trajectory, joint_columns, velocity_column
from rlff.errors import InputError
from rlff.fileio import require_distinct
from rlff.kinds import binary_kind, is_ros1_bag, is_ros2_metadata
from rlff.limits import DISTANCE_RANGE, as_names, check_frame_rate, is_number
from rlff.wording import plural

FORMATS = ("bag", "kinect-text", "msr", "csv", "thesis")
ARMS = ("auto", "right", "left")
#: Joints an import may write, as the user names them; the elbow (``angle``) always.
JOINTS = ("shoulder", "elbow", "wrist")
#: Formats whose positions are in the sensor's frame (the camera at the origin).
SENSOR_FRAMES = ("bag", "kinect-text", "msr")
#: The up direction of the formats whose frame has one by convention (a CSV's is its exporter's), and why.
FORMAT_UP = {"bag": ROS_UP, "kinect-text": KINECT_UP, "msr": KINECT_UP}
FORMAT_UP_WHY = {"bag": "REP 103, as skeleton trackers publish tf", "kinect-text": "the Kinect's camera frame",
                 "msr": "the Kinect's camera frame"}
#: Without torso points, ``--up`` is hinted at when the upper arm lies within this many degrees of
#: one axis in at least this share of the samples (and more often than against the assumed up): in
#: the 26 MSR high throws (z up) it lies so along -z in 2-63 % of the samples and along any other
#: axis in at most 28 % (an overhand thrower's arm is raised much of the time).
HANGING_CONE_DEG = 30.0
HANGING_SHARE = 1 / 3
#: The share of a spacing by which a throw's last stamp may fall short of its grid's next point and
#: still end the grid: stamps rounded to microseconds make the median spacing of 60 Hz samples
#: 0.016667 s, 0.33 us too long, and 113 of them overshoot the last stamp by 38 us (0.2 % of a
#: spacing), which left the last sample off; at 120 Hz a 14 s throw stays within 10 %.
GRID_END_TOLERANCE = 0.1
#: A finished throw is resampled at its own median spacing, but no coarser than this (Hz).
OUTPUT_RATE_HZ = 15.0
#: The median upper arm (shoulder to elbow, m) of a recording in metres: 0.25-0.34 m in every arm
#: of the MSR throws and the test bags (148 arms); the range leaves a factor of 3 either way.
UPPER_ARM_RANGE = (0.1, 1.0)
#: The share of a recording's import done when it is read and when its throws are cut, for the
#: progress told (:func:`import_recordings`): measured on 26-minute recordings of 600 throws, the
#: reading took 35-50 % of the time (Kinect text, a ROS 1 bag), finding the arm and cutting the
#: throws 10 %, labelling and resampling each throw the rest.
READ_SHARE = 0.4
CUT_SHARE = 0.1
#: The rule that keeps one throw of an MSR file.
ONE_PER_MSR_FILE = "one throw per MSR file"
#: Median elbow peak speeds (rad/s) of a set of throws read at an assumed frame rate that pass
#: without a warning: the MSR throws peak at 10-16 rad/s (a median 12.7), a human elbow at about
#: 30 at most; read at a quarter or four times their rate they give 3.8 or about 50.
PLAUSIBLE_PEAK = (5.0, 35.0)
#: Median throw (wind-up to follow-through, s) below which such a set is too fast: 0.9-1.5 s for
#: the MSR throws (10-90 %); read at four times their rate, 0.3 s (the fit then flattens the
#: elbow's peak, so the speed alone does not tell).
SHORTEST_THROW = 0.5
#: A file's throws shorter than SHORTEST_THROW are judged read at a wrong rate only when they
#: also peak above this (rad/s): the shortest real MSR throws (0.45-0.5 s at 15-120 Hz) peak at
#: 5.6-7.5 rad/s, the files read at twice their rate that short at 17-25.
SHORT_AND_FAST = 10.0
#: Median throw (s) above which such a set is too slow: the MSR throws last at most 1.9 s; read
#: at a quarter of their rate 1.9-4 s (the wind-up's walk stops at 1.5 s, so the time alone
#: does not scale).
LONGEST_THROW = 3.0
#: A file's throw that peaks below PLAUSIBLE_PEAK is judged read at a wrong rate only when it
#: also lasts longer than this (s): the slowest real MSR throw (3.9 rad/s) lasts 1.9 s.
SLOW_AND_LONG = 2.0
#: Units a recording's coordinates may be in instead of metres, with their size in metres.
OTHER_UNITS = {"millimetres": 1e-3, "centimetres": 1e-2}
#: An import of several files with more notes than this says each kind of note once, with its counts
#: (:meth:`ImportReport.summary_notes`), so that the warnings after them stay in sight (800 files
#: wrote 2,273 lines of notes).
NOTES_IN_FULL = 20


@dataclass
class ThrowInfo:
    """Where one imported throw came from (times in s from the recording's first frame: the import's
    clock, :attr:`FileReport.clock_origin`).

    ``native_rate_hz`` is 1 / the median spacing of its samples, ``largest_gap`` (s) the longest
    spacing, ``release_confidence`` ``low`` when the release stretch was sparsely sampled,
    ``peak_confidence`` ``low`` when a gap in the extension leaves its peak speed bridged, not
    measured (:mod:`~rlff.capture.extension_gaps`).
    """

    id: str
    start: float
    end: float
    release: float
    peak_velocity: float
    angle_range: tuple[float, float]
    distance: float
    distance_source: str
    landing: float | None
    native_rate_hz: float
    largest_gap: float
    release_confidence: str
    peak_confidence: str = "high"


@dataclass
class FileReport:
    """What the import did with one file.

    ``clock_origin`` is the time (s, the recording's own clock) every time of the report counts
    from: the file's first frame, tracked or not, for text and CSV (the time a video or a
    spreadsheet of it shows, which a manifest's ``start`` and ``end`` are read against); a bag's
    first transform of the arm imported, as its tf stream has no frame before the tracker finds
    the user. ``rejected`` holds every candidate movement not taken as a throw (its ``time`` in s
    on that clock, the ``rule`` that stopped it and the ``reason``); each also has a note,
    or a warning for throws no manifest row names (rule ``manifest``).
    ``trajectories`` counts the trajectories taken from the file: its ``throws``, or a thesis
    matrix's rows (which carry no cut to report). ``motion`` is the arm the throws were cut from
    (:func:`arm_motion`; None for a thesis matrix), for figures, and ``frames_span`` the time (s,
    the recording's clock) of the file's first and last frame, tracked or not
    (:attr:`Recording.frames_span`); :meth:`ImportReport.to_dict` leaves both out.
    """

    source: str
    format: str
    arm: str | None = None
    user: str | None = None
    clock_origin: float = 0.0
    throws: list[ThrowInfo] = field(default_factory=list)
    rejected: list[Rejection] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    trajectories: int = 0
    motion: ArmMotion | None = field(default=None, repr=False, compare=False)
    #: The frame rate (Hz) its time was made from when the file has no time stamps, else None.
    assumed_rate: float | None = None
    frames_span: tuple[float, float] | None = field(default=None, repr=False, compare=False)

    @property
    def estimated_distances(self) -> int:
        """Its throws whose distance is a landing estimate (no manifest row, no distance in the file name)."""
        return sum(throw.distance_source.startswith("landing estimate") for throw in self.throws)

    def untracked_spans(self) -> list[tuple[float, float]]:
        """(from, to) times (s, the recording's clock) of every stretch where the arm was not tracked:
        between the runs of its ``motion`` (lost tracking, :meth:`ArmMotion.lost_spans`) and, where
        the file's frames go on before its first tracked sample or after its last (frames dropped
        with all arm joints at zero, a joint blank), from the file's first frame and to its last."""
        if self.motion is None:
            return []
        spans = self.motion.lost_spans()
        runs = self.motion.runs()
        if self.frames_span is None or not runs:
            return spans
        first, last = float(self.motion.time[runs[0].start]), float(self.motion.time[runs[-1].stop - 1])
        before = [(self.frames_span[0], first)] if self.frames_span[0] < first else []
        after = [(last, self.frames_span[1])] if self.frames_span[1] > last else []
        return before + spans + after

    def reject(self, rejection: Rejection, label: str, noted: bool = True) -> None:
        """Record a candidate not taken (``rejection.time`` on the recording's clock) with a note
        (unless ``noted`` is False: a warning says it)."""
        rejection = Rejection(rejection.time - self.clock_origin, rejection.rule, rejection.reason, rejection.rise)
        self.rejected.append(rejection)
        if noted:
            self.notes.append(f"{Path(self.source).name}: {label}: movement at t={rejection.time:.2f} s is not a throw ({rejection.reason})")


@dataclass
class ImportReport:
    """What the import did, file by file; ``joints`` the joint columns written (``angle`` first),
    ``general`` notes on all files (a joint left out because some file lacks it, the manifest rows
    for recordings not given),
    ``general_warnings`` warnings on no one file (a manifest row that names a file found nowhere,
    :func:`~rlff.capture.manifest_match.rows_for_others`)."""

    files: list[FileReport] = field(default_factory=list)
    joints: list[str] = field(default_factory=list)
    general: list[str] = field(default_factory=list)
    general_warnings: list[str] = field(default_factory=list)

    @property
    def n_throws(self) -> int:
        """Trajectories imported: every file's throws and the rows of thesis matrices."""
        return sum(report.trajectories for report in self.files)

    @property
    def warnings(self) -> list[str]:
        return [warning for report in self.files for warning in report.warnings] + self.general_warnings

    @property
    def estimated_distances(self) -> int:
        """Throws whose distance is a landing estimate (no manifest row, no distance in the file name)."""
        return sum(report.estimated_distances for report in self.files)

    @property
    def notes(self) -> list[str]:
        return [note for report in self.files for note in report.notes] + self.general

    def summary_notes(self) -> list[str]:
        """The notes as ``rlff data import`` says them: each one, for one file or up to
        :data:`NOTES_IN_FULL` notes; for more, each kind once (a kind: the note without the file's
        name, its numbers nor its closing parenthesis), the kind's first note said with how many
        notes and files share it when it repeats, then the :attr:`general` notes."""
        if len(self.files) <= 1 or len(self.notes) <= NOTES_IN_FULL:
            return list(self.notes)
        kinds: dict[str, list[tuple[str, str]]] = {}  # kind -> (file, note without the file's name)
        for file in self.files:
            name = Path(file.source).name
            for note in file.notes:
                text = note.removeprefix(f"{name}: ")
                kind = re.sub(r"\s*\([^()]*(\([^()]*\)[^()]*)*\)$", "", re.sub(r"-?\d+(\.\d+)?", "#", text))
                kinds.setdefault(kind, []).append((name, text))
        said = []
        for notes in kinds.values():
            files = len({name for name, _ in notes})
            name, first = notes[0]
            if len(notes) == 1:
                said.append(f"{name}: {first}")
            elif len({text for _, text in notes}) == 1:
                said.append(f"{first}: {plural(files, 'file')}")
            else:
                said.append(f"{plural(len(notes), 'note')} like this in {plural(files, 'file')} (--json lists each "
                            f"file's): {name}: {first}")
        return said + list(self.general)

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-able summary."""
        return {
            "throws": self.n_throws,
            "estimated_distances": self.estimated_distances,
            "joints": self.joints,
            "notes": self.general,
            "warnings": self.general_warnings,
            "files": [{key: value for key, value in asdict(replace(report, motion=None)).items()
                       if key not in ("motion", "frames_span")} for report in self.files],
        }


def require_exists(path: str | Path) -> None:
    """Refuse a recording ``path`` that does not exist; one holding ``*``, ``?`` or ``[`` is said to
    be a pattern the shell matched to no file (it passes such a word on as it is)."""
    if Path(path).exists():
        return
    if any(char in str(path) for char in "*?["):
        raise InputError(f"{path}: no file matches this pattern (the shell passed it on as it is): check the "
                         "folder and the name")
    raise InputError(f"{path}: no such file or folder")


def detect_format(path: str | Path) -> str:
    """Guess a recording's format from its name and first line.

    ``.bag`` files and ROS 2 bags (a folder, its database or its ``metadata.yaml``) are bags, text
    whose first row is 4 numbers is MSR, 61
    numbers Kinect SDK v1, a file whose first line is rlff's ``# {"trajectory": ...}``
    comment a thesis matrix, ``.csv`` and any other ``.tsv`` a joint CSV. Kinect text with a
    header line or a tracking state after each joint's x y z is refused with what to drop.
    """
    path = Path(path)
    if path.suffix == ".bag" or path.is_dir() or path.suffix in (".db3", ".mcap") or is_ros2_metadata(path):
        return "bag"
    if path.is_file() and (kind := binary_kind(path)) is not None:  # a bag renamed, a gzip: no text to sniff
        raise InputError(f"{path} is {kind}")
    if path.suffix.lower() == ".csv":
        return "csv"
    if path.is_file():
        with path.open(encoding="utf-8", errors="replace") as handle:
            first = next((line for line in handle if line.strip()), "")
            if first.startswith("#") and '"trajectory"' in first:
                return "thesis"  # rlff writes a thesis matrix with a JSON comment before each block
            if path.suffix.lower() == ".tsv":
                return "csv"
            handle.seek(0)
            header = None  # a first line of names, above rows of numbers
            for line in handle:
                fields = line.split("#", 1)[0].replace(",", " ").split()
                if fields:
                    # numbers only: a CSV header of 4 names ("trajectory,angle,distance,velocity",
                    # a dataset renamed .parquet) is no MSR row
                    if not all(is_number(field) for field in fields):
                        if header is None and not any(is_number(field) for field in fields):
                            header = line.strip()
                            continue
                        break
                    if header is None and len(fields) == 4:
                        return "msr"
                    if header is None and len(fields) == KINECT_WIDTH:
                        return "kinect-text"
                    layout = _text_layout(header, len(fields))
                    if layout:
                        raise InputError(f"{path}: cannot tell the format: {layout}")
                    break
    elif not path.exists():
        raise InputError(f"{path}: no such file or folder")
    raise InputError(f"{path}: cannot tell the format; give --format ({'|'.join(FORMATS)})")


def _text_layout(header: str | None, width: int) -> str:
    """What a text file whose rows hold ``width`` numbers, below a ``header`` line (or none), is
    and what to drop to make it Kinect SDK v1 text, or ``""`` when it is nothing rlff knows."""
    named = f"its first line is a header ({header[:40]!r}) above rows of" if header is not None else "its rows hold"
    if width == KINECT_WIDTH and header is not None:
        return f"{named} {width} numbers, Kinect SDK v1 text (a frame number, 20 joints x (x y z)): drop the header line"
    layout = kinect_row_layout(width)
    if layout is None:
        return ""
    if layout.drop is not None:
        drop = f"the header line and {layout.drop}" if header is not None else layout.drop
        return f"{named} {width} numbers, {layout.holds}: drop {drop}, and it reads as Kinect text"
    return f"{named} {width} numbers, {layout.holds}: it looks like Kinect v2 joint text, {KINECT_V2_ROUTE}"


#: The suffix of the files each text format reads, for the files of a folder given in their place.
FORMAT_SUFFIXES = {"kinect-text": ".txt", "msr": ".txt", "csv": ".csv", "thesis": ".txt"}
#: Suffixes of recordings, as :func:`detect_format` tells them.
_RECORDING_SUFFIXES = (".bag", ".txt", ".csv", ".tsv")


def refuse_folder(path: str | Path, format: str | None = None) -> None:
    """:class:`InputError` for a folder given where recordings go, unless it is a ROS 2 bag: it is
    said to be a folder, with the files in it to give instead (``DIR/*.txt``).

    Parameters
    ----------
    path : str or Path
    format : str, optional
        The ``--format`` given (None or ``auto``: guessed). A folder with a ``metadata.yaml``
        or a bag database (``.db3``, ``.mcap``) is a ROS 2 bag and passes, for ``bag`` and
        ``auto``; rosbags then says what is wrong with a damaged one.
    """
    path = Path(path)
    if not path.is_dir():
        return
    guessed = format in (None, "auto")
    if (guessed or format == "bag") and ((path / "metadata.yaml").is_file()
                                         or any(path.glob("*.db3")) or any(path.glob("*.mcap"))):
        return
    files = [child for child in path.iterdir() if child.is_file()]
    if guessed or format == "bag":
        kind = "not a ROS 2 bag (no metadata.yaml in it)"
        wanted = [".bag"] if format == "bag" else list(_RECORDING_SUFFIXES)
    else:
        kind = f"and --format {format} reads files"
        wanted = [FORMAT_SUFFIXES[format]] if format in FORMAT_SUFFIXES else []
    counts = {suffix: sum(child.suffix.lower() == suffix for child in files) for suffix in wanted}
    found = {suffix: count for suffix, count in counts.items() if count}
    bags = [child for child in path.iterdir() if child.is_dir() and (child / "metadata.yaml").is_file()]
    if found:
        suffix = max(found, key=lambda name: found[name])
        hint = f"give the recordings in it: {path}/*{suffix} ({plural(found[suffix], suffix + ' file')})"
    elif bags and (guessed or format == "bag"):
        hint = f"give the ROS 2 bags in it: {path}/*/ ({plural(len(bags), 'bag folder')})"
    else:
        looked = ", ".join(wanted[:-1]) + " or " + wanted[-1] if len(wanted) > 1 else "".join(wanted) or "recording"
        hint = f"give the recordings themselves (the folder holds no {looked} file)"
    raise InputError(f"{path}: is a folder, {kind}: {hint}")


#: The columns that make a table an rlff dataset, throws already imported, rather than joint positions.
DATASET_COLUMNS = ("trajectory", "angle", "velocity")
#: Suffixes of the binary dataset formats (:mod:`rlff.formats`), which hold no recording.
_DATASET_SUFFIXES = (".parquet", ".pq", ".npz")


def refuse_datasets(paths: Sequence[str | os.PathLike]) -> None:
    """:class:`InputError` for rlff datasets given as recordings (a CSV whose header holds
    :data:`DATASET_COLUMNS`, a Parquet or NPZ file): throws already imported, which the joint CSV
    reader would take for positions without a shoulder. The message says what they are and how
    to join them (``rlff data merge``), with the recordings beside them or without."""
    datasets = [str(path) for path in paths if _is_dataset(Path(path))]
    if not datasets:
        return
    shown = " ".join(datasets) if len(datasets) <= 4 else "DATASETS..."
    what = (f"{datasets[0]} is an rlff dataset" if len(datasets) == 1 else
            f"{_listed(datasets)} are rlff datasets")
    what += f" ({', '.join(DATASET_COLUMNS)} columns: throws already imported), not {'a recording' if len(datasets) == 1 else 'recordings'}"
    if len(datasets) < len(paths):
        raise InputError(f"{what}: import the recordings alone (-o new.csv), then join the throws with "
                         f"`rlff data merge {shown} new.csv -o all.csv` (docs/data.md)")
    if len(datasets) == 1:
        raise InputError(f"{what}: it needs no import (`rlff data preprocess {shown} -o clean.csv` cleans it); "
                         "`rlff data merge` joins datasets (docs/data.md)")
    raise InputError(f"{what}: join them with `rlff data merge {shown} -o all.csv` (docs/data.md)")


def _is_dataset(path: Path) -> bool:
    """Whether ``path`` is an rlff dataset file (:func:`refuse_datasets`)."""
    if not path.is_file():
        return False
    if path.suffix.lower() in _DATASET_SUFFIXES:
        return True
    with path.open(encoding="utf-8", errors="replace", newline="") as handle:
        header = next((line for line in handle if line.strip()), "")
    names = {name.strip() for name in next(csv.reader([header]), [])}
    return set(DATASET_COLUMNS) <= names


def _listed(names: Sequence[str], shown: int = 3) -> str:
    """``a, b and c``, the first ``shown`` of ``names`` and how many more."""
    if len(names) > shown:
        return f"{', '.join(names[:shown])} and {len(names) - shown} more"
    return ", ".join(names[:-1]) + f" and {names[-1]}"


def imported_columns(paths: Sequence[str | Path], format: str | None = None) -> tuple[str, ...]:
    """The sample columns every import of ``paths`` writes, known before any is read: a thesis
    matrix passes through as (angle, distance, velocity); a recording's throws have ``time`` too
    (and the other joints' columns where it carries them)."""
    kinds = {detect_format(path) if format in (None, "auto") else format for path in paths}
    return ("angle", "distance", "velocity") if kinds == {"thesis"} else ("time", "angle", "velocity", "distance")


@contextmanager
def _format_named(path: Path, kind: str, given: str | None) -> Iterator[None]:
    """Reading ``path`` as ``kind``: an :class:`InputError` of a format the user gave (``given``)
    that the file's name and first line say it is not (:func:`detect_format`) names the format it
    looks like (``--format thesis`` on an MSR file: "context row 'distance' is not constant"). A
    bag read as a text format is said to be one, the text reader's message left out: it quoted the
    bag's binary bytes as "a header line"; so is a file whose first bytes say what it is
    (:func:`rlff.kinds.binary_kind`: a bag renamed .txt, a gzip)."""
    try:
        yield
    except InputError as exc:
        try:
            looks = detect_format(path) if given not in (None, "auto") else kind
        except InputError as detected:
            # a bag renamed .txt, a gzip: what it is (a ROS 1 bag read as one: the bag reader's words)
            if binary_kind(path) is not None and not (kind == "bag" and is_ros1_bag(path)):
                raise detected from None
            looks = kind
        if looks == kind:
            raise
        if looks == "bag":
            raise InputError(f"{path}: a ROS bag, which --format {kind} does not read (it reads text): leave --format "
                             "out, or give --format bag") from None
        raise InputError(f"{exc} (read as --format {kind}; it looks like {looks}: give --format {looks}, or leave "
                         "--format out)") from None


def read_recording(
    path: Path,
    format: str,
    *,
    topic: str = DEFAULT_TOPIC,
    frames: Sequence[str] = DEFAULT_FRAMES,
    rate_hz: float | None = None,
    columns: Mapping[str, str] | None = None,
    up: str | None = None,
    arm: str = "auto",
) -> Recording:
    """Read one recording in a skeleton format (not ``thesis``); ``arm``, the side whose throws
    will be cut, tells the CSV reader which arm lacking a column is an error."""
    if format == "bag":
        recording = read_bag(path, topic=topic, frames=frames)
    elif format == "kinect-text":
        recording = read_kinect_text(path, rate_hz)
    elif format == "msr":
        recording = read_msr_text(path, rate_hz)
    elif format == "csv":
        recording = read_joint_csv(path, columns, rate_hz, up or "z", arm)
    else:
        raise InputError(f"{path}: unknown format {format!r} (formats: {', '.join(FORMATS)})")
    if up is not None:
        recording.up = axis_vector(up)
    return recording


def import_recordings(
    paths: str | os.PathLike | Sequence[str | os.PathLike],
    format: str | None = None,
    *,
    manifest: str | Path | None = None,
    topic: str = DEFAULT_TOPIC,
    frames: Sequence[str] = DEFAULT_FRAMES,
    arm: str = "auto",
    user: str | None = None,
    rate_hz: float | None = None,
    progress: Callable[[str, str, float], None] | None = None,
    columns: Mapping[str, str] | None = None,
    up: str | None = None,
    segment: SegmentSettings | None = None,
    landing: LandingSettings | None = None,
    joints: Sequence[str] | None = None,
) -> tuple[Dataset, ImportReport]:
    """Import skeleton recordings as a dataset of single, labelled throws.

    Parameters
    ----------
    paths : recordings (files, or ROS 2 bag folders, a bag's ``metadata.yaml`` read as its folder), or one
    format : one of ``bag``, ``kinect-text``, ``msr``, ``csv``, ``thesis``; None or ``auto`` guesses
        it per file from the name and content
    manifest : CSV of basket distances (see :mod:`rlff.capture.label`)
    topic, frames : tf topic and (shoulder, elbow, hand) frames, for bags
    arm : ``auto`` (the arm whose hand sweeps furthest), ``right`` or ``left``
    user : the tracked user whose throws to import (its id in the recordings: ``2`` for the
        frames ``right_elbow_2``...), which the throws' ids and subject then carry (``pair_u2_t1``,
        ``pair_u2``); default the steady user whose hand sweeps furthest
    rate_hz : frame rate of text formats without time stamps (Kinect 30, MSR 15, CSV 30 by default)
    progress : ``progress(path, stage, share)`` for each file as it is ``"reading"``, ``"cutting
        throws"``, ``"labelling throw 3 of 600"`` (each throw in turn) and ``"done"``, with the
        share of the file's work done (0 as it is read, :data:`READ_SHARE` as its throws are cut,
        1 when it is done): a 100-minute recording takes a minute or more, and without its parts
        a progress bar over the files sat at none done all that time
    columns : column map of the CSV format (our name -> the file's)
    up : the up axis of the recordings' frame (``x``, ``-y``...); default per format
    segment, landing : settings of the throw finder and of the landing estimate
    joints : the joints to write, among ``shoulder``, ``elbow`` (always) and ``wrist``; None:
        every joint all the recordings carry (the wrist only where each has a hand point beside
        the wrist; the thesis matrix carries the elbow alone). ``("elbow",)``: the one-joint
        dataset, as before whole-arm capture.

    Returns
    -------
    dataset : Dataset
        One trajectory per throw, its id ``<file stem>_t<N>`` (N its number among the file's
        throws; ``<file stem>_u<user>_t<N>`` with ``user``): ``time``, ``angle``, ``velocity``, the other joints' angles and
        velocities (``shoulder``, ``shoulder_velocity``, ``wrist``, ``wrist_velocity``, rad and
        rad/s), ``distance`` (the basket's, or without one the landing estimate rounded to
        ``landing.distance_step``); metadata
        ``subject``, ``source``, ``target``/``hit`` (when the basket is known), ``landing``,
        ``distance_source``, ``release_time`` (s from the throw's start), ``start_time`` and
        ``end_time`` (s from the recording's first frame, :attr:`FileReport.clock_origin`),
        ``arm``, ``native_rate_hz``, ``largest_gap`` (s), ``release_confidence``. Each throw is
        resampled onto an even grid at its median spacing, no coarser than ``OUTPUT_RATE_HZ``.
    report : ImportReport
        Per file: the throws, every candidate not taken and why, the arm and user kept, and
        notes and warnings (a file without a throw: which rule stopped its best candidate).

    Raises
    ------
    InputError
        A file that cannot be read (named, with what is wrong), an unknown format or arm, a
        manifest row at fault (a throw listed twice with different distances, a throw number
        that does not exist, start after end), a joint that is not known or that a recording
        does not carry, the same file twice or two files holding the same throw sample for
        sample (one recording under two names).
    """
    if isinstance(paths, (str, os.PathLike)):  # one recording: not the characters of its path
        paths = [paths]
    wanted = _check_joints(joints)
    if rate_hz is not None:
        check_frame_rate(rate_hz)
    if format not in (None, "auto", *FORMATS):
        raise InputError(f"unknown format {format!r} (formats: {', '.join(FORMATS)})")
    if arm not in ARMS:
        raise InputError(f"unknown arm {arm!r} (arms: {', '.join(ARMS)})")
    if not paths:
        raise InputError("no recordings given")
    if format in (None, "auto", "bag"):  # a ROS 2 bag's metadata.yaml is the bag: its folder, named as given alone
        paths = [Path(path).parent if is_ros2_metadata(Path(path)) else path for path in paths]
    # a folder given as "." or ".." (metadata.yaml inside the bag: its parent is ".") has no name to
    # make ids and a file-name distance of: it is the folder it stands for ("_t1", source ".", the
    # bag's distance from its name lost)
    paths = [Path(path).resolve() if Path(path).name in ("", "..") else path for path in paths]
    require_distinct(paths, "recording")
    rows = read_manifest(manifest) if manifest is not None else []
    landing = landing or LandingSettings()
    trajectories: list[Trajectory] = []
    report = ImportReport()
    used_ids: set[str] = set()
    origin: dict[str, Path] = {}  # the file of every throw, by id
    for path in paths:  # before anything is read (a missing last file was found after every other was read)
        require_exists(path)
        refuse_folder(path, format)
    refuse_datasets(paths)
    kinds = [detect_format(path) if format in (None, "auto") else format for path in map(Path, paths)]
    if up is not None:
        report.general_warnings.extend(_up_against_conventions(up, paths, kinds))
    if columns and "csv" not in kinds:
        raise InputError(f"a column map (--columns) is for CSV recordings, and none is given (formats: "
                         f"{', '.join(sorted(set(kinds)))})")
    def tell(path: Path, stage: str, share: float) -> None:
        if progress is not None:
            progress(str(path), stage, share)

    for raw_path, kind in zip(paths, kinds, strict=True):
        path = Path(raw_path)
        tell(path, "reading", 0.0)
        if kind == "thesis":
            with _format_named(path, kind, format):
                file_report, found = _import_thesis(path, used_ids)
        else:
            with _format_named(path, kind, format):
                recording = read_recording(path, kind, topic=topic, frames=frames, rate_hz=rate_hz, columns=columns,
                                           up=up, arm=arm)
            tell(path, "cutting throws", READ_SHARE)
            file_report, found = _import_recording(
                recording, kind, arm, user, rows, segment or SegmentSettings(), landing, used_ids, up_given=up is not None,
                told=lambda stage, share, path=path: tell(path, stage, share),
            )
        _require_joints(wanted, file_report, found)
        file_report.trajectories = len(found)
        trajectories.extend(found)
        origin.update((trajectory.id, path) for trajectory in found)
        report.files.append(file_report)
        tell(path, "done", 1.0)
    # a manifest of the whole session, some of its recordings given: their rows are one note
    unused_notes, unused_warnings = rows_for_others(rows, paths)
    report.general.extend(unused_notes)
    report.general_warnings.extend(unused_warnings)
    report.general_warnings.extend(_rate_warnings(report, rate_hz))
    dataset = Dataset(_same_context(_common_joints(trajectories, wanted, report), report))
    _refuse_copies(dataset, origin)
    return dataset, report


def _up_against_conventions(up: str, paths: Sequence[str | os.PathLike], kinds: Sequence[str]) -> list[str]:
    """A warning per format whose frame has its own up axis (:data:`FORMAT_UP`) that ``up``, given
    to every file of an import holding files of other formats too, is not: a bag read with the
    ``--up y`` of the camera-frame CSVs beside it changes its landings and baskets without a word."""
    formats = set(kinds) - {"thesis"}
    if len(formats) < 2:
        return []
    given = axis_vector(up)
    said = []
    for kind, own in FORMAT_UP.items():
        files = [Path(path).name for path, of in zip(paths, kinds, strict=True) if of == kind]
        if files and not np.array_equal(given, own):
            shown = ", ".join(files[:3]) + (f" and {len(files) - 3} more" if len(files) > 3 else "")
            one = len(files) == 1
            said.append(f"--up {up} is applied to every file of this import, but {plural(len(files), kind + ' file')} "
                        f"({shown}) {'is' if one else 'are'} in a frame with {_axis_name(own)} up ({FORMAT_UP_WHY[kind]}) "
                        f"and {'is' if one else 'are'} read with {up} up: {'its' if one else 'their'} releases, landings "
                        "and estimated baskets change with it; import each format apart, with its own --up or none")
    return said


def _rate_warnings(report: ImportReport, rate_hz: float | None) -> list[str]:
    """A warning per format read at an assumed rate (frames without time stamps: Kinect and MSR
    text, a CSV without a time column) whose throws are implausible for a throw, all of them or
    those of some files (a set recorded at two rates): the frame rate is the likely mistake."""
    said = []
    for kind in ("msr", "kinect-text", "csv"):
        files = [file for file in report.files if file.format == kind and file.throws and file.assumed_rate]
        if not files:
            continue
        # the rate the reader assumed, the same for every file of a kind: the format's or --rate
        rate = (f"--rate {rate_hz:g} Hz" if rate_hz is not None else
                f"{files[0].assumed_rate:g} Hz (the format's rate; --rate changes it)" if kind != "csv" else
                f"{files[0].assumed_rate:g} Hz (no time column; --rate, or map the time column with --columns "
                "\"time=NAME\")")
        seen = _implausible([throw for file in files for throw in file.throws])
        if seen:
            count = sum(len(file.throws) for file in files)
            said.append(f"the {count} {kind} throws: {seen}; their files have no time stamps and were read at "
                        f"{rate}: was it the rate they were recorded at?")
            continue
        odd = [(file, why) for file in files if (why := _implausible(file.throws, alone=True))]
        if odd:
            shown = "; ".join(f"{Path(file.source).name}: {why}" for file, why in odd[:3])
            more = f" (and {len(odd) - 3} more)" if len(odd) > 3 else ""
            # the others pass, which says little: a rate off by a factor of 2 mostly passes
            said.append(f"{len(odd)} of {len(files)} {kind} files hold throws unlike a throw at the rate read "
                        f"({rate}): {shown}{more}: were these recorded at another rate? (import them apart with "
                        "their --rate; a rate off by a factor of 2 can pass unseen, so check the others' too)")
    return said


def _implausible(throws: Sequence[ThrowInfo], alone: bool = False) -> str | None:
    """What makes these throws (their medians) unlike a human throw, or None. ``alone``: the
    throws of one file, judged more leniently (one slow or short throw is a person's, not a rate's:
    slow and long together, short and fast together, or longer than any throw)."""
    peak = float(np.median([throw.peak_velocity for throw in throws]))
    duration = float(np.median([throw.end - throw.start for throw in throws]))
    low, high = PLAUSIBLE_PEAK
    if peak < low and (not alone or duration > SLOW_AND_LONG):
        return f"elbows peak at a median {peak:.3g} rad/s, slower than a throw ({low:g}-{high:g} rad/s)"
    if duration > LONGEST_THROW:
        return (f"they last a median {duration:.2g} s wind-up to follow-through, longer than a throw (at most "
                f"{LONGEST_THROW:g} s)")
    said, fast = [], peak > high
    if duration < SHORTEST_THROW and (fast or not alone):
        said.append(f"they last a median {duration:.2g} s wind-up to follow-through, shorter than a throw (at least "
                    f"{SHORTEST_THROW:g} s)")
    elif duration < SHORTEST_THROW and peak > SHORT_AND_FAST:
        said.append(f"they last a median {duration:.2g} s wind-up to follow-through and peak at {peak:.3g} rad/s, "
                    f"shorter than a throw that fast (at least {SHORTEST_THROW:g} s above {SHORT_AND_FAST:g} rad/s)")
    if fast:
        said.append(f"elbows peak at a median {peak:.3g} rad/s, faster than a throw (at most {high:g} rad/s)")
    return ", and their ".join(said) or None


def _refuse_copies(dataset: Dataset, origin: Mapping[str, Path]) -> None:
    """Refuse a throw that two files hold sample for sample, whatever its basket
    (:meth:`Dataset.duplicates`): one recording under two names (one of them naming a distance),
    which :func:`require_distinct`, comparing paths, cannot see and which would count twice.
    Copies within one file are left to the fit's warning."""
    for ids in dataset.duplicates():
        first: dict[Path, str] = {}  # each file of the group and its first copy
        for trajectory_id in ids:
            first.setdefault(origin[trajectory_id], trajectory_id)
        if len(first) > 1:
            (file_a, id_a), (file_b, id_b) = list(first.items())[:2]
            raise InputError(
                f"{file_a} and {file_b} hold the same throw, sample for sample ({id_a} and {id_b}; their baskets "
                "aside): one recording under two names would count twice; give each recording once"
            )


def _same_context(trajectories: list[Trajectory], report: ImportReport) -> list[Trajectory]:
    """Every throw with the basket columns some manifest row gave (``bearing``, ``height``): the
    throws without one stand for the default basket (straight ahead, rim 0.3 m), with a note."""
    out = trajectories
    for name, default in DEFAULT_CONTEXT.items():
        lacking = [t for t in out if name not in t.columns]
        if not lacking or len(lacking) == len(out):
            continue
        report.general.append(
            f"{len(lacking)} throws without a manifest {name} stand for the default basket's ({default:g})"
        )
        out = [t if name in t.columns else t.with_columns(**{name: np.full(len(t), default)}) for t in out]
    return out


def _check_joints(joints: Sequence[str] | None) -> tuple[str, ...] | None:
    """The joint columns asked for (``angle`` for the elbow), or None for every joint there is."""
    if joints is None:
        return None
    joints = as_names(joints)
    unknown = [name for name in joints if name not in JOINTS]
    if unknown:
        raise InputError(f"joint {unknown[0]!r}: not one of {', '.join(JOINTS)}")
    if "elbow" not in joints:
        raise InputError(f"joints {', '.join(joints) or 'none'}: the elbow must be one (its angle is the phase)")
    return tuple("angle" if name == "elbow" else name for name in JOINTS if name in joints)


def _require_joints(wanted: tuple[str, ...] | None, file_report: FileReport, found: list[Trajectory]) -> None:
    """Raise when a file's throws lack a joint asked for by name."""
    if wanted is None or not found:
        return
    for name in wanted:
        if name not in found[0].columns:
            why = ("the thesis matrix holds the elbow only" if file_report.format == "thesis"
                   else "the format has no hand point beside the wrist")
            raise InputError(f"{file_report.source}: no {name} angle ({why}); leave {name} out of the joints")


def _common_joints(
    trajectories: list[Trajectory], wanted: tuple[str, ...] | None, report: ImportReport
) -> list[Trajectory]:
    """Every throw with the same joint columns: those asked for, or those all throws carry."""
    if not trajectories:
        return trajectories
    carried = [set(joint_columns(t.columns)) for t in trajectories]
    keep = set(wanted) if wanted is not None else set.intersection(*carried)
    dropped = sorted(set.union(*carried) - keep)
    if wanted is None and dropped:
        report.general.append(
            f"{', '.join(dropped)} left out: not every recording carries {'it' if len(dropped) == 1 else 'them'}"
        )
    report.joints = list(joint_columns(keep))
    gone = {name for joint in dropped for name in (joint, velocity_column(joint))}
    if not gone:
        return trajectories
    return [t.replace(data={k: v for k, v in t.data.items() if k not in gone}) for t in trajectories]


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


def _subject(path: Path, row: ManifestRow | None, user: str | None = None) -> str:
    """The thrower of a throw of ``path``: its manifest row's ``subject``, else ``sNN`` in the file
    name, else the file's stem; with a ``user`` asked for (``--user 2``) that one followed by
    ``_u2``, as a recording imported once per thrower holds several (their throws then merge
    without two under one id)."""
    if row is not None and row.subject:
        return row.subject
    match = re.search(r"(?:^|_)(s\d+)(?:_|$)", path.stem)
    subject = match.group(1) if match else path.stem
    return subject if user is None else f"{subject}_u{user}"


def arm_motion(recording: Recording, arm: str = "auto",
               user: str | None = None) -> tuple[ArmMotion, list[ArmTrack], list[str], list[str]]:
    """The arm whose throws the import cuts: the consistent user's (or ``user``'s), on the side
    asked for or, with ``auto``, the one whose hand sweeps furthest.

    Returns
    -------
    motion : ArmMotion
        That arm's joints, angles (rad) and velocities (rad/s) on the elbow's own stamps (s).
    arms : list of ArmTrack
        The kept user's arms (both sides where tracked).
    notes : list of str
        Which user and arm were kept, and why.
    warnings : list of str
        An arm left out because a joint it needs was never tracked (it may be the throwing one);
        a user left out whose hand swept as a thrower's does.

    Raises
    ------
    InputError
        No arm on the side asked for, no arm whose joints were all tracked, or coordinates that
        are not in metres.
    """
    path = Path(recording.source)
    arms, notes, warnings = keep_consistent_user(recording, user)
    if arm != "auto":
        arms = [track for track in arms if track.side == arm]
        if not arms:
            sides = sorted({track.side for track in recording.arms})
            raise InputError(f"{path}: no {arm} arm (arms there: {', '.join(sides)})")
    untracked = [(track, track.untracked) for track in arms if track.untracked is not None]
    if len(untracked) == len(arms):
        track, joint = untracked[0]
        raise InputError(f"{path}: {track.label}: the {joint.name} was never tracked ({plural(len(joint), 'sample')})"
                         f"{' and no other arm was' if len(arms) > 1 else ''}: no arm to cut throws from; "
                         "leave the file out")
    warnings += [f"{path}: {track.label} left out: the {joint.name} was never tracked ({plural(len(joint), 'sample')})"
                 for track, joint in untracked]
    arms = [track for track in arms if track.untracked is None]
    motions = [align_arm(track, up=recording.up) for track in arms]
    motion = motions[0] if len(motions) == 1 else throwing_arm(motions)
    _check_metres(path, motion.arm)
    if len(motions) > 1:
        notes.append(f"{path.name}: throwing arm: {motion.arm.side} (the hand that sweeps furthest)")
    return motion, arms, notes, warnings


def _import_recording(
    recording: Recording,
    kind: str,
    arm: str,
    user: str | None,
    rows: list[ManifestRow],
    segment: SegmentSettings,
    landing: LandingSettings,
    used_ids: set[str],
    up_given: bool,
    told: Callable[[str, float], None] = lambda stage, share: None,
) -> tuple[FileReport, list[Trajectory]]:
    """The throws of one recording and its report; ``told(stage, share)`` as each throw is labelled
    (``"labelling throw 3 of 600"``, the share of the file's import done: :func:`import_recordings`)."""
    path = Path(recording.source)
    report = FileReport(str(path), kind, notes=list(recording.notes), warnings=list(recording.warnings),
                        assumed_rate=recording.assumed_rate)
    motion, arms, arm_notes, arm_warnings = arm_motion(recording, arm, user)
    report.motion, report.frames_span = motion, recording.frames_span
    report.notes.extend(arm_notes)
    report.warnings.extend(arm_warnings)
    report.arm, report.user = motion.arm.side, motion.arm.user
    # the file's first frame, tracked or not, where the reader knows it (text, CSV): the time a video
    # or a spreadsheet shows; a bag's tf stream starts with the skeleton
    report.clock_origin = origin = float(recording.frames_span[0] if recording.frames_span else motion.time[0])
    report.notes.extend(_tracking_notes(path, motion, origin))
    if motion.torso == "vertical":
        report.notes.append(
            f"{path.name}: no torso points (neck and hip centre): the shoulder's elevation is measured against the vertical"
        )
    cuts, rejections = find_throws(motion, segment)
    facing = _torso_facing(arms, recording.up) if kind not in SENSOR_FRAMES else None
    releases = []
    for cut in cuts:
        toward = _toward_sensor(motion, cut, recording.up) if kind in SENSOR_FRAMES else facing
        releases.append(estimate_release(motion, cut, recording.up, landing, toward))
    kept, more = _throws_at_a_target(motion, cuts, releases, one_per_file=kind == "msr")
    for rejection in sorted([*rejections, *more], key=lambda item: item.time):
        report.reject(rejection, motion.arm.label)
        if rejection.rule == ONE_PER_MSR_FILE:  # a throw by every other rule: more than a note
            report.warnings.append(f"{path}: a throw at t={rejection.time - origin:.2f} s left out: {rejection.reason} "
                                   "(MSR Action3D files hold one performance; to keep it, cut the file at a frame's "
                                   "first line, 20 lines a frame, into one file per throw)")
    hint = _up_hint(motion, recording.up) if kind == "csv" and not up_given else None
    if not kept:
        if cuts and len(more) == len(cuts):  # every extension taken for the arm coming down to rest
            hint = _all_coming_down(motion, recording.up, len(cuts), up_given)
        report.warnings.append(_no_throw(path, motion, report, segment, hint))
    elif hint:
        report.warnings.append(f"{path}: {hint} (up is taken as {_axis_name(recording.up)}; release and landing depend on it)")
    # a throw keeps its number among the file's throws at a target, so that a manifest row for
    # throw 1 never labels throw 2 because the one-throw rule left throw 1 out
    dropped = [r for r in more if r.rule == ONE_PER_MSR_FILE]
    numbers = _numbers(kept, dropped)
    if rows:
        check_throw_numbers(rows, recording.source, len(kept) + len(dropped))
        for row in rows:
            if row.throw is not None and row.matches(path) and row.throw not in numbers and dropped:
                raise InputError(f"{row.where}: throw {row.throw} of {path.name} was left out: {ONE_PER_MSR_FILE} "
                                 f"(the one with the fastest release, throw {numbers[0]}, is kept)")
        peaks = [float(motion.time[cut.peak] - origin) for cut, _ in kept]
        left_out = [(r.time - origin, r.rule) for r in dropped]
        report.warnings.extend(rows_without_a_throw(rows, recording.source, peaks, left_out))
    trajectories = []
    file_rows = rows_of(rows, path)
    # a file the manifest lists throw by throw: a throw no row names is left out, not labelled by
    # the landing estimate beside the manifest's baskets (the file name's basket still labels it)
    listed = bool(file_rows) and not names_every_throw(file_rows) and distance_from_name(path) is None
    outcomes = []
    labelled = READ_SHARE + CUT_SHARE  # the share of the file done before its first throw is labelled
    for index, (number, (cut, release)) in enumerate(zip(numbers, kept, strict=True)):
        told(f"labelling throw {index + 1} of {len(kept)}", labelled + (1.0 - labelled) * index / len(kept))
        start = float(motion.time[cut.start] - origin)
        row = manifest_entry(rows, recording.source, number, float(motion.time[cut.peak] - origin)) if rows else None
        if row is None and listed:
            rise = float(motion.angle[cut.extension_end] - motion.angle[cut.extension_start])
            report.reject(Rejection(release.time, NO_ROW, unnamed_reason(file_rows, path.name), rise),
                          motion.arm.label, noted=False)  # the file's warning names it
            outcomes.append(Outcome(number, start, None))
            continue
        trajectory = _throw(recording, motion, cut, release, number, row, landing, report, used_ids,
                            segment.rest_velocity, user)
        if trajectory is not None:
            trajectories.append(trajectory)
            outcomes.append(Outcome(number, start, trajectory.meta["distance_source"]))
    if file_rows and (warning := listing_warning(path, file_rows, len(kept) + len(dropped), outcomes)):
        report.warnings.append(warning)
    if kept and not trajectories and (rate := _rate_hint(motion, report, [cut for cut, _ in kept])):
        report.warnings.append(f"{path}: no throw kept; {rate}")
    return report, trajectories


def _check_metres(path: Path, track: ArmTrack) -> None:
    """Refuse a recording whose median upper arm is not a person's in metres (:data:`UPPER_ARM_RANGE`):
    coordinates in millimetres or centimetres would give landings hundreds of metres away.

    Raises
    ------
    InputError
        Naming the file, the arm, its median upper arm and the units the coordinates look like.
    """
    lengths = upper_arm_lengths(track)
    length = float(np.nanmedian(lengths)) if np.isfinite(lengths).any() else float("nan")
    low, high = UPPER_ARM_RANGE
    if not np.isfinite(length) or low <= length <= high:
        return
    units = [name for name, size in OTHER_UNITS.items() if low <= length * size <= high]
    if units:
        looks = f"the coordinates look like {units[0]}"
    elif length > high:
        looks = "the coordinates are not in metres"
    else:
        looks = "the shoulder and elbow points nearly coincide, or the coordinates are not in metres"
    raise InputError(
        f"{path}: the median upper arm (shoulder to elbow, {track.label}) measures {length:.3g} in the file's units, where a person's is "
        f"{low:g}-{high:g} m: {looks}; rlff reads metres (convert the coordinates to metres)"
    )


def _tracking_notes(path: Path, motion: ArmMotion, origin: float) -> list[str]:
    """What the angle step left out: glitch samples, stretches without tracking, untracked joints."""
    notes = []
    for name, count in motion.joint_glitches.items():
        if count:
            notes.append(f"{path.name}: {plural(count, 'glitch sample')} of the {name} angle bridged between "
                         f"{'its' if count == 1 else 'their'} neighbours")
    if motion.glitches.size:
        times = ", ".join(f"{t - origin:.2f}" for t in motion.glitches[:5]) + (", ..." if motion.glitches.size > 5 else "")
        notes.append(
            f"{path.name}: {plural(motion.glitches.size, 'glitch sample')} removed "
            f"(one sample leaving two neighbours that agree) at t={times} s"
        )
    spans = motion.lost_spans()
    if spans:
        longest = max(end - begin for begin, end in spans)
        notes.append(
            f"{path.name}: {len(spans)} stretches without tracking (gaps over {motion.lost_gap:.2f} s or joints missing; "
            f"longest {longest:.2f} s) split the recording; no throw is looked for across them"
        )
    lone = [run for run in motion.runs() if run.stop - run.start < 2]
    if lone:
        notes.append(f"{path.name}: {len(lone)} single samples between stretches without tracking are too short to hold a movement")
    return notes


def _toward_sensor(motion: ArmMotion, cut: ThrowCut, up: np.ndarray) -> np.ndarray | None:
    """Horizontal unit vector from the hand (at the extension's peak) to the sensor at the origin."""
    toward = -motion.hand[cut.peak]
    return _horizontal_unit(toward, up)


def _torso_facing(arms: list, up: np.ndarray) -> np.ndarray | None:
    """The thrower's facing direction from both shoulders (up x (right - left)), or None with one arm."""
    sides = {track.side: track for track in arms}
    if "right" not in sides or "left" not in sides:
        return None
    across = np.median(sides["right"].shoulder.position, axis=0) - np.median(sides["left"].shoulder.position, axis=0)
    return _horizontal_unit(np.cross(up, across), up)


def _horizontal_unit(vector: np.ndarray, up: np.ndarray) -> np.ndarray | None:
    up = np.asarray(up, dtype=float) / np.linalg.norm(up)
    horizontal = vector - (vector @ up) * up
    norm = float(np.linalg.norm(horizontal))
    return horizontal / norm if norm > 1e-9 else None


def _no_throw(path: Path, motion: ArmMotion, report: FileReport, segment: SegmentSettings, hint: str | None) -> str:
    """The warning for a file without a throw: which rule stopped its best candidate, and a hint on ``--up``."""
    message = f"{path}: no throw found ({motion.arm.label})"
    if report.rejected:
        best = max(report.rejected, key=lambda item: item.rise)
        message += f"; the best candidate, at t={best.time:.2f} s, was stopped by rule {best.rule!r}: {best.reason}"
    else:
        low, high = np.percentile(motion.angle, [1, 99])
        rises = motion.angle - np.minimum.accumulate(motion.angle)  # above the lowest before
        top = int(np.argmax(rises))
        at_end = top == motion.angle.size - 1 and rises[top] > 0
        message += (
            f"; the elbow angle never rises by {segment.min_candidate:.2f} rad or more (it stays within "
            f"{low:.2f}-{high:.2f} rad; its largest rise is {rises[top]:.2f} rad"
            + (", still rising where the recording ends: it may stop before the throw's extension)" if at_end else ")")
        )
    rate = _rate_hint(motion, report)
    message = f"{message}; {rate}" if rate else message
    return f"{message}; {hint}" if hint else message


def _rate_hint(motion: ArmMotion, report: FileReport, cuts: Sequence[ThrowCut] = ()) -> str | None:
    """For a file without a throw read at an assumed rate: whether the whole recording is shorter
    than a throw (:data:`SHORTEST_THROW`), or its movements (``cuts``, those the throw rules
    passed) are, or its elbow moves faster than a throw's
    (:data:`PLAUSIBLE_PEAK`), as a file read at many times its rate does, whose throws fail other
    rules (a landing behind the shoulder) before the set's rate check sees them."""
    if not report.assumed_rate:
        return None
    asked = f"was it recorded at the {report.assumed_rate:g} Hz it was read at? (--rate)"
    span = float(motion.time[-1] - motion.time[0])
    if span < SHORTEST_THROW:  # the elbow's speed, fitted over a fixed time, flattens there
        return f"the recording lasts {span:.2g} s, shorter than a throw (at least {SHORTEST_THROW:g} s): {asked}"
    if cuts:
        lasts = float(np.median([motion.time[cut.stop - 1] - motion.time[cut.start] for cut in cuts]))
        if lasts < SHORTEST_THROW:
            return (f"its movements last a median {lasts:.2g} s, wind-up to follow-through, shorter than a throw "
                    f"(at least {SHORTEST_THROW:g} s): {asked}")
    fastest = float(np.max(np.abs(motion.velocity)))
    if fastest > PLAUSIBLE_PEAK[1]:
        return f"its elbow reaches {fastest:.3g} rad/s, faster than a throw (at most {PLAUSIBLE_PEAK[1]:g} rad/s): {asked}"
    return None


def _axis_name(vector: np.ndarray) -> str:
    axis = int(np.argmax(np.abs(vector)))
    return ("-" if vector[axis] < 0 else "") + "xyz"[axis]


def _up_hint(motion: ArmMotion, up: np.ndarray) -> str | None:
    """``--up AXIS`` when the recording says its up is another axis than the assumed one.

    With torso points (neck and hip centre, at least ``MIN_TORSO`` apart) the torso decides: the
    hint names the axis that the median hip centre -> neck lies within 45 degrees of, when that is
    not ``up`` (3-D, a unit vector along an axis). Without them the upper arm does, as a
    possibility only, when it hangs along another axis often enough (:data:`HANGING_SHARE`): an
    overhand thrower's arm is raised much of the time, so its median direction tells little.
    """
    torso = _torso_up(motion.arm)
    if torso is not None:
        axis = int(np.argmax(np.abs(torso)))
        if abs(torso[axis]) < np.cos(np.pi / 4) * np.linalg.norm(torso):
            return None  # leaning away from every axis: it names none
        guess = np.zeros(3)
        guess[axis] = np.sign(torso[axis])
        if np.allclose(guess, up):
            return None
        name = _axis_name(guess)
        return f"the torso (hip centre to neck) points along {name}: {name} is up in this file, not {_axis_name(up)}; try --up {name}"
    direction = motion.arm.elbow.position - positions_at(motion.arm.shoulder, motion.arm.elbow.time)
    direction /= np.maximum(np.linalg.norm(direction, axis=1), 1e-12)[:, None]
    hanging = np.cos(np.radians(HANGING_CONE_DEG))
    shares = np.concatenate([np.mean(-direction > hanging, axis=0), np.mean(direction > hanging, axis=0)])
    axes = np.concatenate([np.eye(3), -np.eye(3)])  # up along each axis, the arm hanging against it
    best = int(np.argmax(shares))
    assumed = float(np.mean(direction @ -np.asarray(up, dtype=float) > hanging))
    if np.allclose(axes[best], up) or shares[best] < HANGING_SHARE or shares[best] <= assumed:
        return None
    name = _axis_name(axes[best])
    return (f"the upper arm hangs along {_axis_name(-axes[best])} (within {HANGING_CONE_DEG:g} degrees) in "
            f"{shares[best]:.0%} of the samples, along {_axis_name(-np.asarray(up))} in {assumed:.0%}: {name} may be up "
            f"in this file (a camera frame); if so, try --up {name}")


def _torso_up(arm: ArmTrack) -> np.ndarray | None:
    """The median hip centre -> neck (m, shape (3,)) while both are tracked, or None without a
    torso (no neck or hip, not tracked together, or shorter than ``MIN_TORSO``)."""
    if arm.neck is None or arm.hip is None or len(arm.neck) < 2 or len(arm.hip) < 2:
        return None
    inside = (arm.neck.time >= arm.hip.time[0]) & (arm.neck.time <= arm.hip.time[-1])  # both tracked
    if not inside.any():
        return None
    torso = np.median(arm.neck.position[inside] - positions_at(arm.hip, arm.neck.time[inside]), axis=0)
    return torso if np.linalg.norm(torso) >= MIN_TORSO else None


def _all_coming_down(motion: ArmMotion, up: np.ndarray, extensions: int, up_given: bool) -> str:
    """What to say of a file whose every extension was taken for the arm coming down to rest: a
    wrong up axis makes every throw's release go down (and back), so the up axis is asked about,
    with the axis the recording says is up when it is another (:func:`_up_hint`)."""
    taken = f"--up {_axis_name(up)}" if up_given else "the format's"
    which = {1: "its extension", 2: "both its extensions"}.get(extensions, f"all {extensions} of its extensions")
    said = (f"{which} went down at the release, as the arm "
            f"coming down to rest does, and as every throw does with a wrong up axis: is {_axis_name(up)} up in this "
            f"file? (up was taken as {_axis_name(up)}, {taken})")
    hanging = _up_hint(motion, up)
    return f"{said}; {hanging}" if hanging else said


def _throws_at_a_target(
    motion: ArmMotion,
    cuts: list[ThrowCut],
    releases: list[Release],
    one_per_file: bool,
) -> tuple[list[tuple[ThrowCut, Release]], list[Rejection]]:
    """Leave out extensions whose release is not at a target (the arm coming down to rest).

    With ``one_per_file`` (MSR Action3D: a file holds one performance of the action), keep only
    the throw with the fastest hand at release. Every throw left out comes back as a rejection.
    """
    kept, rejected = [], []
    for cut, release in zip(cuts, releases, strict=True):
        rise = float(motion.angle[cut.extension_end] - motion.angle[cut.extension_start])
        why = not_at_a_target(release)
        if why is None:
            kept.append((cut, release))
        else:
            rejected.append(Rejection(release.time, "direction", why, rise))
    if one_per_file and len(kept) > 1:
        best = max(kept, key=lambda item: np.hypot(item[1].speed_horizontal, item[1].speed_vertical))
        for cut, release in kept:
            if cut is not best[0]:
                rise = float(motion.angle[cut.extension_end] - motion.angle[cut.extension_start])
                rejected.append(Rejection(
                    release.time, ONE_PER_MSR_FILE,
                    "an MSR file holds one throw, the one with the fastest release is kept", rise,
                ))
        kept = [best]
    return kept, rejected


def _numbers(kept: list[tuple[ThrowCut, Release]], dropped: list[Rejection]) -> list[int]:
    """The 1-based number of each kept throw among the file's throws at a target, those the
    one-throw-per-MSR-file rule ``dropped`` (by their release times) included."""
    times = sorted([*(release.time for _, release in kept), *(rejection.time for rejection in dropped)])
    return [times.index(release.time) + 1 for _, release in kept]


def _resampled(time: np.ndarray, series: dict[str, np.ndarray], rates: dict[str, str],
               gap: float) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """An even grid over ``time`` (T,) at its median spacing (at most 1 / OUTPUT_RATE_HZ) and the
    series on it (PCHIP). Where the last stamp falls short of a grid point by at most
    :data:`GRID_END_TOLERANCE` of a spacing, the spacing is shortened to end the grid on it.

    ``rates`` maps a velocity series to the angle series it is the rate of. Inside a spacing of
    ``time`` longer than ``gap`` (s: tracking lost or frozen mid-motion) a velocity is not
    interpolated between the two samples that bound it (their local fits see only one side of
    the gap: the hold before it, the follow-through after it, both slow), but bridged as the
    derivative of its angle's interpolant, so that it integrates to the angle the gap spans.
    """
    step = min(median_spacing(time), 1.0 / OUTPUT_RATE_HZ)
    span = float(time[-1] - time[0])
    steps = int(np.floor(span / step))
    if steps + 1 - span / step <= GRID_END_TOLERANCE:  # the last stamp a hair before a grid point
        steps += 1
        step = span / steps
    grid = time[0] + step * np.arange(steps + 1)
    before = np.clip(np.searchsorted(time, grid, side="right") - 1, 0, len(time) - 2)
    inside = (np.diff(time)[before] > gap) & (grid > time[before] + 1e-9)
    shapes = {name: PchipInterpolator(time, values) for name, values in series.items()}
    resampled = {name: shape(grid) for name, shape in shapes.items()}
    for name, angle in rates.items():
        if inside.any():
            resampled[name][inside] = shapes[angle].derivative()(grid[inside])
    return grid, resampled


def _peak_gap_warning(path: Path, number: int, gap: ExtensionGap, origin: float, spacing: float, peak: float) -> str:
    """The warning of a throw whose extension lost a sample where the elbow extends fastest
    (``origin`` the recording's clock origin, ``spacing`` its mean spacing while tracked, s;
    ``peak`` the written peak speed, rad/s)."""
    lost = round(gap.length / spacing) - 1
    return (
        f"{path}: throw {number}: its extension has a {gap.length:.2f} s gap in {gap.joints} samples at "
        f"t={gap.start - origin:.2f} s, where the elbow extends fastest (they are {spacing:.3g} s apart "
        f"elsewhere: {plural(lost, 'sample')} lost): {gap.rise:.2f} rad of its {gap.extension_rise:.2f} rad "
        f"extension ({gap.bridged_share:.0%}) are bridged from the fits on either side, which see one side "
        f"of the gap only; the elbow moved at least {gap.least_speed:.3g} rad/s across it, and the peak written, "
        f"{peak:.3g} rad/s, is likely too low (peak_confidence low); check the throw before fitting on it")


def _throw(
    recording: Recording,
    motion: ArmMotion,
    cut: ThrowCut,
    release: Release,
    number: int,
    row: ManifestRow | None,
    landing: LandingSettings,
    report: FileReport,
    used_ids: set[str],
    segment_rest: float,
    user: str | None = None,
) -> Trajectory | None:
    """The trajectory of one kept throw, labelled, with its warnings in ``report`` (None when its
    landing stands for no basket); ``row`` is the manifest row that names it, ``segment_rest`` the
    throw finder's rest speed (rad/s), ``user`` the user asked for (``--user``), which its id and
    subject carry (:func:`_subject`)."""
    path = Path(recording.source)
    origin = report.clock_origin
    window = slice(cut.start, cut.stop)
    native = motion.time[window]
    if row is not None and row.height is not None:  # judged where the ball crosses the basket's rim
        landing = replace(landing, target_height=row.height)
    landed = landing_distance(release, landing)
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
        rise = float(motion.angle[cut.extension_end] - motion.angle[cut.extension_start])
        report.reject(
            Rejection(release.time, "landing", "no basket distance and the ball never comes down to "
                      f"{landing.target_height} m from the estimated release", rise),
            motion.arm.label,
        )
        report.warnings.append(
            f"{path}: throw {number} at t={native[0] - origin:.2f} s left out: no basket distance and the ball "
            f"never comes down to {landing.target_height} m from the estimated release"
        )
        return None
    if target is None and not DISTANCE_RANGE[0] <= landed <= DISTANCE_RANGE[1]:  # no basket stands there
        # + 0.0 after rounding: a ball at the feet reads 0.00 m, not -0.00
        behind = ": behind the shoulder" if landed < 0 else ""
        reason = f"no basket distance and the estimated landing ({round(landed, 2) + 0.0:.2f} m{behind}) is "
        if landed < DISTANCE_RANGE[0]:
            reason += f"nearer than any basket ({DISTANCE_RANGE[0]:g} m): the hand came down near the body"
        else:
            reason += f"farther than any basket ({DISTANCE_RANGE[1]:g} m): check --up and that the recording is in metres"
        rise = float(motion.angle[cut.extension_end] - motion.angle[cut.extension_start])
        report.reject(Rejection(release.time, "landing", reason, rise), motion.arm.label)
        report.warnings.append(f"{path}: throw {number} at t={native[0] - origin:.2f} s left out: {reason}")
        return None
    spacing = np.diff(native)
    native_rate = 1.0 / median_spacing(native) if spacing.size else float("nan")
    largest_gap = float(spacing.max()) if spacing.size else 0.0
    resumed = [run.start for run in motion.runs()[1:]]  # where tracking came back after a loss
    if cut.start in resumed and abs(motion.velocity[cut.start]) > segment_rest:
        report.warnings.append(
            f"{path}: throw {number} begins at t={native[0] - origin:.2f} s, where tracking resumed after a "
            f"{native[0] - motion.time[cut.start - 1]:.2f} s gap, with the elbow already moving "
            f"({motion.velocity[cut.start]:.3g} rad/s): what came before is not measured (its wind-up, perhaps part "
            "of its extension and release); check the throw before fitting on it")
    usual = median_spacing(motion.time)
    extension_gap = max(EXTENSION_GAP_FACTOR * usual, EXTENSION_GAP_S)
    longest = longest_gap(motion, cut)
    long_gap = longest if longest is not None and longest.length > extension_gap else None
    at_the_peak = gap_at_the_peak(motion, cut, extension_gap)
    peak_confidence = "low" if long_gap is not None or at_the_peak is not None else "high"
    identifier = _unique_id(f"{path.stem}{'' if user is None else f'_u{user}'}_t{number}", used_ids)
    meta: dict[str, Any] = {
        "subject": _subject(path, row, user),
        "source": str(path),
        "distance_source": source_of_distance,
        "release_time": float(release.time - native[0]),
        "start_time": float(native[0] - origin),
        "end_time": float(native[-1] - origin),
        "arm": motion.arm.side,
        "native_rate_hz": native_rate,
        "largest_gap": largest_gap,
        "release_confidence": release.confidence,
        "peak_confidence": peak_confidence,
    }
    if np.isfinite(landed):
        meta["landing"] = landed
    if target is not None:
        meta["target"] = float(target)
        if np.isfinite(landed):
            meta["hit"] = bool(abs(landed - target) <= landing.hit_radius)
    series = {"angle": motion.angle[window], "velocity": motion.velocity[window]}
    rates = {"velocity": "angle"}
    for name, values in motion.joints.items():
        series[name] = values[window]
        series[velocity_column(name)] = motion.joint_velocities[name][window]
        rates[velocity_column(name)] = name
    if native.size > 1:
        grid, series = _resampled(native, series, rates, extension_gap)
    else:
        grid = native
    peak = float(series["velocity"].max())
    if long_gap is not None:
        report.warnings.append(
            f"{path}: throw {number}: its extension has a {long_gap.length:.2f} s gap in {long_gap.joints} samples at "
            f"t={long_gap.start - origin:.2f} s (they are {usual:.3g} s apart elsewhere: a tracker frozen or lost "
            f"there): its speed across it is bridged from the angles on either side, not measured (peak {peak:.3g} "
            "rad/s); check the throw before fitting on it")
    if at_the_peak is not None:
        report.warnings.append(_peak_gap_warning(path, number, at_the_peak, origin, tracked_spacing(motion), peak))
    report.throws.append(
        ThrowInfo(
            identifier, float(native[0] - origin), float(native[-1] - origin), float(release.time - origin),
            peak, (float(series["angle"].min()), float(series["angle"].max())), float(distance),
            source_of_distance, float(landed) if np.isfinite(landed) else None,
            native_rate, largest_gap, release.confidence, peak_confidence,
        )
    )
    data = {"time": grid - grid[0], **series, "distance": np.full(grid.size, float(distance))}
    for name in ("bearing", "height"):
        value = getattr(row, name) if row is not None else None
        if value is not None:
            data[name] = np.full(grid.size, float(value))
    return Trajectory(identifier, data, meta)
