"""The target: an open square basket standing on the ground, on a bearing line from the robot."""

from __future__ import annotations

from dataclasses import dataclass, fields
from numbers import Real

import numpy as np

from rlff.dataset import BEARING_RANGE
from rlff.errors import InputError
from rlff.limits import check_distance
from rlff.sim.arm import BALL_RADIUS

#: Thickness of the basket's walls and floor (m).
WALL = 0.01


@dataclass(frozen=True)
class Basket:
    """A square basket on the ground, its centre ``distance`` m along the bearing line.

    Parameters
    ----------
    distance : float
        Horizontal distance from the robot's joint 1 axis to the centre of the basket (m).
    rim_height : float
        Height of the rim above the ground (m).
    opening : float
        Inner width of the square opening (m).
    bearing : float
        Direction of the basket seen from above (deg): 0 straight ahead (the robot's x axis),
        positive to the left (counter-clockwise, the sense of joint 1); -180..180. The basket's
        walls face the robot.

    Raises
    ------
    InputError
        A value out of its range, the message starting with ``basket`` and the parameter's name
        (``basket rim_height 0.01 m is no higher ...``), so that a caller can add where the
        value came from.
    """

    distance: float
    rim_height: float = 0.3
    opening: float = 0.35
    bearing: float = 0.0

    def __post_init__(self) -> None:
        for name in (f.name for f in fields(self)):
            _require_number(name, getattr(self, name))
        check_distance("basket distance", self.distance)
        for name in ("rim_height", "opening"):
            value = getattr(self, name)
            if not np.isfinite(value) or value <= 0:
                raise InputError(f"basket {name} must be a positive number of metres, got {value}")
        if self.rim_height <= WALL + BALL_RADIUS:
            raise InputError(f"basket rim_height {self.rim_height:g} m is no higher than a ball resting on "
                             f"the basket's floor reaches ({WALL + BALL_RADIUS:g} m to its centre): its walls would "
                             "not keep the ball in; give the rim's height above the ground in metres")
        if self.opening <= 2 * BALL_RADIUS:
            raise InputError(f"basket opening {self.opening:g} m is no wider than the ball "
                             f"({2 * BALL_RADIUS:g} m across): no throw drops into it")
        if self.opening >= 2 * self.distance:
            raise InputError(f"basket opening {self.opening:g} m reaches back past the robot from a basket "
                             f"{self.distance:g} m away: give the opening's inner width in metres (0.35 is the thesis' "
                             "basket)")
        low, high = BEARING_RANGE
        if not (np.isfinite(self.bearing) and low <= self.bearing <= high):
            raise InputError(f"basket bearing must be {low:g}..{high:g} degrees, got {self.bearing}")
        object.__setattr__(self, "distance", float(self.distance))
        object.__setattr__(self, "rim_height", float(self.rim_height))
        object.__setattr__(self, "opening", float(self.opening))
        object.__setattr__(self, "bearing", float(self.bearing))

    @property
    def direction(self) -> np.ndarray:
        """Unit vector (2,) of the bearing line on the floor (x forward, y left)."""
        angle = np.radians(self.bearing)
        return np.array([np.cos(angle), np.sin(angle)])

    @property
    def centre(self) -> np.ndarray:
        """Centre of the basket on the floor (2,): x, y (m)."""
        return self.distance * self.direction

    def along_line(self, x: float, y: float) -> tuple[float, float]:
        """A floor point (m) as (distance along the bearing line from joint 1's axis, lateral
        offset from the line: + left of it), both m."""
        ux, uy = self.direction
        return float(x * ux + y * uy), float(-x * uy + y * ux)

    def holds(self, position: np.ndarray, radius: float) -> bool:
        """Whether a ball of ``radius`` (m) centred at ``position`` (3,) is inside: within the
        opening, and wholly below the rim or lying on the floor (its centre within half a radius
        of where a ball at rest there has it; the walls reach above that, :meth:`__post_init__`).
        With the rim's rule alone a rim below the ball's top at rest (0.076 m) could never hold a
        ball: a tester's run at a 0.07 m rim threw its budget with the ball lying in the basket."""
        x, y, z = np.asarray(position, dtype=float)
        along, lateral = self.along_line(x, y)
        half = 0.5 * self.opening
        below = z < self.rim_height - radius or z < WALL + 1.5 * radius
        return bool(abs(along - self.distance) < half and abs(lateral) < half and below)

    def to_dict(self) -> dict[str, float]:
        """Plain values for JSON: distance, rim_height, opening (m) and bearing (deg)."""
        return {"distance": self.distance, "rim_height": self.rim_height, "opening": self.opening,
                "bearing": self.bearing}


def _require_number(name: str, value: object) -> None:
    """:class:`InputError` unless ``value`` is a real number (not a str: ``Basket("1.2")`` failed
    deep in the checks with a TypeError comparing a float with a str)."""
    if not isinstance(value, Real) or isinstance(value, bool):
        raise InputError(f"basket {name} must be a number, got {value!r} ({type(value).__name__})")


def as_basket(basket: Basket | float) -> Basket:
    """``basket``, or the default basket ``Basket(basket)`` at a distance (m) given as a number;
    :class:`InputError` for anything else (a float had failed with an AttributeError)."""
    if isinstance(basket, Basket):
        return basket
    if isinstance(basket, Real) and not isinstance(basket, bool):
        return Basket(float(basket))
    raise InputError(f"basket must be a Basket or its distance in m, got {basket!r} ({type(basket).__name__})")
