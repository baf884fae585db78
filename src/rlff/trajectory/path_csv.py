"""Reading a generated path: the model's CSV of (angle, velocity[, time]) for one throw.

The model writes ``angle`` (rad), ``velocity`` (rad/s), ``time`` (s) and further columns (pdf,
exploration, gmr_mean); of a whole-arm model also the other joints' positions and velocities
(``shoulder``, ``shoulder_velocity``, ``wrist``, ``wrist_velocity``) and the basket's context
(``distance``, ``bearing``, ``height``). These are read; the rest does not matter here. A
``trajectory`` column, if present, must hold a single id: one file is one throw.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from rlff.errors import InputError
from rlff.fileio import require_file
from rlff.wording import bad_cell

#: The further joint columns of a whole-arm path (rad, rad/s) and its context columns.
JOINT_COLUMNS = ("shoulder", "shoulder_velocity", "wrist", "wrist_velocity")
CONTEXT_COLUMNS = ("distance", "bearing", "height")


@dataclass(frozen=True)
class GeneratedPath:
    """A human joint path: ``angle`` (rad), ``velocity`` (rad/s), ``time`` (s) or None, each (T,).

    ``joints`` holds the further joint columns the file has (:data:`JOINT_COLUMNS`, each (T,));
    ``context`` the basket's context values it was generated for (distance m, bearing deg,
    height m), where the file has them.
    """

    angle: np.ndarray
    velocity: np.ndarray
    time: np.ndarray | None
    joints: dict[str, np.ndarray] = field(default_factory=dict)
    context: dict[str, float] = field(default_factory=dict)

    def to_path(self) -> dict[str, np.ndarray]:
        """The columns as a :data:`rlff.robot.mapping.HumanPath`."""
        path = {"angle": self.angle, "velocity": self.velocity, **self.joints}
        if self.time is not None:
            path["time"] = self.time
        return path


def _renaming_hint(missing: list[str], columns) -> str:
    """For columns ``missing`` that the file has in other case or with spaces about them (a
    spreadsheet's ``ANGLE``, `` angle``): what to rename, as the end of the missing-columns
    message; "" where it has none of them so."""
    found = {str(column).strip().lower(): str(column) for column in columns}
    renames = [f"{found[name]!r} to {name!r}" for name in missing if name in found]
    if not renames:
        return ""
    return (f"; rlff reads the names as rlff generate writes them, lower case without spaces: rename "
            f"{', '.join(renames)}")


def read_generated_path(path: str | Path) -> GeneratedPath:
    """Read a generated trajectory CSV; :class:`InputError` naming the file and column at fault."""
    path = require_file(path)
    try:
        table = pd.read_csv(path)
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise InputError(f"{path}: not a readable CSV ({exc})") from None
    missing = [column for column in ("angle", "velocity") if column not in table]
    if missing:
        raise InputError(f"{path}: missing columns {missing} (has {', '.join(map(str, table.columns))})"
                         f"{_renaming_hint(missing, table.columns)}")
    if "trajectory" in table and table["trajectory"].nunique() > 1:
        raise InputError(f"{path}: holds {table['trajectory'].nunique()} trajectories; give one throw per file")
    columns = {}
    for column in ("angle", "velocity", "time", *JOINT_COLUMNS, *CONTEXT_COLUMNS):
        if column not in table:
            continue
        values = pd.to_numeric(table[column], errors="coerce").to_numpy(float)
        bad = np.flatnonzero(~np.isfinite(values))
        if bad.size:
            raise InputError(f"{path}: column {column!r} row {int(bad[0]) + 1} has {bad_cell(table[column].iloc[bad[0]])}")
        columns[column] = values
    if columns["angle"].size < 2:
        raise InputError(f"{path}: needs at least 2 rows, has {columns['angle'].size}")
    context = {}
    for column in CONTEXT_COLUMNS:
        if column in columns:
            values = columns.pop(column)
            if np.ptp(values) > 0:
                raise InputError(f"{path}: column {column!r} changes along the throw "
                                 f"({values.min():g} to {values.max():g}); one file is one throw")
            context[column] = float(values[0])
    joints = {column: columns[column] for column in JOINT_COLUMNS if column in columns}
    return GeneratedPath(columns["angle"], columns["velocity"], columns.get("time"), joints, context)
