"""Learning from failure: the closed loop, its update strategies, the attempts log, baselines.

A method of one's own subclasses :class:`Method`: it sees the :class:`Problem` and proposes
each throw as a :class:`Proposal` (docs/learn.md, "Writing your own method")."""

from rlff.learn.attempt import Attempt
from rlff.learn.from_pose import plan_from_pose
from rlff.learn.loop import METHODS, LearningResult, learn
from rlff.learn.method import Method, Problem, Proposal, scale_speed
from rlff.learn.strategies import STRATEGIES

__all__ = ["METHODS", "STRATEGIES", "Attempt", "LearningResult", "Method", "Problem", "Proposal", "learn",
           "plan_from_pose", "scale_speed"]
