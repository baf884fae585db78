"""What ``rlff robot send`` takes: every file of ``rlff robot export`` that makes sense over ROS.

A generated trajectory CSV is planned, a robot trajectory JSON or CSV checked
(:func:`rlff.robot.plan.load_for_robot`); a ROS 1 bag (a file) or a ROS 2 bag (a folder) holding
one JointTrajectory on the robot's trajectory topic (its file's ``[ros] trajectory_topic``), in
the controller's joint names and convention (its file's ``[ros.joints]``), is read back into
rlff's and checked like a robot trajectory. A Comau program runs on the Comau controller, not over ROS:
refused in one line saying what to send instead.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
from rosbags.rosbag1 import ReaderError as Ros1ReaderError
from rosbags.rosbag2 import ReaderError as Ros2ReaderError

from rlff.errors import InputError
from rlff.kinds import is_ros1_bag, is_ros2_metadata
from rlff.robot.description import Robot
from rlff.robot.export import read_bag, read_planned_for, trajectory_topics
from rlff.robot.links import require_above_base
from rlff.robot.plan import GENERATED, RobotPlan, is_comau_program, load_for_robot
from rlff.robot.planned_for import (
    checked_against,
    other_convention,
    require_convention,
    require_planned_for,
)
from rlff.trajectory.check import check_start, check_trajectory
from rlff.trajectory.joint import JointTrajectory
from rlff.trajectory.limits import ClipReport
from rlff.trajectory.planner import APPROACH_SPEED, plan_transition

#: The export formats ``robot send`` reads.
SENDABLE = ("json", "csv", "ros1-bag", "ros2-bag")


def load_for_sending(
    path: str | Path,
    robot: Robot,
    period: float | None,
    clip: bool = False,
    start: np.ndarray | None = None,
    approach: bool = False,
    joints: Sequence[str] | None = None,
    bearing: float | None = None,
    approach_speed: float = APPROACH_SPEED,
) -> tuple[str, RobotPlan]:
    """The checked trajectory to send from ``path``, and the file's kind.

    Parameters
    ----------
    path : path
        A generated trajectory CSV, or an export in one of :data:`SENDABLE`.
    robot : Robot
    period, clip
        For a generated throw (see :func:`rlff.robot.plan.plan`).
    start : array of shape (J,), optional
        The arm's pose (rad, ``robot``'s joints in order): a generated throw is planned from
        there, any other trajectory must start there.
    approach : bool
        With ``start``: a trajectory that starts at rest elsewhere is sent after a planned
        approach from the arm's pose to its first point (:func:`with_approach`), instead of
        being refused.
    joints, bearing : optional
        For a generated throw: the robot joints it drives (default the one joint of
        ``[throwing]``) and the basket's bearing (deg; default the file's, else 0), see
        :func:`rlff.robot.plan.load_for_robot`.
    approach_speed : float
        Share of the joints' limits any approach from ``start`` uses
        (:data:`rlff.trajectory.planner.APPROACH_SPEED`).

    Returns
    -------
    kind : str
        ``"generated path"``, ``"robot trajectory"``, ``"ros1-bag"`` or ``"ros2-bag"``.
    plan : RobotPlan

    Raises
    ------
    InputError
        A file of another kind, a bag without exactly one trajectory, or a trajectory failing the
        motion check; one line naming the file.
    """
    path = Path(path)
    if is_ros2_metadata(path):  # a ROS 2 bag's metadata.yaml stands for its folder, as the importer takes it
        path = path.parent
    kind = _bag_kind(path)
    if kind is None:
        if is_comau_program(path):
            raise InputError(f"{path}: a Comau program, which runs on the Comau controller, not over ROS; "
                             f"send the generated trajectory CSV or an export in {', '.join(SENDABLE)}")
        # a generated throw is planned from start; a robot trajectory is read as it is (start is
        # checked below)
        kind, plan = load_for_robot(path, robot, period, clip, start, joints=joints, bearing=bearing,
                                    approach_speed=approach_speed)
        if kind == GENERATED:
            return kind, plan
        trajectory, recorded = plan.trajectory, True  # load_for_robot checked its record
    else:
        trajectory, recorded = _one_trajectory(path, robot)
    if approach and start is not None:
        trajectory = with_approach(robot, trajectory, start, period, approach_speed)
    _require_start(path, robot, trajectory, start, recorded)
    return kind, RobotPlan(trajectory, trajectory, ClipReport())


def with_approach(robot: Robot, trajectory: JointTrajectory, start: np.ndarray,
                  period: float | None, approach_speed: float = APPROACH_SPEED) -> JointTrajectory:
    """``trajectory`` after the planned motion from the arm at rest at ``start`` to its first point.

    Parameters
    ----------
    robot : Robot
    trajectory : JointTrajectory
        Starting at rest (velocities and accelerations 0 at its first point).
    start : array of shape (J,)
        The arm's pose (rad, ``robot``'s joints in order), at rest.
    period : float or None
        Sampling period (s) of the approach (the planner's default when None).
    approach_speed : float
        Share of the joints' limits the approach uses (:data:`rlff.trajectory.planner.APPROACH_SPEED`).

    Returns
    -------
    JointTrajectory
        The approach (jerk-limited, :func:`rlff.trajectory.planner.plan_transition`), then the
        trajectory shifted by the approach's duration (its release time too); ``trajectory``
        itself when the arm is already at its first point.

    Raises
    ------
    InputError
        The trajectory does not start at rest, or the approach would leave a limit.
    """
    names = trajectory.joint_names
    here = np.asarray(start, dtype=float)[[robot.index(name) for name in names]]
    if np.allclose(here, trajectory.positions[0], rtol=0.0, atol=1e-9):
        return trajectory
    moving = np.abs(trajectory.velocities[0]) > 1e-9
    accelerating = np.abs(trajectory.accelerations[0]) > 1e-9
    if moving.any() or accelerating.any():
        j = int(np.argmax(moving)) if moving.any() else int(np.argmax(accelerating))
        state = (f"{names[j]} at {trajectory.velocities[0, j]:.4g} rad/s" if moving.any()
                 else f"{names[j]} accelerating at {trajectory.accelerations[0, j]:.4g} rad/s^2")
        raise InputError(f"the trajectory does not start at rest ({state} at its first point, t = "
                         f"{trajectory.time[0]:.3f} s): an approach ends at rest, so none to a moving start is "
                         "planned; send a trajectory that starts at rest, as the exports of rlff robot export do")
    rest = np.zeros(len(names))
    move = plan_transition(here, rest, rest, trajectory.positions[0], rest, [robot.joint(n) for n in names],
                           period=period, share=approach_speed)
    shift = move.duration
    after = trajectory.time[1:] - trajectory.time[0] + shift
    release = None if trajectory.release_time is None else trajectory.release_time - trajectory.time[0] + shift
    return JointTrajectory(
        names, np.concatenate([move.time, after]),
        np.concatenate([move.positions, trajectory.positions[1:]]),
        np.concatenate([move.velocities, trajectory.velocities[1:]]),
        np.concatenate([move.accelerations, trajectory.accelerations[1:]]),
        release_time=release,
    )


def _require_start(path: Path, robot: Robot, trajectory: JointTrajectory, start: np.ndarray | None,
                   recorded: bool = True) -> None:
    """The motion check of a trajectory sent as it is: from rest (as every robot output and
    read-back, :func:`rlff.trajectory.check.check_trajectory` with ``start_at_rest``), at the
    arm's pose ``start`` if given. A refusal of a file that does not say which robot it was
    planned for (not ``recorded``) says which robot file it was checked against."""
    pose = start
    names, joints = trajectory.joint_names, robot.ros.joints
    if start is not None:
        # said as the approach line says it: a joint [ros.joints] maps in the controller's name and
        # counting (as its bag and the arm's joint states have it), rlff's name beside it
        start = np.asarray(start, dtype=float)[[robot.index(name) for name in names]]
        try:
            check_start(joints.to_controller(trajectory), joints.positions_to_controller(names, start),
                        labels=[joints.label(name) for name in names])
        except InputError as exc:
            raise type(exc)(f"{path}: {exc}; send with approach (--approach) to move there first, or send the generated "
                            "trajectory CSV to have the motion planned from the arm's pose") from None
    try:  # a start not at rest says what to do; --approach would not change it (an approach ends at rest)
        check_trajectory(trajectory, robot.joints, start=start, start_at_rest=True)
        require_above_base(robot, trajectory, "the trajectory", held=pose)  # the joints it leaves out stay put
    except InputError as exc:
        raise type(exc)(f"{path}: {exc}{'' if recorded else checked_against(robot)}") from None


def _bag_kind(path: Path) -> str | None:
    if path.is_dir():
        if not (path / "metadata.yaml").is_file():
            raise InputError(f"{path}: a folder, but not a ROS 2 bag (no metadata.yaml)")
        return "ros2-bag"
    return "ros1-bag" if is_ros1_bag(path) else None


def _one_trajectory(path: Path, robot: Robot) -> tuple[JointTrajectory, bool]:
    """The one trajectory of the bag ``path`` on ``robot``'s trajectory topic, in rlff's joints and
    convention, and whether the bag says it was planned for ``robot`` (False: it does not say,
    :func:`rlff.robot.planned_for.require_planned_for`)."""
    topic = robot.ros.trajectory_topic
    try:
        trajectories = read_bag(path, topic)
    except (Ros1ReaderError, Ros2ReaderError) as exc:
        raise InputError(f"{path}: not a readable bag ({exc})") from None
    if not trajectories:
        others = [name for name in trajectory_topics(path) if name != topic]
        if others:
            raise InputError(f"{path}: holds no trajectory on {topic} ({robot.ros_origin('trajectory_topic')}), "
                             f"but JointTrajectory messages on {', '.join(others)}: export it again with this "
                             "robot file, or send it with the robot file it was exported with")
    if len(trajectories) != 1:
        raise InputError(f"{path}: holds {len(trajectories)} trajectories on {topic}; send a bag with one")
    record = read_planned_for(path, topic)
    recorded = require_planned_for(path, record, robot)  # before its joints: says whose
    try:  # the bag is the controller's (the robot file's [ros.joints]); rlff checks and plans in its own
        trajectory = robot.ros.joints.from_controller(trajectories[0])
    except InputError as exc:  # other controller names: said by name, before the map's digest
        raise InputError(f"{path}: {exc}; export it again with this robot file, or send it with the robot file it "
                         "was exported with") from None
    unknown = [name for name in trajectory.joint_names if name not in robot.joint_names]
    if unknown:  # the bag's controller names are none this file maps: said with the remedy
        other = other_convention(record, robot) is not None
        expected = robot.ros.joints.controller_names(robot.joint_names)
        raise InputError(f"{path}: holds joints {', '.join(unknown)}, which {robot.source} does not have (its "
                         f"controller's joint names: {', '.join(expected)})"
                         f"{': the bag was written with another [ros.joints] map' if other else ''}; export it again "
                         "with this robot file, or send it with the robot file it was exported with")
    require_convention(path, record, robot)  # the same names, but the same offsets and signs?
    return trajectory, recorded
