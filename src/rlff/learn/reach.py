"""What the arm's throws reach: the whole-arm throw's reach, aim and speed law, and when a run
stops because the basket is beyond the arm.

The loop's throws are one shape along its angle grid, sped up or slowed down as a whole (one
factor on every driven joint's velocity). The robot file's geometry says where the free flight
from a throw's release state comes down (to about a centimetre in the simulation), and so how
far a shape reaches at the joints' speed limits (:func:`arm_reach`), the factor that aims it at a
basket (:func:`aimed_factor`), the landing's elasticity in the speed (:func:`release_elasticity`)
and where faster stops helping (:func:`saturation_factor`): what the whole-arm calibration and
the loop's checks before the first throw use.

After a throw, the landing the executor reported and the gain the fastest release would add to
it say whether the basket is within the real arm's reach (:func:`shortfall_at_the_limit`): the
loop stops after :data:`SHORT_AT_THE_LIMIT` throws in a row that say it is not
(:func:`beyond_reach`), as an arm slower than its robot file, a late release or a heavier ball
make it; a run ``until="centred"`` stops too where only its centre window is beyond the arm, and
says so. The other way, where a throw comes down with every speed (:func:`typical_landing`)
says how slow the searches must go for a near basket.

A run also stops when its method throws the same throw again and again
(:func:`let_go_the_same_way`): after :data:`SAME_AT_THE_LIMIT` at the arm's speed limit, where
asking for more speed gets the same throw (:func:`same_throw_at_the_limit`), and after
:data:`SAME_REPORTED` anywhere when each was reported the same (:func:`same_throw_reported_the_same`).

Hand-written: bisections on one speed factor and a closed-form flight, the project's own
reasoning about its throws.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from rlff.dataset import joint_outputs
from rlff.errors import InputError
from rlff.learn.attempt import Attempt
from rlff.learn.demos import drives_whole_arm
from rlff.robot.mapping import scaled_speed
from rlff.trajectory.planner import MARGIN
from rlff.wording import numbered, signed

#: Throws in a row that came down short of the basket's rim even sped up to the fastest release
#: the joints allow, after which a run stops: the basket is beyond what this arm throws.
SHORT_AT_THE_LIMIT = 3
#: Throws in a row that let go the same way at the fastest release the joints allow, after which
#: a run stops: the method asks for more speed than the arm has, and the ball comes down as before
#: (failure and hindsight on the real MSR throws at 1.6 m: every throw 0.58 m long, to the budget).
SAME_AT_THE_LIMIT = 3
#: Attempts in a row that let go the same way and were reported the same (the same hit or
#: miss, the same miss to :data:`SAME_MISS` where one was reported), after which a run stops
#: wherever the release is: the method is not changing its throw. Generous, as a method told the
#: same may still change its mind: failure refits its model with every failed throw, and over the
#: learning benchmark's grid with a budget of 60 (short, wide and overshooting, seeds 100-101,
#: every method, both feedbacks: 324 runs) it threw one throw up to 12 times in a row before
#: another (seed 101 at 1.9 m); 50 is four times that, and above every budget of the benchmark
#: (20-30), so none of its rows can change. A tester's failure run with binary feedback threw one
#: throw below the speed limit 1,000 times, to its budget.
SAME_REPORTED = 50
#: Largest spread (m) of the misses reported for the same throw that still counts as the same
#: report (:func:`same_throw_reported_the_same`): a centimetre.
SAME_MISS = 0.01
#: A throw counts as let go as fast as the joints allow when its last driven joint could go at
#: most this factor faster: the planner keeps :data:`rlff.trajectory.planner.MARGIN` of the speed
#: limits, and a throw asked for at the limit lets go a little below it (a UR5e-like file at 3.12
#: of its 3.14 rad/s, and within 0.1 %, the rule until 2026-12-06, it never counted: one throw
#: 7 mm beyond the rim was thrown 18 times).
AT_THE_LIMIT = 1 / MARGIN
#: The slowest speed factor the aim and the reach look at, as a share of the fastest, and the
#: points of their log-spaced grid (:func:`aimed_factor`, :func:`arm_reach`).
_SLOWEST_AIM, _AIM_GRID = 0.05, 48
#: What limits a throw's speed when the planner cannot make it faster (:func:`fastest_factor`).
NO_ROOM = "the planner runs out of room to wind up or brake within the position limits"


@dataclass(frozen=True)
class ArmReach:
    """How far the loop's whole-arm throws go (see :func:`arm_reach`).

    Attributes
    ----------
    distance : float
        Where the ball comes down through the rim's height (m from the joint 1 axis); ``-inf``
        when it never does.
    factor : float
        The speed factor on the shape that gets there.
    limiting : str
        What sets ``factor``: a joint at its speed limit, or the planner's room to wind up or brake.
    """

    distance: float
    factor: float
    limiting: str


def arm_reach(mapping, shape: dict[str, np.ndarray], rim_height: float, pedestal: float = 0.0, *,
              headroom: float = 0.0) -> ArmReach:
    """The reach of the whole-arm throws of ``shape`` through ``mapping``.

    Every method throws a shape along the loop's angle grid, sped up or slowed down as a whole
    (one factor on every joint's velocity). The motion planner keeps a throw's first pose and
    its release state exactly and plans the swing between them within the limits
    (:func:`rlff.trajectory.planner.plan_throw`; a swing too short for the release speed is
    preceded by a wind-up, which must stay within the position limits), so the farthest of
    these throws is ``shape`` (the loop's first throw, or the demonstrations' typical throw,
    :func:`rlff.learn.demos.typical_throw`: columns of shape (T,) along the angle grid, the
    velocities forward) at the largest factor that keeps the elbow's joint within its speed
    limit at the release (the other joints saturate at theirs) and that the planner can still
    execute, found by bisection; its ball comes down where the release state sends it
    (:func:`release_crossing_of`). With ``headroom`` (0 <= h < 1) the largest factor is
    ``1 - headroom`` of that: the reach with that share of the joints' speed kept in reserve.
    """
    if not 0.0 <= headroom < 1.0:
        raise InputError(f"speed headroom must be a share in [0, 1), got {headroom!r}")
    factor, limiting = fastest_factor(mapping, shape, 1 - headroom)
    if not math.isfinite(factor):
        return ArmReach(release_crossing_of(mapping, scaled_speed(shape, factor), rim_height, pedestal), factor, limiting)
    # the farthest of the slower throws too: where a joint's speed turns the ball up or back (the
    # real MSR throws with joints 2 and 3 at their fastest came down 1.22 m behind the base, and
    # a basket at 0.8 m, which a slower throw hits, was refused), the fastest is not the farthest
    factors = np.r_[factor * np.geomspace(_SLOWEST_AIM, 1.0, _AIM_GRID)[:-1], factor]
    landings = np.array([release_crossing_of(mapping, scaled_speed(shape, f), rim_height, pedestal) for f in factors])
    best = int(np.argmax(landings))
    if best < factors.size - 1 and landings[best] > landings[-1]:
        limiting = f"{limiting}; the farthest at {factors[best] / factor:.2g} of that speed, faster throws come down nearer"
    return ArmReach(float(landings[best]), float(factors[best]), limiting)


def fastest_factor(mapping, path: dict[str, np.ndarray], share: float = 1.0) -> tuple[float, str]:
    """The largest factor on every velocity of ``path`` (columns of shape (T,), no ``time``) at
    which the arm still makes the throw, and what sets it: the last driven joint's speed limit
    at the release (:func:`release_speed_factor`; ``share`` of it), or, where the planner cannot
    execute that throw (:func:`rlff.robot.plan.plan_path`, saturated as the loop executes it),
    the room to wind up before the swing or to brake after the release within the position
    limits, found by bisection. A joint whose range ends just past the release stops a fast
    throw as surely as its speed limit does (a tester's arm with joint_2's upper limit at
    -0.05 rad let go at 1.41 rad/s of its 1.8, and the speed limit alone said the throw could go
    10 times faster: 7 identical throws 0.27 m short, and the run never stopped). inf when no
    driven joint moves at the release."""
    from rlff.robot.plan import plan_path

    factor, limiting = release_speed_factor(mapping, path)
    if not math.isfinite(factor):
        return factor, limiting
    factor *= share * (1 - 1e-9)  # at the limit, not a rounding beyond it

    def executable(f: float) -> bool:
        try:
            plan_path(mapping, scaled_speed(path, f), clip=True)  # saturated as the loop executes it
        except InputError:
            return False
        return True

    if not executable(factor):
        low, high = 0.0, factor
        for _ in range(14):  # the factor to 1e-4 of the speed limit's
            middle = 0.5 * (low + high)
            low, high = (middle, high) if executable(middle) else (low, middle)
        factor, limiting = low, NO_ROOM
    return factor, limiting


def release_elasticity(mapping, typical: dict[str, np.ndarray], target: float, rim_height: float,
                       pedestal: float = 0.0) -> float:
    """The elasticity d ln L / d ln u of the landing L in the throw's speed u near ``target`` (m),
    from the arm's kinematics: the demonstrations' typical throw (``typical``,
    :func:`rlff.learn.demos.typical_throw`) sped up or slowed down as a
    whole until its release state sends the ball to ``target`` (or as far as it goes), its
    landing differentiated there. A one-joint throw from the base has about 1.6 (the speed
    calibration's prior); a whole-arm throw released above and behind the base has more, and
    the calibration centres its prior on it.
    """
    highest, _ = release_speed_factor(mapping, typical)

    def landing(f: float) -> float:
        return release_crossing_of(mapping, scaled_speed(typical, f), rim_height, pedestal)

    low, high = 0.05, highest
    if landing(high) > target:
        for _ in range(30):
            middle = math.sqrt(low * high)
            low, high = (middle, high) if landing(middle) < target else (low, middle)
    step = 1.03
    near, far = landing(high / step), landing(high)
    if not (near > 0 and far > near):
        return 1.6
    return float(np.clip(math.log(far / near) / math.log(step), 0.5, 5.0))


def aimed_factor(mapping, target: float, rim_height: float, pedestal: float, proposal) -> float:
    """The factor on every velocity of ``proposal`` (a whole-arm throw) that sends its ball to
    ``target`` (m) by the arm's kinematics and the free flight from the release
    (:func:`release_crossing_of`): the slowest on a log grid from a twentieth of the speed at which
    its first joint reaches its limit to the fastest release within the joints' speed limits
    whose ball gets there, refined by bisection in log speed (the farthest throw when none
    does); 1 when its release sends the ball nowhere.

    This is what a whole-arm throw's speed calibration takes as the speed where the basket is
    (its prior's centre): the mapping from the people's joints to the robot's changes where a
    throw lands far more than the one-joint mapping does, while the robot's own geometry
    predicts the free flight from a release state (in the simulation to about a centimetre).
    """
    path = proposal.path
    highest, _ = release_speed_factor(mapping, path)
    if not np.isfinite(highest):
        return 1.0

    def landing(f: float) -> float:
        return release_crossing_of(mapping, scaled_speed(path, f), rim_height, pedestal)

    # the slowest throw of the grid that gets there: from a twentieth of the speed at which the
    # FIRST driven joint reaches its limit (the last's, when a joint hardly moves at the release,
    # is where the others saturated long before: the real MSR throws with joints 2, 3 and 5 let
    # joint 5 go at a nineteenth of its limit, the grid began above the aim, and every throw for
    # a basket at 1.2-2.5 m came down 0.3-2.9 m long); a landing need not grow with the speed
    # everywhere (a joint that turns the ball up or back), so the grid is scanned before the bisection
    fastest = highest * (1 - 1e-9)
    factors = np.geomspace(min(_SLOWEST_AIM * first_saturation(mapping, path), fastest), fastest, _AIM_GRID)
    landings = np.array([landing(f) for f in factors])
    reached = np.flatnonzero(landings >= target)
    if not reached.size:  # beyond every throw: the farthest one
        best = int(np.argmax(landings))
        return float(factors[best]) if np.isfinite(landings[best]) else 1.0
    if reached[0] == 0:
        return float(factors[0])
    low, high = float(factors[reached[0] - 1]), float(factors[reached[0]])
    for _ in range(40):
        middle = math.sqrt(low * high)
        low, high = (middle, high) if landing(middle) < target else (low, middle)
    return math.sqrt(low * high)


def first_saturation(mapping, path: dict[str, np.ndarray]) -> float:
    """The factor on every velocity of ``path`` at which the first driven joint reaches its speed
    limit at the release (:func:`release_speed_factor` gives the last); inf when none moves."""
    return min((factor for factor, _ in _saturations(mapping, path)), default=math.inf)


def saturation_factor(mapping, proposal) -> float:
    """The factor on every velocity of ``proposal`` (a whole-arm throw) beyond which no driven
    joint can go faster at the release (see :func:`release_speed_factor`)."""
    return release_speed_factor(mapping, proposal.path)[0]


def release_speed_factor(mapping, path: dict[str, np.ndarray]) -> tuple[float, str]:
    """The factor on every velocity of ``path`` at which the last driven joint reaches its speed
    limit at the release, and that joint (as the reason): below it, the joints that get there
    first saturate (as every executed throw does: the robot never exceeds a limit) while the
    others still speed up and throw farther; above it, nothing changes."""
    saturations = _saturations(mapping, path)
    if not saturations:
        return math.inf, ""
    factor, name = max(saturations, key=lambda saturation: saturation[0])  # the first of equals
    return factor, f"every joint reaches its speed limit (the last: {name})"


def _saturations(mapping, path: dict[str, np.ndarray]) -> list[tuple[float, str]]:
    """For each driven joint moving at ``path``'s release, in the mapping's order: the factor on
    every velocity at which it reaches its speed limit there, and its name."""
    limits = mapping.max_human_speeds()
    columns = (c for c in joint_outputs(mapping.human_columns) if c.endswith("velocity"))
    return [(limits[column] / abs(float(path[column][-1])), name)
            for column, name in zip(columns, mapping.driven_joints, strict=True) if abs(float(path[column][-1])) > 0]


def more_joints(mapping) -> list[str]:
    """The joints of the robot file's ``[whole_arm]`` table a whole-arm ``mapping`` leaves
    undriven, which may throw farther (none for a one-joint mapping), in the table's order."""
    if not drives_whole_arm(mapping):
        return []
    return [name for name in (mapping.robot.whole_arm or {}).get("joints", {}) if name not in mapping.driven_joints]


def more_joints_words(mapping) -> str:
    """``--joints joint_2,joint_3,joint_5 may reach farther`` for :func:`more_joints`, or ""."""
    more = more_joints(mapping)
    return f"--joints {','.join((*sorted(mapping.driven_joints), *more))} may reach farther" if more else ""


def release_crossing_of(mapping, path: dict[str, np.ndarray], rim_height: float, pedestal: float) -> float:
    """Where the ball of ``path``'s release comes down through the rim's height (m from joint 1's
    axis, no drag): the arm's in-plane ball velocity at the release pose (joint 1 turns the plane
    to the bearing; it does not change the distance); ``-inf`` when it never does or the arm is
    too low."""
    from rlff.sim.reach import release_crossing

    release, _ = mapping.path_to_robot(path, clip=True)
    return release_crossing(mapping.robot, release.positions[-1], release.velocities[-1], rim_height, pedestal,
                            clearance=True)


def typical_landing(mapping, typical: dict[str, np.ndarray], rim_height: float, pedestal: float,
                    speed: float) -> float:
    """Where ``typical`` (:func:`rlff.learn.demos.typical_throw`), sped up or slowed down as a
    whole to the release speed ``speed`` (rad/s, the demonstrations' units, as
    :func:`rlff.learn.method.release_speed` measures it), comes down through the rim's height (m
    from joint 1's axis, :func:`release_crossing_of`); ``-inf`` when it never does."""
    from rlff.learn.method import release_speed

    own = release_speed(typical["angle"], typical["velocity"])
    if not own > 0:
        return -math.inf
    return release_crossing_of(mapping, scaled_speed(typical, speed / own), rim_height, pedestal)


def widest_hit(basket) -> float:
    """Largest distance (m) from the basket's centre at which a ball coming down to the rim's
    height can still end in the basket: half the opening and the ball's radius (its centre over
    the rim, so that it strikes the rim's top and may drop in)."""
    from rlff.sim.arm import BALL_RADIUS

    return 0.5 * basket.opening + BALL_RADIUS


def shortfall_at_the_limit(attempt: Attempt, mapping, basket, tolerance: float, pedestal: float = 0.0,
                           seen: Sequence[Attempt] = ()) -> float:
    """How far (m) ``attempt`` would still have come down short of the window ``tolerance`` (m)
    about the basket's centre had the robot released it as fast as its joints allow; 0 when that
    throw could reach the window, or when the attempt did not land short of it or reported no
    landing.

    Two judgements, the larger counts:

    - the attempt's executed path, every velocity scaled by one factor up to where the last
      driven joint reaches its speed limit at the release (the others saturate at theirs, as the
      robot saturates them) or the planner runs out of room to brake within the position limits
      (:func:`fastest_factor`), gains what the free flight from its release state gains
      (:func:`release_crossing_of`): that gain is added to the landing the executor reported. An
      arm slower than its file, or one that lets go late, gains less than the file says, so this
      errs towards throwing again;
    - a throw among ``seen`` (the run's attempts) that let go from the same release pose at the
      fastest the joints allow, its release velocities the attempt's sped up, came down where
      the attempt's would at best (:func:`fastest_seen`): no model, only that a faster release
      of the same direction throws farther.

    The shape is the attempt's: a method that changes the release angle could reach farther,
    which is why :func:`rlff.learn.learn` asks for :data:`SHORT_AT_THE_LIMIT` such throws in a row.
    """
    if not (math.isfinite(attempt.miss) and attempt.miss < -tolerance):
        return 0.0
    observed = fastest_seen(attempt, seen, mapping)
    shortfall = max(0.0, -tolerance - observed) if math.isfinite(observed) else 0.0
    path = _untimed(attempt)
    factor, _ = fastest_factor(mapping, path)
    if not math.isfinite(factor):
        return shortfall
    now = release_crossing_of(mapping, path, basket.rim_height, pedestal)
    fastest = release_crossing_of(mapping, scaled_speed(path, max(factor, 1.0)), basket.rim_height, pedestal)
    if not (math.isfinite(now) and math.isfinite(fastest)):
        return shortfall
    return max(shortfall, -tolerance - (attempt.miss + max(fastest - now, 0.0)))


def fastest_seen(attempt: Attempt, seen: Sequence[Attempt], mapping) -> float:
    """The signed miss (m) of the farthest throw in ``seen`` that let go from ``attempt``'s
    release pose as fast as the joints allow (the last driven joint within :data:`AT_THE_LIMIT`
    of its speed limit), every driven joint at least as fast as in ``attempt`` and in the same direction
    (:func:`at_least_as_fast`); NaN when none did, or none reported a landing."""
    pose, velocity = _release_state(attempt, mapping)
    misses = []
    for other in seen:
        if not math.isfinite(other.miss):
            continue
        other_pose, other_velocity = _release_state(other, mapping)
        if not np.allclose(other_pose, pose, rtol=0.0, atol=1e-6):
            continue
        if not at_least_as_fast(other_velocity, velocity):
            continue
        if release_speed_factor(mapping, _untimed(other))[0] <= AT_THE_LIMIT:
            misses.append(other.miss)
    return max(misses) if misses else math.nan


def at_least_as_fast(faster: np.ndarray, slower: np.ndarray) -> bool:
    """Whether release velocities ``faster`` (rad/s, shape (J,)) have every joint at least as fast
    as ``slower`` in the same direction, a joint still in ``slower`` still in ``faster``: what one
    shape sped up by a larger factor gives, each joint saturating at its own limit (a whole-arm
    throw at the fastest release is seldom the slower one's velocities times one factor: with a
    late release, people of seed 4 threw 10 times at 4.5 m, each slower window judged on the
    model's gain alone, where 3 say the basket is beyond the arm)."""
    still = np.abs(slower) <= 1e-12
    if np.any(np.abs(faster[still]) > 1e-9):
        return False
    moving = ~still
    return bool(np.all(faster[moving] / slower[moving] >= 1.0 - 1e-9))


def _untimed(attempt: Attempt) -> dict[str, np.ndarray]:
    """``attempt``'s executed path without its time: what :func:`scaled` speeds up (the time of
    a path sped up follows from its angle and velocity, not from the attempt's)."""
    return {column: values for column, values in attempt.path.items() if column != "time"}


def _release_state(attempt: Attempt, mapping) -> tuple[np.ndarray, np.ndarray]:
    """The release pose (rad) and velocities (rad/s) of ``attempt``'s driven columns, in the
    order of ``mapping``'s (the elbow's first), shape (J,) each."""
    path = attempt.path
    pose = [path[column][-1] for column in mapping.human_columns]
    velocity = [path[column][-1] for column in joint_outputs(mapping.human_columns) if column.endswith("velocity")]
    return np.array(pose, dtype=float), np.array(velocity, dtype=float)


def beyond_reach(history: Sequence[Attempt], mapping, basket, pedestal: float,
                 centre_window: float = math.inf) -> tuple[str, bool] | None:
    """A note that the run stops because what it aims for is beyond the arm's reach, and whether
    that is the centre window alone (the basket is not shown to be), else None.

    Each of the last :data:`SHORT_AT_THE_LIMIT` attempts came down short of the window by more
    than its fastest release would make up (:func:`shortfall_at_the_limit`). The window is the
    basket's rim (:func:`widest_hit`), or with a finite ``centre_window`` (m, a run
    ``until="centred"``) that narrower window about the centre; where the run hit the basket, or
    a fastest release would still reach its rim, only the centre window is beyond the arm, and
    the note says so (the basket was hit at attempt 1, and a ball 15 mm short of the centre
    window at the limit had been said to be "out of this arm's reach", with advice to check the
    arm's speed limits or move the basket, until 2026-12-07). Needs the landings: under binary
    feedback from an operator (no landing reported) it never stops a run.
    """
    last = history[-SHORT_AT_THE_LIMIT:]
    if len(last) < SHORT_AT_THE_LIMIT:
        return None
    rim = widest_hit(basket)
    shortfalls = _shortfalls(last, history, mapping, basket, min(rim, centre_window), pedestal)
    if shortfalls is None:
        return None
    joints = ", ".join(mapping.driven_joints)
    allow = "allows" if len(mapping.driven_joints) == 1 else "allow"
    more = more_joints_words(mapping)  # a whole-arm run: the joints it leaves may throw farther
    if centre_window < rim:
        hits = [attempt.index for attempt in history if attempt.hit]
        at_rim = None if hits else _shortfalls(last, history, mapping, basket, rim, pedestal)
        if at_rim is None:
            within = f"within {_length(centre_window)} of the basket's centre"
            if hits:
                basket_words = (f"not the basket at {basket.distance:g} m: attempt{'s' if len(hits) > 1 else ''} "
                                f"{numbered(hits)} hit it")
                instead = (f"Take the hit (rlff learn's --out writes the run's last hit, attempt {hits[-1]}, "
                           f"robot-ready; rlff robot export of the log with --attempt {hits[-1]} too)")
            else:
                basket_words = f"though the basket's rim at {basket.distance:g} m may not be"
                instead = "Stop at the first hit instead (until='hit')"
            instead += ", or allow a wider window (a larger centre_share)"
            if more:
                instead += f", or drive more joints ({more})"
            return (f"stopped after attempt {last[-1].index}: the centre window ({within}) is beyond this arm's "
                    f"fastest throws, {basket_words}. Attempts {last[0].index}-{last[-1].index} came down short, "
                    f"and even at the fastest release {joints} {allow} they would have fallen "
                    f"{_lengths(shortfalls)} short of the centre window. {instead}"), True
        shortfalls = at_rim  # no hit, and short of the rim too: the basket is beyond the arm
    if fastest_factor(mapping, _untimed(last[-1]))[1] == NO_ROOM:
        why = ("The release is as fast as the arm can still wind up for and brake from within its position "
               "limits: if the arm's range allows, widen the robot file's lower/upper of the throwing joint, or "
               "move the basket nearer")
    else:
        why = ("An arm slower than its robot file, a late release or a heavier ball does that: check the robot "
               "file's speed limits, or move the basket nearer")
    if more:
        why += f", or drive more joints ({more})"
    return (f"stopped after attempt {last[-1].index}: the basket at {basket.distance:g} m is out of this arm's reach. "
            f"Attempts {last[0].index}-{last[-1].index} came down short, and even at the fastest release {joints} "
            f"{allow} they would have fallen {_lengths(shortfalls)} short of the basket's rim. {why} (rlff sim reach "
            "says how far the arm throws)"), False


def _shortfalls(last: Sequence[Attempt], history: Sequence[Attempt], mapping, basket, tolerance: float,
                pedestal: float) -> list[float] | None:
    """:func:`shortfall_at_the_limit` (m) of each of ``last`` to the window ``tolerance`` (m), the
    newest first; None as soon as one is 0 (most runs end the judgement at the newest)."""
    shortfalls = []
    for attempt in reversed(last):
        shortfall = shortfall_at_the_limit(attempt, mapping, basket, tolerance, pedestal, history)
        if not shortfall:
            return None
        shortfalls.append(shortfall)
    return shortfalls


def _length(metres: float) -> str:
    """A short length in words: ``0.0875 m``, or in millimetres under a centimetre (``1.75 mm``)."""
    return f"{metres:.3g} m" if metres >= 0.01 else f"{1000 * metres:.3g} mm"


def _lengths(shortfalls: Sequence[float]) -> str:
    """The range of ``shortfalls`` (m): ``0.26 m``, ``0.12-0.26 m``, in millimetres to a tenth where
    the least is under a centimetre (``1.0 mm``, ``4.0-15.3 mm``), which had printed as ``0.00 m``."""
    low, high = min(shortfalls), max(shortfalls)
    low_words, high_words = (f"{low:.2f}", f"{high:.2f}") if low >= 0.01 else (f"{1000 * low:.1f}", f"{1000 * high:.1f}")
    unit = "m" if low >= 0.01 else "mm"
    return f"{low_words} {unit}" if low_words == high_words else f"{low_words}-{high_words} {unit}"


def let_go_the_same_way(attempts: Sequence[Attempt], mapping) -> bool:
    """Whether every one of ``attempts`` let go from the release pose and at the release
    velocities of the last (``mapping``'s driven columns, to 1e-6 rad and rad/s): the same
    throw, as far as the ball's flight goes. The newest are compared first."""
    pose, velocity = _release_state(attempts[-1], mapping)
    for attempt in reversed(attempts[:-1]):
        other_pose, other_velocity = _release_state(attempt, mapping)
        if not (np.allclose(other_pose, pose, rtol=0.0, atol=1e-6)
                and np.allclose(other_velocity, velocity, rtol=0.0, atol=1e-6)):
            return False
    return True


def same_throw_at_the_limit(history: Sequence[Attempt], mapping, aimed: bool = False) -> str | None:
    """A note that the run stops when each of the last :data:`SAME_AT_THE_LIMIT` attempts let go
    from the same release pose at the same velocities (to 1e-6 rad and rad/s), the last driven
    joint at its speed limit (within :data:`AT_THE_LIMIT`), else None. ``aimed``: the run is aimed
    by the arm's kinematics already (``Problem.aim``), so the note does not advise that aim.

    Such a method asks again and again for a faster release than the arm makes: the saturated
    throw it gets lets go as the last one did, so the ball comes down where it did (to the
    simulation's centimetre and a real ball's spread). The rule of :func:`beyond_reach` stops
    such throws when they come down short; this one also when they come down long (the method
    moves the wrong way for this arm), and where no landing was reported.
    """
    last = history[-SAME_AT_THE_LIMIT:]
    if len(last) < SAME_AT_THE_LIMIT or not let_go_the_same_way(last, mapping):
        return None
    if release_speed_factor(mapping, _untimed(last[-1]))[0] > AT_THE_LIMIT:
        return None
    landed = [attempt.miss for attempt in last if math.isfinite(attempt.miss)]
    came_down = ""
    if landed:
        low, high = f"{min(landed):+.2f}", f"{max(landed):+.2f}"
        came_down = f" and came down {low} m" if low == high else f" and came down {low} to {high} m"
        came_down += " from the basket's centre"
    joints = ", ".join(mapping.driven_joints)
    allow = "allows" if len(mapping.driven_joints) == 1 else "allow"
    if landed and min(landed) > 0:
        why = ("The method asks for more speed than the arm has where the fastest throw already comes down long: it "
               "moves the wrong way for this arm (another update"
               + (")" if aimed else ", or aim='kinematics' for recorded throws or a robot file of your own)"))
    else:
        why = "The method asks for more speed than the arm has (another update, or a nearer basket)"
    return (f"stopped after attempt {last[-1].index}: attempts {last[0].index}-{last[-1].index} let go the same "
            f"way, at the fastest release {joints} {allow}{came_down}, and the next would too. {why}")


def same_throw_reported_the_same(reported: Sequence[Attempt], mapping) -> str | None:
    """A note that the run stops when each of the last :data:`SAME_REPORTED` attempts let go the
    same way (:func:`let_go_the_same_way`) and was reported the same, else None.

    ``reported`` are the run's attempts as its method was told them (binary feedback: no landing,
    miss NaN; ``until="centred"``: a hit only within the centre window). Reported the same: the
    same hit flag, and misses within :data:`SAME_MISS` (m) of each other, or all not measured (a
    miss is finite or NaN: a ball that never came down through the rim's height is reported where
    it first touched, :func:`rlff.learn.loop.reported_outcome`). A method that throws the same
    throw and is told the same about it again and again is not changing its throw, at the
    arm's speed limit (:func:`same_throw_at_the_limit`, after fewer) or below it: the next throw
    would be the same, and on a real arm every one of them is a throw wasted.
    """
    last = reported[-SAME_REPORTED:]
    if len(last) < SAME_REPORTED or not let_go_the_same_way(last, mapping):
        return None
    if len({bool(attempt.hit) for attempt in last}) > 1:
        return None
    misses = np.array([attempt.miss for attempt in last], dtype=float)
    if np.all(np.isfinite(misses)):
        if np.ptp(misses) > SAME_MISS:
            return None
        low, high = signed(float(np.min(misses))), signed(float(np.max(misses)))
        at = f", {low} m" if low == high else f", {low} to {high} m"
        outcome = f"{at} from the basket's centre"
    elif np.all(np.isnan(misses)):
        outcome = ""
    else:  # some measured, some not
        return None
    told = f"{'a hit' if last[-1].hit else 'a miss'}{outcome}"
    instead = "another update" if np.any(~np.isnan(misses)) else \
        "another update, or distance feedback (the signed miss says which way to move)"
    return (f"stopped after attempt {last[-1].index}: attempts {last[0].index}-{last[-1].index} let go the same way "
            f"and each was reported the same ({told}): the method is not changing its throw, and the next would be "
            f"the same again. Try {instead}, or check the feedback: an executor or an operator that reports every "
            "throw alike leaves the method nothing to learn from")
