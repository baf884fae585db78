"""Timed joint trajectories: time from (angle, velocity), resampling, limits."""

from rlff.trajectory.joint import JointTrajectory
from rlff.trajectory.limits import (
           ClipReport,
           LimitChange,
           clip_to_limits,
           limit_changes,
           require_within_limits,
)
from rlff.trajectory.resample import CONTROLLER_PERIODS, resample
from rlff.trajectory.timing import time_along_path

__all__ = ["CONTROLLER_PERIODS", "ClipReport", "JointTrajectory", "LimitChange", "clip_to_limits",
           "limit_changes", "require_within_limits", "resample", "time_along_path"]
