"""The ``rlff`` command: parses arguments, calls the library, prints.

Bad input (an :class:`rlff.errors.InputError` or a usage error) ends with a one-line reason on
stderr and exit code 2; ``-v`` adds the traceback.
"""

from __future__ import annotations

import sys
import traceback

import typer

from rlff.cli._common import stderr, verbosity
from rlff.errors import InputError

app = typer.Typer(
    name="rlff",
    help="Robot learning from failed demonstrations: from skeleton recordings to robot throws.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    context_settings={"help_option_names": ["-h", "--help"]},
)


@app.callback()
def _root(
    quiet: bool = typer.Option(False, "--quiet", "-q", help="Print only results and errors."),
    verbose: bool = typer.Option(False, "--verbose", "-v", help="More detail; tracebacks on errors."),
) -> None:
    verbosity.quiet = quiet
    verbosity.verbose = verbose


def _register() -> None:
    """Attach the command groups; each module owns its commands."""
    from rlff.cli import commands

    commands.register(app)


_register()


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``rlff`` console script; returns the exit code."""
    args = sys.argv[1:] if argv is None else list(argv)
    verbose = "-v" in args or "--verbose" in args
    try:
        app(args=args, prog_name="rlff")  # standalone: usage errors print and exit 2 themselves
    except SystemExit as exc:
        return exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
    except InputError as exc:
        if verbose:
            traceback.print_exc()
        stderr().print(f"rlff: error: {exc}", highlight=False, markup=False)
        return 2
    except KeyboardInterrupt:
        stderr().print("rlff: interrupted", highlight=False)
        return 130
    return 0


def run() -> None:
    """Console-script wrapper that exits with :func:`main`'s code."""
    sys.exit(main())
