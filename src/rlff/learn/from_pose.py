"""The loop's throw planned from where the arm is: what an executor sends to an arm.

:func:`rlff.learn.learn` plans every attempt's throw from rest at the throw's own first pose (the
plan it simulates, logs and replays). A real arm is elsewhere: wherever the last throw braked it,
1.0-1.2 rad away on the Comau's joint_2 from the second attempt on. Sent as it is, such a
trajectory starts with a jump, which a controller either refuses (ros2_control's
joint_trajectory_controller, rlff's own server) or follows by jerking the arm there.
:func:`plan_from_pose` puts an approach from the arm's pose in front of the same throw; the ROS
executors (:class:`rlff.learn.robot.RobotExecutor`) send what it returns, and an executor of
one's own should too.
"""

from __future__ import annotations

import numpy as np

from rlff.errors import InputError
from rlff.trajectory.joint import JointTrajectory
from rlff.trajectory.planner import APPROACH_SPEED, plan_throw

#: Sampling period (s) of a throw planned for a live arm: its controller interpolates between
#: the points, so 10 ms (``rlff robot send``'s default; files are sampled at 2 ms).
LIVE_PERIOD = 0.01


def plan_from_pose(trajectory: JointTrajectory, robot, pose: np.ndarray, *, approach_speed: float = APPROACH_SPEED,
                   period: float = LIVE_PERIOD) -> JointTrajectory:
    """``trajectory``, a throw the loop handed an executor, planned to start where the arm is.

    The approach from ``pose`` to the throw's first pose at ``approach_speed`` of the joints'
    limits, then the same throw: the same start, the same release (position and velocity, where
    the ball's flight is decided) and braking to rest, planned by
    :func:`rlff.trajectory.planner.plan_throw` as the loop planned it, then checked as every goal
    is (:func:`rlff.robot.goal.check_goal` from ``pose``, and no link below the base's plane).

    Parameters
    ----------
    trajectory : JointTrajectory
        The planned throw :func:`rlff.learn.learn` hands its executor: from rest at its first
        pose, through its release (``release_time``) to rest.
    robot : str or Robot
        The robot the loop plans for: ``learn``'s ``robot`` (a name, a robot file or a
        description).
    pose : array of shape (J,)
        Where the arm is, at rest (rad): every joint of ``robot``, in its order (as its joint
        states give them).
    approach_speed : float
        Share of the joints' velocity, acceleration and jerk limits the approach uses (0 < s <= 1).
    period : float
        Sampling period (s) of the result: :data:`LIVE_PERIOD` for a goal a controller
        interpolates; the loop's own plans are sampled at 2 ms.

    Returns
    -------
    JointTrajectory
        ``trajectory``'s joints from ``pose`` at rest to rest after the release; its
        ``release_time`` is the release's time (later than ``trajectory``'s by the approach).

    Raises
    ------
    InputError
        A trajectory that is not a planned throw (no ``release_time``, or one that is not the
        release: not a sample, the arm at rest or slowing down there, as
        :func:`rlff.robot.export.require_release` refuses a file's), a pose that is not one angle
        (rad) per joint of ``robot`` or has one beyond its limits (every joint, those the throw
        leaves out too), or a motion that fails the check from ``pose`` (an approach that passes
        below the base's plane), naming the joint and the numbers.
    """
    from rlff.robot.controller import in_controller_words
    from rlff.robot.description import Robot, load_robot
    from rlff.robot.export import require_release
    from rlff.robot.goal import check_goal
    from rlff.robot.links import require_above_base
    from rlff.robot.send import goal_start

    model = robot if isinstance(robot, Robot) else load_robot(robot)
    if trajectory.release_time is None:
        raise InputError("plan_from_pose takes the planned throw learn hands its executor (release_time set); this "
                         "trajectory has no release")
    pose = np.asarray(pose, dtype=float)
    if pose.shape != (len(model.joints),) or not np.all(np.isfinite(pose)):
        raise InputError(f"the arm's pose must be {len(model.joints)} finite angles (rad), one per joint of "
                         f"{model.name} ({', '.join(model.joint_names)}), got {pose.tolist()}")
    for joint, value in zip(model.joints, pose, strict=True):  # the joints the throw leaves out too
        for beyond, side, limit in ((value > joint.upper, "upper", joint.upper),
                                    (value < joint.lower, "lower", joint.lower)):
            if beyond:
                raise InputError(in_controller_words(model, (
                    f"planned from the arm's pose: {joint.name} starts at {value:.6g} rad, already beyond its "
                    f"{side} limit {limit:.6g} rad in the robot file: move the arm inside its limits, or check the "
                    "robot file's limits against the arm's")))
    trajectory = require_release("the throw given to plan_from_pose", trajectory)  # released at its fastest, at a sample
    release = int(np.argmin(np.abs(trajectory.time - trajectory.release_time)))
    throw = JointTrajectory(trajectory.joint_names, trajectory.time[:release + 1],
                            trajectory.positions[:release + 1], trajectory.velocities[:release + 1])
    start = goal_start(model, trajectory, pose)
    try:
        planned = plan_throw(throw, model.joints, start=start, period=period, approach_speed=approach_speed)
        check_goal(model, planned, start)
        require_above_base(model, planned, "the throw", held=pose)
    except InputError as exc:  # worded as the controller's refusals are (a [ros.joints] map's joints both ways)
        raise type(exc)(in_controller_words(model, f"planned from the arm's pose: {exc}")) from None
    return planned
