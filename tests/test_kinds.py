"""Which of rlff's tables a CSV is, from its header (rlff.kinds.header_names, csv_kind), and the
readers that say "this is X, not Y" asking that one rule: until 2026-12-07 the model loader, the
robot's reader and the demonstrations' reader each read the header in its own way, and called the
same file a dataset in one and "text" or "neither a generated path nor a robot trajectory" in
another."""

from __future__ import annotations

import gzip

import pytest

from rlff.cli.model import _is_generated_path, read_data
from rlff.errors import InputError
from rlff.kinds import DATASET, GENERATED, ROBOT_TRAJECTORY, csv_kind, header_names
from rlff.model.model import Model, _looks_like_dataset
from rlff.robot.plan import robot_file_kind


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


#: Headers that the three readers told apart each in its own way until 2026-12-07.
_HEADERS = {
    "dataset, its id last": "angle,distance,velocity,trajectory\n0.5,2,4,a\n0.6,2,5,a\n",
    "dataset, capitals and spaces": " Trajectory , Angle,Distance,Velocity\na,0.5,2,4\na,0.6,2,5\n",
    "dataset, quoted names": '"trajectory","angle","distance","velocity"\n"a",0.5,2,4\n"a",0.6,2,5\n',
    "dataset, blank lines first": "\n\ntrajectory,angle,distance,velocity\na,0.5,2,4\na,0.6,2,5\n",
    "dataset without an angle": "trajectory,x,y\na,1,2\na,2,3\n",
    "path, capitals and spaces": " Angle , Velocity ,Time\n0.5,4,0\n0.6,5,0.02\n",
    "path, quoted names": '"angle","velocity","time"\n0.5,4,0\n0.6,5,0.02\n',
    "path, blank lines first": "\n\nangle,velocity,time\n0.5,4,0\n0.6,5,0.02\n",
    "path without its velocity": "angle,time\n0.5,0\n0.6,0.02\n",
    "path with a byte-order mark": "\ufeffangle,velocity,time\n0.5,4,0\n0.6,5,0.02\n",
}


def _robot_kind(path):
    """What the robot's reader calls ``path``: its kind, or DATASET where it says demonstrations."""
    try:
        return robot_file_kind(path)
    except InputError as exc:
        return DATASET if " is demonstrations (a dataset" in str(exc) else None


@pytest.mark.parametrize("case", _HEADERS)
def test_the_three_readers_name_a_header_as_csv_kind_does(tmp_path, case):
    path = _file(tmp_path, _HEADERS[case])
    kind = csv_kind(header_names(path))
    assert kind == (DATASET if case.startswith("dataset") else GENERATED)
    assert _is_generated_path(path) == (kind == GENERATED)
    assert _looks_like_dataset(path) == (kind == DATASET)
    assert _robot_kind(path) == kind


@pytest.mark.parametrize("case", ["dataset, its id last", "dataset, capitals and spaces", "dataset, quoted names",
                                  "dataset, blank lines first"])
def test_a_dataset_given_as_the_model_is_said_to_be_one_wherever_its_trajectory_column_is(tmp_path, case):
    # "is text (its first line: 'angle,distance,velocity,trajectory'), not a model": only a header
    # that started with "trajectory," was a dataset's
    path = _file(tmp_path, _HEADERS[case])
    with pytest.raises(InputError, match=r"file\.csv: a dataset, not a model \(model\.json\): fit one first, rlff fit "):
        Model.load(path)


@pytest.mark.parametrize("case", ["dataset, capitals and spaces", "dataset without an angle"])
def test_a_dataset_given_where_a_path_goes_is_said_to_be_demonstrations(tmp_path, case):
    # "neither a generated path (angle, velocity[, time]) nor a robot trajectory ...": only a
    # header with "angle" and "trajectory", as written, was demonstrations'
    path = _file(tmp_path, _HEADERS[case])
    with pytest.raises(InputError, match=r"file\.csv is demonstrations \(a dataset, its throws by the trajectory "
                                         r"column\), not a generated path: fit a model to them"):
        robot_file_kind(path)


def test_a_path_of_names_in_capitals_and_spaces_is_a_generated_path_to_the_robot(tmp_path):
    # " Angle , Velocity ,Time" was "neither a generated path (angle, velocity[, time]) nor ..."
    # there, and a generated path to rlff fit (its reader then says which names it misses)
    assert robot_file_kind(_file(tmp_path, _HEADERS["path, capitals and spaces"])) == GENERATED


@pytest.mark.parametrize("case", ["path, quoted names", "path, blank lines first", "path without its velocity"])
def test_a_path_given_as_demonstrations_is_said_to_be_a_generated_path(tmp_path, case):
    # "no 'trajectory' column (columns: angle, velocity, time)": its header was read from the
    # file's first line, split at commas with its quotes, and needed a velocity column
    path = _file(tmp_path, _HEADERS[case])
    with pytest.raises(InputError, match=r"file\.csv is a generated path \(rlff generate writes it\), not demonstrations"):
        read_data(path)


@pytest.mark.parametrize(("data", "said"), [
    (gzip.compress(b"angle,velocity\n0.5,4\n"), "is gzip-compressed (it starts with the bytes 1f 8b), not UTF-8 "
     "text: decompress it first (gunzip -c FILE > new.csv); then"),
    ("angle,velocity\n".encode("utf-16"), "is UTF-16 text (it starts with the byte-order mark ff fe), not UTF-8 "
     "text: save it as UTF-8 (iconv -f UTF-16 -t UTF-8 FILE > new.csv); then"),
    (b"", "is empty (0 bytes):"),
    (b"\n\n", "is text of blank lines:"),
], ids=["gzip", "utf-16", "empty", "blank"])
def test_a_file_of_no_text_header_given_where_a_path_goes_says_what_it_is(tmp_path, data, said):
    # "neither a generated path nor a robot trajectory: not a readable CSV or JSON ('utf-8' codec
    # can't decode byte 0x8b in position 1: invalid start byte)"
    path = _file(tmp_path, data, "path.csv")
    with pytest.raises(InputError) as refused:
        robot_file_kind(path)
    assert str(refused.value) == (f"{path} {said} give a generated path CSV or a robot trajectory JSON/CSV that "
                                  "`rlff robot export` wrote")


@pytest.mark.parametrize(("name", "new"), [("path.csv.gz", "new.csv"), ("demos.CSV.GZ", "new.CSV"),
                                           ("path.csv", "new.csv"), ("path.gz", "new"), ("path", "new")])
def test_a_gzip_is_told_to_be_decompressed_to_a_name_without_gz(tmp_path, name, new):
    # "gunzip -c FILE > new.gz": a decompressed path.csv.gz was told to be written as a .gz again
    from rlff.kinds import binary_kind

    said = binary_kind(_file(tmp_path, gzip.compress(b"angle,velocity\n"), name))
    assert said is not None and said.endswith(f"decompress it first (gunzip -c FILE > {new})"), said
