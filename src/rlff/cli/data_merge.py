"""``rlff data merge``: datasets (import batches, cleaned sets) joined into one."""

from __future__ import annotations

from pathlib import Path

import typer

from rlff.cli._common import emit_json, say_first, stdout, warn_copies
from rlff.cli.data import app
from rlff.cli.output import guard, output_option
from rlff.wording import plural


@app.command("merge")
def merge_command(
    files: list[Path] = typer.Argument(..., help="Datasets to join, in order (.csv, .parquet, .npz or thesis .txt)."),
    output: Path = output_option(..., "--output", "-o", example="all.csv", help="Dataset to write (.csv, .parquet, .npz; .txt: the thesis matrix)."),
    as_json: bool = typer.Option(False, "--json", help="Print what was joined as JSON."),
) -> None:
    """Join datasets into one: the throws of every file, in the order given.

    A throw two files hold under one id is kept once when both copies are the same (every sample
    and every metadata value: one recording in two import batches); the same id with different
    throws is refused, naming what differs. The files must have the same columns.
    """
    from rlff.cli.model import read_data
    from rlff.dataset import merge_datasets
    from rlff.formats import check_holds, format_of, write_dataset

    guard(inputs={"FILES": files}, outputs={"-o/--output": output})
    format_of(output)  # an extension rlff cannot write fails before any file is read
    named = [(str(path), read_data(path)) for path in files]
    check_holds(output, named[0][1].columns, named[0][0])
    merged = merge_datasets(named)
    warn_copies(merged.dataset, output)
    write_dataset(merged.dataset, output)
    counts = {name: len(dataset) for name, dataset in named}
    if as_json:
        emit_json({
            "output": str(output), "trajectories": len(merged.dataset), "samples": merged.dataset.n_samples,
            "inputs": [{"file": name, "trajectories": count} for name, count in counts.items()],
            "kept_once": [{"trajectory": trajectory, "first": first, "again": again}
                          for trajectory, first, again in merged.kept_once],
        })
        return
    say_first([f"{trajectory}: in {first} and again in {again}, the same throw: kept once"
               for trajectory, first, again in merged.kept_once], "--json lists every one")
    once = f", {plural(len(merged.kept_once), 'throw')} held twice kept once" if merged.kept_once else ""
    stdout().print(f"{plural(len(merged.dataset), 'throw')} from {plural(len(files), 'dataset')}{once} -> {output}")
