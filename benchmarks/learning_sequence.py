"""Baskets in sequence: does carrying one basket's hit to the next save attempts?

    .venv/bin/python benchmarks/learning_sequence.py [--seeds 8] [--first-seed 100]
        [--scenario short] [--landings none] [--gap none] [--methods calibrate,sweep] [--jobs 2]

For every seed the scenario's two baskets are learned one after the other, in both orders (near
then far, far then near), with binary feedback: the first from scratch, the second once from
scratch and once carrying the first's hit (``learn(..., carry_from=[first log])``,
:mod:`rlff.learn.carry`). Every method gets the same carried log of its own first run. Prints,
per method, the mean attempts of the second basket alone and carried (a run without a hit counts
as 21), the paired p of the two (Wilcoxon signed-rank), and the paired p of each method's carried
runs against the first method's. Seeds from 100 up were not used to choose
:data:`rlff.learn.carry.CARRY_SCALE` (measured on seeds 0-47).
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

import joblib
import numpy as np

from rlff.learn.loop import learn
from rlff.learn.scenarios import Feedback, Scenario, demonstrations, reporting_executor
from rlff.learn.statistics import paired_p_value

BUDGET = 20


def attempts(result) -> int:
    """Attempts to the hit (budget + 1 without one)."""
    return result.attempts if result.hit else BUDGET + 1


def pair(scenario: Scenario, seed: int, method: str, first: float, second: float) -> tuple[int, int, int]:
    """Attempts at ``first``, at ``second`` alone and at ``second`` carrying ``first``'s hit."""
    demos = demonstrations(seed, scenario)
    feedback = Feedback("binary", "binary")

    def run(basket: float, **options):
        return learn(demos, basket, budget=BUDGET, feedback="binary", update=method, seed=seed,
                     robot=scenario.robot, opening=scenario.opening,
                     executor=reporting_executor(scenario, feedback, basket, seed), executed_on="sim", **options)

    with tempfile.TemporaryDirectory() as folder:
        log = Path(folder) / "first.jsonl"
        before = run(first, log_path=log)
        alone = run(second)
        carried = run(second, carry_from=[log])
    return attempts(before), attempts(alone), attempts(carried)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=8)
    parser.add_argument("--first-seed", type=int, default=100)
    parser.add_argument("--scenario", default="short")
    parser.add_argument("--landings", default="none")
    parser.add_argument("--gap", default="none")
    parser.add_argument("--methods", default="calibrate,sweep")
    parser.add_argument("--jobs", type=int, default=2)
    args = parser.parse_args()
    scenario = Scenario(args.scenario, landings=args.landings, gap=args.gap)
    near, far = sorted(scenario.baskets)[0], sorted(scenario.baskets)[-1]
    methods = args.methods.split(",")
    seeds = range(args.first_seed, args.first_seed + args.seeds)
    cases = [(m, s, a, b) for m in methods for s in seeds for a, b in ((near, far), (far, near))]
    out = joblib.Parallel(n_jobs=args.jobs)(joblib.delayed(pair)(scenario, s, m, a, b) for m, s, a, b in cases)
    table = {m: np.array([o for (mm, *_), o in zip(cases, out, strict=True) if mm == m]) for m in methods}
    print(f"{scenario.name}, landings {scenario.landings}, binary feedback, seeds {seeds.start}-{seeds.stop - 1}, "
          f"baskets {near:g} and {far:g} m in both orders ({2 * len(seeds)} pairs; no hit: {BUDGET + 1})\n")
    print(f"| method | first basket | second alone | second carried | p carried vs alone | p carried vs {methods[0]} |")
    print("|---|---|---|---|---|---|")
    reference = table[methods[0]][:, 2]
    for method, rows in table.items():
        vs = "" if method == methods[0] else f"{paired_p_value(reference, rows[:, 2]):.3g}"
        print(f"| {method} | {rows[:, 0].mean():.2f} | {rows[:, 1].mean():.2f} | {rows[:, 2].mean():.2f} | "
              f"{paired_p_value(rows[:, 2], rows[:, 1]):.3g} | {vs} |")
    for method, rows in table.items():
        for label, index in (("near then far", slice(0, None, 2)), ("far then near", slice(1, None, 2))):
            part = rows[index]
            print(f"  {method}, {label}: second alone {part[:, 1].mean():.2f}, carried {part[:, 2].mean():.2f}")


if __name__ == "__main__":
    main()
