"""One self-contained HTML file from a run directory.

Every figure is embedded as a ``data:`` URI and the style sheet is inline, so the file can be
mailed, archived or opened offline; a Content-Security-Policy forbids any network request. The
page is plain HTML and CSS (no script).
"""

from __future__ import annotations

import base64
import html
import math
from collections.abc import Mapping, Sequence
from importlib import resources
from pathlib import Path
from string import Template

from rlff.fileio import write_text
from rlff.report.run import (
    FIGURE_TYPES,
    FigureEntry,
    Run,
    Scalar,
    Section,
    Table,
    figure_file,
    read_run,
)
from rlff.wording import plural


def _package_text(name: str) -> str:
    return resources.files("rlff.report").joinpath(name).read_text(encoding="utf-8")


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("rlff")
    except PackageNotFoundError:
        return "(development)"


def format_value(value: Scalar) -> str:
    """A fact or table cell as text: 4 significant digits for floats (from 1e5 with an exponent;
    below 0.001 to 3 decimals, ``0.000`` for what rounds to zero, never ``-0.000``: a column of
    misses read -5.986e-04 beside -0.0028, a density traded 7.772e-15), yes/no for booleans."""
    if value is None:
        return "–"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float):
        if math.isnan(value):
            return "–"
        if value == 0:
            return "0"
        if abs(value) < 1e-3:
            text = f"{value:.3f}"
            return "0.000" if float(text) == 0 else text
        if abs(value) >= 1e5:
            return f"{value:.3e}"
        return f"{value:.4g}"
    return str(value)


def _cell(value: Scalar, outcome: bool) -> str:
    text = html.escape(format_value(value))
    if isinstance(value, bool):
        kind = ("yes" if value else "no") if outcome else "flag"
        return f'<td class="{kind}">{text}</td>'
    if value is None:
        return f'<td class="none">{text}</td>'
    if isinstance(value, str):
        return f'<td class="text">{text}</td>'
    return f"<td>{text}</td>"


def _facts(facts: Mapping[str, Scalar]) -> str:
    if not facts:
        return ""
    items = "".join(
        f"<dt>{html.escape(name)}</dt><dd>{html.escape(format_value(value))}</dd>"
        for name, value in facts.items()
    )
    return f'<dl class="facts">{items}</dl>'


def _table(table: Table) -> str:
    head = "".join(f"<th>{html.escape(c)}</th>" for c in table.columns)
    outcome = [c in table.outcome_columns for c in table.columns]
    body = "".join(
        "<tr>" + "".join(_cell(v, o) for v, o in zip(row, outcome, strict=True)) + "</tr>" for row in table.rows
    )
    return f"<h3>{html.escape(table.title)}</h3><table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


def _data_uri(run_dir: Path, file: str) -> str:
    path = figure_file(run_dir, file)  # inside the run, an image of its extension's type
    mime = FIGURE_TYPES[path.suffix.lower()][0]
    return f"data:{mime};base64,{base64.b64encode(path.read_bytes()).decode('ascii')}"


def _figure(entry: FigureEntry, run_dir: Path) -> str:
    caption = f"<strong>{html.escape(entry.title)}.</strong> {html.escape(entry.caption)}"
    return (
        f'<figure><img src="{_data_uri(run_dir, entry.file)}" alt="{html.escape(entry.title, quote=True)}">'
        f"<figcaption>{caption}</figcaption></figure>"
    )


def _section(section: Section, figures: Sequence[FigureEntry], run_dir: Path) -> str:
    parts = [f'<section id="{html.escape(section.id, quote=True)}"><h2>{html.escape(section.title)}</h2>']
    if section.text:
        parts.extend(f"<p>{html.escape(paragraph)}</p>" for paragraph in section.text.split("\n\n"))
    parts.append(_facts(section.facts))
    parts.extend(_table(table) for table in section.tables)
    parts.extend(_figure(entry, run_dir) for entry in figures)
    parts.append("</section>")
    return "\n".join(parts)


def render_report(run: Run, run_dir: str | Path, source: str | Path | None = None) -> str:
    """The HTML text of the report of ``run`` whose figures live under ``run_dir`` (the report
    names ``source`` as where it comes from, default ``run_dir``).

    Raises
    ------
    InputError
        A figure file outside ``run_dir``, missing, or not an image of its extension's type
        (:func:`rlff.report.run.figure_file`), named.
    """
    run_dir = Path(run_dir)
    nav = "\n".join(
        f'<li><a href="#{html.escape(s.id, quote=True)}">{html.escape(s.title)}</a></li>' for s in run.sections
    )
    sections = "\n".join(
        _section(s, [f for f in run.figures if f.section == s.id], run_dir) for s in run.sections
    )
    settings = ""
    if run.settings:
        settings = _facts(run.settings)
    return Template(_package_text("template.html")).substitute(
        title=html.escape(run.title),
        meta=html.escape(f"created {run.created} · {plural(len(run.sections), 'section')} · "
                         f"{plural(len(run.figures), 'figure')}"),
        settings=settings,
        nav=nav,
        sections=sections,
        css=_package_text("style.css"),
        version=html.escape(_version()),
        source=html.escape(str(run_dir if source is None else source)),
    )


def build_report(run_dir: str | Path, out_html: str | Path) -> Path:
    """Write the self-contained HTML report of the run in ``run_dir`` to ``out_html``.

    Parameters
    ----------
    run_dir : path
        A run directory (``run.json`` and its figures, see :mod:`rlff.report.run`).
    out_html : path
        The HTML file to write; missing folders are created.

    Returns
    -------
    Path
        ``out_html``.

    Raises
    ------
    InputError
        The run directory or its ``run.json`` is missing or invalid, or a figure is missing, outside
        the run directory or not an image of the type its extension names.
    """
    run = read_run(run_dir)
    return write_text(out_html, render_report(run, run_dir))
