"""The thesis' synthetic demonstrations (section 4.1.1, eq. 4.1, figure 4.1).

Eleven trajectories of 50 points each, angle evenly spaced over [0, 10] (symbolic units), basket
distance z = 1, 2, ..., 11, and velocity = f(z) (-angle^2 + 10 angle) / 2 with the multiplication
factor f(z) = 1 + slope (z - 1) (slope 0.1 by default): every curve starts and ends at rest and
the farther baskets get the faster throws.
"""

from __future__ import annotations

import numpy as np

from rlff.dataset import Dataset, Trajectory
from rlff.errors import InputError

#: Length of the angle range; the base curve -x^2 + 10 x is zero at both ends.
ANGLE_SPAN = 10.0


def thesis_dataset(
    factor_slope: float = 0.1, n_trajectories: int = 11, n_points: int = 50
) -> Dataset:
    """The thesis' synthetic set as a dataset with columns angle, distance, velocity.

    Parameters
    ----------
    factor_slope : float
        Slope of the multiplication factor f(z) = 1 + slope (z - 1).
    n_trajectories : int
        Number of trajectories, at distances z = 1, 2, ..., n_trajectories.
    n_points : int
        Points per trajectory, angle evenly spaced over [0, 10].

    Returns
    -------
    Dataset
        Trajectories ``z01``, ``z02``... with metadata ``source`` ("thesis synthetic") and
        ``target`` (z); context column ``distance``.
    """
    if not np.isfinite(factor_slope):
        raise InputError(f"factor slope must be finite, got {factor_slope}")
    if n_trajectories < 1:
        raise InputError(f"need at least 1 trajectory, got {n_trajectories}")
    if n_points < 2:
        raise InputError(f"need at least 2 points per trajectory, got {n_points}")
    angle = np.linspace(0.0, ANGLE_SPAN, n_points)
    base = (-(angle**2) + ANGLE_SPAN * angle) / 2.0
    width = len(str(n_trajectories))
    trajectories = []
    for z in range(1, n_trajectories + 1):
        factor = 1.0 + factor_slope * (z - 1)
        trajectories.append(
            Trajectory(
                f"z{z:0{max(width, 2)}d}",
                {"angle": angle, "distance": np.full(n_points, float(z)), "velocity": factor * base},
                {"source": "thesis synthetic", "target": float(z)},
            )
        )
    return Dataset(trajectories, context=("distance",))
