"""An arm that is not its robot file: how the simulated arm executes a commanded trajectory.

A real arm never quite is its robot file. A :class:`Gap` says how the simulated one differs from
the file the loop and the planner use, ``speed:G`` (it reaches G of the commanded joint speeds, as
under a controller's speed override or a servo that lags) or ``delay:S`` (the gripper lets go S
seconds after the planned release), and :meth:`Gap.executed` turns a commanded
:class:`~rlff.trajectory.JointTrajectory` into the one that arm makes. Its name (``none``,
``speed:0.9``, ``delay:0.02``) is the text form the command line and the attempts log use.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from rlff.errors import InputError
from rlff.limits import parse_number


@dataclass(frozen=True)
class Gap:
    """How the simulated arm differs from the robot file the methods plan with.

    Parameters
    ----------
    name : str
        As written on the command line (``none``, ``speed:0.95``, ``delay:0.02``).
    speed : float
        Fraction (0, 1] of the commanded joint speeds the arm reaches: the trajectory runs
        1 / speed times slower along the same path (positions kept, velocities scaled).
    delay : float
        Seconds (>= 0) the ball leaves after the planned release: at the first sample at or
        after it, further along the throw's braking.
    """

    name: str = "none"
    speed: float = 1.0
    delay: float = 0.0

    @property
    def none(self) -> bool:
        """The arm is its robot file."""
        return self.speed == 1.0 and self.delay == 0.0

    def executed(self, trajectory):
        """The :class:`~rlff.trajectory.JointTrajectory` the arm makes of the commanded one."""
        if self.none:
            return trajectory
        time = trajectory.time / self.speed
        release = trajectory.release_time
        if release is not None:
            index = min(int(np.searchsorted(trajectory.time, release + self.delay - 1e-12)), len(time) - 1)
            release = float(time[index])
        return replace(trajectory, time=time, velocities=trajectory.velocities * self.speed,
                       accelerations=trajectory.accelerations * self.speed**2, release_time=release)


def parse_gap(text: str) -> Gap:
    """The gap of ``none``, ``speed:G`` (0 < G <= 1) or ``delay:S`` (0 <= S <= 0.2 s)."""
    word, _, value = text.strip().partition(":")
    if word == "none" and not value:
        return Gap()
    if word in ("speed", "delay"):
        if not value.strip():  # "'' is not a number" had not said what was missing
            raise InputError(f"gap {text!r}: give its value after ':', e.g. "
                             + ("speed:0.9 (the fraction of the commanded speed the arm reaches)" if word == "speed"
                                else "delay:0.02 (the seconds the release comes late)"))
        number = parse_number(value, f"gap {text!r}")
        if word == "speed" and 0 < number <= 1:
            return Gap(f"speed:{number:g}", speed=number)
        if word == "delay" and 0 <= number <= 0.2:
            return Gap(f"delay:{number:g}", delay=number)
        raise InputError(f"gap {text!r}: speed takes the fraction of the commanded speed the arm reaches "
                         "(0 < G <= 1), delay the seconds the release comes late (0 to 0.2 s)")
    raise InputError(f"unknown gap {text!r} (known: none, speed:G, delay:S)")
