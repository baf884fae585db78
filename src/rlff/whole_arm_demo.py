"""The whole-arm part of ``rlff demo``: the robot learns every basket the people aimed at, and more.

Simulated people throw with the shoulder and the elbow (and the wrist) at baskets 1 to 4 m away
on bearings 0 to 90 deg and mostly miss (:func:`rlff.synthetic.throws.whole_arm_demonstrations`)
→ the thesis' cleaning steps → for every basket, demonstrated or not, the learning loop with
the default method and binary feedback throws whole-arm (joint 2 from the shoulder, joint 3 from
the elbow, and joint 5 from the wrist where the loop refuses the basket as beyond what the
first two reach), joint 1 turned to the basket's bearing, until it hits or 10 attempts are spent.

The robot learns from what a recording knows: the basket each person aimed at, not where the ball
came down. Every basket is thrown at one bearing, the bearings taken in turn along the distances,
so that every distance and every bearing appear without throwing every pair.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from rlff.dataset import Dataset, write_csv
from rlff.errors import InputError
from rlff.report.folder import RunPaths

if TYPE_CHECKING:
    from rlff.sim.gap import Gap

#: Most attempts of every basket's run (the issue's goal: a hit within 10).
BUDGET = 10
#: The baskets nobody demonstrated (m), between and beyond the demonstrated ones.
UNSEEN = (1.25, 1.75, 3.75, 4.25, 4.5)
#: Bearings (deg) the baskets are put at, in turn.
BEARINGS = (0.0, 30.0, 60.0, 90.0, 45.0)
#: The joints of a whole-arm throw, and the joint added for a basket beyond their reach.
ARM_JOINTS = ("joint_2", "joint_3")
WRIST_JOINT = "joint_5"
#: Share of the joints' speed limits that joints 2 and 3 keep in reserve before joint 5 joins: they
#: throw alone only at baskets they reach at 90 % of their fastest throw. At the edge of their reach
#: an arm a few per cent slower than its robot file (a speed override, a lagging servo) falls short
#: at the limit and has nothing faster to try (``benchmarks/whole_arm_gap.py``: with a 5 % slower
#: arm, or a release 20 ms late, 3 of 60 baskets at 4-4.5 m went unhit with no headroom).
SPEED_HEADROOM = 0.1


@dataclass(frozen=True)
class BasketRun:
    """One basket's learning run.

    Attributes
    ----------
    distance : float
        Basket centre from joint 1's axis (m).
    bearing : float
        Its direction (deg, 0 straight ahead, positive to the left).
    demonstrated : bool
        People threw at this distance.
    joints : tuple of str
        The robot joints the throw drove.
    hit : bool
        The last attempt hit.
    attempts : int
    misses : list of float
        Signed miss along the bearing line of every attempt (m; NaN where the ball never came
        down).
    flight : dict or None
        The last attempt's release: ``position`` and ``velocity`` (3,) of the ball (m, m/s; x
        forward, y left, z up), the basket's ``rim_height`` (m) and ``hit``, for the 3-D
        figure; None when nothing was thrown.
    refused : str
        Why the loop threw nothing (the basket out of the loop's reach), else empty.
    """

    distance: float
    bearing: float
    demonstrated: bool
    joints: tuple[str, ...]
    hit: bool
    attempts: int
    misses: list[float]
    flight: dict | None
    refused: str = ""


@dataclass(frozen=True)
class WholeArm:
    """What the whole-arm part did.

    Attributes
    ----------
    demonstrations, demonstration_hits, clean_trajectories : int
        Simulated throws, how many hit, how many the cleaning kept.
    demonstrated_distances : list of float
        Distances left after the cleaning (m).
    runs : list of BasketRun
        One per basket, in the order learned.
    clean : Dataset
        The cleaned demonstrations.
    learned : dict of (distance, bearing) to LearningResult
    """

    demonstrations: int
    demonstration_hits: int
    clean_trajectories: int
    demonstrated_distances: list[float]
    runs: list[BasketRun]
    clean: Dataset
    learned: dict


def baskets(demonstrated: Sequence[float], unseen: Sequence[float] = UNSEEN,
            bearings: Sequence[float] = BEARINGS) -> list[tuple[float, float]]:
    """(distance (m), bearing (deg)) of every basket: each of the ``demonstrated`` distances (those
    the people aim at) and the ``unseen`` ones once, in order of distance, the bearings taken in
    turn (each of them appears once there are at least as many distances as bearings)."""
    distances = sorted({*map(float, demonstrated), *(float(d) for d in unseen)})
    return [(d, float(bearings[i % len(bearings)])) for i, d in enumerate(distances)]


def basket_log(distance: float, bearing: float) -> str:
    """The attempts log of the basket at ``distance`` (m) and ``bearing`` (deg), relative to the
    output folder: ``attempts/whole-arm/3.75m-60deg.jsonl``."""
    return f"attempts/whole-arm/{distance:g}m-{bearing:g}deg.jsonl"


def run_whole_arm(
    out_dir: Path | RunPaths,
    targets: Sequence[tuple[float, float]],
    *,
    seed: int = 0,
    robot=None,
    budget: int = BUDGET,
    note: Callable[[str], None] | None = None,
    gap: Gap | None = None,
) -> WholeArm:
    """Simulate the whole-arm people, clean their throws and learn each of the ``targets``.

    Writes ``whole-arm-demos.csv``, ``whole-arm-clean.csv`` and the attempts logs
    ``attempts/whole-arm/<distance>m-<bearing>deg.jsonl`` into ``out_dir``. The baskets are
    learned in the order given, each starting from the speed offset of the hits before it
    with the same joints (``learn(..., carry_from=...)``, :mod:`rlff.learn.carry`).

    Parameters
    ----------
    out_dir : Path or RunPaths
        The folder; a :class:`rlff.report.folder.RunFolder` lists every file before it is written.
    targets : sequence of (distance, bearing)
        The baskets to learn (m, deg), in order of distance: :func:`baskets` for every
        demonstrated and unseen one (the demo's full plan), or a few.
    seed : int
        Seed of the people and of the learning runs.
    robot : Robot, optional
        Default: the built-in Comau Smart5 SiX.
    budget : int
        Most attempts per basket.
    note : callable, optional
        Told what is being done (each basket's attempts).
    gap : Gap, optional
        How the simulated arm differs from ``robot`` (:class:`rlff.sim.gap.Gap`): the
        loop plans with ``robot``, the throws are simulated with the gap applied.

    Raises
    ------
    InputError
        Fewer than 2 demonstrations survive the cleaning.
    """
    from rlff.learn import learn
    from rlff.learn.loop import learnable_basket
    from rlff.learn.scenarios import with_landings
    from rlff.preprocess import Pipeline
    from rlff.robot import load_robot, mapping_for
    from rlff.sim import Basket
    from rlff.synthetic.throws import whole_arm_demonstrations

    out = out_dir if isinstance(out_dir, RunPaths) else RunPaths(out_dir)
    robot = load_robot() if robot is None else robot
    tell = note or (lambda text: None)
    tell("whole arm: simulating the people")
    raw = whole_arm_demonstrations(seed=seed, joints=("shoulder", "elbow", "wrist"))
    write_csv(raw, out.file("whole-arm-demos.csv"))
    clean, _ = Pipeline.preset("thesis").run(raw)
    if len(clean) < 2:
        raise InputError(f"the preprocessing left {len(clean)} whole-arm throws: too few to learn from (seed {seed})")
    write_csv(clean, out.file("whole-arm-clean.csv"))
    demonstrated = sorted({float(t["distance"][0]) for t in clean})
    aimed = with_landings(clean, "none", seed)
    choices = [ARM_JOINTS, (*ARM_JOINTS, WRIST_JOINT)] if "wrist" in clean.columns else [ARM_JOINTS]

    runs, learned = [], {}
    last_hit: dict[tuple[str, ...], Path] = {}  # per joint set: the log of the last basket hit
    for distance, bearing in targets:
        log = out.log(basket_log(distance, bearing))
        log.unlink(missing_ok=True)
        for joints in choices:  # joint 5 only where joints 2 and 3 do not reach with headroom
            if joints != choices[-1] and distance > learnable_basket(
                    aimed, mapping_for(robot, joints), Basket(distance), seed=seed, headroom=SPEED_HEADROOM):
                continue
            outcomes = []
            executor = _recording_simulator(robot, Basket(distance, bearing=bearing), outcomes, gap)
            try:
                result = learn(
                    aimed, distance, budget=budget, feedback="binary", seed=seed, robot=robot.name, log_path=log,
                    joints=joints, bearing=bearing, executor=executor, executed_on="sim", carry_from=[last_hit[joints]] if joints in last_hit else [],
                    progress=lambda attempt, d=distance, b=bearing: tell(
                        f"whole arm at {d:g} m, {b:g} deg: attempt {attempt.index} ({'hit' if attempt.hit else 'miss'})"),
                )
                refused = ""
                break
            except InputError as exc:  # out of the loop's reach (nothing thrown, no log line written)
                refused = str(exc)
                log.unlink(missing_ok=True)
        if refused:  # the table says so, the other baskets go on
            runs.append(BasketRun(distance, bearing, distance in demonstrated, tuple(joints), False, 0, [], None,
                                  refused))
            continue
        last = outcomes[-1]
        runs.append(BasketRun(
            distance, bearing, distance in demonstrated, tuple(joints), result.hit, result.attempts,
            list(result.misses),
            {"position": [float(v) for v in last.release.position], "velocity": [float(v) for v in last.release.velocity],
             "rim_height": last.basket.rim_height, "hit": bool(last.hit)},
        ))
        learned[(distance, bearing)] = result
        if result.hit:  # the next basket with these joints starts from the speed offset this hit found
            last_hit[joints] = log
    hits = sum(1 for t in raw if t.meta.get("hit") is True)
    return WholeArm(len(raw), hits, len(clean), demonstrated, runs, clean, learned)


def _recording_simulator(robot, basket, outcomes: list, gap: Gap | None = None):
    """The learning loop's MuJoCo executor for ``basket``, keeping every outcome in ``outcomes``
    (the last one's release draws the flight in the 3-D figure); ``gap`` applied to every
    trajectory."""
    from rlff.sim import simulate_throw

    def execute(trajectory):
        outcome = simulate_throw(trajectory if gap is None else gap.executed(trajectory), basket, robot=robot,
                                 check_motion=False)  # planned, and checked, by the loop's plan_path
        outcomes.append(outcome)
        return outcome

    return execute


def summary_rows(runs: Sequence[BasketRun]) -> list[list]:
    """The report's table: one row per basket."""
    return [[r.distance, r.bearing, r.demonstrated, ", ".join(r.joints), r.hit, r.attempts,
             r.misses[0] if r.misses else None, r.misses[-1] if r.misses else None, r.refused or None] for r in runs]


#: Columns of :func:`summary_rows`.
SUMMARY_COLUMNS = ["distance (m)", "bearing (deg)", "demonstrated", "joints", "hit", "attempts",
                   "first miss (m)", "last miss (m)", "not thrown because"]


def whole_arm_section(whole: WholeArm):
    """The report section of the whole-arm part (a :class:`rlff.report.Section`)."""
    from rlff.report import Section, Table

    runs = whole.runs
    hits = [r for r in runs if r.hit]
    attempts = [r.attempts for r in hits]
    bearings = sorted({r.bearing for r in runs})
    return Section(
        "whole-arm", "Whole-arm throws around the robot",
        "Simulated people throw with the shoulder and the elbow together (the shoulder leads, the elbow "
        "extends after it) at baskets 1 to 4 m away on bearings 0 to 90°, recorded and cleaned like the "
        "one-joint people above, and mostly miss. For every basket, demonstrated or not, the learning loop "
        f"(its default method, calibrate, with binary feedback: hit or miss only) throws with the robot's "
        f"joint 2 following the shoulder and joint 3 the elbow (and joint 5 the wrist where a basket lies "
        f"beyond what those two reach), joint 1 turned to the basket's bearing, at most {BUDGET} times. It "
        "learns from the basket each person aimed at, not from where their ball came down. Each distance "
        "is thrown at one bearing, the bearings in turn.",
        facts={
            "throws recorded": whole.demonstrations, "of them hits": whole.demonstration_hits,
            "kept after cleaning": whole.clean_trajectories,
            "demonstrated distances (m)": ", ".join(f"{d:g}" for d in whole.demonstrated_distances),
            "basket bearings thrown at (deg)": ", ".join(f"{b:g}" for b in bearings),
            "baskets hit": f"{len(hits)} of {len(runs)}",
            "attempts to a hit (mean, most)": (f"{np.mean(attempts):.1f}, {max(attempts)}" if attempts else "none hit"),
        },
        tables=[Table("Attempts per basket", SUMMARY_COLUMNS, summary_rows(runs))],
    )


def whole_arm_figures(out: RunPaths, whole: WholeArm, robot) -> list[tuple[Path, str, str, str]]:
    """The whole-arm figures, into ``out``'s ``figures/``: every basket's last flight in 3-D, and
    each joint of the farthest basket hit (a demonstrated one where any was hit) at its last
    throw, human and robot; (png, section, title, caption) in report order."""
    from rlff.learn.replay import plan_attempt
    from rlff.plots.flights import flights_3d
    from rlff.plots.throw import joint_trajectories
    from rlff.robot import mapping_for

    entries = []
    thrown = [run for run in whole.runs if run.flight is not None]
    if not thrown:
        return entries
    flights = [{**run.flight, "distance": run.distance, "bearing": run.bearing} for run in thrown]
    saved = flights_3d(flights, out.figure("whole-arm-flights"),
                       title="The last throw at every basket, around the robot")
    entries.append((saved.png, "whole-arm", "Every basket's last throw in 3-D",
                    "The robot's base at the origin, each basket at its distance and bearing (the rim's height drawn), "
                    "and the ball's flight of the last attempt at each, from the release (dot) down through the rim "
                    "(solid) to the floor (dotted); green: hit, red: the budget ran out."))
    demonstrated = {float(t["distance"][0]) for t in whole.clean}
    # the farthest basket hit where people threw too, so their throws can be drawn behind it
    shown = max(thrown, key=lambda r: (r.hit, r.distance in demonstrated, r.distance))
    attempt = whole.learned[(shown.distance, shown.bearing)].history[-1]
    mapping = mapping_for(robot, shown.joints)
    planned = plan_attempt(attempt, mapping, bearing=shown.bearing).trajectory
    demos = [{c: t[c] for c in t.columns} for t in whole.clean
             if float(t["distance"][0]) == shown.distance and "time" in t.columns]
    human = executed_throw(planned, mapping)
    for demo in demos:  # a demonstration's last sample is its release
        demo["time"] = demo["time"] - demo["time"][-1]
    saved = joint_trajectories(
        human, planned, list(zip(mapping.driven_joints, mapping.human_columns, strict=True)),
        out.figure("whole-arm-joints"), demos=demos,
        limits={j.name: (j.lower, j.upper) for j in robot.joints},
        speeds={j.name: j.max_velocity for j in robot.joints},
        turned=(mapping.bearing_joint,) if mapping.bearing_joint else (),
        title=f"Each joint of the last throw at {shown.distance:g} m, {shown.bearing:g}° "
              f"({'hit' if shown.hit else 'miss'})")
    entries.append((saved.png, "whole-arm", "Each joint, human and robot",
                    "Left: the throw the robot executed, from rest to the release, mapped back to the people's "
                    "units, over the time to its release; the demonstrations at that distance in grey. The robot "
                    "keeps the model's first pose and release and plans the swing between within its own limits, "
                    "so its wind-up may go where no elbow goes (below 0 rad). Right: "
                    "the robot joints they drive over the planned trajectory, from the start pose with joint 1 "
                    "already turned to the bearing, the throw to its release "
                    "(dashed) and the braking; dotted: each joint's position limits beside its positions and its "
                    "speed limits beside its velocities."))
    return entries


def executed_throw(planned, mapping) -> dict[str, np.ndarray]:
    """The part of a planned whole-arm throw that makes the throw, in the people's units: from the
    arm's last rest before the release (a wind-up included) to the release.

    Not the attempt's path: that is what the planner was given, the model's shape at its own
    samples with every speed clipped into the limits (a saturated joint's velocity is flat while
    its angle rises at many times that), of which the planner keeps the first pose and the
    release; the motion between is ruckig's.

    Parameters
    ----------
    planned : rlff.trajectory.JointTrajectory
        A planned throw (``release_time`` set).
    mapping : rlff.robot.mapping.ArmMapping

    Returns
    -------
    dict of str to array of shape (T,)
        The driven human columns (rad, rad/s) and ``time`` (s in human time, 0 at the release).
    """
    release = int(np.searchsorted(planned.time, planned.release_time))
    resting = np.flatnonzero(np.all(planned.velocities[:release + 1] == 0, axis=1))
    start = int(resting[-1]) if resting.size else 0
    path = {name: values[start:release + 1] for name, values in mapping.path_from_robot(planned).items()}
    path["time"] = path["time"] - path["time"][-1]
    return path
