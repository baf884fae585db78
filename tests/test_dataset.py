"""The Dataset model: validation, bulk construction, grouping by context, the CSV long format."""

from __future__ import annotations

import gzip
from pathlib import Path

import numpy as np
import pytest

from rlff.dataset import (
    ARM_JOINT_COLUMNS,
    THROW_CONTEXT,
    UNITS,
    Dataset,
    Trajectory,
    check_units,
    copies_warning,
    joint_columns,
    merge_datasets,
    peak_only_note,
    read_csv,
    velocity_column,
    write_csv,
)
from rlff.errors import InputError


def _trajectory(name: str, distance: float, n: int = 4, **meta) -> Trajectory:
    angle = np.linspace(0.7, 2.5, n)
    return Trajectory(
        name,
        {"time": np.arange(n) / 30.0, "angle": angle, "distance": np.full(n, distance), "velocity": 2 * angle},
        meta,
    )


def test_trajectory_rejects_nan_ragged_and_empty():
    with pytest.raises(InputError, match=r"'t': column 'angle' has a non-finite value at sample 1"):
        Trajectory("t", {"angle": [0.0, np.nan]})
    with pytest.raises(InputError, match="has 3 samples, expected 2"):
        Trajectory("t", {"angle": [0.0, 1.0], "velocity": [1.0, 2.0, 3.0]})
    with pytest.raises(InputError, match="no samples"):
        Trajectory("t", {"angle": []})


@pytest.mark.parametrize(("values", "words"), [
    (np.array([True, False]), "booleans"),
    (np.array(["0.1", "0.2"]), "text"),
    (np.array([0.1, 0.2], dtype=object), "Python objects"),
    ([0.1, None], "Python objects"),
])
def test_a_column_that_is_no_numbers_is_refused_naming_it(values, words):
    # booleans were taken as 0.0 and 1.0, and text such as "0.1" as its number, without a word
    with pytest.raises(InputError, match=rf"^trajectory 't': column 'angle' must hold numbers, not {words}$"):
        Trajectory("t", {"angle": values, "velocity": [1.0, 2.0]})
    with pytest.raises(InputError, match=rf"^column 'angle' must hold numbers, not {words}$"):
        Dataset.from_columns({"angle": values, "velocity": [1.0, 2.0]}, ["t"], [2])


def test_integer_columns_are_numbers_kept_as_floats():
    trajectory = Trajectory("t", {"angle": np.array([1, 2], dtype=np.int32), "velocity": [3, 4]})
    assert trajectory["angle"].dtype == np.float64 and trajectory["velocity"].tolist() == [3.0, 4.0]


@pytest.mark.parametrize("index", [3, 5, -4, np.int64(7)])
def test_an_index_past_the_trajectories_says_how_many_there_are(index):
    # it said Python's "tuple index out of range"
    dataset = Dataset([_trajectory(name, 1.0) for name in "abc"])
    with pytest.raises(IndexError, match=rf"^trajectory index {index} out of range: the dataset has 3 trajectories "
                                         r"\(0 to 2, or -3 to -1\)$"):
        dataset[index]
    assert dataset[-3].id == "a" and dataset[2].id == "c"
    with pytest.raises(IndexError, match=r"the dataset has 1 trajectory \(index 0, or -1\)$"):
        dataset[:1][index]
    with pytest.raises(IndexError, match=r"the dataset has no trajectories$"):
        dataset[:0][index]


def test_dataset_rejects_duplicates_varying_context_and_time_going_back():
    with pytest.raises(InputError, match="duplicate trajectory id 'a'"):
        Dataset([_trajectory("a", 1.0), _trajectory("a", 2.0)])
    varying = _trajectory("a", 1.0).with_columns(distance=np.array([1.0, 1.0, 2.0, 1.0]))
    with pytest.raises(InputError, match="context column 'distance' is not constant"):
        Dataset([varying])
    backwards = _trajectory("a", 1.0).with_columns(time=np.array([0.0, 0.1, 0.1, 0.2]))
    with pytest.raises(InputError, match="time does not increase at sample 2"):
        Dataset([backwards])


def test_something_other_than_trajectories_is_refused_saying_how_a_dataset_is_made():
    # Dataset([{"angle": [0.1]}]) had failed with AttributeError: 'dict' object has no attribute 'columns'
    with pytest.raises(InputError, match=r"^Dataset takes Trajectory objects, got dict at position 0: make each with "
                                         r"Trajectory\(id, \{column: values\}, meta\), or give the columns of every "
                                         r"trajectory at once to Dataset.from_columns"):
        Dataset([{"angle": [0.1]}])
    with pytest.raises(InputError, match=r"^Dataset takes Trajectory objects, got str 'angle' at position 1: a Dataset "
                                         r"holds Trajectory"):
        Dataset([_trajectory("a", 1.0), "angle"])
    with pytest.raises(InputError, match=r"^trajectory 't': data must be a mapping of column names to arrays of "
                                         r"shape \(T,\), e\.g\. .*, got list$"):
        Trajectory("t", [[0.1, 0.2]])


def test_duplicates_are_trajectories_with_identical_motion_whatever_their_ids_metadata_and_context():
    original = _trajectory("a", 1.0, subject="s01")
    other = _trajectory("b", 2.0).with_columns(velocity=3 * original["angle"])
    nudged = original["angle"].copy()
    nudged[2] = np.nextafter(nudged[2], 3.0)
    dataset = Dataset([
        original, other, original.replace(id="a_copy", meta={"subject": "s02"}),
        original.replace(id="a_nudged").with_columns(angle=nudged), other.replace(id="b_copy"),
        original.replace(id="a_again"), _trajectory("a_longer", 1.0, n=5),
        # the same motion labelled with another basket (a copy whose file name gives a distance) was new
        _trajectory("a_at_2.5m", 2.5),
    ])
    assert dataset.duplicates() == [("a", "a_copy", "a_again", "a_at_2.5m"), ("b", "b_copy")]
    warning = copies_warning(dataset)
    assert warning.startswith("4 throws repeat another sample for sample, distance aside (the first: a and a_copy and "
                              "a_again and a_at_2.5m)")
    assert "count" in warning and "BIC" in warning
    assert Dataset([original, other]).duplicates() == [] and copies_warning(Dataset([original])) is None


def test_two_context_columns_group_trajectories():
    trajectories = [
        _trajectory(f"t{i}", d).with_columns(height=np.full(4, h))
        for i, (d, h) in enumerate([(2.0, 0.3), (1.0, 0.5), (2.0, 0.3), (1.0, 0.3)])
    ]
    dataset = Dataset(trajectories, context=("distance", "height"))
    groups = dataset.by_context()
    assert list(groups) == [(1.0, 0.3), (1.0, 0.5), (2.0, 0.3)]
    assert [t.id for t in groups[(2.0, 0.3)]] == ["t0", "t2"]
    assert dataset.contexts == ((1.0, 0.3), (1.0, 0.5), (2.0, 0.3))


def test_from_columns_equals_the_one_by_one_construction():
    trajectories = [_trajectory("a", 1.0, 3, subject="s1"), _trajectory("b", 2.0, 5, hit=True)]
    expected = Dataset(trajectories)
    columns = {name: np.concatenate([t[name] for t in trajectories]) for name in expected.columns}
    built = Dataset.from_columns(columns, ["a", "b"], [3, 5], [t.meta for t in trajectories])
    assert built.equals(expected)
    assert built.context == ("distance",)
    assert not built[0]["angle"].flags.writeable


def test_from_columns_validates_in_bulk():
    columns = {"time": np.array([0.0, 0.1, 0.2, 0.0, 0.1, 0.1]), "distance": np.ones(6)}
    with pytest.raises(InputError, match=r"trajectory 'b': time does not increase at sample 2; the rows of each "
                                         r"trajectory must be in time order"):
        Dataset.from_columns(columns, ["a", "b"], [3, 3])
    columns = {"time": np.arange(6.0), "distance": np.array([1, 1, 1, 2, 2, 3.0])}
    with pytest.raises(InputError, match="trajectory 'b': context column 'distance' is not constant"):
        Dataset.from_columns(columns, ["a", "b"], [3, 3])
    with pytest.raises(InputError, match="trajectory 'a': column 'time' has a non-finite value at sample 1"):
        Dataset.from_columns({"time": np.array([0.0, np.inf])}, ["a"], [2])
    with pytest.raises(InputError, match="duplicate trajectory id 'a'"):
        Dataset.from_columns({"time": np.arange(4.0)}, ["a", "a"], [2, 2])


def test_the_caller_s_arrays_stay_writeable_and_theirs():
    # a trajectory froze the very arrays it was given: the caller's next in-place edit failed
    angle, velocity = np.linspace(0.7, 2.5, 4), np.full(4, 8.0)
    trajectory = Trajectory("a", {"angle": angle, "velocity": velocity[:]})
    columns = {"angle": np.linspace(0.7, 2.5, 6), "distance": np.full(6, 2.0)}
    built = Dataset.from_columns(columns, ["b", "c"], [3, 3])
    assert angle.flags.writeable and velocity.flags.writeable
    assert all(values.flags.writeable for values in columns.values())
    angle[0], velocity[0], columns["angle"][0] = 0.0, 0.0, 0.0  # and the edits do not reach the library's copies
    assert trajectory["angle"][0] == 0.7 and trajectory["velocity"][0] == 8.0 and built[0]["angle"][0] == 0.7
    assert not trajectory["angle"].flags.writeable and not built[0]["angle"].flags.writeable
    # the library's own read-only columns are shared, not copied, from trajectory to trajectory
    assert trajectory.with_columns(time=np.arange(4.0))["angle"] is trajectory["angle"]


def test_take_keeps_order_metadata_and_read_only_columns():
    trajectory = _trajectory("a", 1.0, 5, subject="s1")
    taken = trajectory.take(np.array([0, 2, 3]))
    np.testing.assert_array_equal(taken["angle"], trajectory["angle"][[0, 2, 3]])
    assert taken.meta == {"subject": "s1"} and taken.columns == trajectory.columns
    assert not taken["time"].flags.writeable
    assert len(trajectory.take(2)) == 1
    with pytest.raises(InputError, match="'a': no samples selected"):
        trajectory.take(slice(3, 3))


def test_equals_sees_a_changed_value_or_meta():
    dataset = Dataset([_trajectory("a", 1.0, subject="s1")])
    other_value = dataset.replace([dataset[0].with_columns(angle=dataset[0]["angle"] + 1e-12)])
    other_meta = dataset.replace([dataset[0].replace(meta={"subject": "s2"})])
    assert dataset.equals(dataset.replace(list(dataset)))
    assert not dataset.equals(other_value)
    assert not dataset.equals(other_meta)


def test_csv_round_trip_is_exact(tmp_path):
    dataset = Dataset([
        _trajectory("s01-d2-1", 2.0, 5, subject="s01", target=2.0, landing=1.8312345678901234, hit=False,
                    release_angle=1.9, release_time=0.5, glitches=1),
        _trajectory("s02-d3-1", 3.0, 7, subject="s02", target=3.0, landing=3.1, hit=True,
                    release_angle=2.0, release_time=0.6, glitches=0),
    ])
    write_csv(dataset, tmp_path / "d.csv")
    back = read_csv(tmp_path / "d.csv")
    assert back.equals(dataset)
    assert back.columns == ("time", "angle", "distance", "velocity")


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("trajectory,angle\na,0.1\na,0.2\nb,\"x\n", r"malformed CSV|line"),
        ("angle,velocity\n0.1,0.2\n", r"no 'trajectory' column"),
        ("trajectory,angle,velocity\na,0.1,0.2\na,zero,0.3\n", r"line 3: column 'angle' has a non-numeric"),
        # the cell as the file shows it, not numpy's repr (np.float64(nan))
        ("trajectory,angle,velocity\na,0.1,0.2\na,nan,0.3\n", r"line 3: column 'angle' has an empty or nan value$"),
        ("trajectory,angle,velocity\na,0.1,0.2\na,,0.3\n", r"line 3: column 'angle' has an empty or nan value$"),
        ("trajectory,angle,velocity\na,0.1,0.2\na,-inf,0.3\n", r"line 3: column 'angle' has a non-finite value -inf$"),
        ("trajectory,angle,time\na,0.1,0.0\na,0.2,0.1\na,0.3,0.1\n", r"line 4: time does not increase"),
        ("trajectory,angle,velocity\na,0.1,0.2\na,0.2,0.3\nb,0.1,0.2\n", r"line 4: trajectory 'b' has a single sample"),
        ("trajectory,subject\na,s1\n", r"no numeric sample columns"),
    ],
)
def test_bad_csv_is_a_clear_error_naming_file_and_line(tmp_path, text, message):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(InputError, match=message) as error:
        read_csv(path)
    assert str(path) in str(error.value)


DEMOS = "trajectory,time,angle\na,0.0,0.1\na,0.1,0.2\n"


@pytest.mark.parametrize(
    ("content", "message"),
    [
        # each said "malformed CSV ('utf-8' codec can't decode byte ...)"
        (gzip.compress(DEMOS.encode()), r"bad.csv is gzip-compressed \(it starts with the bytes 1f 8b\), not UTF-8 "
                                        r"text: decompress it first \(gunzip -c FILE > new.csv\)$"),
        (b"PAR1\x15\x04\x15\xb0", r"bad.csv is a Parquet file \(it starts with PAR1\), not UTF-8 text: give it the "
                                  r"suffix .parquet"),
        (DEMOS.encode("utf-16"), r"bad.csv is UTF-16 text \(it starts with the byte-order mark ff fe\), not UTF-8 "
                                 r"text: save it as UTF-8 \(iconv -f UTF-16 -t UTF-8 FILE > new.csv\)$"),
        (b"\xfe\xff" + DEMOS.encode("utf-16-be"), r"bad.csv is UTF-16 text \(it starts with the byte-order mark fe ff\)"),
        # said "malformed CSV (Error tokenizing data ...)": a bag renamed, a ROS 2 bag's database
        (b"#ROSBAG V2.0\n" + b"E\x00\x00\x00\x04\x00\x00\x00op=\x03", r"bad.csv is a ROS 1 bag \(it starts with "
                                                               r"#ROSBAG V2.0\), not UTF-8 text: give it the suffix .bag"),
        (b"SQLite format 3\x00\x10\x00", r"bad.csv is an SQLite database \(a ROS 2 bag's .db3\?\), not UTF-8 text: give "
                                       r"rlff data import the bag's folder, the one with its metadata.yaml$"),
        ("trajectory,subject\na,José\n".encode("latin-1"), r"malformed CSV \(.*\): rlff reads UTF-8 text; save the "
                                                         r"file as UTF-8$"),
        # said "no 'trajectory' column (columns: trajectory;time;angle)"
        (DEMOS.replace(",", ";").encode(), r"no 'trajectory' column \(columns: trajectory;time;angle\); the file looks "
                                           r"separated by ';' and rlff reads commas: save it comma-separated, with "
                                           r"points as decimal marks$"),
        (DEMOS.replace(",", "\t").encode(), r"the file looks separated by tabs and rlff reads commas"),
        # decimal commas: "the rows have more fields than the header's 1 columns"
        (DEMOS.replace(",", ";").replace(".", ",").encode(), r"more fields than the header's 1 columns; the file "
                                                              r"looks separated by ';'"),
        # said only "time does not increase within trajectory 'a'"
        (b"trajectory,time,angle\na,0.1,0.2\na,0.0,0.1\n", r"line 3: time does not increase within trajectory 'a'; "
                                                            r"the rows of each trajectory must be in time order: sort "
                                                            r"them by trajectory and time$"),
    ],
    ids=["gzip", "parquet", "utf-16-le", "utf-16-be", "ros1-bag", "sqlite", "latin-1", "semicolons", "tabs", "decimal-commas", "time-order"],
)
def test_a_file_that_is_no_comma_separated_utf8_csv_says_what_it_looks_like_and_what_to_do(tmp_path, content,
                                                                                          message):
    path = tmp_path / "bad.csv"
    path.write_bytes(content)
    with pytest.raises(InputError, match=message):
        read_csv(path)


@pytest.mark.parametrize(("cells", "expected"), [
    (("yes", "No"), (True, False)), (("1", "0"), (True, False)), (("hit", "MISS"), (True, False)),
    (("True", "false"), (True, False)), (("y", ""), (True, None)),
])
def test_a_capture_s_hit_column_reads_as_bools(tmp_path, cells, expected):
    path = tmp_path / "hits.csv"
    path.write_text("trajectory,angle,velocity,hit\n" + "".join(
        f"{name},{a},0.5,{cell}\n" for name, cell in zip("ab", cells, strict=True) for a in (0.1, 0.2)))
    back = read_csv(path)
    assert tuple(t.meta.get("hit") for t in back) == expected


def test_a_hit_that_is_no_outcome_is_an_error_naming_line_and_words(tmp_path):
    path = tmp_path / "hits.csv"
    path.write_text("trajectory,angle,velocity,hit\na,0.1,0.5,yes\na,0.2,0.5,yes\nb,0.1,0.5,maybe\nb,0.2,0.5,maybe\n")
    with pytest.raises(InputError, match=r"line 4: trajectory 'b' has hit 'maybe' \(use true/false, yes/no"):
        read_csv(path)


@pytest.mark.parametrize(("value", "expected"), [
    (np.False_, False), (np.True_, True), (0, False), (np.int64(1), True), (0.0, False), ("no", False),
    ("False", False), ("hit", True), (None, None), (float("nan"), None),
])
def test_a_hit_given_in_python_is_read_as_the_readers_read_it(value, expected):
    # numpy's False, 0 or "no" had stayed as given: a method asking whether every demonstration
    # missed (hit is False) took them for outcomes not recorded, and learned otherwise than from CSV
    trajectory = Trajectory("a", {"angle": [0.1, 0.2]}, {"hit": value})
    assert trajectory.meta["hit"] is expected
    assert Dataset.from_columns({"angle": np.array([0.1, 0.2])}, ["a"], [2], [{"hit": value}])[0].meta["hit"] is expected


def test_a_hit_in_python_that_is_no_outcome_is_refused_naming_the_trajectory():
    with pytest.raises(InputError, match=r"trajectory 'b': metadata hit 'maybe' \(use true/false, yes/no"):
        Trajectory("b", {"angle": [0.1, 0.2]}, {"hit": "maybe"})
    with pytest.raises(InputError, match=r"trajectory 'b': metadata hit 2 \(use true/false"):
        Dataset.from_columns({"angle": np.array([0.1, 0.2])}, ["b"], [2], [{"hit": 2}])


def test_an_npz_whose_hits_are_0_and_1_reads_them_as_bools(tmp_path):
    # as numpy and pandas write them (the NPZ keeps every value's type): the 0 had stayed 0
    import json

    from rlff.formats import read_dataset, write_dataset

    path = tmp_path / "hits.npz"
    write_dataset(Dataset([Trajectory(name, {"angle": [0.1, 0.2]}) for name in "ab"]), path)
    with np.load(path) as npz:
        members = dict(npz)
    info = json.loads(str(members["rlff"]))
    info["meta"] = [{"hit": 0}, {"hit": 1}]
    members["rlff"] = np.array(json.dumps(info))
    np.savez(path, **members)
    back = read_dataset(path)
    assert back[0].meta["hit"] is False and back[1].meta["hit"] is True


def test_missing_column_is_named():
    dataset = Dataset([_trajectory("a", 1.0)])
    with pytest.raises(InputError, match=r"no column 'height' in the data \(columns: time, angle, distance, velocity\)"):
        dataset.require(["angle", "height"])


# -- whole-arm columns -----------------------------------------------------------------------


def _arm_trajectory(name: str, distance: float, n: int = 4, joints=("shoulder",), **context) -> Trajectory:
    base = _trajectory(name, distance, n)
    columns = {}
    for k, joint in enumerate(joints):
        columns[joint] = np.linspace(2.6, 2.2, n) + k
        columns[velocity_column(joint)] = np.full(n, -0.4)
    columns.update({key: np.full(n, value) for key, value in context.items()})
    return base.with_columns(**columns)


def test_velocity_column_names_and_units():
    assert velocity_column("angle") == "velocity"
    assert velocity_column("shoulder") == "shoulder_velocity"
    assert velocity_column("wrist") == "wrist_velocity"
    assert ARM_JOINT_COLUMNS == ("shoulder", "wrist")
    assert THROW_CONTEXT == ("distance", "bearing", "height")
    assert UNITS["shoulder"] == UNITS["wrist"] == "rad"
    assert UNITS["shoulder_velocity"] == UNITS["wrist_velocity"] == "rad/s"
    assert (UNITS["bearing"], UNITS["height"]) == ("deg", "m")
    assert joint_columns(["time", "wrist", "angle", "distance", "wrist_velocity"]) == ("angle", "wrist")


def test_any_subset_of_joints_is_valid_but_a_position_needs_its_velocity():
    for joints in ((), ("shoulder",), ("wrist",), ("shoulder", "wrist")):
        dataset = Dataset([_arm_trajectory("a", 1.0, joints=joints), _arm_trajectory("b", 2.0, joints=joints)])
        assert set(joint_columns(dataset.columns)) == {"angle", *joints}
    lonely = _arm_trajectory("a", 1.0, joints=("wrist",))
    lonely = lonely.replace(data={k: v for k, v in lonely.data.items() if k != "wrist_velocity"})
    with pytest.raises(InputError, match="column 'wrist' needs its velocity column 'wrist_velocity'"):
        Dataset([lonely])
    columns = {name: lonely[name] for name in lonely.columns}
    with pytest.raises(InputError, match="column 'wrist' needs its velocity column 'wrist_velocity'"):
        Dataset.from_columns(columns, ["a"], [len(lonely)])


def test_bearing_and_height_are_context_when_present():
    trajectories = [
        _arm_trajectory(f"t{i}", d, bearing=b, height=h)
        for i, (d, b, h) in enumerate([(2.0, 30.0, 0.3), (2.0, 0.0, 1.0), (1.0, 90.0, 0.6), (2.0, 30.0, 0.3)])
    ]
    dataset = Dataset(trajectories)
    assert dataset.context == ("distance", "bearing", "height")
    assert list(dataset.by_context()) == [(1.0, 90.0, 0.6), (2.0, 0.0, 1.0), (2.0, 30.0, 0.3)]
    only_height = Dataset([_arm_trajectory("h", 2.0, height=0.6)])
    assert only_height.context == ("distance", "height")
    varying = _arm_trajectory("v", 1.0, bearing=30.0).with_columns(bearing=np.array([30.0, 30.0, 60.0, 30.0]))
    with pytest.raises(InputError, match="context column 'bearing' is not constant"):
        Dataset([varying])


def test_whole_arm_csv_round_trip_is_exact(tmp_path):
    dataset = Dataset([
        _arm_trajectory("a", 1.5, joints=("shoulder", "wrist"), bearing=60.0, height=0.6),
        _arm_trajectory("b", 3.0, n=6, joints=("shoulder", "wrist"), bearing=-30.0, height=1.0),
    ])
    path = tmp_path / "arm.csv"
    write_csv(dataset, path)
    back = read_csv(path)
    assert back.equals(dataset)
    assert back.context == ("distance", "bearing", "height")
    header = path.read_text().splitlines()[0].split(",")
    assert {"shoulder", "shoulder_velocity", "wrist", "wrist_velocity", "bearing", "height"} <= set(header)


def test_csv_with_a_joint_but_not_its_velocity_is_an_error_naming_the_file(tmp_path):
    path = tmp_path / "arm.csv"
    path.write_text("trajectory,angle,velocity,shoulder,distance\na,1,2,2.5,1\na,1.1,2,2.4,1\n")
    with pytest.raises(InputError, match=r"arm\.csv: column 'shoulder' needs its velocity column"):
        read_csv(path)


def test_an_error_names_the_file_line_past_blank_lines_and_multi_line_notes(tmp_path):
    # pandas skips blank lines and reads a quoted line break as part of its cell: "row + 2" named
    # a line three above the bad cell
    path = tmp_path / "gaps.csv"
    path.write_text(
        "trajectory,angle,velocity,note\n"
        "a,0.1,0.2,\"first take,\nsecond line\"\n"  # lines 2-3
        "\n"
        "a,0.2,0.3,\"first take,\nsecond line\"\n"  # lines 5-6
        "   \n"
        "\n"
        "b,0.1,0.2,x\n"  # line 9
        "b,abc,0.2,x\n"  # line 10
    )
    with pytest.raises(InputError, match=r"gaps.csv, line 10: column 'angle' has a non-numeric"):
        read_csv(path)
    path.write_text("trajectory,angle\n\na,0.1\na,0.2\n\n\nb,0.2\n")
    with pytest.raises(InputError, match=r"gaps.csv, line 7: trajectory 'b' has a single sample"):
        read_csv(path)


def _batches(tmp_path) -> tuple[Dataset, Dataset]:
    """Two import batches written to CSV that share throw "b": (a, b) and (b, c)."""
    first = Dataset([_trajectory("a", 1.0, 3, source="a.txt"), _trajectory("b", 2.0, 3, source="b.txt")])
    second = Dataset([first["b"], _trajectory("c", 3.0, 3, source="c.txt")])
    write_csv(first, tmp_path / "batch1.csv")
    write_csv(second, tmp_path / "batch2.csv")
    return first, second


def _joined(tmp_path, name: str, sort: bool = False) -> Path:
    """The two batches of :func:`_batches` appended by hand (and, with ``sort``, sorted by
    trajectory and time after, as the time-order error used to ask)."""
    header, *rows = (tmp_path / "batch1.csv").read_text().splitlines()
    rows += (tmp_path / "batch2.csv").read_text().splitlines()[1:]
    if sort:
        time = header.split(",").index("time")
        rows.sort(key=lambda row: (row.split(",")[0], float(row.split(",")[time])))
    path = tmp_path / name
    path.write_text("\n".join([header, *rows]) + "\n")
    return path


def test_a_throw_in_two_appended_batches_is_said_to_appear_twice_not_to_need_sorting(tmp_path):
    # said "line 8: time does not increase within trajectory 'b' ... sort them by trajectory and
    # time", and sorting as told gave the same error
    _batches(tmp_path)
    joined = _joined(tmp_path, "joined.csv")
    with pytest.raises(InputError, match=r"joined.csv: trajectory 'b' appears twice \(lines 5-7 and 8-10\): two "
                                         r"datasets joined with a throw in both\? keep one copy \(`rlff data merge"):
        read_csv(joined)
    with pytest.raises(InputError, match=r"sorted.csv, lines 5 and 6: trajectory 'b' holds the same sample twice "
                                         r"\(time 0 s\), as it does each of its samples: two datasets joined"):
        read_csv(_joined(tmp_path, "sorted.csv", sort=True))


def test_the_two_copies_appear_twice_even_when_their_metadata_differ(tmp_path):
    # the same recording imported from two folders: its source differs, and the error said
    # "metadata column 'source' varies within trajectory 'b'"
    _batches(tmp_path)
    text = (tmp_path / "batch2.csv").read_text().replace("b.txt", "other/b.txt")
    (tmp_path / "batch2.csv").write_text(text)
    with pytest.raises(InputError, match=r"trajectory 'b' appears twice \(lines 5-7 and 8-10\)"):
        read_csv(_joined(tmp_path, "joined.csv"))


def test_a_throw_given_twice_without_a_time_column_is_refused_not_read_as_one_twice_as_long(tmp_path):
    # read as trajectory 'b' of 6 samples, its motion run twice, without a word
    throw_b = "b,0.5,2,4\nb,0.6,2,5\nb,0.7,2,6\n"
    path = tmp_path / "thesis_like.csv"
    path.write_text("trajectory,angle,distance,velocity\na,0.1,1,2\na,0.2,1,3\n" + throw_b + "c,0.1,3,2\nc,0.2,3,3\n"
                    + throw_b)
    with pytest.raises(InputError, match=r"thesis_like.csv: trajectory 'b' appears twice \(lines 4-6 and 9-11\)"):
        read_csv(path)
    # the throw that ends one file and starts the next: one block of rows, its motion twice
    path.write_text("trajectory,angle,distance,velocity\na,0.1,1,2\na,0.2,1,3\n" + throw_b + throw_b)
    with pytest.raises(InputError, match=r"trajectory 'b' appears twice \(lines 4-6 and 7-9\)"):
        read_csv(path)


def test_rows_scattered_among_other_trajectories_still_read_in_their_order(tmp_path):
    # another tool's export sorted by time: each trajectory's rows come in many blocks, no copy
    path = tmp_path / "by_time.csv"
    path.write_text("trajectory,time,angle\na,0.0,0.1\nb,0.0,1.0\na,0.1,0.2\nb,0.1,1.1\na,0.2,0.3\n"
                    "b,0.2,1.2\nb,0.3,1.3\n")
    dataset = read_csv(path)
    assert dataset.ids == ("a", "b")
    np.testing.assert_array_equal(dataset["b"]["angle"], [1.0, 1.1, 1.2, 1.3])
    # a single row out of place is a row to sort, said as before
    path.write_text("trajectory,time,angle\na,0.1,0.2\na,0.2,0.3\nb,0.0,1.0\nb,0.1,1.1\na,0.0,0.1\n")
    with pytest.raises(InputError, match=r"line 6: time does not increase within trajectory 'a'; the rows of each "
                                         r"trajectory must be in time order"):
        read_csv(path)
    # one row pasted twice: said as such, not as two datasets joined
    path.write_text("trajectory,time,angle\na,0.0,0.1\na,0.1,0.2\na,0.1,0.2\na,0.2,0.3\n")
    with pytest.raises(InputError, match=r"by_time.csv, lines 3 and 4: trajectory 'a' holds the same sample twice "
                                         r"\(time 0.1 s\): a row given twice\? delete one$"):
        read_csv(path)


def test_merge_keeps_a_throw_two_batches_share_once(tmp_path):
    first, second = _batches(tmp_path)
    merged = merge_datasets([("batch1.csv", read_csv(tmp_path / "batch1.csv")),
                             ("batch2.csv", read_csv(tmp_path / "batch2.csv"))])
    assert merged.dataset.ids == ("a", "b", "c")
    assert merged.kept_once == [("b", "batch1.csv", "batch2.csv")]
    assert merged.dataset.equals(Dataset([*first, second["c"]]))


def test_merge_refuses_one_id_for_two_throws_naming_what_differs():
    first = Dataset([_trajectory("a", 1.0, 3, source="a.txt")])
    relabelled = Dataset([_trajectory("a", 1.5, 3, source="a.txt")])
    with pytest.raises(InputError, match=r"^trajectory 'a' is in one.csv and in two.csv with column 'distance' 1.0 "
                                         r"against 1.5 at sample 0: two throws under one id"):
        merge_datasets([("one.csv", first), ("two.csv", relabelled)])
    elsewhere = Dataset([_trajectory("a", 1.0, 3, source="elsewhere/a.txt")])
    with pytest.raises(InputError, match=r"with metadata 'source' 'a.txt' against 'elsewhere/a.txt'"):
        merge_datasets([("one.csv", first), ("two.csv", elsewhere)])
    longer = Dataset([_trajectory("a", 1.0, 4, source="a.txt")])
    with pytest.raises(InputError, match=r"with 3 samples against 4"):
        merge_datasets([("one.csv", first), ("two.csv", longer)])


def test_merge_keeps_the_metadata_one_copy_lacks_and_refuses_other_columns():
    # a batch imported by an earlier rlff lacks a key the later one writes: the same throw
    older = Dataset([_trajectory("a", 1.0, 3, source="a.txt")])
    newer = Dataset([_trajectory("a", 1.0, 3, source="a.txt", peak_confidence="high")])
    merged = merge_datasets([("old.csv", older), ("new.csv", newer)])
    assert merged.dataset["a"].meta == {"source": "a.txt", "peak_confidence": "high"}
    elbow = Dataset([Trajectory("e", {"angle": [0.1, 0.2], "velocity": [1.0, 2.0], "distance": [1.0, 1.0]})])
    with pytest.raises(InputError, match=r"^elbow.csv and old.csv have different columns \(elbow.csv lacks time\): "
                                         r"datasets merge only with the same columns"):
        merge_datasets([("old.csv", older), ("elbow.csv", elbow)])


def test_a_throw_twice_in_a_parquet_or_npz_file_is_said_to_start_again(tmp_path):
    # two Parquet tables joined: the reader gathers a trajectory's scattered rows, and said "time
    # does not increase at sample 3; ... sort them by trajectory and time"
    import pandas as pd
    import pyarrow as pa
    import pyarrow.parquet as pq

    from rlff.formats import read_parquet

    _batches(tmp_path)
    tables = [pa.Table.from_pandas(pd.read_csv(tmp_path / name), preserve_index=False)
              for name in ("batch1.csv", "batch2.csv")]
    pq.write_table(pa.concat_tables(tables), tmp_path / "joined.parquet")
    with pytest.raises(InputError, match=r"joined.parquet: trajectory 'b': its throw starts again at sample 3: two "
                                         r"datasets joined with a throw in both\? keep one copy"):
        read_parquet(tmp_path / "joined.parquet")
    columns = {"time": np.array([0.0, 0.1, 0.2, 0.0, 0.1, 0.2])}
    with pytest.raises(InputError, match=r"^trajectory 'a': time does not increase at sample 3; the rows"):
        Dataset.from_columns({"time": np.array([0.0, 0.1, 0.2, 0.05, 0.3, 0.4])}, ["a"], [6])
    with pytest.raises(InputError, match=r"^trajectory 'a': its throw starts again at sample 3: two datasets"):
        Dataset.from_columns(columns, ["a"], [6])


# -- units of the velocities ---------------------------------------------------------------------


def _rescaled(dataset: Dataset, factor: float, columns: tuple[str, ...] = ("velocity",),
              drop: tuple[str, ...] = ()) -> Dataset:
    """``dataset`` with ``columns`` multiplied by ``factor`` (another unit) and ``drop`` left out."""
    return Dataset([t.replace(data={c: t[c] * (factor if c in columns else 1.0) for c in t.columns if c not in drop})
                    for t in dataset], context=dataset.context)


@pytest.fixture(scope="module")
def recorded():
    """Simulated recordings as a camera gives them: noise, dropped frames, glitches."""
    from rlff.synthetic.throws import simulate_throws

    return simulate_throws(0, subjects=3, throws_per_distance=2)


def test_a_velocity_in_degrees_per_second_is_refused_by_the_angle_s_change_over_time(recorded):
    # fitted, cleaned and generated from without a word: a throw of 3 ms at 688 "rad/s"
    check_units(recorded)
    assert peak_only_note(recorded.columns) is None
    with pytest.raises(InputError, match=r"^column 'velocity' integrates over the throws' time column to a median "
                                         r"5\d\.?\d* times their angle's change \(along the throw, back and forth\): .*\(degrees per second\? velocity is "
                                         r"in rad/s\)$"):
        check_units(_rescaled(recorded, np.degrees(1.0)))
    with pytest.raises(InputError, match=r"time in milliseconds\? it is in seconds"):
        check_units(_rescaled(recorded, 1000.0, ("time",)))


def test_without_a_time_column_a_velocity_is_checked_by_its_peak_and_the_rest_is_said(recorded):
    untimed = _rescaled(recorded, 1.0, drop=("time",))
    check_units(untimed)
    assert peak_only_note(untimed.columns) == (
        "no time column: column 'velocity' checked against a person's fastest joint (60 rad/s) only, not against "
        "the rate at which the position changes")
    with pytest.raises(InputError, match=r"^column 'velocity' peaks at \d+\.?\d* in the median throw, faster than a "
                                         r"person's joint turns .*degrees per second\?"):
        check_units(_rescaled(untimed, np.degrees(1.0)))


def test_a_recording_s_glitches_faster_than_a_person_pass_where_the_time_column_tells():
    # uncleaned recordings are what preprocessing is for: their glitches peak beyond any arm
    from rlff.synthetic.throws import simulate_throws

    glitchy = simulate_throws(1, subjects=2, throws_per_distance=1, rate_hz=30.0, glitches=0.3, noise=0.3)
    fast = _rescaled(glitchy, 2.0, ("velocity", "angle"))  # twice the angle and its velocity: within two turns
    assert np.median([np.abs(t["velocity"]).max() for t in fast]) > 60.0
    check_units(fast)


def test_a_whole_arm_joint_s_velocity_is_checked_by_its_peak_and_said_to_be():
    from rlff.synthetic.whole_arm import whole_arm_demonstrations

    arm = whole_arm_demonstrations(2)
    check_units(arm)
    assert peak_only_note(arm.columns) == (
        "the elbow's velocity alone is integrated over the time: column 'shoulder_velocity' checked against a "
        "person's fastest joint (60 rad/s) only, not against the rate at which the position changes")
    with pytest.raises(InputError, match=r"^column 'shoulder_velocity' peaks at \d+\.?\d* in the median throw"):
        check_units(_rescaled(arm, np.degrees(1.0), ("shoulder_velocity",)))


def test_a_velocity_without_its_position_is_checked_by_its_peak_and_said_to_be():
    data = Dataset([Trajectory(f"t{k}", {"time": np.arange(4) / 30.0, "velocity": np.array([1.0, 5.0, 9.0, 12.0])})
                    for k in range(3)])
    check_units(data)
    assert peak_only_note(data.columns) == (
        "no angle column: column 'velocity' checked against a person's fastest joint (60 rad/s) only, not against "
        "the rate at which the position changes")
    with pytest.raises(InputError, match=r"^column 'velocity' peaks at 687\.5 in the median throw"):
        check_units(_rescaled(data, np.degrees(1.0)))
