"""The learning benchmark: attempts to the first hit, per method, feedback kind and basket.

Every run starts from simulated human demonstrations, cleaned by the thesis preset, and runs
one method in the loop of :func:`rlff.learn.learn` against the MuJoCo simulation until a hit or
the budget. The grid is seeds x baskets x feedback kinds x methods, in one of two scenarios
(:data:`SCENARIOS`): ``short``, demonstrations that all fall short of near baskets, with baskets
inside and beyond the demonstrated distances; ``wide``, the demo's setting, demonstrations at
1 to 4 m, most of them beyond the robot's reach, with baskets between demonstrated distances.
All baskets are within the robot's reach. Runs go to joblib processes, or to a Ray or Dask
cluster through joblib's backends.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass
from functools import lru_cache

import numpy as np

from rlff.dataset import Dataset
from rlff.errors import InputError


@dataclass(frozen=True)
class Scenario:
    """Which demonstrations a run learns from, and the baskets it is asked to hit.

    Parameters
    ----------
    demo_distances : tuple of float
        Distances (m) the simulated humans aimed at (4 subjects, 3 throws at each).
    all_short : bool
        Every demonstration falls short of its basket.
    baskets : tuple of float
        Basket distances (m), all within the robot's reach.
    """

    demo_distances: tuple[float, ...]
    all_short: bool
    baskets: tuple[float, ...]


#: ``short``: failed throws at near baskets; one basket inside their distances, one beyond.
#: ``wide``: the demo's setting, throws at 1 to 4 m (the robot reaches about 2.2 m, so the human
#: landings beyond that teach it nothing it can do), baskets between demonstrated distances.
SCENARIOS = {
    "short": Scenario((1.0, 1.25, 1.5), all_short=True, baskets=(1.4, 1.9)),
    "wide": Scenario((1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0), all_short=False, baskets=(1.25, 1.75)),
}
#: Distances (m) the simulated humans aimed at in the default scenario.
DEMO_DISTANCES = SCENARIOS["short"].demo_distances
#: Basket distances (m) of the default scenario: one inside the demonstrated range, one beyond.
BASKETS = SCENARIOS["short"].baskets
#: Methods run with each feedback kind.
METHODS_BY_FEEDBACK = {
    "binary": ("calibrate", "failure", "imitation", "random", "cma"),
    "distance": ("calibrate", "hindsight", "failure", "secant", "cma", "random", "imitation"),
}


@dataclass(frozen=True)
class Run:
    """One cell of the grid and its outcome (``attempts`` counts to the first hit or the budget)."""

    method: str
    feedback: str
    basket: float
    seed: int
    hit: bool
    attempts: int


@lru_cache(maxsize=8)
def demonstrations(seed: int, scenario: str = "short") -> Dataset:
    """The demonstrations of one seed in ``scenario``, simulated and cleaned by the thesis preset."""
    from rlff.preprocess import Pipeline
    from rlff.synthetic.throws import simulate_throws

    plan = SCENARIOS[scenario]
    raw = simulate_throws(seed, subjects=4, distances=plan.demo_distances, throws_per_distance=3,
                          all_short=plan.all_short)
    clean, _ = Pipeline.preset("thesis").run(raw)
    return clean


def run_one(demos: Dataset, method: str, feedback: str, basket: float, seed: int, budget: int) -> Run:
    """Run one method once from the demonstrations of ``seed``."""
    from rlff.learn.loop import learn

    result = learn(demos, basket, budget=budget, feedback=feedback, update=method, seed=seed)
    return Run(method, feedback, basket, seed, result.hit, result.attempts)


def learning_benchmark(
    seeds: int = 5,
    *,
    scenario: str = "short",
    baskets: Sequence[float] | None = None,
    methods: dict[str, Sequence[str]] | None = None,
    budget: int = 20,
    jobs: int = 2,
    backend: str | None = None,
    progress: Callable[[Run], None] | None = None,
) -> list[Run]:
    """Run the grid seeds x baskets x feedback kinds x methods.

    Parameters
    ----------
    seeds : int
        Seeds 0 .. seeds - 1; each seed draws its own demonstrations.
    scenario : {"short", "wide"}
        Which demonstrations and baskets (:data:`SCENARIOS`).
    baskets : sequence of float, optional
        Basket distances (m); default the scenario's.
    methods : dict, optional
        Methods per feedback kind; default :data:`METHODS_BY_FEEDBACK`.
    budget : int
        Attempts per run.
    jobs : int
        Parallel workers (joblib processes by default).
    backend : str, optional
        A joblib backend name: ``loky`` (default), ``ray`` or ``dask`` (connects to the cluster
        its package is configured for: ``RAY_ADDRESS``, ``DASK_SCHEDULER_ADDRESS``, or a local one).
    progress : callable, optional
        Called with every finished run.

    Returns
    -------
    list of Run
    """
    import joblib

    if scenario not in SCENARIOS:
        raise InputError(f"unknown scenario {scenario!r} (known: {', '.join(SCENARIOS)})")
    baskets = SCENARIOS[scenario].baskets if baskets is None else baskets
    methods = METHODS_BY_FEEDBACK if methods is None else methods
    cases = [(m, f, float(b), s) for s in range(seeds) for b in baskets
             for f, names in methods.items() for m in names]
    prepare_backend(backend)
    try:  # results as they come, for the progress display, where the backend can stream them
        parallel = joblib.Parallel(n_jobs=jobs, backend=backend, return_as="generator")
    except ValueError:
        parallel = joblib.Parallel(n_jobs=jobs, backend=backend)
    # the demonstrations of every seed, made once and shipped to the workers with each run
    demos = dict(zip(range(seeds), parallel(joblib.delayed(demonstrations)(s, scenario) for s in range(seeds)),
                     strict=True))
    runs = []
    for run in parallel(joblib.delayed(run_one)(demos[case[3]], *case, budget) for case in cases):
        runs.append(run)
        if progress:
            progress(run)
    return runs


#: joblib backends the benchmark runs on; None is joblib's default (loky).
BACKENDS = (None, "loky", "threading", "multiprocessing", "ray", "dask")


def prepare_backend(backend: str | None) -> None:
    """Register the cluster backends joblib does not know by itself; refuse one it cannot use."""
    if backend not in BACKENDS:
        raise InputError(f"--backend: unknown backend {backend!r} (known: {', '.join(b for b in BACKENDS if b)})")
    if backend == "ray":
        try:
            from ray.util.joblib import register_ray
        except ImportError:
            raise InputError("backend 'ray' needs the ray package (pip install 'ray[default]')") from None
        register_ray()
    elif backend == "dask":
        try:
            from dask.distributed import Client, get_client
        except ImportError:
            raise InputError("backend 'dask' needs dask.distributed (pip install distributed)") from None
        try:
            get_client()
        except ValueError:
            Client()  # DASK_SCHEDULER_ADDRESS when set (dask config), else a local cluster


def summary(runs: Sequence[Run], budget: int) -> list[dict]:
    """One row per (feedback, method, basket): median attempts to the first hit and hit share.

    A run without a hit counts as ``budget + 1`` attempts, so a median above the budget means
    that more than half of the runs never hit.
    """
    groups: dict[tuple[str, str, float], list[Run]] = {}
    for run in runs:
        groups.setdefault((run.feedback, run.method, run.basket), []).append(run)
    rows = []
    for (feedback, method, basket), group in groups.items():
        counts = np.array([r.attempts if r.hit else budget + 1 for r in group])
        rows.append({
            "feedback": feedback, "method": method, "basket": basket, "runs": len(group),
            "median": float(np.median(counts)), "mean": float(np.mean(counts)),
            "hit_share": float(np.mean([r.hit for r in group])),
        })
    return rows


def format_table(runs: Sequence[Run], budget: int) -> str:
    """A Markdown table: per feedback and method, median attempts and hit share per basket."""
    rows = summary(runs, budget)
    baskets = sorted({r["basket"] for r in rows})
    by_key = {(r["feedback"], r["method"], r["basket"]): r for r in rows}
    keys = list(dict.fromkeys((r["feedback"], r["method"]) for r in rows))
    header = ["feedback", "method"]
    for basket in baskets:
        header += [f"median attempts, {basket:g} m", f"hit share, {basket:g} m"]
    header += ["median attempts, all"]
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for feedback, method in keys:
        cells = [feedback, method]
        for basket in baskets:
            row = by_key.get((feedback, method, basket))
            cells += ["" if row is None else _median_text(row["median"], budget),
                      "" if row is None else f"{row['hit_share']:.0%}"]
        every = [r.attempts if r.hit else budget + 1 for r in runs
                 if r.feedback == feedback and r.method == method]
        cells.append(_median_text(float(np.median(every)), budget))
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _median_text(value: float, budget: int) -> str:
    if value > budget:
        return f"> {budget}"
    return f"{value:g}" if math.isfinite(value) else ""


def runs_as_dicts(runs: Sequence[Run]) -> list[dict]:
    """The runs as plain dicts (for JSON)."""
    return [asdict(r) for r in runs]
