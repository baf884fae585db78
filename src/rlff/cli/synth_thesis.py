"""``rlff data synth thesis``: the thesis' synthetic demonstrations (section 4.1.1)."""

from __future__ import annotations

from pathlib import Path

import typer

from rlff.cli._common import emit_json, stdout
from rlff.cli.data import synth_app
from rlff.cli.output import guard, output_option
from rlff.wording import plural


@synth_app.command("thesis")
def thesis_command(
    output: Path = output_option(..., "--output", "-o", example="data.csv", help="Dataset to write (.csv; other formats by extension)."),
    factor_slope: float = typer.Option(0.1, "--factor-slope", help="Slope of the velocity factor f(z) = 1 + slope (z - 1)."),
    trajectories: int = typer.Option(11, "--trajectories", help="Number of trajectories, at distances 1, 2, ..."),
    points: int = typer.Option(50, "--points", help="Points per trajectory, angle evenly spaced over [0, 10]."),
    as_json: bool = typer.Option(False, "--json", help="Print a summary as JSON."),
) -> None:
    """The thesis' synthetic set: velocity = f(z) (-angle^2 + 10 angle) / 2 for z = 1..11."""
    from rlff.formats import format_of, write_dataset
    from rlff.synthetic.thesis import thesis_dataset

    guard(inputs={}, outputs={"-o/--output": output})
    format_of(output)
    dataset = thesis_dataset(factor_slope, trajectories, points)
    write_dataset(dataset, output)
    summary = {
        "output": str(output),
        "trajectories": len(dataset),
        "samples": dataset.n_samples,
        "columns": list(dataset.columns),
        "factor_slope": factor_slope,
    }
    if as_json:
        emit_json(summary)
        return
    stdout().print(
        f"{plural(summary['trajectories'], 'trajectory', 'trajectories')}, {plural(summary['samples'], 'sample')} -> {output}"
    )
