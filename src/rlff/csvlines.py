"""Which line of a CSV file a data row came from, for error messages.

pandas skips blank lines and reads a quoted cell across line breaks, so "data row + 2" is the
file line only in a file without either. The files people bring have both (a blank line between
two takes, a note with a line break), and an error that names the wrong line sends them to the
wrong place. The large files' lines are counted only when an error is about to be raised: a
second pass over the file costs nothing then.
"""

from __future__ import annotations

import csv
from pathlib import Path


def data_row_lines(path: str | Path, separator: str = ",") -> list[int]:
    """The 1-based file line on which each data row (header excluded) starts, in row order.

    Blank lines (empty or only white space) are skipped as pandas skips them; a record whose
    quoted cell holds a line break is given by its first line.
    """
    lines = []
    with open(path, newline="", encoding="utf-8-sig", errors="replace") as handle:
        reader = csv.reader(handle, delimiter=separator)
        start = 1
        header = True
        for record in reader:
            if record and (len(record) > 1 or record[0].strip()):
                if not header:
                    lines.append(start)
                header = False
            start = reader.line_num + 1
    return lines


def data_row_line(path: str | Path, row: int, separator: str = ",") -> int:
    """The 1-based file line on which data row ``row`` (0-based, header excluded) starts.

    A row beyond the file's (a file changed since it was read) is given as ``row + 2``, the
    line it would be on without blank lines.
    """
    lines = data_row_lines(path, separator)
    return lines[row] if row < len(lines) else row + 2


def header_separator(path: str | Path) -> str:
    """The field separator of a CSV: of ``,``, ``;`` and tab, the one its header line holds most of
    (``,`` on a tie). A file with ``;`` or tab writes its decimals with a comma or a point."""
    with open(path, encoding="utf-8-sig", errors="replace") as handle:
        header = next((line for line in handle if line.strip()), "")
    return max((",", ";", "\t"), key=header.count)
