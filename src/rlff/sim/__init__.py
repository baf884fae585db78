"""Simulation of a throw in MuJoCo: scene, executing a joint trajectory, outcome, reach, frames.

``simulate_throw(trajectory, Basket(2.0))`` runs one throw and returns a :class:`ThrowOutcome`;
``max_reach(robot)`` says how far the arm can throw at all.
"""

from __future__ import annotations

import ctypes.util
import os

from rlff.errors import InputError

# MuJoCo reads MUJOCO_GL once, at its first import: choose a headless backend before that.
if "MUJOCO_GL" not in os.environ:
    if ctypes.util.find_library("EGL"):
        os.environ["MUJOCO_GL"] = "egl"
    elif ctypes.util.find_library("OSMesa"):
        os.environ["MUJOCO_GL"] = "osmesa"
else:
    # one the user set: MuJoCo's import fails on a backend it does not know or cannot load (with
    # "invalid value" or an AttributeError deep in PyOpenGL), which stopped every throw, not only
    # its frames
    _chosen, _libraries = os.environ["MUJOCO_GL"], {"egl": "EGL", "osmesa": "OSMesa"}
    if _chosen.lower() not in (*_libraries, "glfw"):
        raise InputError(f"MUJOCO_GL={_chosen!r} is no backend MuJoCo knows (egl, osmesa, glfw): unset it, and rlff "
                         "takes EGL or OSMesa where one is installed")
    if _chosen.lower() in _libraries and not ctypes.util.find_library(_libraries[_chosen.lower()]):
        raise InputError(f"MUJOCO_GL={_chosen}: lib{_libraries[_chosen.lower()]} is not installed: install it, or "
                         "unset MUJOCO_GL (rlff then takes the backend that is there, or skips the frames)")

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
