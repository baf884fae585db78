"""A timed multi-joint trajectory: what robots, exports and the simulation take."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from rlff.dataset import as_floats, owned
from rlff.errors import InputError
from rlff.limits import as_names


@dataclass(frozen=True)
class JointTrajectory:
    """Joint positions, velocities and accelerations at increasing times.

    The arrays hold numbers (integers or floats, kept as floats); booleans, text or objects are an
    :class:`InputError` naming the array.

    Parameters
    ----------
    joint_names : sequence of str, length J
    time : array of shape (T,)
        Time from start (s), strictly increasing, starting at 0 or later.
    positions : array of shape (T, J)
        Joint positions (rad).
    velocities : array of shape (T, J)
        Joint velocities (rad/s).
    accelerations : array of shape (T, J), optional
        Joint accelerations (rad/s^2); zeros when not given.
    release_time : float, optional
        Time (s) of the throw's release, one of ``time``, when the trajectory is a planned throw
        (:func:`rlff.trajectory.planner.plan_throw`); None otherwise.
    """

    joint_names: tuple[str, ...]
    time: np.ndarray
    positions: np.ndarray
    velocities: np.ndarray
    accelerations: np.ndarray | None = None
    release_time: float | None = None

    def __post_init__(self) -> None:
        names = tuple(str(n) for n in as_names(self.joint_names))
        # the caller's own arrays stay theirs and writeable: the trajectory freezes copies (owned)
        time = owned(as_floats(self.time, "time"), self.time)
        positions = owned(as_floats(self.positions, "positions"), self.positions)
        velocities = owned(as_floats(self.velocities, "velocities"), self.velocities)
        accelerations = (
            np.zeros_like(positions) if self.accelerations is None
            else owned(as_floats(self.accelerations, "accelerations"), self.accelerations)
        )
        if len(set(names)) != len(names) or not names:
            raise InputError(f"joint names must be unique and non-empty, got {list(names)}")
        if time.ndim != 1 or time.size < 1:
            raise InputError(f"time must be 1-D and non-empty, got shape {time.shape}")
        shape = (time.size, len(names))
        for label, array in (("positions", positions), ("velocities", velocities), ("accelerations", accelerations)):
            if array.shape != shape:
                raise InputError(f"{label} must have shape {shape}, got {array.shape}")
            if not np.all(np.isfinite(array)):
                raise InputError(f"{label} hold NaN or inf")
        if not np.all(np.isfinite(time)) or np.any(np.diff(time) <= 0):
            raise InputError("time must be finite and strictly increasing")
        if self.release_time is not None:
            release = float(self.release_time)
            if not time[0] <= release <= time[-1]:
                raise InputError(f"release time {release} s is outside the trajectory's "
                                 f"{time[0]}..{time[-1]} s")
            object.__setattr__(self, "release_time", release)
        for name, value in (("joint_names", names), ("time", time), ("positions", positions),
                            ("velocities", velocities), ("accelerations", accelerations)):
            if isinstance(value, np.ndarray):
                value.setflags(write=False)
            object.__setattr__(self, name, value)

    def __len__(self) -> int:
        return self.time.size

    def __repr__(self) -> str:
        """One line: the joints, the points, the duration and the release; not the arrays (the
        dataclass printed kilobytes of them)."""
        release = "no release" if self.release_time is None else f"release at {self.release_time:.4g} s"
        return f"JointTrajectory(joints={list(self.joint_names)}, {len(self)} points, {self.duration:.4g} s, {release})"

    @property
    def duration(self) -> float:
        """Time of the last point (s)."""
        return float(self.time[-1])

    def joint_index(self, name: str) -> int:
        """Column of joint ``name``; :class:`InputError` listing the joints if unknown."""
        try:
            return self.joint_names.index(name)
        except ValueError:
            raise InputError(f"unknown joint {name!r} (joints: {', '.join(self.joint_names)})") from None

    def holding(self, names: Sequence[str], still: Sequence[float]) -> JointTrajectory:
        """The trajectory over the joints ``names`` (length J', in that order): the joints it has
        as they are, every other one held at its entry of ``still`` ((J',) rad) at rest, as a
        controller holds the joints a goal does not name."""
        names = as_names(names)
        still = np.asarray(still, dtype=float)
        if still.shape != (len(names),):
            raise InputError(f"still must have one position per joint name ({len(names)}), got shape {still.shape}")
        shape = (len(self), len(names))
        positions, velocities, accelerations = np.tile(still, (shape[0], 1)), np.zeros(shape), np.zeros(shape)
        for column, name in enumerate(names):
            if name in self.joint_names:
                own = self.joint_index(name)
                positions[:, column] = self.positions[:, own]
                velocities[:, column] = self.velocities[:, own]
                accelerations[:, column] = self.accelerations[:, own]
        return JointTrajectory(tuple(names), self.time, positions, velocities, accelerations, self.release_time)

    def select(self, names: Sequence[str]) -> JointTrajectory:
        """The same trajectory restricted to the joints ``names``, in that order."""
        names = as_names(names)
        index = [self.joint_index(n) for n in names]
        return JointTrajectory(tuple(names), self.time, self.positions[:, index],
                               self.velocities[:, index], self.accelerations[:, index],
                               self.release_time)
