"""``rlff demo``: the whole chain on built-in data, with figures and an HTML report."""

from __future__ import annotations

import shlex
from pathlib import Path

import typer

from rlff.cli._common import emit_json, progress, say, seed_option, stdout
from rlff.wording import signed


def register(root: typer.Typer) -> None:
    """Add the top-level ``demo`` command."""
    root.command("demo")(demo_command)


def demo_command(
    out: Path = typer.Option(Path("rlff-demo"), "--output", "-o", "--out", help="Folder for the report, figures, data and model."),
    small: bool = typer.Option(False, "--small", help="A quick version: fewer people, baskets and learning runs."),
    seed: int = seed_option("Seed of the simulated people, the fits and the learning runs."),
    frames: bool = typer.Option(True, "--frames/--no-frames", help="Render the learned throw with MuJoCo beside its drawing (needs OpenGL)."),
    as_json: bool = typer.Option(False, "--json", help="Print the summary as JSON."),
) -> None:
    """Simulated failed demonstrations → cleaning → model → throws → simulated robot → learning → report."""
    from rich.table import Table

    from rlff.cli.output import guard
    from rlff.demo import STAGES, check_demo_options, run_demo

    guard(inputs={}, outputs={"-o/--output": out}, folders={"-o/--output": "the demo's report, figures, data and model"})
    size = "small" if small else "full"
    check_demo_options(out, size, frames=frames)  # before the progress display starts
    with progress("rlff demo", total=len(STAGES)) as advance:
        last = {"done": 0}

        def show(stage: str, done: int, total: int) -> None:
            advance(done - last["done"], description=stage)
            last["done"] = done

        summary = run_demo(out, size=size, seed=seed, progress=show, frames=frames)
    if as_json:
        emit_json(summary.to_json())
        return
    console = stdout()
    hits = f"{summary.demonstration_hits} of {summary.demonstrations} hit"
    console.print(
        f"Demonstrations: {summary.demonstrations} simulated throws ({hits}); "
        f"{summary.clean_trajectories} kept after cleaning; K = {summary.components} by BIC",
        highlight=False,
    )
    throws = Table(title="The model's throws, executed in MuJoCo", title_justify="left")
    for column in ("distance (m)", "demonstrated", "reachable", "outcome"):
        throws.add_column(column, justify="right" if column == "distance (m)" else "left")
    for row in summary.throws:
        outcome = "hit" if row.hit else f"miss {signed(row.miss)} m"
        throws.add_row(f"{row.distance:g}", "yes" if row.demonstrated else "new",
                       "yes" if row.reachable else "no", outcome)
    console.print(throws)
    learning = Table(title=f"Learning from failure at {summary.learning_distance:g} m ({summary.learning_setting})",
                     title_justify="left")
    for column in ("method", "feedback", "result", "misses (m)"):
        learning.add_column(column)
    for row in summary.learning:
        result = f"hit at attempt {row.attempts}" if row.hit else f"no hit in {row.attempts}"
        misses = [signed(m) for m in row.misses]
        if len(misses) > 6:  # keep the table short: the report has them all
            misses = [*misses[:3], "…", *misses[-2:]]
        learning.add_row(row.method, row.feedback, result, " ".join(misses))
    console.print(learning)
    if summary.whole_arm:
        console.print(_whole_arm_table(summary.whole_arm))
    console.print(f"report: {summary.report}  ({len(summary.figures)} figures, {summary.seconds:.0f} s)", highlight=False)
    say(f"open it with: xdg-open {shlex.quote(str(summary.report))}")  # a path with a space, pasted


def _whole_arm_table(runs):
    """The whole-arm baskets: where each stood, what the robot threw with, the attempts to a hit."""
    from rich.table import Table

    hits = sum(1 for r in runs if r.hit)
    table = Table(title=f"Whole-arm learning (calibrate, binary feedback): {hits} of {len(runs)} baskets hit",
                  title_justify="left")
    for column in ("basket", "bearing", "seen", "joints", "result", "misses (m)"):
        table.add_column(column, justify="right" if column in ("basket", "bearing") else "left",
                         no_wrap=column != "misses (m)")
    for r in runs:
        result = f"hit at {r.attempts}" if r.hit else f"no hit in {r.attempts}" if r.attempts else "out of reach"
        misses = ["none" if m != m else signed(m) for m in r.misses]
        if len(misses) > 5:
            misses = [*misses[:2], "…", *misses[-2:]]
        table.add_row(f"{r.distance:g} m", f"{r.bearing:g}°", "yes" if r.demonstrated else "new",
                      ",".join(j.removeprefix("joint_") for j in r.joints), result, " ".join(misses))
    return table
