"""Learning benchmark: attempts to the first hit per method, and the loop's own work per attempt.

    .venv/bin/python benchmarks/learning.py [--seeds N] [--quick] [--jobs N] [--backend NAME]
                                            [--scenario short|wide|both]

Part 1 runs the grid of ``rlff bench learning`` (seeds x baskets x feedback kinds x methods,
real MuJoCo throws) and prints a table per scenario: ``short`` (all-short demonstrations at
1-1.5 m, the grid of ``rlff bench learning``) and ``wide`` (the demo's setting: demonstrations
at 1-4 m, most beyond the robot's reach). Part 2 times what the loop itself does per
attempt (refit the mixture to the demonstrations plus the attempts so far, generate the DMM
throw, update the calibration) on data of the thesis' size, beside one simulated throw, and
prints the ratio to the 50 ms target.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from rlff.learn.benchmark import SCENARIOS, format_table, learning_benchmark

TARGET_MS = 50.0


def loop_work_per_attempt(repeats: int = 10) -> tuple[float, float]:
    """Median wall time (ms) of one update + proposal, and of one simulated throw."""
    from rlff.learn.attempt import Attempt
    from rlff.learn.benchmark import demonstrations
    from rlff.learn.loop import _angle_grid, _components, _learning_demos
    from rlff.learn.method import Problem
    from rlff.learn.strategies import CalibrateUpdate
    from rlff.robot import RobotMapping, load_robot
    from rlff.sim import Basket, simulate_throw
    from rlff.trajectory.timing import time_along_path

    demos = _learning_demos(demonstrations(0))
    problem = Problem(demos=demos, target=1.9, feedback="distance", tolerance=0.14,
                      angles=_angle_grid(demos), components=_components(demos, 0), seed=0)
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
        outcome = simulate_throw(trajectory, Basket(1.9), robot=robot)
        throw_ms.append(1000 * (time.perf_counter() - start))
        angle, executed = mapping.from_robot(trajectory)
        history.append(Attempt(index, 1.9, 1.9, angle, executed, trajectory.time, False,
                               float(outcome.landing_x), float(outcome.miss)))
    print(f"data: {len(demos)} demonstrations, {demos.n_samples} samples, "
          f"{problem.components} components")
    return float(np.median(propose_ms)), float(np.median(throw_ms))


def mean_table(runs, budget: int) -> str:
    """Mean attempts to the first hit over every run of a method (no hit = budget + 1), and hits."""
    lines = ["| feedback | method | mean attempts | runs that hit |", "|---|---|---|---|"]
    keys = dict.fromkeys((r.feedback, r.method) for r in runs)
    for feedback, method in keys:
        group = [r for r in runs if (r.feedback, r.method) == (feedback, method)]
        counts = [r.attempts if r.hit else budget + 1 for r in group]
        lines.append(f"| {feedback} | {method} | {np.mean(counts):.1f} | "
                     f"{sum(r.hit for r in group)}/{len(group)} |")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--budget", type=int, default=20)
    parser.add_argument("--quick", action="store_true", help="2 seeds, budget 12")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--backend", default=None, help="joblib backend (loky, ray, dask)")
    parser.add_argument("--scenario", choices=[*SCENARIOS, "both"], default="both")
    args = parser.parse_args()
    seeds, budget = (min(args.seeds, 2), min(args.budget, 12)) if args.quick else (args.seeds, args.budget)

    for scenario in SCENARIOS if args.scenario == "both" else [args.scenario]:
        start = time.perf_counter()
        runs = learning_benchmark(seeds, scenario=scenario, budget=budget, jobs=args.jobs,
                                  backend=args.backend)
        print(f"## Attempts to the first hit, scenario {scenario} ({seeds} seeds, budget {budget}, "
              f"{time.perf_counter() - start:.0f} s)\n")
        print(format_table(runs, budget) + "\n")
        print(mean_table(runs, budget) + "\n")

    print("\n## The loop's own work per attempt (median)\n")
    work, throw = loop_work_per_attempt()
    print(f"refit + generate + update: {work:.1f} ms ({work / TARGET_MS:.2f} x the {TARGET_MS:g} ms target)")
    print(f"one simulated throw:       {throw:.1f} ms ({work / throw:.2f} x loop work / throw)")


if __name__ == "__main__":
    main()
