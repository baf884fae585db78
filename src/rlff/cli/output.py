"""The output layer every command uses: outputs checked before any work, JSON files written atomically.

A command names its inputs and outputs once, first thing::

    guard(inputs={"DATA": data, "--config": config}, outputs={"-o/--output": output, "--report": report})

and :func:`guard` refuses (an :class:`~rlff.errors.InputError`, so one line and exit 2) an
output that is one of the inputs, two outputs that are the same file, an output file named as a
folder (an existing folder, or, given to an :func:`output_option`, a path ending in ``/``) or a
socket, an output named ``-`` (standard output to many tools: a file named ``-`` was written), an output folder named as anything but a folder (a file, a device, a FIFO: the refusal
says which, and what the command writes there), or one whose folder is a file. A device or a
FIFO given for a file gets the file's bytes (``-o /dev/stdout``). The files themselves are
written by the library through :mod:`rlff.fileio`, so that an existing output is only ever
replaced by a complete one. Missing output folders are created.
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import typer

try:  # newer typer (0.29 is one) carries its own copy of click; older ones use the click package
    from typer._click.globals import get_current_context
except ImportError:  # pragma: no cover - older typer
    from click import get_current_context

from rlff.errors import InputError
from rlff.fileio import check_output_path, check_outputs, path_kind, require_distinct, write_text

PathLike = str | Path

#: Where :func:`output_option` keeps, for :func:`guard`, how each output file was spelt: the click
#: context's ``meta``, which lives as long as the command's invocation.
_SPELLING = "rlff.output_spelling"
#: What an :func:`output_option` (a file of the format its suffix says) is where a command names it
#: among :func:`guard`'s ``folders``: the one format rlff writes as a folder (``rlff robot export
#: -o``, ``rlff learn --out``).
FOLDER_FORMAT = "a ROS 2 bag (a path without a suffix, or --format ros2-bag)"


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
    folders: Iterable[str] | Mapping[str, str] = (),
) -> None:
    """Refuse outputs that would destroy an input or each other, before anything is read.

    Parameters
    ----------
    inputs : mapping of str to path, paths or None
        The user's name of each input (``"DATA"``, ``"--manifest"``) to its path(s); None when not
        given.
    outputs : mapping of str to path or None
        The same for outputs (``"-o/--output"``, ``"--report"``).
    folders : iterable of str, or mapping of str to str
        Names of the outputs that are folders (a ROS 2 bag, a folder of frames); a mapping gives
        what the command writes in each (``"the demo's report, figures, data and model"``), for
        the refusal of a path that is no folder. An :func:`output_option` among them is a file
        whose format is a folder, :data:`FOLDER_FORMAT`.

    Raises
    ------
    InputError
        Naming the option(s) and the path; also the same file given twice to an input that takes
        several, an output file named as a folder (``-o results/``), with the usual file name
        of an :func:`output_option` (``results/model.json``), or as a socket, and an output
        folder named as a file, a device or a FIFO, with what the command writes there.
    """
    contents = dict(folders) if isinstance(folders, Mapping) else dict.fromkeys(folders, "")
    context = get_current_context(silent=True)
    spelling = {} if context is None else context.meta.get(_SPELLING, {})
    for name, value in inputs.items():
        if value is not None and not isinstance(value, (str, Path)):
            require_distinct(value, f"input ({name})")
    for name, path in outputs.items():
        if path is None:
            continue
        folder = name in contents
        text, example = spelling.get(Path(path), (str(path), None))
        if text == "-":  # standard output to many tools; it wrote a file (or a bag's folder) named "-"
            if folder and example is not None:  # a file whose suffix says its format, a bag's folder without one
                what, named = "a file (or, without a suffix, a ROS 2 bag's folder)", f" (e.g. {example}.json)"
            else:
                what, named = ("a folder", "") if folder else ("a file", "" if example is None else f" (e.g. {example})")
            raise InputError(f"{name} -: rlff writes {what} there, not standard output: give its name{named}"
                             + ("" if folder else ", or /dev/stdout for its bytes"))
        kind = path_kind(path)
        if folder and kind not in (None, "a folder"):
            raise InputError(f"{text} is {kind}, not a folder: {_folder_wanted(name, contents[name], example)}")
        if not folder and example is not None and (text.endswith(("/", os.sep)) or kind == "a folder"):
            raise InputError(f"{name} {text} names a folder; give a file name, e.g. {Path(path) / example}")
        if not folder and kind == "a socket":
            raise InputError(f"{text} is a socket, not a file: give a file name for {name}"
                             + ("" if example is None else f", e.g. {Path(path).with_name(example)}"))
        check_output_path(path, folder=folder)
    check_outputs(inputs, outputs)


def _folder_wanted(name: str, contents: str, example: str | None) -> str:
    """What the output ``name``, a folder, is and what to give it: ``contents``, what the command
    writes in it (or ""); ``example``, the usual name of an :func:`output_option`'s file."""
    if example is not None:
        return (f"{name} here is {FOLDER_FORMAT}, which is a folder; give a new folder's path for the bag, "
                f"or a file name whose suffix says its format (e.g. {example}.json)")
    what = f"is the folder for {contents}" if contents else "takes a folder"
    return f"{name} {what}; give a folder's path (a new one is created)"


def robot_file(robot: str) -> Path | None:
    """The robot file ``--robot`` names (an input no output may replace), or None for a built-in
    robot's name."""
    return Path(robot) if robot.endswith(".toml") or Path(robot).is_file() else None


def write_json(path: PathLike, payload: Any) -> Path:
    """Write ``payload`` as indented JSON to ``path`` atomically (a ``--report`` file)."""
    from rlff.cli._common import jsonable

    return write_text(path, json.dumps(payload, default=jsonable, indent=2) + "\n")


__all__ = ["guard", "output_option", "robot_file", "write_json"]
