"""The attempts log: one JSON line per executed attempt, written the moment the attempt ends.

Layout (JSON Lines, UTF-8)::

    {"format": "rlff-attempts", "version": 1, "run": {...}, "budget": 20}   # header: what the run is
    {"attempt": 1, "hit": false, "miss": -0.41, ...}                         # one line per attempt
    {"attempt": 2, ...}

``budget`` (added 2026-12-07, without a new version: a reader that does not know it reads the
log as before, and a log without it reads with the budget unknown) is the attempts the run that
wrote the last attempt was given. It is not part of what the run is (``run``): a run resumed
with another ``--budget`` continues the log, and rewrites the header with its own budget as it
appends its first attempt (the whole file replaced at once, as a new log is written), so that
the log says how many attempts its last run could have made.

Crash safety: each line is appended with a single write, then flushed and fsync'ed, so after a
crash the file holds every finished attempt and at most one partial last line. Reading detects
that partial line (no newline at the end, or not valid JSON), drops it and reports it; a bad
line anywhere else means the file was damaged or edited and is an error naming the line.
A run resumes from the log only if the log's header describes the same run (basket, feedback,
update, seed, demonstrations, the robot's name, digest and ROS names: :func:`robot_record`);
otherwise the mismatch is an error naming the first field that differs, never silently mixed.

One run at a time: opening a log takes an exclusive lock on ``<log>.lock`` (``flock`` through
filelock's :func:`filelock.lock_descriptor`, released by the kernel if the run dies) and writes
the holder's pid, host and start time into it; a second run on the same log is refused with
that holder named. The lock file is left in place and emptied on release.

A run refused before its first attempt leaves no file it created: a new log is written with the
run's first attempt (its header and that line at once), an existing one is not changed before it
(but for a partial last line cut off, or a last newline added), and on release a run that logged
no attempt removes the lock file and the folders it created. It removes the lock file while it
holds it, and a run that locked a lock file no longer at its path locks the one there instead
(:meth:`AttemptLog._acquire`), so two runs never hold two files of one name.
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from filelock import unlock_descriptor

from rlff.errors import InputError
from rlff.fileio import (
    path_kind,
    prepare_output,
    refused,
    refused_in_place,
    write_text,
)
from rlff.kinds import file_kind
from rlff.learn.attempt import Attempt
from rlff.lockfile import claim_lock, lock_holder

if TYPE_CHECKING:
    from rlff.robot.description import Robot
    from rlff.robot.mapping import ArmMapping, RobotMapping

FORMAT = "rlff-attempts"
VERSION = 1


@dataclass(frozen=True)
class LogContents:
    """What a log held when it was opened.

    Parameters
    ----------
    attempts : list of Attempt
        Every complete attempt, in order.
    dropped_partial_line : bool
        A partial last line (a crash mid-write) was found and removed.
    budget : int or None
        The attempts the run that wrote them was given (the header's ``budget``); None in a log
        written before rlff recorded it.
    """

    attempts: list[Attempt]
    dropped_partial_line: bool
    budget: int | None = None


class LogInUse(InputError):
    """Another run holds the attempts log."""


class AttemptLog:
    """An append-only, crash-safe attempts log bound to one run, held by one run at a time.

    Opening an existing file resumes it: the header must describe ``run`` exactly, complete
    attempts are loaded into :attr:`contents`, a partial last line is cut off the file. A log
    that holds no attempt (its run stopped before the first throw) is started afresh for ``run``
    at its first attempt. The log stays locked until :meth:`close` (or the end of a ``with``
    block); a run that appended no attempt by then leaves no file it created (module notes).

    Parameters
    ----------
    path : str or Path
        The JSONL file; created (with its folder) at the first attempt when absent.
    run : dict
        JSON-serialisable description of the run; compared on resume.
    options : mapping of str to (str, str or None), optional
        The run's (dotted) keys a user sets with an option: key -> (the option, how a header
        without the key reads, e.g. ``"'sim'"``; None when the key is always written). On resume a
        difference in these is named first, in this order, with its option.
    budget : int, optional
        The most attempts the run makes, counting those resumed: the header's ``budget``, not
        compared on resume (a resumed run that appends an attempt writes its own); None: the
        header records none.

    Raises
    ------
    LogInUse
        Another run holds the log (the message names its pid and host).
    InputError
        The path is no regular file (:func:`require_log_file`), or the file is not an attempts
        log, belongs to another run, or is damaged before its last line.
    """

    def __init__(self, path: str | Path, run: dict[str, Any],
                 options: Mapping[str, tuple[str, str | None]] | None = None, budget: int | None = None):
        self.path = Path(path)
        self.run = json.loads(json.dumps(run))  # normalised as it will read back
        self.options = dict(options or {})
        self.budget = budget
        #: What this run created, removed again by :meth:`close` if it appends no attempt: the
        #: log's missing folders (deepest first) and, once locked, whether the lock file is new.
        self._new_folders = [folder for folder in self.path.parents if not folder.exists()]
        self._new_lock = False
        self._lock: int | None = None
        self._appended = False
        #: The text a new log, or one started afresh, begins with, or a resumed one's with its
        #: header rewritten for another budget: written whole with the first attempt appended.
        self._unwritten: str | None = None
        require_log_file(self.path)  # before the lock file beside it is made
        try:
            prepare_output(self.path)  # a folder, or a file where its folder should be, is refused
            self._lock, self._new_lock = self._acquire()
            if self.path.exists() and self.path.stat().st_size > 0:
                self.contents = self._resume()
            else:
                self._unwritten = self._header()
                self.contents = LogContents([], False, budget)
        except BaseException:
            self.close()
            raise

    def _header(self) -> str:
        """The header line of this run: its run description and its budget."""
        budget = {} if self.budget is None else {"budget": self.budget}
        return _line({"format": FORMAT, "version": VERSION, "run": self.run, **budget})

    @property
    def lock_path(self) -> Path:
        """The lock file beside the log: ``<log>.lock``."""
        return self.path.with_name(self.path.name + ".lock")

    def close(self) -> None:
        """Release the log for other runs (idempotent); without an attempt appended, remove the
        lock file and the folders this run created."""
        if self._lock is not None:
            if not self._appended and self._new_lock and _is_at(self._lock, self.lock_path):
                self.lock_path.unlink()  # while held: whoever opened it in the meantime locks the next one
            os.ftruncate(self._lock, 0)
            unlock_descriptor(self._lock)
            os.close(self._lock)
            self._lock = None
        if not self._appended:
            for folder in self._new_folders:
                try:
                    folder.rmdir()
                except OSError:  # not empty (another file came), or already gone
                    break
            self._new_folders = []

    def __enter__(self) -> AttemptLog:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def _acquire(self) -> tuple[int, bool]:
        """Lock ``<log>.lock`` without waiting and write the holder into it; the descriptor, and
        whether this run created the file.

        A run that logged nothing removes its lock file while it holds it: a lock taken on that
        file once it is gone is let go, and the file at the path now locked instead.
        """
        while True:
            try:
                fd, created = os.open(self.lock_path, os.O_RDWR | os.O_CREAT | os.O_EXCL, 0o644), True
            except FileExistsError:
                try:
                    fd, created = os.open(self.lock_path, os.O_RDWR), False
                except FileNotFoundError:  # removed since: create it
                    continue
            holder = lock_holder(fd)
            if holder is not None:
                raise LogInUse(f"{self.path} is in use by {holder} (lock file {self.lock_path}); wait for "
                               "that run to end, or use another --log file")
            if _is_at(fd, self.lock_path):
                break
            unlock_descriptor(fd)
            os.close(fd)
        claim_lock(fd, "rlff learn")
        return fd, created

    def append(self, attempt: Attempt) -> None:
        """Write one attempt as a line and make it durable (flush + fsync) before returning."""
        self._append(attempt.to_json())

    def _append(self, record: dict[str, Any]) -> None:
        if self._unwritten is not None:
            # the header and the first attempt, whole or not at all: a log is never left without one
            write_text(self.path, self._unwritten + _line(record))
            self._unwritten = None
        else:
            try:
                with open(self.path, "a", encoding="utf-8") as handle:
                    handle.write(_line(record))
                    handle.flush()
                    os.fsync(handle.fileno())
            except OSError as exc:
                if refused(exc):  # a full disk, a quota, a file-size limit: a write() names no file
                    raise refused_in_place(self.path, exc) from None
                raise
        self._appended = True

    def _resume(self) -> LogContents:
        if not is_attempts_log(self.path):  # a model had read as "line 1: corrupt attempts log"
            raise InputError(f"{self.path} is {file_kind(self.path)}, not an rlff attempts log: a learning run "
                             "resumes only the log (JSONL) an earlier run wrote; give another path to start one")
        raw = self.path.read_bytes()
        lines, records, dropped = _records(self.path, raw)
        if len(records) == 1 and first_difference(_run_of(self.path, records[0]), self.run) is not None:
            # an attempts log of a run that stopped before its first throw (no joint states, a
            # refused basket): nothing in it to keep, and its settings must not bind the next run
            # (an older header, without what this version records, is written anew whole), from
            # this run's first attempt on
            self._unwritten = self._header()
            return LogContents([], dropped, self.budget)
        self._check_header(records[0])
        attempts = _attempts(self.path, records)
        logged_budget = _budget_of(self.path, records[0])
        good = b"".join(line + b"\n" for line in lines[: len(records)])
        if self.budget is not None and logged_budget != self.budget:
            # resumed with another budget: the header says this run's, rewritten with its first attempt
            self._unwritten = self._header() + good.split(b"\n", 1)[1].decode("utf-8")
        if good != raw:
            # Either cut the partial line (good is a prefix of raw) or add the missing newline.
            with open(self.path, "r+b") as handle:
                if raw.startswith(good):
                    handle.truncate(len(good))
                else:
                    handle.seek(0, os.SEEK_END)
                    handle.write(b"\n")
                handle.flush()
                os.fsync(handle.fileno())
        return LogContents(attempts, dropped, logged_budget)

    def _check_header(self, header: dict[str, Any]) -> None:
        logged = _run_of(self.path, header)
        run = run_as_logged(logged, self.run)
        # what the user chose is named before what follows from it (other joints drive other
        # columns of the demonstrations, so their fingerprint differs too; --until centred adds
        # a centre share)
        chosen = (first_difference(_at(logged, key), _at(run, key), key) for key in self.options)
        difference = next((found for found in chosen if found is not None), None) or first_difference(logged, run)
        if difference is None:
            return
        key, before, now = difference
        option, absent = self.options.get(key) or self.options.get(key.split(".")[0]) or (None, None)

        def shown(value: Any) -> str:
            return absent if value is None and absent is not None else brief(value)

        if key == "demos":  # no option sets it: say what changed
            raise InputError(f"{self.path}: the log belongs to another run: {demonstrations_changed(before, now)}")
        before, now = as_listed(key, (before, now), (logged, run))
        # the log's own method resumes it: one of the caller's is named MODULE:CLASS on the command line
        resume = (f", or resume it with --update {before} (for a method of your own, MODULE:CLASS of the class "
                  f"named {before!r})" if key == "update" and isinstance(before, str) else "")
        raise InputError(
            f"{self.path}: the log belongs to another run ({key} = {shown(before)} in the log, {shown(now)} now"
            f"{f', from {option}' if option else ''}); use another log_path (--log){resume}"
        )


def require_log_file(path: str | Path) -> None:
    """Raise :class:`InputError` unless ``path`` is a regular file (a log to resume) or nothing
    yet (a new log): a device, a FIFO, a socket, a folder or a broken link, named as such
    (:func:`rlff.fileio.path_kind`). A device or a FIFO had passed as an output: the lock file
    was made beside it (``/dev/full.lock``) and a FIFO blocked the run at its first attempt."""
    kind = path_kind(path)
    if kind not in (None, "a file"):
        raise InputError(f"{path} is {kind}, not a file: an attempts log is a regular file, resumed when it "
                         "exists, or a new path; give a file's path (e.g. attempts.jsonl)")


def _is_at(fd: int, path: Path) -> bool:
    """Whether the open file ``fd`` is the file at ``path`` (not one removed, or replaced, since)."""
    try:
        here = path.stat()
    except FileNotFoundError:
        return False
    held = os.fstat(fd)
    return (held.st_dev, held.st_ino) == (here.st_dev, here.st_ino)


def demonstrations_changed(logged: Any, now: Any) -> str:
    """Why a log whose header's ``demos`` (the digest of the demonstrations its run learned from,
    :func:`rlff.learn.demos.fingerprint`) is ``logged`` does not resume a run whose digest is
    ``now``, and what to do, in words: the digest alone had named no option and no cause. The
    header check names the options that also choose the demonstrations (the robot, ``--joints``,
    ``--height``) first, so here only their contents differ: rows appended (the day's batch added
    to the file), another file, or the same cleaned by another ``--preset``."""
    return (f"the demonstrations changed since it was written (digest {brief(logged)} in the log, {brief(now)} now): "
            "a batch appended to their file, another file, or the same one cleaned by another --preset gives other "
            "throws. Resume it with the demonstrations (and --preset) it was made with, or learn from these with a "
            "new --log file")


def robot_record(mapping: RobotMapping | ArmMapping) -> dict[str, Any]:
    """What the log's header keeps of the robot: its name, a digest and the description digested,
    and where its controller is on the ROS graph.

    The description is what a throw depends on: every joint's limits (all the numbers of its
    robot-file table), the geometry and the human-to-robot mapping actually used; not where the
    file lies. A whole-arm mapping is described by its driven joints (each with its human joint,
    offset and scale), time scale, bearing joint and start pose; a one-joint one as it always was.
    ``ros`` is the robot file's ``[ros]`` table (:func:`ros_record`): which arm's controller the
    attempts went to, outside the digest (the throw is the same under any names). A log resumes
    only with the same name, description and ROS names, and a changed one is named field by field
    (``robot.description.mapping.angle_scale``, ``robot.ros.action``).
    """
    from rlff.robot.planned_for import description_digest, robot_description

    robot = mapping.robot
    # a trajectory file's description of the robot, and the mapping: a log's throws depend on both
    description = {**robot_description(robot), "mapping": _mapping_description(mapping)}
    return {"name": robot.name, "digest": description_digest(description), "description": description,
            "ros": ros_record(robot)}


def ros_record(robot: Robot) -> dict[str, Any]:
    """The robot file's ``[ros]`` table as a log keeps it: the action, the joint states and
    trajectory topics, and under ``joints`` each joint the controller names or counts otherwise
    (``[ros.joints]``: its name, offset in rad and sign; a table that keeps the joint as rlff has
    it changes nothing and is left out)."""
    names = robot.ros
    joints = {joint: {"name": entry.name, "offset": entry.offset, "sign": entry.sign}
              for joint, entry in names.joints.joints.items() if not names.joints.keeps(joint)}
    return {"action": names.action, "joint_states": names.joint_states, "trajectory_topic": names.trajectory_topic,
            "joints": joints}


#: Keys of :func:`robot_record` that logs written before them lack (``ros``: logs written until 2026-12-06).
#: Such a log resumes without comparing them: with its own robot file as it did, whatever that
#: file's ROS names (the log never said which they were).
LATER_ROBOT_KEYS = ("ros",)


def run_as_logged(logged: dict[str, Any], run: dict[str, Any]) -> dict[str, Any]:
    """``run`` (a header's run description of now) as the header ``logged`` could have held it, for
    comparing the two: its robot record without the :data:`LATER_ROBOT_KEYS` that ``logged``'s lacks."""
    robot, then = run.get("robot"), logged.get("robot")
    if not isinstance(robot, dict) or not isinstance(then, dict):
        return run
    return {**run, "robot": {key: value for key, value in robot.items()
                             if key in then or key not in LATER_ROBOT_KEYS}}


def without_ros(record: Any) -> Any:
    """A robot record (:func:`robot_record`) without its ROS names: whose throw it is and what the
    throw depends on, as replaying a logged throw and carrying its offset compare it (the same
    throw, planned the same way, whichever controller it goes to)."""
    return {key: value for key, value in record.items() if key != "ros"} if isinstance(record, dict) else record


def _mapping_description(mapping: RobotMapping | ArmMapping) -> dict[str, Any]:
    """The numbers of a mapping that decide what the robot does (see :func:`robot_record`)."""
    from rlff.robot.mapping import ArmMapping

    if not isinstance(mapping, ArmMapping):
        return {"joint": mapping.joint, "start_pose": dict(mapping.start_pose),
                "angle_offset": mapping.angle_offset, "angle_scale": mapping.angle_scale,
                "velocity_scale": mapping.velocity_scale}
    return {"driven": {m.joint: {"human": m.human, "offset": m.offset, "scale": m.scale} for m in mapping.joints},
            "time_scale": mapping.time_scale, "bearing_joint": mapping.bearing_joint,
            "start_pose": dict(mapping.start_pose)}


def read_log(path: str | Path) -> tuple[dict[str, Any], LogContents]:
    """The run description and the attempts of a log, read without changing or locking the file.

    A partial last line (a run interrupted mid-write, or one still writing) is left out.

    Raises
    ------
    InputError
        No such file, a folder, not an attempts log, or a damaged line before the last.
    """
    path = Path(path)
    if path.is_dir():
        raise InputError(f"{path}: is a folder; an attempts log is a file (the .jsonl an earlier run's --log wrote)")
    if not path.is_file():
        kind = path_kind(path)  # a FIFO or a device had been called absent
        raise InputError(f"{path}: " + (f"{kind}, not an attempts log (a .jsonl file an earlier run's --log wrote)"
                                         if kind else "no such attempts log"))
    raw = path.read_bytes()
    if not raw.strip():
        raise InputError(f"{path}: an empty file, not an rlff attempts log")
    if not is_attempts_log(path):  # a model had read as "line 1: corrupt attempts log", a damaged log
        raise InputError(f"{path} is {file_kind(path)}, not an rlff attempts log: give the attempts logs (JSONL) "
                         "that rlff learn --log writes")
    _, records, dropped = _records(path, raw)
    return _run_of(path, records[0]), LogContents(_attempts(path, records), dropped, _budget_of(path, records[0]))


def is_attempts_log(path: str | Path) -> bool:
    """Whether the first line of ``path`` is the header of an attempts log, or the start of one
    cut short (a damaged log, which :func:`read_log` then refuses as such)."""
    try:
        with open(path, "rb") as handle:
            line = handle.readline().rstrip(b"\n")
    except OSError:
        return False
    first = _parse(line)
    if first is None:
        return line.startswith(_HEADER_START)
    return first.get("format") == FORMAT


#: How every attempts log begins (:func:`_line` writes the header's ``format`` first).
_HEADER_START = b'{"format":"' + FORMAT.encode() + b'"'


def _records(path: Path, raw: bytes) -> tuple[list[bytes], list[dict[str, Any]], bool]:
    """The lines of a log, its complete records (header first) and whether a partial last line
    was left out."""
    lines = raw.split(b"\n")
    # A complete file ends with a newline, so the final element is empty. Anything else is a
    # last write cut short: kept if it still parses (only its newline is missing), else dropped.
    tail = lines.pop()
    dropped = False
    if tail:
        if _parse(tail) is None:
            dropped = True
        else:
            lines.append(tail)
    records: list[dict[str, Any]] = []
    for number, line in enumerate(lines, start=1):
        record = _parse(line)
        if record is None:
            if number == len(lines) and not dropped:
                dropped = True  # garbled last line: the crash hit the final write
                break
            raise InputError(f"{path}, line {number}: corrupt attempts log (not a JSON object)")
        records.append(record)
    if not records:
        raise InputError(f"{path}: corrupt attempts log (no complete header line)")
    return lines, records, dropped


def _run_of(path: Path, header: dict[str, Any]) -> dict[str, Any]:
    """The run description of a header line, checked."""
    if header.get("format") != FORMAT:
        raise InputError(f"{path}, line 1: not an rlff attempts log (format {header.get('format')!r})")
    if header.get("version") != VERSION:
        raise InputError(f"{path}, line 1: unsupported attempts log version {header.get('version')!r}")
    run = header.get("run")
    if not isinstance(run, dict):
        raise InputError(f"{path}, line 1: corrupt attempts log (no run description)")
    return run


def _budget_of(path: Path, header: dict[str, Any]) -> int | None:
    """The ``budget`` of a header line, checked; None in a header without one (a log written
    before rlff recorded it)."""
    budget = header.get("budget")
    if budget is None:
        return None
    if isinstance(budget, bool) or not isinstance(budget, int) or budget < 1:
        raise InputError(f"{path}, line 1: corrupt attempts log (budget {budget!r}, not a whole number of attempts "
                         ">= 1)")
    return budget


def _attempts(path: Path, records: list[dict[str, Any]]) -> list[Attempt]:
    """The attempts of a log's records after the header, numbered 1, 2, ... in order."""
    attempts = []
    for number, record in enumerate(records[1:], start=2):
        try:
            attempt = Attempt.from_json(record)
        except (KeyError, TypeError, ValueError, OverflowError) as exc:
            raise InputError(f"{path}, line {number}: corrupt attempt record ({exc})") from None
        if attempt.index != len(attempts) + 1:
            raise InputError(
                f"{path}, line {number}: attempt {attempt.index} out of order (expected {len(attempts) + 1})"
            )
        attempts.append(attempt)
    return attempts


def first_difference(logged: Any, now: Any, where: str = "") -> tuple[str, Any, Any] | None:
    """The first leaf that differs between two JSON values, as (dotted key, logged, now), or None.

    Nested objects are compared key by key (in sorted order), so a changed robot description is
    reported as e.g. ``robot.throwing.angle_scale`` rather than as two whole descriptions.
    """
    if isinstance(logged, dict) and isinstance(now, dict):
        for key in sorted(set(logged) | set(now)):
            found = first_difference(logged.get(key), now.get(key), f"{where}.{key}" if where else key)
            if found is not None:
                return found
        return None
    return None if logged == now else (where, logged, now)


def _at(record: dict[str, Any], key: str) -> Any:
    """The value at a dotted ``key`` of nested dicts, or None where any part is absent."""
    for part in key.split("."):
        record = record.get(part) if isinstance(record, dict) else None
    return record


def as_listed(key: str, values: tuple[Any, Any], runs: tuple[dict[str, Any], dict[str, Any]]) -> tuple[Any, Any]:
    """Two values of a header's ``key`` (a log's and this run's, each from its run in ``runs``) as a
    message shows them: a whole-arm run's ``joints`` in the order of its robot's joints, as a user
    lists them (joint_2, joint_3), where the header keeps the mapping's (the elbow's joint first,
    the others as given), which older logs resume by; as they are when both hold the same joints
    (their order is the difference), and anything else."""
    if key != "joints":
        return values
    if all(isinstance(value, list) for value in values) and sorted(map(str, values[0])) == sorted(map(str, values[1])):
        return values
    listed = []
    for value, run in zip(values, runs, strict=True):
        robot = _at(run, "robot.description.joints")
        order = list(robot) if isinstance(robot, dict) else []
        ordered = isinstance(value, list) and all(joint in order for joint in value)
        listed.append(sorted(value, key=order.index) if ordered else value)
    return listed[0], listed[1]


def brief(value: Any, width: int = 60) -> str:
    """``repr(value)`` for a message, cut to ``width`` characters (a whole description is long)."""
    text = repr(value)
    return text if len(text) <= width else text[: width - 1] + "…"


def _line(record: dict[str, Any]) -> str:
    """One JSONL line: compact JSON and a newline."""
    return json.dumps(record, allow_nan=False, separators=(",", ":")) + "\n"


def _parse(line: bytes) -> dict[str, Any] | None:
    """A log line as a JSON object, or None when it is not one."""
    try:
        record = json.loads(line.decode("utf-8"))
    except (UnicodeDecodeError, ValueError):
        return None
    return record if isinstance(record, dict) else None
