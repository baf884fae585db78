"""The run directory: what a run (``rlff demo`` or a script) leaves for the report.

Layout::

    RUN/
      run.json          the record below
      figures/*.png     the figures it refers to (an SVG beside each)
      ...               any further files of the run (data, model, trajectories, logs)

``run.json`` holds ``{"format": "rlff-run", "version": 1, "title", "created" (ISO 8601),
"settings": {...}, "sections": [...], "figures": [...]}``. A section is ``{"id", "title",
"text", "facts": {name: value}, "tables": [{"title", "columns", "rows", "outcome_columns"}]}``:
facts are single
values for scripts and for the summary list of the report, tables are small row sets (one row per
distance, per step, per method). A figure is ``{"file" (relative to RUN), "section" (a section
id), "title", "caption"}``: a PNG, SVG, JPEG or GIF file inside RUN, whose content must be of
the type its extension names. The report shows sections in their order and each figure in its
section.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from rlff.errors import InputError
from rlff.fileio import write_text
from rlff.jsonfile import read_json_object

RUN_FORMAT = "rlff-run"
RUN_VERSION = 1
RUN_FILE = "run.json"

#: A value a fact or a table cell may hold: it must survive JSON.
Scalar = str | int | float | bool | None

#: Figure file types by extension: the MIME type the report embeds them as, and the type's name.
FIGURE_TYPES = {
    ".png": ("image/png", "PNG"),
    ".svg": ("image/svg+xml", "SVG"),
    ".jpg": ("image/jpeg", "JPEG"),
    ".jpeg": ("image/jpeg", "JPEG"),
    ".gif": ("image/gif", "GIF"),
}


def _looks_like(kind: str, head: bytes) -> bool:
    """Whether the first bytes of a file are those of an image of this kind (its name in FIGURE_TYPES)."""
    if kind == "PNG":
        return head.startswith(b"\x89PNG\r\n\x1a\n")
    if kind == "JPEG":
        return head.startswith(b"\xff\xd8\xff")
    if kind == "GIF":
        return head.startswith((b"GIF87a", b"GIF89a"))
    # SVG: XML text whose first element is <svg> (after a declaration, comments, a doctype)
    text = head.decode("utf-8-sig", errors="replace")
    text = re.sub(r"<\?.*?\?>|<!--.*?-->|<!DOCTYPE[^>]*>", "", text, flags=re.DOTALL).lstrip()
    return re.match(r"<svg[\s>]", text) is not None


#: Bytes of a figure read to tell its type.
_HEAD = 4096


def figure_file(run_dir: str | Path, file: str) -> Path:
    """The path of the figure ``file`` of the run in ``run_dir``, checked.

    Raises
    ------
    InputError
        Naming ``file``: a path outside ``run_dir`` (absolute, or leading out of it with ``..``
        or a link), an extension that is not PNG, SVG, JPEG or GIF, no such file, or content that
        is not an image of the type the extension names.
    """
    run_dir = Path(run_dir)
    path = run_dir / file
    try:
        outside = Path(file).is_absolute() or not path.resolve().is_relative_to(run_dir.resolve())
    except (OSError, RuntimeError, ValueError):  # a loop of links, a NUL character
        raise InputError(f"figure file {file!r}: not a usable path") from None
    if outside:
        raise InputError(
            f"figure file {file!r} is outside the run directory {run_dir} (give a path inside it, "
            "relative to it, e.g. figures/bic.png)"
        )
    kind = FIGURE_TYPES.get(path.suffix.lower())
    if kind is None:
        raise InputError(f"figure file {file!r}: unsupported type {path.suffix!r} (use PNG, SVG, JPEG or GIF)")
    if not path.is_file():
        raise InputError(f"figure file {file!r} does not exist in {run_dir}")
    try:
        with path.open("rb") as handle:
            head = handle.read(_HEAD)
    except OSError as exc:
        raise InputError(f"figure file {file!r}: cannot be read ({exc.strerror or exc})") from None
    if not _looks_like(kind[1], head):
        raise InputError(f"figure file {file!r} is not a {kind[1]} image (its content is not that of a {path.suffix} file)")
    return path


@dataclass(frozen=True)
class Table:
    """A small table: named columns and rows of scalars (one per column).

    ``outcome_columns`` name the columns whose yes/no values are outcomes (shown green and red,
    e.g. ``hit``); other booleans are shown plainly.
    """

    title: str
    columns: Sequence[str]
    rows: Sequence[Sequence[Scalar]]
    outcome_columns: Sequence[str] = ("hit",)

    def __post_init__(self) -> None:
        for index, row in enumerate(self.rows):
            if len(row) != len(self.columns):
                raise InputError(
                    f"table {self.title!r}: row {index} has {len(row)} cells, "
                    f"expected {len(self.columns)} ({', '.join(self.columns)})"
                )


@dataclass(frozen=True)
class Section:
    """One section of a run: a short text, facts (name → value) and tables."""

    id: str
    title: str
    text: str = ""
    facts: Mapping[str, Scalar] = field(default_factory=dict)
    tables: Sequence[Table] = ()


@dataclass(frozen=True)
class FigureEntry:
    """A figure file of the run (path relative to the run directory) and where it belongs."""

    file: str
    section: str
    title: str
    caption: str = ""


@dataclass(frozen=True)
class Run:
    """Everything a run records for its report.

    Attributes
    ----------
    title : str
    created : str
        ISO 8601 time of the run.
    settings : mapping
        How the run was made (size, seed, distances, ...).
    sections : sequence of Section
        In display order; ids unique.
    figures : sequence of FigureEntry
        Each in one of the sections.
    """

    title: str
    created: str
    settings: Mapping[str, Scalar] = field(default_factory=dict)
    sections: Sequence[Section] = ()
    figures: Sequence[FigureEntry] = ()

    def __post_init__(self) -> None:
        ids = [section.id for section in self.sections]
        duplicates = sorted({i for i in ids if ids.count(i) > 1})
        if duplicates:
            raise InputError(f"run: duplicate section id {duplicates[0]!r}")
        for entry in self.figures:
            if entry.section not in ids:
                raise InputError(
                    f"run: figure {entry.file!r} belongs to unknown section {entry.section!r} "
                    f"(sections: {', '.join(ids)})"
                )

    def section(self, section_id: str) -> Section:
        """The section with this id."""
        for section in self.sections:
            if section.id == section_id:
                return section
        raise KeyError(section_id)

    def to_dict(self) -> dict[str, Any]:
        """The JSON document of ``run.json``."""
        return {
            "format": RUN_FORMAT,
            "version": RUN_VERSION,
            "title": self.title,
            "created": self.created,
            "settings": dict(self.settings),
            "sections": [
                {
                    "id": s.id,
                    "title": s.title,
                    "text": s.text,
                    "facts": {k: _json_scalar(v, f"fact {k!r}") for k, v in s.facts.items()},
                    "tables": [
                        {
                            "title": t.title,
                            "columns": list(t.columns),
                            "rows": [[_json_scalar(v, f"table {t.title!r}") for v in row] for row in t.rows],
                            "outcome_columns": list(t.outcome_columns),
                        }
                        for t in s.tables
                    ],
                }
                for s in self.sections
            ],
            "figures": [
                {"file": f.file, "section": f.section, "title": f.title, "caption": f.caption}
                for f in self.figures
            ],
        }


def _json_scalar(value: Any, where: str) -> Scalar:
    """A fact or a cell as a JSON scalar: numpy numbers unwrapped, NaN and inf as None."""
    if hasattr(value, "item") and not isinstance(value, str):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if value is None or isinstance(value, (str, int, float, bool)):
        return value
    raise InputError(f"run: {where} holds {type(value).__name__}, expected a number, text or bool")


def write_run(run: Run, run_dir: str | Path) -> Path:
    """Write ``RUN/run.json`` (the figures must already be in place); returns its path.

    Raises
    ------
    InputError
        A figure file that :func:`figure_file` refuses (outside ``run_dir``, missing, not an image
        of its extension's type).
    """
    run_dir = Path(run_dir)
    for entry in run.figures:
        try:
            figure_file(run_dir, entry.file)
        except InputError as exc:
            raise InputError(f"{run_dir}: {exc}") from None
    return write_text(run_dir / RUN_FILE, json.dumps(run.to_dict(), indent=2) + "\n")


def _require(document: Mapping[str, Any], key: str, kind: type | tuple[type, ...], where: str) -> Any:
    if key not in document:
        raise InputError(f"{where}: missing field {key!r}")
    value = document[key]
    if not isinstance(value, kind):
        names = kind.__name__ if isinstance(kind, type) else " or ".join(k.__name__ for k in kind)
        raise InputError(f"{where}: field {key!r} must be {names}, got {type(value).__name__}")
    return value


def require_run_dir(run_dir: str | Path) -> Path:
    """``run_dir`` as a Path, or an :class:`InputError` saying it is missing or a file."""
    run_dir = Path(run_dir)
    if run_dir.is_file():
        hint = (": for an attempts log of `rlff learn`, `rlff plot learning LOG -o OUT` draws its learning curve"
                if run_dir.suffix == ".jsonl" else "")
        # "not a run directory (a folder holding run.json ...)" until 2026-12-07, though a folder of
        # one's own datasets, models and logs is reported too
        raise InputError(f"{run_dir}: is a file, not a folder (one that rlff demo wrote, holding {RUN_FILE} and its "
                         f"figures, or one holding your own datasets, models and attempts logs){hint}")
    if not run_dir.is_dir():
        raise InputError(f"{run_dir}: no such run directory")
    return run_dir


def read_run(run_dir: str | Path) -> Run:
    """Read and validate ``RUN/run.json``.

    Raises
    ------
    InputError
        No such directory or file, a file given as the directory, not JSON, another format or
        version, a missing or mistyped field (named), a figure file that :func:`figure_file`
        refuses (outside the run directory, missing, not an image of its extension's type).
    """
    run_dir = require_run_dir(run_dir)
    path = run_dir / RUN_FILE
    if not path.is_file():
        logs = sorted(run_dir.glob("*.jsonl"))
        hint = (f"; for the attempts log of `rlff learn` ({logs[0].name}), `rlff plot learning LOG -o OUT` draws its "
                "learning curve" if logs else "")
        raise InputError(f"{run_dir}: no {RUN_FILE} (is this a run directory written by `rlff demo`?){hint}")
    document = read_json_object(path)
    if document.get("format") != RUN_FORMAT:
        raise InputError(f"{path}: field 'format' must be {RUN_FORMAT!r}, got {document.get('format')!r}")
    if document.get("version") != RUN_VERSION:
        raise InputError(f"{path}: unsupported version {document.get('version')!r} (this rlff reads {RUN_VERSION})")
    sections = []
    for index, item in enumerate(_require(document, "sections", list, str(path))):
        where = f"{path}: sections[{index}]"
        if not isinstance(item, dict):
            raise InputError(f"{where}: expected an object")
        tables = []
        for t_index, table in enumerate(item.get("tables", [])):
            t_where = f"{where}.tables[{t_index}]"
            if not isinstance(table, dict):
                raise InputError(f"{t_where}: expected an object")
            try:
                tables.append(
                    Table(
                        _require(table, "title", str, t_where),
                        _require(table, "columns", list, t_where),
                        _require(table, "rows", list, t_where),
                        table.get("outcome_columns", ["hit"]),
                    )
                )
            except InputError as exc:
                raise InputError(f"{t_where}: {exc}") from None
        facts = item.get("facts", {})
        if not isinstance(facts, dict):
            raise InputError(f"{where}: field 'facts' must be an object")
        sections.append(
            Section(
                id=_require(item, "id", str, where),
                title=_require(item, "title", str, where),
                text=item.get("text", ""),
                facts=facts,
                tables=tables,
            )
        )
    figures = []
    for index, item in enumerate(document.get("figures", [])):
        where = f"{path}: figures[{index}]"
        if not isinstance(item, dict):
            raise InputError(f"{where}: expected an object")
        entry = FigureEntry(
            file=_require(item, "file", str, where),
            section=_require(item, "section", str, where),
            title=_require(item, "title", str, where),
            caption=item.get("caption", ""),
        )
        try:
            figure_file(run_dir, entry.file)
        except InputError as exc:
            raise InputError(f"{where}: {exc}") from None
        figures.append(entry)
    try:
        return Run(
            title=_require(document, "title", str, str(path)),
            created=_require(document, "created", str, str(path)),
            settings=_require(document, "settings", dict, str(path)) if "settings" in document else {},
            sections=sections,
            figures=figures,
        )
    except InputError as exc:
        raise InputError(f"{path}: {exc}") from None
