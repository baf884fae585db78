"""The Dataset model: validation, bulk construction, grouping by context, the CSV long format."""

from __future__ import annotations

import numpy as np
import pytest

from rlff.dataset import Dataset, Trajectory, read_csv, write_csv
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


def test_dataset_rejects_duplicates_varying_context_and_time_going_back():
    with pytest.raises(InputError, match="duplicate trajectory id 'a'"):
        Dataset([_trajectory("a", 1.0), _trajectory("a", 2.0)])
    varying = _trajectory("a", 1.0).with_columns(distance=np.array([1.0, 1.0, 2.0, 1.0]))
    with pytest.raises(InputError, match="context column 'distance' is not constant"):
        Dataset([varying])
    backwards = _trajectory("a", 1.0).with_columns(time=np.array([0.0, 0.1, 0.1, 0.2]))
    with pytest.raises(InputError, match="time does not increase at sample 2"):
        Dataset([backwards])


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
    with pytest.raises(InputError, match=r"trajectory 'b': time does not increase at sample 2"):
        Dataset.from_columns(columns, ["a", "b"], [3, 3])
    columns = {"time": np.arange(6.0), "distance": np.array([1, 1, 1, 2, 2, 3.0])}
    with pytest.raises(InputError, match="trajectory 'b': context column 'distance' is not constant"):
        Dataset.from_columns(columns, ["a", "b"], [3, 3])
    with pytest.raises(InputError, match="trajectory 'a': column 'time' has a non-finite value at sample 1"):
        Dataset.from_columns({"time": np.array([0.0, np.inf])}, ["a"], [2])
    with pytest.raises(InputError, match="duplicate trajectory id 'a'"):
        Dataset.from_columns({"time": np.arange(4.0)}, ["a", "a"], [2, 2])


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
        ("trajectory,angle,velocity\na,0.1,0.2\na,nan,0.3\n", r"line 3: column 'angle' has a non-numeric or non-finite"),
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


def test_missing_column_is_named():
    dataset = Dataset([_trajectory("a", 1.0)])
    with pytest.raises(InputError, match=r"no column 'height' in the data \(columns: time, angle, distance, velocity\)"):
        dataset.require(["angle", "height"])
