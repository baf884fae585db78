"""Simulation of a throw in MuJoCo: scene, executing a joint trajectory, outcome, reach, frames.

``simulate_throw(trajectory, Basket(2.0))`` runs one throw and returns a :class:`ThrowOutcome`;
``max_reach(robot)`` says how far the arm can throw at all.
"""

from __future__ import annotations

import ctypes.util
import os

# MuJoCo reads MUJOCO_GL once, at its first import: choose a headless backend before that.
if "MUJOCO_GL" not in os.environ:
    if ctypes.util.find_library("EGL"):
        os.environ["MUJOCO_GL"] = "egl"
    elif ctypes.util.find_library("OSMesa"):
        os.environ["MUJOCO_GL"] = "osmesa"

from rlff.sim.basket import Basket  # noqa: E402
from rlff.sim.gap import Gap, parse_gap  # noqa: E402
from rlff.sim.reach import Reach, max_reach, require_reachable, throw_reach  # noqa: E402
from rlff.sim.throw import ReleaseState, ThrowOutcome, simulate_throw  # noqa: E402

__all__ = [
    "Basket",
    "Gap",
    "Reach",
    "ReleaseState",
    "ThrowOutcome",
    "max_reach",
    "parse_gap",
    "require_reachable",
    "simulate_throw",
    "throw_reach",
]
