"""Dataset files: thesis matrix, NPZ, Parquet and the reader/writer by extension."""

from __future__ import annotations

import re

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rlff.dataset import Dataset, Trajectory
from rlff.errors import InputError
from rlff.formats import (
    check_holds,
    read_dataset,
    read_npz,
    read_parquet,
    read_thesis_matrix,
    write_dataset,
    write_thesis_matrix,
)

finite = st.floats(min_value=-1e6, max_value=1e6, allow_nan=False, allow_infinity=False)


@st.composite
def datasets(draw, with_time: bool = True) -> Dataset:
    """Small datasets with arbitrary finite values, ids and metadata."""
    count = draw(st.integers(1, 4))
    trajectories = []
    for k in range(count):
        n = draw(st.integers(2, 6))
        data = {
            "angle": np.array(draw(st.lists(finite, min_size=n, max_size=n))),
            "distance": np.full(n, draw(st.sampled_from([1.0, 2.25, 2.75, 1 / 3]))),
            "velocity": np.array(draw(st.lists(finite, min_size=n, max_size=n))),
        }
        if with_time:
            data["time"] = np.cumsum(draw(st.lists(st.floats(1e-3, 1.0), min_size=n, max_size=n)))
        meta = {"subject": draw(st.sampled_from(["s01", "anna b"])), "target": data["distance"][0],
                "hit": draw(st.booleans())}
        if draw(st.booleans()):  # known for some throws only
            meta["landing"] = draw(finite)
        trajectories.append(Trajectory(f"t{k}-{draw(st.sampled_from(['x', 'y z']))}", data, meta))
    return Dataset(trajectories)


@pytest.mark.parametrize("suffix", [".csv", ".npz", ".parquet"])
@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(dataset=datasets())
def test_round_trip_gives_back_the_same_dataset(tmp_path, suffix, dataset):
    path = tmp_path / f"d{suffix}"
    write_dataset(dataset, path)
    assert read_dataset(path).equals(dataset)


@pytest.mark.parametrize(("separator", "decimal_comma"), [("\t", False), (" ", True), (";", True), (";", False)])
@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(dataset=datasets(with_time=False))
def test_thesis_matrix_round_trip(tmp_path, separator, decimal_comma, dataset):
    path = tmp_path / "d.txt"
    write_thesis_matrix(dataset, path, separator=separator, decimal_comma=decimal_comma)
    assert read_thesis_matrix(path).equals(dataset)


def test_thesis_figure_2_1_reads_with_comma_decimals(tmp_path):
    # thesis figure 2.1: angles, basket distance, velocities; a comma is the decimal separator
    path = tmp_path / "figure.txt"
    path.write_text(
        "0\t0,1\t0,2\t0,3\n"
        "1\t1\t1\t1\n"
        "0\t0,495\t0,98\t1,455\n"
        "\n"
        "0;0,5;1\n"
        "2;2;2\n"
        "0; 1,5 ;2,75\n"
    )
    dataset = read_thesis_matrix(path)
    assert dataset.ids == ("figure-1", "figure-2")
    assert dataset.columns == ("angle", "distance", "velocity")
    np.testing.assert_array_equal(dataset[0]["angle"], [0.0, 0.1, 0.2, 0.3])
    np.testing.assert_array_equal(dataset[0]["velocity"], [0.0, 0.495, 0.98, 1.455])
    np.testing.assert_array_equal(dataset[1]["velocity"], [0.0, 1.5, 2.75])
    assert dataset.contexts == ((1.0,), (2.0,))
    assert dataset[0].meta == {"source": "figure.txt"}


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("0 0,1 0,2\n1 1 1\n0 0,5\n", r"line 3: row 'velocity' has 2 values, the block's first row \(line 1\) has 3"),
        ("0 0.1\n1 1\n0 0.5\n0 0.1\n1 1\n", r"line 5: incomplete block: 2 of 3 rows"),
        ("0 0.1\n1 2\n0 0.5\n", r"line 2: context row 'distance' is not constant"),
        ("0 abc\n1 1\n0 0.5\n", r"line 1: 'abc' is not a number"),
        # quoted as in the file, not with its commas read as decimal points ('0.1.0.2.0.3')
        ("0.1,0.2,0.3\n1,1,1\n0,1,2\n", r"line 1: '0.1,0.2,0.3' is not a number"),
        ("trajectory,angle\na,0.1\n", r"line 1: 'trajectory,angle' is not a number"),
        ("trajectory,angle,velocity\na,0.1,2\n", r"'trajectory,angle,velocity' is not a number .*it looks like CSV: "
                                                 r"a \.csv file is read as CSV"),
        ("0 nan\n1 1\n0 0.5\n", r"line 1: non-finite value in row 'angle'"),
        ("0\n1\n0\n", r"line 1: a single value"),
        ("# nothing here\n", r"no data rows"),
    ],
)
def test_bad_thesis_matrix_names_file_and_line(tmp_path, text, message):
    path = tmp_path / "bad.txt"
    path.write_text(text)
    with pytest.raises(InputError, match=message) as error:
        read_thesis_matrix(path)
    assert str(path) in str(error.value)


def test_thesis_matrix_refuses_to_lose_columns(tmp_path):
    dataset = Dataset([Trajectory("a", {"angle": [0.0, 1.0], "distance": [1.0, 1.0], "velocity": [0.0, 1.0],
                                        "time": [0.0, 0.1]})])
    with pytest.raises(InputError, match=r"d\.txt: \.txt is the thesis matrix, which holds only angle, distance, "
                                         r"velocity \(a text row each per trajectory\), not the column time of the "
                                         r"data: write \.csv, \.npz or \.parquet to keep them$"):
        write_thesis_matrix(dataset, tmp_path / "d.txt")


def test_check_holds_refuses_columns_the_format_cannot_hold_before_any_work(tmp_path):
    check_holds(tmp_path / "d.txt", ("trajectory", "angle", "distance", "velocity"), "the data")
    for name in ("d.csv", "d.npz", "d.parquet"):
        check_holds(tmp_path / name, ("angle", "distance", "velocity", "time", "shoulder"), "the data")
    with pytest.raises(InputError, match=r"d\.tsv: \.tsv is the thesis matrix, .* not the columns time, shoulder of "
                                         r"demos\.csv: write \.csv"):
        check_holds(tmp_path / "d.tsv", ("time", "angle", "distance", "velocity", "shoulder"), "demos.csv")
    with pytest.raises(InputError, match="unknown dataset extension '.dat'"):
        check_holds(tmp_path / "d.dat", ("angle",), "the data")


def test_parquet_from_another_tool_with_scattered_rows(tmp_path):
    # rows of trajectory "a" are interleaved with "b": each keeps its own sample order
    table = pa.table({
        "trajectory": ["a", "b", "a", "b", "a"],
        "angle": [0.1, 1.0, 0.2, 1.1, 0.3],
        "distance": [2.0, 3.0, 2.0, 3.0, 2.0],
        "subject": ["s1", "s2", "s1", "s2", "s1"],
    })
    pq.write_table(table, tmp_path / "d.parquet")
    dataset = read_parquet(tmp_path / "d.parquet")
    assert dataset.ids == ("a", "b")
    np.testing.assert_array_equal(dataset["a"]["angle"], [0.1, 0.2, 0.3])
    assert dataset["b"].meta == {"subject": "s2"}
    assert dataset.context == ("distance",)


def test_parquet_from_another_tool_reads_its_hit_column_as_bools(tmp_path):
    table = {"trajectory": ["a", "a", "b", "b"], "angle": [0.1, 0.2, 0.1, 0.2]}
    pq.write_table(pa.table({**table, "hit": ["yes", "yes", "no", "no"]}), tmp_path / "words.parquet")
    pq.write_table(pa.table({**table, "hit": [1, 1, 0, 0]}), tmp_path / "numbers.parquet")
    for name in ("words", "numbers"):
        assert [t.meta["hit"] for t in read_parquet(tmp_path / f"{name}.parquet")] == [True, False]
    pq.write_table(pa.table({**table, "hit": ["yes", "yes", "perhaps", "perhaps"]}), tmp_path / "bad.parquet")
    with pytest.raises(InputError, match=r"bad.parquet: trajectory 'b' has hit 'perhaps' \(use true/false"):
        read_parquet(tmp_path / "bad.parquet")


def test_a_context_not_in_the_file_is_named_with_the_columns_it_has(tmp_path):
    # as the CSV reader names it; Parquet and NPZ had said "no context column 'bearing' in the data"
    table = {"trajectory": ["a", "a"], "angle": [0.1, 0.2], "distance": [2.0, 2.0]}
    pq.write_table(pa.table(table), tmp_path / "d.parquet")
    with pytest.raises(InputError, match=r"d.parquet: trajectory 'a' has no column 'bearing' \(columns: angle, "
                                         r"distance\)$"):
        read_parquet(tmp_path / "d.parquet", context=("bearing",))


def test_parquet_errors_name_the_file(tmp_path):
    pq.write_table(pa.table({"trajectory": ["a", "a"], "angle": [0.1, None]}), tmp_path / "null.parquet")
    with pytest.raises(InputError, match=r"null.parquet: column 'angle' has an empty value at row 2"):
        read_parquet(tmp_path / "null.parquet")
    pq.write_table(pa.table({"trajectory": ["a", "a", "b"], "angle": [0.1, 0.2, 0.3]}), tmp_path / "one.parquet")
    with pytest.raises(InputError, match=r"one.parquet: trajectory 'b' has a single sample"):
        read_parquet(tmp_path / "one.parquet")
    pq.write_table(pa.table({"trajectory": ["a", "a"], "angle": [0.1, 0.2], "subject": ["x", "y"]}),
                   tmp_path / "meta.parquet")
    with pytest.raises(InputError, match="metadata column 'subject' varies within trajectory 'a'"):
        read_parquet(tmp_path / "meta.parquet")
    # ids whose bytes are not UTF-8 (the fuzz test's damaged file): pyarrow decodes them only when read
    offsets = pa.py_buffer(np.array([0, 2, 2, 4], dtype=np.int32).tobytes())
    ids = pa.Array.from_buffers(pa.string(), 3, [None, offsets, pa.py_buffer(b"\xf40t1")])
    pq.write_table(pa.table({"trajectory": ids, "angle": [0.1, 0.2, 0.3]}), tmp_path / "bytes.parquet")
    with pytest.raises(InputError, match=r"bytes.parquet: damaged Parquet file: a text cell \(a trajectory id or a "
                                         r"metadata value\) is not UTF-8 text"):
        read_parquet(tmp_path / "bytes.parquet")


def _dataset_bytes(tmp_path, suffix: str) -> bytes:
    path = tmp_path / f"whole{suffix}"
    write_dataset(Dataset([Trajectory("t0", {"angle": np.array([0.1, 0.2]), "velocity": np.array([1.0, 2.0])})]), path)
    return path.read_bytes()


# (file content, made in tmp_path: suffix -> bytes; what the message says), for both binary readers
_OTHER_KINDS = {
    "a CSV": (lambda tmp, suffix: b"trajectory,angle,velocity\nt0,0.1,1\nt0,0.2,2\n",
              r"is text \(its first line: 'trajectory,angle,velocity'\), not {what}: rlff reads a dataset by its "
              r"suffix \(\.csv, .*\); give the file the suffix of what it holds"),
    "a text file": (lambda tmp, suffix: b"hello\n", r"is text \(its first line: 'hello'\), not {what}"),
    "an empty file": (lambda tmp, suffix: b"", r"is empty \(0 bytes\), not {what}$"),
    "a single array": (lambda tmp, suffix: b"\x93NUMPY\x01\x00", r"is a single numpy array \(an .npy file"),
    "the other binary format": (
        lambda tmp, suffix: _dataset_bytes(tmp, ".npz" if suffix == ".parquet" else ".parquet"),
        r"is a (ZIP archive|Parquet file) \(it starts with P"),
}
_WHAT = {".npz": (read_npz, r"an NPZ dataset \(a ZIP archive of numpy arrays\)"), ".parquet": (read_parquet, "a Parquet file")}


@pytest.mark.parametrize("suffix", list(_WHAT))
@pytest.mark.parametrize("case", list(_OTHER_KINDS))
def test_a_file_of_another_kind_says_what_it_looks_like(tmp_path, suffix, case):
    # it said pyarrow's "Parquet magic bytes not found in footer" and numpy's "This file contains
    # pickled (object) data" (a CSV or text file as an .npz); an .npy as an .npz was a TypeError
    content, message = _OTHER_KINDS[case]
    read, what = _WHAT[suffix]
    path = tmp_path / f"d{suffix}"
    path.write_bytes(content(tmp_path, suffix))
    with pytest.raises(InputError, match=rf"^{re.escape(str(path))} {message.format(what=what)}"):
        read(path)


@pytest.mark.parametrize(("suffix", "message"), [
    (".npz", r": an NPZ cut short or damaged: it starts as a ZIP archive, as an NPZ does, but the archive's "
             r"directory, at its end, is missing or unreadable$"),
    (".parquet", r": a Parquet file cut short: it starts with PAR1, but does not end with it as a whole one does$"),
])
def test_a_truncated_file_says_it_is_cut_short(tmp_path, suffix, message):
    whole = _dataset_bytes(tmp_path, suffix)
    path = tmp_path / f"cut{suffix}"
    path.write_bytes(whole[: len(whole) // 2])
    with pytest.raises(InputError, match=re.escape(str(path)) + message):
        _WHAT[suffix][0](path)


def test_an_npz_of_other_arrays_lists_what_it_holds(tmp_path):
    path = tmp_path / "other.npz"
    np.savez(path, **{name: np.arange(3) for name in "abcdef"})
    with pytest.raises(InputError, match=rf"^{re.escape(str(path))}: not an rlff NPZ dataset: it holds 'a', 'b', 'c', "
                                         r"'d', 'e', \.\.\. \(rlff's hold 'rlff', 'ids', 'lengths' and a 'column:NAME' "
                                         r"for each column\)$"):
        read_npz(path)
    np.savez(path)
    with pytest.raises(InputError, match="it holds no arrays"):
        read_npz(path)


def test_unknown_extension_and_format(tmp_path):
    with pytest.raises(InputError, match=r"unknown dataset extension '.xlsx'"):
        read_dataset(tmp_path / "d.xlsx")
    with pytest.raises(InputError, match="unknown dataset format 'hdf5'"):
        read_dataset(tmp_path / "d.csv", format="hdf5")
    with pytest.raises(InputError, match="no such file"):
        read_dataset(tmp_path / "missing.npz")


def test_large_parquet_loads_all_samples(tmp_path):
    count, length = 2000, 50
    angle = np.tile(np.linspace(0.7, 3.0, length), count)
    columns = {"angle": angle, "distance": np.repeat(np.arange(count) % 10 * 0.25 + 1.0, length),
               "velocity": angle * 3.0, "time": np.tile(np.arange(length) / 30.0, count)}
    dataset = Dataset.from_columns(columns, [f"t{i}" for i in range(count)], [length] * count,
                                   [{"hit": i % 3 == 0} for i in range(count)])
    write_dataset(dataset, tmp_path / "big.parquet")
    back = read_dataset(tmp_path / "big.parquet")
    assert back.n_samples == count * length
    assert back.equals(dataset)


def test_a_thesis_matrix_that_is_no_text_says_what_it_is(tmp_path):
    # it said "not a text file", for a compressed matrix and a UTF-16 one alike
    path = tmp_path / "m.txt"
    path.write_bytes("0.1\t0.2\n2\t2\n1\t1\n".encode("utf-16"))
    with pytest.raises(InputError, match=r"m.txt is UTF-16 text \(it starts with the byte-order mark ff fe\), not "
                                         r"UTF-8 text: save it as UTF-8 \(iconv -f UTF-16 -t UTF-8 FILE > new.txt\)"):
        read_thesis_matrix(path)
    path.write_bytes(b"0.1\t\xe9\n")
    with pytest.raises(InputError, match=r"m.txt: not UTF-8 text; save it as UTF-8$"):
        read_thesis_matrix(path)
