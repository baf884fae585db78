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
every exported trajectory ends at rest. The program holds no time, so its rows follow one
controller period apart (:data:`MAX_ROW_STEP`). Note that the thesis numbers the driven joint
"joint 2" while it sits in slot 3: the joint whose own slot is taken (joint_3 here) stays where
the main program placed the robot before the throw.

A whole-arm throw (:class:`rlff.robot.mapping.ArmMapping`) moves several joints, so every joint
keeps its own slot (slot k holds joint k, as a plain ``"-j"`` position does: joint_2, joint_3 and
joint_5 carry the throw, joint_1 the turn to the bearing), and the velocity slot carries the
coordinated motion's speed: the percentage of the joint that moves fastest against its maximum
(the controller's joint interpolation moves the others so that all arrive together). The joint
of the velocity slot must not move.
"""

from __future__ import annotations

from collections.abc import Collection
from pathlib import Path

import numpy as np

from rlff.errors import InputError
from rlff.fileio import write_text
from rlff.robot.mapping import ArmMapping, RobotMapping
from rlff.trajectory.joint import JointTrajectory
from rlff.trajectory.resample import CONTROLLER_PERIODS

HEADER = 'coord_type = "-j"'


def joints_left_out(mapping: RobotMapping | ArmMapping) -> str | None:
    """What the program does not carry, for the operator (one line), or None: the joints whose own
    slot holds the driven joint's position or the speed stay wherever the main program placed
    the arm, not at the robot file's start pose."""
    robot = mapping.robot
    if len(robot.joints) != 6:
        return None
    velocity_slot = _slot(mapping, "velocity_slot", 6)
    slots = {velocity_slot: "its speed"}
    if not isinstance(mapping, ArmMapping):
        slots[_slot(mapping, "position_slot", 3)] = f"{mapping.joint}'s position"
    taken = [(slot, robot.joint_names[slot - 1]) for slot in sorted(slots)
             if isinstance(mapping, ArmMapping) or robot.joint_names[slot - 1] != mapping.joint]
    if not taken:
        return None
    pose = mapping.start_pose
    left = " and ".join(f"{name}" + (f" (start pose {np.degrees(pose[name]):.4g} deg)" if name in pose else "")
                        for _, name in taken)
    carried = " and ".join(f"slot {slot} {slots[slot]}" for slot in sorted(slots))
    one = len(taken) == 1
    return (f"the Comau program holds in {carried}: {left} {'is' if one else 'are'} in no slot and "
            f"stay{'s' if one else ''} where the main program placed the arm")


def _slot(mapping: RobotMapping | ArmMapping, key: str, default: int) -> int:
    value = mapping.robot.comau_program.get(key, default)
    if isinstance(value, bool) or not isinstance(value, int) or not 1 <= value <= len(mapping.robot.joints):
        raise InputError(f"{mapping.robot.source}: [comau_program] {key} must be a slot number "
                         f"1..{len(mapping.robot.joints)}, got {value!r}")
    return value


def program_slots(mapping: RobotMapping | ArmMapping, moved: Collection[str]) -> tuple[int, int | None]:
    """The program's velocity slot and, for a one-joint throw, its position slot (None for a
    whole-arm throw: every joint in its own), checked for a throw of ``mapping`` that moves the
    joints ``moved`` (names): what :func:`comau_rows` refuses before it writes a row, and what
    ``rlff learn --out`` checks before its first throw, ``moved`` the joints the run drives (it
    had learned to the end on a live arm, then written nothing).

    Raises
    ------
    InputError
        A robot not of six joints, a ``[comau_program]`` slot outside them, a one-joint throw's
        position and velocity slots the same, a whole-arm throw's velocity slot on a joint of
        ``moved``.
    """
    robot = mapping.robot
    if len(robot.joints) != 6:
        raise InputError(f"the Comau program has six slots; robot {robot.name} has {len(robot.joints)} joints")
    velocity_slot = _slot(mapping, "velocity_slot", 6)
    if isinstance(mapping, ArmMapping):
        held = robot.joint_names[velocity_slot - 1]
        if held in moved:
            raise InputError(f"the Comau program's velocity slot {velocity_slot} is {held}'s, and this trajectory "
                             f"moves {held}; give [comau_program] velocity_slot a joint the throw does not move")
        return velocity_slot, None
    position_slot = _slot(mapping, "position_slot", 3)
    if position_slot == velocity_slot:
        raise InputError(f"{robot.source}: [comau_program] position_slot and velocity_slot are both {position_slot}")
    return velocity_slot, position_slot


def _number(value: float) -> str:
    """Degrees as the thesis writes them: up to 4 decimals, no trailing zeros, no "-0"."""
    text = f"{value:.4f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def comau_rows(traj: JointTrajectory, mapping: RobotMapping | ArmMapping) -> np.ndarray:
    """The program's values, shape (T, 6): degrees, and the speed slot in % of the joint's maximum.

    Parameters
    ----------
    traj : JointTrajectory
        A trajectory of ``mapping.robot`` (every joint, any order).
    mapping : RobotMapping or ArmMapping
        Gives the driven joint and the start pose of the others (one joint, the thesis' layout),
        or the robot of a whole-arm throw (every joint in its own slot).
    """
    robot = mapping.robot
    moved = [name for index, name in enumerate(traj.joint_names) if np.ptp(traj.positions[:, index]) > 1e-9]
    velocity_slot, position_slot = program_slots(mapping, moved)
    if position_slot is None:
        return _whole_arm_rows(traj, mapping, velocity_slot)
    driven = traj.joint_index(mapping.joint)
    position = traj.positions[:, driven]
    held = [name for name in moved if name != mapping.joint]
    if held:
        raise InputError(f"the Comau program carries the motion of {mapping.joint} only; this "
                         f"trajectory also moves {', '.join(held)}: a whole-arm throw's program needs "
                         "the joints it drives (joints, --joints, e.g. joint_2,joint_3)")
    pose = [traj.positions[0, traj.joint_index(name)] if name in traj.joint_names
            else mapping.start_pose.get(name, position[0]) for name in robot.joint_names]
    rows = np.tile(np.degrees(pose), (len(traj), 1))
    rows[:, position_slot - 1] = np.degrees(position)
    rows[:, velocity_slot - 1] = 100.0 * np.abs(traj.velocities[:, driven]) / robot.joint(mapping.joint).max_velocity
    return rows


def _whole_arm_rows(traj: JointTrajectory, mapping: ArmMapping, velocity_slot: int) -> np.ndarray:
    """The rows of a whole-arm throw, shape (T, 6): every joint's position (deg) in its own slot,
    the fastest joint's speed (% of its maximum) in ``velocity_slot``, a slot of a joint the throw
    does not move (:func:`program_slots`)."""
    robot = mapping.robot
    traj = traj.select(robot.joint_names)
    rows = np.degrees(traj.positions)
    _, _, speed_limits = robot.limits()
    share = np.abs(traj.velocities) / speed_limits
    share[:, velocity_slot - 1] = 0.0
    rows[:, velocity_slot - 1] = 100.0 * share.max(axis=1)
    return rows


#: The longest step (s) between two points a program is written for: the longest controller period
#: rlff plans at (:data:`rlff.trajectory.resample.CONTROLLER_PERIODS`). The program holds no time:
#: the controller moves from row to row at each row's speed, so a row's speed stands for the
#: motion to the next only over a controller period. A tester's two points at rest 10 s and 2 rad
#: apart became two rows at speed 0, a move no controller times.
MAX_ROW_STEP = max(CONTROLLER_PERIODS)


def require_row_steps(traj: JointTrajectory, path: Path) -> None:
    """Refuse (:class:`InputError` naming ``path``, the points and what to do) a trajectory whose
    points are more than :data:`MAX_ROW_STEP` apart: its program's rows would not time the motion.
    A trajectory rlff plans is sampled at its ``--period``, every step that long or shorter."""
    steps = np.diff(traj.time)
    if steps.size == 0 or steps.max() <= MAX_ROW_STEP * (1 + 1e-9):
        return
    i = int(np.argmax(steps > MAX_ROW_STEP * (1 + 1e-9)))
    longer = int(np.count_nonzero(steps > MAX_ROW_STEP * (1 + 1e-9)))
    raise InputError(
        f"{path}: not written: points {i} and {i + 1} are {steps[i]:.6g} s apart (t = {traj.time[i]:.6g} to "
        f"{traj.time[i + 1]:.6g} s; {longer} of {steps.size} steps longer than {MAX_ROW_STEP:g} s): the Comau program "
        "holds no time, the controller moves from row to row at each row's speed, so its rows must follow a "
        f"controller period apart, {MAX_ROW_STEP:g} s or less; export the generated path or attempts log (the one a "
        f"robot trajectory was planned from) as a Comau program with a period (--period) of {MAX_ROW_STEP:g} s or less (0.002 "
        "by default)")


def write_comau_program(traj: JointTrajectory, mapping: RobotMapping | ArmMapping, path: Path) -> None:
    """Write the text program: the ``coord_type`` header, then one row per point of ``traj``."""
    lines = [HEADER]
    for row in comau_rows(traj, mapping):
        lines.append("(coord_type," + ",".join(f"'{_number(v)}'" for v in row) + ")")
    write_text(path, "\n".join(lines) + "\n")
