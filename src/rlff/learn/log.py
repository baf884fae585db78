"""The attempts log: one JSON line per executed attempt, written the moment the attempt ends.

Layout (JSON Lines, UTF-8)::

    {"format": "rlff-attempts", "version": 1, "run": {...}}      # header: what the run is
    {"attempt": 1, "hit": false, "miss": -0.41, ...}              # one line per attempt
    {"attempt": 2, ...}

Crash safety: each line is appended with a single write, then flushed and fsync'ed, so after a
crash the file holds every finished attempt and at most one partial last line. Reading detects
that partial line (no newline at the end, or not valid JSON), drops it and reports it; a bad
line anywhere else means the file was damaged or edited and is an error naming the line.
A run resumes from the log only if the log's header describes the same run (basket, feedback,
update, seed, demonstrations); otherwise the mismatch is an error, never silently mixed.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from rlff.errors import InputError
from rlff.learn.attempt import Attempt

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
    """

    attempts: list[Attempt]
    dropped_partial_line: bool


class AttemptLog:
    """An append-only, crash-safe attempts log bound to one run.

    Opening an existing file resumes it: the header must describe ``run`` exactly, complete
    attempts are loaded into :attr:`contents`, a partial last line is cut off the file.

    Parameters
    ----------
    path : str or Path
        The JSONL file; created (with its folder) when absent.
    run : dict
        JSON-serialisable description of the run; compared on resume.

    Raises
    ------
    InputError
        The file is not an attempts log, belongs to another run, or is damaged before its last
        line.
    """

    def __init__(self, path: str | Path, run: dict[str, Any]):
        self.path = Path(path)
        self.run = json.loads(json.dumps(run))  # normalised as it will read back
        if self.path.is_dir():
            raise InputError(f"{self.path}: is a folder, not an attempts log file")
        if self.path.exists() and self.path.stat().st_size > 0:
            self.contents = self._resume()
        else:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self._append({"format": FORMAT, "version": VERSION, "run": self.run})
            self.contents = LogContents([], False)

    def append(self, attempt: Attempt) -> None:
        """Write one attempt as a line and make it durable (flush + fsync) before returning."""
        self._append(attempt.to_json())

    def _append(self, record: dict[str, Any]) -> None:
        line = json.dumps(record, allow_nan=False, separators=(",", ":")) + "\n"
        with open(self.path, "a", encoding="utf-8") as handle:
            handle.write(line)
            handle.flush()
            os.fsync(handle.fileno())

    def _resume(self) -> LogContents:
        raw = self.path.read_bytes()
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
                raise InputError(f"{self.path}, line {number}: corrupt attempts log (not a JSON object)")
            records.append(record)
        if not records:
            raise InputError(f"{self.path}: corrupt attempts log (no complete header line)")
        self._check_header(records[0])
        attempts = []
        for number, record in enumerate(records[1:], start=2):
            try:
                attempt = Attempt.from_json(record)
            except (KeyError, TypeError, ValueError) as exc:
                raise InputError(f"{self.path}, line {number}: corrupt attempt record ({exc})") from None
            if attempt.index != len(attempts) + 1:
                raise InputError(
                    f"{self.path}, line {number}: attempt {attempt.index} out of order "
                    f"(expected {len(attempts) + 1})"
                )
            attempts.append(attempt)
        good = b"".join(line + b"\n" for line in lines[: len(records)])
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
        return LogContents(attempts, dropped)

    def _check_header(self, header: dict[str, Any]) -> None:
        if header.get("format") != FORMAT:
            raise InputError(f"{self.path}, line 1: not an rlff attempts log (format {header.get('format')!r})")
        if header.get("version") != VERSION:
            raise InputError(f"{self.path}, line 1: unsupported attempts log version {header.get('version')!r}")
        logged = header.get("run")
        if not isinstance(logged, dict):
            raise InputError(f"{self.path}, line 1: corrupt attempts log (no run description)")
        for key in sorted(set(logged) | set(self.run)):
            if logged.get(key) != self.run.get(key):
                raise InputError(
                    f"{self.path}: the log belongs to another run ({key} = {logged.get(key)!r} in the "
                    f"log, {self.run.get(key)!r} now); use another --log file"
                )


def _parse(line: bytes) -> dict[str, Any] | None:
    """A log line as a JSON object, or None when it is not one."""
    try:
        record = json.loads(line.decode("utf-8"))
    except (UnicodeDecodeError, ValueError):
        return None
    return record if isinstance(record, dict) else None
