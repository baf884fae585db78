"""``rlff bench ...``: benchmarks that measure rlff on its own tasks."""

from __future__ import annotations

import typer

from rlff.cli._common import (
    MAX_SEED,
    PLAIN_HELP,
    basket_options,
    emit_json,
    progress,
    seed_option,
    stdout,
    warn,
)
from rlff.errors import InputError

app = typer.Typer(rich_markup_mode=PLAIN_HELP, help="Benchmarks: how many attempts learning takes, and against which baselines.",
                  no_args_is_help=True)


def _names(option: str, text: str, known: list[str] | None = None) -> list[str]:
    names = [n.strip() for n in text.split(",") if n.strip()]
    if not names:
        raise InputError(f"{option}: give at least one name")
    unknown = [n for n in names if known is not None and n not in known]
    if unknown:
        raise InputError(f"{option}: unknown {', '.join(map(repr, unknown))} (known: {', '.join(known)})")
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:  # each case would run again and count again in its row's runs and hits
        raise InputError(f"{option}: {', '.join(map(repr, twice))} given twice")
    return names


def _method_classes(names: list[str]) -> dict:
    """``--methods``' names, each the method class it names, checked before any run as the
    library checks them (:func:`rlff.learn.benchmark.method_classes`: two of one ``name`` are
    refused), a name that is no method said with the option."""
    from rlff.learn.benchmark import method_classes
    from rlff.learn.loop import method_of

    for name in names:
        try:
            method_of(name)
        except InputError as exc:
            raise InputError(f"--methods: {exc}") from None
    return dict(zip(names, method_classes(names, "--methods"), strict=True))


def _parsed(option: str, text: str, parse) -> list:
    """Each name of the comma-separated ``text`` (:func:`_names`) read by ``parse``, an error of
    ``parse`` said with the option (the list's own faults name it once: it had read "--landings:
    --landings: 'exact' given twice"). Two names ``parse`` reads as one value are refused as one
    given twice: ``noisy:0.3,noisy:0.30`` had run every case twice and counted both in one row."""
    named = _names(option, text)
    try:
        values = [parse(name) for name in named]
    except InputError as exc:
        raise InputError(f"{option}: {exc}") from None
    for index, value in enumerate(values):
        first = values.index(value)
        if first < index:
            raise InputError(f"{option}: {named[first]!r} and {named[index]!r} are one case given twice")
    return values


@app.command("learning")
def learning(
    seeds: int = typer.Option(8, "--seeds", min=1, help="Seeds (each draws its own demonstrations)."),
    first_seed: int = seed_option("First seed; the methods were tuned on seeds below 100.",
                                  name="--first-seed", default=100),
    scenario: str = typer.Option("short", "--scenario",
                                 help="Demonstrators, comma-separated: short, wide, overshooting, near, mixed "
                                      "(or all)."),
    landings: str = typer.Option("none", "--landings",
                                 help="What is known of the demonstrations' landings, comma-separated: "
                                      "exact, noisy:STD (m) or none."),
    feedback: str = typer.Option("binary,distance", "--feedback",
                                 help="Comma-separated: binary, distance, noisy-distance:STD (m), "
                                      "false-miss:RATE."),
    opening: float = typer.Option(0.35, "--opening", help="Inner width of the basket (m)."),
    baskets: str | None = typer.Option(None, "--baskets",
                                       help="Basket distances (m), comma-separated; default each scenario's own "
                                            "(wide 1.25 and 1.75 m, the others 1.4 and 1.9 m). Within your "
                                            "robot's reach (rlff sim reach)."),
    robot: str = typer.Option("comau_smart5_six", "--robot", help="Robot name or robot file."),
    gap: str = typer.Option("none", "--gap",
                            help="How the simulated arm differs from the robot file, comma-separated: none, "
                                 "speed:G (reaches G of the commanded speed, 0 < G <= 1), delay:S (lets go S s "
                                 "late)."),
    aim: str = typer.Option("auto", "--aim",
                            help="Where every method's speed starts, comma-separated, one case each (rlff learn "
                                 "--aim): auto, kinematics (where the robot file's kinematics send the throw: "
                                 "calibrate's speed search centres there, donut lays the DMM's ring about it (the "
                                 "aim itself, the ring's hole, comes late), the GMR baselines start "
                                 "there, failure and hindsight throw the DMM's throw sped up or slowed down to "
                                 "it; their ablations too), demonstrations."),
    methods: str | None = typer.Option(None, "--methods",
                                       help="Comma-separated methods (default: every method that can use "
                                            "the feedback), as rlff learn --update names them: a method of your "
                                            "own as MODULE:CLASS, e.g. faster:Faster for faster.py here."),
    quick: bool = typer.Option(False, "--quick", help="A small grid: 2 seeds, budget 12."),
    budget: int = typer.Option(20, "--budget", min=1, help="Attempts per run."),
    jobs: int = typer.Option(2, "--jobs", min=1, help="Parallel workers."),
    scheduler: str | None = typer.Option(None, "--scheduler",
                                         help="Address of a Dask scheduler to run on (tcp://HOST:PORT)."),
    as_json: bool = typer.Option(False, "--json", help='Print {"robot": {...}, "rows": [...], "comparisons": [...]}, '
                                                       "each row and comparison with its budget."),
) -> None:
    """Attempts to the first hit over seeds x baskets x feedback kinds x methods, per scenario."""
    from rlff.learn.benchmark import (
        METHODS_BY_FEEDBACK,
        learning_benchmark,
        require_reachable_baskets,
        robot_identity,
    )
    from rlff.learn.scenarios import (
        DEMONSTRATORS,
        Scenario,
        parse_feedback,
        parse_gap,
        parse_landings,
    )
    from rlff.limits import check_distance, parse_number

    people = list(DEMONSTRATORS) if scenario == "all" else _names("--scenario", scenario, list(DEMONSTRATORS))
    knowledge = _parsed("--landings", landings, parse_landings)
    feedbacks = tuple(_parsed("--feedback", feedback, parse_feedback))
    gaps = _parsed("--gap", gap, parse_gap)
    from rlff.learn.loop import AIMS

    aims = _names("--aim", aim, list(AIMS))
    chosen = None
    if methods is not None:
        wanted = _names("--methods", methods)
        classes = _method_classes(wanted)
        chosen = {kind: [classes[m] for m in wanted if kind in classes[m].feedbacks] for kind in METHODS_BY_FEEDBACK}
    distances = None if baskets is None else tuple(
        check_distance("--baskets", parse_number(part, "--baskets")) for part in _names("--baskets", baskets))
    if distances is not None and len(set(distances)) < len(distances):
        raise InputError(f"--baskets {baskets}: a distance given twice")
    try:
        cases = [Scenario(name, landings=known, feedbacks=feedbacks, opening=opening, robot=robot, gap=arm,
                          baskets=distances, aim=where)
                 for name in people for known in knowledge for arm in gaps for where in aims]
    except InputError as exc:
        raise InputError(f"--opening: {exc}") from None
    try:
        identity = robot_identity(robot)
    except InputError as exc:
        raise InputError(f"--robot: {exc}") from None
    # said before the runs start, not by the first run of a basket out of reach (27 runs in)
    with basket_options(opening="--opening"):
        require_reachable_baskets(cases)
    if quick:
        seeds, budget = min(seeds, 2), min(budget, 12)
    if first_seed + seeds - 1 > MAX_SEED:
        raise InputError(f"--first-seed {first_seed} with --seeds {seeds} runs past the largest seed, "
                         f"{MAX_SEED}: give a smaller --first-seed")
    grid = chosen or METHODS_BY_FEEDBACK
    total = sum(seeds * len(case.baskets) * len(grid[f.kind]) for case in cases for f in case.feedbacks)
    if chosen is not None:
        kinds = {f.kind for f in feedbacks}
        unused = [name for name in wanted if not kinds & set(classes[name].feedbacks)]
        needs = "; ".join(f"{name}: {', '.join(classes[name].feedbacks)}" for name in unused)
        if total == 0:  # every method chosen needs another feedback than those given
            raise InputError(f"no method of --methods {methods} works with --feedback {feedback} ({needs})")
        if unused:
            warn(f"--methods: {', '.join(unused)} left out: no --feedback {feedback} they can use ({needs})")
    runs = []  # every finished run, as it finishes: a stopped sweep still reports them

    def finished(run) -> None:
        runs.append(run)
        advance(1)

    try:
        with progress("learning benchmark", total=total) as advance:
            for case in cases:
                learning_benchmark(case, seeds, first_seed=first_seed, methods=chosen, budget=budget,
                                   jobs=jobs, scheduler=scheduler, progress=finished)
    except KeyboardInterrupt:  # Ctrl-C or SIGTERM: the runs that finished are said, then the stop
        if runs:
            warn(f"stopped after {len(runs)} of {total} runs: the {'JSON' if as_json else 'table'} holds those "
                 "alone (each row its runs; comparisons over the seed and basket pairs both methods ran)")
            _say(runs, budget, identity, seeds, first_seed, as_json, stopped=(len(runs), total))
        raise
    _say(runs, budget, identity, seeds, first_seed, as_json)


def _say(runs: list, budget: int, identity: dict, seeds: int, first_seed: int, as_json: bool,
         stopped: tuple[int, int] | None = None) -> None:
    """The benchmark's ``runs`` as ``--json`` or the table on stdout; ``stopped``: (runs finished,
    runs asked for) of a sweep a stop signal ended, said in the JSON (``"stopped"``) and above the
    table."""
    from rlff.learn.benchmark import format_table, report

    if as_json:
        result = report(runs, budget, identity)
        if stopped is not None:
            result["stopped"] = {"runs": stopped[0], "of": stopped[1]}
        emit_json(result)
        return
    drawn = f"Seed {first_seed}" if seeds == 1 else f"Seeds {first_seed}-{first_seed + seeds - 1}"
    if stopped is not None:
        drawn = f"Stopped after {stopped[0]} of {stopped[1]} runs. {drawn}"
    stdout().print(f"{drawn}, budget {budget} (a run without a hit counts as {budget + 1}); p: paired Wilcoxon "
                   "signed-rank, two-sided.\n", highlight=False, markup=False)
    stdout().print(format_table(runs, budget, identity), highlight=False, markup=False)
