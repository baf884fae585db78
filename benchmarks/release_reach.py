"""How far the loop's throws could reach if they let go where other demonstrations let go.

Run: ``.venv/bin/python benchmarks/release_reach.py [--seeds 8] [--first-seed 100] [--robot comau_smart5_six]``.

Every throw of a one-joint learning run lets go at the end of one angle grid
(:func:`rlff.learn.demos.angle_grid`): the first quartile of the demonstrations' last angles, where
most of them still cover the path. Issue 15 asked the donut to explore the release angle where
the demonstrations disagree. This measures what that could win: per scenario of ``rlff bench
learning`` and held-out seed, the farthest basket (centre, m, a 0.35 m opening) the run's
throws reach at the joint's speed limit (and what its acceleration and jerk limits allow over the
swing, :func:`rlff.sim.reach.executable_reach`) when let go at the quartiles of the
demonstrations' last angles, and at the joint's best release position. Prints a Markdown table of
the means over the seeds (min-max in brackets) and the scenarios' baskets.
"""

from __future__ import annotations

import argparse

import numpy as np

from rlff.learn.benchmark import HELD_OUT_SEEDS
from rlff.learn.demos import RELEASE_QUANTILE, usable_demos
from rlff.learn.scenarios import DEMONSTRATORS, Scenario, demonstrations
from rlff.robot import RobotMapping, load_robot
from rlff.sim import Basket
from rlff.sim.reach import executable_reach, farthest_basket

#: Where along the demonstrations' last angles the throws let go: the loop's grid (0.25) and later.
QUANTILES = (RELEASE_QUANTILE, 0.5, 0.75, 1.0)


def reaches(scenario: Scenario, seed: int, mapping: RobotMapping, basket: Basket) -> list[float]:
    """Farthest basket centre (m) of ``basket``'s shape at each of :data:`QUANTILES`'s releases,
    then at the joint's best release, for the demonstrations of ``seed``."""
    demos, _ = usable_demos(demonstrations(seed, scenario), mapping, basket.rim_height)
    first = float(np.median([t["angle"][0] for t in demos]))
    lasts = np.quantile([t["angle"][-1] for t in demos], QUANTILES)
    start = mapping.angle_offset + mapping.angle_scale * first
    joint = mapping.robot.joint(mapping.joint)
    farthest = []
    for last in lasts:
        release = float(np.clip(mapping.angle_offset + mapping.angle_scale * last, joint.lower, joint.upper))
        reach = executable_reach(mapping, basket.rim_height, 0.0, release, swing_from=start).distance
        farthest.append(farthest_basket(reach, basket.opening))
    best = executable_reach(mapping, basket.rim_height, 0.0).distance
    return [*farthest, farthest_basket(best, basket.opening)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=8, help="how many seeds")
    parser.add_argument("--first-seed", type=int, default=HELD_OUT_SEEDS, help="the first seed")
    parser.add_argument("--robot", default="comau_smart5_six", help="robot file (a name or a path)")
    args = parser.parse_args()
    robot = load_robot(args.robot)
    mapping = RobotMapping.for_robot(robot)
    basket = Basket(1.0, opening=0.35)
    seeds = range(args.first_seed, args.first_seed + args.seeds)
    columns = [f"let go at the {q:g} quantile" for q in QUANTILES] + ["best release"]
    print(f"farthest basket centre (m), mean (min-max) over seeds {seeds[0]}-{seeds[-1]}, {robot.name}\n")
    print("| scenario | baskets | " + " | ".join(columns) + " |")
    print("|---" * (len(columns) + 2) + "|")
    for name in DEMONSTRATORS:
        scenario = Scenario(name, landings="none")
        table = np.array([reaches(scenario, seed, mapping, basket) for seed in seeds])  # (seeds, columns)
        cells = [f"{m:.2f} ({lo:.2f}-{hi:.2f})" for m, lo, hi in zip(table.mean(0), table.min(0), table.max(0),
                                                                       strict=True)]
        baskets = ", ".join(f"{b:g}" for b in scenario.baskets)
        print(f"| {name} | {baskets} | " + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    main()
