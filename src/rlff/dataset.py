"""Demonstrations as data: trajectories of samples with named numeric columns, and their metadata.

A :class:`Trajectory` is one demonstration: an ordered series of samples with named numeric
columns (for throwing ``angle`` in rad, ``distance`` in m, ``velocity`` in rad/s and optionally
``time`` in s) and per-trajectory metadata (subject, source file, target distance, outcome).
A :class:`Dataset` is an ordered collection of trajectories that share their columns. Context
columns (``distance`` by default, more may be added: basket height, direction) are constant
within a trajectory.

The CSV long format (one row per sample, a ``trajectory`` id column, then the numeric columns,
then metadata columns constant within a trajectory) is read and written here; other formats live
in :mod:`rlff.formats`.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from rlff.errors import InputError

#: Metadata keys with a meaning to rlff; others are kept as given.
META_KEYS = ("subject", "source", "target", "landing", "hit")
#: Column of the CSV long format that holds the trajectory id.
ID_COLUMN = "trajectory"
#: Default column roles of the throwing task.
THROW_INPUTS = ("angle", "distance")
THROW_OUTPUTS = ("velocity",)
THROW_CONTEXT = ("distance",)
#: Columns that are always numeric sample columns when present.
_NUMERIC_NAMES = ("angle", "distance", "velocity", "time")


@dataclass(frozen=True)
class Trajectory:
    """One demonstration.

    Parameters
    ----------
    id : str
        Identifier, unique within a dataset.
    data : mapping of str to array of shape (T,)
        Sample columns, all of the same length T >= 1, finite floats.
    meta : mapping of str to object
        Per-trajectory metadata: ``subject`` (str), ``source`` (str, file it came from),
        ``target`` (float, m: the basket distance aimed at), ``landing`` (float, m: where the
        ball landed, when known), ``hit`` (bool), and anything else.
    """

    id: str
    data: Mapping[str, np.ndarray]
    meta: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        columns = {}
        length = None
        for name, values in self.data.items():
            array = np.asarray(values, dtype=float)
            if array.ndim != 1:
                raise InputError(f"trajectory {self.id!r}: column {name!r} must be 1-D, got shape {array.shape}")
            if not np.all(np.isfinite(array)):
                bad = int(np.flatnonzero(~np.isfinite(array))[0])
                raise InputError(
                    f"trajectory {self.id!r}: column {name!r} has a non-finite value at sample {bad}"
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
        object.__setattr__(self, "meta", dict(self.meta))
        object.__setattr__(self, "id", str(self.id))

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
        names = self.columns if columns is None else tuple(columns)
        return np.column_stack([self[name] for name in names])

    def context_value(self, names: Sequence[str]) -> tuple[float, ...]:
        """Values of the context columns (constant within the trajectory), one per name."""
        return tuple(float(self[name][0]) for name in names)

    def replace(self, **changes: Any) -> Trajectory:
        """A copy with ``id``, ``data`` or ``meta`` replaced."""
        return replace(self, **changes)

    def with_columns(self, **columns: np.ndarray) -> Trajectory:
        """A copy with some columns replaced or added (all columns must keep one length)."""
        data = dict(self.data)
        data.update(columns)
        return replace(self, data=data)

    def take(self, index: np.ndarray | slice) -> Trajectory:
        """A copy holding only the samples selected by ``index`` (a slice, mask or indices)."""
        return replace(self, data={name: values[index] for name, values in self.data.items()})


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
        Duplicate ids, trajectories with different columns, a context column that varies within
        a trajectory, or a ``time`` column that does not increase strictly.
    """

    def __init__(self, trajectories: Iterable[Trajectory], context: Sequence[str] | None = None):
        self._trajectories = tuple(trajectories)
        columns = self._trajectories[0].columns if self._trajectories else ()
        if context is None:
            context = tuple(name for name in THROW_CONTEXT if name in columns)
        self.context = tuple(context)
        self.columns = columns
        self._validate()

    def _validate(self) -> None:
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
        return self._trajectories[index]

    def __repr__(self) -> str:
        return (
            f"Dataset({len(self)} trajectories, {self.n_samples} samples, "
            f"columns={list(self.columns)}, context={list(self.context)})"
        )

    @property
    def trajectories(self) -> tuple[Trajectory, ...]:
        return self._trajectories

    @property
    def n_samples(self) -> int:
        """Total number of samples over all trajectories."""
        return sum(len(t) for t in self._trajectories)

    def replace(self, trajectories: Iterable[Trajectory]) -> Dataset:
        """A dataset with the same context columns holding other trajectories."""
        return Dataset(trajectories, context=self.context)

    def require(self, columns: Iterable[str]) -> None:
        """Raise :class:`InputError` naming the first of ``columns`` the dataset lacks."""
        for name in columns:
            if name not in self.columns:
                raise InputError(f"no column {name!r} in the data (columns: {', '.join(self.columns)})")

    def to_array(self, columns: Sequence[str] | None = None) -> np.ndarray:
        """All samples stacked as an array of shape (N, D), columns in the order given."""
        names = self.columns if columns is None else tuple(columns)
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


def read_csv(path: str | Path, context: Sequence[str] | None = None) -> Dataset:
    """Read a dataset from the CSV long format.

    One row per sample, a header, a ``trajectory`` id column, numeric sample columns and
    optional metadata columns (``subject``, ``source``, ``target``, ``landing``, ``hit`` or any
    non-numeric column) constant within a trajectory. Row order within a trajectory is kept.

    Raises
    ------
    InputError
        The file is missing or malformed, has no ``trajectory`` column, a non-numeric value in a
        sample column, a non-finite value, or metadata that varies within a trajectory.
    """
    import pandas as pd

    path = Path(path)
    if not path.is_file():
        raise InputError(f"{path}: no such file")
    try:
        frame = pd.read_csv(path, dtype={ID_COLUMN: str}, keep_default_na=True)
    except (pd.errors.ParserError, UnicodeDecodeError) as exc:
        raise InputError(f"{path}: malformed CSV ({str(exc).strip().splitlines()[-1]})") from None
    except pd.errors.EmptyDataError:
        raise InputError(f"{path}: empty file") from None
    if ID_COLUMN not in frame.columns:
        raise InputError(f"{path}: no {ID_COLUMN!r} column (columns: {', '.join(map(str, frame.columns))})")
    if frame.empty:
        raise InputError(f"{path}: no samples")
    if frame[ID_COLUMN].isna().any():
        line = int(np.flatnonzero(frame[ID_COLUMN].isna().to_numpy())[0]) + 2
        raise InputError(f"{path}, line {line}: empty trajectory id")
    numeric_share = {
        c: pd.to_numeric(frame[c], errors="coerce").notna().mean() for c in frame.columns
    }
    # Metadata: the known keys, plus any column with no numeric value at all (a free-text note).
    # A column with some numbers and some text is a sample column with a bad cell: an error below.
    meta_columns = [
        c for c in frame.columns
        if c != ID_COLUMN and (c in META_KEYS or (numeric_share[c] == 0 and c not in _NUMERIC_NAMES))
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
                f"{path}, line {row + 2}: column {name!r} has a non-numeric or non-finite value "
                f"{column.iloc[row]!r}"
            )
        frame[name] = numeric.astype(float)
    trajectories = []
    for trajectory_id, group in frame.groupby(ID_COLUMN, sort=False):
        meta = {}
        for name in meta_columns:
            values = group[name]
            if values.nunique(dropna=False) > 1:
                raise InputError(
                    f"{path}: metadata column {name!r} varies within trajectory {trajectory_id!r}"
                )
            value = _meta_value(values.iloc[0])
            if value is not None:
                meta[name] = value
        data = {name: group[name].to_numpy(dtype=float) for name in sample_columns}
        try:
            trajectories.append(Trajectory(trajectory_id, data, meta))
        except InputError as exc:
            raise InputError(f"{path}: {exc}") from None
    try:
        return Dataset(trajectories, context=context)
    except InputError as exc:
        raise InputError(f"{path}: {exc}") from None


def write_csv(dataset: Dataset, path: str | Path) -> None:
    """Write a dataset in the CSV long format; :func:`read_csv` gives it back exactly.

    Floats are written with ``repr`` precision (17 significant digits) so the round trip is exact.
    """
    import pandas as pd

    path = Path(path)
    meta_keys: list[str] = []
    for trajectory in dataset:
        for key in trajectory.meta:
            if key not in meta_keys:
                meta_keys.append(key)
    parts = []
    for trajectory in dataset:
        part = {ID_COLUMN: np.full(len(trajectory), trajectory.id, dtype=object)}
        part.update({name: trajectory[name] for name in dataset.columns})
        for key in meta_keys:
            part[key] = [trajectory.meta.get(key)] * len(trajectory)
        parts.append(pd.DataFrame(part))
    columns = [ID_COLUMN, *dataset.columns, *meta_keys]
    frame = pd.concat(parts, ignore_index=True) if parts else pd.DataFrame(columns=columns)
    path.parent.mkdir(parents=True, exist_ok=True)
    frame.to_csv(path, index=False, float_format="%.17g", columns=columns)
