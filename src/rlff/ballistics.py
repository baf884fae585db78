"""Projectile flight in a vertical plane: where a released ball crosses a given height.

Pure physics without drag, shared by the simulated demonstrations (outcome of a human throw),
capture (estimated landing of a recorded throw), the simulation (analytic prediction beside
MuJoCo's free flight) and the learning loop. Coordinates: x forward (m), z up (m).
"""

from __future__ import annotations

import numpy as np

#: Standard gravity (m/s^2).
GRAVITY = 9.81


def crossing_distance(
    release_x: np.ndarray | float,
    release_z: np.ndarray | float,
    velocity_x: np.ndarray | float,
    velocity_z: np.ndarray | float,
    height: np.ndarray | float,
    gravity: float = GRAVITY,
) -> np.ndarray:
    """Horizontal position where the ball, on its way down, crosses ``height``.

    Parameters
    ----------
    release_x, release_z : float or array of shape (N,)
        Release position (m).
    velocity_x, velocity_z : float or array of shape (N,)
        Release velocity (m/s).
    height : float or array of shape (N,)
        Height of the crossing (m), e.g. a basket's rim.
    gravity : float
        Gravitational acceleration (m/s^2), positive.

    Returns
    -------
    ndarray of shape (N,) or scalar array
        x at the descending crossing (m); NaN where the ball never reaches ``height``.
    """
    t = flight_time(release_z, velocity_z, height, gravity)
    return np.asarray(release_x, dtype=float) + np.asarray(velocity_x, dtype=float) * t


def flight_time(
    release_z: np.ndarray | float,
    velocity_z: np.ndarray | float,
    height: np.ndarray | float,
    gravity: float = GRAVITY,
) -> np.ndarray:
    """Time (s) from release until the ball crosses ``height`` on its way down; NaN if never.

    ``release_z``, ``velocity_z`` and ``height`` broadcast against each other (numpy's rules):
    scalars and arrays of shape (N,) mix freely.

    Parameters
    ----------
    release_z : float or array
        Release height (m).
    velocity_z : float or array
        Vertical release velocity (m/s), positive up.
    height : float or array
        Height of the crossing (m), e.g. a basket's rim.
    gravity : float
        Gravitational acceleration (m/s^2), positive.

    Returns
    -------
    ndarray of the three's broadcast shape (0-d when all are scalars)
        Time since release (s); NaN where the ball never comes down to ``height``.
    """
    z0, vz, h = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (release_z, velocity_z, height)))
    # z0 + vz t - g t^2 / 2 = h: the larger root is the descending crossing
    discriminant = vz**2 + 2.0 * gravity * (z0 - h)
    with np.errstate(invalid="ignore"):
        t = (vz + np.sqrt(discriminant)) / gravity
    return np.where((discriminant >= 0) & (t >= 0), t, np.nan)


def position_at(
    release: np.ndarray, velocity: np.ndarray, t: np.ndarray | float, gravity: float = GRAVITY
) -> np.ndarray:
    """Ball position after ``t`` seconds of free flight.

    Parameters
    ----------
    release : array of shape (..., 3)
        Release position (x, y, z) in m, z up.
    velocity : array of shape (..., 3)
        Release velocity in m/s.
    t : float or array broadcastable to (...)
        Time since release (s).

    Returns
    -------
    ndarray of shape (..., 3)
    """
    release = np.asarray(release, dtype=float)
    velocity = np.asarray(velocity, dtype=float)
    t = np.asarray(t, dtype=float)[..., None]
    drop = np.zeros_like(release)
    drop[..., 2] = 0.5 * gravity
    return release + velocity * t - drop * t**2
