"""Writing files so that an existing one is only ever replaced by a complete one.

Every writer of rlff (datasets, model.json, trajectories, robot exports and bags, Comau programs,
reports, figures, JSON summaries) goes through :func:`atomic_write` or :func:`atomic_path`: the
content goes to a hidden temporary file in the target's own folder, is flushed and fsync'ed, and
only then renamed over the target with :func:`os.replace`, which POSIX makes atomic within one
file system. A process killed at any moment leaves either the old file or the new one, never a
file cut short (at worst a stray hidden ``.STEM.*.tmp.SUFFIX`` beside it).

Missing output folders are created (as they always were); an output that is an existing folder,
or whose folder is a file, is an :class:`~rlff.errors.InputError` naming the path, and so is a
write the system refuses, at the start or partway (a read-only folder, a full disk, a used-up
quota, a file-size limit): the output the user gave and the system's reason, never the hidden
temporary file, and the output is left as it was.

:func:`check_outputs` refuses, before any work, an output that is one of the inputs or two
outputs that are the same file.
"""

from __future__ import annotations

import contextlib
import errno
import os
import shutil
import sqlite3
import stat
import tempfile
from collections.abc import Iterable, Iterator, Mapping
from pathlib import Path
from typing import IO

from rlff.errors import InputError

_TEMP_SUFFIX = ".tmp"


def _umask_mode() -> int:
    """The mode a plain ``open(path, "w")`` would give a new file (0o666 minus the umask)."""
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


def require_file(path: str | Path) -> Path:
    """``path`` as a Path, or an :class:`InputError` saying it is missing or a folder."""
    path = Path(path)
    if path.is_dir():
        raise InputError(f"{path}: is a folder, not a file")
    if not path.is_file():
        raise InputError(f"{path}: no such file")
    return path


#: The installed rlff package's folder: no output goes inside it (`rlff robot urdf -o` had
#: replaced the built-in robot file with URDF, and every command's default robot broke).
_PACKAGE = Path(__file__).resolve().parent


def check_output_path(path: str | Path, *, folder: bool = False) -> Path:
    """Check, without touching anything, that ``path`` can be made an output.

    Parameters
    ----------
    path : str or Path
        The output file (or folder, with ``folder=True``).
    folder : bool
        The output is a folder (a ROS 2 bag, a frames folder): an existing folder is accepted.

    Returns
    -------
    Path

    Raises
    ------
    InputError
        The path is inside rlff's own package, an existing folder (for a file output), anything
        but a folder (for a folder output: a file, a device, a FIFO, a broken link), or a parent
        of it is a file.
    """
    path = Path(path)
    if _inside(path, _PACKAGE):  # rlff's own files: the built-in robots and presets every run reads
        raise InputError(f"{path}: is inside rlff's own package ({_PACKAGE}), whose built-in robot files and "
                         "presets every run reads; write the output elsewhere")
    if not folder and path.is_dir():
        raise InputError(f"{path}: is a folder; give a file name for the output")
    if folder and (kind := path_kind(path)) not in (None, "a folder"):
        raise InputError(f"{path}: is {kind}, not a folder; give a folder for the output")
    for parent in path.parents:
        if parent.exists():
            if not parent.is_dir():
                raise InputError(f"{path}: {parent} is a file, not a folder")
            break
    return path


def path_kind(path: str | Path) -> str | None:
    """What is at ``path``, for a message: ``"a folder"``, ``"a file"``, ``"a device"``, ``"a FIFO
    (named pipe)"``, ``"a socket"`` (a link: what it leads to), ``"a broken link (to TARGET)"``;
    None where nothing is (or it cannot be looked at)."""
    path = Path(path)
    try:
        mode = path.stat().st_mode
    except FileNotFoundError:
        return f"a broken link (to {os.readlink(path)})" if path.is_symlink() else None
    except OSError:  # a loop of links, a folder not ours to look into: the write itself will say
        return None
    for test, kind in ((stat.S_ISDIR, "a folder"), (stat.S_ISREG, "a file"), (stat.S_ISCHR, "a device"),
                       (stat.S_ISBLK, "a device"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
                       (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return kind
    return None


def prepare_output(path: str | Path, *, folder: bool = False) -> Path:
    """Check that ``path`` can be written (:func:`check_output_path`) and create its missing parent folders.

    Raises
    ------
    InputError
        As :func:`check_output_path`, or the folder cannot be created.
    """
    path = check_output_path(path, folder=folder)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"{path}: cannot create its folder ({exc.strerror})") from None
    return path


def _sync_folder(folder: Path) -> None:
    """Make a rename in ``folder`` durable (POSIX); a no-op where folders cannot be opened."""
    try:
        handle = os.open(folder, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(handle)
    except OSError:
        pass
    finally:
        os.close(handle)


def _fsync_tree(path: Path) -> None:
    files = [path] if path.is_file() else [p for p in path.rglob("*") if p.is_file()]
    for file in files:
        with open(file, "rb") as handle:
            os.fsync(handle.fileno())


@contextlib.contextmanager
def atomic_path(path: str | Path, *, folder: bool = False) -> Iterator[Path]:
    """A temporary path beside ``path`` to write to; renamed over ``path`` when the block succeeds.

    For libraries that write a file (or a folder) by name: pyarrow, matplotlib, rosbags, Pillow.
    A symbolic link keeps being one: the file it names is replaced. A device or a pipe (``-o
    /dev/stdout``, a FIFO) gets the bytes of a temporary file copied in once the block succeeds
    (renamed over, it would be replaced by a plain file).

    Parameters
    ----------
    path : str or Path
        The final output.
    folder : bool
        The writer makes a folder (a ROS 2 bag). The temporary path does not exist yet when
        yielded; it has ``path``'s own name, inside a hidden temporary folder beside ``path``,
        so that a writer naming the files inside after their folder (rosbags names the
        database ``NAME.db3``) names them as they will stay. An existing folder at ``path`` is
        replaced only after the new one is complete.

    Yields
    ------
    Path
        Where to write; keeps ``path``'s suffix so that writers choosing a format by extension
        still do.

    Raises
    ------
    InputError
        As :func:`prepare_output`; and when the system refuses to write there (a read-only or
        immutable folder, ``/proc``, a full disk), naming ``path``, not the temporary file.
    """
    path = prepare_output(path, folder=folder)
    if not folder and path.exists() and not path.is_file():
        # a device or a pipe (/dev/null, /dev/stdout, a FIFO), a link to one included: a rename
        # would put a plain file in its place (as root, /dev/null itself), and writers that seek
        # or remove their file first cannot write into it; written whole to a temporary file,
        # then copied in
        with _through_temporary(path) as temp:
            yield temp
        return
    if not folder and path.is_symlink():
        path = Path(os.path.realpath(path))  # the link stays; the file it names is replaced
    try:
        if folder:
            container = Path(tempfile.mkdtemp(prefix=f".{path.name}.", suffix=_TEMP_SUFFIX, dir=path.parent))
            temp = container / path.name
        else:
            handle, name = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=_TEMP_SUFFIX + path.suffix,
                                            dir=path.parent)
            os.close(handle)
            temp = container = Path(name)
    except OSError as exc:
        raise _cannot_write(path, exc) from None
    try:
        yield temp
        if not temp.exists():
            raise FileNotFoundError(f"{temp}: the writer produced nothing")
        try:
            _fsync_tree(temp)
            if folder:
                _replace_folder(temp, path)
                container.rmdir()
            else:
                os.chmod(temp, _umask_mode() if not path.exists() else path.stat().st_mode & 0o7777)
                os.replace(temp, path)
            _sync_folder(path.parent)
        except OSError as exc:  # a disk that fails to keep the file: about the output alone
            raise _cannot_write(path, exc) from None
    except BaseException as exc:
        if container.is_dir():
            shutil.rmtree(container, ignore_errors=True)
        else:
            container.unlink(missing_ok=True)
        named = {str(name) for name in (getattr(exc, "filename", None), getattr(exc, "filename2", None)) if name}
        if (isinstance(exc, OSError) and any(name.startswith(str(container)) for name in named)) or refused(exc):
            raise _cannot_write(path, exc) from None  # the user never named the hidden temporary file
        raise


@contextlib.contextmanager
def _through_temporary(path: Path) -> Iterator[Path]:
    """A temporary file (in the system's temporary folder) whose bytes go into the device or pipe
    ``path`` when the block succeeds."""
    handle, name = tempfile.mkstemp(prefix=".rlff.", suffix=_TEMP_SUFFIX + path.suffix)
    os.close(handle)
    temp = Path(name)
    try:
        try:
            yield temp
        except BaseException as exc:
            if refused(exc):
                raise _cannot_write(path, exc, through=temp.parent) from None
            raise
        if not temp.exists():
            raise FileNotFoundError(f"{temp}: the writer produced nothing")
        try:
            with open(temp, "rb") as source, open(path, "wb") as sink:
                shutil.copyfileobj(source, sink)
        except OSError as exc:
            raise _cannot_write(path, exc) from None
    finally:
        temp.unlink(missing_ok=True)


#: What to do about a write the system refused partway, by its error number (a full disk, a
#: used-up quota, a file-size limit): errors that name no file (a ``write`` names none).
_REFUSALS = {
    errno.ENOSPC: "free some space there, or write it elsewhere",
    errno.EDQUOT: "free some of your files there (your disk quota is used up), or write it elsewhere",
    errno.EFBIG: "a limit on the size of a file, the shell's (ulimit -f) or the file system's: raise it, or write "
                 "it elsewhere",
}
#: SQLite's words (a ROS 2 bag's database) for the same refusals; it gives no error number.
_SQLITE_REFUSALS = ("database or disk is full", "disk I/O error")


def refused(exc: BaseException) -> bool:
    """Whether ``exc`` is the system refusing a write partway (:data:`_REFUSALS`), which names no
    file: a full disk, a used-up quota or a file-size limit, from Python, pyarrow or SQLite."""
    if isinstance(exc, sqlite3.OperationalError):
        return str(exc) in _SQLITE_REFUSALS
    return isinstance(exc, OSError) and exc.errno in _REFUSALS and exc.filename is None


def refusal_words(exc: OSError | sqlite3.Error) -> str:
    """The system's reason for a refused write, and what to do about a refusal of :data:`_REFUSALS`
    (``"(File too large); a limit on the size of a file, ..."``)."""
    if isinstance(exc, sqlite3.Error):
        return f"({exc}, said by SQLite); a full disk, a used-up quota or a file-size limit (ulimit -f)?"
    if exc.errno in _REFUSALS:  # pyarrow's strerror is a sentence of its own about the same error
        return f"({os.strerror(exc.errno)}); {_REFUSALS[exc.errno]}"
    return f"({exc.strerror or exc})"


def refused_in_place(path: str | Path, exc: OSError) -> InputError:
    """The error for a file written in place (an attempts log's append) whose write the system
    refused partway (:func:`refused`): its path, the system's reason and what to do."""
    return InputError(f"{path}: cannot write there {refusal_words(exc)}")


def _cannot_write(path: Path, exc: OSError | sqlite3.Error, through: Path | None = None) -> InputError:
    """The error for an output the system refuses: the user's path and the system's reason
    (``through``: the folder of the temporary file a device's or a pipe's bytes were refused in)."""
    where = "there" if through is None else f"through the temporary folder {through}"
    return InputError(f"{path}: cannot write the output {where} {refusal_words(exc)}")


def _replace_folder(temp: Path, path: Path) -> None:
    """Put the complete folder ``temp`` at ``path``; an old folder there goes only afterwards."""
    if not path.exists():
        os.replace(temp, path)
        return
    # os.replace cannot put a folder over a non-empty one: move the old aside first. Between the
    # two renames a crash leaves the old folder under its ``.old`` name, never a partial new one.
    old = Path(tempfile.mkdtemp(prefix=f".{path.name}.", suffix=".old", dir=path.parent))
    old.rmdir()
    os.replace(path, old)
    os.replace(temp, path)
    shutil.rmtree(old, ignore_errors=True)


@contextlib.contextmanager
def atomic_write(path: str | Path, mode: str = "w", *, encoding: str | None = "utf-8", newline: str | None = None) -> Iterator[IO]:
    """Open a temporary file beside ``path`` for writing; it replaces ``path`` when the block succeeds.

    Parameters
    ----------
    path : str or Path
        The final output.
    mode : {"w", "wb"}
        Text or binary.
    encoding : str or None
        Text encoding (ignored in binary mode).
    newline : str or None
        As :func:`open`.

    Yields
    ------
    file object
        Flushed and fsync'ed before the rename; on an exception the temporary file is removed
        and ``path`` is left as it was.
    """
    if mode not in ("w", "wb"):
        raise ValueError(f"atomic_write: mode {mode!r}, expected 'w' or 'wb'")
    with atomic_path(path) as temp:
        binary = mode == "wb"
        with open(temp, mode, encoding=None if binary else encoding, newline=None if binary else newline) as handle:
            yield handle
            handle.flush()
            os.fsync(handle.fileno())


def write_text(path: str | Path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically; returns the path."""
    with atomic_write(path) as handle:
        handle.write(text)
    return Path(path)


def _same(a: Path, b: Path) -> bool:
    try:
        if a.exists() and b.exists():
            return os.path.samefile(a, b)
    except OSError:
        pass
    return a.resolve() == b.resolve()


def require_distinct(paths: Iterable[str | Path], what: str = "input") -> None:
    """Refuse the same file given twice (under any name: ``a.bag`` and ``./a.bag``, a link).

    Raises
    ------
    InputError
        Naming both spellings.
    """
    seen: list[Path] = []
    for path in map(Path, paths):
        twin = next((earlier for earlier in seen if _same(earlier, path)), None)
        if twin is not None:
            same = f"{path}" if str(twin) == str(path) else f"{twin} and {path} are the same file"
            raise InputError(f"{same}: the same {what} given twice (it would be read twice)")
        seen.append(path)


def _inside(path: Path, folder: Path) -> bool:
    """Whether ``path`` (resolved, symbolic links followed) is ``folder`` or lies inside it."""
    try:
        path.resolve().relative_to(folder.resolve())
    except ValueError:
        return False
    return True


def check_outputs(
    inputs: Mapping[str, str | Path | Iterable[str | Path] | None],
    outputs: Mapping[str, str | Path | None],
) -> None:
    """Refuse an output that is one of the inputs, or two outputs that are the same file.

    Called before any work, so that nothing is read, computed or written when the command would
    destroy its own input.

    Parameters
    ----------
    inputs : mapping of str to path, paths or None
        What each input is called for the user (``"DATA"``, ``"--manifest"``) to its path(s);
        None for an input not given. An input folder (a ROS 2 bag) also protects the files
        already inside it.
    outputs : mapping of str to path or None
        The same for outputs (``"-o/--output"``, ``"--report"``).

    Raises
    ------
    InputError
        Naming both options and the path.
    """
    named_inputs: list[tuple[str, Path]] = []
    for name, value in inputs.items():
        if value is None:
            continue
        values = [value] if isinstance(value, (str, os.PathLike)) else list(value)
        named_inputs.extend((name, Path(v)) for v in values if v is not None)
    named_outputs = [(name, Path(value)) for name, value in outputs.items() if value is not None]
    for out_name, out in named_outputs:
        for in_name, source in named_inputs:
            if _same(out, source):
                raise InputError(
                    f"{out_name} {out} is the input {in_name} {source}: refusing to overwrite an input "
                    "(write somewhere else)"
                )
            if source.is_dir() and _inside(out, source) and _file_input_inside(out, source):
                raise InputError(f"{out_name} {out} is a file of the input {in_name} {source}: refusing to overwrite it")
    for i, (first_name, first) in enumerate(named_outputs):
        for second_name, second in named_outputs[i + 1:]:
            if _same(first, second):
                raise InputError(f"{first_name} and {second_name} are the same file {first}: give two different paths")


def _file_input_inside(out: Path, folder: Path) -> bool:
    """An existing file inside an input folder is part of that input (a bag's database, run.json)."""
    return out.exists() and not _same(out, folder)


__all__ = [
    "atomic_path", "atomic_write", "check_output_path", "check_outputs", "path_kind", "prepare_output", "refusal_words",
    "refused", "refused_in_place", "require_distinct", "require_file", "write_text",
]
