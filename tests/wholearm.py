"""Human-like whole-arm throws for the robot tests (until simulated whole-arm people exist).

A throw as people make it: the shoulder's elevation rises ~1.0 -> 2.4 rad while the elbow extends
~0.8 -> 2.9 rad and the wrist uncocks ~2.4 -> 3.0 rad, each a minimum-jerk motion released at
the elbow's peak speed, the shoulder leading and the wrist lagging (proximal-to-distal).
"""

from __future__ import annotations

import numpy as np

#: Phase lead of the shoulder and lag of the wrist against the elbow (share of the motion).
LEAD = 0.1


def _minimum_jerk(u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Position and rate (per unit u) of the minimum-jerk profile 0 -> 1 over u in [0, 1]."""
    u = np.clip(u, 0.0, 1.0)
    return 10 * u**3 - 15 * u**4 + 6 * u**5, 30 * u**2 - 60 * u**3 + 30 * u**4


def human_throw(release_speed: float = 8.0, samples: int = 60, wrist: bool = True,
                shoulder: tuple[float, float] = (1.0, 2.4), elbow: tuple[float, float] = (0.8, 2.9),
                hand: tuple[float, float] = (2.4, 3.0)) -> dict[str, np.ndarray]:
    """A whole-arm human path (the columns of :data:`rlff.robot.mapping.HumanPath`).

    ``release_speed`` is the elbow's speed at release (rad/s); the path ends at the release.
    """
    release = 0.5  # the elbow's peak speed of the minimum-jerk profile
    u = np.linspace(0.0, release, samples)
    columns: dict[str, np.ndarray] = {}
    # the elbow travels half its profile to the release: its rate there is 1.875 per unit u
    elbow_span = (elbow[1] - elbow[0]) / _minimum_jerk(np.array(release))[0]
    duration = elbow_span * 1.875 / release_speed
    for name, (first, last), shift in (("angle", elbow, 0.0), ("shoulder", shoulder, LEAD),
                                       ("wrist", hand, -LEAD)):
        if name == "wrist" and not wrist:
            continue
        position, rate = _minimum_jerk(u + shift)
        begin, end = _minimum_jerk(np.array([shift, release + shift]))[0]
        span = (last - first) / (end - begin)
        columns[name] = first + span * (position - begin)
        velocity = span * rate / duration
        columns["velocity" if name == "angle" else f"{name}_velocity"] = velocity
    columns["time"] = u * duration
    return columns
