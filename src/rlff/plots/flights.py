"""The ball's flights in 3-D: the arm's base, the baskets at their bearings and heights, every flight.

Each flight is the closed-form projectile (no drag, as the simulation's free flight) from the
ball's release state down to the floor, drawn solid to where it comes down through its basket's
rim height and dotted below; green where the throw hit, red where it missed.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from rlff.ballistics import flight_time, position_at
from rlff.errors import InputError
from rlff.plots._figure import HIT_COLOUR, MISS_COLOUR, SavedFigure, figure_style, new_figure, save

_BASE_COLOUR = "#4d6a8a"
#: Where the ball left the hand.
_RELEASE_COLOUR = "#e3b505"
_BASKET_COLOUR = "#8c5a2b"


def flights_3d(
    flights: Sequence[Mapping[str, Any]],
    out: str | Path,
    *,
    base_height: float = 0.45,
    title: str | None = None,
) -> SavedFigure:
    """Draw the flights of several throws around the robot in one 3-D view.

    Parameters
    ----------
    flights : sequence of mapping
        One per throw: ``position`` and ``velocity`` (3,) of the ball at release (m, m/s; x
        forward, y left, z up from the floor), ``distance`` (m) and ``bearing`` (deg) of its
        basket's centre from joint 1's axis, ``rim_height`` and ``opening`` (m), ``hit`` (bool).
    out : path
        File stem of the PNG and SVG.
    base_height : float
        Height (m) of the robot's base column drawn at the origin (joint 1's axis).
    title : str, optional

    Raises
    ------
    InputError
        No flights, or one with a missing or malformed field (named).
    """
    if not flights:
        raise InputError("no flights to draw")
    throws = [_checked(index, flight) for index, flight in enumerate(flights)]
    with figure_style():
        figure = new_figure(9.5, 7.5)
        axes = figure.add_subplot(projection="3d")
        reach = max(max(t["distance"] for t in throws) + 0.5, 1.0)
        for bearing in sorted({t["bearing"] for t in throws}):
            ray = np.radians(bearing)
            axes.plot([0, reach * np.cos(ray)], [0, reach * np.sin(ray)], [0, 0], color="grey", linewidth=0.8,
                      linestyle=":")
            axes.text(reach * np.cos(ray), reach * np.sin(ray), 0.0, f"{bearing:g}°", color="grey", fontsize=8)
        axes.plot([0, 0], [0, 0], [0, base_height], color=_BASE_COLOUR, linewidth=8, solid_capstyle="butt")
        axes.scatter([0], [0], [base_height], color=_BASE_COLOUR, s=40, label="robot (joint 1's axis)")
        tops = [base_height]
        for index, throw in enumerate(throws):
            _draw_basket(axes, throw, label="baskets" if index == 0 else None)
            tops.append(_draw_flight(axes, throw))
            # the arm, straightened: from the base to where it let go of the ball
            axes.plot([0, throw["position"][0]], [0, throw["position"][1]], [base_height, throw["position"][2]],
                      color=_BASE_COLOUR, linewidth=1.0, alpha=0.5, label="arm to the release" if index == 0 else None)
        hit = sum(t["hit"] for t in throws)
        axes.scatter([], [], [], color=_RELEASE_COLOUR, edgecolor="black", s=14, label="release")
        axes.plot([], [], color=HIT_COLOUR, label=f"hit ({hit})")
        axes.plot([], [], color=MISS_COLOUR, label=f"miss ({len(throws) - hit})")
        top = max(tops) * 1.05
        axes.set_xlim(-0.3, reach)
        axes.set_ylim(-0.3, reach)
        axes.set_zlim(0.0, top)
        axes.set_box_aspect((reach + 0.3, reach + 0.3, top))  # metres look like metres
        axes.view_init(elev=32, azim=-118)
        axes.set_xlabel("forward x (m)")
        axes.set_ylabel("left y (m)")
        axes.set_zlabel("height z (m)")
        axes.legend(loc="upper left", fontsize=8)
        axes.set_title(title or f"{len(throws)} throws around the robot, seen in 3-D")
    return save(figure, out)


def _checked(index: int, flight: Mapping[str, Any]) -> dict[str, Any]:
    """One flight's fields as floats and arrays; :class:`InputError` naming what is wrong."""
    try:
        throw = {
            "position": np.asarray(flight["position"], dtype=float),
            "velocity": np.asarray(flight["velocity"], dtype=float),
            "distance": float(flight["distance"]),
            "bearing": float(flight.get("bearing", 0.0)),
            "rim_height": float(flight.get("rim_height", 0.3)),
            "opening": float(flight.get("opening", 0.35)),
            "hit": bool(flight["hit"]),
        }
    except (KeyError, TypeError, ValueError, OverflowError) as exc:
        raise InputError(f"flight {index}: missing or malformed field {exc}") from None
    if throw["position"].shape != (3,) or throw["velocity"].shape != (3,):
        raise InputError(f"flight {index}: position and velocity must be (x, y, z)")
    return throw


def _draw_basket(axes, throw: Mapping[str, Any], label: str | None) -> None:
    """The basket as a square box on the floor, its walls facing joint 1's axis."""
    ray = np.radians(throw["bearing"])
    along, across = np.array([np.cos(ray), np.sin(ray)]), np.array([-np.sin(ray), np.cos(ray)])
    half = 0.5 * throw["opening"]
    centre = throw["distance"] * along
    corners = np.array([centre + a * half * along + b * half * across for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1), (-1, -1))])
    for z in (0.0, throw["rim_height"]):
        axes.plot(corners[:, 0], corners[:, 1], np.full(5, z), color=_BASKET_COLOUR, linewidth=1.6,
                  label=label if z else None)
    for x, y in corners[:4]:
        axes.plot([x, x], [y, y], [0.0, throw["rim_height"]], color=_BASKET_COLOUR, linewidth=1.0)
    axes.text(*(centre + half * across * 1.4), throw["rim_height"], f"{throw['distance']:g} m", fontsize=7,
              color=_BASKET_COLOUR)


def _draw_flight(axes, throw: Mapping[str, Any]) -> float:
    """The flight from the release to the floor; its highest point (m)."""
    colour = HIT_COLOUR if throw["hit"] else MISS_COLOUR
    position, velocity = throw["position"], throw["velocity"]
    to_rim = float(flight_time(position[2], velocity[2], throw["rim_height"]))
    to_floor = float(flight_time(position[2], velocity[2], 0.0))
    if not np.isfinite(to_floor):
        return float(position[2])
    split = to_rim if np.isfinite(to_rim) else 0.0
    above = position_at(position, velocity, np.linspace(0.0, split, 60))
    below = position_at(position, velocity, np.linspace(split, to_floor, 15))
    axes.plot(above[:, 0], above[:, 1], above[:, 2], color=colour, linewidth=1.4)
    axes.plot(below[:, 0], below[:, 1], below[:, 2], color=colour, linewidth=1.0, linestyle=":")
    axes.scatter([position[0]], [position[1]], [position[2]], color=_RELEASE_COLOUR, edgecolor="black", s=14)
    return float(max(above[:, 2].max(), position[2]))
