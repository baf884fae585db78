"""``rlff bench ...``: benchmarks that measure rlff on its own tasks."""

from __future__ import annotations

import typer

from rlff.cli._common import emit_json, progress, stdout
from rlff.errors import InputError

app = typer.Typer(help="Benchmarks: how many attempts learning takes, and against which baselines.",
                  no_args_is_help=True)


@app.command("learning")
def learning(
    seeds: int = typer.Option(5, "--seeds", min=1, help="Seeds (each draws its own demonstrations)."),
    quick: bool = typer.Option(False, "--quick", help="A small grid: 2 seeds, budget 12."),
    budget: int = typer.Option(20, "--budget", min=1, help="Attempts per run."),
    scenario: str = typer.Option("short", "--scenario",
                                 help="short (all-short demonstrations at 1-1.5 m), wide (1-4 m) or both."),
    jobs: int = typer.Option(2, "--jobs", min=1, help="Parallel workers."),
    backend: str | None = typer.Option(None, "--backend",
                                       help="joblib backend: loky (default), threading, multiprocessing, ray or dask."),
    as_json: bool = typer.Option(False, "--json", help="Print every run and the summary as JSON."),
) -> None:
    """Attempts to the first hit over seeds x baskets x feedback kinds x methods, per scenario."""
    from rlff.learn.benchmark import (
        METHODS_BY_FEEDBACK,
        SCENARIOS,
        format_table,
        learning_benchmark,
        prepare_backend,
        runs_as_dicts,
        summary,
    )

    if scenario != "both" and scenario not in SCENARIOS:
        raise InputError(f"--scenario: unknown scenario {scenario!r} (known: {', '.join(SCENARIOS)}, both)")
    names = list(SCENARIOS) if scenario == "both" else [scenario]
    if quick:
        seeds, budget = min(seeds, 2), min(budget, 12)
    prepare_backend(backend)  # a missing cluster package fails before the progress display
    methods = sum(len(m) for m in METHODS_BY_FEEDBACK.values())
    total = sum(seeds * len(SCENARIOS[name].baskets) * methods for name in names)
    runs_by_scenario = {}
    with progress("learning benchmark", total=total) as advance:
        for name in names:
            runs_by_scenario[name] = learning_benchmark(seeds, scenario=name, budget=budget, jobs=jobs,
                                                        backend=backend, progress=lambda run: advance(1))
    if as_json:
        emit_json({
            "budget": budget,
            "scenario": scenario,
            "runs": [{"scenario": name, **run} for name, runs in runs_by_scenario.items()
                     for run in runs_as_dicts(runs)],
            "summary": [{"scenario": name, **row} for name, runs in runs_by_scenario.items()
                        for row in summary(runs, budget)],
        })
        return
    for name, runs in runs_by_scenario.items():
        if len(names) > 1:
            stdout().print(f"## Scenario {name}\n", highlight=False, markup=False)
        stdout().print(format_table(runs, budget) + ("\n" if len(names) > 1 else ""), highlight=False, markup=False)
