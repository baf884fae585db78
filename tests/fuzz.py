"""Hypothesis strategies that damage files, and the one check every reader must pass.

A reader given any bytes either returns (and then what it returns holds only finite numbers
where numbers are promised) or raises :class:`rlff.errors.InputError` whose message names the
file. Any other exception escapes the test and fails it.

Damage comes in three kinds, mixed by the strategies below:

- bytes: truncation, bit flips, inserted or deleted runs, repeated runs, an empty file;
- text: a field replaced by NaN, inf, 1e308, an empty cell, a word, a quote; lines dropped,
  repeated or swapped; a column dropped or repeated (in the header or everywhere);
- JSON documents: any value (or key) replaced by another JSON value of any type, or removed;
  TOML documents the same way (written back as TOML, null as a string).
"""

from __future__ import annotations

import json
import os
import re
import tempfile
from collections.abc import Callable
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from hypothesis import HealthCheck, settings
from hypothesis import strategies as st

from rlff.errors import InputError

#: Settings of every fuzz test: bounded examples (the whole suite stays well under a minute).
#: Locally every run draws new inputs (that is how the fuzz finds bugs); under CI the draw is
#: derandomised, so a clean clone's verdict does not depend on the luck of the draw.
FUZZ = settings(
    max_examples=60,
    deadline=None,
    derandomize=os.environ.get("CI", "").lower() == "true",
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large, HealthCheck.filter_too_much],
)

#: What a damaged field may become.
ODD_FIELDS = (
    "nan", "NaN", "-nan", "inf", "-inf", "Infinity", "1e308", "-1e308", "1e309", "1e-320", "0", "-0",
    "-1", "9" * 40, "", " ", "x", "true", "null", '"', "'", ",", ";", "#", "[", "{", "=", "\t", "é",
)
_FIELD = re.compile(r"([^\s,;=:\[\]{}\"]+)")


def check_reader(read: Callable[[Path], Any], path: Path) -> Any:
    """``read(path)``: its result, or None when it raised an InputError naming ``path``.

    Any exception other than InputError propagates (and fails the calling test).
    """
    try:
        return read(path)
    except InputError as exc:
        assert str(path) in str(exc), f"the message does not name the file {path}: {exc}"
        return None


@contextmanager
def file_with(content: bytes, name: str):
    """A fresh temporary file ``name`` holding ``content``; yields its path."""
    with tempfile.TemporaryDirectory(prefix="rlff-fuzz-") as folder:
        path = Path(folder) / name
        path.write_bytes(content)
        yield path


@st.composite
def damaged_bytes(draw: st.DrawFn, seed: bytes) -> bytes:
    """``seed`` cut short, with bytes flipped, inserted, deleted or repeated, or empty."""
    kind = draw(st.sampled_from(("truncate", "flip", "insert", "delete", "repeat", "empty")))
    if kind == "empty" or not seed:
        return b""
    data = bytearray(seed)
    if kind == "truncate":
        return bytes(data[: draw(st.integers(0, len(data) - 1))])
    for _ in range(draw(st.integers(1, 6))):
        at = draw(st.integers(0, max(0, len(data) - 1)))
        if kind == "flip" and data:
            data[at] ^= 1 << draw(st.integers(0, 7)) if draw(st.booleans()) else draw(st.integers(1, 255))
        elif kind == "insert":
            data[at:at] = draw(st.binary(min_size=1, max_size=16))
        elif kind == "delete":
            del data[at : at + draw(st.integers(1, 64))]
        elif kind == "repeat":
            data[at:at] = data[max(0, at - draw(st.integers(1, 64))) : at]
    return bytes(data)


def _cells(line: str) -> list[str]:
    return line.rstrip("\r\n").split(",")


@st.composite
def damaged_text(draw: st.DrawFn, seed: str) -> bytes:
    """``seed`` (UTF-8 text) with fields replaced, lines dropped, repeated or swapped, or a
    comma-separated column dropped or repeated; 1 to 4 edits."""
    lines = seed.splitlines(keepends=True) or [""]
    for _ in range(draw(st.integers(1, 4))):
        kind = draw(st.sampled_from(("field", "field", "field", "drop", "repeat", "swap", "column", "header")))
        row = draw(st.integers(0, len(lines) - 1))
        if kind == "field":
            fields = list(_FIELD.finditer(lines[row]))
            if not fields:
                continue
            match = fields[draw(st.integers(0, len(fields) - 1))]
            odd = draw(st.sampled_from(ODD_FIELDS) | st.text(max_size=6))
            lines[row] = lines[row][: match.start()] + odd + lines[row][match.end() :]
        elif kind == "drop" and len(lines) > 1:
            del lines[row]
        elif kind == "repeat":
            lines.insert(row, lines[row])
        elif kind == "swap":
            other = draw(st.integers(0, len(lines) - 1))
            lines[row], lines[other] = lines[other], lines[row]
        elif kind in ("column", "header"):
            width = len(_cells(lines[0]))
            column = draw(st.integers(0, max(0, width - 1)))
            repeat = draw(st.booleans())
            targets = range(1) if kind == "header" else range(len(lines))
            for i in targets:
                cells = _cells(lines[i])
                if column < len(cells):
                    if repeat:
                        cells.insert(column, cells[column])
                    else:
                        del cells[column]
                lines[i] = ",".join(cells) + "\n"
    return "".join(lines).encode("utf-8", errors="surrogatepass")


#: Any JSON value, NaN and infinities included (Python's json reads them).
JSON_VALUES = st.recursive(
    st.none()
    | st.booleans()
    | st.integers(-(10**30), 10**30)
    | st.floats(allow_nan=True, allow_infinity=True)
    | st.sampled_from([1e308, -1e308, 0.0, -1.0, 1e-320])
    | st.text(max_size=8),
    lambda children: st.lists(children, max_size=4) | st.dictionaries(st.text(max_size=6), children, max_size=3),
    max_leaves=8,
)


def _paths(value: Any, prefix: tuple = ()) -> list[tuple]:
    """Every path (keys and indices) into a JSON value, the value itself included."""
    found = [prefix]
    if isinstance(value, dict):
        for key, child in value.items():
            found += _paths(child, (*prefix, key))
    elif isinstance(value, list):
        for index, child in enumerate(value):
            found += _paths(child, (*prefix, index))
    return found


@st.composite
def damaged_json(draw: st.DrawFn, document: Any) -> Any:
    """A deep copy of ``document`` with 1 to 3 values replaced by any JSON value or removed."""
    document = json.loads(json.dumps(document))
    for _ in range(draw(st.integers(1, 3))):
        # a depth first, then a path of that depth: the few shallow paths (whole tables, whole
        # arrays) are hit as often as the many leaves
        paths = _paths(document)
        depth = draw(st.sampled_from(sorted({len(path) for path in paths})))
        path = draw(st.sampled_from([path for path in paths if len(path) == depth]))
        if not path:
            document = draw(JSON_VALUES)
            continue
        parent = document
        try:
            for key in path[:-1]:
                parent = parent[key]
            if draw(st.booleans()) and isinstance(parent, dict):
                del parent[path[-1]]
            else:
                parent[path[-1]] = draw(JSON_VALUES)
        except (KeyError, IndexError, TypeError):
            continue  # an earlier edit removed or replaced this path
    return document


def damaged(seed: bytes, text: bool = True) -> st.SearchStrategy[bytes]:
    """Damaged bytes of ``seed``, and for a text file also damaged text."""
    if not text:
        return damaged_bytes(seed)
    return st.one_of(damaged_bytes(seed), damaged_text(seed.decode("utf-8")))


def json_bytes(document: Any) -> st.SearchStrategy[bytes]:
    """``document`` damaged as JSON (then written with NaN and Infinity allowed), as text or as bytes."""
    seed = json.dumps(document).encode()
    return st.one_of(
        damaged_json(document).map(lambda value: json.dumps(value, allow_nan=True).encode()),
        damaged(seed),
    )


def toml_value(value: Any) -> str:
    """A JSON-like value as TOML (inline tables and arrays; None becomes the string "null")."""
    if value is None:
        return '"null"'
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        if value != value:
            return "nan"
        if value in (float("inf"), -float("inf")):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, int):
        return str(max(min(value, 2**63 - 1), -(2**63)))  # TOML integers are 64-bit
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(item) for item in value) + "]"
    return "{" + ", ".join(f"{json.dumps(str(key))} = {toml_value(item)}" for key, item in value.items()) + "}"


def damaged_toml(document: dict) -> st.SearchStrategy[bytes]:
    """A TOML ``document`` (as parsed by tomllib) with values replaced or removed, as TOML text."""

    def write(value: Any) -> bytes:
        if not isinstance(value, dict):
            value = {"value": value}
        return "".join(f"{json.dumps(str(key))} = {toml_value(item)}\n" for key, item in value.items()).encode()

    return damaged_json(document).map(write)
