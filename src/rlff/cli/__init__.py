"""The ``rlff`` command's boundary with the process: its stop signals, its exit code, its one error line.

The one error boundary is :func:`main`:

- bad input (an :class:`rlff.errors.InputError`, an operating-system error on a file the user
  named, or a usage error such as an unknown option) ends with one line on stderr,
  ``rlff: error: ...``, and exit code 2;
- any other :class:`rlff.errors.RlffError` (a robot that failed or cannot be reached: no ROS, no
  master or action server, an arm state that cannot be trusted) ends with the same one line and
  exit code 1;
- a package rlff declares (or an extra of it declares) that is not installed ends with one line
  naming it and the ``pip install`` that adds it, and exit code 1
  (:mod:`rlff.cli.missing_package`);
- anything else is a bug: one line ``rlff: internal error: ...`` with a hint to rerun with
  ``--debug``, and exit code 1;
- a stop signal ends the command with ``rlff: interrupted`` (Ctrl-C, exit code 130) or ``rlff:
  terminated`` (SIGTERM, 143), whatever error it caused on its way out (:func:`_stop_of`): one
  that lands in an import is turned by the importer into an ImportError or a RuntimeError, which
  had been called a bug;
- output whose reader went away (``rlff sim throw ... | head -1``) ends the command quietly with
  exit code 141 (:func:`_output_closed`);
- ``--debug`` prints the traceback of either, and lets numpy's RuntimeWarnings through (they are
  silenced otherwise: the library checks its results for non-finite values and says so);
- ``-v`` only adds detail to what commands print; it no longer shows tracebacks.

This module imports nothing but the standard library's lightest modules, so that the stop
signals are rlff's before typer, rich and the command modules load (a few tenths of a second, in
which a Ctrl-C printed a traceback): the command tree is :mod:`rlff.cli.root`, imported by
:func:`main`.
"""

from __future__ import annotations

import atexit
import os
import signal
import sys
import threading
import traceback
import warnings

from rlff.errors import InputError, Interrupted, RlffError, Terminated


def _command():
    """The click command of every ``rlff`` command (:func:`rlff.cli.root.command`)."""
    from rlff.cli.root import command

    return command()


def _fail(message: str, code: int, exc: BaseException, debug: bool) -> int:
    """Say ``message`` (``exc``'s traceback first with ``--debug``); returns ``code``."""
    from rlff.cli._common import stderr

    if debug:
        traceback.print_exception(exc)
    stderr().print("rlff: " + " ".join(message.split()))  # one line, whatever the message holds
    return code


def _os_error(exc: OSError) -> str:
    """An operating-system error as one line, with the file it concerns when it names one; a write
    the system refused partway names none (a full disk, a quota, ``ulimit -f``): the library's
    writers name their file themselves (:mod:`rlff.fileio`), so such an error here came from
    code that did not."""
    from rlff.fileio import refusal_words, refused

    if refused(exc):
        return f"error: a write was refused {refusal_words(exc)}"
    reason = exc.strerror or str(exc)
    return f"error: {exc.filename}: {reason}" if exc.filename is not None else f"error: {reason}"


class _Stop:
    """The SIGINT and SIGTERM handler while a command runs: raises :class:`Interrupted` (a
    KeyboardInterrupt), or :class:`Terminated` for SIGTERM, and remembers which (an error the
    stop caused on its way out is reported as the stop: :func:`_stop_of`).

    Once the command has ended (:meth:`ended`; the ``rlff`` process only, :func:`run`), a stop
    signal no longer changes what it did: the command's output is complete and its exit code
    stands. Python's exit joins worker processes (``bench --jobs``) and unloads the libraries,
    seconds with ROS 2, SciPy and MuJoCo loaded on a busy machine: a Ctrl-C there printed a
    traceback of loky's join, and a SIGTERM killed a ``robot send`` whose goal had succeeded,
    exit 143. The first such signal is let go, a second exits at once with the command's code;
    the last moments of the exit, when Python no longer runs handlers, ignore them
    (:meth:`ignore_at_the_end`).
    """

    def __init__(self) -> None:
        self.signal: int | None = None
        self.code: int | None = None  # the command's exit code, once it has ended
        self.late: int | None = None  # a stop signal that came after that

    def __call__(self, signum, frame) -> None:
        if self.code is not None:
            if self.late is not None:  # asked twice: leave now, the command's output flushed
                _flush_outputs()
                os._exit(self.code)
            self.late = signum
            return
        self.signal = signum
        raise Terminated() if signum == signal.SIGTERM else Interrupted()

    def ended(self, code: int) -> None:
        """The command ended with ``code``: stop signals from here on leave it as it is."""
        self.code = code

    def ignore_at_the_end(self) -> None:
        """Ignore the stop signals this handler takes, for the rest of an exit after
        :meth:`ended`: an ``atexit`` function registered before anything else (so run last),
        because Python puts back the default action of every signal it handled before it unloads
        its modules, and a SIGTERM then killed the process (143) however the command had ended."""
        if self.code is None:
            return
        for signum in (signal.SIGINT, signal.SIGTERM):
            if signal.getsignal(signum) is self:
                signal.signal(signum, signal.SIG_IGN)


def _flush_outputs() -> None:
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):  # closed, or its reader gone
            pass


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``rlff`` command line in a Python program; returns the exit code.

    Ctrl-C ends a command with ``rlff: interrupted`` and exit code 130, SIGTERM (a supervisor's
    stop) with ``rlff: terminated`` and 143. Both are raised where the command is, so that its
    clean-up runs: a goal on the arm is cancelled rather than left running mid-throw. The signal
    handlers in place before are put back on return.
    """
    return _run(sys.argv[1:] if argv is None else list(argv), _Stop(), process=False)


def run() -> None:
    """The ``rlff`` console script: :func:`main`, whose exit code a stop signal no longer changes
    once the command has ended (:class:`_Stop`)."""
    stop = _Stop()
    atexit.register(stop.ignore_at_the_end)  # registered first, so called last
    sys.exit(_run(sys.argv[1:], stop, process=True))


def _run(args: list[str], stop: _Stop, *, process: bool) -> int:
    """Run the command ``args`` under ``stop``; ``process``: it is the ``rlff`` process's, and
    ``stop`` stays in place after it (:meth:`_Stop.ended`)."""
    if threading.current_thread() is not threading.main_thread():  # signals reach the main thread only
        return _reported(_main(args, None))
    previous = {signal.SIGTERM: signal.signal(signal.SIGTERM, stop)}
    if signal.getsignal(signal.SIGINT) is signal.default_int_handler:  # an ignored SIGINT stays ignored
        previous[signal.SIGINT] = signal.signal(signal.SIGINT, stop)
    try:
        try:
            code = _main(args, stop)
            if process:
                stop.ended(code)
        except KeyboardInterrupt as exc:  # a stop that came as the command returned, before ended()
            code = _STOP_CODES[_stop_of(exc, stop)]
            if process:
                stop.ended(code)
    finally:
        if not process or stop.code is None:
            for signum, handler in previous.items():
                signal.signal(signum, handler)
    return _reported(code)


#: The exit code of a command a stop signal ended, by signal (128 + its number, as the shell says).
_STOP_CODES = {signal.SIGINT: 130, signal.SIGTERM: 143}


def _reported(code: int) -> int:
    """``code``, said on stderr when a stop signal ended the command (130, 143)."""
    said = {130: "rlff: interrupted", 143: "rlff: terminated"}.get(code)
    if said is not None:
        try:
            sys.stderr.write(said + "\n")
            sys.stderr.flush()
        except (OSError, ValueError):  # stderr closed: the code says it
            pass
    return code


def _stop_of(exc: BaseException, stop: _Stop | None) -> int | None:
    """The stop signal that ended the command with ``exc``, or None: the signal the handler saw,
    or a :class:`Terminated` (SIGTERM) or another KeyboardInterrupt (SIGINT) that ``exc`` is or
    came from (its ``__cause__`` and ``__context__``, link by link).

    A signal that lands in an import surfaces as the importer's error, the stop its cause: an
    extension module's initialisation (``import mujoco``) raises ``ImportError: initialization
    failed``, a class that dataclasses builds a RuntimeError.
    """
    if stop is not None and stop.signal is not None:
        return stop.signal
    links, seen = [exc], set()
    while links:
        link = links.pop()
        if link is None or id(link) in seen:
            continue
        seen.add(id(link))
        if isinstance(link, Terminated):
            return signal.SIGTERM
        if isinstance(link, KeyboardInterrupt):
            return signal.SIGINT
        links += [link.__context__, link.__cause__]
    return None


def _output_closed() -> int:
    """Exit code 141 for a command whose stdout or stderr was closed by its reader, said nowhere.

    141 (128 + SIGPIPE) rather than 0: the command did not finish (its output was cut short, and it
    stopped where it was), and it is what the shell reports for any program a closed pipe stops
    (``yes | head -1`` under ``set -o pipefail``), as 130 and 143 are for SIGINT and SIGTERM.
    rlff does not let SIGPIPE kill it, which would skip the clean-up (a goal on the arm cancelled).
    """
    # Python flushes both streams once more at exit, which fails again on the closed pipe
    # ("Exception ignored ... BrokenPipeError", exit 120): they write to /dev/null from here on
    devnull = os.open(os.devnull, os.O_WRONLY)
    for stream in (sys.stdout, sys.stderr):
        try:
            os.dup2(devnull, stream.fileno())
        except (OSError, ValueError):  # a stream with no file descriptor (a test's capture)
            pass
    os.close(devnull)
    return 141


def _main(args: list[str], stop: _Stop | None) -> int:
    debug = "--debug" in args
    with warnings.catch_warnings():
        if not debug:
            # numpy's overflow/invalid-value warnings: results are checked for finiteness where
            # they matter and reported as one InputError line; the raw warnings are noise
            warnings.simplefilter("ignore", RuntimeWarning)
        shown = warnings.showwarning
        said: set[str] = set()

        def show(message, category, filename, lineno, file=None, line=None) -> None:
            # one `warning:` line, as every other, once (a benchmark reads its robot file several
            # times, a learning run refits its model every attempt), never Python's form with a
            # source path and line; with --debug, others' than rlff's own categories in that form
            if debug and not category.__module__.startswith("rlff."):
                shown(message, category, filename, lineno, file, line)
                return
            from rlff.cli._common import warn

            if str(message) not in said:
                said.add(str(message))
                warn(str(message))

        warnings.showwarning = show
        from rlff.cli._common import say
        from rlff.model import compile_notice

        compile_notice.tell_with(say)  # the model's kernels compiling on a cold cache: said once
        try:
            code = _command().main(args=args, prog_name="rlff", standalone_mode=False)
        except SystemExit as exc:
            return exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
        except BaseException as exc:  # noqa: BLE001 - the boundary: every end is one line and a code
            return _ended(exc, args, debug, stop)
        finally:
            compile_notice.tell_with(None)
    if code == 130 and stop is not None and stop.signal is not None:  # typer's code for any KeyboardInterrupt
        return _STOP_CODES[stop.signal]
    return code if isinstance(code, int) else 0


def _ended(exc: BaseException, args: list[str], debug: bool, stop: _Stop | None) -> int:
    """The exit code of a command that ended with ``exc``, its one line said."""
    signum = _stop_of(exc, stop)
    if signum is not None:
        # an error rlff raised on purpose while stopping is said too; one the stop caused (an
        # import it cut short) is no bug: its traceback is for --debug
        if isinstance(exc, (RlffError, OSError)):
            return _fail(_error_line(exc), _STOP_CODES[signum], exc, debug)
        if debug and not isinstance(exc, KeyboardInterrupt):
            traceback.print_exception(exc)
        return _STOP_CODES[signum]
    code = _click_ended(exc, args, debug)
    if code is not None:
        return code
    from rlff.cli._common import OutputClosed

    if isinstance(exc, OutputClosed):
        return _output_closed()
    if isinstance(exc, InputError):
        return _fail(_error_line(exc), 2, exc, debug)
    if isinstance(exc, RlffError):  # not the input: the robot failed, or is not there
        return _fail(_error_line(exc), 1, exc, debug)
    if isinstance(exc, OSError):  # a file the user named: missing, a folder, no permission, disk full
        return _fail(_error_line(exc), 2, exc, debug)
    if isinstance(exc, ModuleNotFoundError):
        from rlff.cli.missing_package import missing_package_line

        line = missing_package_line(exc)
        if line is not None:  # an installation without it, not a bug
            return _fail(line, 1, exc, debug)
    if isinstance(exc, Exception):
        return _fail(f"internal error: {type(exc).__name__}: {exc} (a bug in rlff: rerun with --debug "
                     "for the traceback and report it)", 1, exc, debug)
    raise exc


def _error_line(exc: RlffError | OSError) -> str:
    return f"error: {exc}" if isinstance(exc, RlffError) else _os_error(exc)


def _click_ended(exc: BaseException, args: list[str], debug: bool) -> int | None:
    """The exit code of a command line click refused (usage, a missing argument, no subcommand),
    its line said; None for an error of another kind."""
    try:  # newer typer (0.29 is one) carries its own copy of click; older ones use the click package
        from typer._click import exceptions as click_errors
        from typer._click.utils import echo
    except ImportError:  # pragma: no cover - older typer
        from click import exceptions as click_errors
        from click.utils import echo
    import typer

    if isinstance(exc, click_errors.NoArgsIsHelpError):
        # `rlff data` alone: the group's help, as --help prints it, and the usage-error code
        echo(exc.format_message())
        return 2
    if isinstance(exc, click_errors.UsageError):
        from rlff.cli.root import usage

        return _fail(usage(exc, args), 2, exc, debug)
    if isinstance(exc, click_errors.ClickException):
        return _fail(f"error: {exc.format_message()}", 2, exc, debug)
    if isinstance(exc, typer.Abort):  # click's word for a KeyboardInterrupt, or an EOF at its prompt
        return 130
    return None
