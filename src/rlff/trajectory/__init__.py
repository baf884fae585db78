"""Timed joint trajectories: resampling, limits, the motion planner (:mod:`rlff.trajectory.planner`)
and the one check (:mod:`rlff.trajectory.check`); time from (angle, velocity) is
:func:`rlff.timing.time_along_path`, kept here too as part of this package's names."""

from rlff.timing import time_along_path
from rlff.trajectory.check import MotionLimitError, check_trajectory
from rlff.trajectory.joint import JointTrajectory
from rlff.trajectory.limits import (
           ClipReport,
           LimitChange,
           clip_to_limits,
           limit_changes,
           require_within_limits,
)
from rlff.trajectory.planner import plan_stop, plan_throw, plan_transition
from rlff.trajectory.resample import CONTROLLER_PERIODS, resample

__all__ = ["CONTROLLER_PERIODS", "ClipReport", "JointTrajectory", "LimitChange", "MotionLimitError",
           "check_trajectory", "clip_to_limits", "limit_changes", "plan_stop", "plan_throw",
           "plan_transition", "require_within_limits", "resample", "time_along_path"]
