"""A generated throw's CSV, as ``rlff generate`` writes it, for the tests that need one to throw."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from rlff.timing import time_along_path


def generated_path(path: Path, peak: float = 9.0) -> Path:
    """A generated throw as the model writes it: elbow angle 0.7 -> 1.95 rad, speeding up to ``peak`` rad/s."""
    angle = np.linspace(0.7, 1.95, 30)
    velocity = peak * np.sin(0.5 * np.pi * (angle - 0.7) / 1.25) ** 0.5
    velocity[0] = 0.5
    time = time_along_path(angle, velocity)
    rows = ["angle,velocity,time,pdf,exploration,gmr_mean"]
    rows += [f"{a:.17g},{v:.17g},{t:.17g},0.5,0.0,{v:.17g}" for a, v, t in zip(angle, velocity, time, strict=True)]
    path.write_text("\n".join(rows) + "\n")
    return path
