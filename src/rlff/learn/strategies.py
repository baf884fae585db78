"""Update strategies: how the robot's attempts change the Donut Mixture Model between attempts.

Every strategy refits the mixture to the demonstrations plus what the attempts taught, and asks
the DMM for a throw (the mode of the donut density at every angle, thesis section 2.4). They
differ in how the attempts join the data, with what weight, and which distance is asked for.

``failure`` (Grollman & Billard 2011)
    Each failed attempt joins the data labelled with the target distance. Attempts that disagree
    with the demonstrations widen the conditional variance there, so the exploration factor
    grows and the donut pushes the next throw away from what failed. Works with both feedback
    kinds; slow when the demonstrations agree, because the exploration then starts small.
``hindsight``
    Each attempt joins the data labelled with the distance it actually reached (a throw for 3 m
    that landed at 2.6 m becomes a demonstration for 2.6 m). Needs distance feedback.

    Both throw the DMM's own throw; with an aim (``Problem.aim``) sped up or slowed down by the
    factor that aims their first throw at the basket, the attempts joining the data divided by it
    (:class:`RefitUpdate`).
``calibrate`` (this project's strategy)
    Two facts about throwing decide it. The robot does not land where the human did (the
    human-to-robot mapping changes the arm, the release height and the speed), but the order
    stays: a faster throw lands farther. And with the release angle fixed at the end of the
    path, where the ball lands is decided by the speed over the release part of the path. So
    the DMM gives the throw's *shape* and a posterior over the law
    log(L / Z) = a + b log(u / u0) between the release speed u and the landing L gives its
    *speed*:

    - the DMM is refitted to the demonstrations labelled with where they landed when that is
      known (a failed demonstration still shows which distance its throw is good for) plus, with
      distance feedback, every attempt labelled with where it landed (hindsight) and weighted
      3 times a demonstration, so the robot's own throws outweigh the human ones they
      contradict; its exploration stays on, so where the demonstrations disagree the shape
      still explores;
    - u0 is the release speed of the GMR mean for Z from the demonstrations alone; the prior is
      a ~ N(0, 0.3) (that throw lands near the basket) and b log-normal about 1.6 (a
      projectile's range from its release point grows with the square of the speed; the
      release height and the release point's offset from the base bring the elasticity of the
      distance from the base down to about 1.3-1.9 here);
    - distance feedback: each landing is a noisy observation of the law;
    - the next throw is the DMM's shape scaled to the speed with the highest posterior
      probability of a hit, never beyond the robot's speed limit. The law is stated in the
      *executed* speed, so a throw the robot had to saturate counts for what it did;
    - binary feedback says neither short nor long, so there the speed comes from the window
      search of :mod:`rlff.learn.windows` instead: the release speed's hit windows, tiled from
      a centre to the speed limit, thrown in the order of their prior probability (normal about
      the centre; everything beyond the limit belongs to the fastest window, as the basket is
      within reach). The centre is the speed that one range law fitted to all the
      demonstrations' known landings gives for the basket (:mod:`rlff.learn.landings`; the
      prior's width its error and the robot's scatter about it), else the GMR mean's speed;
      where no landing is known and every demonstration missed, the prior rules out the speeds
      at which the failures would have hit and throws the ring about them first
      (:mod:`rlff.learn.outcomes`: the donut's reasoning, stated in the release speed);
    - the shape keeps to one side of the donut (``continuity``) and is capped at its release
      speed (:func:`fastest_at_release`), so that the release speed alone decides the landing
      even where the demonstrations disagree and the DMM's mode would jump between sides.

    A whole-arm throw (several joints, :mod:`rlff.learn.loop`) is scaled as a whole (every
    velocity by one factor, :func:`rlff.learn.method.scale_speed`); its shape is asked for within
    the demonstrations' labels (:func:`shape_distance`); u0 is the speed at which the arm's
    kinematics send that shape to Z (``Problem.aim``), b's prior is centred on the elasticity they
    give there (``Problem.elasticity``), and the search goes up to where every joint saturates,
    in the speed asked for (``Problem.saturation``).
"""

from __future__ import annotations

import math
from abc import abstractmethod
from collections.abc import Callable, Sequence
from dataclasses import replace
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np
from scipy.special import logsumexp
from scipy.stats import norm

from rlff.dataset import Dataset, Trajectory
from rlff.errors import InputError
from rlff.learn.attempt import Attempt
from rlff.learn.carry import CARRY_SCALE
from rlff.learn.landings import LABELS_SCALE, ROBOT_SCALE, LandingSpeed, aims_shift, landing_speed
from rlff.learn.method import (
    ONE_JOINT_OUTPUTS,
    Method,
    Problem,
    Proposal,
    attempt_trajectory,
    known_labels,
    labelled_demos,
    release_samples,
    release_speed,
    scale_speed,
    training_set,
)
from rlff.learn.outcomes import all_missed, outcomes_prior
from rlff.learn.windows import (
    LOWEST,
    PRIOR_SCALE,
    RANGE_ELASTICITY,
    WindowSearch,
    lowest_for,
    window_width,
)

if TYPE_CHECKING:
    from rlff.model import Model


class DmmStrategy(Method):
    """A strategy that refits the DMM to weighted data and asks it for a distance."""

    #: Weight of a robot attempt relative to a demonstration.
    robot_weight: float = 1.0
    #: The DMM's exploration (``"auto"``: the thesis' factor; 0: the DMM without its donut).
    exploration: str | float = "auto"
    #: Where the throw's shape comes from: ``"dmm"`` (the donut's mode) or ``"gmr"`` (the GMR mean).
    shape_source: str = "dmm"
    #: The method this one ablates (None for the methods themselves).
    ablates: str | None = None

    def fit(self, data: Dataset, sample_weight: np.ndarray):
        """The mixture model of ``data`` (weighted), with the run's number of components."""
        # one EM start: the number of components is fixed and the data change by one throw
        # between refits, so restarts buy little and triple the loop's own time per attempt
        return self.problem.fit(data, sample_weight, n_init=1)

    def generate(self, data: Dataset, sample_weight: np.ndarray, query: float, info: dict, *,
                 continuity: bool = False, model: Model | None = None) -> Proposal:
        """Fit the mixture to ``data`` and return the DMM's throw for distance ``query`` (m).

        ``continuity`` keeps the path on the donut side that continues it where two modes are
        nearly as high (see :func:`rlff.model.donut.dmm_mode`). ``model``: the mixture of
        ``data`` when it is already fitted (it is then not fitted again).
        """
        problem = self.problem
        model = self.fit(data, sample_weight) if model is None else model
        if self.shape_source == "gmr":
            inputs = np.column_stack([problem.angles, np.full(problem.angles.size, float(query))])
            mean = model.condition(inputs).mean
            return Proposal.of_outputs(problem.angles, mean, model.outputs, query, 0.0, info)
        try:
            path = model.generate({"distance": query}, problem.angles, exploration=self.exploration,
                                  continuity=continuity)
        except InputError:
            # The model refuses a path with no forward motion anywhere (a donut mode, or even
            # the GMR mean, on the wrong side of zero all along): that is no throw, and the
            # loop executes it as a crawl, a miss like any other.
            inputs = np.column_stack([problem.angles, np.full(problem.angles.size, float(query))])
            mean = model.condition(inputs).mean
            return Proposal.of_outputs(problem.angles, mean, model.outputs, query, 0.0, {**info, "no_motion": True})
        return Proposal.of_outputs(path.angle, path.outputs, path.output_names, query,
                                   float(np.mean(path.exploration)), info)


class RefitUpdate(DmmStrategy):
    """A strategy whose throw is the DMM's own, refitted with the attempts that joined the data
    (``failure``, ``hindsight``), thrown at the speed the arm's kinematics aim at when the run has
    an aim (``Problem.aim``: ``aim="kinematics"``, or a whole-arm throw).

    The DMM still learns in the demonstrations' speeds; the robot throws its throw with every
    velocity times one factor (:attr:`aimed`), the one at which the arm's kinematics send the
    DMM's throw from the demonstrations alone to the basket, as the GMR baselines start at the
    aimed speed of their own throw; every attempt joins the data with its velocities divided by
    it, back in the demonstrations' speeds. Without an aim the factor is 1 and the throw is the
    DMM's. (Until 2026-12-06 both ignored the aim: on the real MSR throws at 1.6 m every throw
    asked for more than joint_2's speed limit and came down 0.58 m long, aimed or not.)

    They carry no hits from run to run (:attr:`Method.carries` is False): they learn by moving
    the DMM, not a speed over a start of their own, so their attempts log no ``log_factor`` and a
    carried one would not move their throws; ``learn`` refuses them a carry before any throw.
    """

    @abstractmethod
    def joined(self, history: Sequence[Attempt]) -> list[tuple[Attempt, float]]:
        """The attempts of ``history`` that join the data, each with its distance label (m)."""

    def propose(self, history: Sequence[Attempt]) -> Proposal:
        return scale_speed(self.dmm_throw(self.joined(history)), self.aimed)

    def dmm_throw(self, joined: Sequence[tuple[Attempt, float]]) -> Proposal:
        """The DMM's throw for the target (demonstrations' speeds), fitted to the demonstrations
        and the ``joined`` attempts (each with its label, m), their velocities divided by
        :attr:`aimed`."""
        if not joined:
            return self.demonstrations_throw
        problem = self.problem
        trajectories = labelled_demos(problem.demos) + [
            unaimed(attempt_trajectory(attempt, label), self.aimed) for attempt, label in joined]
        weights = [1.0] * len(problem.demos) + [self.robot_weight] * len(joined)
        data, sample_weight = training_set(trajectories, weights)
        return self.generate(data, sample_weight, problem.target, {})

    @cached_property
    def demonstrations_throw(self) -> Proposal:
        """The DMM's throw for the target from the demonstrations alone (no attempt joined yet,
        or none labels anything), fitted once."""
        problem = self.problem
        data, sample_weight = training_set(labelled_demos(problem.demos), [1.0] * len(problem.demos))
        return self.generate(data, sample_weight, problem.target, {})

    @cached_property
    def aimed(self) -> float:
        """The factor on every velocity of the DMM's throws: the one at which the arm's kinematics
        send its throw from the demonstrations alone (no attempt joined) to the basket
        (``Problem.aim``, :func:`rlff.learn.reach.aimed_factor`), fixed for the run; 1 without an aim."""
        problem = self.problem
        return 1.0 if problem.aim is None else float(problem.aim(self.demonstrations_throw))


def unaimed(trajectory: Trajectory, factor: float) -> Trajectory:
    """An attempt's training ``trajectory`` with every velocity column (rad/s) divided by
    ``factor``, the aim's (:attr:`RefitUpdate.aimed`): back in the demonstrations' speeds."""
    if factor == 1.0:
        return trajectory
    return trajectory.with_columns(**{column: trajectory[column] / factor for column in trajectory.columns
                                      if column == "velocity" or column.endswith("_velocity")})


class FailureUpdate(RefitUpdate):
    """Grollman & Billard: attempts join the data labelled with the target distance."""

    name = "failure"

    def joined(self, history: Sequence[Attempt]) -> list[tuple[Attempt, float]]:
        return [(attempt, self.problem.target) for attempt in history]


class HindsightUpdate(RefitUpdate):
    """Attempts join the data labelled with the distance they reached (needs distance feedback)."""

    name = "hindsight"
    feedbacks = ("distance",)

    def joined(self, history: Sequence[Attempt]) -> list[tuple[Attempt, float]]:
        # a throw with no landing labels nothing
        return [(attempt, attempt.landing) for attempt in history if attempt.landing > 0]


class SpeedCalibration:
    """Posterior over how the landing follows the release speed: log(L / Z) = a + b log(u / u0).

    ``u`` is the robot's speed over the release part of the path (in the demonstrations' units),
    ``u0`` a reference speed (the DMM's first proposal). The posterior lives on an (a, b) grid:
    a ~ N(0, ``prior_scale``) says how far from the basket the first proposal may land, b is
    log-normal about ``slope`` (a projectile's range from the release point grows with the square
    of its speed; measured from the robot's base that is an elasticity of 1.3-1.9 at these
    distances, 1.6 by default, and a whole-arm throw's from the arm's kinematics) and wide enough
    to be learned from the attempts.

    Parameters
    ----------
    target : float
        Basket distance Z (m).
    tolerance : float
        Half-width of the hit window around Z (m).
    reference : float
        Reference speed u0 (rad/s).
    max_speed : float
        Fastest release speed the robot can make (rad/s); no proposal goes beyond it.
    prior_scale : float
        Prior standard deviation of a (log units).
    noise : float
        Standard deviation (log units) of a landing about the law.
    lowest : float
        Slowest log speed factor of the candidates: :data:`LOWEST`, or lower where a near basket
        needs it (:func:`rlff.learn.windows.lowest_for`).
    """

    def __init__(
        self,
        target: float,
        tolerance: float,
        reference: float,
        max_speed: float = np.inf,
        *,
        prior_scale: float = 0.3,
        slope: float = 1.6,
        slope_scale: float = 0.25,
        noise: float = 0.03,
        lowest: float = LOWEST,
    ):
        self.target = float(target)
        self.tolerance = float(tolerance)
        self.reference = float(reference)
        self.noise = float(noise)
        # candidate speeds u / u0, log-spaced 0.01 apart, shape (C,): from e^-1.2 (or lower, where
        # the arm's kinematics say a near basket needs it) to e^1.2, or on to the robot's limit
        # where that lies beyond (a GMR mean extrapolated to a throw that hardly moves at its
        # release, :func:`rlff.learn.windows.reachable_top`)
        span = -LOWEST
        top = max(span, math.log(max_speed / self.reference)) if math.isfinite(max_speed) else span
        bottom = -lowest
        ratios = np.exp(-bottom + 0.01 * np.arange(int(round((top + bottom) / 0.01)) + 1))
        self.ratios = ratios[ratios * self.reference <= max_speed]
        if self.ratios.size == 0:
            self.ratios = np.array([max_speed / self.reference])
        # a, shape (A,), in steps of prior_scale / 20 over 4 standard deviations either side,
        # wider by what a law of twice the prior's slope needs to put the basket at candidates
        # beyond e^1.2 (the first landings then lie that far from the prior)
        beyond = max(0.0, math.log(self.ratios[-1]) - span)
        steps = 80 + math.ceil(2.0 * slope * beyond / (prior_scale / 20))
        self.offset = prior_scale / 20 * np.arange(-steps, steps + 1)
        self.slope = np.geomspace(0.2, 5.0, 41)  # b, shape (B,)
        self.log_p = (
            -0.5 * (self.offset[:, None] / prior_scale) ** 2
            - 0.5 * (np.log(self.slope[None, :] / slope) / slope_scale) ** 2
        )

    def _log_x(self, speed: float) -> float:
        return float(np.log(max(speed, 1e-9) / self.reference))

    def observe_landing(self, speed: float, landing: float) -> None:
        """Distance feedback: a throw with release speed ``speed`` landed at ``landing`` (m).

        A ball that came down at or behind the robot's base (``landing`` <= 0; a throw that
        hardly moved at its release) is outside the law, whose landings are forward: it is
        counted as censored, "no farther than the hit window's half-width" (otherwise the
        posterior stayed as it was, and the same throw was made again for the whole budget)."""
        if math.isnan(landing):
            return  # no landing reported
        predicted = self.offset[:, None] + self.slope[None, :] * self._log_x(speed)
        if landing > 0:
            residual = np.log(landing / self.target) - predicted
            self.log_p = self.log_p - 0.5 * (residual / self.noise) ** 2
        else:
            self.log_p = self.log_p + norm.logcdf((np.log(self.tolerance / self.target) - predicted) / self.noise)

    def posterior(self) -> np.ndarray:
        """Normalised posterior on the grid, shape (A, B)."""
        return np.exp(self.log_p - logsumexp(self.log_p))

    def best_speed(self) -> tuple[float, float]:
        """The release speed (rad/s) most likely to hit, and its probability of a hit.

        P(hit | u) = sum over b of P(-h - b x < a < h - b x | b), x = log(u / u0), h the window
        in log units: for every b the posterior's cumulative sum over a, interpolated, gives
        that interval's mass for all candidate speeds at once.
        """
        weights = self.posterior()  # (A, B)
        cdf = np.vstack([np.zeros(self.slope.size), np.cumsum(weights, axis=0)])  # (A + 1, B)
        step = self.offset[1] - self.offset[0]
        edges = np.r_[self.offset - 0.5 * step, self.offset[-1] + 0.5 * step]  # cell edges of a
        half = self.tolerance / self.target
        x = np.log(self.ratios)  # (C,)
        expected = np.zeros(x.size)
        for j, b in enumerate(self.slope):
            expected += (np.interp(half - b * x, edges, cdf[:, j])
                         - np.interp(-half - b * x, edges, cdf[:, j]))
        best = int(np.argmax(expected))
        return float(self.ratios[best] * self.reference), float(expected[best])


#: Standard deviation (log speed) of a whole-arm throw's prior about the speed its kinematics aim
#: at the basket (:func:`rlff.learn.reach.aimed_factor`): in the simulation the aim's landing is
#: within about 1 cm; on an arm a few per cent slower than its robot file, or one that lets go
#: late, it is off by about 0.05.
AIM_SCALE = 0.1


class CalibrateUpdate(DmmStrategy):
    """This project's strategy: the DMM gives the throw, the attempts calibrate its speed."""

    name = "calibrate"
    carries = True  # its window search and its distance calibration start at Problem.carried_shift
    robot_weight = 3.0
    #: With binary feedback, whether the window search comes back to a window that missed (with
    #: the run's ``Problem.misreport``, :func:`rlff.learn.windows.with_retries`).
    retries_misses = True

    def __init__(self, problem: Problem):
        super().__init__(problem)
        self.demos = labelled_demos(problem.demos)
        #: Distance (m) the throw's shape is asked for: see :func:`shape_distance`.
        self.shape_query = shape_distance(problem)
        inputs = np.column_stack([problem.angles, np.full(problem.angles.size, self.shape_query)])
        #: The mixture of the demonstrations alone, fitted once per run with the model's restarts
        #: as the baselines fit it (with one start, held-out seed 13491's mixture of `short`
        #: people put the GMR mean's release for 1.9 m at 3.98 rad/s where the baselines' put it
        #: at 7.5; the hit is at the limit, 11.3, and the run missed 20 times).
        self.model = model = problem.demonstrations_model()
        #: The GMR mean's throw from the demonstrations alone, and its release speed (rad/s):
        #: where the calibration's prior says the basket is.
        self.first = Proposal.of_outputs(problem.angles, model.condition(inputs).mean, model.outputs, problem.target)
        self.reference = release_speed(problem.angles, self.first.velocity)
        self._demos_shape: Proposal | None = None
        self._windows: WindowSearch | None = None
        self._lowest: dict[tuple[float, float], float] = {}  # see :meth:`lowest`
        self._prior = ""  # the window search's prior, by name (set with the windows)
        if problem.aim is not None:  # the arm's kinematics say how fast (a whole-arm throw, or --aim)
            self.reference = self.aimed_speed()
        if not self.reference > 0:
            raise InputError(f"the GMR throw for {problem.target:g} m does not move at its "
                             "release: the demonstrations give no throw to calibrate")

    def aimed_speed(self) -> float:
        """The driven joint's release speed (rad/s) at which the arm's kinematics send this
        method's first throw to the basket (``Problem.aim``): its shape from the demonstrations
        alone, capped at the release, as :meth:`propose` scales it. (Aiming the GMR mean's throw
        instead, whose other joints move differently, put the MSR throw for 2 m at 2.17 m.)"""
        problem = self.problem
        thrown = capped_at_release(problem.angles, self.shape([]))
        speed = release_speed(problem.angles, thrown.velocity)
        if not speed > 0:  # no motion at the release: propose throws the GMR mean's throw
            thrown, speed = self.first, release_speed(problem.angles, self.first.velocity)
        return speed * problem.aim(thrown)

    def _thrown(self, shape: Proposal) -> tuple[Proposal, float]:
        """The throw of ``shape`` capped at its release, and its release speed (rad/s); the GMR
        mean's throw where ``shape`` does not move at its release."""
        problem = self.problem
        throw = capped_at_release(problem.angles, shape)
        speed = release_speed(problem.angles, throw.velocity)
        if not speed > 0:  # no motion at the release: keep the demonstrations' shape
            throw = self.first
            speed = release_speed(problem.angles, throw.velocity)
        return throw, speed

    def _fastest(self, throw: Proposal, speed: float) -> float:
        """The fastest release speed (rad/s) ``throw``, released at ``speed``, is asked for (see
        :meth:`propose`)."""
        problem = self.problem
        if problem.saturation is None:
            return speed * problem.max_speed / max(abs(float(throw.velocity[-1])), 1e-12)
        return speed * problem.saturation(throw)

    def propose(self, history: Sequence[Attempt]) -> Proposal:
        problem = self.problem
        shape = self.shape(history)
        throw, speed = self._thrown(shape)
        # the fastest speed asked for: a whole arm's, where every joint saturates at its limit;
        # one joint's, where the path's last sample reaches the joint's limit. The planner lets go
        # at that sample's velocity and plans the swing from the first pose up to it, so a peak
        # earlier in the path saturates without changing what the robot does (with every sample
        # held to the limit, seed 118's throw for 1.9 m with noisy landings, which peaks
        # mid-path, was released at 8.5 rad/s instead of 10.2 and fell 0.46 m short 20 times).
        # The speed is the mean over the path's last tenth, and a human throw's last sample is
        # often slower than the ones before it: with the limit put on that mean, seed 13306's
        # throw for 1.9 m with noisy landings let go at 0.91 of the limit, fell 0.29 m short
        # there and missed 20 times, in a basket within the joint's reach.
        fastest = self._fastest(throw, speed)
        if problem.feedback == "binary":
            # the windows are the first attempt's, also in a run resumed from its log (``donut``'s
            # shape, and with it the fastest speed, changes with every miss: a resumed whole-arm
            # run had laid them on a later shape and thrown otherwise from there, tester J)
            first = fastest if not history or self._windows is not None else self._fastest(*self._thrown(self.shape([])))
            x, mass = self.windows(first).offset(len(history))
            wanted = min(self.reference * math.exp(x), fastest)
            info = {"speed": round(wanted, 4), "log_factor": round(x, 4), "p_window": round(mass, 4),
                    "prior": self._prior}
        else:
            # carried hits: the first proposal at the speed they point to
            start = self.reference * math.exp(problem.carried_shift)
            calibration = SpeedCalibration(problem.target, problem.tolerance, start, fastest,
                                           slope=problem.elasticity, lowest=self.lowest(start, RANGE_ELASTICITY))
            for attempt in history:
                executed = release_speed(problem.angles, np.interp(problem.angles, attempt.angle,
                                                                   attempt.velocity))
                if problem.saturation is not None:  # whole arm: the speed asked for (see Problem)
                    executed = float(attempt.info.get("speed", executed))
                calibration.observe_landing(executed, attempt.landing)
            wanted, p_hit = calibration.best_speed()
            info = {"speed": round(wanted, 4), "log_factor": round(math.log(wanted / self.reference), 4),
                    "p_hit": round(p_hit, 4)}
        factor = wanted / speed
        if problem.saturation is None:
            # never beyond the limit at the release sample: the binary windows are made on the
            # first attempt's shape, and ``donut``'s shape changes with every miss
            factor = min(factor, problem.max_speed / max(abs(float(throw.velocity[-1])), 1e-12))
        return replace(scale_speed(throw, factor), query=problem.target, exploration=shape.exploration,
                       info=info)

    def windows(self, fastest: float) -> WindowSearch:
        """The binary search over the release speed's hit windows up to the speed ``fastest``
        (rad/s; made once per run, on the first attempt's throw, :meth:`propose`), its windows as
        wide as the hit window seen through the elasticity of the landing in the speed
        (``Problem.elasticity``)."""
        if self._windows is None:
            problem = self.problem
            centre, scale = self.speed_centre()
            self._prior, density = self.speed_prior()
            self._windows = WindowSearch(problem.target, problem.tolerance, math.log(fastest / self.reference),
                                         density, scale=scale, elasticity=problem.elasticity, centre=centre,
                                         misreport=problem.misreport if self.retries_misses else 0.0,
                                         lowest=self.lowest(self.reference, problem.elasticity))
        return self._windows

    def lowest(self, reference: float, elasticity: float) -> float:
        """The slowest log speed factor over ``reference`` (rad/s) the speed search goes down to
        with windows sized by ``elasticity`` (:func:`rlff.learn.windows.lowest_for`): the same for
        the whole run (its reference and the basket stay), so found once and kept."""
        key = (reference, elasticity)
        if key not in self._lowest:
            problem = self.problem
            self._lowest[key] = lowest_for(problem.landing, reference, problem.target, problem.tolerance,
                                           window_width(problem.target, problem.tolerance, elasticity))
        return self._lowest[key]

    def speed_centre(self) -> tuple[float, float]:
        """Where the window search's lattice and normal prior are centred (log speed factor), and
        the prior's standard deviation: about the mean offset of earlier baskets' hits with
        :data:`rlff.learn.carry.CARRY_SCALE` when the run carries them; about the speed the demonstrations' landings point to
        when enough of them are known (:func:`rlff.learn.landings.landing_speed`; its standard
        error and :data:`rlff.learn.landings.ROBOT_SCALE` added in quadrature); without landings
        about the GMR mean's speed where every demonstration missed (the failures' prior's
        lattice), else about where the range law through the demonstrations' labels puts the
        basket (:func:`rlff.learn.landings.aims_shift`: near / wide / overshooting / mixed
        2.47 / 2.37 / 1.78 / 2.35 -> 2.25 / 2.36 / 1.78 / 2.21 attempts on the tuning seeds 0-95,
        emulated on measured hit curves), the first with :data:`rlff.learn.windows.PRIOR_SCALE`,
        the second with the narrower :data:`rlff.learn.landings.LABELS_SCALE`. A
        whole-arm throw's u0 is where
        the arm's kinematics aim (:func:`rlff.learn.reach.aimed_factor`), and its prior is
        :data:`AIM_SCALE` about it: as wide as the GMR mean's, its tail beyond the speed limit
        outweighed the aim's window wherever the limit lay within three windows above the aim,
        and the first throw went to the limit (0.2-0.8 m long on the people of seed 1 at 4-4.5 m)."""
        problem = self.problem
        belief = self.speed_belief
        if belief == "carried":
            return problem.carried_shift, CARRY_SCALE
        if belief == "landings":
            law = self.landings_law
            return math.log(law.speed / self.reference), math.hypot(law.log_error, ROBOT_SCALE)
        if belief == "aim":
            return 0.0, AIM_SCALE
        if belief == "failures":  # the failures' prior, whose lattice is laid about u0
            return 0.0, PRIOR_SCALE
        return aims_shift(problem.demos, problem.angles, problem.target, self.reference,
                          problem.elasticity), LABELS_SCALE

    @cached_property
    def speed_belief(self) -> str:
        """What the window search's prior rests on, decided once for :meth:`speed_centre` and
        :meth:`speed_prior`, first that applies: ``carried`` (earlier baskets' hits), ``landings``
        (at least 3 known landings, a one-joint throw), ``aim`` (a whole-arm throw's kinematic
        aim), ``failures`` (every demonstration missed) or ``labels`` (the range law through the
        demonstrations' labels)."""
        problem = self.problem
        if problem.carried:
            return "carried"
        if self.landings_law is not None:
            return "landings"
        if problem.aim is not None:
            return "aim"
        return "failures" if all_missed(problem.demos) else "labels"

    @cached_property
    def landings_law(self) -> LandingSpeed | None:
        """The speed the demonstrations' known landings point to (None: fewer than 3 known, or a
        whole-arm throw, whose u0 the arm's kinematics give); fitted once, for the centre and the
        prior of the window search."""
        problem = self.problem
        if problem.aim is not None:
            return None
        return landing_speed(problem.demos, problem.angles, problem.target, problem.elasticity)

    def speed_prior(self) -> tuple[str, Callable[[np.ndarray], np.ndarray] | None]:
        """The window search's prior over the hit's log speed factor: its name, which the
        attempts log records as ``prior``, and its log density (None: the normal prior about
        :meth:`speed_centre`). ``carried``: normal about the speed earlier baskets' hits point to
        (:mod:`rlff.learn.carry`); ``landings``: normal about the speed the known landings point to;
        ``failures``: where every demonstration missed and none of their landings is known (a
        one-joint throw), the prior of :mod:`rlff.learn.outcomes` (the speeds at which they would
        have hit ruled out, the ring about them first); ``aim``: normal about a whole-arm throw's
        kinematic aim; ``labels``: normal about where the range law through the demonstrations'
        labels puts the basket (:meth:`speed_belief`; before 2026-12-05 the log called the last
        two ``normal``)."""
        problem = self.problem
        belief = self.speed_belief
        if belief == "failures":
            return belief, outcomes_prior(problem.demos, problem.angles, problem.target, problem.tolerance,
                                          self.reference, problem.elasticity)
        return belief, None

    def shape(self, history: Sequence[Attempt]) -> Proposal:
        """The DMM's throw for the target from the demonstrations and the landed attempts.

        With binary feedback no attempt joins the data (a miss has no landing to label it
        with), so the throw is the same every time and is computed once.
        """
        landed = [a for a in history if a.landing > 0]  # NaN under binary feedback
        if not landed and self._demos_shape is not None:
            return self._demos_shape
        trajectories = list(self.demos) + [attempt_trajectory(a, a.landing) for a in landed]
        weights = [1.0] * len(self.demos) + [self.robot_weight] * len(landed)
        data, sample_weight = training_set(trajectories, weights)
        shape = self.generate(data, sample_weight, self.shape_query, {}, continuity=True,
                              model=None if landed else self.model)
        if not landed:
            self._demos_shape = shape
        return shape


class DonutSearch(CalibrateUpdate):
    """``calibrate`` with the window search ordered by the DMM's density of the release speed.

    The demonstrations all missed, so the hit is not where they agree: the DMM puts its density
    on a ring about each component's mean, as far out as the demonstrations disagree. With
    binary feedback the hit windows of the release speed are thrown in the order of the mass
    the DMM (fitted to the demonstrations, conditioned on the release part of the path and the
    basket) gives each, instead of the normal prior about the GMR mean that ``calibrate`` uses.
    Every miss also joins the data labelled with the target, as in Grollman & Billard's update:
    where the misses disagree with the demonstrations the donut moves the throw's shape away from
    what failed (for a whole arm the other joints' path and release pose; for one joint the
    planner keeps only the release, so this changes nothing the ball sees). With distance
    feedback it is ``calibrate`` with the attempts weighted as one demonstration each instead of
    three.
    """

    name = "donut"
    robot_weight = 1.0
    #: No window twice in the first pass, whatever ``--misreport`` says: the DMM's ring gives the
    #: windows masses so uneven that a likely window's retry came before an unlikely one that was
    #: the hit (held-out block 100-107, binary: 62 of 480 runs of ``donut`` and its ablations
    #: later, none sooner, e.g. ``short`` without labels 8 -> 13 throws), and with 20 % false
    #: misses it gained nothing (seeds 41000-41007, ``short``: 12.3 -> 13.4).
    retries_misses = False

    def speed_prior(self) -> tuple[str, Callable[[np.ndarray], np.ndarray] | None]:
        from rlff.model.donut import dmm_marginal_pdf, exploration_factor

        problem = self.problem
        if problem.carried:  # the robot's own hits say more than where the demonstrations disagree
            return "carried", None
        tail = release_samples(problem.angles.size)
        inputs = np.column_stack([problem.angles[-tail:], np.full(tail, self.shape_query)])
        conditional = self.model.condition(inputs)
        if self.exploration == "auto":
            eps = exploration_factor(conditional.covariance)
        else:
            eps = np.full(tail, float(self.exploration))
        mean = conditional.mean[:, 0]  # (tail,), its mean speed is the reference u0

        def log_density(x: np.ndarray) -> np.ndarray:
            # the GMR mean's release part scaled by e^x, density in log speed (Jacobian u)
            velocity = mean[:, None] * np.exp(x)[None, :]  # (tail, G)
            # the speed's density, a whole arm's other outputs integrated out (one output: dmm_pdf)
            pdf = np.mean(dmm_marginal_pdf(conditional, velocity, eps), axis=0)
            return np.log(np.maximum(pdf, 1e-300)) + x

        return "dmm", log_density

    def shape(self, history: Sequence[Attempt]) -> Proposal:
        if self.problem.feedback == "distance":
            return super().shape(history)
        failed = [a for a in history if not a.hit]
        if not failed and self._demos_shape is not None:
            return self._demos_shape
        trajectories = list(self.demos) + [attempt_trajectory(a, self.problem.target) for a in failed]
        weights = [1.0] * len(self.demos) + [self.robot_weight] * len(failed)
        data, sample_weight = training_set(trajectories, weights)
        shape = self.generate(data, sample_weight, self.shape_query, {}, continuity=True,
                              model=None if failed else self.model)
        if not failed:
            self._demos_shape = shape
        return shape


def shape_distance(problem: Problem) -> float:
    """The distance (m) a calibrated throw's shape is asked for: the target, except that a
    whole-arm throw's is kept within the demonstrations' labels. A whole-arm shape holds the other
    joints' positions, and a regression extrapolated beyond its data moves the release pose (on
    the MSR throws, labelled up to 2.75 m, the shoulder's release fell from 2.0 rad at 2 m to 1.4
    rad at 4 m, and the throw's reach with it); the speed calibration takes the throw the rest of
    the way. A one-joint shape is a velocity only, which the calibration rescales anyway."""
    if problem.outputs == ONE_JOINT_OUTPUTS:
        return problem.target
    labels = known_labels(problem.demos)
    return float(np.clip(problem.target, labels.min(), labels.max()))


def fastest_at_release(angles: np.ndarray, velocity: np.ndarray) -> np.ndarray:
    """The path's velocity (rad/s), shape (T,), capped at its release speed.

    Where the demonstrations disagree, the DMM's mode can switch between the donut's sides along
    the path and run faster before the release than at it. Scaled to a release speed, such a
    path hits the joint's limit before the release, and the velocity servo cannot brake to the
    commanded release speed in time: the landing then follows the saturated middle of the path,
    not the release speed the calibration sets. Capped, the throw is fastest at its release, as
    a throw should be, and the release speed alone decides where it lands.
    """
    cap = release_speed(angles, velocity)
    return np.sign(velocity) * np.minimum(np.abs(velocity), cap)


def capped_at_release(angles: np.ndarray, proposal: Proposal) -> Proposal:
    """``proposal`` with its elbow capped by :func:`fastest_at_release` and every other joint's
    velocity slowed by the same factor at each sample (the coordinated throw keeps one time base)."""
    capped = fastest_at_release(angles, proposal.velocity)
    moving = proposal.velocity != 0
    factor = np.ones(capped.shape)
    factor[moving] = capped[moving] / proposal.velocity[moving]
    return replace(scale_speed(proposal, factor), velocity=capped)


def ablations(method: type[DmmStrategy]) -> list[type[DmmStrategy]]:
    """The method without its donut (exploration 0) and with the GMR mean's shape instead of the DMM's."""
    return [
        type(f"{method.__name__}NoExploration", (method,), {
            "name": f"{method.name}:no-exploration", "exploration": 0.0, "ablates": method.name,
            "__doc__": f"``{method.name}`` with the DMM's exploration off (ablation)."}),
        type(f"{method.__name__}GmrMean", (method,), {
            "name": f"{method.name}:gmr-mean", "shape_source": "gmr", "ablates": method.name,
            "__doc__": f"``{method.name}`` with the GMR mean as the throw's shape (ablation)."}),
    ]


#: This project's methods (the rest are baselines and ablations).
PROJECT_METHODS = ("calibrate", "donut")
STRATEGIES: dict[str, type[DmmStrategy]] = {
    cls.name: cls
    for method in (FailureUpdate, HindsightUpdate, CalibrateUpdate, DonutSearch)
    for cls in (method, *ablations(method))
}

