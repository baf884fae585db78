"""The ``rlff`` command: parses arguments, calls the library, prints.

The one error boundary is :func:`main`:

- bad input (an :class:`rlff.errors.InputError`, an operating-system error on a file the user
  named, or a usage error such as an unknown option) ends with one line on stderr,
  ``rlff: error: ...``, and exit code 2;
- any other :class:`rlff.errors.RlffError` (a robot that failed or cannot be reached: no ROS, no
  master or action server, an arm state that cannot be trusted) ends with the same one line and
  exit code 1;
- anything else is a bug: one line ``rlff: internal error: ...`` with a hint to rerun with
  ``--debug``, and exit code 1;
- output whose reader went away (``rlff sim throw ... | head -1``) ends the command quietly with
  exit code 141 (:func:`_output_closed`);
- ``--debug`` prints the traceback of either, and lets numpy's RuntimeWarnings through (they are
  silenced otherwise: the library checks its results for non-finite values and says so);
- ``-v`` only adds detail to what commands print; it no longer shows tracebacks.
"""

from __future__ import annotations

import os
import re
import signal
import sys
import threading
import traceback
import warnings

import typer

try:  # typer >= 0.20 carries its own copy of click; before, it used the click package
    from typer._click import exceptions as click_errors
    from typer._click.core import Context
    from typer._click.utils import echo
except ImportError:  # pragma: no cover - older typer
    from click import Context
    from click import exceptions as click_errors
    from click.utils import echo

from rlff.cli._common import PLAIN_HELP, OutputClosed, stderr, verbosity
from rlff.errors import InputError, Interrupted, RlffError, Terminated

HELP_OPTIONS = ["-h", "--help"]

app = typer.Typer(
    rich_markup_mode=PLAIN_HELP,
    name="rlff",
    help="Robot learning from failed demonstrations: from skeleton recordings to robot throws.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    context_settings={"help_option_names": HELP_OPTIONS},
)


def _version(value: bool) -> None:
    if value:
        from rlff import __version__

        sys.stdout.write(f"rlff {__version__}\n")
        raise typer.Exit(0)


@app.callback()
def _root(
    quiet: bool = typer.Option(False, "--quiet", "-q", help="Print only results, warnings and errors."),
    verbose: bool = typer.Option(False, "--verbose", "-v", help="More detail in what commands print."),
    debug: bool = typer.Option(False, "--debug", help="Show the traceback of an error, and numpy's warnings."),
    version: bool = typer.Option(False, "--version", callback=_version, is_eager=True, help="Print the version and exit."),
) -> None:
    verbosity.quiet = quiet
    verbosity.verbose = verbose
    verbosity.debug = debug


def _register() -> None:
    """Attach the command groups; each module owns its commands."""
    from rlff.cli import commands

    commands.register(app)


_register()


def _command():
    """The click command of :data:`app`, with flags shown as flags in help.

    typer labels every option with its type, ``--json <bool>`` too, which reads as if the flag
    took a value (``--json true`` is refused); a flag's label is blanked here, once for the tree.
    """
    command = typer.main.get_command(app)
    stack = [command]
    while stack:
        node = stack.pop()
        # -h/--help is made on first use and then kept: make it now to label it too
        help_option = node.get_help_option(Context(node, help_option_names=HELP_OPTIONS))
        for param in [*node.params, help_option]:
            if getattr(param, "is_flag", False):
                param.metavar = ""
        stack.extend(getattr(node, "commands", {}).values())
    return command


def _fail(message: str, code: int, debug: bool) -> int:
    if debug:
        traceback.print_exc()
    stderr().print("rlff: " + " ".join(message.split()))  # one line, whatever the message holds
    return code


def _usage(exc, args: list[str]) -> str:
    """A click usage error as one line: the command, the fault and the value given, where to look."""
    command = exc.ctx.command_path if exc.ctx is not None else _command_path(args)
    message = exc.format_message()
    given = _given(getattr(exc, "param", None), args)
    if given is not None and repr(given) not in message:
        message += f" (got {given!r})"
    # --basket 1,5: a decimal comma where a float is asked for (an integer's error says "integer")
    if "valid number" in message and given is not None and re.fullmatch(r"[+-]?\d+,\d+", given):
        message += f"; numbers take a decimal point: {given.replace(',', '.')}"
    unknown = getattr(exc, "option_name", None)
    takes_context = exc.ctx is not None and any("--context" in getattr(p, "opts", ()) for p in exc.ctx.command.params)
    if unknown and takes_context and not getattr(exc, "possibilities", None):  # --distance 2: a context
        name = unknown.lstrip("-").split("=")[0]
        message += f"; a context value goes as -c NAME=VALUE, e.g. -c {name}=..."
    own = {opt for param in _command().params for opt in getattr(param, "opts", ())}
    if unknown in own and command != "rlff":  # rlff data preprocess -q: an option of rlff itself
        message += f"; {unknown} goes before the subcommand: rlff {unknown} {command.removeprefix('rlff ')} ..."
    where = "" if command == "rlff" else f"{command}: "  # rlff's own error says "rlff: error:" already
    return f"error: {where}{message} (see {command} --help)"


def _command_path(args: list[str]) -> str:
    """``rlff bench learning`` of ``bench learning --seeds``: the (sub)commands named in ``args``,
    for an error click raises without a context (an option's value missing at the end)."""
    command, path = _command(), ["rlff"]
    for arg in args:
        if arg.startswith("-"):
            continue
        command = getattr(command, "commands", {}).get(arg)
        if command is None:
            break
        path.append(arg)
    return " ".join(path)


def _given(param, args: list[str]) -> str | None:
    """The value the user gave an option, as typed (``--seed x`` or ``--seed=x``), if any."""
    for name in getattr(param, "opts", None) or ():
        for index, arg in enumerate(args):
            if arg == name and index + 1 < len(args):
                return args[index + 1]
            if arg.startswith(name + "="):
                return arg[len(name) + 1:]
    return None


def _os_error(exc: OSError) -> str:
    """An operating-system error as one line, with the file it concerns when it names one."""
    reason = exc.strerror or str(exc)
    return f"error: {exc.filename}: {reason}" if exc.filename is not None else f"error: {reason}"


class _Stop:
    """The SIGINT and SIGTERM handler while a command runs: raises :class:`Interrupted` (a
    KeyboardInterrupt), or :class:`Terminated` for SIGTERM, and remembers which (Typer turns
    either into exit code 130, the kind lost)."""

    def __init__(self) -> None:
        self.signal: int | None = None

    def __call__(self, signum, frame) -> None:
        self.signal = signum
        raise Terminated() if signum == signal.SIGTERM else Interrupted()


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``rlff`` console script; returns the exit code.

    Ctrl-C ends a command with ``rlff: interrupted`` and exit code 130, SIGTERM (a supervisor's
    stop) with ``rlff: terminated`` and 143. Both are raised where the command is, so that its
    clean-up runs: a goal on the arm is cancelled rather than left running mid-throw.
    """
    args = sys.argv[1:] if argv is None else list(argv)
    if threading.current_thread() is not threading.main_thread():  # signals reach the main thread only
        return _reported(_main(args), None)
    stop = _Stop()
    previous = {signal.SIGTERM: signal.signal(signal.SIGTERM, stop)}
    if signal.getsignal(signal.SIGINT) is signal.default_int_handler:  # an ignored SIGINT stays ignored
        previous[signal.SIGINT] = signal.signal(signal.SIGINT, stop)
    try:
        code = _main(args)
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)
    return _reported(code, stop.signal)


def _reported(code: int, signum: int | None) -> int:
    """An interrupted command's code (130) said on stderr, 143 when SIGTERM stopped it."""
    if code != 130:
        return code
    if signum == signal.SIGTERM:
        stderr().print("rlff: terminated")
        return 143
    stderr().print("rlff: interrupted")
    return 130


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


def _main(args: list[str]) -> int:
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
        try:
            code = _command().main(args=args, prog_name="rlff", standalone_mode=False)
        except click_errors.NoArgsIsHelpError as exc:
            # `rlff data` alone: the group's help, as --help prints it, and the usage-error code
            echo(exc.format_message())
            return 2
        except click_errors.UsageError as exc:
            return _fail(_usage(exc, args), 2, debug)
        except click_errors.ClickException as exc:
            return _fail(f"error: {exc.format_message()}", 2, debug)
        except (typer.Abort, KeyboardInterrupt):
            return 130  # said by main
        except OutputClosed:
            return _output_closed()
        except InputError as exc:
            return _fail(f"error: {exc}", 2, debug)
        except RlffError as exc:  # not the input: the robot failed, or is not there
            return _fail(f"error: {exc}", 1, debug)
        except OSError as exc:  # a file the user named: missing, a folder, no permission, disk full
            return _fail(_os_error(exc), 2, debug)
        except SystemExit as exc:
            return exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
        except Exception as exc:
            return _fail(f"internal error: {type(exc).__name__}: {exc} (a bug in rlff: rerun with --debug "
                         "for the traceback and report it)", 1, debug)
    return code if isinstance(code, int) else 0


def run() -> None:
    """Console-script wrapper that exits with :func:`main`'s code."""
    sys.exit(main())
