"""``rlff report``: one self-contained HTML file from a run directory."""

from __future__ import annotations

from pathlib import Path

import typer

from rlff.cli._common import emit_json, stdout
from rlff.cli.output import output_option


def register(root: typer.Typer) -> None:
    """Add the top-level ``report`` command."""
    root.command("report")(report_command)


def report_command(
    run: Path = typer.Argument(..., help="Run directory (run.json and figures), e.g. the output of `rlff demo`; or a "
                                         "folder of your own chain's files (datasets, model.json, attempts logs)."),
    out: Path | None = output_option(None, "--output", "-o", "--out", example="report.html", help="HTML file to write (default: RUN/report.html)."),
    as_json: bool = typer.Option(False, "--json", help="Print the written path as JSON."),
) -> None:
    """Build the HTML report of a run: figures embedded, no network needed to open it."""
    from rlff.cli.output import guard
    from rlff.report import build_report
    from rlff.report.run import FIGURE_TYPES, RUN_FILE, require_run_dir

    require_run_dir(run)  # before RUN/report.html is checked as an output
    target = out if out is not None else run / "report.html"
    if not (run / RUN_FILE).is_file():
        _chain_report(run, target, as_json)
        return
    # what the report reads: run.json and the figures beside it
    read = [path for path in run.rglob("*") if path.name == "run.json" or path.suffix.lower() in FIGURE_TYPES]
    guard(inputs={"RUN": read}, outputs={"-o/--output": target})
    written = build_report(run, target)
    if as_json:
        emit_json({"report": written})
    else:
        stdout().print(f"report: {written}", highlight=False)


def _chain_report(folder: Path, target: Path, as_json: bool) -> None:
    """The report of a folder without run.json: its datasets, models and attempts logs
    (:mod:`rlff.chain_report`), the figures drawn in a temporary run directory and embedded."""
    import tempfile
    from contextlib import nullcontext

    from rlff.chain_report import COUNTED, DATASET_SUFFIXES, chain_run
    from rlff.cli._common import progress, say, warn
    from rlff.cli.output import guard
    from rlff.fileio import write_text
    from rlff.report.html import render_report
    from rlff.report.run import write_run
    from rlff.wording import plural

    read = [path for path in folder.iterdir() if path.suffix.lower() in (*DATASET_SUFFIXES, ".json", ".jsonl")]
    guard(inputs={"RUN": read}, outputs={"-o/--output": target})
    with tempfile.TemporaryDirectory(prefix="rlff-report-") as scratch:
        # a folder of lab-sized datasets takes a minute or more to read and draw: said as it goes
        # a folder of nothing it reads is refused at once, without a progress line before the error
        with progress(f"report of {folder}", total=None) if read else nullcontext(lambda *args, **kwargs: None) \
                as advance:
            told = {"done": 0}

            def show(step: str, done: int, total: int) -> None:
                advance(done - told["done"], description=step, total=total)
                told["done"] = done

            run, passed, not_reported = chain_run(folder, Path(scratch) / "figures", progress=show)
        for why in passed:
            warn(f"{folder}: passed over {why}")
        if not_reported:  # rlff's own outputs with nothing to tabulate: counted once, not a warning each
            say(f"{folder}: {not_reported}")
        write_run(run, scratch)
        written = write_text(target, render_report(run, scratch, source=folder))
    # what it found, not the kinds it did not ("its 0 datasets, 0 models and 1 attempts log")
    kinds = [plural(run.settings[key], noun, many) for key, (noun, many) in COUNTED.items() if run.settings[key]]
    say(f"{folder}: no run.json: a report of its " + (f"{', '.join(kinds[:-1])} and {kinds[-1]}" if len(kinds) > 1
                                                      else kinds[0]))
    if as_json:
        emit_json({"report": written})
    else:
        stdout().print(f"report: {written}", highlight=False)
