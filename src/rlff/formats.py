"""Dataset files: the thesis' matrix text format, NPZ and Parquet, and a reader/writer by extension.

The CSV long format lives beside the types in :mod:`rlff.dataset`. Here:

- the thesis matrix (thesis figure 2.1): three rows per trajectory (angles; basket distance;
  velocities), values separated by tabs, spaces or semicolons, a comma accepted as the decimal
  separator. An optional comment line ``# {"trajectory": ID, ...metadata}`` before a block names
  the trajectory and carries its metadata, so that a written file reads back the same dataset;
  other lines starting with ``#`` are comments.
- NPZ (numpy): whole columns, trajectory lengths, ids and metadata as JSON; no pickles.
- Parquet (pyarrow): the CSV long format as a typed table, with the context columns and the
  metadata keys in the schema's metadata; fast for large sets.
"""

from __future__ import annotations

import json
import re
import zipfile
import zlib
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from rlff.dataset import (
    ID_COLUMN,
    META_KEYS,
    MIN_FILE_SAMPLES,
    Dataset,
    parse_hit,
    read_csv,
    write_csv,
)
from rlff.errors import InputError
from rlff.fileio import atomic_path, atomic_write, require_file, write_text
from rlff.kinds import EMPTY, binary_kind, file_kind, rlff_kind
from rlff.limits import is_number

#: Format names and the file extensions that select them.
FORMATS = {"csv": (".csv",), "thesis": (".txt", ".tsv"), "npz": (".npz",), "parquet": (".parquet", ".pq")}
#: Rows of a thesis matrix block, in order.
THESIS_ROWS = ("angle", "distance", "velocity")
#: Key of rlff's own entry in a Parquet schema's metadata and in an NPZ file.
_RLFF_KEY = "rlff"
_FILE_TAG = {"format": "rlff-dataset", "version": 1}
_SEPARATORS = re.compile(r"[\t ;]+")


def _jsonable(value: Any) -> Any:
    if isinstance(value, np.generic):
        return value.item()
    raise TypeError(f"metadata value of type {type(value).__name__} cannot be stored")


def _require_file(path: Path) -> None:
    require_file(path)


def _marks(path: Path) -> tuple[bytes, bytes]:
    """The first and the last four bytes of the file ``path`` (where a Parquet file and a ZIP
    archive, an NPZ, carry their marks)."""
    try:
        with open(path, "rb") as handle:
            head = handle.read(4)
            size = handle.seek(0, 2)
            handle.seek(max(size - 4, 0))
            return head, handle.read(4)
    except OSError as exc:
        raise InputError(f"{path}: cannot be read ({exc.strerror or exc})") from None


def _not_a(path: Path, what: str) -> InputError:
    """The error for a file that is not ``what`` (its format by the suffix): what it looks like,
    and, unless it is empty, that the suffix says the format."""
    kind = file_kind(path)
    if kind == EMPTY:
        return InputError(f"{path} is {kind}, not {what}")
    known = ", ".join(s for suffixes in FORMATS.values() for s in suffixes)
    return InputError(f"{path} is {kind}, not {what}: rlff reads a dataset by its suffix ({known}); give the file "
                      "the suffix of what it holds")


# -- thesis matrix -----------------------------------------------------------------------------


def read_thesis_matrix(
    path: str | Path, rows: Sequence[str] = THESIS_ROWS, context: Sequence[str] = ("distance",)
) -> Dataset:
    """Read the thesis' matrix format: one row per column, ``len(rows)`` rows per trajectory.

    Parameters
    ----------
    path : str or Path
        Text file. Values are separated by tabs, spaces or semicolons; a comma is read as the
        decimal separator (``0,495`` is 0.495). Blank lines are skipped.
    rows : sequence of str
        Names of the rows of a block (default angle in rad, distance in m, velocity in rad/s).
    context : sequence of str
        Rows that hold a context (constant within a block).

    Returns
    -------
    Dataset
        One trajectory per block, ids ``<file stem>-<k>`` (k from 1) unless a comment line
        ``# {"trajectory": ...}`` names it; ``source`` metadata is the file name.

    Raises
    ------
    InputError
        Naming the file and line: a value that is not a number, rows of a block with different
        lengths, an incomplete last block, a non-finite value, a context row that is not constant.
    """
    path = Path(path)
    _require_file(path)
    try:
        lines = path.read_text().splitlines()
    except UnicodeDecodeError:
        kind = binary_kind(path)
        raise InputError(f"{path} is {kind}" if kind else f"{path}: not UTF-8 text; save it as UTF-8") from None
    blocks: list[tuple[list[int], list[np.ndarray], dict[str, Any] | None]] = []
    pending_header: dict[str, Any] | None = None
    current_lines: list[int] = []
    current_rows: list[np.ndarray] = []
    for number, line in enumerate(lines, start=1):
        text = line.strip()
        if not text:
            continue
        if text.startswith("#"):
            pending_header = _header(text, path, number) or pending_header
            continue
        tokens = [t for t in _SEPARATORS.split(text) if t]
        try:
            values = np.array([float(t.replace(",", ".")) for t in tokens])
        except ValueError:
            bad = next(t for t in tokens if not is_number(t.replace(",", ".")))  # quoted as in the file
            # several commas in one token: a CSV file under the thesis matrix's suffix
            csv = "; it looks like CSV: a .csv file is read as CSV" if bad.count(",") > 1 else ""
            raise InputError(
                f"{path}, line {number}: {bad!r} is not a number (values are separated by tabs, "
                f"spaces or semicolons; a comma is a decimal separator){csv}"
            ) from None
        if not np.all(np.isfinite(values)):
            raise InputError(f"{path}, line {number}: non-finite value in row {rows[len(current_rows)]!r}")
        if current_rows and values.size != current_rows[0].size:
            raise InputError(
                f"{path}, line {number}: row {rows[len(current_rows)]!r} has {values.size} values, "
                f"the block's first row (line {current_lines[0]}) has {current_rows[0].size}"
            )
        if values.size < MIN_FILE_SAMPLES:
            raise InputError(
                f"{path}, line {number}: a single value: a trajectory needs at least {MIN_FILE_SAMPLES} samples"
            )
        current_lines.append(number)
        current_rows.append(values)
        if len(current_rows) == len(rows):
            blocks.append((current_lines, current_rows, pending_header))
            current_lines, current_rows, pending_header = [], [], None
    if current_rows:
        raise InputError(
            f"{path}, line {current_lines[-1]}: incomplete block: {len(current_rows)} of "
            f"{len(rows)} rows ({', '.join(rows)})"
        )
    if not blocks:
        raise InputError(f"{path}: no data rows")
    trajectories_data, ids, metas = [], [], []
    for k, (numbers, values, header) in enumerate(blocks, start=1):
        # a header written by write_thesis_matrix restores id and metadata as they were
        meta = dict(header) if header is not None else {"source": path.name}
        ids.append(str(meta.pop(ID_COLUMN, f"{path.stem}-{k}")))
        metas.append(meta)
        trajectories_data.append(dict(zip(rows, values, strict=True)))
        for name, row, number in zip(rows, values, numbers, strict=True):
            if name in context and np.ptp(row) > 1e-9 * max(1.0, float(np.max(np.abs(row)))):
                raise InputError(f"{path}, line {number}: context row {name!r} is not constant")
    columns = {name: np.concatenate([d[name] for d in trajectories_data]) for name in rows}
    lengths = [len(d[rows[0]]) for d in trajectories_data]
    try:
        return Dataset.from_columns(columns, ids, lengths, metas, tuple(context))
    except InputError as exc:
        raise InputError(f"{path}: {exc}") from None


def _header(text: str, path: Path, number: int) -> dict[str, Any] | None:
    """The trajectory header a comment line carries, or None for a plain comment."""
    body = text[1:].strip()
    if not body.startswith("{"):
        return None
    try:
        header = json.loads(body)
    except json.JSONDecodeError as exc:
        raise InputError(f"{path}, line {number}: malformed trajectory header ({exc.msg})") from None
    if not isinstance(header, dict) or ID_COLUMN not in header:
        return None
    return header


def write_thesis_matrix(
    dataset: Dataset,
    path: str | Path,
    *,
    rows: Sequence[str] = THESIS_ROWS,
    separator: str = "\t",
    decimal_comma: bool = False,
    header: bool = True,
) -> None:
    """Write the thesis' matrix format; :func:`read_thesis_matrix` gives the dataset back.

    Parameters
    ----------
    dataset : Dataset
        Must hold exactly the columns in ``rows``.
    path : str or Path
    rows : sequence of str
        Columns written, one text row each, in this order.
    separator : str
        Tab, space or semicolon.
    decimal_comma : bool
        Write ``0,495`` instead of ``0.495`` (as the thesis' tables do).
    header : bool
        Write a ``# {"trajectory": ...}`` comment line with the id and metadata before each
        block (needed for an exact round trip of ids and metadata).

    Raises
    ------
    InputError
        A column of ``rows`` is missing, the dataset has other columns (they would be lost), or
        the separator is not one the reader accepts.
    """
    if separator not in ("\t", " ", ";"):
        raise InputError(f"separator {separator!r}: use a tab, a space or a semicolon")
    dataset.require(rows)
    extra = [name for name in dataset.columns if name not in rows]
    if extra:
        raise InputError(_thesis_refusal(path, rows, "the data", extra))
    out = []
    for trajectory in dataset:
        if header:
            record = {ID_COLUMN: trajectory.id, **trajectory.meta}
            out.append("# " + json.dumps(record, default=_jsonable))
        for name in rows:
            text = separator.join(repr(float(v)) for v in trajectory[name])
            out.append(text.replace(".", ",") if decimal_comma else text)
    write_text(path, "\n".join(out) + "\n")


def _thesis_refusal(path: str | Path, rows: Sequence[str], what: str, extra: Sequence[str]) -> str:
    """Why a thesis matrix at ``path`` cannot hold ``what``: its ``extra`` columns, beyond ``rows``."""
    suffix = Path(path).suffix or "the thesis format"
    columns = f"column{'s' if len(extra) > 1 else ''} {', '.join(extra)}"
    return (f"{path}: {suffix} is the thesis matrix, which holds only {', '.join(rows)} (a text row each per "
            f"trajectory), not the {columns} of {what}: write .csv, .npz or .parquet to keep them")


def check_holds(path: str | Path, columns: Sequence[str], what: str, format: str | None = None) -> None:
    """Refuse, before any work, an output whose format cannot hold ``columns``: the thesis matrix
    (``.txt``, ``.tsv``) holds only :data:`THESIS_ROWS`; every other format any column.

    Parameters
    ----------
    path : str or Path
        The output; its format from its extension unless ``format`` is given.
    columns : sequence of str
        The sample columns the data written there will have (the ``trajectory`` id and the
        metadata ride along in every format).
    what : str
        The data in words, for the message ("the simulated throws", "demos.csv").

    Raises
    ------
    InputError
        An unknown extension or format, or a column the format cannot hold, naming the format,
        what it holds and the suffixes to use instead.
    """
    if format_of(path, format) != "thesis":
        return
    extra = [name for name in columns if name not in THESIS_ROWS and name != ID_COLUMN]
    if extra:
        raise InputError(_thesis_refusal(path, THESIS_ROWS, what, extra))


# -- NPZ ---------------------------------------------------------------------------------------


def write_npz(dataset: Dataset, path: str | Path) -> None:
    """Write a dataset as an uncompressed NPZ: whole columns plus lengths, ids and metadata."""
    arrays = {f"column:{name}": _column(dataset, name) for name in dataset.columns}
    info = {
        **_FILE_TAG,
        "columns": list(dataset.columns),
        "context": list(dataset.context),
        "meta": [t.meta for t in dataset],
    }
    with atomic_write(path, "wb") as handle:
        np.savez(
            handle,
            ids=np.array(dataset.ids, dtype=str),
            lengths=np.array([len(t) for t in dataset], dtype=np.int64),
            **{_RLFF_KEY: np.array(json.dumps(info, default=_jsonable))},
            **arrays,
        )


def read_npz(path: str | Path) -> Dataset:
    """Read a dataset written by :func:`write_npz`.

    Raises
    ------
    InputError
        Not a readable NPZ (damaged or cut short), or members that are missing or of the wrong
        type or shape (named in the message), or data that do not make a dataset.
    """
    path = Path(path)
    _require_file(path)
    if _marks(path)[0] not in _ZIP_MARKS:
        raise _not_a(path, "an NPZ dataset (a ZIP archive of numpy arrays)")
    try:
        npz = np.load(path, allow_pickle=False)
    except _NPZ_DAMAGE:
        raise InputError(f"{path}: an NPZ cut short or damaged: it starts as a ZIP archive, as an NPZ does, but "
                         "the archive's directory, at its end, is missing or unreadable") from None
    members = {}
    with npz:
        for key in npz.files:
            try:
                members[key] = npz[key]
            except _NPZ_DAMAGE:
                raise InputError(f"{path}: damaged NPZ: its member {key!r} cannot be read (a byte changed, or the "
                                 "file cut short)") from None
    columns, ids, lengths, info = _npz_contents(path, members)
    _check_lengths(path, ids, lengths)
    try:
        return Dataset.from_columns(columns, ids, lengths, info["meta"], info["context"])
    except InputError as exc:
        raise InputError(f"{path}: {exc}") from None


#: What numpy raises on a damaged or truncated .npz (a zip of .npy members): the zip layer
#: (BadZipFile, zlib.error, EOFError), the .npy header (ValueError, SyntaxError from its
#: literal_eval) or the file itself (OSError).
_NPZ_DAMAGE = (OSError, ValueError, EOFError, SyntaxError, zipfile.BadZipFile, zlib.error)
#: The first bytes of a ZIP archive (an NPZ): of its first member, or of the end of an empty one.
_ZIP_MARKS = (b"PK\x03\x04", b"PK\x05\x06")
#: Member names of a foreign NPZ that an error lists.
_LISTED = 5


def _npz_contents(
    path: Path, members: dict[str, np.ndarray]
) -> tuple[dict[str, np.ndarray], list[str], np.ndarray, dict[str, Any]]:
    """The checked members of an rlff NPZ: columns, ids, lengths and the rlff entry."""

    def fail(member: str, problem: str) -> InputError:
        return InputError(f"{path}: not an rlff NPZ dataset (member {member!r} {problem})")

    if not {_RLFF_KEY, "ids", "lengths"} & members.keys():
        held = ", ".join(repr(key) for key in list(members)[:_LISTED]) + (", ..." if len(members) > _LISTED else "")
        raise InputError(f"{path}: not an rlff NPZ dataset: it holds {held or 'no arrays'} (rlff's hold "
                         f"{_RLFF_KEY!r}, 'ids', 'lengths' and a 'column:NAME' for each column)")
    for member in (_RLFF_KEY, "ids", "lengths"):
        if member not in members:
            raise fail(member, "is missing")
    entry = members[_RLFF_KEY]
    if entry.shape != () or entry.dtype.kind != "U":
        raise fail(_RLFF_KEY, "must be one string")
    try:
        info = json.loads(str(entry))
    except json.JSONDecodeError:
        raise fail(_RLFF_KEY, "is not JSON") from None
    if not isinstance(info, dict):
        raise fail(_RLFF_KEY, "must hold a JSON object")
    for key in ("columns", "context"):
        if not isinstance(info.get(key), list) or not all(isinstance(name, str) for name in info[key]):
            raise fail(_RLFF_KEY, f"must list the {key} names")
    if not isinstance(info.get("meta"), list) or not all(isinstance(meta, dict) for meta in info["meta"]):
        raise fail(_RLFF_KEY, "must hold one metadata object per trajectory")
    ids, lengths = members["ids"], members["lengths"]
    if ids.ndim != 1 or ids.dtype.kind != "U":
        raise fail("ids", "must be a 1-D array of strings")
    if lengths.ndim != 1 or lengths.dtype.kind not in "iu":
        raise fail("lengths", "must be a 1-D array of integers")
    if lengths.size != ids.size:
        raise fail("lengths", f"has {lengths.size} entries for {ids.size} ids")
    columns = {}
    for name in info["columns"]:
        values = members.get(f"column:{name}")
        if values is None:
            raise fail(f"column:{name}", "is missing")
        if values.ndim != 1 or values.dtype.kind not in "fiu":
            raise fail(f"column:{name}", "must be a 1-D array of numbers")
        columns[name] = values
    return columns, ids.tolist(), lengths, info


def _check_lengths(path: Path, ids: list[str], lengths: np.ndarray) -> None:
    short = np.flatnonzero(np.asarray(lengths) < MIN_FILE_SAMPLES)
    if short.size:
        raise InputError(
            f"{path}: trajectory {ids[short[0]]!r} has a single sample (a demonstration needs at "
            f"least {MIN_FILE_SAMPLES})"
        )


def _column(dataset: Dataset, name: str) -> np.ndarray:
    if not len(dataset):
        return np.empty(0)
    return np.concatenate([t[name] for t in dataset])


# -- Parquet -----------------------------------------------------------------------------------


def write_parquet(dataset: Dataset, path: str | Path) -> None:
    """Write a dataset as Parquet: the CSV long format as a typed table.

    Metadata values become columns constant within a trajectory (bools, numbers or strings);
    the context columns and metadata keys go into the schema's metadata so that
    :func:`read_parquet` restores them exactly.
    """
    import pyarrow as pa
    import pyarrow.parquet as pq

    lengths = np.array([len(t) for t in dataset], dtype=np.int64)
    owner = np.repeat(np.arange(len(dataset)), lengths)
    fields: dict[str, pa.Array] = {
        ID_COLUMN: pa.DictionaryArray.from_arrays(
            pa.array(owner, type=pa.int32()), pa.array(dataset.ids, type=pa.string())
        )
    }
    for name in dataset.columns:
        fields[name] = pa.array(_column(dataset, name), type=pa.float64())
    meta_keys = list(dict.fromkeys(key for t in dataset for key in t.meta))
    for key in meta_keys:
        values = [t.meta.get(key) for t in dataset]
        try:
            per_trajectory = pa.array(values)
        except (pa.ArrowInvalid, pa.ArrowTypeError):
            per_trajectory = pa.array([None if v is None else str(v) for v in values])
        fields[key] = per_trajectory.take(pa.array(owner))
    info = {**_FILE_TAG, "context": list(dataset.context), "meta_keys": meta_keys}
    table = pa.table(fields).replace_schema_metadata({_RLFF_KEY: json.dumps(info)})
    with atomic_path(path) as temp:
        pq.write_table(table, temp)


def read_parquet(path: str | Path, context: Sequence[str] | None = None) -> Dataset:
    """Read a dataset from Parquet (written by :func:`write_parquet` or any long-format table).

    Rows of one trajectory must be contiguous or are gathered in their file order (a trajectory's
    samples are never reordered). Without rlff's schema metadata, string and bool columns and the
    known metadata keys (subject, source, target, landing, hit) are metadata, the rest samples;
    ``hit`` is read as :func:`rlff.dataset.parse_hit` reads it (0/1, yes/no, ... as bools).
    """
    import pyarrow as pa
    import pyarrow.parquet as pq

    path = Path(path)
    _require_file(path)
    head, tail = _marks(path)
    if head != b"PAR1":
        raise _not_a(path, "a Parquet file")
    try:
        table = pq.read_table(path)
    except (pa.ArrowException, OSError) as exc:
        if tail != b"PAR1":
            raise InputError(f"{path}: a Parquet file cut short: it starts with PAR1, but does not end with it as a "
                             "whole one does") from None
        raise InputError(f"{path}: damaged Parquet file ({exc})") from None
    try:
        table.column_names  # noqa: B018 -- pyarrow decodes the names only when they are asked for
    except UnicodeDecodeError:
        raise InputError(f"{path}: damaged Parquet file: a column name is not UTF-8 text") from None
    try:  # pyarrow decodes text cells (ids, subjects) only as they are read
        return _dataset_of_table(path, table, context)
    except UnicodeDecodeError:
        raise InputError(f"{path}: damaged Parquet file: a text cell (a trajectory id or a metadata value) is not "
                         "UTF-8 text") from None


def _dataset_of_table(path: Path, table: Any, context: Sequence[str] | None) -> Dataset:
    """The dataset of a Parquet file's ``table`` (a pyarrow Table), checked as :func:`read_parquet` says."""
    import pyarrow as pa

    info = _parquet_info(path, table)
    if ID_COLUMN not in table.column_names:
        raise InputError(f"{path}: no {ID_COLUMN!r} column (columns: {', '.join(table.column_names)})")
    if "meta_keys" in info:
        meta_keys = list(info["meta_keys"])
    else:
        meta_keys = [
            f.name for f in table.schema
            if f.name != ID_COLUMN and (f.name in META_KEYS or not pa.types.is_floating(f.type)
                                        and not pa.types.is_integer(f.type))
        ]
    if context is None and "context" in info:
        context = info["context"]
    ids_column = table.column(ID_COLUMN).combine_chunks()
    if ids_column.null_count:
        row = int(np.flatnonzero(ids_column.is_null().to_numpy(zero_copy_only=False))[0])
        raise InputError(f"{path}: empty trajectory id at row {row + 1}")
    if not pa.types.is_dictionary(ids_column.type):
        ids_column = ids_column.cast(pa.string()).dictionary_encode()
    codes = ids_column.indices.to_numpy(zero_copy_only=False)
    names = ids_column.dictionary.to_pylist()
    if codes.size and not 0 <= codes.min() <= codes.max() < len(names):
        # a damaged file: pyarrow reads a dictionary page and indices that do not belong together
        raise InputError(f"{path}: damaged Parquet file: the {ID_COLUMN!r} column refers to ids it does not hold")
    order = None
    if codes.size > 1 and np.count_nonzero(np.diff(codes)) + 1 != np.count_nonzero(np.bincount(codes)):
        # rows of a trajectory are scattered: gather them, keeping each trajectory's own order
        first_seen = np.unique(codes, return_index=True)[1]
        rank = np.empty(len(names), dtype=np.int64)
        rank[codes[np.sort(first_seen)]] = np.arange(first_seen.size)
        order = np.argsort(rank[codes], kind="stable")
        codes = codes[order]
    starts = np.flatnonzero(np.concatenate([[True], codes[1:] != codes[:-1]])) if codes.size else np.empty(0, int)
    lengths = np.diff(np.append(starts, codes.size))
    ids = [names[c] for c in codes[starts].tolist()]
    _check_lengths(path, ids, lengths)
    columns = {}
    for name in table.column_names:
        if name == ID_COLUMN or name in meta_keys:
            continue
        column = table.column(name)
        try:
            values = column.to_numpy().astype(float, copy=False)
        except (pa.ArrowInvalid, ValueError, TypeError):
            raise InputError(f"{path}: column {name!r} is not numeric ({column.type})") from None
        if column.null_count:
            row = int(np.flatnonzero(column.is_null().to_numpy(zero_copy_only=False))[0])
            raise InputError(f"{path}: column {name!r} has an empty value at row {row + 1}")
        columns[name] = values if order is None else values[order]
    metas: list[dict[str, Any]] = [{} for _ in ids]
    for key in meta_keys:
        column = table.column(key).combine_chunks()
        if order is not None:
            column = column.take(pa.array(order))
        encoded = column.dictionary_encode() if not pa.types.is_dictionary(column.type) else column
        meta_codes = encoded.indices.fill_null(-1).to_numpy(zero_copy_only=False)
        varying = np.flatnonzero(meta_codes != np.repeat(meta_codes[starts], lengths))
        if varying.size:
            owner = np.searchsorted(starts, varying[0], side="right") - 1
            raise InputError(f"{path}: metadata column {key!r} varies within trajectory {ids[owner]!r}")
        for trajectory_id, meta, value in zip(ids, metas, column.take(pa.array(starts)).to_pylist(), strict=True):
            if key == "hit":
                try:
                    value = parse_hit(value)
                except ValueError as exc:
                    raise InputError(f"{path}: trajectory {trajectory_id!r} has hit {exc}") from None
            if value is not None:
                meta[key] = value
    try:
        return Dataset.from_columns(columns, ids, lengths, metas, context)
    except InputError as exc:
        raise InputError(f"{path}: {exc}") from None


def _parquet_info(path: Path, table: Any) -> dict[str, Any]:
    """rlff's entry in the schema metadata (context and metadata keys), checked; {} if absent."""
    raw = (table.schema.metadata or {}).get(_RLFF_KEY.encode())
    if raw is None:
        return {}
    try:
        info = json.loads(raw)
    except (json.JSONDecodeError, UnicodeDecodeError):
        info = None
    if not isinstance(info, dict):
        raise InputError(f"{path}: damaged rlff entry in the Parquet metadata (not a JSON object)")
    for key in ("context", "meta_keys"):
        names = info.get(key, [])
        if not isinstance(names, list) or not all(isinstance(name, str) for name in names):
            raise InputError(f"{path}: damaged rlff entry in the Parquet metadata ({key!r} is not a list of names)")
    absent = [name for name in info.get("meta_keys", []) if name not in table.column_names]
    if absent:
        raise InputError(f"{path}: metadata column {absent[0]!r} listed in the Parquet metadata is missing")
    return info


# -- dispatch ----------------------------------------------------------------------------------


def format_of(path: str | Path, format: str | None = None) -> str:
    """The format name for ``path``: ``format`` when given, else from the extension."""
    if format is not None:
        if format not in FORMATS:
            raise InputError(f"unknown dataset format {format!r} (known: {', '.join(FORMATS)})")
        return format
    suffix = Path(path).suffix.lower()
    for name, suffixes in FORMATS.items():
        if suffix in suffixes:
            return name
    known = ", ".join(s for suffixes in FORMATS.values() for s in suffixes)
    raise InputError(f"{path}: unknown dataset extension {suffix!r} (known: {known})")


def read_dataset(path: str | Path, format: str | None = None) -> Dataset:
    """Read a dataset in any format; by extension (.csv, .txt/.tsv, .npz, .parquet) by default."""
    readers = {"csv": read_csv, "thesis": read_thesis_matrix, "npz": read_npz, "parquet": read_parquet}
    if Path(path).is_dir():
        require_file(path)  # a folder is said to be one, not an unknown extension
    if format is None and (kind := rlff_kind(path)) is not None:
        raise InputError(f"{path} is {kind}, not a dataset of demonstrations (.csv, .parquet, .npz or .txt)")
    return readers[format_of(path, format)](path)


def write_dataset(dataset: Dataset, path: str | Path, format: str | None = None) -> None:
    """Write a dataset in any format; by extension (.csv, .txt/.tsv, .npz, .parquet) by default."""
    writers = {"csv": write_csv, "thesis": write_thesis_matrix, "npz": write_npz, "parquet": write_parquet}
    writers[format_of(path, format)](dataset, path)


__all__ = [
    "FORMATS",
    "THESIS_ROWS",
    "check_holds",
    "format_of",
    "read_dataset",
    "read_npz",
    "read_parquet",
    "read_thesis_matrix",
    "write_dataset",
    "write_npz",
    "write_parquet",
    "write_thesis_matrix",
]
