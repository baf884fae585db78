"""What the ROS 1 and ROS 2 clients say when the arm's controller is not where the robot file's
``[ros]`` table says: no action server at its ``action``.

A name copied from a topic list is the likeliest slip: ``rostopic list`` shows an action as its
topics (``/arm_controller/follow_joint_trajectory/goal``, ``.../status``, ...), ``ros2 topic
list`` as its hidden ones (``.../_action/feedback``, ``.../_action/status``). The action is the
part before them, and the message says so.
"""

from __future__ import annotations

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
