"""Does the simulated verdict depend on the step? Throws scaled in speed across the basket.

Run: ``.venv/bin/python benchmarks/sim_verdict.py [--throws 200] [--figure docs/figures/sim-verdict.png]``.

One joint-2 swing (half a cosine from rest to its peak speed, released at its end, the shape of
``tests/test_sim_throw.py``'s ``swing``) is thrown at ``--throws`` peak speeds whose landings
span the basket at 1.75 m from 0.35 m short to 0.35 m long. Each throw is simulated three ways,
side by side in one run:

- ``2 ms, speculative`` — the default (MuJoCo's speculative contacts, a 2 ms step);
- ``2 ms, plain`` — the same step without speculative contacts (the verdict before them);
- ``0.25 ms reference`` — the same scene at an eighth of the step.

It prints, per way, the hits among the balls coming down more than 3 cm inside the window
(``|miss| < opening/2 - radius - 0.03``), the misses among those more than 3 cm outside the rim
(``|miss| > opening/2 + wall + 0.03``), the agreement with the reference and the wall time per
throw; ``--figure`` draws every verdict against the landing.
"""

from __future__ import annotations

import argparse
import statistics
import time

import mujoco
import numpy as np

from rlff.robot import load_robot
from rlff.sim import Basket, simulate_throw
from rlff.sim.arm import BALL_RADIUS, Arm
from rlff.sim.basket import WALL
from rlff.sim.scene import build_scene
from rlff.trajectory.joint import JointTrajectory

BASKET = Basket(1.75)
#: Landing (m) per rad/s of peak speed of this swing, and the landing at 2 rad/s (measured).
SPEED_SLOPE, LANDING_AT_2 = 0.82, 1.651
MARGIN = 0.03
SPECULATIVE = int(mujoco.mjtEnableBit.mjENBL_SPECULATIVE)


def swing(peak: float, start: float = -1.2, release: float = -0.06, points: int = 120) -> JointTrajectory:
    """Joint 2 from rest to ``peak`` rad/s (half a cosine) between ``start`` and ``release`` (rad)."""
    duration = 2.0 * (release - start) / peak
    t = np.linspace(0.0, duration, points)
    phase = np.pi * t / duration
    positions, velocities = np.zeros((points, 6)), np.zeros((points, 6))
    positions[:, 1] = start + peak * (t / 2.0 - duration / (2.0 * np.pi) * np.sin(phase))
    velocities[:, 1] = peak * (1.0 - np.cos(phase)) / 2.0
    positions[:, 2], positions[:, 4] = -1.373, -0.198
    return JointTrajectory(tuple(f"joint_{i}" for i in range(1, 7)), t, positions, velocities)


def throws(count: int) -> np.ndarray:
    """Peak speeds (rad/s) whose landings span the basket from 0.35 m short to 0.35 m long."""
    landings = BASKET.distance + np.linspace(-0.35, 0.35, count)
    return 2.0 + (landings - LANDING_AT_2) / SPEED_SLOPE


def verdicts(peaks: np.ndarray, timestep: float, speculative: bool) -> tuple[list, float]:
    """(hit, miss) of every throw and the median wall time (ms) per throw."""
    robot = load_robot()
    model = build_scene(Arm.from_robot(robot), BASKET, 0.0, timestep).model
    flags = model.opt.enableflags
    model.opt.enableflags = flags | SPECULATIVE if speculative else flags & ~SPECULATIVE
    outcomes, seconds = [], []
    try:
        for peak in peaks:
            start = time.perf_counter()
            outcome = simulate_throw(swing(float(peak)), BASKET, robot=robot, timestep=timestep, check_reach=False,
                                     check_motion=False)  # a swing cut at its release
            seconds.append(time.perf_counter() - start)
            outcomes.append((outcome.hit, outcome.miss))
    finally:
        model.opt.enableflags = flags
    return outcomes, 1000 * statistics.median(seconds)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--throws", type=int, default=200, help="Throws across the basket.")
    parser.add_argument("--figure", help="Write the verdicts against the landing to this PNG.")
    args = parser.parse_args()
    peaks = throws(args.throws)
    ways = {"2 ms, speculative (default)": (0.002, True), "2 ms, plain (before)": (0.002, False),
            "0.25 ms reference": (0.00025, True)}
    results = {name: verdicts(peaks, *setting) for name, setting in ways.items()}
    reference = results["0.25 ms reference"][0]
    inner = 0.5 * BASKET.opening - BALL_RADIUS - MARGIN
    outer = 0.5 * BASKET.opening + WALL + MARGIN
    print(f"{args.throws} throws across the basket at {BASKET.distance:g} m (landings 0.35 m short to 0.35 m long)")
    print(f"{'':<30}{'inside: hits':>14}{'outside: misses':>17}{'agree with ref':>16}{'ms per throw':>14}")
    for name, (outcomes, ms) in results.items():
        inside = [hit for hit, miss in outcomes if abs(miss) < inner]
        outside = [not hit for hit, miss in outcomes if abs(miss) > outer]
        agree = sum(a[0] == b[0] for a, b in zip(outcomes, reference, strict=True))
        print(f"{name:<30}{f'{sum(inside)}/{len(inside)}':>14}{f'{sum(outside)}/{len(outside)}':>17}"
              f"{f'{agree}/{len(outcomes)}':>16}{ms:>14.2f}")
    if args.figure:
        draw(results, args.figure)


def draw(results: dict, path: str) -> None:
    """Every verdict (hit or miss) against the landing's signed miss, one row per way."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    half, window = 0.5 * BASKET.opening, 0.5 * BASKET.opening - BALL_RADIUS
    figure, axes = plt.subplots(figsize=(9, 3.2), layout="constrained")
    axes.axvspan(-window, window, color="#d9f0d3", zorder=0, label="window: |miss| < opening/2 - radius")
    for side in (-1, 1):
        axes.axvspan(side * half, side * (half + WALL), color="#8c6d46", alpha=0.8,
                     label="rim (wall)" if side < 0 else None)
        axes.axvspan(side * (window - MARGIN), side * window, color="#dddddd", alpha=0.7, zorder=0.5)
        axes.axvspan(side * (half + WALL), side * (half + WALL + MARGIN), color="#dddddd", alpha=0.7, zorder=0.5,
                     label="within 3 cm of the window or the rim" if side < 0 else None)
    for row, (outcomes, _) in enumerate(results.values()):
        miss = np.array([m for _, m in outcomes])
        hit = np.array([h for h, _ in outcomes])
        axes.scatter(miss[hit], np.full(hit.sum(), row), marker="o", s=14, color="#1a9850",
                     label="hit" if row == 0 else None)
        axes.scatter(miss[~hit], np.full((~hit).sum(), row), marker="x", s=14, color="#d73027",
                     label="miss" if row == 0 else None)
    axes.set_yticks(range(len(results)), list(results))
    axes.set_ylim(-0.6, len(results) - 0.4)
    axes.invert_yaxis()
    axes.set_xlabel("signed miss of the landing on the rim's plane (m): < 0 short, > 0 long")
    axes.set_title(f"Verdict of {len(next(iter(results.values()))[0])} throws across a basket at "
                   f"{BASKET.distance:g} m, by simulation step")
    axes.legend(loc="upper center", bbox_to_anchor=(0.5, -0.28), ncol=3, fontsize=8, frameon=False)
    figure.savefig(path, dpi=120)
    plt.close(figure)
    print(f"figure: {path}")


if __name__ == "__main__":
    main()
