"""A server's stop: the first SIGTERM or Ctrl-C is a request its loop takes, a second ends it at once.

The signals are raised in this process (Python runs their handlers in the main thread, where
pytest runs the tests); the live tests (test_ros1_live.py, test_ros2_live.py) stop real servers
mid-goal with SIGTERM.
"""

from __future__ import annotations

import signal
import time

import pytest

from rlff.cli import _Stop
from rlff.errors import Terminated
from rlff.robot.stopping import ANSWER_GRACE, StopRequest, run_until_stopped


@pytest.fixture
def command_line():
    """The command line's own SIGTERM and SIGINT handler, installed as ``rlff`` installs it."""
    handler = _Stop()
    previous = {signum: signal.signal(signum, handler) for signum in (signal.SIGTERM, signal.SIGINT)}
    yield handler
    for signum, old in previous.items():
        signal.signal(signum, old)


def test_the_first_signal_is_a_request_and_a_second_the_command_line_s_stop(command_line):
    stop = StopRequest()
    with stop.caught():
        signal.raise_signal(signal.SIGTERM)
        assert stop.requested.is_set() and stop.by == "SIGTERM"
        assert command_line.signal is None  # nothing raised: the server's loop takes the request
        with pytest.raises(Terminated):
            signal.raise_signal(signal.SIGTERM)
    assert command_line.signal == signal.SIGTERM  # so `rlff` says "terminated" and exits 143
    assert stop.again == "SIGTERM"
    assert signal.getsignal(signal.SIGTERM) is command_line and signal.getsignal(signal.SIGINT) is command_line


def test_an_ignored_sigint_stays_ignored(command_line):
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # a background job of a non-interactive shell
    stop = StopRequest()
    with stop.caught():
        assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
        assert signal.getsignal(signal.SIGTERM) is stop


def _loop(stop: StopRequest, signals: dict[int, int], brake: bool, settled_after: int | None,
          said: list[str]) -> tuple[int, float]:
    """:func:`run_until_stopped` over steps of 10 ms that raise ``signals`` (step number: signal)
    and settle from step ``settled_after`` on, its log in ``said``; (steps taken, seconds taken)."""
    steps: list[float] = []

    def step() -> bool:
        steps.append(time.monotonic())
        if len(steps) in signals:
            signal.raise_signal(signals[len(steps)])
        time.sleep(0.01)
        return True

    start = time.monotonic()
    with stop.caught():
        run_until_stopped(step, stop, lambda by: brake,
                          lambda: settled_after is not None and len(steps) >= settled_after, said.append,
                          lambda text: said.append(f"warning: {text}"))
    return len(steps), time.monotonic() - start


def test_a_stop_with_nothing_moving_ends_the_loop_at_once(command_line):
    said: list[str] = []
    steps, _ = _loop(StopRequest(), {3: signal.SIGTERM}, False, None, said)
    assert steps == 3 and said == ["stopped by SIGTERM: no goal running, shutting down"]


def test_a_stop_mid_goal_goes_on_until_settled_and_the_answer_s_grace(command_line):
    said: list[str] = []
    steps, took = _loop(StopRequest(), {3: signal.SIGINT}, True, 20, said)
    assert said == ["stopped by SIGINT: braking the arm to rest and answering its goal before shutting down; "
                    "a second SIGTERM or Ctrl-C exits at once"]
    assert took >= ANSWER_GRACE and steps > 20 + ANSWER_GRACE / 0.1  # ticking all along


def test_a_second_signal_while_braking_is_logged_and_ends_at_once(command_line):
    said: list[str] = []
    with pytest.raises(Terminated):
        _loop(StopRequest(), {3: signal.SIGINT, 6: signal.SIGTERM}, True, None, said)
    assert command_line.signal == signal.SIGTERM  # `rlff` says "terminated", exit 143
    assert said[-1] == ("warning: stopped again by SIGTERM while braking: exiting at once, before the arm is at "
                        "rest and its goal answered")
