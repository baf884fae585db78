"""What ``rlff robot send`` takes: every file of ``rlff robot export`` that makes sense over ROS.

A generated trajectory CSV is planned, a robot trajectory JSON or CSV checked
(:func:`rlff.robot.plan.load_for_robot`); a ROS 1 bag (a file) or a ROS 2 bag (a folder) holding
one JointTrajectory on the trajectory topic is checked like a robot trajectory. A Comau program
runs on the Comau controller, not over ROS: refused in one line saying what to send instead.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from rosbags.rosbag1 import ReaderError as Ros1ReaderError
from rosbags.rosbag2 import ReaderError as Ros2ReaderError

from rlff.errors import InputError
from rlff.robot.comau import HEADER as COMAU_HEADER
from rlff.robot.description import Robot
from rlff.robot.export import TRAJECTORY_TOPIC, read_bag
from rlff.robot.plan import GENERATED, RobotPlan, load_for_robot
from rlff.trajectory.check import check_trajectory
from rlff.trajectory.joint import JointTrajectory
from rlff.trajectory.limits import ClipReport

#: The export formats ``robot send`` reads.
SENDABLE = ("json", "csv", "ros1-bag", "ros2-bag")
_ROS1_BAG_MAGIC = b"#ROSBAG V2.0"


def load_for_sending(
    path: str | Path,
    robot: Robot,
    period: float | None,
    clip: bool = False,
    start: np.ndarray | None = None,
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
    kind = _bag_kind(path)
    if kind is None:
        if _is_comau_program(path):
            raise InputError(f"{path}: a Comau program, which runs on the Comau controller, not over ROS; "
                             f"send the generated trajectory CSV or an export in {', '.join(SENDABLE)}")
        kind, plan = load_for_robot(path, robot, period, clip)
        if kind == GENERATED:
            return kind, plan if start is None else load_for_robot(path, robot, period, clip, start)[1]
        trajectory = plan.trajectory
    else:
        trajectory = _one_trajectory(path)
    _require_start(path, robot, trajectory, start)
    return kind, RobotPlan(trajectory, trajectory, ClipReport())


def _require_start(path: Path, robot: Robot, trajectory: JointTrajectory, start: np.ndarray | None) -> None:
    """The motion check of a trajectory sent as it is, from the arm's pose ``start`` if given."""
    if start is not None:
        start = np.asarray(start, dtype=float)[[robot.index(name) for name in trajectory.joint_names]]
    try:
        check_trajectory(trajectory, robot.joints, start=start)
    except InputError as exc:
        hint = ("" if start is None else
                "; send the generated trajectory CSV to have the motion planned from the arm's pose")
        raise type(exc)(f"{path}: {exc}{hint}") from None


def _bag_kind(path: Path) -> str | None:
    if path.is_dir():
        if not (path / "metadata.yaml").is_file():
            raise InputError(f"{path}: a folder, but not a ROS 2 bag (no metadata.yaml)")
        return "ros2-bag"
    if path.is_file():
        with open(path, "rb") as stream:
            if stream.read(len(_ROS1_BAG_MAGIC)) == _ROS1_BAG_MAGIC:
                return "ros1-bag"
    return None


def _is_comau_program(path: Path) -> bool:
    if not path.is_file():
        return False
    with open(path, "rb") as stream:
        return stream.read(len(COMAU_HEADER)).decode("utf-8", errors="replace") == COMAU_HEADER


def _one_trajectory(path: Path) -> JointTrajectory:
    try:
        trajectories = read_bag(path)
    except (Ros1ReaderError, Ros2ReaderError) as exc:
        raise InputError(f"{path}: not a readable bag ({exc})") from None
    if len(trajectories) != 1:
        raise InputError(f"{path}: holds {len(trajectories)} trajectories on {TRAJECTORY_TOPIC}; "
                         "send a bag with one")
    return trajectories[0]
