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
``dask.distributed``: ``pip install 'rlff[cluster]'``).

Before any run, every basket of the grid is checked against the robot's reach
(:func:`require_reachable_baskets`): an arm of one's own that throws less far than the Comau
would otherwise fail at its first run of a far basket, after all the runs before it. The
results name the robot they were measured on (:func:`robot_identity`): a table of another arm
reads like the Comau's otherwise.
"""

from __future__ import annotations

import contextlib
import math
import warnings
from collections.abc import Callable, Iterator, Mapping, Sequence
from typing import Any

from rlff.dataset import Dataset
from rlff.errors import InputError
from rlff.learn import statistics
from rlff.learn.method import Method
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
        "hindsight:gmr-mean", "failure", "failure:no-exploration", "failure:gmr-mean", "imitation",
    ),
}
#: Seed of the first run of the record: the methods were tuned on seeds below it.
HELD_OUT_SEEDS = 100
#: Seconds to wait for a Dask scheduler to answer.
SCHEDULER_TIMEOUT = 10.0
#: The extra of pyproject.toml that brings ``distributed``, which ``scheduler`` needs.
CLUSTER_EXTRA = "cluster"


def demonstrations(seed: int, scenario: Scenario | str = "short") -> Dataset:
    """The demonstrations of one seed; a scenario given by name knows the landings exactly."""
    if isinstance(scenario, str):
        scenario = Scenario(scenario, landings="exact")
    return scenario_demonstrations(seed, scenario)


def run_one(demos: Dataset, scenario: Scenario, feedback: Feedback, method: str | type[Method], basket: float,
            seed: int, budget: int) -> Run:
    """Run one method (a name of :data:`rlff.learn.METHODS`, or a :class:`rlff.learn.Method`
    subclass) once from the demonstrations of ``seed``.

    Raises
    ------
    InputError
        The run's, prefixed with which run it is (scenario, landings, seed, basket, feedback,
        method): one run of hundreds that fails ends the benchmark with that one line.
    """
    from rlff.learn.loop import learn
    from rlff.robot.description import RobotFileWarning

    try:
        with warnings.catch_warnings():  # the robot file's warnings: said once, before the runs
            warnings.simplefilter("ignore", RobotFileWarning)
            result = learn(demos, basket, budget=budget, feedback=feedback.kind, update=method, seed=seed,
                           robot=scenario.robot, opening=scenario.opening, aim=scenario.aim,
                           executor=reporting_executor(scenario, feedback, basket, seed), executed_on="sim")
    except InputError as exc:
        raise InputError(f"{scenario.name}, landings {scenario.landings}, seed {seed}, basket {basket:g} m, "
                         f"{feedback.name} feedback, {getattr(method, 'name', method)}: {exc}") from None
    return Run(scenario.name, scenario.landings, feedback.name, result.update, float(basket), seed, result.hit,
               result.attempts)


def learning_benchmark(
    scenario: Scenario | None = None,
    seeds: int = 8,
    *,
    first_seed: int = HELD_OUT_SEEDS,
    methods: Mapping[str, Sequence[str | type[Method]] | str | type[Method]] | None = None,
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
        Methods per feedback kind (``binary``, ``distance``), a sequence of them or one alone
        (:func:`one_or_many`): names of :data:`rlff.learn.METHODS`
        or methods of one's own, :class:`rlff.learn.Method` subclasses, which the workers import
        by their module and name (a class in a module of one's own, not one made in a function);
        default :data:`METHODS_BY_FEEDBACK`. Only the scenario's feedback kinds it names run
        (``{"distance": (Faster, "secant")}`` runs those two with distance feedback and nothing
        with binary feedback).
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

    Raises
    ------
    InputError
        Before any run: a key of ``methods`` that is no feedback kind, a method that is none
        (:func:`rlff.learn.loop.method_of`) or is given for a feedback it cannot use, ``methods``
        that name none of the scenario's feedback kinds, or a basket out of reach.
    """
    import joblib

    scenario = Scenario() if scenario is None else scenario
    methods = METHODS_BY_FEEDBACK if methods is None else one_or_many(methods)
    if not (isinstance(seeds, int) and seeds >= 1) or not (isinstance(first_seed, int) and first_seed >= 0):
        raise InputError(f"seeds must be >= 1 and first seed >= 0, got {seeds!r} and {first_seed!r}")
    require_methods(methods, scenario)
    require_reachable_baskets([scenario])
    seed_list = range(first_seed, first_seed + seeds)
    cases = [(f, m, float(b), s) for s in seed_list for b in scenario.baskets
             for f in scenario.feedbacks for m in methods.get(f.kind, ())]
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
        # what the loop's throws reach depends on where the demonstrations let go: judged for
        # every seed here, as each run would judge it before its first throw, not 27 runs in
        require_learnable_baskets(scenario, demos)
        runs = []
        for run in parallel(joblib.delayed(run_one)(demos[s], scenario, f, m, b, s, budget)
                            for f, m, b, s in cases):
            runs.append(run)
            if progress:
                progress(run)
    return runs


def one_or_many(methods: Mapping[str, Sequence[str | type[Method]] | str | type[Method]],
                ) -> dict[str, Sequence[str | type[Method]]]:
    """``methods`` with one method given alone for a kind (a name, MODULE:CLASS or a class) taken
    as a list of it: ``{"binary": "sweep"}`` is ``{"binary": ("sweep",)}``. (A name had been
    taken letter by letter: ``unknown update 's'``.)"""
    return {kind: (named,) if isinstance(named, str | type) else named for kind, named in methods.items()}


def require_methods(methods: Mapping[str, Sequence[str | type[Method]]], scenario: Scenario) -> None:
    """Raise :class:`InputError` unless every key of ``methods`` is a feedback kind, every
    method a method (:func:`rlff.learn.loop.method_of`) that can use the feedback it is given
    for, no two of a kind's methods one method's name (:func:`method_classes`), and ``methods``
    names at least one method for a feedback kind of ``scenario``; said before any run, not by a
    worker (a kind the scenario runs and ``methods`` does not name had ended the benchmark with
    ``KeyError: 'binary'``)."""
    from rlff.learn.method import FEEDBACKS

    unknown = [kind for kind in methods if kind not in FEEDBACKS]
    if unknown:
        raise InputError(f"methods: {', '.join(map(repr, unknown))} is no feedback kind; give methods per feedback "
                         f"kind, {' or '.join(map(repr, FEEDBACKS))}, e.g. {{'distance': ('secant',)}}")
    for kind, named in methods.items():
        # a method of one's own that is not one fails here, and so do two of one name
        for method_class in method_classes(named, f"methods[{kind!r}]"):
            if kind not in method_class.feedbacks:
                raise InputError(f"methods[{kind!r}]: {method_class.name} needs {' or '.join(method_class.feedbacks)} "
                                 f"feedback, not {kind}; give it under {method_class.feedbacks[0]!r}")
    kinds = list(dict.fromkeys(feedback.kind for feedback in scenario.feedbacks))
    if not any(methods.get(kind) for kind in kinds):
        named = [kind for kind, listed in methods.items() if listed]
        raise InputError(f"methods name methods for {' and '.join(named) or 'no'} feedback, and scenario "
                         f"{scenario.name} runs {' and '.join(kinds)} feedback: nothing to run; give methods for "
                         f"{' or '.join(map(repr, kinds))}, or a Scenario whose feedbacks are of the kinds named")


def method_classes(named: Sequence[str | type[Method]], where: str = "methods") -> list[type[Method]]:
    """The method class each of ``named`` is (:func:`rlff.learn.loop.method_of`: a built-in
    method's name, MODULE:CLASS or a :class:`rlff.learn.Method` subclass), in order.

    Raises
    ------
    InputError
        ``method_of``'s, or two of ``named`` that are one method's ``name`` (the same name twice, a
        class and its MODULE:CLASS, two classes of one name): a benchmark's rows and runs know a
        method by its name, so its runs would count twice in one row. Said as ``where`` (e.g.
        ``--methods``) names the list.
    """
    from rlff.learn.loop import method_of

    classes = [method_of(method) for method in named]
    first: dict[str, str | type[Method]] = {}
    for method, method_class in zip(named, classes, strict=True):
        if method_class.name not in first:
            first[method_class.name] = method
            continue
        before = first[method_class.name]
        if before == method:
            raise InputError(f"{where}: {_given(method)!r} given twice: its runs would count twice in one row")
        raise InputError(f"{where}: {_given(before)} and {_given(method)} are both the method {method_class.name!r}: "
                         "its runs would count twice in one row")
    return classes


def _given(method: str | type[Method]) -> str:
    """A method as it was given: its name (or MODULE:CLASS), or ``class MODULE.CLASS``."""
    return method if isinstance(method, str) else f"class {method.__module__}.{method.__qualname__}"


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
        # said as the other missing packages are (rlff.cli.missing_package): the extra that brings it
        raise InputError(f"--scheduler needs the Python package distributed (dask.distributed), from rlff's optional "
                         f"'{CLUSTER_EXTRA}' extra, which is not installed in this Python: install it with "
                         f"`pip install 'rlff[{CLUSTER_EXTRA}]'`") from None
    try:
        client = Client(scheduler, timeout=SCHEDULER_TIMEOUT)
    except (OSError, TimeoutError, ValueError) as exc:
        raise InputError(f"--scheduler {scheduler!r}: no Dask scheduler answers there ({exc})") from None
    try:
        with joblib.parallel_config(backend="dask"):
            yield
    finally:
        client.close()


def report(runs: Sequence[Run], budget: int, robot: dict[str, Any] | None = None) -> dict:
    """``{"rows": [...], "comparisons": [...]}`` of :mod:`rlff.learn.statistics`, each row and
    comparison with the ``budget`` its runs had (a run without a hit counts as budget + 1: a median
    of 11 with budget 10 is "never hit", and rows of several files stay readable side by side),
    and ``"robot"`` (:func:`robot_identity`) when given."""
    result: dict[str, Any] = {} if robot is None else {"robot": robot}
    result["rows"] = [{**row, "budget": budget} for row in statistics.rows(runs, budget, PROJECT_METHODS)]
    result["comparisons"] = [{**pair, "budget": budget} for pair in statistics.comparisons(runs, budget, PROJECT_METHODS)]
    return result


def robot_identity(robot: str) -> dict[str, Any]:
    """The robot a benchmark runs on, as its table and ``--json`` name it.

    Parameters
    ----------
    robot : str
        A built-in robot's name or a robot file (:attr:`Scenario.robot`).

    Returns
    -------
    dict
        ``name`` (the robot file's ``name``), ``file`` (the file as given, None for a built-in
        robot) and ``digest``: the digest an attempts log of ``rlff learn`` with this robot
        records (:func:`rlff.learn.log.robot_record`), so that a table can be matched with logs.
    """
    from rlff.learn.log import robot_record
    from rlff.robot import RobotMapping, load_robot
    from rlff.robot.description import available_robots

    description = load_robot(robot)
    built_in = robot in available_robots()
    return {"name": description.name, "file": None if built_in else str(robot),
            "digest": robot_record(RobotMapping.for_robot(description))["digest"]}


def robot_words(identity: dict[str, Any]) -> str:
    """"ur5e_like (robot file arms/ur5e.toml, digest b26ab21fb834f341)", or "(built in, ...)"."""
    where = "built in" if identity.get("file") is None else f"robot file {identity['file']}"
    return f"{identity['name']} ({where}, digest {identity['digest']})"


def require_reachable_baskets(scenarios: Sequence[Scenario]) -> None:
    """Raise :class:`InputError` before any run when a basket of ``scenarios`` is beyond the
    robot's reach, as :func:`rlff.sim.require_reachable` judges it for the joints the loop throws
    with (the robot file's mapping) on the floor.

    The message names the robot, the basket and the farthest basket the robot reaches, which of
    the scenarios' own baskets it reaches and how to pass others, or, for baskets chosen
    (``--baskets``), how far they may be.
    """
    from rlff.learn.scenarios import DEMONSTRATORS
    from rlff.robot import RobotMapping, load_robot
    from rlff.sim import Basket
    from rlff.sim.reach import (
        PLANE_JOINTS,
        came_down_words,
        centimetres_below,
        executable_reach,
        farthest_basket,
        farthest_words,
        throw_reach,
    )

    for robot in dict.fromkeys(s.robot for s in scenarios):
        description = load_robot(robot)
        mapping = RobotMapping.for_robot(description)
        mine = [s for s in scenarios if s.robot == robot]
        farthest, beyond, within = {}, {}, {}  # farthest basket (m) per opening; the baskets out and in
        for scenario in mine:
            rim = Basket(scenario.baskets[0], opening=scenario.opening).rim_height
            # the mapping's own throws (its joint alone, released where it throws farthest): the
            # free pose of throw_reach put a joint_3 thrower's joint_2 at its limit, 0.25 m farther
            reach = (executable_reach(mapping, rim, 0.0).distance if mapping.joint in PLANE_JOINTS
                     else throw_reach(description, rim, 0.0, ("joint_2",)).distance)
            farthest[scenario.opening] = (reach, rim, farthest_basket(reach, scenario.opening))
            for distance in scenario.baskets:
                side = within if distance <= farthest[scenario.opening][2] else beyond
                side.setdefault(distance, scenario)
        if not beyond:
            continue
        distance, scenario = min(beyond.items())
        reach, rim, edge = farthest[scenario.opening]
        who = f"{description.name} ({'built in' if robot == description.name else robot})"
        chosen = scenario.baskets != DEMONSTRATORS[scenario.demonstrators].baskets
        alone = (f"{mapping.joint} alone at its speed limit (the other joints at the [throwing] start pose)"
                 if mapping.joint in PLANE_JOINTS else "joint_2 at its speed limit")
        why = f"throwing with {alone}, the ball {came_down_words(reach, rim)}, so {farthest_words(edge, scenario.opening)}"
        if chosen:
            raise InputError(f"--baskets: basket at {distance:.2f} m is out of reach of {who}: {why}; give baskets "
                             f"up to {centimetres_below(edge)} m")
        named = ", ".join(dict.fromkeys(s.demonstrators for s in mine))
        reached = sorted(within)
        among = (f"of the baskets of {named} ({_metres(sorted({*beyond, *within}))}) it reaches "
                 + (_metres(reached) if reached else "none"))
        example = f", e.g. --baskets {','.join(f'{d:g}' for d in reached)}" if reached else ""
        option = f"--robot {robot}" + ("" if robot == description.name else f" ({description.name})")
        raise InputError(f"{option} does not reach the basket at {distance:.2f} m of "
                         f"scenario {scenario.demonstrators}: {why}; {among}: pass baskets within its reach with "
                         f"--baskets{example} (rlff sim reach --robot {robot} for what it throws)")


def require_learnable_baskets(scenario: Scenario, demos: dict[int, Dataset]) -> None:
    """Raise :class:`InputError` when a basket of ``scenario`` is beyond what the learning loop's
    throws reach from the demonstrations of a seed (``demos``: seed to demonstrations), as
    :func:`rlff.learn.learn` judges it before its first throw
    (:func:`rlff.learn.loop.learnable_basket`): within the robot's reach
    (:func:`require_reachable_baskets`), a throw from where the demonstrations let go may still
    fall short of it."""
    from rlff.learn.loop import learnable_basket
    from rlff.learn.scenarios import DEMONSTRATORS
    from rlff.robot import load_robot, mapping_for
    from rlff.sim import Basket
    from rlff.sim.reach import centimetres_below

    description = load_robot(scenario.robot)
    mapping = mapping_for(description, None)
    for seed, shown in demos.items():
        farthest = {distance: learnable_basket(shown, mapping, Basket(distance, opening=scenario.opening), seed=seed)
                    for distance in scenario.baskets}
        beyond = [distance for distance in scenario.baskets if distance > farthest[distance]]
        if not beyond:
            continue
        distance = min(beyond)
        within = [d for d in scenario.baskets if d not in beyond]
        chosen = scenario.baskets != DEMONSTRATORS[scenario.demonstrators].baskets
        option = "--baskets" if chosen else f"--robot {scenario.robot}" + (
            "" if scenario.robot == description.name else f" ({description.name})")
        kept = f"; it reaches {_metres(within)}" if within else ""
        raise InputError(
            f"{option}: the basket at {distance:.2f} m is out of reach of the throws {description.name} executes from "
            f"the demonstrations of scenario {scenario.demonstrators}, seed {seed} (released where they let go, as "
            f"late as the last of them, as rlff learn judges it before its first throw): the farthest basket with a "
            f"{scenario.opening:.2f} m opening is at {centimetres_below(farthest[distance])} m{kept}: pass nearer "
            "baskets with --baskets")


def _metres(distances: Sequence[float]) -> str:
    return ", ".join(f"{d:.2f}" for d in distances) + " m"


def format_table(runs: Sequence[Run], budget: int, robot: dict[str, Any] | None = None) -> str:
    """A Markdown table: per feedback and method, the median, the mean, the hits, and the paired
    p-values of the project's methods against it; under a line naming the robot
    (:func:`robot_identity`) when given."""
    result = report(runs, budget)
    p_values = {(c["scenario"], c["landings"], c["feedback"], c["method"], c["baseline"]): c["p_value"]
                for c in result["comparisons"]}
    compared = [name for name in PROJECT_METHODS if any(c["method"] == name for c in result["comparisons"])]
    header = ["scenario", "landings", "feedback", "method", "median", "mean", "hits",
              *[f"p vs {name}" for name in compared]]  # a column only for the project's methods that ran
    lines = [] if robot is None else [f"Robot: {robot_words(robot)}", ""]
    lines += ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
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

