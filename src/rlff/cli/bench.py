"""``rlff bench ...``: benchmarks that measure rlff on its own tasks."""

from __future__ import annotations

import typer

from rlff.cli._common import emit_json, progress, stdout

app = typer.Typer(help="Benchmarks: how many attempts learning takes, and against which baselines.",
                  no_args_is_help=True)


@app.command("learning")
def learning(
    seeds: int = typer.Option(5, "--seeds", min=1, help="Seeds (each draws its own demonstrations)."),
    quick: bool = typer.Option(False, "--quick", help="A small grid: 2 seeds, budget 12."),
    budget: int = typer.Option(20, "--budget", min=1, help="Attempts per run."),
    jobs: int = typer.Option(2, "--jobs", min=1, help="Parallel workers."),
    backend: str | None = typer.Option(None, "--backend",
                                       help="joblib backend: loky (default), ray or dask."),
    as_json: bool = typer.Option(False, "--json", help="Print every run and the summary as JSON."),
) -> None:
    """Attempts to the first hit over seeds x baskets x feedback kinds x methods."""
    from rlff.learn.benchmark import (
        BASKETS,
        METHODS_BY_FEEDBACK,
        format_table,
        learning_benchmark,
        prepare_backend,
        runs_as_dicts,
        summary,
    )

    if quick:
        seeds, budget = min(seeds, 2), min(budget, 12)
    prepare_backend(backend)  # a missing cluster package fails before the progress display
    total = seeds * len(BASKETS) * sum(len(m) for m in METHODS_BY_FEEDBACK.values())
    with progress("learning benchmark", total=total) as advance:
        runs = learning_benchmark(seeds, budget=budget, jobs=jobs, backend=backend,
                                  progress=lambda run: advance(1))
    if as_json:
        emit_json({"budget": budget, "runs": runs_as_dicts(runs), "summary": summary(runs, budget)})
        return
    stdout().print(format_table(runs, budget), highlight=False, markup=False)
