"""The output layer every command uses: outputs checked before any work, JSON files written atomically.

A command names its inputs and outputs once, first thing::

    guard(inputs={"DATA": data, "--config": config}, outputs={"-o/--output": output, "--report": report})

and :func:`guard` refuses (an :class:`~rlff.errors.InputError`, so one line and exit 2) an
output that is one of the inputs, two outputs that are the same file, an output that is an
existing folder, or one whose folder is a file. The files themselves are written by the library
through :mod:`rlff.fileio`, so that an existing output is only ever replaced by a complete one.
Missing output folders are created.
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

from rlff.fileio import check_output_path, check_outputs, require_distinct, write_text

PathLike = str | Path


def guard(
    inputs: Mapping[str, PathLike | Iterable[PathLike] | None],
    outputs: Mapping[str, PathLike | None],
    *,
    folders: Iterable[str] = (),
) -> None:
    """Refuse outputs that would destroy an input or each other, before anything is read.

    Parameters
    ----------
    inputs : mapping of str to path, paths or None
        The user's name of each input (``"DATA"``, ``"--manifest"``) to its path(s); None when not
        given.
    outputs : mapping of str to path or None
        The same for outputs (``"-o/--output"``, ``"--report"``).
    folders : iterable of str
        Names of the outputs that are folders (a ROS 2 bag, a folder of frames).

    Raises
    ------
    InputError
        Naming the option(s) and the path; also the same file given twice to an input that takes
        several.
    """
    folder_names = set(folders)
    for name, value in inputs.items():
        if value is not None and not isinstance(value, (str, Path)):
            require_distinct(value, f"input ({name})")
    for name, path in outputs.items():
        if path is not None:
            check_output_path(path, folder=name in folder_names)
    check_outputs(inputs, outputs)


def robot_file(robot: str) -> Path | None:
    """The robot file ``--robot`` names (an input no output may replace), or None for a built-in
    robot's name."""
    return Path(robot) if robot.endswith(".toml") or Path(robot).is_file() else None


def write_json(path: PathLike, payload: Any) -> Path:
    """Write ``payload`` as indented JSON to ``path`` atomically (a ``--report`` file)."""
    from rlff.cli._common import jsonable

    return write_text(path, json.dumps(payload, default=jsonable, indent=2) + "\n")


__all__ = ["guard", "robot_file", "write_json"]
