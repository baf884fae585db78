"""Learning benchmark: attempts to the first hit per method, and the loop's own work per attempt.

    .venv/bin/python benchmarks/learning.py [--seeds N] [--first-seed S] [--quick] [--jobs N]
        [--scheduler ADDRESS] [--scenario short,wide,...|all] [--landings none,exact,noisy:0.3]
        [--gap none,speed:0.95,delay:0.02]

Part 1 runs the grid of ``rlff bench learning`` (seeds x baskets x feedback kinds x methods,
real MuJoCo throws) for every scenario, knowledge of the landings and gap between the simulated
arm and its robot file asked for, on held-out
seeds (100 and up by default), and prints one table each with the paired Wilcoxon p-values of
the project's methods against every baseline and ablation. Part 2 times what the loop itself
does per attempt (refit the mixture to the demonstrations plus the attempts so far, generate
the DMM throw, update the calibration) on data of the thesis' size, beside one simulated throw,
and prints the ratio to the 50 ms target.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from rlff.learn.benchmark import HELD_OUT_SEEDS, format_table, learning_benchmark, robot_identity
from rlff.learn.scenarios import DEMONSTRATORS, Scenario

TARGET_MS = 50.0


def loop_work_per_attempt(repeats: int = 10) -> tuple[float, float]:
    """Median wall time (ms) of one update + proposal + out-of-reach check, and of one simulated throw."""
    from rlff.learn.attempt import Attempt
    from rlff.learn.benchmark import demonstrations
    from rlff.learn.demos import angle_grid, learning_demos, loop_components
    from rlff.learn.method import Problem
    from rlff.learn.reach import beyond_reach, widest_hit
    from rlff.learn.strategies import CalibrateUpdate
    from rlff.robot import RobotMapping, load_robot
    from rlff.sim import Basket, simulate_throw
    from rlff.timing import time_along_path

    demos = learning_demos(demonstrations(0))
    problem = Problem(demos=demos, target=1.9, feedback="distance", tolerance=0.14,
                      angles=angle_grid(demos), components=loop_components(demos, 0), seed=0)
    robot = load_robot()
    mapping = RobotMapping.for_robot(robot)
    method = CalibrateUpdate(problem)
    history: list[Attempt] = []
    propose_ms, throw_ms = [], []
    for index in range(1, repeats + 1):
        start = time.perf_counter()
        proposal = method.propose(history)
        propose_ms.append(1000 * (time.perf_counter() - start))
        velocity = np.maximum(proposal.velocity, 0.0)
        trajectory, _ = mapping.to_robot(proposal.angle, velocity,
                                         time_along_path(proposal.angle, velocity), clip=True)
        start = time.perf_counter()
        outcome = simulate_throw(trajectory, Basket(1.9), robot=robot, check_motion=False)  # mapped, unplanned
        throw_ms.append(1000 * (time.perf_counter() - start))
        angle, executed = mapping.from_robot(trajectory)
        history.append(Attempt(index, 1.9, 1.9, angle, executed, trajectory.time, False,
                               float(outcome.landing_x), float(outcome.miss)))
        start = time.perf_counter()  # the loop's judgement of the attempts before the next throw
        beyond_reach(history, mapping, Basket(1.9), widest_hit(Basket(1.9)), 0.0)
        propose_ms[-1] += 1000 * (time.perf_counter() - start)
    print(f"data: {len(demos)} demonstrations, {demos.n_samples} samples, "
          f"{problem.components} components")
    return float(np.median(propose_ms)), float(np.median(throw_ms))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=8)
    parser.add_argument("--first-seed", type=int, default=HELD_OUT_SEEDS)
    parser.add_argument("--budget", type=int, default=20)
    parser.add_argument("--quick", action="store_true", help="2 seeds, budget 12")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--scheduler", default=None, help="Dask scheduler address")
    parser.add_argument("--scenario", default="short,wide", help="comma-separated demonstrators, or all")
    parser.add_argument("--landings", default="none,exact,noisy:0.3", help="comma-separated")
    parser.add_argument("--gap", default="none", help="comma-separated: none, speed:G, delay:S")
    args = parser.parse_args()
    seeds, budget = (min(args.seeds, 2), min(args.budget, 12)) if args.quick else (args.seeds, args.budget)
    people = list(DEMONSTRATORS) if args.scenario == "all" else args.scenario.split(",")

    for name in people:
        for landings in args.landings.split(","):
            for gap in args.gap.split(","):
                start = time.perf_counter()
                scenario = Scenario(name, landings=landings, gap=gap)
                runs = learning_benchmark(scenario, seeds, first_seed=args.first_seed, budget=budget,
                                          jobs=args.jobs, scheduler=args.scheduler)
                print(f"## {scenario.name}, landings {landings} (seeds {args.first_seed}-"
                      f"{args.first_seed + seeds - 1}, budget {budget}, {time.perf_counter() - start:.0f} s)\n")
                print(format_table(runs, budget, robot_identity(scenario.robot)) + "\n")

    print("\n## The loop's own work per attempt (median)\n")
    work, throw = loop_work_per_attempt()
    print(f"refit + generate + update + out-of-reach check: {work:.1f} ms ({work / TARGET_MS:.2f} x the {TARGET_MS:g} ms target)")
    print(f"one simulated throw:                            {throw:.1f} ms ({work / throw:.2f} x loop work / throw)")


if __name__ == "__main__":
    main()
