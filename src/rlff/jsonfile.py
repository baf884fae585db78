"""Reading a JSON document that holds one object, with errors that name the file.

Model files, run directories, simulated throw outcomes and robot trajectories are all JSON
objects; this is the one place that turns a missing, binary or malformed file into an
:class:`~rlff.errors.InputError`.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from rlff.errors import InputError
from rlff.fileio import require_file


def read_json_object(path: str | Path) -> dict[str, Any]:
    """The JSON object stored in ``path``.

    Raises
    ------
    InputError
        No such file, not a UTF-8 text file, not valid JSON (with line and column), or a JSON
        value other than an object.
    """
    path = require_file(path)
    try:
        document = json.loads(path.read_text(encoding="utf-8"))
    except UnicodeDecodeError:
        raise InputError(f"{path}: not a text file") from None
    except json.JSONDecodeError as exc:
        raise InputError(f"{path}: not valid JSON (line {exc.lineno}, column {exc.colno}: {exc.msg})") from None
    if not isinstance(document, dict):
        raise InputError(f"{path}: expected a JSON object, got {type(document).__name__}")
    return document
