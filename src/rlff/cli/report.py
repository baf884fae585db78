"""``rlff report``: one self-contained HTML file from a run directory."""

from __future__ import annotations

from pathlib import Path

import typer

from rlff.cli._common import emit_json, stdout


def register(root: typer.Typer) -> None:
    """Add the top-level ``report`` command."""
    root.command("report")(report_command)


def report_command(
    run: Path = typer.Argument(..., help="Run directory (run.json and figures), e.g. the output of `rlff demo`."),
    out: Path | None = typer.Option(None, "--out", "-o", help="HTML file to write [default: RUN/report.html]."),
    as_json: bool = typer.Option(False, "--json", help="Print the written path as JSON."),
) -> None:
    """Build the HTML report of a run: figures embedded, no network needed to open it."""
    from rlff.report import build_report

    written = build_report(run, out if out is not None else run / "report.html")
    if as_json:
        emit_json({"report": written})
    else:
        stdout().print(f"report: {written}", highlight=False)
