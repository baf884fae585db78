"""A small whole-arm data set for the model tests: throws with elbow, shoulder (and wrist).

Smaller and smoother than the simulated whole-arm people of rlff.synthetic (no camera, no
glitches), so that the model tests run in milliseconds and test the model alone: each throw extends the elbow from 0.8 to 2.9 rad while the shoulder
rises and the wrist flicks, faster for farther baskets, with per-throw scatter. Columns follow the
whole-arm contract: angle, velocity (the elbow), shoulder, shoulder_velocity, wrist,
wrist_velocity (rad, rad/s), distance (m), optionally bearing (deg) and time (s).
"""

from __future__ import annotations

import numpy as np

from rlff.dataset import Dataset, Trajectory

ELBOW_START, ELBOW_END = 0.8, 2.9


def whole_arm_throws(
    seed: int = 0,
    distances: tuple[float, ...] = (1.0, 2.0, 3.0, 4.0),
    throws: int = 4,
    samples: int = 40,
    wrist: bool = True,
    bearings: tuple[float, ...] | None = None,
) -> Dataset:
    """Throws (``throws`` per distance and bearing) of ``samples`` samples each.

    The elbow angle rises monotonically (a smooth step in time over the throw's duration T), the
    shoulder elevation rises from 0.9 rad by an amount growing with the distance, the wrist flicks
    from 2.6 towards 3.1 rad late in the throw. Velocities are the exact time derivatives.
    """
    rng = np.random.default_rng(seed)
    trajectories = []
    for bearing in bearings or (None,):
        for distance in distances:
            for j in range(throws):
                duration = 0.45 / (1.0 + 0.12 * distance) * rng.uniform(0.92, 1.08)
                time = np.linspace(0.0, duration, samples)
                s = time / duration
                step = 3 * s**2 - 2 * s**3  # smooth step 0 -> 1
                step_rate = 6 * s * (1 - s) / duration
                rise = 0.5 + 0.12 * distance + rng.normal(0, 0.03)
                flick = 3 * s**4 - 2 * s**6  # late: the wrist moves at the end
                flick_rate = (12 * s**3 - 12 * s**5) / duration
                columns = {
                    "angle": ELBOW_START + (ELBOW_END - ELBOW_START) * step,
                    "velocity": (ELBOW_END - ELBOW_START) * step_rate,
                    "shoulder": 0.9 + rise * step,
                    "shoulder_velocity": rise * step_rate,
                    "distance": np.full(samples, distance),
                    "time": time,
                }
                if wrist:
                    amount = 0.5 * rng.uniform(0.8, 1.2)
                    columns["wrist"] = 2.6 + amount * flick
                    columns["wrist_velocity"] = amount * flick_rate
                name = f"d{distance:g}-{j}"
                if bearing is not None:
                    columns["bearing"] = np.full(samples, float(bearing))
                    name = f"b{bearing:g}-{name}"
                trajectories.append(Trajectory(name, columns, {"target": distance}))
    return Dataset(trajectories, context=("distance",) if bearings is None else ("distance", "bearing"))
