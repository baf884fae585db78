"""What a file is, for the errors of a reader given it where another kind goes: an rlff file, from
its ``format`` field (a model where demonstrations go said only "unknown dataset extension
'.json'"), or a file that is no UTF-8 text, from its first bytes (a gzip, a Parquet or a UTF-16
file given as a CSV said "malformed CSV ('utf-8' codec can't decode byte 0x8b ...)"), or any file
given to a binary reader (a CSV given as Parquet said "Parquet magic bytes not found in footer",
and as an NPZ "This file contains pickled (object) data"); and which of rlff's tables a CSV is, from
its header (:func:`csv_kind`: a dataset, a generated path or a robot trajectory), the one rule
every reader that says "this is X, not Y" asks."""

from __future__ import annotations

import codecs
import csv
import re
from collections.abc import Sequence
from pathlib import Path

#: The ``format`` field of each JSON document or log rlff writes, and what to call that file.
KINDS = {
    "rlff-model": "an rlff model (rlff fit writes it)",
    "rlff-joint-trajectory": "a robot trajectory (rlff robot export -f json writes it)",
    "rlff-attempts": "an attempts log (rlff learn --log writes it)",
    "rlff-run": "a run summary (rlff demo's run.json)",
    "rlff-preprocess-report": "a cleaning report (rlff data preprocess --report writes it)",
}
#: Bytes read from a file's start to find its ``format`` (rlff writes it first).
_HEAD = 4096
_FORMAT = re.compile(rb'"format"\s*:\s*"(rlff-[a-z-]+)"')


#: The first line of a ROS 1 bag (format 2.0, the one rosbag writes).
ROS1_BAG_MAGIC = b"#ROSBAG V2.0\n"
#: The first bytes of the files that are given as a text file (a CSV, a thesis matrix) but are no
#: UTF-8 text: what the file is and what to do (``{new}``: a file name of the same suffix).
_SIGNATURES = (
    (b"\x1f\x8b", "gzip-compressed (it starts with the bytes 1f 8b)", "decompress it first (gunzip -c FILE > {new})"),
    (b"PAR1", "a Parquet file (it starts with PAR1)", "give it the suffix .parquet, by which rlff reads Parquet"),
    (b"\xff\xfe", "UTF-16 text (it starts with the byte-order mark ff fe)",
     "save it as UTF-8 (iconv -f UTF-16 -t UTF-8 FILE > {new})"),
    (b"\xfe\xff", "UTF-16 text (it starts with the byte-order mark fe ff)",
     "save it as UTF-8 (iconv -f UTF-16 -t UTF-8 FILE > {new})"),
    (b"PK\x03\x04", "a ZIP archive (it starts with PK: an .xlsx workbook? an .npz?)",
     "save a workbook's sheet as CSV; give an .npz its suffix"),
    # a bag renamed (or saved without its suffix) was read as text: "malformed CSV (Error
    # tokenizing data ...)", "cannot tell the format"
    (ROS1_BAG_MAGIC, "a ROS 1 bag (it starts with #ROSBAG V2.0)",
     "give it the suffix .bag, by which rlff reads ROS 1 bags"),
    (b"SQLite format 3\x00", "an SQLite database (a ROS 2 bag's .db3?)",
     "give rlff data import the bag's folder, the one with its metadata.yaml"),
    (b"\x89MCAP", "an MCAP file (a ROS 2 bag's .mcap?)",
     "give rlff data import the bag's folder, the one with its metadata.yaml"),
)


def binary_kind(path: str | Path) -> str | None:
    """What ``path`` is when its first bytes say it is no UTF-8 text, and what to do, as one phrase
    (``"gzip-compressed (it starts with the bytes 1f 8b), not UTF-8 text: decompress it first
    ..."``); None for any other file, or one not readable."""
    try:
        with open(path, "rb") as handle:
            head = handle.read(max(len(magic) for magic, _, _ in _SIGNATURES))
    except OSError:
        return None
    for magic, kind, remedy in _SIGNATURES:
        if head.startswith(magic):
            return f"{kind}, not UTF-8 text: {remedy.format(new=_new_name(Path(path), magic))}"
    return None


def _new_name(path: Path, magic: bytes) -> str:
    """The file name a remedy writes to: ``new`` with ``path``'s suffix, the one before ``.gz`` for
    a gzip (``demos.csv.gz`` decompresses to ``new.csv``, not ``new.gz``)."""
    suffixes = path.suffixes
    if magic == b"\x1f\x8b" and suffixes and suffixes[-1].lower() == ".gz":
        suffixes = suffixes[:-1]
    return "new" + (suffixes[-1] if suffixes else "")


#: The first bytes of binary files that :data:`_SIGNATURES` does not hold (they are not given as text).
_BINARY = ((b"\x93NUMPY", "a single numpy array (an .npy file: it starts with \\x93NUMPY)"),)
#: What :func:`file_kind` calls a file of no bytes.
EMPTY = "empty (0 bytes)"
#: Characters of a text file's first line that :func:`file_kind` quotes.
_QUOTED = 60


def file_kind(path: str | Path) -> str:
    """What ``path`` looks like, as a phrase for "``path`` is ...": ``"empty (0 bytes)"``, a binary
    kind from its first bytes (``"a ZIP archive (it starts with PK: ...)"``), an rlff file
    (:data:`KINDS`' words), ``"text (its first line: 'trajectory,angle,...')"``, or
    ``"binary data of no kind rlff knows (it starts with the bytes 00 01 02 03)"``."""
    try:
        with open(path, "rb") as handle:
            head = handle.read(_HEAD)
    except OSError as exc:
        return f"not readable ({exc.strerror})"
    if not head:
        return EMPTY
    for magic, kind in (*((magic, kind) for magic, kind, _ in _SIGNATURES), *_BINARY):
        if head.startswith(magic):
            return kind
    if (kind := _rlff_kind_in(head)) is not None:
        return kind
    try:  # the last character may be cut by the _HEAD bytes read
        text = codecs.getincrementaldecoder("utf-8")().decode(head, final=len(head) < _HEAD)
    except UnicodeDecodeError:
        text = "\0"
    if "\0" in text:
        return f"binary data of no kind rlff knows (it starts with the bytes {head[:4].hex(' ')})"
    line = next((line.strip() for line in text.splitlines() if line.strip()), "")
    quoted = line if len(line) <= _QUOTED else line[:_QUOTED] + "..."
    return f"text (its first line: {quoted!r})" if line else "text of blank lines"


def rlff_kind(path: str | Path) -> str | None:
    """What the rlff file ``path`` is (:data:`KINDS`' words), or None: not an rlff JSON document or
    log, or not readable."""
    try:
        with open(path, "rb") as handle:
            head = handle.read(_HEAD)
    except OSError:
        return None
    return _rlff_kind_in(head)


def _rlff_kind_in(head: bytes) -> str | None:
    """What the rlff file whose first bytes are ``head`` is (:data:`KINDS`' words), or None."""
    found = _FORMAT.search(head)
    return KINDS.get(found.group(1).decode()) if found else None


def is_ros2_metadata(path: str | Path) -> bool:
    """Whether ``path`` is the ``metadata.yaml`` of a ROS 2 bag, the file that makes its folder one."""
    path = Path(path)
    return path.name == "metadata.yaml" and path.is_file()


def is_ros1_bag(path: str | Path) -> bool:
    """Whether ``path`` is a file that opens as a ROS 1 bag does (:data:`ROS1_BAG_MAGIC`)."""
    path = Path(path)
    if not path.is_file():
        return False
    with open(path, "rb") as stream:
        return stream.read(len(ROS1_BAG_MAGIC)) == ROS1_BAG_MAGIC


#: What :func:`csv_kind` calls the tables rlff reads and writes as CSV: demonstrations (``rlff data
#: import`` writes them), a generated path (``rlff generate``) and a robot trajectory (``rlff robot
#: export -f csv``).
DATASET, GENERATED, ROBOT_TRAJECTORY = "dataset", "generated path", "robot trajectory"
#: Bytes of a file :func:`header_names` reads for its header (a wide header is a few kB; a file of
#: another kind may have no line break at all).
_HEADER_BYTES = 1 << 16


def header_names(path: str | Path) -> tuple[str, ...] | None:
    """The column names of the CSV ``path``'s header, as pandas reads them: its first line that is
    not blank (blank lines before it skipped), split at commas, a name's quotes dropped (a
    spreadsheet's ``"angle", "velocity"``) and a UTF-8 byte-order mark; each name stripped of
    spaces, its case kept for messages (:func:`csv_kind` compares names case-insensitively).

    ``()`` for a file of blank lines; None for no file, one not readable, or a header that is no
    UTF-8 text (a gzip, UTF-16, ...)."""
    try:
        with open(path, "rb") as handle:
            head = handle.read(_HEADER_BYTES)
    except OSError:
        return None
    lines = re.split(rb"\r\n?|\n", head.removeprefix(codecs.BOM_UTF8))
    line = next((line for line in lines if line.strip()), b"")
    try:  # a header as long as the bytes read may end in a cut character
        text = codecs.getincrementaldecoder("utf-8")().decode(line, final=len(head) < _HEADER_BYTES)
    except UnicodeDecodeError:
        return None
    return tuple(name.strip() for name in next(csv.reader([text], skipinitialspace=True), []))


def csv_kind(names: Sequence[str] | None) -> str | None:
    """Which of rlff's tables a CSV whose header holds ``names`` (:func:`header_names`) is, its names
    compared stripped and case-insensitively, in this order:

    - :data:`DATASET`: a ``trajectory`` column, where it may be (the id of each sample's throw), or
      a thesis matrix's first line, a throw's header comment ``# {"trajectory": ...}``;
    - :data:`GENERATED`: an ``angle`` column (the path variable) and no ``trajectory``; its
      ``velocity`` is not asked for here, so that a path without it is told that it misses it;
    - :data:`ROBOT_TRAJECTORY`: a ``time`` column and ``<joint>_position`` columns;

    None for any other header, or none (``names`` None)."""
    if not names:
        return None
    lower = [name.strip().lower() for name in names]
    if "trajectory" in lower or (lower[0].startswith("#") and '"trajectory"' in lower[0]):
        return DATASET
    if "angle" in lower:
        return GENERATED
    if "time" in lower and any(name.endswith("_position") for name in lower):
        return ROBOT_TRAJECTORY
    return None
