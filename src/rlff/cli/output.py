"""The output layer every command uses: outputs checked before any work, JSON files written atomically.

A command names its inputs and outputs once, first thing::

    guard(inputs={"DATA": data, "--config": config}, outputs={"-o/--output": output, "--report": report})

and :func:`guard` refuses (an :class:`~rlff.errors.InputError`, so one line and exit 2) an
output that is one of the inputs, two outputs that are the same file, an output file named as a
folder (an existing folder, or, given to an :func:`output_option`, a path ending in ``/``),
or one whose folder is a file. The files themselves are written by the library through
:mod:`rlff.fileio`, so that an existing output is only ever replaced by a complete one. Missing
output folders are created.
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import typer

try:  # typer >= 0.20 carries its own copy of click; before, it used the click package
    from typer._click.globals import get_current_context
except ImportError:  # pragma: no cover - older typer
    from click import get_current_context

from rlff.errors import InputError
from rlff.fileio import check_output_path, check_outputs, require_distinct, write_text

PathLike = str | Path

#: Where :func:`output_option` keeps, for :func:`guard`, how each output file was spelt: the click
#: context's ``meta``, which lives as long as the command's invocation.
_SPELLING = "rlff.output_spelling"


def output_option(default: Any, *names: str, example: str, help: str) -> Any:
    """A typer option that names an output file whose usual name is ``example`` (``"model.json"``).

    ``Path`` forgets a trailing separator (``-o results/`` is ``results``, and a file of that name
    was written): the path as typed and ``example`` are kept for :func:`guard`, which refuses a
    folder where a file goes and suggests a name in it (``results/model.json``).
    """

    def parse(text: str) -> Path:
        path = Path(text)
        context = get_current_context(silent=True)
        if context is not None:
            context.meta.setdefault(_SPELLING, {})[path] = (text, example)
        return path

    return typer.Option(default, *names, parser=parse, metavar="<path>", help=help)


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
        several, and an output file named as a folder (``-o results/``), with the usual file name
        of an :func:`output_option` (``results/model.json``).
    """
    folder_names = set(folders)
    context = get_current_context(silent=True)
    spelling = {} if context is None else context.meta.get(_SPELLING, {})
    for name, value in inputs.items():
        if value is not None and not isinstance(value, (str, Path)):
            require_distinct(value, f"input ({name})")
    for name, path in outputs.items():
        if path is None:
            continue
        folder = name in folder_names
        text, example = spelling.get(Path(path), (str(path), None))
        if not folder and example is not None and (text.endswith(("/", os.sep)) or Path(path).is_dir()):
            raise InputError(f"{name} {text} names a folder; give a file name, e.g. {Path(path) / example}")
        check_output_path(path, folder=folder)
    check_outputs(inputs, outputs)


def robot_file(robot: str) -> Path | None:
    """The robot file ``--robot`` names (an input no output may replace), or None for a built-in
    robot's name."""
    return Path(robot) if robot.endswith(".toml") or Path(robot).is_file() else None


def write_json(path: PathLike, payload: Any) -> Path:
    """Write ``payload`` as indented JSON to ``path`` atomically (a ``--report`` file)."""
    from rlff.cli._common import jsonable

    return write_text(path, json.dumps(payload, default=jsonable, indent=2) + "\n")


__all__ = ["guard", "output_option", "robot_file", "write_json"]
