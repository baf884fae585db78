"""Test rig for live ROS 2: an isolated domain, rlff's server as a process, and rclpy nodes of the test.

Every test session picks its own ROS_DOMAIN_ID (random, so that concurrent runs on one machine do
not see each other) and keeps discovery on this host (ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST).
The test's own nodes use the generated control_msgs type directly, independent of rlff's code.
"""

from __future__ import annotations

import itertools
import os
import random
import signal
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import numpy as np
import pytest

ACTION = "/comau_controller/follow_joint_trajectory"


def ros2_missing() -> str | None:
    """Why the ROS 2 tests cannot run (checked in a child, which leaves this process' imports alone)."""
    probe = subprocess.run([sys.executable, "-c", "from rlff.robot import ros2; print(ros2.missing() or '')"],
                           capture_output=True, text=True, timeout=120)
    return probe.stdout.strip() or probe.stderr.strip()[-500:] or None


def require_ros2() -> None:
    """Skip without ROS 2, but fail in CI, where scripts/setup.sh --test must have installed it."""
    reason = ros2_missing()
    if reason is None:
        return
    if os.environ.get("CI") == "true":
        pytest.fail(reason)
    pytest.skip(reason)


#: Domains per pytest-xdist worker: worker w uses 1 + 40 w .. 40 + 40 w (Fast DDS fits up to 232).
_BLOCK = 40
_WORKER = int(os.environ.get("PYTEST_XDIST_WORKER", "gw0").removeprefix("gw") or 0) % 5
_DOMAINS = itertools.count(random.SystemRandom().randrange(_BLOCK))


def free_domain() -> int:
    """A ROS_DOMAIN_ID of its own for each caller: the worker's block of domains, taken in turn
    from a random start, so that test modules, workers and concurrent runs do not see each other;
    a domain where an ``rlff robot serve --ros 2`` of this host already runs (its lock held: a
    user's, or another run's) is passed over (one on 77 failed ten tests of a run at once)."""
    for _ in range(_BLOCK):
        domain = 1 + _BLOCK * _WORKER + next(_DOMAINS) % _BLOCK
        if not _served_on_this_host(domain):
            return domain
    return domain


def _served_on_this_host(domain: int) -> bool:
    """Whether an rlff server of this host holds an action's lock in ``domain``
    (:func:`rlff.robot.ros2.server._claim_on_this_host`'s lock files)."""
    from filelock import lock_descriptor

    for path in Path(tempfile.gettempdir()).glob(f"rlff-ros2-domain{domain}-*.lock"):
        try:
            fd = os.open(path, os.O_RDWR)
        except OSError:
            continue
        try:
            if not lock_descriptor(fd, blocking=False):
                return True
        finally:
            os.close(fd)  # and with it the lock just taken
    return False


def ros2_env(domain: int, home: Path) -> dict[str, str]:
    env = dict(os.environ, ROS_DOMAIN_ID=str(domain), ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST",
               ROS_LOG_DIR=str(home / "log"), ROS_HOME=str(home), PYTHONUNBUFFERED="1")
    env.pop("ROS_LOCALHOST_ONLY", None)
    return env


def wait_until(predicate, seconds: float, what: str) -> None:
    deadline = time.monotonic() + seconds
    while not predicate():
        if time.monotonic() > deadline:
            raise AssertionError(f"timed out waiting for {what}")
        time.sleep(0.05)


def stop(proc: subprocess.Popen) -> None:
    if proc.poll() is None:
        proc.send_signal(signal.SIGINT)
        try:
            proc.wait(15)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


class Server:
    """``rlff robot serve --ros 2 ARGS`` in a process of its own (run by ``prefix``, e.g. ``ip netns
    exec NAME``), its output in ``log``."""

    def __init__(self, env: dict[str, str], log: Path, *args: str, prefix: list[str] | None = None) -> None:
        self.log = log
        command = [*(prefix or []), sys.executable, "-m", "rlff", "robot", "serve", "--ros", "2", *args]
        with open(log, "w") as out:
            self.proc = subprocess.Popen(command, env=env, stdout=out, stderr=subprocess.STDOUT)
        wait_until(lambda: "serving /" in log.read_text() or self.proc.poll() is not None, 120,
                   "rlff robot serve --ros 2")
        assert self.proc.poll() is None, log.read_text()

    def text(self) -> str:
        return self.log.read_text()

    def close(self) -> None:
        stop(self.proc)


class RosNode:
    """An rclpy context and node of the test, spinning in a thread, recording the joint states
    (``states``, default /joint_states).

    One executor thread unless ``threads`` says more: rclpy's MultiThreadedExecutor kept a core
    busy on its own (ros2/rclpy#1223) and the node then saw /joint_states at 30 Hz with gaps of
    a second instead of 100 Hz, which made the live tests flaky. A node whose callbacks block
    (a test's own action server waiting for a cancel) needs ``threads`` > 1.
    """

    def __init__(self, domain: int, name: str = "rlff_test", threads: int = 1, states: str = "/joint_states") -> None:
        from rlff.robot.rospath import prefer

        prefer(2)  # this worker may have imported ROS 1's std_msgs & co. (e.g. for `rlff robot send`)
        import rclpy
        from rclpy.executors import MultiThreadedExecutor, SingleThreadedExecutor
        from rclpy.node import Node
        from sensor_msgs.msg import JointState

        self.rclpy = rclpy
        self.context = rclpy.Context()
        rclpy.init(context=self.context, domain_id=domain)
        self.node = Node(name, context=self.context)
        self.executor = (SingleThreadedExecutor(context=self.context) if threads == 1
                         else MultiThreadedExecutor(num_threads=threads, context=self.context))
        self.executor.add_node(self.node)
        self._states: list[tuple[float, np.ndarray, np.ndarray]] = []
        self.names: list[str] = []
        self._lock = threading.Lock()
        self.node.create_subscription(JointState, states, self._on_state, 50)
        self._thread = threading.Thread(target=self._spin, daemon=True)
        self._thread.start()

    def _spin(self) -> None:
        try:
            self.executor.spin()
        except Exception:  # noqa: BLE001 - shut down under the spin
            pass

    def _on_state(self, msg) -> None:
        stamp = msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9
        with self._lock:
            self._states.append((stamp, np.array(msg.position), np.array(msg.velocity)))
            self.names = list(msg.name)  # the last message's joint names

    def states(self, since: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
        """Recorded (stamps (N,) s, positions (N, J) rad) of /joint_states from ``since`` on."""
        with self._lock:
            kept = [(s, p) for s, p, _ in self._states if s >= since]
        if not kept:
            return np.empty(0), np.empty((0, 6))
        return np.array([s for s, _ in kept]), np.vstack([p for _, p in kept])

    def velocities(self, since: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
        """Recorded (stamps (N,) s, velocities (N, J) rad/s) of /joint_states from ``since`` on."""
        with self._lock:
            kept = [(s, v) for s, _, v in self._states if s >= since]
        if not kept:
            return np.empty(0), np.empty((0, 6))
        return np.array([s for s, _ in kept]), np.vstack([v for _, v in kept])

    def latest(self, after: float | None = None, seconds: float = 30.0) -> tuple[float, np.ndarray]:
        """The latest /joint_states (stamp, positions), waiting for one stamped after ``after``."""
        def fresh() -> bool:
            stamps, _ = self.states()
            return stamps.size > 0 and (after is None or stamps[-1] > after)

        wait_until(fresh, seconds, "/joint_states")
        stamps, positions = self.states()
        return float(stamps[-1]), positions[-1]

    def now(self) -> float:
        return self.node.get_clock().now().nanoseconds * 1e-9

    def close(self) -> None:
        self.executor.shutdown(timeout_sec=2.0)
        self._thread.join(timeout=2.0)
        self.node.destroy_node()
        if self.context.ok():
            self.rclpy.shutdown(context=self.context)


def wait_future(future, seconds: float, what: str):
    wait_until(future.done, seconds, what)
    return future.result()
