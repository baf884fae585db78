"""The Comau text program of thesis 4.4: the trajectory as rows for the robot's main program.

The controller software of the thesis could not take a velocity per point, so its modified main
program reads, for every point, one row of six joint values in degrees behind a ``coord_type``
of ``"-j"`` (joint coordinates)::

    coord_type = "-j"
    (coord_type,'0','-65','-25','0','90','0')
    (coord_type,'0','-65','-37.2006','0','90','12.37')

Each slot k (1..6) holds joint k of the robot at the start pose (the driven joint's start being
its first point), except two: the position slot (3 in the thesis) carries the driven joint's
position at the point, and the velocity slot (6, a joint the main program holds at a constant
position) carries its speed as a percentage of the driven joint's maximum speed. The slots are
the ``[comau_program]`` table of the robot file. The program carries one joint's motion: a
trajectory that moves another joint is refused. The last row is the arm at rest (speed 0), as
every exported trajectory ends at rest. Note that the thesis numbers the driven joint
"joint 2" while it sits in slot 3: the joint whose own slot is taken (joint_3 here) stays where
the main program placed the robot before the throw.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from rlff.errors import InputError
from rlff.robot.mapping import RobotMapping
from rlff.trajectory.joint import JointTrajectory

HEADER = 'coord_type = "-j"'


def _slot(mapping: RobotMapping, key: str, default: int) -> int:
    value = mapping.robot.comau_program.get(key, default)
    if isinstance(value, bool) or not isinstance(value, int) or not 1 <= value <= len(mapping.robot.joints):
        raise InputError(f"{mapping.robot.source}: [comau_program] {key} must be a slot number "
                         f"1..{len(mapping.robot.joints)}, got {value!r}")
    return value


def _number(value: float) -> str:
    """Degrees as the thesis writes them: up to 4 decimals, no trailing zeros, no "-0"."""
    text = f"{value:.4f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def comau_rows(traj: JointTrajectory, mapping: RobotMapping) -> np.ndarray:
    """The program's values, shape (T, 6): degrees, and the speed slot in % of the joint's maximum.

    Parameters
    ----------
    traj : JointTrajectory
        A trajectory of ``mapping.robot`` (every joint, any order).
    mapping : RobotMapping
        Gives the driven joint and the start pose of the others.
    """
    robot = mapping.robot
    if len(robot.joints) != 6:
        raise InputError(f"the Comau program has six slots; robot {robot.name} has {len(robot.joints)} joints")
    position_slot = _slot(mapping, "position_slot", 3)
    velocity_slot = _slot(mapping, "velocity_slot", 6)
    if position_slot == velocity_slot:
        raise InputError(f"{robot.source}: [comau_program] position_slot and velocity_slot are both {position_slot}")
    driven = traj.joint_index(mapping.joint)
    position = traj.positions[:, driven]
    held = [name for index, name in enumerate(traj.joint_names)
            if name != mapping.joint and np.ptp(traj.positions[:, index]) > 1e-9]
    if held:
        raise InputError(f"the Comau program carries the motion of {mapping.joint} only; this "
                         f"trajectory also moves {', '.join(held)}")
    pose = [traj.positions[0, traj.joint_index(name)] if name in traj.joint_names
            else mapping.start_pose.get(name, position[0]) for name in robot.joint_names]
    rows = np.tile(np.degrees(pose), (len(traj), 1))
    rows[:, position_slot - 1] = np.degrees(position)
    rows[:, velocity_slot - 1] = 100.0 * np.abs(traj.velocities[:, driven]) / robot.joint(mapping.joint).max_velocity
    return rows


def write_comau_program(traj: JointTrajectory, mapping: RobotMapping, path: Path) -> None:
    """Write the text program: the ``coord_type`` header, then one row per point of ``traj``."""
    lines = [HEADER]
    for row in comau_rows(traj, mapping):
        lines.append("(coord_type," + ",".join(f"'{_number(v)}'" for v in row) + ")")
    Path(path).write_text("\n".join(lines) + "\n", encoding="utf-8")
