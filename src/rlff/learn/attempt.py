"""One executed attempt of the learning loop: what the robot did and what came of it."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from rlff.errors import InputError


@dataclass(frozen=True)
class Attempt:
    """An executed throw, in the units of the demonstrations it joins.

    Parameters
    ----------
    index : int
        1 for the first attempt of a run.
    target : float
        Basket distance aimed at (m).
    query : float
        Distance the model was asked for (m): the target for the plain strategies, the
        calibrated label for ``calibrate``, ``nan`` for the baselines that do not query a model.
    angle, velocity : array of shape (T,)
        The path of the joint the elbow drives as the motion planner was given it, mapped back
        to the demonstrations' units (rad, rad/s): the proposal saturated at the robot's
        limits, at its own samples. The planner executes its first pose and its release (the
        last sample, all the ball's flight depends on) exactly and times the motion between
        (:mod:`rlff.trajectory.planner`), so planning this path again gives the executed trajectory.
    time : array of shape (T,)
        Time of each sample (s) along that path.
    hit : bool
        The ball ended in the basket.
    landing : float
        First landing point along the throwing direction (m): where the ball came down through
        the rim's height, or first touched the ground or the basket when it never did (as
        :func:`rlff.sim.simulate_throw` reports it); NaN where not measured, and as a method
        sees it under binary feedback.
    miss : float
        Signed miss (m): the landing's distance from the basket's centre, negative short of it,
        positive beyond it, hits included; NaN like ``landing``.
    exploration : float
        Mean DMM exploration factor along the generated path (0 for baselines without one).
    clipped : int
        Number of samples the robot mapping clipped to a joint limit (0 when within limits).
    seconds : float
        Wall time of the attempt (s): model, mapping and execution.
    info : dict
        Whatever else the method reports (JSON-serialisable), e.g. a baseline's parameters.
    arm : dict of str to array of shape (T,)
        The other driven joints' path, as ``angle``'s, in the demonstrations' units: ``shoulder`` (rad),
        ``shoulder_velocity`` (rad/s), ``wrist``, ``wrist_velocity``; empty for a one-joint throw.
    """

    index: int
    target: float
    query: float
    angle: np.ndarray
    velocity: np.ndarray
    time: np.ndarray
    hit: bool
    landing: float
    miss: float
    exploration: float = 0.0
    clipped: int = 0
    seconds: float = 0.0
    info: dict[str, Any] = field(default_factory=dict)
    arm: dict[str, np.ndarray] = field(default_factory=dict)

    def __post_init__(self) -> None:
        for name in ("angle", "velocity", "time"):
            array = np.asarray(getattr(self, name), dtype=float)
            if array.ndim != 1 or array.size < 2:
                raise InputError(f"attempt {self.index}: {name} must be 1-D with >= 2 samples")
            object.__setattr__(self, name, array)
        if not (self.angle.size == self.velocity.size == self.time.size):
            raise InputError(f"attempt {self.index}: angle, velocity and time differ in length")
        arm = {name: np.asarray(values, dtype=float) for name, values in self.arm.items()}
        for name, values in arm.items():
            if values.shape != self.angle.shape:
                raise InputError(f"attempt {self.index}: {name} has {values.size} samples, angle {self.angle.size}")
        object.__setattr__(self, "arm", arm)

    @property
    def path(self) -> dict[str, np.ndarray]:
        """The whole executed path (``rlff.robot.mapping.HumanPath``): angle, velocity, time and
        :attr:`arm`."""
        return {"angle": self.angle, "velocity": self.velocity, "time": self.time, **self.arm}

    def to_json(self) -> dict[str, Any]:
        """A plain dict for one line of the attempts log."""
        return {
            "attempt": self.index,
            "target": self.target,
            "query": _finite_or_none(self.query),
            "hit": bool(self.hit),
            "landing": _finite_or_none(self.landing),
            "miss": _finite_or_none(self.miss),
            "exploration": self.exploration,
            "clipped": self.clipped,
            "seconds": self.seconds,
            "angle": self.angle.tolist(),
            "velocity": self.velocity.tolist(),
            "time": self.time.tolist(),
            "info": self.info,
            # a one-joint attempt writes no "arm": its line is what older versions wrote
            **({"arm": {name: values.tolist() for name, values in self.arm.items()}} if self.arm else {}),
        }

    @classmethod
    def from_json(cls, record: dict[str, Any]) -> Attempt:
        """The attempt of one log line; :class:`KeyError`/``TypeError``/``ValueError`` if malformed."""
        return cls(
            index=int(record["attempt"]),
            target=float(record["target"]),
            query=_float_or_nan(record["query"]),
            angle=np.asarray(record["angle"], dtype=float),
            velocity=np.asarray(record["velocity"], dtype=float),
            time=np.asarray(record["time"], dtype=float),
            hit=bool(record["hit"]),
            landing=_float_or_nan(record["landing"]),
            miss=_float_or_nan(record["miss"]),
            exploration=float(record["exploration"]),
            clipped=int(record["clipped"]),
            seconds=float(record["seconds"]),
            info=dict(record["info"]),
            arm={str(name): np.asarray(values, dtype=float) for name, values in dict(record.get("arm", {})).items()},
        )


def _finite_or_none(value: float) -> float | None:
    """A float for JSON: None stands for NaN (no landing, no query), which JSON cannot hold."""
    return float(value) if np.isfinite(value) else None


def _float_or_nan(value: float | None) -> float:
    return float("nan") if value is None else float(value)
