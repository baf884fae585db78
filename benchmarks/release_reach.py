"""How far a one-joint learning run's throws reach, let go where the demonstrations let go.

Run: ``.venv/bin/python benchmarks/release_reach.py [--seeds 8] [--first-seed 100] [--robot comau_smart5_six]``.

A one-joint learning run lets go at the end of one angle grid (:func:`rlff.learn.demos.angle_grid`):
by default the first quartile of the demonstrations' last angles, where most of them still cover
the path; for a basket beyond that release's reach, later, at the median, the third quartile or
the last of them (:func:`rlff.learn.loop.release_quantile`, since 2026-12-08; issue 15 asked the
donut to explore the release angle where the demonstrations disagree). This measures what each
release reaches: per scenario of ``rlff bench learning`` and held-out seed, the farthest basket
(centre, m, a 0.35 m opening) the run's throws reach at the joint's speed limit (and what its
acceleration and jerk limits allow over the swing, :func:`rlff.sim.reach.executable_reach`) let
go at each of those releases, and at the joint's best release position. Prints a Markdown table
of the means over the seeds (min-max in brackets) and the scenarios' baskets.
"""

from __future__ import annotations

import argparse

import numpy as np

from rlff.learn.benchmark import HELD_OUT_SEEDS
from rlff.learn.demos import RELEASE_QUANTILES, usable_demos
from rlff.learn.loop import release_reaches
from rlff.learn.scenarios import DEMONSTRATORS, Scenario, demonstrations
from rlff.robot import RobotMapping, load_robot
from rlff.sim import Basket
from rlff.sim.reach import executable_reach, farthest_basket


def reaches(scenario: Scenario, seed: int, mapping: RobotMapping, basket: Basket) -> list[float]:
    """Farthest basket centre (m) of ``basket``'s shape at each of the releases of
    :data:`~rlff.learn.demos.RELEASE_QUANTILES`, then at the joint's best release, for the
    demonstrations of ``seed``."""
    demos, _ = usable_demos(demonstrations(seed, scenario), mapping, basket.rim_height)
    farthest = release_reaches(demos, mapping, basket, 0.0)
    best = executable_reach(mapping, basket.rim_height, 0.0).distance
    return [*(farthest[q] for q in RELEASE_QUANTILES), farthest_basket(best, basket.opening)]


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
    columns = [f"let go at the {q:g} quantile" for q in RELEASE_QUANTILES] + ["best release"]
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
