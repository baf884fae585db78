"""The whole idea on built-in data, in one call: ``run_demo(out_dir)`` (``rlff demo``).

Simulated people throw at baskets from 1 to 4 m and mostly miss → the thesis' cleaning steps →
the number of Gaussian components by BIC → the model → a throw for every basket distance, also
distances nobody demonstrated → the robot (Comau Smart5 SiX) throws each of them in MuJoCo with
joint 2 alone, as the thesis did → for a distance nobody demonstrated, the robot learns from its
failures until it hits → then the whole arm (:mod:`rlff.whole_arm_demo`): people who throw with
shoulder and elbow, and the robot learning every demonstrated and unseen basket from 1 to 4.5 m
at bearings 0 to 90 deg with joints 2, 3 (and 5) → figures, a ``run.json`` and a self-contained
HTML report in ``out_dir``.

Layout of ``out_dir``: ``report.html``, ``run.json`` (see :mod:`rlff.report.run`),
``figures/*.png|svg``, ``demos.csv`` (the simulated recordings), ``clean.csv`` (after the
preprocessing), ``model.json``, ``attempts/<method>.jsonl`` (the learning runs' logs),
``whole-arm-demos.csv``, ``whole-arm-clean.csv`` and ``attempts/whole-arm/*.jsonl``; the
listing of what the run wrote, ``.rlff-run``, and the lock the run holds the folder with,
``.rlff-run.lock`` (:mod:`rlff.report.folder`).
"""

from __future__ import annotations

import math
import platform
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from rlff.dataset import Dataset, write_csv
from rlff.errors import InputError
from rlff.report import FigureEntry, Run, Section, Table, build_report, write_run
from rlff.report.folder import RunFolder, RunPaths, check_run_folder
from rlff.synthetic.throws import THESIS_DISTANCES
from rlff.whole_arm_demo import BasketRun, basket_log, baskets, whole_arm_section
from rlff.wording import signed_metres

if TYPE_CHECKING:
    from rlff.sim.gap import Gap

#: What happens, in order; ``progress`` is called with each as it starts.
STAGES = (
    "simulating human demonstrations",
    "preprocessing (thesis preset)",
    "choosing K by BIC and fitting the model",
    "generating throws for every distance",
    "throwing them with the simulated robot",
    "learning from failure",
    "whole arm: learning every basket around the robot",
    "drawing the figures",
    "writing the report",
)


@dataclass(frozen=True)
class DemoSize:
    """How much the demo does.

    Attributes
    ----------
    subjects : int
        Simulated people.
    distances : tuple of float
        Basket distances they throw at (m).
    throws_per_distance : int
        Throws of each person at each basket.
    budget : int
        Most attempts of each learning run.
    methods : tuple of (update, feedback)
        The learning runs, compared in the learning curve.
    whole_arm_baskets : tuple of (distance, bearing)
        The whole-arm baskets (m, deg), known before the run as the names of their attempts
        logs are (:func:`run_files`).
    """

    subjects: int
    distances: tuple[float, ...]
    throws_per_distance: int
    budget: int
    methods: tuple[tuple[str, str], ...]
    whole_arm_baskets: tuple[tuple[float, float], ...]


#: How the arm the learning is shown on differs from its robot file when, on the arm as the file
#: describes it, the loop's first throw hits at every reachable distance (the demonstrations'
#: labels read through the range law put it there, as on the full plan's people): it reaches
#: 90 % of the commanded joint speeds, as a loaded arm or a lagging controller may (a
#: :class:`rlff.sim.gap.Gap`, the learning benchmark's ``--gap``), and the robot has to
#: learn that from its misses.
SHOWCASE_GAP = "speed:0.9"

SIZES = {
    # the thesis' recording plan (section 4.2): 10 people, 4 throws at each of 10 baskets
    "full": DemoSize(
        subjects=10,
        distances=(1.0, 1.5, 2.0, 2.25, 2.5, 2.75, 3.0, 3.25, 3.5, 4.0),
        throws_per_distance=4,
        budget=15,
        methods=(
            ("calibrate", "binary"),
            ("hindsight", "distance"),
            ("failure", "binary"),
            ("secant", "distance"),
            ("imitation", "binary"),
        ),
        # every distance the whole-arm people aim at (the thesis' ten) and the unseen ones, the
        # bearings in turn
        whole_arm_baskets=tuple(baskets(THESIS_DISTANCES)),
    ),
    # for tests and a first look: fewer people and baskets, two learning runs
    "small": DemoSize(
        subjects=4,
        distances=(1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0),
        throws_per_distance=3,
        budget=8,
        methods=(("calibrate", "binary"), ("imitation", "binary")),
        whole_arm_baskets=((2.0, 0.0), (3.75, 60.0), (4.5, 90.0)),
    ),
}


@dataclass(frozen=True)
class ThrowRow:
    """One generated throw executed by the simulated robot."""

    distance: float
    demonstrated: bool
    reachable: bool
    hit: bool
    landing: float
    miss: float


@dataclass(frozen=True)
class LearningRow:
    """One learning run: a method, its feedback and how it went."""

    method: str
    feedback: str
    hit: bool
    attempts: int
    misses: list[float]


@dataclass
class DemoSummary:
    """What a demo run did and where it put things.

    Attributes
    ----------
    out_dir, report, run_json : Path
    figures : list of Path
        The PNG files (an SVG beside each).
    size : str
    seed : int
    demonstrations, demonstration_hits : int
        Simulated throws, and how many of them hit.
    clean_trajectories : int
        Trajectories left after the preprocessing.
    demonstrated_distances : list of float
        Distances left after the preprocessing (m).
    components : int
        K chosen by BIC.
    throws : list of ThrowRow
        The model's throw for every distance, executed in the simulation.
    learning_distance : float
        The distance (m) of the learning runs; nobody demonstrated it (unless every reachable new
        distance is hit at the first throw).
    learning_arm : str
        How the arm of the learning runs differs from its robot file: ``none``, or
        :data:`SHOWCASE_GAP` where the loop's first throw hits everywhere on the faithful arm.
    learning : list of LearningRow
    whole_arm : list of BasketRun
        The whole-arm learning run of every basket (see :mod:`rlff.whole_arm_demo`).
    stage_seconds : dict of str to float
        Wall time of each stage (s).
    seconds : float
        Wall time of the whole run (s).
    """

    out_dir: Path
    report: Path
    run_json: Path
    figures: list[Path]
    size: str
    seed: int
    demonstrations: int
    demonstration_hits: int
    clean_trajectories: int
    demonstrated_distances: list[float]
    components: int
    throws: list[ThrowRow]
    learning_distance: float
    learning_arm: str
    learning: list[LearningRow]
    whole_arm: list[BasketRun] = field(default_factory=list)
    stage_seconds: dict[str, float] = field(default_factory=dict)
    seconds: float = 0.0

    @property
    def learning_setting(self) -> str:
        """Where the learning basket stands and on which arm, in a few words for a title:
        ``not demonstrated`` or ``demonstrated``, then the arm where it is not its robot file."""
        from rlff.sim.gap import parse_gap

        where = "demonstrated" if self.learning_distance in self.demonstrated_distances else "not demonstrated"
        gap = parse_gap(self.learning_arm)
        return where if gap.none else f"{where}; the arm {arm_words(gap)}"

    def to_json(self) -> dict[str, Any]:
        """Plain values for ``rlff demo --json``."""
        data = asdict(self)
        for key in ("out_dir", "report", "run_json"):
            data[key] = str(data[key])
        data["figures"] = [str(p) for p in self.figures]
        return _finite(data)


def _finite(value: Any) -> Any:
    """Replace NaN and inf by None, recursively, so the result is strict JSON."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: _finite(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_finite(v) for v in value]
    return value


class _Clock:
    """Times the stages and reports each to ``progress`` as it starts."""

    def __init__(self, progress: Callable[[str, int, int], None] | None) -> None:
        self.progress = progress
        self.seconds: dict[str, float] = {}
        self.start = time.perf_counter()
        self._current: tuple[str, float] | None = None

    def stage(self, name: str) -> None:
        self._close()
        if self.progress is not None:
            self.progress(name, STAGES.index(name), len(STAGES))
        self._current = (name, time.perf_counter())

    def note(self, text: str) -> None:
        """Tell ``progress`` what the current stage is doing, without ending it."""
        if self.progress is not None and self._current is not None:
            self.progress(text, STAGES.index(self._current[0]), len(STAGES))

    def _close(self) -> None:
        if self._current is not None:
            name, began = self._current
            self.seconds[name] = round(time.perf_counter() - began, 3)
            self._current = None

    def finish(self) -> float:
        self._close()
        if self.progress is not None:
            self.progress("done", len(STAGES), len(STAGES))
        return time.perf_counter() - self.start


def _forward(velocity: np.ndarray) -> np.ndarray:
    """The velocity (rad/s) with dips below zero set to zero: the demo's throws move forward
    (increasing angle), and a mixture's output can dip just below zero where a throw starts
    from rest."""
    return np.maximum(velocity, 0.0)


def _output_distances(demonstrated: list[float], farthest: float) -> tuple[list[float], list[float]]:
    """Distances to generate throws for: three demonstrated ones (nearest, middle, farthest) and
    some nobody demonstrated: the middles of the two widest gaps between demonstrated distances
    within the robot's reach (``farthest``, m), of the widest gap beyond it, and one distance
    beyond the farthest demonstration."""
    shown = sorted({demonstrated[0], demonstrated[len(demonstrated) // 2], demonstrated[-1]})
    gaps = sorted(((b - a, round(0.5 * (a + b), 3)) for a, b in zip(demonstrated, demonstrated[1:], strict=False)),
                  reverse=True)
    within = [middle for _, middle in gaps if middle <= farthest - 0.05][:2]
    beyond = [middle for _, middle in gaps if middle > farthest - 0.05][:1]
    if not within:  # nothing demonstrated on both sides of a reachable distance: halfway to the nearest one
        nearest = min(demonstrated)
        candidate = round(min(farthest - 0.1, nearest + 0.5) if nearest < farthest else farthest - 0.2, 3)
        within = [candidate] if all(abs(candidate - d) > 0.05 for d in demonstrated) else []
    new = {*within, *beyond, round(demonstrated[-1] + 0.5, 3)}
    return shown, sorted(new)


def _learning_distance(demonstrated: list[float], farthest: float,
                       first_throw: Callable[[float], tuple[bool, float]]) -> tuple[float, bool]:
    """The basket the robot learns at, and whether the learning loop's own first throw misses
    there (``first_throw(distance)``: its hit and signed miss in m), so that learning has
    something to do: on a 0.1 m grid of reachable distances at least 0.1 m from every
    demonstrated one, where that throw misses by most; else the reachable demonstrated distance
    where it misses by most; else (it hits everywhere) the one where it lands farthest from the
    basket's middle."""
    grid = np.round(np.arange(min(demonstrated) + 0.1, farthest - 0.05 + 1e-9, 0.1), 3)
    new = [float(d) for d in grid if all(abs(d - x) >= 0.1 - 1e-9 for x in demonstrated)]
    throws: dict[float, tuple[bool, float]] = {}

    def by_miss(d: float) -> float:
        return abs(throws[d][1]) if math.isfinite(throws[d][1]) else -1.0

    for candidates in (new, [d for d in demonstrated if d <= farthest]):
        throws.update({d: first_throw(d) for d in candidates})
        missed = [d for d in candidates if not throws[d][0]]
        if missed:
            return max(missed, key=by_miss), True
    if not throws:
        raise InputError("no demonstrated or new distance is within the robot's reach: no basket to learn at")
    return max(throws, key=by_miss), False


def _learning_arm_and_basket(demonstrated: list[float], learnable: float,
                             first_throw: Callable[[float, Gap], tuple[bool, float]]) -> tuple[Gap, float]:
    """The arm and the basket the learning is shown on: the arm as its robot file says where the
    loop's first throw misses somewhere (:func:`_learning_distance`); else one that is not its
    file (:data:`SHOWCASE_GAP`), among the distances that arm reaches (a drag-free range goes as
    the speed squared); else (it hits everywhere there too) the arm as its file says after all.
    ``first_throw(distance, gap)``: the loop's first throw's hit and signed miss (m)."""
    from rlff.sim.gap import Gap, parse_gap

    faithful = Gap()
    distance, missed = _learning_distance(demonstrated, learnable, lambda d: first_throw(d, faithful))
    if missed:
        return faithful, distance
    slower = parse_gap(SHOWCASE_GAP)
    on_slower, missed = _learning_distance(demonstrated, learnable * slower.speed**2,
                                           lambda d: first_throw(d, slower))
    return (slower, on_slower) if missed else (faithful, distance)


#: The data, model, run and report files every run writes, whatever its size, inside its folder.
DATA_FILES = (
    "demos.csv", "clean.csv", "model.json", "run.json", "report.html", "whole-arm-demos.csv", "whole-arm-clean.csv",
)
#: The figures a run draws, by stem (``figures/STEM.png`` and ``.svg``): ``learned-throw`` where a
#: method hits, the whole-arm two where a whole-arm basket was thrown at.
FIGURES = (
    "demonstrations-per-distance", "preprocessing", "clean-3d", "bic", "kmeans-em", "components", "donuts",
    "dmm-density", "outputs", "first-throw", "learning", "learned-throw", "whole-arm-flights", "whole-arm-joints",
)
#: The learned throw rendered by MuJoCo (:mod:`rlff.sim.render`): its frames, numbered from 0 (one
#: of an earlier, longer throw removed), and the GIF.
FRAMES = ("figures/frames/frame_*.png", "figures/frames/throw.gif")
#: The names of every file a run writes, whatever its size, as paths inside its folder (``*``: one
#: name): the last run's listing names only files of these to be removed (:mod:`rlff.report.folder`).
WRITES = (
    *DATA_FILES,
    "attempts/*.jsonl", "attempts/*.jsonl.lock", "attempts/whole-arm/*.jsonl", "attempts/whole-arm/*.jsonl.lock",
    "figures/*.png", "figures/*.svg", *FRAMES,
)
PROGRAM = "rlff demo"


def _failures(raw, said: str) -> str:
    """``most throws miss`` when most of ``raw``'s throws missed, else ``34 of 84 throws miss``
    (a seed's people may hit more often than not): ``said`` after the count."""
    misses = sum(1 for t in raw if t.meta.get("hit") is False)
    return f"most {said}" if 2 * misses > len(raw) else f"{misses} of {len(raw)} {said}"


def run_files(size: str, *, frames: bool = True) -> tuple[str, ...]:
    """Every file a run of ``size`` (``frames``: rendering the learned throw) writes or may write,
    by name, as paths inside its folder: :data:`DATA_FILES` (the data, the model, ``run.json``, the
    report), each learning run's and each whole-arm basket's attempts log and its lock, each figure of
    :data:`FIGURES` and (``frames``) the frames of :data:`FRAMES`, whose number the run knows only
    as it writes them. A file of another name in the folder is neither written nor removed."""
    plan = SIZES[size]
    logs = ([f"attempts/{method}.jsonl" for method, _ in plan.methods]
            + [basket_log(distance, bearing) for distance, bearing in plan.whole_arm_baskets])
    return (
        *DATA_FILES,
        *(name for log in logs for name in (log, f"{log}.lock")),
        *(f"figures/{stem}.{suffix}" for stem in FIGURES for suffix in ("png", "svg")),
        *(FRAMES if frames else ()),
    )


def check_demo_options(out_dir: str | Path, size: str, *, frames: bool = True) -> None:
    """Raise :class:`InputError` for an unknown size, an output path that is not a folder, a folder
    another run holds, or one that holds files the run writes (:func:`run_files`) that its last
    run did not write (:func:`rlff.report.folder.check_run_folder`): the run would replace them."""
    _check_size_and_path(out_dir, size)
    check_run_folder(out_dir, run_files(size, frames=frames), PROGRAM, names=WRITES)


def _check_size_and_path(out_dir: str | Path, size: str) -> None:
    if size not in SIZES:
        raise InputError(f"unknown demo size {size!r} (known: {', '.join(SIZES)})")
    if Path(out_dir).exists() and not Path(out_dir).is_dir():
        raise InputError(f"{out_dir}: exists and is not a folder")


def run_demo(
    out_dir: str | Path,
    *,
    size: str = "full",
    seed: int = 0,
    progress: Callable[[str, int, int], None] | None = None,
    frames: bool = True,
) -> DemoSummary:
    """Run the whole chain on built-in data and write figures, ``run.json`` and ``report.html``.

    Parameters
    ----------
    out_dir : path
        Output folder (created), held by this run alone. The files the folder's last run listed
        as its own (finished or stopped, unchanged since) are removed first; a folder holding
        other files that the run writes (:func:`run_files`) is refused (:func:`check_demo_options`,
        :mod:`rlff.report.folder`); any other file is left as it is.
    size : {"full", "small"}
        ``full`` follows the thesis' recording plan (400 throws, 5 learning runs);
        ``small`` is a quick version (84 throws, 2 learning runs).
    seed : int
        Seed of the simulated people, the fits and the learning runs.
    progress : callable, optional
        ``progress(stage, done, total)`` as each stage of :data:`STAGES` starts, with a longer
        description during long stages (each learning attempt), and ``("done", total, total)``
        at the end.
    frames : bool
        Also render the learned throw with MuJoCo's offscreen renderer (frames and a GIF in
        ``figures/frames``, one frame beside the drawing); skipped when no OpenGL backend works.
        The drawing is always made.

    Returns
    -------
    DemoSummary

    Raises
    ------
    InputError
        As :func:`check_demo_options`: another run holds ``out_dir`` (:class:`rlff.report.folder.FolderInUse`),
        or it holds files the run writes that its last run did not write; or a stage found too
        little to go on.
    """
    _check_size_and_path(out_dir, size)
    with RunFolder(out_dir, run_files(size, frames=frames), PROGRAM, names=WRITES) as folder:
        summary = _run(folder, size, seed=seed, progress=progress, frames=frames)
        folder.finish()
    return summary


def _run(folder: RunFolder, size: str, *, seed: int, progress: Callable[[str, int, int], None] | None,
         frames: bool) -> DemoSummary:
    """:func:`run_demo` in the folder it holds, every file listed in ``folder`` before it is written."""
    from rlff.learn import learn
    from rlff.learn.demos import loop_components, usable_demos
    from rlff.learn.loop import learnable_basket, release_note
    from rlff.learn.scenarios import with_landings
    from rlff.model import Model
    from rlff.preprocess import Pipeline
    from rlff.robot import RobotMapping, load_robot
    from rlff.sim import Basket, max_reach, simulate_throw
    from rlff.sim.reach import farthest_basket
    from rlff.synthetic.throws import simulate_throws
    from rlff.timing import time_along_path
    from rlff.whole_arm_demo import run_whole_arm, whole_arm_figures

    plan = SIZES[size]
    out_dir = folder.path
    clock = _Clock(progress)

    clock.stage(STAGES[0])
    raw = simulate_throws(
        seed, subjects=plan.subjects, distances=plan.distances, throws_per_distance=plan.throws_per_distance
    )
    write_csv(raw, folder.file("demos.csv"))
    raw_hits = sum(1 for t in raw if t.meta.get("hit") is True)

    clock.stage(STAGES[1])
    clean, preprocessing = Pipeline.preset("thesis").run(raw)
    if len(clean) < 2:
        raise InputError(f"the preprocessing left {len(clean)} trajectories: too few to learn from (seed {seed})")
    write_csv(clean, folder.file("clean.csv"))
    demonstrated = sorted({float(t["distance"][0]) for t in clean})

    clock.stage(STAGES[2])
    model = Model.fit(clean, inputs=("angle", "distance"), outputs=("velocity",), components="auto", seed=seed)
    model.save(folder.file("model.json"))

    clock.stage(STAGES[3])
    robot = load_robot()
    basket_shape = Basket(1.0)
    farthest = farthest_basket(max_reach(robot, basket_shape.rim_height), basket_shape.opening)
    shown, new = _output_distances(demonstrated, farthest)
    showcase_method, showcase_feedback = plan.methods[0]  # the loop's default method
    # the robot learns from what a recording knows: the basket each person aimed at, not where
    # the ball came down (given the landings, calibrate hits at once nearly everywhere)
    aimed = with_landings(clean, "none", seed)

    def first_throw(distance: float, gap) -> tuple[bool, float]:
        clock.note(f"the learning basket: the loop's first throw at {distance:g} m"
                   + ("" if gap.none else f" ({gap.name})"))
        first = learn(aimed, distance, budget=1, feedback=showcase_feedback, update=showcase_method, seed=seed,
                      robot=robot.name, gap=gap.name).history[0]
        return first.hit, first.miss

    # no farther than what the learning loop's own throws reach (its angle grid, the motion limits)
    mapping = RobotMapping.for_robot(robot)
    learnable = min(farthest, learnable_basket(aimed, mapping, basket_shape))
    learning_gap, learning_distance = _learning_arm_and_basket(demonstrated, learnable, first_throw)
    # the K the loop's runs fit: BIC on the set they learn from; where their throws let go
    usable = usable_demos(aimed, mapping, basket_shape.rim_height)[0]
    loop_k = loop_components(usable, seed)
    loop_release = release_note(usable, mapping, Basket(learning_distance))
    new = sorted({*new, learning_distance})  # its throw is in the table too
    angles = _angle_grid(clean)
    # continuity: where two modes are nearly as high, keep to the one that continues the throw
    # (a robot cannot jump between the sides of a donut); the report gives the density traded
    paths = {d: model.generate({"distance": d}, angles, continuity=True) for d in sorted({*shown, *new})}

    clock.stage(STAGES[4])
    throws: list[ThrowRow] = []
    for distance, path in paths.items():
        velocity = _forward(np.asarray(path.velocity, dtype=float))
        trajectory, _ = mapping.to_robot(path.angle, velocity, time_along_path(path.angle, velocity), clip=True)
        # the mapped path itself, released at its end as the thesis executed it (unplanned: it ends
        # moving), so past the motion check a planned throw passes
        outcome = simulate_throw(trajectory, Basket(distance), robot=robot, check_reach=False, check_motion=False)
        throws.append(
            ThrowRow(distance, distance in demonstrated, distance <= farthest, bool(outcome.hit),
                     float(outcome.landing_x), float(outcome.miss))
        )

    clock.stage(STAGES[5])
    learning: list[LearningRow] = []
    results = {}
    for method, feedback in plan.methods:
        log = folder.log(f"attempts/{method}.jsonl")
        result = learn(
            aimed, learning_distance, budget=plan.budget, feedback=feedback, update=method, seed=seed,
            log_path=log, robot=robot.name, gap=learning_gap.name,
            progress=lambda attempt, method=method: clock.note(
                f"learning at {learning_distance:g} m: {method}, attempt {attempt.index}"
                f" ({'hit' if attempt.hit else f'miss {signed_metres(attempt.miss)}'})"
            ),
        )
        results[method] = result
        learning.append(LearningRow(method, feedback, result.hit, result.attempts, list(result.misses)))

    clock.stage(STAGES[6])
    whole_arm = run_whole_arm(folder, plan.whole_arm_baskets, seed=seed, robot=robot, note=clock.note)

    clock.stage(STAGES[7])
    figure_entries = _figures(
        folder, raw=raw, clean=clean, preprocessing=preprocessing, model=model, paths=paths,
        demonstrated=demonstrated, learning_distance=learning_distance,
        learning_gap=learning_gap, results=results, logs_dir=out_dir / "attempts", mapping=mapping, robot=robot,
        frames=frames, seed=seed, loop_k=loop_k,
    )
    figure_entries += whole_arm_figures(folder, whole_arm, robot)

    clock.stage(STAGES[8])
    run = _run_record(
        size=size, seed=seed, raw=raw, raw_hits=raw_hits, clean=clean, preprocessing=preprocessing,
        model=model, paths=paths, demonstrated=demonstrated, throws=throws, farthest=farthest,
        learning_distance=learning_distance, learning_gap=learning_gap, learning=learning, budget=plan.budget,
        loop_components=loop_k, loop_release=loop_release,
        figures=[FigureEntry(p.relative_to(out_dir).as_posix(), s, t, c) for p, s, t, c in figure_entries],
        whole_arm=whole_arm,
    )
    folder.file("run.json")
    run_json = write_run(run, out_dir)
    report = build_report(out_dir, folder.file("report.html"))
    seconds = clock.finish()
    return DemoSummary(
        out_dir=out_dir, report=report, run_json=run_json, figures=[p for p, *_ in figure_entries], size=size,
        seed=seed, demonstrations=len(raw), demonstration_hits=raw_hits, clean_trajectories=len(clean),
        demonstrated_distances=demonstrated, components=int(model.n_components), throws=throws,
        learning_distance=learning_distance, learning_arm=learning_gap.name, learning=learning,
        whole_arm=whole_arm.runs,
        stage_seconds=clock.seconds, seconds=round(seconds, 3),
    )


def _angle_grid(clean: Dataset, points: int = 120) -> np.ndarray:
    """Angles (rad) of the generated throws: from the median first to the median last angle."""
    first = float(np.median([t["angle"][0] for t in clean]))
    last = float(np.median([t["angle"][-1] for t in clean]))
    return np.linspace(first, last, points)


def _figures(
    out: RunPaths, *, raw, clean, preprocessing, model, paths, demonstrated, learning_distance,
    learning_gap, results, logs_dir: Path, mapping, robot, frames: bool, seed: int, loop_k: int,
) -> list[tuple[Path, str, str, str]]:
    """Draw every figure into ``out``'s ``figures/``; returns (png path, section, title, caption)
    in report order (``logs_dir``: the learning runs' attempts logs, ``METHOD.jsonl``; ``loop_k``:
    the components of the learning loop's own model, which the DMM figure's caption names)."""
    from rlff.plots.data import dataset_3d, dataset_slices
    from rlff.plots.donut import dmm_heatmap, donut_family
    from rlff.plots.learning import learning_curves_from_logs
    from rlff.plots.mixture import kmeans_em_steps, model_components, selection_curve
    from rlff.plots.outputs import output_trajectories
    from rlff.plots.preprocess import preprocessing_steps
    from rlff.plots.throw import throw_snapshot_from_outcome

    entries: list[tuple[Path, str, str, str]] = []

    def add(saved, section: str, title: str, caption: str) -> None:
        entries.append((saved.png, section, title, caption))

    middle = demonstrated[len(demonstrated) // 2]
    add(dataset_slices(raw, out.figure("demonstrations-per-distance")), "data", "The recorded throws per basket distance",
        "Elbow angle and angular velocity of every simulated throw as a depth camera and a skeleton tracker "
        "record them: wind-up, extension, stop; tracking glitches are the grey dots, left out of the lines. Green throws hit "
        f"the basket, red ones missed: {_failures(raw, 'demonstrations are failures')}.")
    add(preprocessing_steps(
        [(s.step, s.before, s.after if s.after is not None else s.before, s.summary()) for s in preprocessing.steps],
        out.figure("preprocessing")), "preprocessing", "Each cleaning step, before and after",
        "Grey: the data entering a step; coloured by distance: what leaves it (thesis section 4.3).")
    add(dataset_3d(clean, out.figure("clean-3d"),
                   title=f"After cleaning: {len(clean)} throws, {clean.n_samples} samples"),
        "preprocessing", "The cleaned demonstrations in 3-D",
        "What the model learns from: (angle, distance, velocity) of every kept throw up to the release "
        "(thesis fig. 4.43, 4.47).")
    effective = model.fit_info["effective_samples"]  # n as the model's fit counted it
    add(selection_curve(model.selection.table, out.figure("bic"), n_samples=model.fit_info["n_samples"],
                        effective_samples=effective), "model", "Choosing K",
        "BIC = -2 ln L + p ln n against the number of components, n counted as the fit counts it (densified "
        "samples as the share of a measurement they are; the title says how many); the lowest wins, the model's "
        "K (thesis eq. 2.2).")
    add(kmeans_em_steps(clean.to_array(("angle", "velocity")), out.figure("kmeans-em"), seed=seed,
                        effective_samples=effective), "model",
        "k-means, then EM",
        "k-means places the components (top), EM fits their weights, means and covariances (bottom); "
        "shown on the (angle, velocity) plane (thesis fig. 2.3-2.4).")
    add(model_components(model, clean, middle, out.figure("components")), "model",
        f"The components at {middle:g} m",
        "The model's Gaussian components conditioned on the basket distance, as 1σ and 2σ ellipses over "
        "the demonstrations of that distance (thesis fig. 4.2-4.3, 4.47-4.48).")
    add(donut_family(out.figure("donuts")), "model", "A Gaussian and its donuts",
        "The Donut Mixture Model replaces each Gaussian by a donut whose hole grows with the exploration "
        "factor ε (thesis fig. 2.5, eq. 2.8).")
    add(dmm_heatmap(model, learning_distance, out.figure("dmm-density"), dataset=clean), "outputs",
        f"The DMM density at {learning_distance:g} m",
        "The density of the joint velocity for every joint angle (hotter is higher), the GMR mean and the "
        f"throw chosen at the highest density of each angle (thesis fig. 2.7, 4.4), of the model above "
        f"(K = {model.n_components}); the learning loop fits its own (K = {loop_k}, Learning from failure), so "
        "its throws are not this one.")
    add(output_trajectories(paths, out.figure("outputs"), dataset=clean), "outputs",
        "Generated throws, demonstrated and new distances",
        "Farther baskets get faster throws, also at distances nobody demonstrated (dashed; thesis fig. 4.7, 4.50).")
    first_method, first_run = next(iter(results.items()))
    on_arm = "" if learning_gap.none else f"; the arm {arm_words(learning_gap)}"
    first_throw = _replay(first_run.history[0], mapping, robot, learning_distance, learning_gap)
    add(throw_snapshot_from_outcome(first_throw, out.figure("first-throw"), robot=robot,
                                    title=f"The loop's first throw at {learning_distance:g} m ({first_method}), "
                                          "before learning"),
        "simulation", "The robot's first throw",
        f"The first attempt of the learning loop ({first_method}) on the Comau's joint 2, executed again in "
        f"MuJoCo{on_arm}: the arm at the release, the ball's flight and the basket.")
    # the runs' logs drawn as `rlff plot learning` draws them: the same names, colours and band
    add(learning_curves_from_logs([logs_dir / f"{name}.jsonl" for name in results], out.figure("learning")),
        "learning", "Learning from failure",
        "Signed miss of every attempt until the first hit (star), per method.")
    best = next((r for r in results.values() if r.hit), None)
    if best is not None:
        outcome = _replay(best.history[-1], mapping, robot, learning_distance, learning_gap,
                          out.folder("figures/frames") if frames else None)
        add(throw_snapshot_from_outcome(outcome, out.figure("learned-throw"), robot=robot,
                                        title=f"The learned throw at {learning_distance:g} m ({best.update})"),
            "learning", "The learned throw", f"The hit found by the learning loop, executed again in MuJoCo{on_arm}.")
    return entries


def _replay(attempt, mapping, robot, distance: float, gap, frames_dir: Path | None = None):
    """An attempt of the learning loop executed again in MuJoCo (for its figure), on the arm it
    was made on (its robot file less ``gap``, :class:`rlff.sim.gap.Gap`)."""
    from rlff.learn.replay import plan_attempt
    from rlff.sim import Basket, simulate_throw

    # planned as `rlff sim throw LOG --attempt N` plans it: the landing the table gives
    trajectory = plan_attempt(attempt, mapping, clip=True).trajectory
    return simulate_throw(gap.executed(trajectory), Basket(distance), robot=robot, check_reach=False,
                          frames_dir=frames_dir)


def arm_words(gap) -> str:
    """What the arm of the learning runs does, in a few words after "the arm" (``gap``:
    :class:`rlff.sim.gap.Gap`)."""
    if gap.none:
        return "is as its robot file describes it"
    if gap.delay:
        return f"lets the ball go {1000 * gap.delay:.0f} ms late"
    return f"reaches {100 * gap.speed:.0f} % of the commanded joint speeds"


def _learning_basket_words(distance: float, demonstrated: list[float], gap, method: str, missed: bool) -> str:
    """The report's sentences on where the learning basket stands and on which arm (``missed``:
    whether the loop's first throw misses there)."""
    who = "people demonstrated it" if distance in demonstrated else "nobody demonstrated it"
    if not missed:
        return (f"The basket is put at {distance:g} m: {who} and the robot can reach it. The learning loop's own "
                f"first throw ({method}) goes in at every distance the arm can reach, even on an arm slower than "
                "its robot file: the demonstrations' labels, read through the range law, put it there. Of those "
                "distances this is where it comes down farthest from the basket's middle. ")
    if gap.none:
        return (f"The basket is put at {distance:g} m: {who}, the robot can reach it, and of such distances "
                f"it is where the learning loop's own first throw ({method}) missed most. ")
    return (f"On the arm as its robot file describes it, the learning loop's own first throw ({method}) went "
            "in at every distance the arm can reach: the demonstrations' labels, read through the range law, "
            "put it there. So the learning is shown on an arm that is not its robot file, as a real one may "
            f"not be: it {arm_words(gap)} ({gap.name}), which nothing in the loop knows. The basket is put at {distance:g} m: "
            f"{who}, and on that arm it is where the first throw missed most. ")


def _run_record(
    *, size, seed, raw, raw_hits, clean, preprocessing, model, paths, demonstrated, throws, farthest,
    learning_distance, learning_gap, learning, budget, loop_components, loop_release, figures, whole_arm,
) -> Run:
    """The run.json record: facts and tables per section (``loop_release``: the learning runs'
    note that they let go later than the default, :func:`rlff.learn.loop.release_note`, or "")."""
    raw_distances = sorted({float(t["distance"][0]) for t in raw})
    per_distance = []
    for distance in raw_distances:
        group = [t for t in raw if float(t["distance"][0]) == distance]
        hits = sum(1 for t in group if t.meta.get("hit") is True)
        kept = sum(1 for t in clean if float(t["distance"][0]) == distance)
        per_distance.append([distance, len(group), hits, len(group) - hits, kept])
    steps = [
        [s.step, len(s.before), len(s.after if s.after is not None else s.before), s.before.n_samples,
         (s.after if s.after is not None else s.before).n_samples, s.summary()]
        for s in preprocessing.steps
    ]
    # ln L as BIC counts it (BIC = -2 ln L + p ln n_e, the figure's caption), as `rlff fit` prints
    # it: over all n samples scaled by n_e / n; the raw sum had not fitted the BIC beside it
    n, effective = model.fit_info["n_samples"], model.fit_info["effective_samples"]
    share = 1.0 if effective is None else effective / n
    selection = [[row["n_components"], row["bic"], row["aic"], row["log_likelihood"] * share]
                 for row in model.selection.table]
    selection_title = ("Model selection" if effective is None else
                       f"Model selection (ln L scaled to {effective:.4g} effective samples of {n}, as BIC counts it)")
    outputs = []
    for distance, path in paths.items():
        velocity = np.asarray(path.velocity, dtype=float)
        outputs.append([
            distance, distance in demonstrated, float(np.max(velocity)), float(velocity[-1]),
            float(np.mean(path.exploration)), float(np.mean(np.abs(velocity - np.asarray(path.gmr_mean)))),
            float(np.max(path.density_traded)),
        ])
    subjects = sorted({str(t.meta.get("subject")) for t in raw if "subject" in t.meta})
    sections = [
        Section(
            "data", "Demonstrations",
            "Simulated people throw a ball overhand at baskets 1 to 4 m away, recorded like a depth camera "
            "and a skeleton tracker would (15-30 Hz, noise, dropped frames, tracking glitches). "
            f"{_failures(raw, 'throws miss').capitalize()}: the failed demonstrations the robot learns from.",
            facts={"throws": len(raw), "hits": raw_hits, "hit rate": raw_hits / max(len(raw), 1),
                   "people": len(subjects), "samples": raw.n_samples, "basket distances (m)": ", ".join(f"{d:g}" for d in raw_distances)},
            tables=[Table("Throws per basket", ["distance (m)", "throws", "hits", "misses", "kept after cleaning"], per_distance)],
        ),
        Section(
            "preprocessing", "Preprocessing",
            "The thesis' cleaning steps (section 4.3), run automatically; each says what it changed.",
            facts={"trajectories kept": len(clean), "samples kept": clean.n_samples,
                   "distances kept (m)": ", ".join(f"{d:g}" for d in demonstrated)},
            tables=[Table("Steps", ["step", "trajectories in", "out", "samples in", "out", "what it did"], steps)],
        ),
        Section(
            "model", "Model",
            "A Gaussian mixture over (angle, distance, velocity), K chosen by the lowest BIC; conditioned on "
            "the angle and the distance it gives the GMR mean and variance, and its donuts the DMM.",
            facts={"components K": int(model.n_components), "criterion": "BIC",
                   **{f"{name} resolution": f"{value:g} (step^2/12 added to every component's variance)"
                      for name, value in model.fit_info.get("context_resolution", {}).items() if value > 0}},
            tables=[Table(selection_title, ["K", "BIC", "AIC", "ln L"], selection)],
        ),
        Section(
            "outputs", "Generated throws",
            "For each basket distance the throw is the velocity of highest DMM density at every angle. Where two "
            "modes are nearly as high the output keeps to the one that continues the throw (a robot cannot jump "
            "between the two sides of a donut); the last column says how much density that gave up at most.",
            facts={"distances (m)": ", ".join(f"{d:g}" for d in paths),
                   "not demonstrated (m)": ", ".join(f"{d:g}" for d in paths if d not in demonstrated)},
            tables=[Table("Throws per distance", ["distance (m)", "demonstrated", "peak velocity (rad/s)",
                                                  "release velocity (rad/s)", "mean exploration ε",
                                                  "mean |DMM − GMR| (rad/s)", "most density traded"], outputs)],
        ),
        Section(
            "simulation", "Simulated robot throws",
            "Each generated throw drives the Comau Smart5 SiX's joint 2 in MuJoCo; the ball is let go at the end "
            "of the path. Baskets beyond the arm's reach with joint 2 alone are marked unreachable.",
            facts={"robot reach (m)": farthest},
            tables=[Table("Outcomes", ["distance (m)", "demonstrated", "reachable", "hit", "landing (m)", "miss (m)"],
                          [[r.distance, r.demonstrated, r.reachable, r.hit, r.landing, r.miss] for r in throws])],
        ),
        Section(
            "learning", "Learning from failure",
            _learning_basket_words(learning_distance, demonstrated, learning_gap, learning[0].method,
                                   missed=not (learning[0].hit and learning[0].attempts == 1))
            + "It learns from the demonstrations labelled with the basket each person aimed at, not with where "
            "their ball came down (which a recording does not see). "
            f"The robot throws, sees the outcome, updates and throws again, at most {budget} times per method. "
            f"The loop fits its own model, not the K = {model.n_components} one above: {loop_components} "
            "components (BIC over the measured samples, at most 4) on the demonstrations thinned to at most "
            "600 samples, refitted at every attempt; calibrate throws the DMM's mode for the basket (keeping "
            "to one side of the donut, capped at its release speed) scaled to a release speed: with binary "
            "feedback the next of the release speed's hit windows, the likeliest first, with distance "
            "feedback the one its calibration of landing against speed picks; failure and hindsight the DMM's "
            "throw refitted with their attempts, secant and imitation the GMR mean."
            + (f" Every method's throws let go later than usual: {loop_release}." if loop_release else ""),
            facts={"basket (m)": learning_distance, "arm": arm_words(learning_gap) + ("" if learning_gap.none else f" ({learning_gap.name})"), "budget": budget,
                   "loop components K": loop_components},
            tables=[Table("Runs", ["method", "feedback", "hit", "attempts", "first throw miss (m)", "last miss (m)"],
                          [[r.method, r.feedback, r.hit, r.attempts, r.misses[0] if r.misses else None,
                            r.misses[-1] if r.misses else None] for r in learning])],
        ),
        whole_arm_section(whole_arm),
    ]
    return Run(
        title="rlff demo: learning to throw from failed demonstrations",
        created=datetime.now(UTC).isoformat(timespec="seconds"),
        settings={"size": size, "seed": seed, "python": platform.python_version()},
        sections=sections,
        figures=figures,
    )
