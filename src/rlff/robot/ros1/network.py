"""Who may talk to rlff's ROS 1 nodes: the loopback address when the master is on this host.

A rospy node serves its XML-RPC API and its topics on the address that ``ROS_IP`` (or
``ROS_HOSTNAME``) names, and on every interface when neither does. With a master on this host
(``ROS_MASTER_URI`` naming localhost or a 127.x address) rlff's nodes bind to 127.0.0.1 unless
opened to the network, which they say in a warning. A master on another host needs the network.
"""

from __future__ import annotations

import ipaddress
import os
from urllib.parse import urlparse

DEFAULT_MASTER = "http://localhost:11311"
WARNING = ("ROS 1 node open to the network ({address}): any host that reaches {master} can command "
           "and watch this arm; drop network (--network) to keep it on this host")


def master_is_local(uri: str) -> bool:
    """Whether the master URI names this host's loopback (localhost, 127.x, ::1)."""
    host = urlparse(uri).hostname or ""
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def limit_to_loopback(network: bool = False) -> str | None:
    """Bind the nodes this process starts to 127.0.0.1 when the master is local and not ``network``.

    Returns the warning to show when the node is open to the network (``network`` given, or a
    master on another host that the node must reach anyway), else None.
    """
    master = os.environ.get("ROS_MASTER_URI", DEFAULT_MASTER)
    parsed = urlparse(master)
    if parsed.scheme not in ("http", "https") or not parsed.hostname:
        return None  # not a master URI at all: finding the master says so, in one line
    if not network and master_is_local(master):
        os.environ["ROS_IP"] = "127.0.0.1"
        os.environ.pop("ROS_HOSTNAME", None)
        return None
    address = os.environ.get("ROS_IP") or os.environ.get("ROS_HOSTNAME") or "every interface"
    return WARNING.format(address=address, master=master)
