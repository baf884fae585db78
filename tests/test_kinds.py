"""Which of rlff's tables a CSV is, from its header (rlff.kinds.header_names, csv_kind)."""

from __future__ import annotations

import gzip

import pytest

from rlff.kinds import DATASET, GENERATED, ROBOT_TRAJECTORY, csv_kind, header_names


def _file(tmp_path, text: str | bytes, name: str = "file.csv"):
    path = tmp_path / name
    if isinstance(text, str):
        path.write_text(text, encoding="utf-8")
    else:
        path.write_bytes(text)
    return path


@pytest.mark.parametrize(("text", "names"), [
    ("trajectory,angle,distance,velocity\na,0.5,2,4\n", ("trajectory", "angle", "distance", "velocity")),
    ("\ufeffangle,velocity\n0.5,4\n", ("angle", "velocity")),  # a spreadsheet's UTF-8 with its byte-order mark
    ("\n \n\nangle,velocity\n0.5,4\n", ("angle", "velocity")),  # blank lines before it, as pandas skips them
    (' "Angle" , "Velocity (rad/s)","a,b"\r\n0.5,4,1\r\n', ("Angle", "Velocity (rad/s)", "a,b")),
    ("time,joint_1_position\r0,1\r", ("time", "joint_1_position")),  # old Mac line ends
    ("\n\n  \n", ()),
    ("", ()),
])
def test_header_names_are_the_first_line_that_is_not_blank_stripped_and_unquoted_in_their_case(tmp_path, text, names):
    assert header_names(_file(tmp_path, text)) == names


def test_header_names_are_none_for_no_file_a_folder_or_no_utf8_text(tmp_path):
    assert header_names(tmp_path / "missing.csv") is None
    assert header_names(tmp_path) is None
    assert header_names(_file(tmp_path, gzip.compress(b"angle,velocity\n"), "path.csv.gz")) is None
    assert header_names(_file(tmp_path, "angle,velocity\n".encode("utf-16"), "utf16.csv")) is None
    # only the header need be UTF-8: a Latin-1 note in a row is its reader's to refuse
    assert header_names(_file(tmp_path, "angle,velocity,note\n0.5,4,caf\xe9\n".encode("latin-1"))) == (
        "angle", "velocity", "note")


def test_a_header_cut_by_the_bytes_read_keeps_its_names_before_the_cut(tmp_path):
    names = header_names(_file(tmp_path, "angle,velocity," + "é" * 70_000 + "\n"))
    assert names is not None and names[:2] == ("angle", "velocity")


@pytest.mark.parametrize(("names", "kind"), [
    (("trajectory", "angle", "distance", "velocity"), DATASET),
    (("angle", "distance", "velocity", "trajectory"), DATASET),  # the id where it may be
    (("trajectory", "x", "y"), DATASET),  # a dataset of any columns (rlff fit --inputs x --outputs y)
    ((" Trajectory ", "ANGLE"), DATASET),
    (('# {"trajectory": "t1"', '"distance": 2.0}'), DATASET),  # a thesis matrix's throw header
    (("angle", "velocity", "time", "pdf", "exploration", "gmr_mean"), GENERATED),
    (("angle", "time"), GENERATED),  # its reader says that it misses its velocity
    (("Angle", "Velocity"), GENERATED),
    (("time", "joint_1_position", "joint_1_velocity", "joint_1_acceleration"), ROBOT_TRAJECTORY),
    (("Time", "Joint_2_Position"), ROBOT_TRAJECTORY),
    (("time", "joint_1_velocity"), None),
    (("joint_1_position",), None),
    (("x", "y"), None),
    (("# a note", "angle"), GENERATED),  # a comment without a throw header is a name like another
    (("# a note on the trajectory",), None),
    ((), None),
    (None, None),
])
def test_csv_kind_names_rlff_tables_by_their_columns(names, kind):
    assert csv_kind(names) == kind


def test_a_thesis_matrix_whose_first_line_is_a_throw_header_is_a_dataset(tmp_path):
    path = _file(tmp_path, '\n# {"trajectory": "t1", "distance": 2.0}\n0.1 0.2\n2 2\n3 4\n', "throws.txt")
    assert csv_kind(header_names(path)) == DATASET
    assert csv_kind(header_names(_file(tmp_path, "# recorded 2026-12-07\n0.1 0.2\n", "plain.txt"))) is None
