"""Demonstrations as data: trajectories of samples with named numeric columns, and their metadata.

A :class:`Trajectory` is one demonstration: an ordered series of samples with named numeric
columns (for throwing ``angle`` in rad, ``distance`` in m, ``velocity`` in rad/s and optionally
``time`` in s) and per-trajectory metadata (subject, source file, target distance, outcome).
A :class:`Dataset` is an ordered collection of trajectories that share their columns. Context
columns (``distance``, ``bearing``, ``height``: those present) are constant within a trajectory.

Whole-arm throws carry further joints beside the elbow's ``angle`` (the phase variable) and its
``velocity``: ``shoulder`` (rad, the upper arm's elevation against the torso's downward axis: 0
hanging, pi/2 horizontal, pi straight up) and ``wrist`` (rad, the included angle between forearm
and hand, about pi straight), each with its rate ``shoulder_velocity`` / ``wrist_velocity``
(rad/s). A dataset may carry any subset of them, but a joint's position never without its
velocity. The basket's ``bearing`` (deg, 0 straight ahead, positive to the left) and ``height``
(m, its rim above the floor; absent: the default basket, rim 0.3 m) are context columns.

The CSV long format (one row per sample, a ``trajectory`` id column, then the numeric columns,
then metadata columns constant within a trajectory) is read and written here; other formats live
in :mod:`rlff.formats`. :func:`merge_datasets` joins datasets (import batches) into one.
"""

from __future__ import annotations

import hashlib
import math
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from rlff.csvlines import data_row_line, data_row_lines, header_separator
from rlff.errors import InputError
from rlff.fileio import require_file
from rlff.kinds import binary_kind
from rlff.limits import DISTANCE_RANGE, MAX_MAGNITUDE, as_names, centimetres_hint, require_radians
from rlff.wording import bad_cell, plural

#: What to do about a time that does not increase within a trajectory: rows out of order (a file
#: sorted by another column, rows pasted in the wrong place).
TIME_ORDER_HINT = "the rows of each trajectory must be in time order: sort them by trajectory and time"
#: What to do about a throw given twice under its id in one file: two datasets joined (appended,
#: pasted) that both hold it, which no sorting mends.
TWICE_HINT = ("two datasets joined with a throw in both? keep one copy (`rlff data merge A.csv B.csv -o all.csv` joins "
              "datasets, keeping a throw both hold once)")
#: Metadata keys with a meaning to rlff (read as metadata even when numeric); others are kept
#: as given. ``release_angle`` (rad) and ``release_time`` (s) locate the ball's release when known
#: (simulated throws), ``glitches`` counts the tracking glitches a simulated throw holds,
#: ``cut_angle`` (rad) is where preprocessing cut a throw at its release; ``start_time`` and
#: ``end_time`` (s) place an imported throw in its recording; ``measured_share`` is the share of
#: a trajectory's samples that stand for a measurement (densifying interpolates the rest);
#: ``distance_source``, ``arm``, ``release_confidence`` and ``peak_confidence`` are set by capture.
META_KEYS = (
    "subject", "source", "target", "landing", "hit", "release_angle", "release_time", "glitches",
    "cut_angle", "start_time", "end_time", "measured_share", "native_rate_hz", "largest_gap",
    "distance_source", "arm", "release_confidence", "peak_confidence",
)
#: Metadata keys whose values are text: the CSV reader keeps their cells as written, never as a
#: number, a bool or a missing value (subject ``007`` stays ``"007"``, ``nan`` stays ``"nan"``),
#: as the trajectory ids. Only an empty cell is no value.
TEXT_META_KEYS = ("subject", "source", "distance_source", "arm", "release_confidence", "peak_confidence")
#: Column of the CSV long format that holds the trajectory id.
ID_COLUMN = "trajectory"
#: Default column roles of the throwing task.
THROW_INPUTS = ("angle", "distance")
THROW_OUTPUTS = ("velocity",)
#: Context columns of the throwing task, in this order; a dataset uses those it has.
THROW_CONTEXT = ("distance", "bearing", "height")
#: The elbow's angle is the phase variable; these joints of a whole-arm throw ride beside it.
ARM_JOINT_COLUMNS = ("shoulder", "wrist")
#: Every joint position column, the phase first.
JOINT_COLUMNS = ("angle", *ARM_JOINT_COLUMNS)
#: Fewest samples of a trajectory read from a file: a single sample is no motion (a cut gone wrong).
MIN_FILE_SAMPLES = 2
#: Units of the throwing task's columns; every stage keeps them (no step converts units).
UNITS = {
    "angle": "rad", "velocity": "rad/s",
    "shoulder": "rad", "shoulder_velocity": "rad/s",
    "wrist": "rad", "wrist_velocity": "rad/s",
    "distance": "m", "bearing": "deg", "height": "m",
    "time": "s",
}
#: Columns that are always numeric sample columns when present.
_NUMERIC_NAMES = tuple(UNITS)
#: Ranges of the basket's context columns a simulation or a label may give: its bearing (deg)
#: and its rim's height (m, below a standing person's hand at release).
BEARING_RANGE = (-180.0, 180.0)
HEIGHT_RANGE = (0.0, 1.5)
#: The context a dataset without ``bearing`` or ``height`` stands for: straight ahead (deg), the
#: default basket's rim (m).
DEFAULT_CONTEXT = {"bearing": 0.0, "height": 0.3}


def velocity_column(name: str) -> str:
    """The velocity column of joint position column ``name``: ``"angle"`` -> ``"velocity"``,
    ``"shoulder"`` -> ``"shoulder_velocity"``."""
    return "velocity" if name == "angle" else f"{name}_velocity"


def joint_outputs(human_columns: Sequence[str]) -> tuple[str, ...]:
    """The model outputs of a throw driving ``human_columns`` (``"angle"`` first): the elbow's
    velocity, then every other joint's position and velocity, e.g. ``("velocity", "shoulder",
    "shoulder_velocity")``. The other joints' positions are outputs because the phase is the
    elbow's angle, not theirs."""
    return ("velocity", *(c for column in human_columns[1:] for c in (column, velocity_column(column))))


def joint_columns(columns: Iterable[str]) -> tuple[str, ...]:
    """The joint position columns among ``columns``, in the order of :data:`JOINT_COLUMNS`."""
    present = set(columns)
    return tuple(name for name in JOINT_COLUMNS if name in present)


def _check_joint_velocities(columns: Sequence[str]) -> None:
    """Raise :class:`InputError` when an arm joint's position column comes without its velocity."""
    for name in ARM_JOINT_COLUMNS:
        if name in columns and velocity_column(name) not in columns:
            raise InputError(
                f"column {name!r} needs its velocity column {velocity_column(name)!r} "
                f"(columns: {', '.join(columns)})"
            )


def owned(array: np.ndarray, given: Any) -> np.ndarray:
    """``array``, the float conversion of ``given``, as one the library may freeze: a copy when
    it may be the caller's own writeable array (numpy converts a float64 array, or a view of
    one, to itself), so that making the trajectory's column read-only leaves theirs writeable.

    A list or tuple always converts to a new array, and a read-only array is already frozen:
    neither is copied (the library's own columns, passed from trajectory to trajectory, stay
    shared).
    """
    if array.flags.writeable and not isinstance(given, list | tuple):
        return array.copy()
    return array


#: Numpy dtype kinds that are no numbers, in words: numpy turns booleans into 0 and 1, and text
#: such as "2" into 2.0, without a word.
_NOT_NUMBERS = {"b": "booleans", "U": "text", "S": "bytes", "O": "Python objects", "c": "complex numbers",
                "M": "dates", "m": "time spans", "V": "records"}


def as_floats(values: Any, what: str) -> np.ndarray:
    """``values`` as a float array (itself when it is one), or an :class:`InputError` saying that
    ``what`` (``"column 'angle'"``) must hold numbers: integers and floats pass, booleans, text and
    objects do not."""
    array = np.asarray(values)
    if array.dtype.kind in _NOT_NUMBERS:
        raise InputError(f"{what} must hold numbers, not {_NOT_NUMBERS[array.dtype.kind]}")
    return array.astype(float, copy=False)


@dataclass(frozen=True)
class Trajectory:
    """One demonstration.

    Parameters
    ----------
    id : str
        Identifier, unique within a dataset.
    data : mapping of str to array of shape (T,)
        Sample columns, all of the same length T >= 1, finite numbers (integers or floats, kept
        as floats; booleans, text and objects are refused).
    meta : mapping of str to object
        Per-trajectory metadata: ``subject`` (str), ``source`` (str, file it came from),
        ``target`` (float, m: the basket distance aimed at), ``landing`` (float, m: where the
        ball landed, when known), ``hit`` (bool; numpy's, 0/1 and yes/no read as bools by
        :func:`meta_with_hit`), and anything else.
    """

    id: str
    data: Mapping[str, np.ndarray]
    meta: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if not isinstance(self.data, Mapping):
            raise InputError(f"trajectory {self.id!r}: data must be a mapping of column names to arrays of shape (T,), "
                             f"e.g. {{'angle': [...], 'velocity': [...]}}, got {type(self.data).__name__}")
        columns = {}
        length = None
        for name, values in self.data.items():
            array = owned(as_floats(values, f"trajectory {self.id!r}: column {name!r}"), values)
            if array.ndim != 1:
                raise InputError(f"trajectory {self.id!r}: column {name!r} must be 1-D, got shape {array.shape}")
            usable = np.abs(array) <= MAX_MAGNITUDE  # finite and small enough to square and sum
            if not usable.all():
                bad = int(np.flatnonzero(~usable)[0])
                raise InputError(
                    f"trajectory {self.id!r}: column {name!r} has {_unusable(array[bad])} at sample {bad}"
                )
            if length is None:
                length = array.size
            elif array.size != length:
                raise InputError(
                    f"trajectory {self.id!r}: column {name!r} has {array.size} samples, expected {length}"
                )
            array.setflags(write=False)
            columns[name] = array
        if not columns:
            raise InputError(f"trajectory {self.id!r} has no columns")
        if length == 0:
            raise InputError(f"trajectory {self.id!r} has no samples")
        object.__setattr__(self, "data", columns)
        object.__setattr__(self, "meta", meta_with_hit(self.id, self.meta))
        object.__setattr__(self, "id", str(self.id))

    @classmethod
    def _trusted(cls, id: str, data: dict[str, np.ndarray], meta: dict[str, Any]) -> Trajectory:
        """Build without validation from columns already checked in bulk (read-only float arrays).

        Loading a million samples one trajectory at a time spends its time validating small
        arrays; :meth:`Dataset.from_columns` validates them all at once and comes here.
        """
        trajectory = object.__new__(cls)
        object.__setattr__(trajectory, "id", id)
        object.__setattr__(trajectory, "data", data)
        object.__setattr__(trajectory, "meta", meta)
        return trajectory

    def __len__(self) -> int:
        return next(iter(self.data.values())).size

    @property
    def columns(self) -> tuple[str, ...]:
        """Names of the sample columns, in order."""
        return tuple(self.data)

    def __getitem__(self, column: str) -> np.ndarray:
        try:
            return self.data[column]
        except KeyError:
            raise InputError(
                f"trajectory {self.id!r} has no column {column!r} (columns: {', '.join(self.data)})"
            ) from None

    def to_array(self, columns: Sequence[str] | None = None) -> np.ndarray:
        """Samples as an array of shape (T, D), columns in the order given (default: all)."""
        names = self.columns if columns is None else as_names(columns)
        return np.column_stack([self[name] for name in names])

    def context_value(self, names: Sequence[str]) -> tuple[float, ...]:
        """Values of the context columns (constant within the trajectory), one per name."""
        return tuple(float(self[name][0]) for name in names)

    def replace(self, **changes: Any) -> Trajectory:
        """A copy with ``id``, ``data`` or ``meta`` replaced."""
        return replace(self, **changes)

    def samples_digest(self, columns: Iterable[str] | None = None) -> bytes:
        """SHA-256 of the samples: the name and values of every column (or of ``columns``), bit
        for bit, in name order (not the id or the metadata). Equal digests: the same samples."""
        digest = hashlib.sha256(str(len(self)).encode())
        for name in sorted(self.columns if columns is None else columns):
            digest.update(name.encode() + b"\0")
            digest.update(np.ascontiguousarray(self[name]).tobytes())
        return digest.digest()

    def with_columns(self, **columns: np.ndarray) -> Trajectory:
        """A copy with some columns replaced or added (all columns must keep one length)."""
        data = dict(self.data)
        data.update(columns)
        return replace(self, data=data)

    def take(self, index: np.ndarray | slice) -> Trajectory:
        """A copy holding only the samples selected by ``index`` (a slice, mask or indices).

        Samples of a valid trajectory stay valid, so only the length is checked (the cleaning
        steps call this for every trajectory).
        """
        data = {}
        for name, values in self.data.items():
            selected = np.atleast_1d(values[index])
            selected.setflags(write=False)
            data[name] = selected
        if not next(iter(data.values())).size:
            raise InputError(f"trajectory {self.id!r}: no samples selected")
        return Trajectory._trusted(self.id, data, dict(self.meta))


class Dataset(Sequence[Trajectory]):
    """An ordered collection of trajectories that share their sample columns.

    Parameters
    ----------
    trajectories : iterable of Trajectory
        May be empty (a pipeline that rejects everything returns an empty dataset).
    context : sequence of str
        Context columns: constant within each trajectory (default ``("distance",)`` when the
        trajectories have a ``distance`` column, else none).

    Raises
    ------
    InputError
        Something other than a :class:`Trajectory` among the trajectories (a dict, a frame's
        column names), duplicate ids, trajectories with different columns, a context column that
        varies within a trajectory, a ``time`` column that does not increase strictly, or a
        ``shoulder`` or ``wrist`` column without its velocity column.
    """

    def __init__(self, trajectories: Iterable[Trajectory], context: Sequence[str] | None = None):
        self._trajectories = tuple(trajectories)
        _require_trajectories(self._trajectories)
        columns = self._trajectories[0].columns if self._trajectories else ()
        if context is None:
            context = tuple(name for name in THROW_CONTEXT if name in columns)
        self.context = as_names(context)
        self.columns = columns
        self._validate()

    @classmethod
    def from_columns(
        cls,
        columns: Mapping[str, np.ndarray],
        ids: Sequence[str],
        lengths: Sequence[int] | np.ndarray,
        meta: Sequence[Mapping[str, Any]] | None = None,
        context: Sequence[str] | None = None,
    ) -> Dataset:
        """Build a dataset from whole columns, validated in bulk (fast for large sets).

        Parameters
        ----------
        columns : mapping of str to array of shape (N,)
            Sample columns of all trajectories, one after the other.
        ids : sequence of str, length S
            Trajectory ids, in the order their samples appear.
        lengths : sequence of int, length S
            Number of samples of each trajectory (each >= 1, summing to N).
        meta : sequence of mappings, length S, optional
            Per-trajectory metadata.
        context : sequence of str, optional
            Context columns, as in :class:`Dataset`.

        Raises
        ------
        InputError
            As :class:`Trajectory` and :class:`Dataset` would for the same data.
        """
        ids = [str(i) for i in ids]
        lengths = np.asarray(lengths, dtype=np.int64).reshape(-1)
        metas = [dict(m) for m in meta] if meta is not None else [{} for _ in ids]
        if not (len(ids) == lengths.size == len(metas)):
            raise InputError(f"{len(ids)} ids, {lengths.size} lengths and {len(metas)} metadata records")
        metas = [meta_with_hit(trajectory_id, m) for trajectory_id, m in zip(ids, metas, strict=True)]
        if lengths.size and lengths.min() < 1:
            raise InputError(f"trajectory {ids[int(np.argmin(lengths))]!r} has no samples")
        if len(set(ids)) != len(ids):
            unique, counts = np.unique(ids, return_counts=True)
            raise InputError(f"duplicate trajectory id {str(unique[np.argmax(counts > 1)])!r}")
        starts = np.concatenate([[0], np.cumsum(lengths)[:-1]]).astype(np.int64)
        total = int(lengths.sum())
        owner = np.repeat(np.arange(lengths.size), lengths)
        arrays: dict[str, np.ndarray] = {}
        for name, values in columns.items():
            array = owned(np.ascontiguousarray(as_floats(values, f"column {name!r}")), values)
            if array.shape != (total,):
                raise InputError(f"column {name!r} has shape {array.shape}, expected ({total},)")
            usable = np.abs(array) <= MAX_MAGNITUDE
            if not usable.all():
                row = int(np.flatnonzero(~usable)[0])
                raise InputError(
                    f"trajectory {ids[owner[row]]!r}: column {name!r} has {_unusable(array[row])} at "
                    f"sample {row - starts[owner[row]]}"
                )
            array.setflags(write=False)
            arrays[name] = array
        if not arrays and ids:
            raise InputError(f"trajectory {ids[0]!r} has no columns")
        _check_joint_velocities(tuple(arrays))
        context = tuple(name for name in THROW_CONTEXT if name in arrays) if context is None else as_names(context)
        if lengths.size:
            for name in context:
                if name not in arrays:  # as the first trajectory would say it (Trajectory.__getitem__)
                    raise InputError(f"trajectory {ids[0]!r} has no column {name!r} (columns: {', '.join(arrays)})")
                values = arrays[name]
                spread = np.maximum.reduceat(values, starts) - np.minimum.reduceat(values, starts)
                scale = np.maximum(1.0, np.maximum.reduceat(np.abs(values), starts))
                bad = np.flatnonzero(spread > 1e-9 * scale)
                if bad.size:
                    raise InputError(f"trajectory {ids[bad[0]]!r}: context column {name!r} is not constant")
            if "time" in arrays and total > 1:
                steps = np.diff(arrays["time"])
                inside = np.ones(total - 1, dtype=bool)
                inside[starts[1:] - 1] = False  # a step across two trajectories is not a step
                bad = np.flatnonzero(inside & (steps <= 0))
                if bad.size:
                    row = int(bad[0]) + 1
                    first = int(starts[owner[row]])
                    # its first sample again: the throw given twice (two tables joined, their rows gathered)
                    again = all(array[row] == array[first] for array in arrays.values())
                    raise InputError(
                        f"trajectory {ids[owner[row]]!r}: " + (
                            f"its throw starts again at sample {row - first}: {TWICE_HINT}" if again else
                            f"time does not increase at sample {row - first}; {TIME_ORDER_HINT}")
                    )
        trajectories = [
            Trajectory._trusted(
                trajectory_id,
                {name: array[start : start + length] for name, array in arrays.items()},
                trajectory_meta,
            )
            for trajectory_id, start, length, trajectory_meta in zip(
                ids, starts.tolist(), lengths.tolist(), metas, strict=True
            )
        ]
        dataset = cls.__new__(cls)
        dataset._trajectories = tuple(trajectories)
        dataset.context = tuple(context)
        dataset.columns = tuple(arrays)
        return dataset

    def _validate(self) -> None:
        _check_joint_velocities(self.columns)
        seen: set[str] = set()
        for trajectory in self._trajectories:
            if trajectory.id in seen:
                raise InputError(f"duplicate trajectory id {trajectory.id!r}")
            seen.add(trajectory.id)
            if set(trajectory.columns) != set(self.columns):
                raise InputError(
                    f"trajectory {trajectory.id!r} has columns {list(trajectory.columns)}, "
                    f"expected {list(self.columns)}"
                )
            for name in self.context:
                values = trajectory[name]
                if np.ptp(values) > 1e-9 * max(1.0, float(np.max(np.abs(values)))):
                    raise InputError(
                        f"trajectory {trajectory.id!r}: context column {name!r} is not constant"
                    )
            if "time" in trajectory.columns and len(trajectory) > 1:
                steps = np.diff(trajectory["time"])
                if np.any(steps <= 0):
                    bad = int(np.flatnonzero(steps <= 0)[0]) + 1
                    raise InputError(
                        f"trajectory {trajectory.id!r}: time does not increase at sample {bad}"
                    )

    # -- sequence protocol -------------------------------------------------------------------
    def __len__(self) -> int:
        return len(self._trajectories)

    def __iter__(self) -> Iterator[Trajectory]:
        return iter(self._trajectories)

    def __getitem__(self, index):  # type: ignore[override]
        if isinstance(index, slice):
            return Dataset(self._trajectories[index], context=self.context)
        if isinstance(index, str):
            for trajectory in self._trajectories:
                if trajectory.id == index:
                    return trajectory
            raise KeyError(index)
        try:
            return self._trajectories[index]
        except IndexError:  # Python's "tuple index out of range" named neither the index nor the length
            count = len(self._trajectories)
            held = {0: "no trajectories", 1: "1 trajectory (index 0, or -1)"}.get(
                count, f"{count} trajectories (0 to {count - 1}, or -{count} to -1)")
            raise IndexError(f"trajectory index {index} out of range: the dataset has {held}") from None

    def __repr__(self) -> str:
        return (
            f"Dataset({len(self)} trajectories, {self.n_samples} samples, "
            f"columns={list(self.columns)}, context={list(self.context)})"
        )

    @property
    def trajectories(self) -> tuple[Trajectory, ...]:
        return self._trajectories

    @property
    def ids(self) -> tuple[str, ...]:
        """Trajectory ids, in order."""
        return tuple(t.id for t in self._trajectories)

    @property
    def contexts(self) -> tuple[tuple[float, ...], ...]:
        """The distinct context values, sorted ascending."""
        return tuple(self.by_context())

    @property
    def n_samples(self) -> int:
        """Total number of samples over all trajectories."""
        return sum(len(t) for t in self._trajectories)

    def equals(self, other: Dataset) -> bool:
        """True when ``other`` holds the same trajectories (ids, columns, values, metadata) in
        the same order with the same context columns; values compared exactly."""
        if self.context != other.context or set(self.columns) != set(other.columns):
            return False
        if self.ids != other.ids:
            return False
        return all(
            mine.meta == theirs.meta
            and all(np.array_equal(mine[name], theirs[name]) for name in self.columns)
            for mine, theirs in zip(self._trajectories, other._trajectories, strict=True)
        )

    def duplicates(self) -> list[tuple[str, ...]]:
        """Groups of ids whose trajectories hold the same motion: the same values in every column
        but the context columns, bit for bit (ids, metadata and the context, the basket a throw is
        labelled with, may differ), each group in dataset order, the groups in the order of their
        first trajectory. A throw given twice (a recording imported under two names, one of them
        naming a basket; a file appended to itself) counts twice in a fit, as if it were new
        evidence.
        """
        groups: dict[bytes, list[str]] = {}
        for trajectory in self._trajectories:
            motion = [name for name in trajectory.columns if name not in self.context]
            groups.setdefault(trajectory.samples_digest(motion), []).append(trajectory.id)
        return [tuple(ids) for ids in groups.values() if len(ids) > 1]

    def replace(self, trajectories: Iterable[Trajectory]) -> Dataset:
        """A dataset with the same context columns holding other trajectories.

        When none are left, the result keeps this dataset's column names, so that the steps after
        a step that rejected everything still find their columns.
        """
        dataset = Dataset(trajectories, context=self.context)
        if not len(dataset):
            dataset.columns = self.columns
        return dataset

    def require(self, columns: Iterable[str]) -> None:
        """Raise :class:`InputError` naming the first of ``columns`` the dataset lacks."""
        for name in columns:
            if name not in self.columns:
                metadata = any(name in trajectory.meta for trajectory in self.trajectories)
                what = (f"column {name!r} is metadata (one value per trajectory), not a sample column" if metadata
                        else f"no column {name!r} in the data")
                raise InputError(f"{what} (columns: {', '.join(self.columns)})")

    def to_array(self, columns: Sequence[str] | None = None) -> np.ndarray:
        """All samples stacked as an array of shape (N, D), columns in the order given."""
        names = self.columns if columns is None else as_names(columns)
        self.require(names)
        if not self._trajectories:
            return np.empty((0, len(names)))
        return np.concatenate([t.to_array(names) for t in self._trajectories])

    def by_context(self) -> dict[tuple[float, ...], list[Trajectory]]:
        """Trajectories grouped by their context value, contexts sorted ascending."""
        groups: dict[tuple[float, ...], list[Trajectory]] = {}
        for trajectory in self._trajectories:
            groups.setdefault(trajectory.context_value(self.context), []).append(trajectory)
        return dict(sorted(groups.items()))


def _require_trajectories(given: Sequence[Any]) -> None:
    """:class:`InputError` at the first of ``given`` that is no :class:`Trajectory`, saying what
    it is and how a dataset is made (a dict had failed with an AttributeError on ``columns``)."""
    for position, item in enumerate(given):
        if isinstance(item, Trajectory):
            continue
        what = f"{type(item).__name__} {item!r}" if isinstance(item, str | int | float) else type(item).__name__
        made = ("make each with Trajectory(id, {column: values}, meta)" if isinstance(item, Mapping) else
                "a Dataset holds Trajectory(id, {column: values}, meta) objects")
        raise InputError(f"Dataset takes Trajectory objects, got {what} at position {position}: {made}, or give "
                         "the columns of every trajectory at once to Dataset.from_columns (a CSV: "
                         "rlff.formats.read_dataset)")


#: How far (a factor either way) the elbow's speed integrated over the time column may read, in
#: the median throw, from the way its angle travels (the sum of its steps' sizes, back and forth):
#: 0.99 on the real MSR throws as imported (10-90 % of them 0.93-1.04), 1.01 cleaned, 0.89 for the
#: simulated camera and 0.59 for its noisiest (noise and glitches 0.3: the noise's zig-zag adds
#: way that a velocity by central differences halves); a velocity in deg/s reads 50-60. Against
#: the net change a recording's throw, wound up and followed through back near its start angle,
#: had read 3.9 from a change of a few hundredths of a radian.
VELOCITY_AGREEMENT = 3.0
#: The fastest a person's joint turns at the peak of a throw (rad/s), in the median over the
#: throws: elbows peak at about 5-20 (docs/data.md; 12.7 on the real MSR throws, 12.8 for the
#: simulated people), a pitcher's at about 40. In deg/s the same throws peak at 300-1100.
HUMAN_SPEED = 60.0


def check_units(dataset: Dataset, named: Callable[[str], str] = lambda column: f"column {column!r}") -> None:
    """:class:`InputError` when ``dataset``'s basket distances (``distance``) are not metres, its
    joint angles (:data:`JOINT_COLUMNS`) not radians or their velocities not rad/s: a distance
    outside :data:`rlff.limits.DISTANCE_RANGE` (a model fitted to 75-275 cm could be asked for
    none of its baskets and extrapolated at 1.5 m), an angle beyond two turns
    (:func:`rlff.limits.require_radians`), a ``velocity`` that is not the rate of change of the
    ``angle`` (its magnitude's integral over the ``time`` column in the median throw more than
    :data:`VELOCITY_AGREEMENT` times the way the angle travels, or less than its inverse), or,
    where no ``time`` column or position tells (:func:`velocities_by_peak`, said by
    :func:`peak_only_note`), a velocity column that peaks faster than a person's joint turns
    (:data:`HUMAN_SPEED`, in the median over the throws). A recording's tracking glitches may
    peak beyond a person's speed; with a ``time`` column they integrate to the position's change
    all the same, so uncleaned recordings pass.
    ``named(column)`` words a column in the message (``"column 'distance'"``).

    In deg/s, the velocities had been fitted, cleaned and generated from without a word (a
    generated throw of 3 ms peaking at 688 "rad/s"), and had sent every throw of the learning
    loop to the speed limit.

    :meth:`rlff.preprocess.Pipeline.run` checks the dataset it cleans so, the command line every
    file of demonstrations it reads, :func:`rlff.learn.demos.require_units` the demonstrations
    it learns from, and :meth:`rlff.model.Model.fit` the distances and angles it fits
    (:func:`check_column_units`) and their velocities (:func:`check_velocity_units`).
    """
    if not len(dataset):
        return
    checked = [name for name in ("distance", *JOINT_COLUMNS) if name in dataset.columns]
    check_column_units({name: dataset.to_array([name])[:, 0] for name in checked}, named)
    check_velocity_units(dataset, dataset.columns, named)


def check_velocity_units(
    throws: Iterable[Mapping[str, np.ndarray]],
    columns: Sequence[str],
    named: Callable[[str], str] = lambda column: f"column {column!r}",
) -> None:
    """The velocities' part of :func:`check_units`: :class:`InputError` when a velocity column
    among ``columns`` is not rad/s, over ``throws`` (a :class:`Dataset`, or one mapping of column
    to array (n,) a throw, holding ``columns``). :meth:`rlff.model.Model.fit` checks the velocities
    it fits so (until 2026-12-07 it fitted deg/s given from Python without a word)."""
    peaked = velocities_by_peak(columns)
    if "velocity" in columns and "velocity" not in peaked:
        _check_velocity_in_time(throws, named)
    for column in peaked:
        _check_human_speed(throws, column, named)


def velocities_by_peak(columns: Sequence[str]) -> tuple[str, ...]:
    """The velocity columns among ``columns`` that :func:`check_units` checks by their peak
    alone: all but the elbow's ``velocity`` with a ``time`` and an ``angle`` column, which it
    integrates over the time. (The other joints move less in a throw: their way is a few tenths
    of a radian, and a real recording's shoulder, cleaned, read 5.2 times it.)"""
    timed = {"velocity"} if {"time", "angle"} <= set(columns) else set()
    return tuple(column for column in columns if column.endswith("velocity") and column not in timed)


def peak_only_note(columns: Sequence[str]) -> str | None:
    """What :func:`check_units` could not check in a dataset of ``columns``, in words: the
    velocities it checks by their peak alone (:func:`velocities_by_peak`), which a velocity in
    deg/s that a slow throw keeps below :data:`HUMAN_SPEED` passes; None when there are none."""
    peaked = velocities_by_peak(columns)
    if not peaked:
        return None
    why = ("no time column" if "time" not in columns else "no angle column" if "angle" not in columns
           else "the elbow's velocity alone is integrated over the time")
    return (f"{why}: {', '.join(f'column {column!r}' for column in peaked)} checked against a person's fastest joint ({HUMAN_SPEED:g} "
            "rad/s) only, not against the rate at which the position changes")


def _check_human_speed(dataset: Iterable[Mapping[str, np.ndarray]], column: str, named: Callable[[str], str]) -> None:
    """See :func:`check_units`: the velocity ``column``'s median peak within :data:`HUMAN_SPEED`."""
    peak = float(np.median([np.max(np.abs(trajectory[column])) for trajectory in dataset]))
    if peak > HUMAN_SPEED:
        raise InputError(f"{named(column)} peaks at {peak:.4g} in the median throw, faster than a person's joint "
                         f"turns (up to {HUMAN_SPEED:g} rad/s; elbows peak at about 5-20): degrees per second? "
                         "velocity is in rad/s")


def _check_velocity_in_time(dataset: Iterable[Mapping[str, np.ndarray]], named: Callable[[str], str]) -> None:
    """See :func:`check_units`: the ``velocity``'s size over ``time`` against the way the ``angle`` travels."""
    ratios = []
    for trajectory in dataset:
        way = float(np.sum(np.abs(np.diff(trajectory["angle"]))))
        if way > 1e-3:
            ratios.append(float(np.trapezoid(np.abs(trajectory["velocity"]), trajectory["time"])) / way)
    if not ratios:
        return
    ratio = float(np.median(ratios))
    if not 1.0 / VELOCITY_AGREEMENT <= ratio <= VELOCITY_AGREEMENT:
        hint = (" (degrees per second? velocity is in rad/s)" if 40.0 < ratio < 80.0
                else " (time in milliseconds? it is in seconds)" if 300.0 < ratio < 3000.0 else "")
        raise InputError(f"{named('velocity')} integrates over the throws' time column to a median {ratio:.3g} "
                         "times their angle's change (along the throw, back and forth): it should be the angle's "
                         f"rate of change, rad/s with the angle in rad and the time in s{hint}")


def check_column_units(
    columns: Mapping[str, np.ndarray],
    named: Callable[[str], str] = lambda column: f"column {column!r}",
    *,
    landings: bool = False,
) -> None:
    """:func:`check_units` of named columns, each an array of shape (N,); columns other than
    ``distance`` and :data:`JOINT_COLUMNS` are not checked.

    ``landings``: the distances may be where throws came down, not baskets (a learning method's
    training set labels a throw with its landing), so a distance nearer than any basket but above
    0 m is taken; beyond the farthest one it is refused all the same (centimetres)."""
    values = np.asarray(columns.get("distance", ()), dtype=float)
    if values.size:
        low, high = float(values.min()), float(values.max())
        too_near = low <= 0.0 if landings else low < DISTANCE_RANGE[0]
        if too_near or high > DISTANCE_RANGE[1]:
            raise InputError(f"{named('distance')} holds {low:g} to {high:g}, outside the basket distances "
                             f"{DISTANCE_RANGE[0]:g} to {DISTANCE_RANGE[1]:g} m{centimetres_hint(high, nearest=low)}")
    for column in joint_columns(columns):
        require_radians(columns[column], named(column))


def copies_warning(dataset: Dataset) -> str | None:
    """A warning naming the first of the throws whose samples another throw repeats
    (:meth:`Dataset.duplicates`) and what they do to a fit; None when there are none."""
    groups = dataset.duplicates()
    if not groups:
        return None
    copies = sum(len(ids) - 1 for ids in groups)
    aside = f", {', '.join(dataset.context)} aside" if dataset.context else ""
    return (
        f"{plural(copies, 'throw')} {'repeats' if copies == 1 else 'repeat'} another sample for sample{aside} (the "
        f"first: {' and '.join(groups[0])}): every copy counts in the fit and in BIC as a new throw "
        "(BIC then favours a larger K); keep one of each"
    )


# -- joining datasets --------------------------------------------------------------------------
#
# A lab imports its recordings in batches, a session at a time, and wants them as one dataset to
# clean and fit. Appending the files by hand gives a throw two batches share (one recording
# imported twice) twice under one id, which every reader then refuses. merge_datasets joins
# datasets in the order given and keeps such a throw once when both copies are the same (every
# sample bit for bit, every metadata value they both have); two different throws under one id are
# refused, naming what differs, since which to keep is the user's call.


@dataclass(frozen=True)
class Merged:
    """The result of :func:`merge_datasets`.

    Attributes
    ----------
    dataset : Dataset
        Every trajectory of the inputs, in their order, a throw held by several inputs once (where
        it first came).
    kept_once : list of (str, str, str)
        ``(id, first input, later input)`` for each throw a later input held again.
    """

    dataset: Dataset
    kept_once: list[tuple[str, str, str]]


def merge_datasets(named: Sequence[tuple[str, Dataset]]) -> Merged:
    """Join datasets into one, a throw two of them hold identically kept once.

    Identical: every sample bit for bit, and every metadata key both copies have with one value;
    a key only one copy has (imports by two versions of rlff, the later writing a key more) is
    kept on the throw.

    Parameters
    ----------
    named : sequence of (str, Dataset)
        Each dataset with the name it is called by in messages (its file), in the order to join.

    Returns
    -------
    Merged

    Raises
    ------
    InputError
        No datasets; two with different sample columns or context columns (naming what one has
        and the other lacks); an id held by two with different samples or metadata (naming the
        column or the metadata key that differs).
    """
    if not named:
        raise InputError("no datasets to merge")
    first_name, first = named[0]
    trajectories: dict[str, tuple[str, Trajectory]] = {}
    kept_once: list[tuple[str, str, str]] = []
    for name, dataset in named:
        _require_same_columns(first_name, first, name, dataset)
        for trajectory in dataset:
            earlier = trajectories.get(trajectory.id)
            if earlier is None:
                trajectories[trajectory.id] = (name, trajectory)
                continue
            difference = _difference(earlier[1], trajectory)
            if difference is not None:
                raise InputError(
                    f"trajectory {trajectory.id!r} is in {earlier[0]} and in {name} with {difference}: two throws "
                    "under one id (or one throw imported with other settings); rename one, or drop one of them from "
                    "its file"
                )
            # a metadata key one copy lacks (a key a later rlff writes) is the other's; the keys both have agree
            trajectories[trajectory.id] = (earlier[0], earlier[1].replace(meta={**earlier[1].meta, **trajectory.meta}))
            kept_once.append((trajectory.id, earlier[0], name))
    return Merged(first.replace(trajectory for _, trajectory in trajectories.values()), kept_once)


def _require_same_columns(first_name: str, first: Dataset, name: str, dataset: Dataset) -> None:
    """:class:`InputError` when ``dataset`` has other sample or context columns than ``first``."""
    if set(dataset.columns) != set(first.columns):
        only_first = [column for column in first.columns if column not in dataset.columns]
        only_this = [column for column in dataset.columns if column not in first.columns]
        lacks = []
        if only_first:
            lacks.append(f"{name} lacks {', '.join(only_first)}")
        if only_this:
            lacks.append(f"{first_name} lacks {', '.join(only_this)}")
        raise InputError(
            f"{name} and {first_name} have different columns ({'; '.join(lacks)}): datasets merge only with the same "
            "columns (import every batch with the same --joints)"
        )
    if tuple(dataset.context) != tuple(first.context):
        raise InputError(
            f"{name} has the context columns {', '.join(dataset.context) or 'none'}, {first_name} "
            f"{', '.join(first.context) or 'none'}: datasets merge only with the same context"
        )


def _difference(first: Trajectory, other: Trajectory) -> str | None:
    """How two trajectories under one id differ, in words (``"column 'distance' 2.75 against 2.5"``),
    or None when every sample is the same and so is the value of every metadata key both have."""
    if len(first) != len(other):
        return f"{len(first)} samples against {len(other)}"
    for column in first.columns:
        mine, theirs = first[column], other[column]
        if not np.array_equal(mine, theirs):
            at = int(np.flatnonzero(mine != theirs)[0])
            return f"column {column!r} {float(mine[at])!r} against {float(theirs[at])!r} at sample {at}"
    for key in first.meta.keys() & other.meta.keys():
        if first.meta[key] != other.meta[key]:
            return f"metadata {key!r} {first.meta[key]!r} against {other.meta[key]!r}"
    return None


def _unusable(value: float) -> str:
    """How a value that fails the ``|x| <= MAX_MAGNITUDE`` check is described."""
    if not np.isfinite(value):
        return "a non-finite value"
    return f"the value {value:g}, beyond the ±{MAX_MAGNITUDE:g} data values may reach"


# -- CSV long format -------------------------------------------------------------------------


def _meta_value(value: Any) -> Any:
    """A CSV cell as metadata: bools and numbers parsed, empty cells dropped (None)."""
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return None
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        return float(value)
    text = str(value)
    if text.lower() in ("true", "false"):
        return text.lower() == "true"
    return text


#: How a capture's ``hit`` column may say whether the ball went in (case-insensitive).
HIT_WORDS = {"true": True, "yes": True, "y": True, "1": True, "hit": True,
             "false": False, "no": False, "n": False, "0": False, "miss": False}


def parse_hit(value: Any) -> bool | None:
    """A ``hit`` metadata value as a bool (None: empty), from a bool, 0/1 or one of
    :data:`HIT_WORDS`: what the CSV and Parquet readers store as ``hit``.

    Raises
    ------
    ValueError
        Anything else: a learning method that reads ``hit`` must not take a typo for "unknown".
    """
    value = _meta_value(value)
    if value is None or isinstance(value, bool):
        return value
    if isinstance(value, float) and value.is_integer():
        value = int(value)
    word = str(value).strip().lower()
    if word not in HIT_WORDS:
        raise ValueError(f"{value!r} (use true/false, yes/no, 1/0 or hit/miss)")
    return HIT_WORDS[word]


def meta_with_hit(trajectory_id: Any, meta: Mapping[str, Any]) -> dict[str, Any]:
    """A trajectory's metadata as a dict, its ``hit`` (when there is one) a bool or None as
    :func:`parse_hit` reads it: numpy's and pandas' False, 0 and 1, "no" or "False" are the bools
    they spell, so that demonstrations learn alike from memory, CSV, Parquet and NPZ (where a 0
    stays 0). Before, only the CSV and Parquet readers read them, and a method that asks whether
    every demonstration missed (``hit is False``) took an NPZ's 0 for "not recorded".

    Raises
    ------
    InputError
        A ``hit`` that spells no outcome, naming the trajectory and what is taken.
    """
    meta = dict(meta)
    if "hit" in meta:
        try:
            meta["hit"] = parse_hit(meta["hit"])
        except ValueError as exc:
            raise InputError(f"trajectory {str(trajectory_id)!r}: metadata hit {exc}") from None
    return meta


#: The cells pandas reads as missing by default (its documented ``na_values`` list): what the CSV
#: reader still takes for a missing value in every column but the id and :data:`TEXT_META_KEYS`.
_PANDAS_NA = ("", "#N/A", "#N/A N/A", "#NA", "-1.#IND", "-1.#QNAN", "-NaN", "-nan", "1.#IND", "1.#QNAN",
              "<NA>", "N/A", "NA", "NULL", "NaN", "None", "n/a", "nan", "null")


def read_csv(path: str | Path, context: Sequence[str] | None = None) -> Dataset:
    """Read a dataset from the CSV long format.

    One row per sample, a header, a ``trajectory`` id column, numeric sample columns and
    optional metadata columns (those of :data:`META_KEYS` or any non-numeric column) constant
    within a trajectory. Row order within a trajectory is kept. Ids and the text keys
    (:data:`TEXT_META_KEYS`: ``subject``, ``source``, ...) are kept as written (``007`` stays
    ``"007"``; only an empty cell is no value); ``hit`` reads as a bool from true/false, yes/no, 1/0
    or hit/miss (:data:`HIT_WORDS`); other metadata cells read as numbers, bools (true/false) or
    text, as they look.

    Raises
    ------
    InputError
        The file is missing or malformed, has no ``trajectory`` column, a non-numeric value in a
        sample column, a non-finite value, metadata that varies within a trajectory, a
        trajectory of a single sample, a ``time`` column that does not increase, or a ``hit``
        that is none of :data:`HIT_WORDS`.
    """
    import pandas as pd

    path = require_file(path)
    if (kind := binary_kind(path)) is not None:
        raise InputError(f"{path} is {kind}")
    try:
        # ids and text metadata are read as written: only an empty cell is missing there (pandas
        # would read "nan", "NA" or "None" as missing, and "007" or "1e3" as a number elsewhere)
        header = pd.read_csv(path, nrows=0).columns
        text = [name for name in header if name == ID_COLUMN or name in TEXT_META_KEYS]
        frame = pd.read_csv(
            path, dtype=dict.fromkeys(text, str), keep_default_na=False,
            na_values={name: [""] if name in text else _PANDAS_NA for name in header},
        )
    except pd.errors.ParserError as exc:
        raise InputError(f"{path}: malformed CSV ({str(exc).strip().splitlines()[-1]})") from None
    except UnicodeDecodeError as exc:
        raise InputError(f"{path}: malformed CSV ({exc}): rlff reads UTF-8 text; save the file as UTF-8") from None
    except pd.errors.EmptyDataError:
        raise InputError(f"{path}: empty file") from None
    if not isinstance(frame.index, pd.RangeIndex):  # pandas made the first fields the row labels
        raise InputError(f"{path}: the rows have more fields than the header's {len(frame.columns)} columns"
                         + separator_hint(path))
    if ID_COLUMN not in frame.columns:
        raise InputError(f"{path}: no {ID_COLUMN!r} column (columns: {', '.join(map(str, frame.columns))})"
                         + separator_hint(path))
    if frame.empty:
        raise InputError(f"{path}: no samples")
    if frame[ID_COLUMN].isna().any():
        line = data_row_line(path, int(np.flatnonzero(frame[ID_COLUMN].isna().to_numpy())[0]))
        raise InputError(f"{path}, line {line}: empty trajectory id")
    # Metadata: the known keys, plus any column with no numeric value at all (a free-text note).
    # A column with some numbers and some text is a sample column with a bad cell: an error below.
    meta_columns = [
        c for c in frame.columns
        if c != ID_COLUMN and (c in META_KEYS or (c not in _NUMERIC_NAMES and _holds_no_number(frame[c])))
    ]
    sample_columns = [c for c in frame.columns if c != ID_COLUMN and c not in meta_columns]
    if not sample_columns:
        raise InputError(f"{path}: no numeric sample columns")
    for name in sample_columns:
        column = frame[name]
        numeric = pd.to_numeric(column, errors="coerce")
        bad = numeric.isna() | ~np.isfinite(numeric.to_numpy(dtype=float, na_value=np.nan))
        if bad.any():
            row = int(np.flatnonzero(bad.to_numpy())[0])
            raise InputError(
                f"{path}, line {data_row_line(path, row)}: column {name!r} has {bad_cell(column.iloc[row])}"
            )
        frame[name] = numeric.astype(float)
    ids, rows, lengths = _trajectory_rows(frame[ID_COLUMN])
    starts = np.concatenate([[0], np.cumsum(lengths)[:-1]]).astype(np.int64)
    samples = {name: frame[name].to_numpy(dtype=float)[rows] for name in sample_columns}
    meta = {name: _MetaColumn.read(name, frame[name], rows, starts) for name in meta_columns}
    # every check a trajectory may fail, screened column-wise; the few trajectories the screen
    # flags are checked one by one, in file order, so that the first fault is the one named
    for index in np.flatnonzero(_suspects(rows, starts, lengths, samples, meta.values())).tolist():
        span = slice(starts[index], starts[index] + lengths[index])
        fault = _trajectory_fault(path, ids[index], rows[span], {name: samples[name][span] for name in samples},
                                  {name: column.of(index) for name, column in meta.items()})
        if fault is not None:
            raise InputError(fault)
    metas = [{} for _ in ids]
    for name, column in meta.items():
        for trajectory_meta, value in zip(metas, column.values, strict=True):
            if value is not None:
                trajectory_meta[name] = value
    try:  # a dataset-wide fault: a context column that varies or is missing, a joint without its velocity
        return Dataset.from_columns(samples, ids, lengths, metas, context=context)
    except InputError as exc:
        raise InputError(f"{path}: {exc}") from None


def _holds_no_number(column: Any) -> bool:
    """Whether no cell of a CSV column (a pandas Series) reads as a number: a free-text note, or
    only empty cells. A column pandas read as numbers (or bools) holds one unless all are empty."""
    import pandas as pd

    if pd.api.types.is_numeric_dtype(column.dtype):
        return not column.notna().any()
    return not pd.to_numeric(column, errors="coerce").notna().any()


def _trajectory_rows(ids: Any) -> tuple[list[str], np.ndarray, np.ndarray]:
    """The trajectories of a CSV's data rows, in the order their ids first appear.

    Parameters
    ----------
    ids : pandas Series of str, length N
        The ``trajectory`` column (no empty cell).

    Returns
    -------
    ids : list of str, length S
    rows : array of int, shape (N,)
        The data rows (0-based, header excluded) grouped by trajectory, in file order within each.
    lengths : array of int, shape (S,)
        Rows of each trajectory.
    """
    import pandas as pd

    codes, uniques = pd.factorize(ids)
    return [str(value) for value in uniques], np.argsort(codes, kind="stable"), np.bincount(codes, minlength=len(uniques))


@dataclass(frozen=True)
class _MetaColumn:
    """One metadata column of a CSV, per trajectory.

    ``values`` (length S) holds each trajectory's value as read from its first row (None: no
    value, or a ``hit`` that spells no outcome), ``varies`` (bool, shape (S,)) whether its rows
    hold more than one value (an empty cell counts as one), and ``hit_faults`` why a trajectory's
    ``hit`` spells no outcome, by trajectory index.
    """

    values: list[Any]
    varies: np.ndarray
    hit_faults: dict[int, str]

    @classmethod
    def read(cls, name: str, column: Any, rows: np.ndarray, starts: np.ndarray) -> _MetaColumn:
        """Read column ``name`` (a pandas Series of N cells) for the trajectories whose rows
        ``rows`` (N,) are grouped from ``starts`` (S,) on."""
        import pandas as pd

        codes = pd.factorize(column)[0][rows]  # an empty cell -1: a value of its own
        varies = np.minimum.reduceat(codes, starts) != np.maximum.reduceat(codes, starts)
        values: list[Any] = []
        hit_faults: dict[int, str] = {}
        for index, cell in enumerate(column.to_numpy()[rows[starts]].tolist()):
            if name == "hit":
                try:
                    values.append(parse_hit(cell))
                except ValueError as exc:
                    values.append(None)
                    hit_faults[index] = str(exc)
            elif name in TEXT_META_KEYS:
                values.append(None if pd.isna(cell) else str(cell))
            else:
                values.append(_meta_value(cell))
        return cls(values, varies, hit_faults)

    def of(self, index: int) -> tuple[Any, bool, str | None]:
        """Trajectory ``index``'s value, whether it varies, and why its ``hit`` is no outcome."""
        return self.values[index], bool(self.varies[index]), self.hit_faults.get(index)


def _suspects(rows: np.ndarray, starts: np.ndarray, lengths: np.ndarray, samples: Mapping[str, np.ndarray],
              meta: Iterable[_MetaColumn]) -> np.ndarray:
    """Which trajectories may fail a check of :func:`_trajectory_fault`, shape (S,) bool: the
    others pass every one. Flagged: rows scattered among other ids', a time that does not
    increase (or no time column: a throw given twice is then told by its samples), a single
    sample, a value beyond ``MAX_MAGNITUDE``, metadata that varies or a ``hit`` that is no outcome."""
    ends = starts + lengths - 1
    flagged = (lengths < MIN_FILE_SAMPLES) | (rows[ends] - rows[starts] != lengths - 1)
    if "time" not in samples:
        flagged[:] = True
    else:
        step_back = np.zeros(rows.size, dtype=bool)
        step_back[1:] = np.diff(samples["time"]) <= 0
        step_back[starts] = False  # a step across two trajectories is not a step
        flagged |= np.logical_or.reduceat(step_back, starts)
    for values in samples.values():
        flagged |= np.logical_or.reduceat(~(np.abs(values) <= MAX_MAGNITUDE), starts)
    for column in meta:
        flagged |= column.varies
        flagged[list(column.hit_faults)] = True
    return flagged


def _trajectory_fault(path: Path, trajectory_id: str, rows: np.ndarray, data: Mapping[str, np.ndarray],
                      meta: Mapping[str, tuple[Any, bool, str | None]]) -> str | None:
    """Why one trajectory of a CSV is refused, as the error's text, or None.

    Parameters
    ----------
    path : Path
    trajectory_id : str
    rows : array of int, shape (T,)
        Its data rows (0-based, header excluded), in file order.
    data : mapping of str to array of shape (T,)
        Its sample columns.
    meta : mapping of str to (value, varies, hit fault)
        Its metadata columns, as :meth:`_MetaColumn.of` gives them.
    """
    # before the metadata: the two copies of a throw may differ there (its source's path)
    fault = _given_twice(path, trajectory_id, rows, data)
    if fault is not None:
        return fault
    values = {}
    for name, (value, varies, hit_fault) in meta.items():
        if varies:
            return f"{path}: metadata column {name!r} varies within trajectory {trajectory_id!r}"
        if hit_fault is not None:
            return f"{path}, line {data_row_line(path, int(rows[0]))}: trajectory {trajectory_id!r} has hit {hit_fault}"
        if value is not None:
            values[name] = value
    if rows.size < MIN_FILE_SAMPLES:
        return (f"{path}, line {data_row_line(path, int(rows[0]))}: trajectory {trajectory_id!r} has a single "
                "sample (a demonstration needs at least 2)")
    if "time" in data and np.any(np.diff(data["time"]) <= 0):
        row = int(rows[int(np.flatnonzero(np.diff(data["time"]) <= 0)[0]) + 1])
        return (f"{path}, line {data_row_line(path, row)}: time does not increase within trajectory {trajectory_id!r}"
                f"; {TIME_ORDER_HINT}")
    try:
        Trajectory(trajectory_id, data, values)
    except InputError as exc:
        return f"{path}: {exc}"
    return None


def _given_twice(path: Path, trajectory_id: str, rows: np.ndarray, data: Mapping[str, np.ndarray]) -> str | None:
    """Why the rows of one trajectory id in a CSV hold a throw given twice (two datasets joined),
    as the error's text, or None.

    Parameters
    ----------
    path : Path
        The CSV file, for the lines named.
    trajectory_id : str
    rows : array of int, shape (T,)
        The id's data rows (0-based, header excluded), in file order.
    data : mapping of str to array of shape (T,)
        Its sample columns, in the same order.

    Two datasets appended give the throw again after itself, its time starting again (the two
    copies one block of rows when the throw ends one file and starts the other); sorted by
    trajectory and time after, each sample comes twice in a row. Sorting, which a time that does
    not increase asks for, mends neither. Rows scattered among other ids' (another tool's export)
    are no fault, nor is a single row out of place.
    """
    starts = np.flatnonzero(np.diff(rows) > 1) + 1  # where the id's rows resume after other ids'
    if not starts.size and "time" in data and np.all(np.diff(data["time"]) > 0):
        return None  # the usual trajectory: one block of rows in time order
    samples = np.column_stack(list(data.values()))
    again = _start_again(data, samples, starts)
    if again is not None:
        lines = _row_lines(path, rows)
        copies = np.split(np.arange(rows.size), np.union1d(starts, [again]))
        spans = [f"{lines[copy[0]]}-{lines[copy[-1]]}" for copy in copies[:3]]
        more = f" and {len(copies) - 3} more" if len(copies) > 3 else ""
        shown = (" and ".join(spans) if len(spans) == 2 else ", ".join(spans)) + more
        times = "twice" if len(copies) == 2 else f"{len(copies)} times"
        return f"{path}: trajectory {trajectory_id!r} appears {times} (lines {shown}): {TWICE_HINT}"
    if "time" not in data:
        return None
    repeats = np.flatnonzero(np.diff(data["time"]) == 0) + 1
    same = (samples[repeats] == samples[repeats - 1]).all(axis=1)
    if not repeats.size or not same[0]:
        return None
    first = int(repeats[0])
    lines = _row_lines(path, rows)
    where = f"{path}, lines {lines[first - 1]} and {lines[first]}: trajectory {trajectory_id!r} holds the same sample twice"
    if same.all() and 2 * repeats.size == rows.size:
        return f"{where} (time {data['time'][first]:g} s), as it does each of its samples: {TWICE_HINT}"
    return f"{where} (time {data['time'][first]:g} s): a row given twice? delete one"


def _start_again(data: Mapping[str, np.ndarray], samples: np.ndarray, starts: np.ndarray) -> int | None:
    """Where a trajectory's throw starts again (the index of the row), or None.

    ``samples`` (T, D) are its rows, ``starts`` the index of each block of rows but the first
    (rows of other ids between). Starting again: a block of two rows or more whose time goes back
    below where the block above ended, or, without a time column, that repeats an earlier block
    sample for sample; within one block, the throw's first sample again where its time goes back
    (without a time column: the second half the first, sample for sample). A time that stays (a
    sample given twice in a row) is :func:`_given_twice`'s other case.
    """
    lengths = np.diff(np.append(starts, len(samples)))
    if "time" in data:
        time = data["time"]
        back = starts[(time[starts] < time[starts - 1]) & (lengths >= MIN_FILE_SAMPLES)]
        if back.size:
            return int(back[0])
        steps = np.flatnonzero(np.diff(time) < 0) + 1
        if steps.size and np.array_equal(samples[steps[0]], samples[0]):
            return int(steps[0])
        return None
    seen: set[bytes] = set()
    for start, block in zip(np.append(0, starts), np.split(samples, starts), strict=True):
        if len(block) >= MIN_FILE_SAMPLES:
            digest = hashlib.sha256(np.ascontiguousarray(block).tobytes()).digest()
            if digest in seen:
                return int(start)
            seen.add(digest)
    half = len(samples) // 2
    if len(samples) % 2 == 0 and half >= MIN_FILE_SAMPLES and np.array_equal(samples[:half], samples[half:]):
        return half
    return None


def _row_lines(path: Path, rows: np.ndarray) -> list[int]:
    """The 1-based file line of each data row in ``rows`` (0-based, header excluded)."""
    lines = data_row_lines(path)
    return [lines[row] if row < len(lines) else row + 2 for row in rows.tolist()]


def separator_hint(path: Path) -> str:
    """Why a file has no ``trajectory`` column, or rows longer than its header, when its header is
    separated by ``;`` or tabs (a spreadsheet's export, its decimal commas splitting the rows'
    numbers), said with what to do; "" for a comma-separated header."""
    separator = header_separator(path)
    if separator == ",":
        return ""
    shown = "tabs" if separator == "\t" else repr(separator)
    return (f"; the file looks separated by {shown} and rlff reads commas: save it comma-separated, with points as "
            "decimal marks")


def write_csv(dataset: Dataset, path: str | Path) -> None:
    """Write a dataset in the CSV long format; :func:`read_csv` gives back its samples, ids and
    metadata exactly.

    A CSV cell holds no type: ids and the values of :data:`TEXT_META_KEYS` come back as the text
    written, other metadata as what its text looks like, so a text value that looks like a number
    or a bool under a key of one's own (``{"session": "007"}``) comes back as one (a column of
    numbers under a key not in :data:`META_KEYS`, as a sample column); Parquet and NPZ keep every
    value's type.

    Floats are written as the shortest decimal that reads back to the same double, through
    pyarrow's CSV writer (:mod:`rlff.csvtable`), and atomically: an existing file is only ever
    replaced by a complete one.
    """
    from rlff.csvtable import per_group_text, write_csv_columns

    meta_keys: list[str] = []
    for trajectory in dataset:
        for key in trajectory.meta:
            if key not in meta_keys:
                meta_keys.append(key)
    lengths = [len(trajectory) for trajectory in dataset]
    columns: dict[str, Any] = {ID_COLUMN: per_group_text(dataset.ids, lengths)}
    for name in dataset.columns:
        columns[name] = np.concatenate([t[name] for t in dataset]) if lengths else np.empty(0)
    for key in meta_keys:
        columns[key] = per_group_text([t.meta.get(key) for t in dataset], lengths)
    write_csv_columns(path, columns)
