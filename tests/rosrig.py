"""The ROS 1 rig of the live tests: a real roscore on a free port, ``rlff robot serve``, recorders.

Each test module that uses :func:`ros_fixture` gets its own roscore on a free loopback port (and
its own ROS_HOME), so concurrent test runs on one machine never share a master. The executed
path is what the server publishes on /joint_states, recorded by Debian's own ``rostopic echo``
(another process); :func:`peaks` turns it into the largest speeds and accelerations.

Without Debian's ROS 1 packages the tests skip locally and FAIL in CI (CI=true).
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import time
import xmlrpc.client
from importlib import resources
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from rlff.robot import RobotMapping, load_robot

ROBOT = load_robot()
#: Speed (rad/s) and acceleration (rad/s^2) limits of the robot's joints, (J,).
VMAX = np.array([joint.max_velocity for joint in ROBOT.joints])
AMAX = np.array([joint.max_acceleration for joint in ROBOT.joints])
DRIVEN = 1  # column of joint_2
GOAL_SCRIPT = Path(__file__).with_name("ros1_goal.py")


def missing() -> str | None:
    """Why the live ROS 1 tests cannot run here, or None."""
    if shutil.which("roscore") is None or shutil.which("rostopic") is None:
        return "roscore/rostopic are not installed (scripts/setup.sh --test installs ros-core)"
    # in a child: importing ROS 1 here would put its packages before the ROS 2 wheels' of the
    # same names (std_msgs, trajectory_msgs, ...) for the ROS 2 tests of this worker
    probe = subprocess.run([sys.executable, "-c", "from rlff.robot import ros1; print(ros1.missing() or '')"],
                           capture_output=True, text=True, timeout=120)
    problem = probe.stdout.strip() or probe.stderr.strip()[-500:]
    return f"ROS 1 is not reachable from the venv ({problem}); run scripts/setup.sh --test" if problem else None


@pytest.fixture(scope="module", autouse=True)
def ros_installed():
    """Skip the module without ROS 1 (fail in CI); bind it in a module to use it there."""
    reason = missing()
    if reason is None:
        return
    if os.environ.get("CI") == "true":
        pytest.fail(reason)
    pytest.skip(reason)


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


def ros_env(port: int, home: Path) -> dict[str, str]:
    env = dict(os.environ, ROS_MASTER_URI=f"http://127.0.0.1:{port}", ROS_IP="127.0.0.1",
               ROS_HOME=str(home), ROS_LOG_DIR=str(home / "log"), PYTHONUNBUFFERED="1")
    env.pop("ROS_HOSTNAME", None)
    return env


def wait(predicate, seconds: float, what: str) -> None:
    deadline = time.monotonic() + seconds
    while not predicate():
        if time.monotonic() > deadline:
            raise AssertionError(f"timed out waiting for {what}")
        time.sleep(0.1)


def stop(proc: subprocess.Popen) -> None:
    """Ctrl-C ``proc`` (kill it after 10 s)."""
    if proc.poll() is None:
        proc.send_signal(signal.SIGINT)
        try:
            proc.wait(10)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


class Ros:
    """A roscore and an ``rlff robot serve`` on a free loopback port (no server with ``serve=False``)."""

    def __init__(self, folder: Path, *serve_args: str, serve: bool = True) -> None:
        self.port = free_port()
        self.folder = folder
        self.env = ros_env(self.port, folder)
        self.core = subprocess.Popen(["roscore", "-p", str(self.port)], env=self.env,
                                     stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        self.master = xmlrpc.client.ServerProxy(self.env["ROS_MASTER_URI"])

        def master_up() -> bool:
            try:
                return self.master.getPid("/test")[0] == 1
            except OSError:
                return False

        wait(master_up, 60, "roscore")
        self.server_log = folder / "serve.log"
        if not serve:
            self.server = subprocess.Popen([sys.executable, "-c", "pass"])  # nothing to stop
            return
        with open(self.server_log, "w") as log:
            self.server = subprocess.Popen([sys.executable, "-m", "rlff", "robot", "serve", *serve_args],
                                           env=self.env, stdout=log, stderr=subprocess.STDOUT)
        wait(lambda: "serving /" in self.server_log.read_text(), 120, "rlff robot serve")

    def rlff(self, *args: str, timeout: float = 120, env: dict | None = None) -> subprocess.CompletedProcess:
        return subprocess.run([sys.executable, "-m", "rlff", *args], env=env or self.env, capture_output=True,
                              text=True, timeout=timeout)

    def goal(self, folder: Path, spec: dict, *args: str) -> dict:
        """Send a raw goal (see tests/ros1_goal.py) and return its result."""
        path = folder / "goal.json"
        path.write_text(json.dumps(spec))
        done = subprocess.run([sys.executable, str(GOAL_SCRIPT), str(path), *args], env=self.env,
                              capture_output=True, text=True, timeout=180)
        assert done.returncode == 0, done.stdout + done.stderr
        return json.loads(done.stdout.strip().splitlines()[-1])

    def record(self, path: Path, topic: str = "/joint_states") -> subprocess.Popen:
        """``rostopic echo -p TOPIC`` (JointState) into ``path``; returns once the first state arrived."""
        out = open(path, "w")  # noqa: SIM115 (closed by the process' end)
        proc = subprocess.Popen(["rostopic", "echo", "-p", topic], env=self.env, stdout=out,
                                stderr=subprocess.DEVNULL)
        out.close()
        wait(lambda: path.read_text().count("\n") >= 3, 180, topic)
        return proc

    def log(self) -> str:
        return self.server_log.read_text()

    def pose(self, folder: Path, topic: str = "/joint_states") -> np.ndarray:
        """The arm's pose (J,) now, from one recorded message on ``topic`` (JointState)."""
        recorder = self.record(folder / "pose.csv", topic)
        stop(recorder)
        return states(folder / "pose.csv")[1][-1]

    def close(self) -> None:
        stop(self.server)
        stop(self.core)


def ros_fixture(tmp_path_factory):
    """The body of a module's ``ros`` fixture: one rig for the module."""
    rig = Ros(tmp_path_factory.mktemp("ros"))
    yield rig
    rig.close()


def states(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """Recorded (stamp (N,) s, positions (N, 6) rad) of /joint_states."""
    table = pd.read_csv(path)
    stamps = table["field.header.stamp"].to_numpy(np.int64)
    positions = table[[f"field.position{i}" for i in range(6)]].to_numpy(float)
    return stamps / 1e9, positions


def peaks(stamps: np.ndarray, positions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Largest |velocity| and |acceleration| (J,) of a recorded motion, from divided differences.

    Each state is the arm's at exactly its stamp, so for its C2 motion a first divided
    difference is the velocity and twice a second one the acceleration at some instant between
    the stamps (mean value theorem), whatever the spacing: neither can exceed what the motion
    reached, and a jump of the motion shows as a huge value.
    """
    velocity = np.diff(positions, axis=0) / np.diff(stamps)[:, None]
    acceleration = 2 * np.diff(velocity, axis=0) / (stamps[2:] - stamps[:-2])[:, None]
    return np.abs(velocity).max(axis=0), np.abs(acceleration).max(axis=0)


def execution_error(stamps: np.ndarray, positions: np.ndarray, sent, start: float) -> tuple[float, float]:
    """How closely a recorded motion followed the sent trajectory: (delay s, largest error rad).

    The sent points joined by quintic segments through their positions, velocities and
    accelerations (as the server interpolates; scipy's own quintic Hermite here) against the
    recorded positions over the motion. The goal starts at its stamp ``start`` (s), or on receipt
    if it arrives later (a loaded machine): the delay (1 ms steps up to 0.5 s) that fits best.
    """
    from scipy.interpolate import BPoly

    quintic = BPoly.from_derivatives(sent.time, np.stack([sent.positions, sent.velocities,
                                                          sent.accelerations], axis=1))

    def error(delay: float) -> float:
        elapsed = stamps - start - delay
        moving = (elapsed >= 0) & (elapsed <= sent.duration)
        return float(np.abs(positions[moving] - quintic(elapsed[moving])).max()) if moving.sum() >= 20 else np.inf

    delays = np.arange(0.0, 0.5, 0.001)
    errors = [error(delay) for delay in delays]
    best = int(np.argmin(errors))
    return float(delays[best]), errors[best]


def human_csv(path: Path, robot_positions: np.ndarray, robot_speed: np.ndarray) -> Path:
    """A generated-trajectory CSV whose mapped joint_2 path is ``robot_positions`` (rad) at ``robot_speed``."""
    mapping = RobotMapping.for_robot(ROBOT)
    angle = (robot_positions - mapping.angle_offset) / mapping.angle_scale
    velocity = robot_speed / mapping.velocity_scale
    pd.DataFrame({"angle": angle, "velocity": velocity, "pdf": 1.0, "exploration": 0.0,
                  "gmr_mean": velocity}).to_csv(path, index=False)
    return path


def throw_csv(folder: Path, name: str, lower: float, upper: float, peak: float) -> Path:
    """A generated throw of joint_2 from ``lower`` to ``upper`` (rad), from 0.2 rad/s up to ``peak``
    + 0.2 rad/s at its release, the fastest point, as a throw lets go. The planner holds no speed
    above the release's, so the release's speed sets how long the motion takes (a throw that let go
    at 0.2 rad/s crept for 12 s: ``peak`` 0 for a motion of several seconds)."""
    q = np.linspace(lower, upper, 30)
    speed = np.sign(upper - lower) * (0.2 + peak * np.sin(np.linspace(0, np.pi / 2, 30)))
    return human_csv(folder / name, q, speed)


def robot_file(folder: Path, name: str, edit) -> Path:
    """A copy of the robot file, changed by ``edit`` (text to text)."""
    text = (resources.files("rlff") / "robots" / "comau_smart5_six.toml").read_text()
    path = folder / name
    path.write_text(edit(text))
    return path


#: Names of an arm in a namespace of its own, for a robot file's [ros] table.
ARM_NAMES = {"action": "/arm/follow_joint_trajectory", "joint_states": "/arm/joint_states",
             "trajectory_topic": "/arm/joint_trajectory"}


def named_robot_file(folder: Path, name: str, **names: str) -> Path:
    """A copy of the robot file whose [ros] table gives ``names`` (e.g. action="/arm/...")."""
    def edit(text: str) -> str:
        for key, value in names.items():
            line = f'{key} = "{getattr(ROBOT.ros, key)}"'
            assert text.count(line) == 1, line
            text = text.replace(line, f'{key} = "{value}"')
        return text

    return robot_file(folder, name, edit)


UR_NAMES = ("shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint", "wrist_1_joint", "wrist_2_joint",
            "wrist_3_joint")
#: The [ros.joints] tables of a UR-named controller: joint_2 and joint_3 with the zeros of
#: docs/robot.md's example, joint_5 counted the other way round from an offset (to exercise a
#: sign), the rest renamed only.
UR_MAP = """
[ros.joints.joint_1]
name = "shoulder_pan_joint"

[ros.joints.joint_2]
name = "shoulder_lift_joint"
offset = -1.5707963267948966

[ros.joints.joint_3]
name = "elbow_joint"
offset = 1.5707963267948966
sign = 1

[ros.joints.joint_4]
name = "wrist_1_joint"

[ros.joints.joint_5]
name = "wrist_2_joint"
offset = 0.25
sign = -1

[ros.joints.joint_6]
name = "wrist_3_joint"
"""


def ur_file(path, tables: str = UR_MAP):
    """The built-in Comau file (rlff's joints, [geometry]) with ``tables`` added after its [ros]."""
    path.write_text((resources.files("rlff") / "robots" / "comau_smart5_six.toml").read_text(encoding="utf-8") + tables)
    return path
