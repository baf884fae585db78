"""Learning from failure: the closed loop, its update strategies, the attempts log, baselines."""

from rlff.learn.attempt import Attempt
from rlff.learn.from_pose import plan_from_pose
from rlff.learn.loop import METHODS, LearningResult, learn
from rlff.learn.strategies import STRATEGIES

__all__ = ["METHODS", "STRATEGIES", "Attempt", "LearningResult", "learn", "plan_from_pose"]
