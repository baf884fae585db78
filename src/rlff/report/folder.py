"""A run's output folder: held by one run at a time, and replaced only where a run wrote it.

A run (``rlff demo``) says up front every file it writes or may write, ``writes``, by name
(``demos.csv``, ``attempts/calibrate.jsonl``, ``figures/bic.png``; ``*`` for one name only where
the name is known as the run writes it, a frame of a rendered throw), all of them of the names
a run of its program writes, whatever its options, ``names`` (``attempts/*.jsonl``,
``figures/*.png``, ...; ``*`` is one name that does not start with a dot). It lists every file in
the folder's ``.rlff-run`` before it writes it, with its SHA-256 once the run has finished. The
next run into the folder removes what that listing names, unchanged since, before its first
file, so that a smaller run (``rlff demo --small`` after a full one) leaves none of the earlier
run's logs or figures to be taken for its own. A file of ``writes`` that the listing does not
name, or one changed since the run wrote it, may be someone's own (an attempts log of ``rlff
learn``, an edited figure, a ``run.json`` of :func:`rlff.report.write_run`): the folder is
refused before anything is written or removed. Any other file is left as it is, of the names
the program writes or not (``figures/mine.png``, ``attempts/notes.jsonl``): the run neither
writes nor removes it.

One run at a time: a run holds an exclusive lock on ``.rlff-run.lock`` (``flock`` through
filelock's :func:`filelock.lock_descriptor`, released by the kernel if the run dies) with its pid,
host and start time written in it; a second run into the folder is refused naming that holder, as
a second ``rlff learn`` on one attempts log is (:mod:`rlff.learn.log`). The lock file is left in
place and emptied on release.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import re
from collections.abc import Sequence
from fnmatch import fnmatchcase
from pathlib import Path

from filelock import unlock_descriptor

from rlff.errors import InputError
from rlff.fileio import write_text
from rlff.lockfile import claim_lock, lock_holder

#: The listing of the files the folder's last run wrote, and the lock a run holds.
LISTING = ".rlff-run"
LOCK = ".rlff-run.lock"
FORMAT = "rlff-run-files"
VERSION = 1


class FolderInUse(InputError):
    """Another run holds the folder."""


class RunPaths:
    """Where a run's files go inside ``path``, by their paths relative to it (POSIX, ``attempts/x.jsonl``).

    A plain folder: nothing is recorded (:class:`RunFolder` lists each file before it is written).
    """

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)

    def file(self, relative: str) -> Path:
        """The path of the file ``relative``."""
        self._claim(relative)
        return self.path / relative

    def folder(self, relative: str) -> Path:
        """The path of the folder ``relative``, every file of which the run writes."""
        self._claim(f"{relative.rstrip('/')}/")
        return self.path / relative

    def figure(self, stem: str) -> Path:
        """``figures/STEM``, the path a plot is given: it writes ``STEM.png`` and ``STEM.svg``."""
        self._claim(f"figures/{stem}.png", f"figures/{stem}.svg")
        return self.path / "figures" / stem

    def log(self, relative: str) -> Path:
        """The path of the attempts log ``relative``; its lock file ``relative.lock`` goes beside it."""
        self._claim(relative, f"{relative}.lock")
        return self.path / relative

    def _claim(self, *names: str) -> None:
        """Files (``folder/``: every file in it) about to be written; a plain folder records nothing."""


class RunFolder(RunPaths):
    """A run's output folder, held by this run: created, locked, checked and cleared of the last run's files.

    Parameters
    ----------
    path : str or Path
        The folder (created with its parents when missing).
    writes : sequence of str
        The files this run writes, or may write, relative to ``path``: each by name, ``*`` for one
        name only where the run knows it as it writes the file (``figures/frames/frame_*.png``);
        every file the run writes must be one of them, and each must be of ``names``.
    program : str
        What runs, for the lock's holder and the messages (``rlff demo``).
    names : sequence of str, optional
        The names of every file a run of ``program`` may write, whatever its options, ``*`` for
        one name (``figures/*.png``): the last run's listing names only files of these to be
        removed. Default ``writes``.

    Raises
    ------
    FolderInUse
        Another run holds the folder (the message names its pid and host).
    InputError
        The folder holds files of ``writes`` that its last run did not list as its own, or that
        changed since (:func:`check_run_folder`); or it cannot be created.
    ValueError
        A file of ``writes`` is not of ``names``.
    """

    def __init__(self, path: str | Path, writes: Sequence[str], program: str, *,
                 names: Sequence[str] | None = None) -> None:
        super().__init__(path)
        self.writes = tuple(writes)
        self.names = self.writes if names is None else tuple(names)
        self.program = program
        _require_of_names(self.writes, self.names, program)
        try:
            self.path.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise InputError(f"{self.path}: cannot create the folder ({exc.strerror})") from None
        self._lock: int | None = _acquire(self.path / LOCK, program)
        try:
            earlier = _earlier_files(self.path, self.writes, self.names, program)
            _remove(self.path, earlier)
            self.files: dict[str, str | None] = {}  # what this run wrote: path -> SHA-256 once finished
            self._write_listing(finished=False)
        except BaseException:
            self.close()
            raise

    def _claim(self, *names: str) -> None:
        """List ``names`` (``folder/``: the files of ``writes`` in it) as this run's, before they are written.

        Raises
        ------
        ValueError
            A name (a folder holding none) is not of ``writes``: a bug, the check before the run
            would not have seen a file of that name.
        """
        for name in names:
            if not _listable(name, self.writes):
                raise ValueError(f"{name}: not among the files this {self.program} said it would write "
                                 f"({', '.join(self.writes)})")
        if any(name not in self.files for name in names):
            self.files.update((name, None) for name in names)
            self._write_listing(finished=False)

    def finish(self) -> None:
        """List every file the run wrote with its SHA-256: a later run replaces them only as they are now."""
        written: dict[str, str | None] = {}
        for key in self.files:
            names = _files_under(self.path, key) if key.endswith("/") else [key]
            for name in filter(lambda name: _is_written(name, self.writes), names):
                digest = _sha256(self.path / name)
                if digest is not None:
                    written[name] = digest
        self.files = written
        self._write_listing(finished=True)

    def close(self) -> None:
        """Release the folder for other runs (idempotent)."""
        if self._lock is None:
            return
        os.ftruncate(self._lock, 0)
        unlock_descriptor(self._lock)
        os.close(self._lock)
        self._lock = None

    def __enter__(self) -> RunFolder:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def _write_listing(self, *, finished: bool) -> None:
        write_text(self.path / LISTING, json.dumps(
            {"format": FORMAT, "version": VERSION, "program": self.program, "finished": finished, "files": self.files},
            indent=1) + "\n")


def check_run_folder(path: str | Path, writes: Sequence[str], program: str, *,
                     names: Sequence[str] | None = None) -> None:
    """Raise where a :class:`RunFolder` of ``path`` would be refused, changing nothing.

    Raises
    ------
    FolderInUse
        Another run holds the folder.
    InputError
        The folder holds files of ``writes`` that its last run did not list as its own (or none:
        no listing), or that changed since that run finished.
    """
    path = Path(path)
    names = writes if names is None else names
    _require_of_names(writes, names, program)
    if not path.is_dir():
        return
    if (path / LOCK).exists():
        with contextlib.suppress(OSError):  # gone meanwhile, or not ours to open: the run itself will say
            os.close(_acquire(path / LOCK, program, create=False, claim=False))
    _earlier_files(path, writes, names, program)


def _require_of_names(writes: Sequence[str], names: Sequence[str], program: str) -> None:
    """Raise ValueError (a bug) for a file of ``writes`` that is not of ``names``: the listing of
    the run that wrote it would not let the next run remove it."""
    strays = [name for name in writes if not _is_written(name, names)]
    if strays:
        raise ValueError(f"{', '.join(strays)}: not of the names {program} writes ({', '.join(names)})")


def _acquire(lock: Path, program: str, *, create: bool = True, claim: bool = True) -> int:
    """Lock ``lock`` without waiting and (``claim``) write the holder into it; the descriptor
    (released when closed). ``claim=False`` only tries: it releases the lock at once."""
    fd = os.open(lock, os.O_RDWR | (os.O_CREAT if create else 0), 0o644)
    holder = lock_holder(fd)
    if holder is not None:
        raise FolderInUse(f"{lock.parent} is in use by {holder} (lock file {lock}); wait for that run to end, "
                          "or give another folder with -o")
    if not claim:
        unlock_descriptor(fd)
        return fd
    claim_lock(fd, program)
    return fd


def _earlier_files(path: Path, writes: Sequence[str], names: Sequence[str], program: str) -> list[str]:
    """The files of ``names`` in ``path`` that its last run listed, every one as that run wrote it:
    the files to remove. Other files of ``names`` are left where the run does not write them.

    Raises
    ------
    InputError
        Naming the files of ``writes`` the run would replace that are not the last run's: not
        in its listing, or changed since it finished.
    """
    found = _read_listing(path, names)
    listing = found or {}
    folders = [key for key in listing if key.endswith("/")]
    earlier, foreign, changed = [], [], set()
    for name in _present(path, names):
        listed = name in listing or any(name.startswith(folder) for folder in folders)
        if listed and (listing.get(name) is None or _sha256(path / name) == listing[name]):
            earlier.append(name)
        elif _is_written(name, writes):
            foreign.append(name)
            if listed:
                changed.add(name)
    if foreign:
        raise InputError(_refusal(path, foreign, changed, program, listing=found is not None))
    return earlier


def _refusal(path: Path, foreign: Sequence[str], changed: set[str], program: str, *, listing: bool) -> str:
    """The words of a folder refused for the files ``foreign`` the run would write (``changed``:
    those the last run listed, changed since), every one named, and what to do; ``listing``: the
    folder has the listing of a run (a folder of an older run, or of the user's, has none)."""
    files = f"{len(foreign)} file{'s' if len(foreign) > 1 else ''} {program} would write"
    said = _named(foreign, dict.fromkeys(changed, f" (changed since {program} wrote it)"))
    if listing:
        why = f"holds {files} that the last {program} there did not write" + (", or changed since" if changed else "")
        return (f"{path}: {why}: {said}; nothing was written or removed: move or remove those files, or give "
                "another folder with -o")
    return (f"{path}: holds {files}, and no list of the files a run of {program} wrote there ({LISTING}; an "
            f"{program} older than that list kept none), so it cannot tell them from files of yours: {said}; nothing "
            f"was written or removed: if an older {program} wrote them, remove them (or move them out of the folder) "
            f"and run {program} again; if any are yours, move them, or give another folder with -o")


def _named(files: Sequence[str], notes: dict[str, str]) -> str:
    """``files`` (POSIX, relative) for a message, each folder's together and a run of numbered
    files as its first and last: ``run.json, attempts/calibrate.jsonl, figures/ (bic.png,
    bic.svg), figures/frames/ (frame_0000.png to frame_0059.png, throw.gif)``; ``notes``: words
    after a file's name (`` (changed since ...)``)."""
    folders: dict[str, list[str]] = {}
    for name in sorted(files, key=lambda name: ("/" in name, name)):
        folder, _, base = name.rpartition("/")
        folders.setdefault(folder, []).append(base + notes.get(name, ""))
    parts = []
    for folder, words in folders.items():
        if not folder:
            parts += _numbered_runs(words)
        elif len(words) == 1:
            parts.append(f"{folder}/{words[0]}")
        else:
            parts.append(f"{folder}/ ({', '.join(_numbered_runs(words))})")
    return ", ".join(parts)


_NUMBERED = re.compile(r"(\D*)(\d+)(\D*)")


def _numbered_runs(bases: Sequence[str]) -> list[str]:
    """``bases`` with every run of three or more numbered alike and one after another
    (``frame_0000.png``, ``frame_0001.png``, ...) said as ``FIRST to LAST``."""
    words: list[str] = []
    run: list[str] = []

    def close() -> None:
        words.extend([f"{run[0]} to {run[-1]}"] if len(run) >= 3 else run)
        run.clear()

    for base in bases:
        match, last = _NUMBERED.fullmatch(base), _NUMBERED.fullmatch(run[-1]) if run else None
        follows = (match is not None and last is not None and match[1] == last[1] and match[3] == last[3]
                   and len(match[2]) == len(last[2]) and int(match[2]) == int(last[2]) + 1)
        if not follows:
            close()
        run.append(base)
    close()
    return words


def _read_listing(path: Path, names: Sequence[str]) -> dict[str, str | None] | None:
    """The files (and ``folder/`` of files) the last run in ``path`` listed, to their SHA-256
    (None where the run did not finish); None where there is no listing or it is not one.
    Only files of ``names`` count: a listing names nothing else to be removed."""
    try:
        data = json.loads((path / LISTING).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    files = data.get("files") if isinstance(data, dict) and data.get("format") == FORMAT else None
    if not isinstance(files, dict):
        return None
    return {name: digest for name, digest in files.items()
            if isinstance(name, str) and (digest is None or isinstance(digest, str)) and _listable(name, names)}


def _is_written(relative: str, writes: Sequence[str]) -> bool:
    """Whether ``relative`` (POSIX, inside the folder) is of one of the names in ``writes``; no
    part may start with a dot (a temporary file of an atomic write, the listing, the lock)."""
    parts = relative.split("/")
    if any(not part or part.startswith(".") for part in parts):
        return False
    return any(len(pattern.split("/")) == len(parts)
               and all(fnmatchcase(part, name) for part, name in zip(parts, pattern.split("/"), strict=True))
               for pattern in writes)


def _listable(name: str, writes: Sequence[str]) -> bool:
    """Whether a run may list ``name``: a file of the names in ``writes``, or a folder
    (``figures/frames/``) that files of them are in (``figures/frames/frame_*.png``), of which
    the run lists those it wrote once it has finished."""
    if not name.endswith("/"):
        return _is_written(name, writes)
    return any(pattern.startswith(name) and "/" not in pattern[len(name):] for pattern in writes)


def _present(path: Path, writes: Sequence[str]) -> list[str]:
    """The files (and links) in ``path`` of the names in ``writes``, relative to it, sorted."""
    names = [entry.name for entry in path.iterdir() if entry.is_symlink() or not entry.is_dir()]
    for top in {pattern.split("/")[0] for pattern in writes if "/" in pattern}:
        names += _files_under(path, top)
    return sorted(name for name in names if _is_written(name, writes))


def _files_under(path: Path, folder: str) -> list[str]:
    """The files (and links) anywhere under ``path / folder`` outside hidden folders, relative to ``path``."""
    names = []
    for root, dirs, files in os.walk(path / folder):
        dirs[:] = [d for d in dirs if not d.startswith(".")]
        names += [Path(root, name).relative_to(path).as_posix() for name in files]
    return names


def _sha256(path: Path) -> str | None:
    """The SHA-256 of the file at ``path`` (hex), or None where it cannot be read."""
    try:
        with path.open("rb") as handle:
            return hashlib.file_digest(handle, "sha256").hexdigest()
    except OSError:
        return None


def _remove(path: Path, names: Sequence[str]) -> None:
    """Remove the files ``names`` (relative to ``path``) and the folders they leave empty."""
    folders = set()
    for name in names:
        (path / name).unlink(missing_ok=True)
        folders |= {parent for parent in (path / name).parents if parent != path and path in parent.parents}
    for folder in sorted(folders, key=lambda p: len(p.parts), reverse=True):
        with contextlib.suppress(OSError):  # not empty: someone's files beside the run's
            folder.rmdir()
