"""Finding the ROS master before a node starts, so that a missing roscore is a clear error.

rospy itself would wait for a master forever; rlff's commands give up after a timeout instead.
"""

from __future__ import annotations

import socket
import time
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
