"""The trajectory a simulated throw executes, from a file.

Two kinds of files: a generated human path (CSV with ``angle``, ``velocity`` [, ``time``], as
the model writes it), mapped to the robot with the robot file's ``[throwing]`` mapping and
planned like every robot output (approach, the throw to its release, braking to rest:
:func:`rlff.robot.plan.plan`); or a robot joint trajectory as ``rlff robot export`` writes it
(JSON, or CSV with ``time`` and ``<joint>_position`` columns), taken as it is. Both pass the one
motion check (:func:`rlff.trajectory.check.check_trajectory`) before MuJoCo executes them.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from rlff.robot.description import Robot
from rlff.robot.plan import GENERATED, load_for_robot
from rlff.trajectory.joint import JointTrajectory

#: Controller period (s) a generated path is planned at for the simulation: its servo step.
SIM_PERIOD = 0.002


@dataclass(frozen=True)
class LoadedThrow:
    """A trajectory ready to simulate, what kind of file it came from and what planning did."""

    trajectory: JointTrajectory
    kind: str  # "generated path" or "robot trajectory"
    summary: str


def load_throw(path: str | Path, robot: Robot, clip: bool = False) -> LoadedThrow:
    """Read ``path`` and turn it into ``robot``'s checked joint trajectory.

    Parameters
    ----------
    path : str or Path
        Generated path CSV, robot trajectory CSV, or robot trajectory JSON.
    robot : Robot
        The robot; its ``[throwing]`` table maps a generated path.
    clip : bool
        Clip a mapped path into the joint limits (and say what changed) instead of refusing it.

    Raises
    ------
    InputError
        Unreadable file, missing columns, a value beyond a joint limit (without ``clip``), or a
        trajectory that fails the motion check.
    """
    kind, plan = load_for_robot(path, robot, SIM_PERIOD, clip)
    trajectory = plan.trajectory
    if kind == GENERATED:
        return LoadedThrow(trajectory, kind, f"mapped to {robot.throwing.get('joint')} of {robot.name}: "
                                             f"{plan.summary()}")
    return LoadedThrow(trajectory, kind, f"{len(trajectory)} points of {len(trajectory.joint_names)} joints")
