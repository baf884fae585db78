"""Stopping a simulated-arm server safely (``rlff robot serve``, ROS 1 and ROS 2).

A server asked to stop (SIGTERM from a supervisor or ``kill``, Ctrl-C) while its arm moves must
neither leave the arm mid-motion nor its client waiting for an answer. So the first SIGINT or
SIGTERM is a request (:class:`StopRequest`), not an exception raised wherever the main thread
happens to be (in the middle of a tick, or of the executor's turn), and the server's loop
(:func:`run_until_stopped`) takes it between two of its turns: the controller brakes the arm to
rest as a cancel does (:meth:`rlff.robot.controller.TrajectoryController.stop`), the server
keeps ticking (publishing the joint states) until the arm stands still and the goal is answered
ABORTED with the reason, goes on :data:`ANSWER_GRACE` s more for that answer to reach the
client, and returns: the process exits 0. With nothing moving it returns at once.

A second signal while the server brakes does what it would have done without the server's
handler (the command line's: ``rlff: terminated``, exit 143, or ``rlff: interrupted``, 130), at
once, after a warning in the server's log.
"""

from __future__ import annotations

import signal
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager

from rlff.errors import Interrupted, Terminated

#: Seconds a stopped server goes on after its last goal was answered, for the answer to reach the
#: client before the node shuts down (rclpy sends it from a task of its executor, rospy from a
#: publisher's thread: neither has left the process when the goal's state changes).
ANSWER_GRACE = 0.5


class StopRequest:
    """The SIGINT and SIGTERM handler of a running server.

    The first signal sets :attr:`requested` (and :attr:`by`, the signal's name) and returns; a
    second one calls the handler that was installed before (the command line's raises
    :class:`~rlff.errors.Terminated` or :class:`~rlff.errors.Interrupted`) and raises that
    KeyboardInterrupt itself if the handler did not (:attr:`again` names it).
    """

    def __init__(self) -> None:
        self.requested = threading.Event()
        self.by = ""
        self.again = ""
        self._previous: dict[int, object] = {}

    def __call__(self, signum: int, frame) -> None:
        name = signal.Signals(signum).name
        if not self.requested.is_set():
            self.by = name
            self.requested.set()
            return
        self.again = name
        previous = self._previous.get(signum)
        if callable(previous):
            previous(signum, frame)
        raise Terminated() if signum == signal.SIGTERM else Interrupted()

    @contextmanager
    def caught(self) -> Iterator[StopRequest]:
        """Handle SIGTERM and SIGINT (unless SIGINT is ignored, as in a background job of a script)
        while the block runs, then put the previous handlers back. Signals reach the main thread
        only: in another one this handles nothing."""
        if threading.current_thread() is not threading.main_thread():
            yield self
            return
        self._previous = {signal.SIGTERM: signal.signal(signal.SIGTERM, self)}
        if signal.getsignal(signal.SIGINT) is not signal.SIG_IGN:
            self._previous[signal.SIGINT] = signal.signal(signal.SIGINT, self)
        try:
            yield self
        finally:
            for signum, handler in self._previous.items():
                signal.signal(signum, handler)


def run_until_stopped(step: Callable[[], bool], stop: StopRequest, brake: Callable[[str], bool],
                      settled: Callable[[], bool], log: Callable[[str], None],
                      warn: Callable[[str], None]) -> None:
    """Run a server's loop until it is asked to stop, then until it has stopped safely.

    Parameters
    ----------
    step : callable
        One turn of the server's loop (a tick and the sleep to the next, or one turn of the ROS 2
        executor); returns False once ROS has shut down, which ends this at once.
    stop : StopRequest
        Installed (:meth:`StopRequest.caught`) by the caller.
    brake : callable
        Called once, with the signal's name, on the stop request: the controller brakes the arm
        and takes no new goal. Returns whether anything is left to finish (a motion, a goal to
        answer); if not, this returns at once.
    settled : callable
        Whether the arm stands still and every goal has been answered.
    log, warn : callable
        The server's log, for the stop and for a second signal (which propagates).
    """
    try:
        while not stop.requested.is_set():
            if not step():
                return
        if not brake(stop.by):
            log(f"stopped by {stop.by}: no goal running, shutting down")
            return
        log(f"stopped by {stop.by}: braking the arm to rest and answering its goal before shutting down; "
            "a second SIGTERM or Ctrl-C exits at once")
        answered = None
        while step():
            if answered is None and settled():
                answered = time.monotonic()
            if answered is not None and time.monotonic() - answered >= ANSWER_GRACE:
                return
    except KeyboardInterrupt:
        if stop.again:
            warn(f"stopped again by {stop.again} while braking: exiting at once, before the arm is at rest "
                 "and its goal answered")
        raise
