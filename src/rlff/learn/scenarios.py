"""Learning scenarios as data: who demonstrated, what is known of their landings, what the robot
is told after each throw, the basket and the robot.

A :class:`Scenario` is everything a benchmark run depends on besides the method and the seed:

demonstrators
    How the simulated people throw (:data:`DEMONSTRATORS`): ``short`` (every throw falls short,
    baskets at 1-1.5 m), ``wide`` (the demo's setting, 1-4 m, most beyond the robot's reach),
    ``overshooting`` (people who throw too hard), ``near`` (baskets at 0.8-1.1 m only, the
    robot asked for farther ones) and ``mixed`` (half the subjects short, half long).
landings
    What the demonstrations' metadata say about where each throw came down: ``exact`` (as the
    simulation knows it), ``noisy:STD`` (an estimate with a normal error of STD metres, as a
    capture gives it from the hand's release) or ``none`` (only the basket aimed at).
feedback
    What each attempt reports (:class:`Feedback`): ``binary``, ``distance``,
    ``noisy-distance:STD`` (the landing with a normal error of STD metres) or
    ``false-miss:RATE`` (binary, and a hit is reported as a miss with probability RATE, as a
    ball that bounces out of a real basket is).
opening, robot
    The basket's inner width (m) and the robot (name or robot file).
gap
    How the arm that throws differs from the robot file every method plans with (:class:`Gap`):
    ``none``, ``speed:G`` (the arm reaches G times the commanded speed, as under a controller's
    speed override or a servo that lags) or ``delay:S`` (the gripper lets go S seconds after the
    planned release). A real arm is never exactly its file.

The noise of the landings and of the feedback is drawn from the run's seed, so a run is
reproducible and every method of a seed sees the same demonstrations.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rlff.dataset import Dataset
from rlff.errors import InputError
from rlff.learn.robot import ReportedOutcome
from rlff.limits import check_distance, parse_number
from rlff.sim.gap import Gap, parse_gap


@dataclass(frozen=True)
class Demonstrators:
    """Simulated people and the baskets the robot is then asked for.

    Parameters
    ----------
    distances : tuple of float
        Basket distances (m) the people aimed at (4 subjects, 3 throws at each).
    baskets : tuple of float
        Basket distances (m) the robot learns at, all within its reach (about 2.2 m).
    bias : float
        Mean fraction of the needed speed a subject falls short by (negative: throws too hard).
    all_short : bool
        Every throw falls short of its basket.
    mixed : bool
        Half the subjects fall short by ``bias``, the other half overshoot by as much.
    """

    distances: tuple[float, ...]
    baskets: tuple[float, ...]
    bias: float = 0.05
    all_short: bool = False
    mixed: bool = False


DEMONSTRATORS = {
    "short": Demonstrators((1.0, 1.25, 1.5), (1.4, 1.9), all_short=True),
    "wide": Demonstrators((1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0), (1.25, 1.75)),
    "overshooting": Demonstrators((1.0, 1.25, 1.5), (1.4, 1.9), bias=-0.15),
    "near": Demonstrators((0.8, 0.9, 1.0, 1.1), (1.4, 1.9)),
    "mixed": Demonstrators((1.0, 1.25, 1.5, 1.75, 2.0), (1.4, 1.9), bias=0.15, mixed=True),
}


@dataclass(frozen=True)
class Feedback:
    """What an attempt reports, and how faithfully.

    Parameters
    ----------
    name : str
        As written on the command line (``binary``, ``distance``, ``noisy-distance:0.05``,
        ``false-miss:0.2``).
    kind : {"binary", "distance"}
        What the loop hands the method.
    noise : float
        Standard deviation (m) of the reported landing about the true one.
    false_miss : float
        Probability that a hit is reported as a miss.
    """

    name: str
    kind: str
    noise: float = 0.0
    false_miss: float = 0.0

    @property
    def faithful(self) -> bool:
        """The report is what happened."""
        return self.noise == 0 and self.false_miss == 0


def parse_feedback(text: str) -> Feedback:
    """The feedback of ``binary``, ``distance``, ``noisy-distance:STD`` or ``false-miss:RATE``."""
    word, _, value = text.strip().partition(":")
    if word in ("binary", "distance") and not value:
        return Feedback(word, word)
    if word in ("noisy-distance", "false-miss"):
        takes = ("a standard deviation > 0 (m), e.g. noisy-distance:0.05" if word == "noisy-distance" else
                 "a rate above 0 and below 1 (the share of hits reported as misses), e.g. false-miss:0.2")
        if not value.strip():  # "'' is not a number" had not said what was missing
            raise InputError(f"feedback {text!r}: give its value after ':', {takes}")
        number = parse_number(value, f"feedback {text!r}")
        if word == "noisy-distance" and number > 0:
            return Feedback(f"{word}:{number:g}", "distance", noise=number)
        if word == "false-miss" and 0 < number < 1:
            return Feedback(f"{word}:{number:g}", "binary", false_miss=number)
        raise InputError(f"feedback {text!r}: {word} takes {takes}")
    raise InputError(f"unknown feedback {text!r} (known: binary, distance, noisy-distance:STD, "
                     "false-miss:RATE)")


def parse_landings(text: str) -> str:
    """``exact``, ``none`` or ``noisy:STD`` (STD > 0, m), normalised."""
    word, _, value = text.strip().partition(":")
    if word in ("exact", "none") and not value:
        return word
    if word == "noisy":
        if not value.strip():  # "'' is not a number" had not said what was missing
            raise InputError(f"landings {text!r}: give the standard deviation after ':' (m), e.g. noisy:0.3")
        std = parse_number(value, f"landings {text!r}")
        if std > 0:
            return f"noisy:{std:g}"
    raise InputError(f"landings {text!r}: use exact, none or noisy:STD (a standard deviation > 0, m)")


@dataclass(frozen=True)
class Scenario:
    """Everything a learning run depends on besides the method and the seed.

    Parameters
    ----------
    demonstrators : str
        A key of :data:`DEMONSTRATORS`.
    landings : str
        ``exact``, ``noisy:STD`` or ``none``.
    feedbacks : tuple of Feedback
        The feedback kinds to run.
    opening : float
        Inner width of the basket (m).
    robot : str
        Robot name or robot file.
    baskets : tuple of float, optional
        Basket distances (m); default the demonstrators'.
    gap : Gap or str
        How the simulated arm differs from ``robot`` (default none).
    aim : str
        Where the speed search starts, one of :data:`rlff.learn.loop.AIMS` (default ``auto``).
    """

    demonstrators: str = "short"
    landings: str = "none"
    feedbacks: tuple[Feedback, ...] = (Feedback("binary", "binary"), Feedback("distance", "distance"))
    opening: float = 0.35
    robot: str = "comau_smart5_six"
    baskets: tuple[float, ...] | None = None
    gap: Gap | str = Gap()
    aim: str = "auto"

    def __post_init__(self) -> None:
        from rlff.learn.loop import AIMS

        if self.aim not in AIMS:
            raise InputError(f"unknown aim {self.aim!r} (known: {', '.join(AIMS)})")
        if isinstance(self.gap, str):
            object.__setattr__(self, "gap", parse_gap(self.gap))
        if self.demonstrators not in DEMONSTRATORS:
            raise InputError(f"unknown scenario {self.demonstrators!r} (known: {', '.join(DEMONSTRATORS)})")
        object.__setattr__(self, "landings", parse_landings(self.landings))
        if not (math.isfinite(self.opening) and self.opening > 0):
            raise InputError(f"basket opening must be a width > 0 (m), got {self.opening!r}")
        if self.baskets is None:
            object.__setattr__(self, "baskets", DEMONSTRATORS[self.demonstrators].baskets)
        if not self.baskets:
            raise InputError("a scenario needs at least one basket")
        object.__setattr__(self, "baskets", tuple(check_distance("basket", float(b)) for b in self.baskets))

    @property
    def name(self) -> str:
        """The demonstrators, the gap when there is one and the aim when not the default
        (``short/speed:0.95/aim:kinematics``)."""
        parts = [self.demonstrators, *([] if self.gap.none else [self.gap.name]),
                 *([] if self.aim == "auto" else [f"aim:{self.aim}"])]
        return "/".join(parts)


def demonstrations(seed: int, scenario: Scenario) -> Dataset:
    """The demonstrations of one seed, simulated, cleaned by the thesis preset, with the
    scenario's knowledge of their landings in the ``landing`` metadata (absent for ``none``)."""
    from rlff.preprocess import Pipeline
    from rlff.synthetic.throws import simulate_throws

    people = DEMONSTRATORS[scenario.demonstrators]
    common = {"distances": people.distances, "throws_per_distance": 3, "all_short": people.all_short}
    if people.mixed:
        short = simulate_throws(seed, subjects=["s01", "s02"], bias=people.bias, **common)
        long = simulate_throws(seed + 10_000, subjects=["s03", "s04"], bias=-people.bias, **common)
        raw = Dataset(list(short) + list(long), context=("distance",))
    else:
        raw = simulate_throws(seed, subjects=4, bias=people.bias, **common)
    clean, _ = Pipeline.preset("thesis").run(raw)
    return with_landings(clean, scenario.landings, seed)


def with_landings(demos: Dataset, landings: str, seed: int) -> Dataset:
    """The demonstrations with their ``landing`` metadata as ``landings`` says it is known."""
    if landings == "exact":
        return demos
    rng = np.random.default_rng([seed, 7])
    std = float(landings.partition(":")[2] or 0.0)
    trajectories = []
    for t in demos:
        meta = dict(t.meta)
        truth = meta.pop("landing", None)
        if std and truth is not None:
            meta["landing"] = float(truth) + std * float(rng.standard_normal())
        trajectories.append(t.replace(meta=meta))
    return Dataset(trajectories, context=demos.context)


def reporting_executor(scenario: Scenario, feedback: Feedback, basket: float, seed: int):
    """The MuJoCo simulation of ``basket`` by the scenario's arm (its gap applied to every
    trajectory), its outcomes reported as ``feedback`` says.

    Returns None for faithful feedback and no gap (the loop's own simulator is the same). The
    noise of attempt k is drawn from (seed, k), so a run is reproducible.
    """
    if feedback.faithful and scenario.gap.none:
        return None
    from rlff.robot import load_robot
    from rlff.sim import Basket, simulate_throw

    robot = load_robot(scenario.robot)
    target = Basket(float(basket), opening=scenario.opening)
    calls = [0]

    def execute(trajectory):
        calls[0] += 1
        # the loop's plan_path ran the motion check on it: not run again for every throw
        outcome = simulate_throw(scenario.gap.executed(trajectory), target, robot=robot, check_motion=False)
        rng = np.random.default_rng([seed, calls[0], 11])
        landing, hit = float(outcome.landing_x), bool(outcome.hit)
        if feedback.noise and math.isfinite(landing):
            landing += feedback.noise * float(rng.standard_normal())
        if hit and rng.random() < feedback.false_miss:
            hit = False
        miss = landing - target.distance if math.isfinite(landing) else float(outcome.miss)
        return ReportedOutcome(hit, landing, miss)

    return execute
