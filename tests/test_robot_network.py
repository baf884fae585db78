"""Who may move the arm, as the environment the nodes start with: this host only unless asked."""

from __future__ import annotations

import os

import pytest

from rlff.robot.ros1.network import limit_to_loopback, master_is_local
from rlff.robot.ros2.network import VARIABLE, limit_discovery


@pytest.mark.parametrize(("uri", "local"), [
    ("http://localhost:11311", True), ("http://127.0.0.1:40000", True), ("http://127.8.9.1:1", True),
    ("http://[::1]:11311", True), ("http://robot-pc:11311", False), ("http://192.0.2.7:11311", False)])
def test_a_master_on_this_host_is_recognised(uri, local):
    assert master_is_local(uri) is local


def test_ros1_nodes_bind_to_the_loopback_address_when_the_master_is_local(monkeypatch):
    monkeypatch.setenv("ROS_MASTER_URI", "http://127.0.0.1:11311")
    monkeypatch.setenv("ROS_HOSTNAME", "robot-pc")
    monkeypatch.delenv("ROS_IP", raising=False)
    assert limit_to_loopback() is None
    assert os.environ["ROS_IP"] == "127.0.0.1" and "ROS_HOSTNAME" not in os.environ


def test_ros1_network_or_a_remote_master_is_said_in_a_warning(monkeypatch):
    monkeypatch.setenv("ROS_MASTER_URI", "http://127.0.0.1:11311")
    monkeypatch.delenv("ROS_IP", raising=False)
    monkeypatch.delenv("ROS_HOSTNAME", raising=False)
    assert "open to the network (every interface)" in limit_to_loopback(network=True)
    monkeypatch.setenv("ROS_MASTER_URI", "http://robot-pc:11311")
    monkeypatch.setenv("ROS_IP", "192.0.2.7")
    warning = limit_to_loopback()
    assert "(192.0.2.7)" in warning and "http://robot-pc:11311" in warning


def test_ros2_discovery_is_localhost_unless_opened(monkeypatch):
    monkeypatch.setenv(VARIABLE, "SUBNET")  # whatever the environment says, the default is this host
    assert limit_discovery() is None
    assert os.environ[VARIABLE] == "LOCALHOST"
    monkeypatch.setenv("ROS_DOMAIN_ID", "42")
    warning = limit_discovery(network=True)
    assert os.environ[VARIABLE] == "SUBNET" and "ROS_DOMAIN_ID 42" in warning
    monkeypatch.setenv(VARIABLE, "SYSTEM_DEFAULT")
    limit_discovery(network=True)
    assert os.environ[VARIABLE] == "SYSTEM_DEFAULT"  # a range the user chose is kept
