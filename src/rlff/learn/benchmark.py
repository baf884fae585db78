"""The learning benchmark: attempts to the first hit, per method, in a scenario, over seeds.

Every run starts from simulated human demonstrations (:mod:`rlff.learn.scenarios`: who
demonstrated, what is known of their landings), cleaned by the thesis preset, and runs one
method in the loop of :func:`rlff.learn.learn` against the MuJoCo simulation until the feedback
reports a hit or the budget is spent. The grid is seeds x baskets x feedback kinds x methods;
every method of a (seed, basket) pair sees the same demonstrations and the same information.
Seeds start at ``first_seed``: the methods were tuned on seeds below 100, so tables for the
record come from seeds 100 and above.

The runs are independent and go to joblib workers: local processes (``loky``), or a Dask
cluster given its scheduler's address (joblib's ``dask`` backend, which needs
``dask.distributed``).
"""

from __future__ import annotations

import contextlib
import math
import warnings
from collections.abc import Callable, Iterator, Sequence

from rlff.dataset import Dataset
from rlff.errors import InputError
from rlff.learn import statistics
from rlff.learn.scenarios import Feedback, Scenario, reporting_executor
from rlff.learn.scenarios import demonstrations as scenario_demonstrations
from rlff.learn.statistics import Run
from rlff.learn.strategies import PROJECT_METHODS

#: Methods run with each feedback kind: the project's methods with their ablations, then the
#: baselines that can use that feedback (CMA-ES, the secant and GP-BO need a distance).
METHODS_BY_FEEDBACK = {
    "binary": (
        "calibrate", "calibrate:no-exploration", "calibrate:gmr-mean",
        "donut", "donut:no-exploration", "donut:gmr-mean",
        "sweep", "random", "failure", "failure:no-exploration", "failure:gmr-mean", "imitation",
    ),
    "distance": (
        "calibrate", "calibrate:no-exploration", "calibrate:gmr-mean",
        "donut", "donut:no-exploration", "donut:gmr-mean",
        "secant", "gp-bo", "cma", "random", "hindsight", "hindsight:no-exploration",
        "hindsight:gmr-mean", "failure", "imitation",
    ),
}
#: Seed of the first run of the record: the methods were tuned on seeds below it.
HELD_OUT_SEEDS = 100
#: Seconds to wait for a Dask scheduler to answer.
SCHEDULER_TIMEOUT = 10.0


def demonstrations(seed: int, scenario: Scenario | str = "short") -> Dataset:
    """The demonstrations of one seed; a scenario given by name knows the landings exactly."""
    if isinstance(scenario, str):
        scenario = Scenario(scenario, landings="exact")
    return scenario_demonstrations(seed, scenario)


def run_one(demos: Dataset, scenario: Scenario, feedback: Feedback, method: str, basket: float, seed: int,
            budget: int) -> Run:
    """Run one method once from the demonstrations of ``seed``."""
    from rlff.learn.loop import learn

    result = learn(demos, basket, budget=budget, feedback=feedback.kind, update=method, seed=seed,
                   robot=scenario.robot, opening=scenario.opening,
                   executor=reporting_executor(scenario, feedback, basket, seed))
    return Run(scenario.name, scenario.landings, feedback.name, method, float(basket), seed, result.hit,
               result.attempts)


def learning_benchmark(
    scenario: Scenario | None = None,
    seeds: int = 8,
    *,
    first_seed: int = HELD_OUT_SEEDS,
    methods: dict[str, Sequence[str]] | None = None,
    budget: int = 20,
    jobs: int = 2,
    scheduler: str | None = None,
    progress: Callable[[Run], None] | None = None,
) -> list[Run]:
    """Run the grid seeds x baskets x feedback kinds x methods of one scenario.

    Parameters
    ----------
    scenario : Scenario, optional
        Demonstrators, landings, feedback kinds, basket opening and robot; default ``short``
        with no landings, binary and distance feedback.
    seeds : int
        Number of seeds, ``first_seed`` .. ``first_seed + seeds - 1``; each seed draws its own
        demonstrations.
    first_seed : int
        The first seed (default 100: above the seeds the methods were tuned on).
    methods : dict, optional
        Methods per feedback kind (``binary``, ``distance``); default :data:`METHODS_BY_FEEDBACK`.
    budget : int
        Attempts per run.
    jobs : int
        Parallel workers: local processes, or at most this many tasks at once on the cluster.
    scheduler : str, optional
        Address of a Dask scheduler (``tcp://host:8786``): the runs go to its workers.
    progress : callable, optional
        Called with every finished run.

    Returns
    -------
    list of Run
    """
    import joblib

    scenario = Scenario() if scenario is None else scenario
    methods = METHODS_BY_FEEDBACK if methods is None else methods
    if not (isinstance(seeds, int) and seeds >= 1) or not (isinstance(first_seed, int) and first_seed >= 0):
        raise InputError(f"seeds must be >= 1 and first seed >= 0, got {seeds!r} and {first_seed!r}")
    seed_list = range(first_seed, first_seed + seeds)
    cases = [(f, m, float(b), s) for s in seed_list for b in scenario.baskets
             for f in scenario.feedbacks for m in methods[f.kind]]
    with parallel_backend(scheduler), warnings.catch_warnings():
        # loky takes a worker's memory after its first task (the demonstrations) as the mark for
        # a leak and restarts it, with this warning, once it has grown by 300 MB: the runs' first
        # imports, compiled kernels and MuJoCo scenes do that (about 110 -> 370 MB), then it stays
        # flat (measured over 36 runs); the restart is harmless, the warning only alarms
        warnings.filterwarnings("ignore", message="A worker stopped while some jobs were given", category=UserWarning)
        parallel = joblib.Parallel(n_jobs=jobs, return_as="generator")
        # the demonstrations of every seed, made once and shipped to the workers with each run
        demos = dict(zip(seed_list, parallel(joblib.delayed(scenario_demonstrations)(s, scenario)
                                             for s in seed_list), strict=True))
        runs = []
        for run in parallel(joblib.delayed(run_one)(demos[s], scenario, f, m, b, s, budget)
                            for f, m, b, s in cases):
            runs.append(run)
            if progress:
                progress(run)
    return runs


@contextlib.contextmanager
def parallel_backend(scheduler: str | None) -> Iterator[None]:
    """joblib's local processes, or its Dask backend on the scheduler at ``scheduler``."""
    import joblib

    if scheduler is None:
        yield
        return
    try:
        from dask.distributed import Client
    except ImportError:
        raise InputError("--scheduler needs dask.distributed (pip install distributed)") from None
    try:
        client = Client(scheduler, timeout=SCHEDULER_TIMEOUT)
    except (OSError, TimeoutError, ValueError) as exc:
        raise InputError(f"--scheduler {scheduler!r}: no Dask scheduler answers there ({exc})") from None
    try:
        with joblib.parallel_config(backend="dask"):
            yield
    finally:
        client.close()


def report(runs: Sequence[Run], budget: int) -> dict:
    """``{"rows": [...], "comparisons": [...]}`` of :mod:`rlff.learn.statistics`."""
    return {
        "rows": statistics.rows(runs, budget, PROJECT_METHODS),
        "comparisons": statistics.comparisons(runs, budget, PROJECT_METHODS),
    }


def format_table(runs: Sequence[Run], budget: int) -> str:
    """A Markdown table: per feedback and method, the median, the mean, the hits, and the paired
    p-values of the project's methods against it."""
    result = report(runs, budget)
    p_values = {(c["scenario"], c["landings"], c["feedback"], c["method"], c["baseline"]): c["p_value"]
                for c in result["comparisons"]}
    compared = [name for name in PROJECT_METHODS if any(c["method"] == name for c in result["comparisons"])]
    header = ["scenario", "landings", "feedback", "method", "median", "mean", "hits",
              *[f"p vs {name}" for name in compared]]  # a column only for the project's methods that ran
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for row in result["rows"]:
        key = (row["scenario"], row["landings"], row["feedback"])
        name = row["method"] if row["baseline"] else f"**{row['method']}**"
        cells = [*key, name, _median_text(row["median"], budget), f"{row['mean']:.1f}",
                 f"{row['hits']}/{row['runs']}"]
        for mine in compared:
            p = p_values.get((*key, mine, row["method"]))
            cells.append("" if p is None else f"{p:.2g}")  # 0.00042 is not 0.000
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _median_text(value: float, budget: int) -> str:
    if value > budget:
        return f"> {budget}"
    return f"{value:g}" if math.isfinite(value) else ""

