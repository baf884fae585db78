"""Who may move the arm: by default rlff's ROS 2 server cannot be reached from another host.

"Another host" is another network namespace on this machine: two namespaces made for the test,
joined by a veth pair with documentation addresses (192.0.2.0/24, never routed anywhere). The
server runs in one, a probe (an rclpy action client with ROS 2's default, network-wide
discovery) in the other. Controls: the probe in the server's own namespace finds the default
server, and from the other namespace it finds a server started with --network.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys

import pytest

from ros2rig import Server, free_domain, require_ros2, ros2_env

pytestmark = [pytest.mark.ros2, pytest.mark.integration, pytest.mark.slow]

PROBE = """
import sys, rclpy
from rclpy.action import ActionClient
from control_msgs.action import FollowJointTrajectory
rclpy.init()
node = rclpy.create_node("rlff_network_probe")
client = ActionClient(node, FollowJointTrajectory, "/comau_controller/follow_joint_trajectory")
print("found" if client.wait_for_server(timeout_sec=float(sys.argv[1])) else "not found", flush=True)
rclpy.shutdown()
"""


def _ip(*args: str) -> None:
    subprocess.run(["ip", *args], check=True, capture_output=True, text=True, timeout=30)


@pytest.fixture(scope="module")
def namespaces():
    """Two network namespaces joined by a veth pair; yields their names (server's, other)."""
    require_ros2()
    reason = None
    if shutil.which("ip") is None:
        reason = "ip (iproute2) is not installed (scripts/debian-packages.txt)"
    elif os.geteuid() != 0:
        reason = "network namespaces need root"
    if reason:
        if os.environ.get("CI") == "true":
            pytest.fail(reason)
        pytest.skip(reason)
    tag = f"{os.getpid() % 100000}"
    server, other = f"rlff-{tag}-a", f"rlff-{tag}-b"
    made = []
    try:
        for name in (server, other):
            _ip("netns", "add", name)
            made.append(name)
        _ip("link", "add", f"r{tag}a", "type", "veth", "peer", "name", f"r{tag}b")
        for name, link, address in ((server, f"r{tag}a", "192.0.2.1/24"), (other, f"r{tag}b", "192.0.2.2/24")):
            _ip("link", "set", link, "netns", name)
            _ip("-n", name, "addr", "add", address, "dev", link)
            _ip("-n", name, "link", "set", "lo", "up")
            _ip("-n", name, "link", "set", link, "up", "multicast", "on")
            _ip("-n", name, "route", "add", "224.0.0.0/4", "dev", link)  # DDS discovery is multicast
        yield server, other
    finally:
        for name in made:
            subprocess.run(["ip", "netns", "del", name], capture_output=True, timeout=30)


def _probe(namespace: str, env: dict[str, str], seconds: float) -> str:
    probe_env = dict(env, ROS_AUTOMATIC_DISCOVERY_RANGE="SUBNET")  # ROS 2's default: the whole network
    done = subprocess.run(["ip", "netns", "exec", namespace, sys.executable, "-c", PROBE, str(seconds)],
                          env=probe_env, capture_output=True, text=True, timeout=seconds + 60)
    assert done.returncode == 0, done.stderr
    return done.stdout.strip()


def _serve(namespace: str, env: dict[str, str], log, *args: str) -> Server:
    return Server(env, log, *args, prefix=["ip", "netns", "exec", namespace])


def test_the_default_server_is_not_reachable_from_another_namespace(namespaces, tmp_path):
    inside, outside = namespaces
    env = ros2_env(free_domain(), tmp_path)
    server = _serve(inside, env, tmp_path / "serve.log")
    try:
        assert "this host only" in server.text()
        assert _probe(inside, env, 20) == "found"  # the server is up, and found on its own host
        assert _probe(outside, env, 10) == "not found"
    finally:
        server.close()


def test_network_opens_the_server_to_another_namespace_with_a_warning(namespaces, tmp_path):
    inside, outside = namespaces
    env = ros2_env(free_domain(), tmp_path)
    server = _serve(inside, env, tmp_path / "serve.log", "--network")
    try:
        assert any(line.startswith("warning: ROS 2 discovery is open to the network")
                   for line in server.text().splitlines()), server.text()
        assert _probe(outside, env, 30) == "found"
    finally:
        server.close()
