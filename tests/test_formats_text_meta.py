"""Text metadata (subject, source, ...) and ids through a CSV round trip: kept as written.

A CSV cell holds no type. pandas read ``007`` as 7, ``1e3`` as 1000.0, ``nan`` as missing and
``True`` as a bool, so a subject ``0042`` (the importer takes it from a file ``0042.txt``) came back
as ``42``, and ``reject_contexts``, which groups by subject, saw other subjects than the Parquet file.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from rlff.dataset import TEXT_META_KEYS, Dataset, Trajectory, read_csv, write_csv
from rlff.errors import InputError
from rlff.formats import read_dataset, write_dataset

TRICKY = ["007", "1e3", "0042", "nan", "True", "NA", "None", "-0", " 5 "]


def _dataset(subjects, ids=None, **meta) -> Dataset:
    angle = np.array([0.5, 1.0, 1.5])
    trajectories = []
    for index, subject in enumerate(subjects):
        record = dict(meta)
        if subject is not None:
            record["subject"] = subject
        trajectories.append(
            Trajectory(
                ids[index] if ids else f"t{index}",
                {"angle": angle, "velocity": angle * (2 + index), "distance": np.full(3, 2.0)},
                record,
            )
        )
    return Dataset(trajectories)


@pytest.mark.parametrize("subject", TRICKY)
def test_a_text_subject_alone_in_its_column_reads_back_as_written(tmp_path, subject):
    # alone (every row the same text), pandas typed the whole column from it: '7', 1000.0, NaN, True
    dataset = _dataset([subject, subject])
    write_csv(dataset, tmp_path / "x.csv")
    again = read_csv(tmp_path / "x.csv")
    assert [t.meta["subject"] for t in again] == [subject, subject]
    assert again.equals(dataset)


@pytest.mark.parametrize("suffix", [".csv", ".parquet", ".npz", ".txt"])
def test_every_format_keeps_text_metadata_exactly(tmp_path, suffix):
    meta = {"source": "0042.txt", "distance_source": "1.5", "arm": "1", "release_confidence": "0",
            "target": 2.0, "hit": True, "glitches": 3}
    dataset = _dataset([*TRICKY, None], **meta)
    path = tmp_path / f"x{suffix}"
    write_dataset(dataset, path)
    again = read_dataset(path)
    assert again.equals(dataset)
    assert again.columns == dataset.columns or suffix == ".txt"  # the thesis matrix orders its rows
    assert [t.meta.get("subject") for t in again] == [*TRICKY, None]
    for trajectory in again:
        assert {key: trajectory.meta[key] for key in meta} == meta
        assert type(trajectory.meta["glitches"]) is int and type(trajectory.meta["target"]) is float


def test_csv_ids_that_pandas_took_for_missing_read_back(tmp_path):
    dataset = _dataset(["a", "b", "c"], ids=["nan", "NA", "007"])
    write_csv(dataset, tmp_path / "x.csv")
    assert read_csv(tmp_path / "x.csv").ids == ("nan", "NA", "007")


def test_an_older_csv_file_reads_its_text_metadata_as_text(tmp_path):
    # as earlier versions wrote it (the writer is unchanged): plain cells, no type anywhere
    path = tmp_path / "old.csv"
    path.write_text(
        "trajectory,angle,velocity,distance,subject,source,arm,target,hit,note,glitches\n"
        "a,0.5,1.0,2.0,007,0042.txt,1,2.0,True,nan,2\n"
        "a,1.0,2.0,2.0,007,0042.txt,1,2.0,True,nan,2\n"
        "b,0.5,1.5,2.0,,0043.txt,2,2.5,no,free text,0\n"
        "b,1.0,2.5,2.0,,0043.txt,2,2.5,no,free text,0\n"
    )
    dataset = read_csv(path)
    assert dataset.columns == ("angle", "velocity", "distance")
    first, second = dataset
    # text keys as written; an empty cell is no value
    assert first.meta == {"subject": "007", "source": "0042.txt", "arm": "1", "target": 2.0, "hit": True,
                          "glitches": 2}
    assert second.meta == {"source": "0043.txt", "arm": "2", "target": 2.5, "hit": False, "note": "free text",
                           "glitches": 0}


def test_a_text_key_that_varies_within_a_trajectory_is_still_an_error(tmp_path):
    path = tmp_path / "x.csv"
    path.write_text("trajectory,angle,velocity,distance,subject\na,0.5,1,2,7\na,1.0,2,2,7.0\n")
    with pytest.raises(InputError, match="metadata column 'subject' varies within trajectory 'a'"):
        read_csv(path)


def test_a_bad_sample_cell_is_still_named(tmp_path):
    path = tmp_path / "x.csv"
    path.write_text("trajectory,angle,velocity,distance,subject\na,0.5,1,2,nan\na,nan,2,2,nan\n")
    with pytest.raises(InputError, match=r"line 3: column 'angle' has an empty or nan value"):
        read_csv(path)


def test_the_missing_cells_of_other_columns_are_pandas_own():
    # the reader lists pandas' default missing-value cells to keep them for the other columns
    parsers = pytest.importorskip("pandas._libs.parsers")
    from rlff.dataset import _PANDAS_NA

    assert set(_PANDAS_NA) == set(parsers.STR_NA_VALUES)


def test_the_text_keys_are_metadata_keys():
    from rlff.dataset import META_KEYS

    assert set(TEXT_META_KEYS) <= set(META_KEYS)


def test_import_keeps_a_subject_from_the_manifest_or_the_file_name(tmp_path):
    # the tester's path: rlff data import -o x.csv, then read_dataset
    sys.path.insert(0, str(Path(__file__).parent))
    import bagfactory as bf
    from rlff.capture import import_recordings

    named = bf.write_ros1_bag(tmp_path / "0042.bag", bf.standard_simulation(seed=11, n_throws=2))
    other = bf.write_ros1_bag(tmp_path / "b.bag", bf.standard_simulation(seed=12, n_throws=2))
    manifest = tmp_path / "manifest.csv"
    manifest.write_text(
        "file,throw,distance,subject\n0042.bag,1,2.0,\n0042.bag,2,2.5,\nb.bag,1,2.0,007\nb.bag,2,2.5,1e3\n"
    )
    dataset, _ = import_recordings([named, other], "bag", manifest=manifest)
    assert [t.meta["subject"] for t in dataset] == ["0042", "0042", "007", "1e3"]
    for suffix in (".csv", ".parquet"):
        write_dataset(dataset, tmp_path / f"x{suffix}")
        again = read_dataset(tmp_path / f"x{suffix}")
        assert [t.meta["subject"] for t in again] == ["0042", "0042", "007", "1e3"]
        assert again.equals(dataset)
