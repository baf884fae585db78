"""What a manifest says of one recording's throws: which row labels each, which throws no row names.

A manifest lists the throws of a recording by number (``throw``) or by time (``start``, ``end``);
the import numbers the throws it finds in the recording. The two agree only when the import finds
the throws the person who wrote the manifest counted. When it finds more (a pump before the throw,
a throw cut in two), the rows label throws by a count that is not theirs, and a throw no row names
has no basket the manifest vouches for. Such a throw is left out rather than labelled with the
landing estimate beside the manifest's baskets (unless the file name gives the file's basket), and
the file gets one warning: how many throws were found against how many its rows list, and which
throws took which basket.

A manifest usually lists a whole session, of which a subset is imported or drawn (``rlff plot
cuts`` on one recording, with the import's manifest): its rows for the recordings not given are
one note (:func:`rows_for_others`), and only a row naming a file found nowhere (a misspelt name)
is a warning.
"""

from __future__ import annotations

import glob
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from rlff.capture.label import ManifestRow
from rlff.wording import plural

#: The rule of a throw left out because no manifest row names it.
NO_ROW = "manifest"


@dataclass(frozen=True)
class Outcome:
    """What became of one throw of a recording with manifest rows.

    ``number`` is its 1-based number among the file's throws, ``start`` its start (s from the
    recording's first frame), ``source`` the ``distance_source`` it was labelled from, or None
    when it was left out because no row names it.
    """

    number: int
    start: float
    source: str | None


def rows_of(rows: list[ManifestRow], source: str | Path) -> list[ManifestRow]:
    """The manifest rows that name the recording ``source`` (:meth:`ManifestRow.matches`)."""
    return [row for row in rows if row.matches(source)]


def rows_for_others(rows: list[ManifestRow], paths: Sequence[str | Path]) -> tuple[list[str], list[str]]:
    """What to say of the manifest rows that name none of the recordings ``paths``: (notes, warnings).

    Rows naming a recording that is beside one given or beside the manifest (another recording of
    the session) are one note, or, when no row names any recording given (the manifest of another
    session?), one warning; a row naming a file found in neither place (misspelt, or a recording
    missing) is a warning of its own.
    """
    unused = [row for row in rows if not any(row.matches(path) for path in paths)]
    if not unused:
        return [], []
    folders = {Path(rows[0].manifest).parent, *(Path(path).parent for path in paths)}
    found = [_on_disk(row.file, folders) for row in unused]
    warnings = [f"{row.where}: {row.file} is none of the recordings given; the row is not used"
                for row, there in zip(unused, found, strict=True) if not there]
    others = [row for row, there in zip(unused, found, strict=True) if there]
    if not others:
        return [], warnings
    manifest = rows[0].manifest
    names = list(dict.fromkeys(row.file for row in others))
    shown = ", ".join(names[:3]) + (f" and {len(names) - 3} more" if len(names) > 3 else "")
    if len(unused) == len(rows):
        return [], [*warnings, f"manifest {manifest} names none of the recordings given: its "
                               f"{plural(len(others), 'row')} for {plural(len(names), 'other recording')} ({shown}) "
                               "are not used; give the manifest of these recordings"]
    counted = f"{plural(len(others), 'row')} {'names' if len(others) == 1 else 'name'}"
    return [f"manifest {manifest}: {counted} {plural(len(names), 'recording')} not given ({shown}): not used"], warnings


def _on_disk(name: str, folders: set[Path]) -> bool:
    """Whether the recording a manifest row names (a file or a ROS 2 bag folder, or its stem, as
    :meth:`ManifestRow.matches` takes it) is in one of ``folders``."""
    for folder in folders:
        path = folder / name
        if path.exists() or any(path.parent.glob(glob.escape(path.name) + ".*")):
            return True
    return False


def names_every_throw(file_rows: list[ManifestRow]) -> bool:
    """Whether one of a recording's rows names neither a throw nor a time span: it labels them all."""
    return any(row.throw is None and not row.has_span for row in file_rows)


def unnamed_reason(file_rows: list[ManifestRow], name: str) -> str:
    """Why a throw of recording ``name`` is left out: no row of its manifest names it."""
    manifest = file_rows[0].manifest
    numbered = sorted({row.throw for row in file_rows if row.throw is not None})
    if numbered:
        listed = f"its rows for {name} list {_throws(numbered)}"
    else:
        listed = f"its rows for {name} name throws by time, and none spans this one's extension peak"
    return f"no row of manifest {manifest} names it ({listed}); its basket is not known"


def listing_warning(path: str | Path, file_rows: list[ManifestRow], found: int, outcomes: list[Outcome]) -> str | None:
    """The warning for a recording whose throws and manifest rows disagree, or None when they agree.

    Parameters
    ----------
    path : the recording
    file_rows : its manifest rows (:func:`rows_of`), at least one
    found : how many throws at a target the import found in it (numbered 1 to ``found``)
    outcomes : what became of each of its throws that reached labelling

    They disagree when the file holds more throws than the highest throw number its rows give
    (the numbers may then label the wrong throws), or when a throw was left out as no row names it.
    """
    numbered = sorted({row.throw for row in file_rows if row.throw is not None})
    more = bool(numbered) and found > numbered[-1]
    left_out = [outcome for outcome in outcomes if outcome.source is None]
    if not more and not left_out:
        return None
    manifest = file_rows[0].manifest
    lines = sorted(row.line for row in file_rows if row.throw is not None)
    said = []
    by_source: dict[str, list[Outcome]] = {}
    for outcome in outcomes:
        if outcome.source is not None:
            by_source.setdefault(outcome.source, []).append(outcome)
    for source, taken in by_source.items():
        how = f"its rows' baskets by {'number' if numbered else 'time'}" if source == "manifest" else "the file name's basket"
        said.append(f"{_throws([o.number for o in taken])} ({_times(taken)}) took {how}")
    if left_out:
        said.append(f"{_throws([o.number for o in left_out])} ({_times(left_out)}) {'was' if len(left_out) == 1 else 'were'} "
                    f"left out: no row names {'it' if len(left_out) == 1 else 'them'}")
    if more:
        head = (f"{path}: {plural(found, 'throw')} found, where manifest {manifest} lists {len(numbered)} "
                f"({_throws(numbered)}, {'line' if len(lines) == 1 else 'lines'} {', '.join(map(str, lines))})")
        advice = (f"if the file holds {numbered[-1]} {'throw' if numbered[-1] == 1 else 'throws'}, the cut found more "
                  "(a pump before a throw, a throw cut in two) and the rows may label the wrong ones: check where the "
                  "import cut it (rlff plot cuts on the file, with this import's options and --manifest), and name its throws by time in the "
                  "manifest (start and end columns)")
    else:
        head = f"{path}: manifest {manifest} does not name every throw found there"
        advice = "add a row for each throw to keep it"
    return f"{head}: {'; '.join(said)}; {advice}"


def _throws(numbers: list[int]) -> str:
    """``throw 3``, ``throws 1 and 2``, ``throws 3, 4 and 5``."""
    if len(numbers) == 1:
        return f"throw {numbers[0]}"
    return f"throws {', '.join(map(str, numbers[:-1]))} and {numbers[-1]}"


def _times(outcomes: list[Outcome]) -> str:
    """``t=1.33 s``, ``t=5.80, 6.60 s``: where the throws start."""
    return f"t={', '.join(f'{o.start:.2f}' for o in outcomes)} s"
