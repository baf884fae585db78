"""The target: an open square basket standing on the ground in front of the robot."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rlff.errors import InputError
from rlff.limits import check_distance

#: Thickness of the basket's walls and floor (m).
WALL = 0.01


@dataclass(frozen=True)
class Basket:
    """A square basket on the ground, centred on the robot's forward axis.

    Parameters
    ----------
    distance : float
        Horizontal distance from the robot's joint 1 axis to the centre of the basket (m).
    rim_height : float
        Height of the rim above the ground (m).
    opening : float
        Inner width of the square opening (m).
    """

    distance: float
    rim_height: float = 0.3
    opening: float = 0.35

    def __post_init__(self) -> None:
        for name in ("distance", "rim_height", "opening"):
            value = getattr(self, name)
            if not np.isfinite(value) or value <= 0:
                raise InputError(f"basket {name} must be a positive number of metres, got {value}")
        check_distance("basket distance", self.distance)
        object.__setattr__(self, "distance", float(self.distance))
        object.__setattr__(self, "rim_height", float(self.rim_height))
        object.__setattr__(self, "opening", float(self.opening))

    def holds(self, position: np.ndarray, radius: float) -> bool:
        """Whether a ball of ``radius`` (m) centred at ``position`` (3,) is inside, below the rim."""
        x, y, z = np.asarray(position, dtype=float)
        half = 0.5 * self.opening
        return bool(abs(x - self.distance) < half and abs(y) < half and z < self.rim_height - radius)

    def to_dict(self) -> dict[str, float]:
        """Plain values for JSON: distance, rim_height and opening (m)."""
        return {"distance": self.distance, "rim_height": self.rim_height, "opening": self.opening}
