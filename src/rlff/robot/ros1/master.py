"""Finding the ROS master before a node starts, so that a missing roscore is a clear error.

rospy itself would wait for a master forever; rlff's commands give up after a timeout instead.
"""

from __future__ import annotations

import socket
import time
import xmlrpc.client
from urllib.parse import urlsplit

import rosgraph

from rlff.errors import InputError, RlffError


class RosUnavailable(RlffError):
    """No ROS master (or no action server) answered in time."""


def wait_for_master(timeout: float) -> str:
    """The master's URI once it answers; :class:`RosUnavailable` after ``timeout`` s without."""
    uri = rosgraph.get_master_uri()
    parsed = urlsplit(uri)
    if parsed.scheme not in ("http", "https") or not parsed.hostname:
        raise InputError(f"ROS_MASTER_URI {uri!r} is not a URL like http://localhost:11311")
    try:
        parsed.port  # noqa: B018 - a port that is not a number raises here
    except ValueError:
        raise InputError(f"ROS_MASTER_URI {uri!r}: the port is not a number") from None
    master = rosgraph.Master("/rlff_probe", master_uri=uri)
    deadline = time.monotonic() + timeout
    previous = socket.getdefaulttimeout()
    socket.setdefaulttimeout(max(0.2, min(2.0, timeout)))
    try:
        while True:
            try:
                master.getPid()
                return uri
            except (OSError, rosgraph.MasterException):
                if time.monotonic() >= deadline:
                    raise RosUnavailable(f"no ROS master at {uri} after {timeout:.3g} s: start roscore, "
                                         "or set ROS_MASTER_URI") from None
                time.sleep(0.1)
    finally:
        socket.setdefaulttimeout(previous)


class ServerRunning(InputError):
    """Another server already runs under the node name or serves the action."""


def _answers(uri: str) -> bool:
    """Whether the node at XML-RPC ``uri`` answers (a node killed hard stays registered)."""
    try:
        code, _, _ = xmlrpc.client.ServerProxy(uri).getPid("/rlff_probe")
    except (OSError, xmlrpc.client.Error):
        return False
    return code == 1


def require_no_server(node_name: str, status_topic: str) -> None:
    """:class:`ServerRunning` if a live node is called ``node_name`` or publishes ``status_topic``.

    ``status_topic`` is the action server's status topic (every actionlib server publishes it);
    registrations of nodes that no longer answer are ignored.
    """
    master = rosgraph.Master("/rlff_probe")
    name = rosgraph.names.ns_join(rosgraph.names.get_ros_namespace(), node_name)  # as init_node names it
    previous = socket.getdefaulttimeout()
    socket.setdefaulttimeout(2.0)
    try:
        try:
            uri = master.lookupNode(name)
        except rosgraph.MasterError:
            uri = None
        if uri and _answers(uri):
            raise ServerRunning(f"a node {name} is already running ({uri}): stop that `rlff robot serve` "
                                "first; a second one would replace it")
        publishers, _, _ = master.getSystemState()
        for topic, nodes in publishers:
            if topic != status_topic:
                continue
            for node in nodes:
                try:
                    node_uri = master.lookupNode(node)
                except rosgraph.MasterError:
                    continue
                if _answers(node_uri):
                    raise ServerRunning(f"{node} already serves the action of {status_topic} "
                                        f"({node_uri}): stop it first; a second server would compete for the goals")
    finally:
        socket.setdefaulttimeout(previous)


def publishers_of(topic: str) -> int | None:
    """How many nodes the master lists as publishers of ``topic`` (a node killed hard stays
    listed); None when the master cannot be asked."""
    previous = socket.getdefaulttimeout()
    socket.setdefaulttimeout(2.0)
    try:
        publishers, _, _ = rosgraph.Master("/rlff_probe").getSystemState()
    except (OSError, rosgraph.MasterException):
        return None
    finally:
        socket.setdefaulttimeout(previous)
    return sum(len(nodes) for name, nodes in publishers if name == topic)
