"""Learning through a robot: ``rlff learn --executor ros2`` against ``rlff robot serve --ros 2``.

Each attempt runs as a goal on the live server; the outcome comes from a "vision system" node of
the test, which publishes the next of its scripted landings (geometry_msgs/PointStamped on
/rlff/landing) whenever a goal of the action succeeds, or from a person typing at the prompt.
The attempts log must hold exactly those landings, and a second run must resume it.
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
import threading

import pytest

from ros2rig import ACTION, RosNode, Server, free_domain, require_ros2, ros2_env

pytestmark = [pytest.mark.ros2, pytest.mark.integration, pytest.mark.slow]

BASKET = 2.0  # m
# misses of -0.8, -0.5, +0.6, -0.3, +0.4, -0.2, then the basket's centre: a hit
LANDINGS = [1.2, 1.5, 2.6, 1.7, 2.4, 1.8, 2.0]


@pytest.fixture(scope="module")
def domain():
    require_ros2()
    return free_domain()


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    return tmp_path_factory.mktemp("learn")


@pytest.fixture(scope="module")
def server(domain, folder):
    server = Server(ros2_env(domain, folder), folder / "serve.log")
    yield server
    server.close()


@pytest.fixture(scope="module")
def demos(folder):
    path = folder / "demos.csv"
    made = subprocess.run([sys.executable, "-m", "rlff", "data", "synth", "throws", "-o", str(path), "--seed", "3"],
                          capture_output=True, text=True, timeout=300)
    assert made.returncode == 0, made.stderr
    return path


class Vision:
    """Publishes the next scripted landing each time a goal of the action succeeds."""

    def __init__(self, node: RosNode, landings: list[float]) -> None:
        from action_msgs.msg import GoalStatus, GoalStatusArray
        from geometry_msgs.msg import PointStamped

        self.landings = list(landings)
        self.published: list[float] = []
        self._done: set[bytes] = set()
        self._lock = threading.Lock()
        publisher = node.node.create_publisher(PointStamped, "/rlff/landing", 10)

        def on_status(msg) -> None:
            with self._lock:
                for status in msg.status_list:
                    goal = bytes(status.goal_info.goal_id.uuid)
                    if status.status == GoalStatus.STATUS_SUCCEEDED and goal not in self._done and self.landings:
                        self._done.add(goal)
                        landing = PointStamped()
                        landing.header.stamp = node.node.get_clock().now().to_msg()
                        landing.point.x = self.landings.pop(0)
                        publisher.publish(landing)
                        self.published.append(landing.point.x)

        node.node.create_subscription(GoalStatusArray, f"{ACTION}/_action/status", on_status, 10)


@pytest.fixture(scope="module")
def vision(server, domain):
    node = RosNode(domain, "test_vision")
    yield Vision(node, LANDINGS)
    node.close()


def learn(domain, folder, demos, *args: str, stdin: str | None = None) -> subprocess.CompletedProcess:
    """``rlff learn`` on the served arm; its moves to each throw's start at the full limits (the
    default quarter took 2 s of real time per attempt; the pace is test_ros1_live's subject)."""
    return subprocess.run([sys.executable, "-m", "rlff", "learn", str(demos), "--preset", "thesis", "--basket",
                           str(BASKET), "--executor", "ros2", "--approach-speed", "1", *args], env=ros2_env(domain, folder),
                          capture_output=True, text=True, timeout=600, input=stdin)


def attempts(log) -> list[dict]:
    lines = [json.loads(line) for line in log.read_text().splitlines()]
    assert lines[0]["format"] == "rlff-attempts" and lines[0]["run"]["executor"] == "ros2"
    return lines[1:]


def test_five_attempts_with_landings_from_a_topic_then_a_resume(server, vision, domain, folder, demos):
    log = folder / "attempts.jsonl"
    first = learn(domain, folder, demos, "--outcome", "topic", "--budget", "5", "--log", str(log), "--json")
    assert first.returncode == 0, first.stderr
    result = json.loads(first.stdout)
    assert (result["attempts"], result["hit"], result["resumed"]) == (5, False, 0)
    assert result["landings"] == pytest.approx(LANDINGS[:5])
    assert result["misses"] == pytest.approx([x - BASKET for x in LANDINGS[:5]])
    recorded = attempts(log)
    assert [a["landing"] for a in recorded] == pytest.approx(LANDINGS[:5])
    assert not any(a["hit"] for a in recorded)
    assert server.text().count("trajectory completed") == 5  # every attempt ran on the arm

    second = learn(domain, folder, demos, "--outcome", "topic", "--budget", "10", "--log", str(log), "--json")
    assert second.returncode == 0, second.stderr
    result = json.loads(second.stdout)
    assert (result["attempts"], result["hit"], result["resumed"]) == (7, True, 5)
    assert result["landings"] == pytest.approx(LANDINGS)
    recorded = attempts(log)
    assert [a["attempt"] for a in recorded] == list(range(1, 8)) and recorded[-1]["hit"]
    assert recorded[-1]["miss"] == 0.0
    # the resumed run's throws are announced as the log numbers them (it said "attempt 1" for 6); the
    # progress lines of a stderr that is no terminal also name the log's attempts as the run reads them
    announced = [int(line.split(":")[0].split()[1]) for line in second.stderr.splitlines()
                 if re.match(r"attempt \d+: approach first", line)]
    assert announced and min(announced) == 6, second.stderr
    assert server.text().count("trajectory completed") == 7
    assert vision.published == pytest.approx(LANDINGS)


def test_outcomes_typed_at_the_prompt(server, domain, folder, demos):
    log = folder / "asked.jsonl"
    # an answer it cannot read is asked again; -0.4 m is a miss 40 cm short, then a hit
    done = learn(domain, folder, demos, "--outcome", "ask", "--feedback", "distance", "--update", "calibrate",
                 "--budget", "5", "--log", str(log), "--json", stdin="\nmaybe\n\n-0.4\n\nhit\n")
    assert done.returncode == 0, done.stderr
    result = json.loads(done.stdout)
    assert (result["attempts"], result["hit"]) == (2, True)
    # a typed hit is in the basket, not measured: no landing, no miss (null), in the log too
    assert result["landings"][0] == pytest.approx(BASKET - 0.4) and result["landings"][1] is None
    assert result["misses"][0] == pytest.approx(-0.4) and result["misses"][1] is None
    assert [(a["hit"], a["miss"]) for a in attempts(log)][1] == (True, None)
    assert "answer 'maybe': type hit, miss, or the signed miss in m" in done.stderr
    assert "attempt 1: the signed miss in m (negative short; 0 or hit)?" in done.stderr
    # the typed miss is shown as --outcome topic shows a measured one (it read "attempt 1: miss, ...")
    assert "attempt 1: miss -0.40 m, exploration " in done.stderr and "attempt 2: hit, exploration " in done.stderr
    # each throw waited for an empty line: whoever answers may stand where the ball lands
    assert done.stderr.count("the arm is about to throw: Enter to throw, Ctrl-C to stop") == 2


def test_an_answer_typed_ahead_does_not_throw(server, domain, folder, demos):
    log = folder / "ahead.jsonl"
    before = server.text().count(" accepted:")
    # "-0.5" for attempt 1, then "miss" typed ahead: not taken for attempt 2's go, asked again
    done = learn(domain, folder, demos, "--outcome", "ask", "--budget", "3", "--log", str(log), stdin="\n-0.5\nmiss\n")
    assert done.returncode == 2
    assert "attempt 2: not thrown yet, so nothing to answer: an empty line (Enter) throws" in done.stderr
    assert server.text().count(" accepted:") == before + 1  # the second throw never went out
    assert [a["landing"] for a in attempts(log)] == pytest.approx([BASKET - 0.5])


def test_a_closed_stdin_stops_the_run_and_keeps_the_log(server, domain, folder, demos):
    log = folder / "closed.jsonl"
    done = learn(domain, folder, demos, "--outcome", "ask", "--budget", "3", "--log", str(log), stdin="\n-0.5\n")
    assert done.returncode == 2
    assert done.stderr.strip().splitlines()[-1] == (
        "rlff: error: --outcome ask: no answer (stdin is closed); the attempts so far are in the log")
    assert [a["landing"] for a in attempts(log)] == pytest.approx([BASKET - 0.5])


def test_whole_arm_attempts_at_a_bearing_with_typed_outcomes(server, domain, folder):
    from armrobot import arm_robot_file

    demos = folder / "arm-demos.csv"
    made = subprocess.run([sys.executable, "-m", "rlff", "data", "synth", "throws", "--whole-arm", "--subjects", "3",
                           "--distances", "1,1.5,2", "--bearings", "0,60", "--heights", "0.3", "-o", str(demos),
                           "--seed", "4"], capture_output=True, text=True, timeout=300)
    assert made.returncode == 0, made.stderr
    log = folder / "arm.jsonl"
    before = server.text().count("trajectory completed")
    done = subprocess.run([sys.executable, "-m", "rlff", "learn", str(demos), "--preset", "thesis", "--basket", "1.5",
                           "--joints", "joint_2,joint_3", "--bearing", "60", "--robot", str(arm_robot_file(folder)),
                           "--executor", "ros2", "--outcome", "ask", "--budget", "3", "--log", str(log), "--json"],
                          env=ros2_env(domain, folder), capture_output=True, text=True, timeout=600, input="\nmiss\n\nhit\n")
    assert done.returncode == 0, done.stderr
    result = json.loads(done.stdout)
    assert (result["attempts"], result["hit"]) == (2, True)
    assert server.text().count("trajectory completed") == before + 2  # both whole-arm throws ran on the arm
    header, *lines = (json.loads(line) for line in log.read_text().splitlines())
    assert header["run"]["joints"] == ["joint_3", "joint_2"] and header["run"]["basket"]["bearing"] == 60.0
    assert all(set(line["arm"]) == {"shoulder", "shoulder_velocity"} for line in lines)


@pytest.mark.parametrize("when", ["mid-throw", "at-the-prompt"])
def test_a_learn_stopped_on_the_arm_says_what_became_of_the_attempt(server, domain, folder, demos, when):
    """SIGTERM (a supervisor's stop) mid-throw: the goal is cancelled, and the attempt, never logged,
    is thrown again on resume; at the prompt: thrown, but not logged. Each on a line of its own."""
    import signal
    import time

    from ros2rig import wait_until

    log = folder / f"stopped-{when}.jsonl"
    accepted, completed = server.text().count(" accepted:"), server.text().count("trajectory completed")
    learner = subprocess.Popen([sys.executable, "-m", "rlff", "learn", str(demos), "--preset", "thesis", "--basket",
                                str(BASKET), "--executor", "ros2", "--outcome", "ask", "--budget", "3", "--log",
                                str(log)], env=ros2_env(domain, folder), stdin=subprocess.PIPE,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    learner.stdin.write("\n")  # the first throw's go
    learner.stdin.flush()
    if when == "mid-throw":
        wait_until(lambda: server.text().count(" accepted:") > accepted or learner.poll() is not None, 300,
                   "the first throw's goal")
    else:
        wait_until(lambda: server.text().count("trajectory completed") > completed or learner.poll() is not None,
                   300, "the first throw to end")
        time.sleep(1.0)  # at the prompt
    assert learner.poll() is None, learner.communicate()
    learner.send_signal(signal.SIGTERM)
    _, err = learner.communicate(timeout=120)
    assert learner.returncode == 143, err
    lines = err.strip().splitlines()
    said = ("rlff: attempt 1: goal cancelled; not logged: a resumed run throws it again" if when == "mid-throw"
            else "rlff: attempt 1: thrown, but no outcome given: not logged: a resumed run throws it again")
    kept = f"rlff: no attempt was logged to {log} yet: the same command starts the run again"  # what it kept
    assert lines[-3:] == [said, kept, "rlff: terminated"], err
    assert any(line.startswith("attempt 1: approach first: ") and "joint_2 " in line for line in lines), err
    assert not log.exists()  # nothing logged: a run that logs no attempt leaves no log (it held its header alone)




def test_a_learned_throw_sent_again_comes_down_where_it_did_while_learning(demos, tmp_path):
    """A server that throws each finished goal in MuJoCo: every attempt thrown by the loop comes
    down where the same attempt sent again from the log (``rlff robot send LOG --attempt N``) does,
    so what the log keeps is what the arm threw. The executor had planned the loop's planned
    throw again as if its braking ended at its release: a motion of its own (0.1 rad/s apart, 4 cm
    apart where the ball came down here), its release put at its end."""
    domain = free_domain()
    server = Server(ros2_env(domain, tmp_path), tmp_path / "serve.log", "--sim", "mujoco", "--basket", str(BASKET))
    log = tmp_path / "mujoco.jsonl"
    try:  # the second throw starts where the first braked: an approach first
        done = learn(domain, tmp_path, demos, "--outcome", "ask", "--budget", "2", "--log", str(log),
                     stdin="\n-0.5\n\n-0.4\n")
        assert done.returncode == 0, done.stderr
        sent = []
        for attempt in (1, 2):
            again = subprocess.run([sys.executable, "-m", "rlff", "robot", "send", str(log), "--attempt", str(attempt),
                                    "--ros", "2", "--json", "--timeout", "120"], env=ros2_env(domain, tmp_path),
                                   capture_output=True, text=True, timeout=300)
            assert again.returncode == 0, again.stderr
            sent.append(json.loads(again.stdout)["error_string"])
    finally:
        server.close()
    landed = [float(x) for x in re.findall(r"MuJoCo throw: \w+, landed at ([-\d.]+) m", server.text())]
    assert len(landed) == 4 and min(landed) > 1.0, server.text()  # thrown, not dropped
    assert all(text.startswith("MuJoCo throw: ") for text in sent), sent
    assert landed[:2] == pytest.approx(landed[2:], abs=1e-3)  # said to the millimetre
