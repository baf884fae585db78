"""Whole-arm learning on an arm that is not its robot file: attempts per basket, with and without a gap.

Run: ``.venv/bin/python benchmarks/whole_arm_gap.py [--seeds 1,4,5,6] [--gaps none,speed:0.95,delay:0.02]``.

``rlff demo``'s whole-arm part (:func:`rlff.whole_arm_demo.run_whole_arm`: the simulated people,
the thesis preset, ``calibrate`` with binary feedback, at most 10 attempts, every demonstrated
distance and the unseen ones) with the throws simulated on an arm that differs from the robot
file the loop plans and aims with (:class:`rlff.learn.scenarios.Gap`). Prints, per seed and gap,
the attempts to the hit per basket (``-`` for no hit in the budget), and per gap the baskets hit
and the mean attempts (a basket without a hit counts as 11). The people of seeds 0, 2 and 3
tuned the robot file's whole-arm defaults; the default seeds are the others.
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

from rlff.sim.gap import parse_gap
from rlff.synthetic.throws import THESIS_DISTANCES
from rlff.whole_arm_demo import BUDGET, baskets, run_whole_arm


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", default="1,4,5,6", help="comma-separated seeds of the people")
    parser.add_argument("--gaps", default="none,speed:0.95,delay:0.02", help="comma-separated gaps")
    args = parser.parse_args()
    seeds = [int(s) for s in args.seeds.split(",")]
    gaps = [parse_gap(g) for g in args.gaps.split(",")]
    totals = {}
    print("| seed | gap | attempts per basket (m: attempts) |\n|---|---|---|")
    with tempfile.TemporaryDirectory() as folder:
        for seed in seeds:
            for gap in gaps:
                runs = run_whole_arm(Path(folder), baskets(THESIS_DISTANCES), seed=seed, gap=gap).runs
                cells = " ".join(f"{r.distance:g}:{r.attempts if r.hit else '-'}" for r in runs)
                print(f"| {seed} | {gap.name} | {cells} |", flush=True)
                hits, attempts = totals.get(gap.name, (0, []))
                totals[gap.name] = (hits + sum(r.hit for r in runs),
                                    attempts + [r.attempts if r.hit else BUDGET + 1 for r in runs])
    print("\n| gap | baskets hit | mean attempts |\n|---|---|---|")
    for name, (hits, attempts) in totals.items():
        print(f"| {name} | {hits} of {len(attempts)} | {sum(attempts) / len(attempts):.2f} |")


if __name__ == "__main__":
    main()
