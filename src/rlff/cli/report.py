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
    out: Path | None = typer.Option(None, "--output", "-o", "--out", help="HTML file to write (default: RUN/report.html)."),
    as_json: bool = typer.Option(False, "--json", help="Print the written path as JSON."),
) -> None:
    """Build the HTML report of a run: figures embedded, no network needed to open it."""
    from rlff.cli.output import guard
    from rlff.report import build_report
    from rlff.report.run import FIGURE_TYPES, require_run_dir

    require_run_dir(run)  # before RUN/report.html is checked as an output
    target = out if out is not None else run / "report.html"
    # what the report reads: run.json and the figures beside it
    read = [path for path in run.rglob("*") if path.name == "run.json" or path.suffix.lower() in FIGURE_TYPES]
    guard(inputs={"RUN": read}, outputs={"-o/--output": target})
    written = build_report(run, target)
    if as_json:
        emit_json({"report": written})
    else:
        stdout().print(f"report: {written}", highlight=False)
