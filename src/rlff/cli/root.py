"""The ``rlff`` command tree: the root command, its global options, and every command group.

Imported by :func:`rlff.cli.main` once the stop signals are its own: typer, rich and the command
modules take a few tenths of a second to import, and a Ctrl-C in them printed a traceback. The
command modules import the library inside their commands (:mod:`rlff.cli.commands`).
"""

from __future__ import annotations

import functools
import re
import sys

import typer

try:  # newer typer (0.29 is one) carries its own copy of click; older ones use the click package
    from typer._click.core import Context
except ImportError:  # pragma: no cover - older typer
    from click import Context

from rlff.cli._common import PLAIN_HELP, verbosity

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


@functools.cache
def command():
    """The click command of :data:`app`, every group attached, with flags shown as flags in help.

    typer labels every option with its type, ``--json <bool>`` too, which reads as if the flag
    took a value (``--json true`` is refused); a flag's label is blanked here, once for the tree.
    """
    from rlff.cli import commands

    commands.register(app)
    built = typer.main.get_command(app)
    stack = [built]
    while stack:
        node = stack.pop()
        # -h/--help is made on first use and then kept: make it now to label it too
        help_option = node.get_help_option(Context(node, help_option_names=HELP_OPTIONS))
        for param in [*node.params, help_option]:
            if getattr(param, "is_flag", False):
                param.metavar = ""
        node.parse_args = functools.partial(_warn_repeats, node, node.parse_args)
        stack.extend(getattr(node, "commands", {}).values())
    return built


def _warn_repeats(node, parse_args, ctx, args: list[str]) -> list[str]:
    """``node``'s ``parse_args`` (``ctx``, ``args``), with a warning for an option that takes one
    value given twice with two values: click keeps the last, as command lines do (a script's
    options overridden at its end), but without a word (``rlff sim throw --basket 1.75 --basket
    2`` threw at 2 m, ``rlff generate -o first.csv -o second.csv`` wrote only the second). A
    group's own options end at its subcommand's name."""
    from rlff.cli._common import warn

    takes_one = {name: param for param in node.params
                 if param.param_type_name == "option" and not param.is_flag and not param.multiple
                 and not param.count and param.nargs == 1
                 for name in (*param.opts, *param.secondary_opts)}
    seen: dict[str, tuple[str, str]] = {}  # the option's first name -> (name as given, value)
    index = 0
    while index < len(args):
        arg = args[index]
        if arg == "--":
            break
        name, value = arg, None
        if arg.startswith("--") and "=" in arg:
            name, value = arg.split("=", 1)
        elif arg.startswith("-") and not arg.startswith("--") and len(arg) > 2 and arg[:2] in takes_one:
            name, value = arg[:2], arg[2:]  # -ofile
        param = takes_one.get(name)
        if param is None:
            if hasattr(node, "commands") and not arg.startswith("-"):
                break  # a group's subcommand: what follows is its own
            index += 1
            continue
        if value is None:
            value = args[index + 1] if index + 1 < len(args) else None
            index += 1
        index += 1
        if value is None:
            break  # click says the value is missing
        key = param.opts[0]
        if key in seen and seen[key][1] != value:
            first, before = seen[key]
            warn(f"{name} given twice ({first} {before}, then {name} {value}): the last, {value}, is taken")
        seen[key] = (name, value)
    return parse_args(ctx, args)


def usage(exc, args: list[str]) -> str:
    """A click usage error as one line: the command, the fault and the value given, where to look."""
    path = exc.ctx.command_path if exc.ctx is not None else _command_path(args)
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
    own = {opt for param in command().params for opt in getattr(param, "opts", ())}
    if unknown in own and path != "rlff":  # rlff data preprocess -q: an option of rlff itself
        message += f"; {unknown} goes before the subcommand: rlff {unknown} {path.removeprefix('rlff ')} ..."
    where = "" if path == "rlff" else f"{path}: "  # rlff's own error says "rlff: error:" already
    return f"error: {where}{message} (see {path} --help)"


def _command_path(args: list[str]) -> str:
    """``rlff bench learning`` of ``bench learning --seeds``: the (sub)commands named in ``args``,
    for an error click raises without a context (an option's value missing at the end)."""
    node, path = command(), ["rlff"]
    for arg in args:
        if arg.startswith("-"):
            continue
        node = getattr(node, "commands", {}).get(arg)
        if node is None:
            break
        path.append(arg)
    return " ".join(path)


def _given(param, args: list[str]) -> str | None:
    """The value the user gave an option, as typed (``--seed x`` or ``--seed=x``), if any: the
    last one given under any of its names, the one click takes (``--budget 1 --budget 0`` had
    quoted the 1 in the 0's error)."""
    names = getattr(param, "opts", None) or ()
    value = None
    for index, arg in enumerate(args):
        for name in names:
            if arg == name and index + 1 < len(args):
                value = args[index + 1]
            elif arg.startswith(name + "="):
                value = arg[len(name) + 1:]
    return value
