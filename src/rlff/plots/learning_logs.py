"""Attempts logs for learning curves: what a log's run was (its task and its settings), which logs
may share a figure, and the legend names that tell their curves apart.

Two logs are of one task when their runs threw at the same basket (distance, bearing, rim
height) with the same robot (name, description digest, pedestal) and the same joints: only then
are their curves comparable, and only such logs share a figure (:func:`require_one_task`). Within
a task the runs may differ in how they learn and on which arm: the method, the feedback, the
simulated arm's gap (``--gap``), when they stop (``--until``) and the basket's opening. A curve
is named by its method and by each of these settings that differs between the figure's logs,
where its value is not the default (``calibrate, distance feedback, arm speed:0.9``); curves
still named alike get their file's name (:func:`curve_names`). What all the logs share that is
not the default goes into the title (:func:`shared_settings`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from rlff.errors import InputError
from rlff.learn.log import LogContents, read_log

#: The rim height (m), opening (m) and stop rule of a log that does not say (the loop's defaults).
DEFAULT_RIM_HEIGHT, DEFAULT_OPENING, DEFAULT_UNTIL = 0.3, 0.35, "hit"


@dataclass(frozen=True)
class LoggedRun:
    """What a learning curve needs of one attempts log.

    Attributes
    ----------
    method : str
        The run's update strategy or baseline.
    feedback : str
    basket : float
        Basket distance (m).
    misses : list of float
        Signed miss of every attempt (m).
    hits : list of bool
    robot : str or None
        The robot the run threw with (its robot file's ``name``), None in a log that does not say.
    digest : str or None
        The digest of the robot's description and mapping the log records (two robot files of
        one name differ in it).
    joints : tuple of str
        The robot joints the throws drove (``joint_2``; a whole-arm run's several), empty when the
        log does not say.
    bearing : float
        The basket's bearing (degrees from the robot's forward axis, positive to the left).
    opening : float
        The basket's inner width (m; 0.35 in a log that does not say).
    gap : str
        How the simulated arm differed from its robot file (``none``, ``speed:0.9``, ...).
    rim_height : float
        The basket rim's height (m; 0.3 in a log that does not say).
    until : str
        When the run stopped: at the first ``hit``, or at the first ``centred`` one.
    pedestal : float
        The robot base's height (m).
    file : str
        The log's file name.
    """

    method: str
    feedback: str
    basket: float
    misses: list[float]
    hits: list[bool]
    robot: str | None = None
    digest: str | None = None
    joints: tuple[str, ...] = ()
    bearing: float = 0.0
    opening: float = DEFAULT_OPENING
    gap: str = "none"
    rim_height: float = DEFAULT_RIM_HEIGHT
    until: str = DEFAULT_UNTIL
    pedestal: float = 0.0
    file: str = ""


def read_learning_log(path: str | Path) -> LoggedRun:
    """Read an attempts log of ``rlff learn`` (JSONL) for plotting, without changing the file.

    The log is read as the loop reads it to resume (:func:`rlff.learn.log.read_log`): a last line
    cut short by a crash is left out, and what the loop would refuse is refused here too.

    Raises
    ------
    InputError
        No such file, not an rlff attempts log, or a damaged line before the last one; or a run
        record whose basket distance, bearing, opening, rim height or pedestal is not a number.
    """
    path = Path(path)
    return logged_run(path, *read_log(path))


def logged_run(path: Path, run: dict, contents: LogContents) -> LoggedRun:
    """The :class:`LoggedRun` of the attempts log ``path`` already read: its header's ``run`` and
    its ``contents`` (:func:`rlff.learn.log.read_log`).

    Raises
    ------
    InputError
        A run record whose basket distance, bearing, opening, rim height or pedestal is not a number.
    """
    basket = run.get("basket") if isinstance(run.get("basket"), dict) else {}
    try:
        distance = float(basket["distance"])
        bearing = float(basket.get("bearing", 0.0))  # left out for a basket straight ahead
        opening = float(basket.get("opening", DEFAULT_OPENING))
        rim_height = float(basket.get("rim_height", DEFAULT_RIM_HEIGHT))
        pedestal = float(run.get("pedestal", 0.0))
    except KeyError:
        raise InputError(f"{path}, line 1: the run record has no basket distance") from None
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"{path}, line 1: the run's basket distance, bearing, opening or rim height or its "
                         "pedestal is not a number") from None
    robot = run.get("robot") if isinstance(run.get("robot"), dict) else {}
    name, digest = robot.get("name"), robot.get("digest")
    # a miss nobody measured (typed "miss" on a live arm) is logged as null and read as NaN
    return LoggedRun(str(run.get("update", path.stem)), str(run.get("feedback", "")), distance,
                     [attempt.miss for attempt in contents.attempts], [attempt.hit for attempt in contents.attempts],
                     None if name is None else str(name), None if digest is None else str(digest),
                     _thrown_joints(run), bearing, opening, str(run.get("gap", "none")), rim_height,
                     str(run.get("until", DEFAULT_UNTIL)), pedestal, path.name)


def _thrown_joints(run: dict) -> tuple[str, ...]:
    """The robot joints an attempts log's run drove: its ``joints`` (a whole-arm run), else the
    joint of the one-joint mapping its robot record holds, else none known."""
    joints = run.get("joints")
    if isinstance(joints, list) and all(isinstance(j, str) for j in joints):
        return tuple(sorted(joints))
    mapping = _at(run, "robot", "description", "mapping")
    if isinstance(mapping, dict):
        if isinstance(mapping.get("joint"), str):
            return (mapping["joint"],)
        if isinstance(mapping.get("driven"), dict):
            return tuple(sorted(map(str, mapping["driven"])))
    return ()


def _at(record: object, *keys: str) -> object:
    """The value at ``keys`` of nested dicts, or None where a part is absent."""
    for key in keys:
        record = record.get(key) if isinstance(record, dict) else None
    return record


def _robot_words(run: LoggedRun) -> str | None:
    return None if run.robot is None else run.robot + (f" ({run.digest})" if run.digest else "")


#: What makes a run's task, each as it reads in a message (None: the log does not say, which
#: matches any value): the basket's distance, bearing and rim height, the robot and its pedestal,
#: the joints thrown with.
TASK_FIELDS: dict[str, Callable[[LoggedRun], str | None]] = {
    "basket": lambda run: f"{run.basket:g} m",
    "bearing": lambda run: f"{run.bearing:g}°",
    "rim height": lambda run: f"{run.rim_height:g} m",
    "robot": _robot_words,
    "pedestal": lambda run: f"{run.pedestal:g} m",
    "joints": lambda run: ", ".join(run.joints) or None,
}

#: How a run learned within its task, each as a curve's name says it, and the value that goes
#: unsaid (the default; None: every value is said).
SETTINGS: dict[str, tuple[Callable[[LoggedRun], str], str | None]] = {
    "feedback": (lambda run: f"{run.feedback} feedback", None),
    "gap": (lambda run: f"arm {run.gap}", "arm none"),
    "until": (lambda run: f"until {run.until}", f"until {DEFAULT_UNTIL}"),
    "opening": (lambda run: f"opening {run.opening:g} m", f"opening {DEFAULT_OPENING:g} m"),
}


def task_key(run: LoggedRun) -> tuple[str | None, ...]:
    """The run's task (:data:`TASK_FIELDS`, in order): logs of one key may share a figure."""
    return tuple(field(run) for field in TASK_FIELDS.values())


def require_one_task(runs: Sequence[LoggedRun]) -> None:
    """Refuse logs of different tasks, naming each field that differs and the files of each value.

    Raises
    ------
    InputError
        ``the logs are for different tasks: bearing 0° (a.jsonl), 60° (b.jsonl); plot each
        task's logs separately ...``.
    """
    differ = {}
    for name, field in TASK_FIELDS.items():
        files: dict[str, list[str]] = {}
        for run in runs:
            value = field(run)
            if value is not None:
                files.setdefault(value, []).append(run.file)
        if len(files) > 1:
            differ[name] = f"{name} " + ", ".join(f"{value} ({', '.join(names)})" for value, names in files.items())
    if "joints" in differ and len({run.robot for run in runs} - {None}) == 1:
        differ.pop("robot", None)  # one robot whose digest differs with the joints it maps: the joints say it
    if differ:
        raise InputError(f"the logs are for different tasks: {'; '.join(differ.values())}; plot each task's logs separately "
                         "(rlff report FOLDER draws one figure per task)")


def curve_names(runs: Sequence[LoggedRun]) -> list[str]:
    """A legend name for each run's curve: the method, then each setting that differs between the
    runs where the run's value is not the default, then, for names still alike, the file's name."""
    differing = [(said, default) for said, default in SETTINGS.values() if len({said(run) for run in runs}) > 1]
    names = []
    for run in runs:
        words = [said(run) for said, default in differing if said(run) != default]
        names.append(", ".join([run.method, *words]))
    return [f"{name} ({run.file})" if names.count(name) > 1 else name for name, run in zip(names, runs, strict=True)]


def shared_settings(runs: Sequence[LoggedRun]) -> list[str]:
    """What the runs of one task (:func:`require_one_task`) share beyond the basket's distance
    that is not the default, in a few words each for a title: the bearing, the rim, a whole-arm
    run's joints, the pedestal, then the settings all of them learned with (``["bearing 60°",
    "binary feedback", "arm speed:0.9"]``)."""
    first = runs[0]
    words = []
    if first.bearing:
        words.append(f"bearing {first.bearing:g}°")
    if first.rim_height != DEFAULT_RIM_HEIGHT:
        words.append(f"rim {first.rim_height:g} m")
    if len(first.joints) > 1:
        words.append(f"joints {', '.join(first.joints)}")
    if first.pedestal:
        words.append(f"pedestal {first.pedestal:g} m")
    words += [said(first) for said, default in SETTINGS.values()
              if len({said(run) for run in runs}) == 1 and said(first) != default]
    return words
