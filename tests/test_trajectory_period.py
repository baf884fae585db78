"""A throw refused at a coarse controller period that plans at a fine one blames the period."""

from __future__ import annotations

import numpy as np
import pytest

from rlff.robot.description import load_robot
from rlff.robot.mapping import RobotMapping
from rlff.trajectory.check import MotionLimitError
from rlff.trajectory.joint import JointTrajectory
from rlff.trajectory.planner import plan_throw

ROBOT = load_robot()
MAPPING = RobotMapping.for_robot(ROBOT)


def throw(first: float, release: float, speed: float) -> JointTrajectory:
    """joint_2's throw from ``first`` to ``release`` (rad), released at ``speed`` (rad/s)."""
    positions = np.tile(MAPPING.pose(), (2, 1))
    positions[:, 1] = [first, release]
    velocities = np.zeros_like(positions)
    velocities[1, 1] = speed
    return JointTrajectory(ROBOT.joint_names, [0.0, 1.0], positions, velocities)


@pytest.mark.parametrize(("path", "phase"), [((-1.2159, -0.6, 2.0), "the throw (start to release)"),
                                             ((-0.5, 1.5, 2.0), "no room to brake after the release")])
def test_a_throw_that_plans_at_a_fine_period_is_refused_for_its_coarse_one(path, phase):
    """At --period 0.5 the wind-up refusal said "a slower release, or a throw further from that
    limit", though the same throw plans at 0.002-0.1 s."""
    for period in (0.002, 0.01, 0.1):
        plan_throw(throw(*path), ROBOT.joints, period=period)
    with pytest.raises(MotionLimitError) as refused:
        plan_throw(throw(*path), ROBOT.joints, period=0.5)
    said = str(refused.value)
    assert said.startswith(f"{phase}: joint_2 would reach ")
    assert said.endswith("the 0.5 s controller period leaves no room, not the throw: at that period the profile "
                         "changes its acceleration more slowly (its jerk planned lower, so the quintic between samples "
                         "that far apart stays within the limits) and lasts whole periods; the same throw plans at "
                         "0.002 s: give a shorter --period (0.002 for a file, 0.01 for a live goal)"), said
    assert "a slower release" not in said


def test_a_throw_that_fits_at_no_period_blames_the_throw():
    with pytest.raises(MotionLimitError, match=r"no room to brake after the release: .*: a slower release, or one "
                                               r"further from that limit"):
        plan_throw(throw(1.5, 2.6, 2.5), ROBOT.joints, period=0.5)
