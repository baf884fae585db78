"""The dataset CSV reader: the same Dataset and the same first fault whichever way (column-wise or
one trajectory at a time) a trajectory is checked. Its speed against pyarrow's and pandas' read of
the same file is benchmarks/csv_reading.py's (a ratio printed, not asserted here)."""

from __future__ import annotations

import numpy as np
import pytest

from rlff.dataset import Dataset, Trajectory, read_csv, write_csv
from rlff.errors import InputError


def _throws(count: int, length: int) -> Dataset:
    """``count`` throws of ``length`` samples with metadata of every kind a CSV holds: text kept
    as written, hit words, numbers, bools, empty cells."""
    rng = np.random.default_rng(3)
    trajectories = []
    for index in range(count):
        time_ = np.arange(length) / 30.0
        meta = {"subject": ["007", "nan", "s01"][index % 3], "source": f"take {index}.bag", "hit": index % 2 == 0,
                "target": float(rng.choice([1.5, 2.0, 2.5])), "glitches": index % 4}
        if index % 3:
            meta["note"] = ["calm", "windy, late"][index % 2]  # a cell with a comma: written quoted
        if index % 7:
            meta["landing"] = float(rng.uniform(1.0, 3.0))
        trajectories.append(Trajectory(f"t{index:04d}", {
            "time": time_, "angle": np.linspace(0.7, 3.0, length) + rng.normal(0.0, 0.01, length),
            "distance": np.full(length, meta["target"]), "velocity": rng.normal(5.0, 1.0, length)}, meta))
    return Dataset(trajectories)


def test_scattered_rows_read_as_contiguous_ones_with_every_kind_of_metadata(tmp_path):
    # scattered trajectories are checked one at a time, contiguous ones column-wise: both give
    # back what was written, the metadata of the same types
    dataset = _throws(12, 5)
    path = tmp_path / "throws.csv"
    write_csv(dataset, path)
    lines = path.read_text().splitlines()
    throws = [lines[1 + 5 * index : 6 + 5 * index] for index in range(12)]
    # the first 6 throws' rows interleaved two by two, each throw's in time order
    scattered = [row for first, second in zip(throws[:6:2], throws[1:6:2], strict=True)
                 for pair in zip(first, second, strict=True) for row in pair]
    scattered += [row for throw in throws[6:] for row in throw]
    (tmp_path / "scattered.csv").write_text("\n".join([lines[0], *scattered]) + "\n")
    for read in (read_csv(path), read_csv(tmp_path / "scattered.csv")):
        assert read.ids == dataset.ids
        assert read.equals(dataset)
        for mine, theirs in zip(read, dataset, strict=True):
            assert list(mine.meta) == list(theirs.meta)
            assert [(type(v), v) for v in mine.meta.values()] == [(type(v), v) for v in theirs.meta.values()]
            assert all(not values.flags.writeable and values.dtype == np.float64 for values in mine.data.values())


HEADER = "trajectory,time,angle,velocity,subject\n"


@pytest.mark.parametrize(("rows", "message"), [
    ("a,0,1,2,s\na,1,1,2,s\nb,0,1,1e300,s\nb,1,1,2,s\nc,0,1,2,s1\nc,1,1,2,s2\n",
     "trajectory 'b': column 'velocity' has the value 1e+300"),
    ("c,0,1,2,s1\nc,1,1,2,s2\nb,0,1,1e300,s\nb,1,1,2,s\n", "metadata column 'subject' varies within trajectory 'c'"),
    ("a,0,1,2,s\nb,0,1,2,s\nb,1,1,2,s\na,1,1,2,s\nc,0,1,2,s\nc,1,1,2,s\nc,0,1,2,s\nc,1,1,2,s\nd,0,1,2,s\n",
     "trajectory 'c' appears twice (lines 6-7 and 8-9)"),
    ("a,0,1,2,s\na,1,1,2,s\nb,0,1,2,s\nc,0,1,2,s\nc,0.5,1,2,s\nc,0.2,1,2,s\n", "line 4: trajectory 'b' has a single"),
])
def test_the_first_trajectory_at_fault_in_the_file_is_the_one_named(tmp_path, rows, message):
    path = tmp_path / "faults.csv"
    path.write_text(HEADER + rows)
    with pytest.raises(InputError, match=message.replace("(", r"\(").replace(")", r"\)").replace("+", r"\+")):
        read_csv(path)


def test_a_context_not_in_the_file_is_named_as_the_dataset_names_it(tmp_path):
    path = tmp_path / "throws.csv"
    write_csv(_throws(2, 3), path)
    with pytest.raises(InputError, match=r"throws.csv: trajectory 't0000' has no column 'bearing'"):
        read_csv(path, context=("bearing",))
