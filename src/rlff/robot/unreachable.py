"""What the ROS 1 and ROS 2 clients say when the arm's controller is not where the robot file's
``[ros]`` table says: nothing on its ``joint_states``, no action server at its ``action``.

Nothing on the joint states is told apart by what the ROS graph knows of the topic: no publisher
of it at all (the driver is not running, or publishes elsewhere), or publishers that sent nothing
in time (a driver that publishes no state; over ROS 2 also one whose QoS the subscription does
not take, or one discovered late). ROS 2's discovery counts against the wait: it cannot tell a
publisher not yet discovered from none, and a timeout must bound the wait for a driver that is
not there; so a wait over ROS 2 shorter than rlff's default
(:data:`rlff.robot.send.CONNECT_TIMEOUT`) is said to be possibly short.

A name copied from a topic list is the likeliest slip for the action: ``rostopic list`` shows an
action as its topics (``/arm_controller/follow_joint_trajectory/goal``, ``.../status``, ...),
``ros2 topic list`` as its hidden ones (``.../_action/feedback``, ``.../_action/status``). The
action is the part before them, and the message says so.
"""

from __future__ import annotations

from rlff.robot.description import Robot
from rlff.robot.send import CONNECT_TIMEOUT

#: The last segment of each topic of a ROS 1 action (actionlib's).
ROS1_ACTION_TOPICS = ("goal", "cancel", "status", "feedback", "result")
#: Where a ROS 2 action keeps its topics and services, after its name.
ROS2_ACTION_PART = "/_action/"


def action_topic_hint(action: str) -> str:
    """For the error of no action server at ``action``: when ``action`` names one of an action's
    topics (see the module), which name the action has, as the start of a sentence that goes on
    with the other causes (``the action is the part before /goal, /arm_controller/...: name that
    in [ros] action; or ``); empty otherwise."""
    if ROS2_ACTION_PART in action:
        name, _, rest = action.partition(ROS2_ACTION_PART)
        part = ROS2_ACTION_PART + rest
    else:
        name, _, last = action.rpartition("/")
        part = f"/{last}"
        if last not in ROS1_ACTION_TOPICS or not name:
            return ""
    return f"the action is the part before {part}, {name} ({part} names one of its topics): name that in [ros] action; or "


def no_joint_states(robot: Robot, waited: float, why: str) -> str:
    """The error for no message on ``robot``'s joint states topic within ``waited`` s, ``why`` (the
    transport's words for what its graph knows of the topic) after what it means."""
    return (f"nothing on {robot.ros.joint_states} within {waited:g} s ({robot.ros_origin('joint_states')}): the "
            f"arm's pose is unknown; {why}")


def ros2_no_joint_states(robot: Robot, waited: float, publishers: int) -> str:
    """:func:`no_joint_states` over ROS 2, with the ``publishers`` of the topic its discovery found."""
    topic = robot.ros.joint_states
    if publishers:
        found = ("a publisher of it was discovered, and nothing came from it" if publishers == 1 else
                 f"{publishers} publishers of it were discovered, and nothing came from them")
        why = (f"{found}: does the arm's driver publish its state, with a QoS a reliable subscription takes? "
               f"(`ros2 topic hz {topic}`, `ros2 topic info -v {topic}`)")
    else:
        why = ("no publisher of it was discovered: is the arm's driver, or `rlff robot serve --ros 2`, running, with "
               "the same ROS_DOMAIN_ID, or does it publish on another topic? (`ros2 topic find "
               "sensor_msgs/msg/JointState`)")
    if waited < CONNECT_TIMEOUT:  # 1.5 to 2 s failed on a loaded 2-core machine, where discovery took 1.6 to 2.8 s
        why += (f"; discovery alone can take seconds on a loaded machine: if the driver publishes, give a timeout (--timeout) "
                f"above {waited:g} s, or leave it out ({CONNECT_TIMEOUT:g} s)")
    return no_joint_states(robot, waited, why)


def ros1_no_joint_states(robot: Robot, waited: float, publishers: int | None) -> str:
    """:func:`no_joint_states` over ROS 1, with the ``publishers`` of the topic the master lists
    (None: the master could not be asked)."""
    topic = robot.ros.joint_states
    if publishers:
        listed = ("the master lists a publisher of it, and nothing came from it" if publishers == 1 else
                  f"the master lists {publishers} publishers of it, and nothing came from them")
        why = (f"{listed}: does the arm's driver publish its state, and can this host reach the driver's (ROS_IP "
               f"or ROS_HOSTNAME on both)? (`rostopic hz {topic}`, `rostopic info {topic}`)")
    else:
        listed = "no node publishes it (the master lists none): " if publishers == 0 else ""
        why = (f"{listed}is the arm's driver, or `rlff robot serve`, running, or does it publish on another "
               "topic? (`rostopic find sensor_msgs/JointState`)")
    return no_joint_states(robot, waited, why)
