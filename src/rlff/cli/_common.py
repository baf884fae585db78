"""What every command shares: the consoles, verbosity, JSON output and progress bars.

Commands only parse arguments, call the library and print; no logic lives in the CLI layer.
"""

from __future__ import annotations

import datetime
import json
import sys
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import typer
from rich.console import Console

# numpy and rich.progress are imported where they are used so that `rlff --help` starts fast


@dataclass
class Verbosity:
    """Global flags set by the root command (-q / -v / --debug)."""

    quiet: bool = False
    verbose: bool = False
    debug: bool = False


verbosity = Verbosity()


# Markup and emoji codes are off: file names and values print as they are ("a:b:c.csv", "[x].csv").
#: Help texts are plain text: rich markup would swallow a robot file's table names ("[whole_arm]").
PLAIN_HELP = None

class OutputClosed(Exception):
    """The reader of rlff's stdout or stderr went away (``rlff sim throw ... | head -1``):
    :func:`rlff.cli.main` ends the command quietly, with exit code 141.

    Not a BrokenPipeError: click turns that (any OSError of EPIPE) into exit code 1 on its way out.
    """


class _Console(Console):
    """A rich console that leaves a closed pipe to :func:`rlff.cli.main`: rich's own handling
    exits with code 1, which says "a bug in rlff"."""

    def on_broken_pipe(self) -> None:
        self.quiet = True  # nothing more to write: its buffer is dropped
        raise OutputClosed() from None


def stdout() -> Console:
    """Console for results (follows ``sys.stdout`` so test runners can capture it)."""
    return _Console(file=sys.stdout, soft_wrap=True, markup=False, emoji=False, highlight=False)


def stderr() -> Console:
    """Console for progress, notes and warnings."""
    return _Console(file=sys.stderr, soft_wrap=True, markup=False, emoji=False, highlight=False)


#: The largest seed an option takes: numpy's generators take any non-negative integer, but
#: scikit-learn's ``random_state`` and CMA-ES (``numpy.random.seed``) at most 2**32 - 1.
MAX_SEED = 2**32 - 1


def seed_option(help: str, *, name: str = "--seed", default: int = 0) -> Any:
    """A seed option: an integer from 0 to :data:`MAX_SEED`, anything else a usage error (exit 2)."""
    return typer.Option(default, name, min=0, max=MAX_SEED, help=help)


#: ``--approach-speed``: the share of the joints' limits a live throw's approach uses (the move
#: from the arm's pose to the throw's start). The value of
#: :data:`rlff.trajectory.planner.APPROACH_SPEED`, written out so that ``rlff`` starts without
#: numpy (tests/test_cli_startup.py; tests/test_robot_cli.py checks that the two agree).
APPROACH_SPEED_OPTION = typer.Option(
    0.25, "--approach-speed",
    help="Share of the joints' speed, acceleration and jerk limits the move from the arm's pose to the "
         "throw's start uses (0.25: a quarter; 1: full speed). The throw itself uses the limits.")


def check_approach_speed_option(value: float) -> None:
    """``--approach-speed`` checked before anything connects (an :class:`InputError` naming it)."""
    from rlff.errors import InputError
    from rlff.trajectory.planner import check_approach_speed

    try:
        check_approach_speed(value)
    except InputError as exc:
        raise InputError(f"--approach-speed {value:.10g}: {exc}") from None


@contextmanager
def basket_options(**options: str) -> Iterator[None]:
    """Name the option a basket's value came from in the errors of :class:`rlff.sim.Basket`, which
    name its parameter: ``basket_options(rim_height="--height")`` turns "basket rim_height 0.01 m is
    no higher ..." into "basket rim_height (--height) 0.01 m is no higher ..."."""
    from rlff.errors import InputError

    try:
        yield
    except InputError as exc:
        message = str(exc)
        for parameter, option in options.items():
            words = f"basket {parameter}"
            if message.startswith(words):
                raise InputError(f"{words} ({option}){message[len(words):]}") from None
        raise


def input_words(path: Any, loaded: Any, attempt: int | None) -> str:
    """What a loaded trajectory file was and became (``loaded``: the
    :class:`rlff.learn.replay.ThrowInput` of ``path``, ``attempt`` as asked for), for one line.

    An attempt the loop clipped into the joint limits (its log's ``clipped``) is logged with its
    clipped path, which planned again clips nothing: "nothing clipped" alone said that the log's
    ``clipped: 9`` never happened. The line says both.
    """
    from rlff.learn.replay import pick_attempt
    from rlff.wording import plural

    words = loaded.kind
    if loaded.run is None or loaded.plan.clipped_points:
        return words
    chosen, _ = pick_attempt(path, attempt)
    if not chosen.clipped:
        return words
    logged = (f"the loop clipped {plural(chosen.clipped, 'value')} into the joint limits when it threw it "
              "(the log's 'clipped') and logged the path as clipped")
    if words.endswith("; nothing clipped"):
        return words.removesuffix("nothing clipped") + logged + ": nothing more to clip"
    return f"{words}; {logged}"


def given(ctx: typer.Context, *names: str) -> list[str]:
    """The options among the command's parameters ``names`` that the user gave, as they are
    spelt (``--centre-share``), not those left at their default, which a command cannot tell from
    its value alone: an option that only matters beside another is refused without it, rather
    than ignored. A name that is no parameter of the command is a bug (it had counted as given)."""
    options = {param.name: param for param in ctx.command.params}
    unknown = [name for name in names if name not in options]
    if unknown:
        raise ValueError(f"no parameter {unknown[0]!r} in {ctx.command.name}")
    return [options[name].opts[0] for name in names
            if ctx.get_parameter_source(name).name not in ("DEFAULT", "DEFAULT_MAP")]


def say(message: str) -> None:
    """A note for the user on stderr, unless -q."""
    if not verbosity.quiet:
        stderr().print(message)


def warn(message: str) -> None:
    """A warning on stderr, also under -q: it says a result may be wrong or incomplete."""
    stderr().print(f"warning: {message}")


def say_first(lines: list[str], where_all: str, limit: int = 10) -> None:
    """Say the first ``limit`` of ``lines`` and how many more there are, and where to find them all
    (``where_all``, e.g. "--json lists every one"): hundreds of lines bury what matters."""
    for line in lines[:limit]:
        say(line)
    if len(lines) > limit:
        say(f"... and {len(lines) - limit} more ({where_all})")


def warn_copies(dataset: Any, source: Any) -> None:
    """Warn of the throws of ``source`` (a Dataset read from it) that repeat another sample for
    sample: they count twice in a fit."""
    from rlff.dataset import copies_warning

    warning = copies_warning(dataset)
    if warning is not None:
        warn(f"{source}: {warning}")


def jsonable(value: Any) -> Any:
    """``json.dumps``' ``default``: numpy arrays and scalars, and paths."""
    import numpy as np

    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    if hasattr(value, "__fspath__"):
        return str(value)
    raise TypeError(f"not JSON serialisable: {type(value).__name__}")


def emit_json(payload: Any) -> None:
    """Print a machine-readable result on stdout: strict JSON, a non-finite number as ``null``
    (Python's ``NaN`` and ``Infinity`` are no JSON, and ``jq`` and browsers refuse them)."""
    text = json.dumps(payload, default=jsonable, indent=2)
    try:
        json.loads(text, parse_constant=_refuse)
    except ValueError:  # NaN or +-Infinity somewhere: null instead
        text = json.dumps(json.loads(text, parse_constant=lambda _: None), indent=2)
    try:
        sys.stdout.write(text + "\n")
        sys.stdout.flush()
    except BrokenPipeError:
        raise OutputClosed() from None


def _refuse(constant: str) -> None:
    raise ValueError(constant)


#: Without a terminal on stderr (a log file, a pipe), where a bar shows nothing until the command
#: ends, :func:`progress` prints a line at every this share of the work ...
PLAIN_STEP = 0.1
#: ... and at least every this many seconds, the work's progress or not.
PLAIN_SECONDS = 30.0
#: Shares of a unit of work (:func:`progress`' ``advance(0.1)``) that add up to within this of a
#: whole number are that number: ten tenths are one file done, not 0.9999999999999999 of one.
_WHOLE = 1e-9


@contextmanager
def progress(description: str, total: int | None) -> Iterator[Callable[..., None]]:
    """Progress of long work on stderr; yields ``advance(n=1, description=None, total=None)``
    (``total``: a new total, when the work turned out longer than said). ``n`` may be a share of
    one unit of the work (a part of one long file: ``0.4``): the bar fills by it, the count says
    the whole units done, and shares that add up to a whole unit count as it.

    On a terminal, a rich progress bar. Otherwise (stderr redirected to a file or a pipe, where the
    bar shows nothing until the command ends and a long job looks hung) a plain line as the work
    starts, at every tenth of it (:data:`PLAIN_STEP`), every :data:`PLAIN_SECONDS` s and at its
    end: ``importing 3/10 (30 %) 0:00:12`` (``3/?`` without a total). A line every
    :data:`PLAIN_SECONDS` s where the progress has not changed since the line before says the work
    goes on, with the time since it started: ``importing 3/10 (30 %) ... still working (1 min 30
    s)``. Silent with -q.
    """
    if verbosity.quiet:
        yield lambda *args, **kwargs: None
        return
    console = stderr()
    if not console.is_terminal:
        lines = _ProgressLines(console, description, total)
        try:
            yield lines.advance
        finally:
            lines.close()
        return
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    bar = Progress(
        TextColumn("{task.description}", style="progress.description", markup=False),
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
        console=console,
        transient=False,
    )
    with bar:
        task = bar.add_task(description, total=total)

        def advance(n: float = 1, description: str | None = None, total: int | None = None) -> None:
            if description is not None:
                bar.update(task, description=description)
            if total is not None:
                bar.update(task, total=total)
            bar.advance(task, n)
            done = next(shown.completed for shown in bar.tasks if shown.id == task)
            if done != round(done) and abs(done - round(done)) < _WHOLE:
                bar.update(task, completed=round(done))

        yield advance


def files_advance(advance: Callable[..., None]) -> Callable[[str, str, float], None]:
    """:func:`rlff.capture.import_recordings`' ``progress(path, stage, share)`` as the ``advance``
    of a bar that counts files (:func:`progress`): each file fills one unit by
    its share done, its name and stage the description ("session.bag: labelling throw 3 of 600")."""
    file_share = {"done": 0.0}  # of the file being imported

    def show(path: str, stage: str, share: float) -> None:
        advance(share - file_share["done"], description=f"{Path(path).name}: {stage}")
        file_share["done"] = 0.0 if stage == "done" else share

    return show


class _ProgressLines:
    """:func:`progress` as plain lines on ``console``, for a stderr that is no terminal.

    ``advance`` may come from another thread than the one that opened it (a robot's feedback); a
    thread of its own says the progress every :data:`PLAIN_SECONDS` s that nothing else did.
    """

    def __init__(self, console: Console, description: str, total: int | None) -> None:
        self.console = console
        self.description = description
        self.total = total
        self.done = 0
        self.started = time.monotonic()
        self.lock = threading.Lock()
        with self.lock:
            self._say()
        self.closed = threading.Event()
        self.timer = threading.Thread(target=self._every, name="rlff-progress", daemon=True)
        self.timer.start()

    def advance(self, n: float = 1, description: str | None = None, total: int | None = None) -> None:
        with self.lock:
            if self.closed.is_set():  # a robot's feedback after the goal's end: the last line is said
                return
            if description is not None:
                self.description = description
            if total is not None:
                self.total = total
            step = self._step()
            self.done += n
            if abs(self.done - round(self.done)) < _WHOLE:  # shares of a unit that add up to it
                self.done = round(self.done)
            if self._step() > step:
                self._say()

    def close(self) -> None:
        self.closed.set()
        self.timer.join()
        with self.lock:
            if self.said != self._line(with_time=False):
                self._say()

    def _step(self) -> int:
        """How many :data:`PLAIN_STEP` of the work are done (0 without a total)."""
        return int(self.done / self.total / PLAIN_STEP + 1e-9) if self.total else 0

    def _line(self, with_time: bool = True) -> str:
        whole = int(self.done)  # a file half read is no file done: "0/1 (50 %)"
        if self.total:
            line = f"{self.description} {whole}/{self.total} ({100 * self.done / self.total:.0f} %)"
        else:
            line = f"{self.description} {whole}/?"
        elapsed = datetime.timedelta(seconds=int(time.monotonic() - self.started))
        return f"{line} {elapsed}" if with_time else line

    def _say(self, heartbeat: bool = False) -> None:
        """Print the progress now (the lock held); a ``heartbeat`` (:meth:`_every`) with the same
        progress as the line before says the work goes on, and for how long, instead of that line again."""
        line = self._line(with_time=False)
        if heartbeat and line == self.said:
            shown = f"{line} ... still working ({_duration(time.monotonic() - self.started)})"
        else:
            shown = self._line()
        self.console.print(shown, markup=False, highlight=False)
        self.said, self.said_at = line, time.monotonic()

    def _every(self) -> None:
        while not self.closed.wait(max(0.0, self.said_at + PLAIN_SECONDS - time.monotonic())):
            with self.lock:
                if time.monotonic() - self.said_at >= PLAIN_SECONDS:
                    try:
                        self._say(heartbeat=True)
                    except OutputClosed:  # stderr's reader went away: the command's next line ends it (141)
                        return


def _duration(seconds: float) -> str:
    """A time of ``seconds`` (s) in words, to the whole second: ``45 s``, ``1 min 30 s``, ``2 h 0 min 5 s``."""
    whole = int(seconds)
    hours, minutes, rest = whole // 3600, whole // 60 % 60, whole % 60
    if hours:
        return f"{hours} h {minutes} min {rest} s"
    return f"{minutes} min {rest} s" if minutes else f"{rest} s"
