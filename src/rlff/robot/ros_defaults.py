"""What a robot file without a ``[ros]`` table leaves to rlff's defaults, said before a bag is
written or a live node talks to the arm's controller.

A robot file may leave ``[ros]`` out (docs/robot.md): its bags, goals and server then use the
names of the thesis' Comau driver (:class:`rlff.robot.description.RosNames`' defaults) and the
file's own joint names. For the built-in Comau those are right; for another arm they are a
guess that only ``rlff robot show`` had said (a tester's UR5e file exported a bag on
``/comau/joint_trajectory`` without a word). A name the controller does not have moves nothing
(no server answers at the action, a controller refuses joints it does not know), so the
commands say it once rather than refuse: a rehearsal against ``rlff robot serve`` of the same
file meets on the same defaults, as the robot files of the tests do.
"""

from __future__ import annotations

from collections.abc import Sequence

from rlff.robot.description import Robot, RosNames

#: The ``[ros]`` keys, as the table names them.
ROS_KEYS = ("action", "joint_states", "trajectory_topic")


def leaves_ros_to_defaults(robot: Robot) -> bool:
    """Whether ``robot`` names nothing of its controller: its file has no ``[ros]`` table (nor a
    :class:`RosNames` given in code), so every name is rlff's default and the joints are the file's."""
    names = robot.ros
    return (not names.stated and not names.joints.joints
            and all(getattr(names, key) == getattr(RosNames, key) for key in ROS_KEYS))


def ros_defaults_note(robot: Robot, doing: str, keys: Sequence[str]) -> str | None:
    """One line saying that ``robot``'s file has no ``[ros]`` table and which names ``doing``
    (e.g. ``"the bag is written"``) therefore uses: the ``keys`` of :data:`ROS_KEYS` it uses, at
    rlff's defaults, and the file's joint names; how to give the controller's own. None when the
    file names its controller (or ``robot`` is the built-in Comau, whose file states the defaults)."""
    if not leaves_ros_to_defaults(robot):
        return None
    used = ", ".join(f"{key} {getattr(robot.ros, key)}" for key in keys)
    return (f"{robot.source} has no [ros] table: {doing} with rlff's defaults, the Comau driver's {used}, and "
            f"the robot file's joint names ({', '.join(robot.joint_names)}); if your arm's controller has other "
            "names, give them in a [ros] table (action, joint_states, trajectory_topic; a [ros.joints.<joint>] "
            "table of name, offset and sign for each joint it names or counts otherwise; docs/robot.md)")


def bag_defaults_note(robot: Robot, fmt: str) -> str | None:
    """:func:`ros_defaults_note` of a file written in format ``fmt`` (``ros1-bag``, ``ros2-bag``,
    ``json``, ...) for ``robot``: a bag carries the ``trajectory_topic`` it is written on, the
    other formats no ROS name (None for them), as ``rlff robot export`` and ``rlff learn --out``
    say it."""
    if not fmt.endswith("-bag"):
        return None
    return ros_defaults_note(robot, "the bag is written", ("trajectory_topic",))
