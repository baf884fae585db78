"""Who may talk to rlff's ROS 2 nodes: this host only by default, the network when asked.

ROS 2 discovers peers according to ``ROS_AUTOMATIC_DISCOVERY_RANGE`` (rmw reads it when a
context's first node is created): ``LOCALHOST`` keeps discovery and traffic on this machine,
``SUBNET`` (ROS 2's own default) lets any host of the local network find, command and watch
the arm. rlff's server and client set ``LOCALHOST`` unless opened to the network, which they
say in a warning. ``ROS_DOMAIN_ID`` is left to the user (0 when unset), as in any ROS 2 tool.
"""

from __future__ import annotations

import os

from rlff.errors import InputError

VARIABLE = "ROS_AUTOMATIC_DISCOVERY_RANGE"
WARNING = ("ROS 2 discovery is open to the network (ROS_AUTOMATIC_DISCOVERY_RANGE={range}): any host "
           "on it that shares ROS_DOMAIN_ID {domain} can command and watch this arm; use SROS2 "
           "enclaves (docs/robot.md) or drop network (--network)")


def limit_discovery(network: bool = False) -> str | None:
    """Set the discovery range for the ROS 2 contexts this process creates next.

    Parameters
    ----------
    network : bool
        False: this host only (``LOCALHOST``, whatever the environment said). True: the range
        the environment sets, ``SUBNET`` when it sets none.

    Returns
    -------
    str or None
        The warning to show when the nodes are open to the network.
    """
    if not network:
        os.environ[VARIABLE] = "LOCALHOST"
        return None
    if os.environ.get(VARIABLE, "LOCALHOST") == "LOCALHOST":
        os.environ[VARIABLE] = "SUBNET"
    return WARNING.format(range=os.environ[VARIABLE], domain=os.environ.get("ROS_DOMAIN_ID", "0"))


def make_node(name: str, context):
    """An rclpy node in ``context``; a node the security settings forbid is an :class:`InputError`.

    With ``ROS_SECURITY_ENABLE=true`` rcl loads the enclave's keys and Fast DDS' security plugins,
    which the PyPI wheels are built without (docs/robot.md, "Who may move the arm").
    """
    from rclpy.node import Node

    try:
        return Node(name, context=context)
    except Exception as exc:  # rclpy's RCLError, from its compiled module
        if os.environ.get("ROS_SECURITY_ENABLE", "").lower() == "true":
            reason = str(exc).splitlines()[0]
            raise InputError(f"ROS_SECURITY_ENABLE=true, but the node cannot start securely: {reason} "
                             "(the ROS 2 wheels' Fast DDS has no security libraries: see docs/robot.md)") from None
        raise
