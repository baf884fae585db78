"""Reading a generated path: the model's CSV of (angle, velocity[, time]) for one throw.

The model writes ``angle`` (rad), ``velocity`` (rad/s), ``time`` (s) and further columns (pdf,
exploration, gmr_mean); only the first three matter here. A ``trajectory`` column, if present,
must hold a single id: one file is one throw.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from rlff.errors import InputError


@dataclass(frozen=True)
class GeneratedPath:
    """A human joint path: ``angle`` (rad), ``velocity`` (rad/s), ``time`` (s) or None, each (T,)."""

    angle: np.ndarray
    velocity: np.ndarray
    time: np.ndarray | None


def read_generated_path(path: str | Path) -> GeneratedPath:
    """Read a generated trajectory CSV; :class:`InputError` naming the file and column at fault."""
    path = Path(path)
    if path.is_dir():
        raise InputError(f"{path}: is a folder, not a trajectory CSV file")
    try:
        table = pd.read_csv(path)
    except FileNotFoundError:
        raise InputError(f"{path}: no such file") from None
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise InputError(f"{path}: not a readable CSV ({exc})") from None
    missing = [column for column in ("angle", "velocity") if column not in table]
    if missing:
        raise InputError(f"{path}: missing columns {missing} (has {', '.join(map(str, table.columns))})")
    if "trajectory" in table and table["trajectory"].nunique() > 1:
        raise InputError(f"{path}: holds {table['trajectory'].nunique()} trajectories; give one throw per file")
    columns = {}
    for column in ("angle", "velocity", "time"):
        if column not in table:
            continue
        values = pd.to_numeric(table[column], errors="coerce").to_numpy(float)
        bad = np.flatnonzero(~np.isfinite(values))
        if bad.size:
            raise InputError(f"{path}: column {column!r} row {int(bad[0]) + 1} is "
                             f"{table[column].iloc[bad[0]]!r}, not a finite number")
        columns[column] = values
    if columns["angle"].size < 2:
        raise InputError(f"{path}: needs at least 2 rows, has {columns['angle'].size}")
    return GeneratedPath(columns["angle"], columns["velocity"], columns.get("time"))
