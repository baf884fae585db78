"""Fuzzing every file reader: damaged input loads or is an InputError naming the file.

Each test starts from a good file written by rlff itself, damages it (see tests/fuzz.py: bytes,
text fields and columns, JSON values) and checks that the reader returns something sound or
refuses with :class:`rlff.errors.InputError` naming the file; any other exception fails. Where
the reader returns numbers, they must be finite. Examples are bounded (``fuzz.FUZZ``) so the
suite stays fast; hypothesis keeps the failures it found in ``.hypothesis`` and replays them.
"""

from __future__ import annotations

import io
import json
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

sys.path.insert(0, str(Path(__file__).parent))
from fuzz import (  # noqa: E402
    FUZZ,
    ODD_FIELDS,
    check_reader,
    damaged,
    damaged_toml,
    file_with,
    json_bytes,
    toml_value,
)
from rlff.dataset import Dataset, Trajectory, write_csv  # noqa: E402
from rlff.errors import InputError  # noqa: E402
from rlff.formats import read_dataset, write_npz, write_parquet, write_thesis_matrix  # noqa: E402


def small_dataset(time: bool = True) -> Dataset:
    """Two throws with every kind of column: samples, time, context and metadata (the thesis
    matrix holds angle, distance and velocity only)."""
    rng = np.random.default_rng(0)
    trajectories = []
    for number, distance in enumerate((1.5, 2.5)):
        columns = {"angle": np.sort(rng.uniform(0.5, 2.5, 6)), "distance": np.full(6, distance),
                   "velocity": rng.normal(5, 1, 6)}
        if time:
            columns["time"] = np.arange(6) / 30.0
        trajectories.append(Trajectory(f"t{number}", columns, {"subject": "s1", "hit": bool(number), "target": distance}))
    return Dataset(trajectories)


def seed_file(write, name: str) -> bytes:
    """The bytes ``write(path)`` puts into a file called ``name``."""
    with file_with(b"", name) as path:
        write(path)
        return path.read_bytes()


def assert_finite_dataset(dataset: Dataset | None) -> None:
    if dataset is None:
        return
    for trajectory in dataset:
        for name in dataset.columns:
            assert np.all(np.isfinite(trajectory[name])), (trajectory.id, name)


# -- datasets: CSV, thesis matrix, NPZ, Parquet ---------------------------------------------------

CSV_SEED = seed_file(lambda path: write_csv(small_dataset(), path), "d.csv")
THESIS_SEED = seed_file(lambda path: write_thesis_matrix(small_dataset(time=False), path), "d.txt")
NPZ_SEED = seed_file(lambda path: write_npz(small_dataset(), path), "d.npz")
PARQUET_SEED = seed_file(lambda path: write_parquet(small_dataset(), path), "d.parquet")


@FUZZ
@given(st.data())
def test_dataset_csv(data):
    with file_with(data.draw(damaged(CSV_SEED)), "demos.csv") as path:
        assert_finite_dataset(check_reader(read_dataset, path))


#: Column names a table may have, repeated or missing.
_COLUMNS = ("trajectory", "angle", "distance", "velocity", "time", "subject", "hit", "angle", "")
_CELLS = st.sampled_from(ODD_FIELDS) | st.floats(allow_nan=True).map(repr) | st.sampled_from(("t0", "t1"))


@FUZZ
@given(
    header=st.lists(st.sampled_from(_COLUMNS), min_size=0, max_size=7),
    rows=st.lists(st.lists(_CELLS, min_size=0, max_size=8), max_size=6),
)
def test_dataset_csv_of_any_columns_and_cells(header, rows):
    text = "\n".join(",".join(cells) for cells in [header, *rows]) + "\n"
    with file_with(text.encode(), "table.csv") as path:
        assert_finite_dataset(check_reader(read_dataset, path))


@FUZZ
@given(st.data())
def test_dataset_thesis_matrix(data):
    with file_with(data.draw(damaged(THESIS_SEED)), "demos.txt") as path:
        assert_finite_dataset(check_reader(read_dataset, path))


@FUZZ
@given(st.data())
def test_dataset_npz(data):
    with file_with(data.draw(damaged(NPZ_SEED, text=False)), "demos.npz") as path:
        assert_finite_dataset(check_reader(read_dataset, path))


def _npz_parts() -> dict:
    with np.load(io.BytesIO(NPZ_SEED), allow_pickle=False) as npz:
        return {key: npz[key] for key in npz.files}


_ARRAYS = st.one_of(
    st.lists(st.floats(allow_nan=True, allow_infinity=True), max_size=14).map(np.array),
    st.lists(st.integers(-3, 20), max_size=4).map(lambda v: np.array(v, dtype=np.int64)),
    st.lists(st.text(max_size=3), max_size=3).map(lambda v: np.array(v, dtype=str)),
    st.just(np.zeros((2, 2))),
    st.just(np.array(3.0)),
)


@FUZZ
@given(st.data())
def test_dataset_npz_with_wrong_members(data):
    """A valid zip of valid arrays, with members replaced by arrays of other types and shapes,
    removed, or the rlff entry's JSON damaged."""
    parts = _npz_parts()
    info = json.loads(str(parts["rlff"]))
    for _ in range(data.draw(st.integers(1, 3))):
        key = data.draw(st.sampled_from(sorted(parts)))
        action = data.draw(st.sampled_from(("replace", "remove", "json")))
        if action == "remove":
            parts.pop(key, None)
        elif action == "json":
            from fuzz import damaged_json

            parts["rlff"] = np.array(json.dumps(data.draw(damaged_json(info)), allow_nan=True))
        else:
            parts[key] = data.draw(_ARRAYS)
    buffer = io.BytesIO()
    np.savez(buffer, **parts)
    with file_with(buffer.getvalue(), "demos.npz") as path:
        assert_finite_dataset(check_reader(read_dataset, path))


@FUZZ
@given(st.data())
def test_dataset_parquet(data):
    with file_with(data.draw(damaged(PARQUET_SEED, text=False)), "demos.parquet") as path:
        assert_finite_dataset(check_reader(read_dataset, path))


def test_a_parquet_file_whose_ids_point_past_their_dictionary_is_damaged():
    """Found by the fuzzing above on a random run: pyarrow reads this damaged file's id column
    with indices beyond its dictionary, and the reader indexed the names with them."""
    path = Path(__file__).parent / "data" / "damaged_ids.parquet"
    with pytest.raises(InputError, match="damaged Parquet file: the 'trajectory' column refers to ids it does not hold"):
        read_dataset(path)


def test_a_parquet_file_whose_column_name_is_not_utf8_is_damaged(tmp_path):
    """Found by the fuzzing above on a random run: one flipped byte in the footer made a column
    name that pyarrow could not decode, and its UnicodeDecodeError escaped the reader."""
    path = tmp_path / "demos.parquet"
    write_parquet(small_dataset(), path)
    content = path.read_bytes()
    # the footer names the column twice, in the schema (first) and in its chunk's path
    assert content.count(b"\x05angle") == 2
    path.write_bytes(content.replace(b"\x05angle", b"\x05\xe1ngle", 1))
    with pytest.raises(InputError, match="damaged Parquet file: a column name is not UTF-8 text"):
        read_dataset(path)


_PARQUET_COLUMNS = {
    "float": st.lists(st.floats(allow_nan=True, allow_infinity=True) | st.none(), min_size=4, max_size=4),
    "int": st.lists(st.integers(-(2**62), 2**62) | st.none(), min_size=4, max_size=4),
    "text": st.lists(st.text(max_size=3) | st.none(), min_size=4, max_size=4),
    "bool": st.lists(st.booleans() | st.none(), min_size=4, max_size=4),
}


@FUZZ
@given(
    columns=st.lists(
        st.tuples(st.sampled_from(_COLUMNS[:-1]), st.sampled_from(sorted(_PARQUET_COLUMNS))), max_size=6
    ),
    data=st.data(),
)
def test_dataset_parquet_of_any_columns_and_types(columns, data):
    import pyarrow as pa
    import pyarrow.parquet as pq

    fields = {}
    for name, kind in columns:
        fields.setdefault(name, pa.array(data.draw(_PARQUET_COLUMNS[kind])))
    with file_with(b"", "table.parquet") as path:
        pq.write_table(pa.table(fields) if fields else pa.table({}), path)
        assert_finite_dataset(check_reader(read_dataset, path))


# -- model.json -------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def model_document() -> dict:
    from rlff.model import Model

    rng = np.random.default_rng(1)
    X = np.column_stack([rng.uniform(0, 3, 60), np.repeat([1.0, 2.0, 3.0], 20), rng.normal(5, 1, 60)])
    return Model.fit(X, components=2).to_dict()


@FUZZ
@given(st.data())
def test_model_json(model_document, data):
    from rlff.model import Model

    with file_with(data.draw(json_bytes(model_document)), "model.json") as path:
        model = check_reader(Model.load, path)
        if model is not None:
            for array in (model.mixture.weights_, model.mixture.means_, model.mixture.covariances_):
                assert np.all(np.isfinite(array))


# -- the attempts log -------------------------------------------------------------------------------

_RUN = {"basket": 2.0, "feedback": "binary", "seed": 0}


def _log_seed() -> bytes:
    from rlff.learn.attempt import Attempt
    from rlff.learn.log import AttemptLog

    def write(path: Path) -> None:
        with AttemptLog(path, _RUN) as log:
            for index in (1, 2):
                log.append(Attempt(index, 2.0, 2.0, np.array([0.5, 1.0, 1.5]), np.array([3.0, 4.0, 3.5]),
                                   np.array([0.0, 0.1, 0.2]), index == 2, 1.8 + 0.1 * index, -0.2 + 0.1 * index))

    return seed_file(write, "attempts.jsonl")


LOG_SEED = _log_seed()


@st.composite
def damaged_log(draw: st.DrawFn) -> bytes:
    """The log with a line's JSON damaged, or its bytes or text."""
    from fuzz import damaged_json

    lines = LOG_SEED.decode().splitlines()
    if draw(st.booleans()):
        number = draw(st.integers(0, len(lines) - 1))
        lines[number] = json.dumps(draw(damaged_json(json.loads(lines[number]))), allow_nan=True)
        return ("\n".join(lines) + "\n").encode()
    return draw(damaged(LOG_SEED))


@FUZZ
@given(damaged_log())
def test_attempts_log(content):
    from rlff.learn.log import AttemptLog

    with file_with(content, "attempts.jsonl") as path:
        log = check_reader(lambda p: AttemptLog(p, _RUN), path)
        if log is not None:
            log.close()  # one run holds a log at a time
            assert all(attempt.index == number for number, attempt in enumerate(log.contents.attempts, start=1))
            # the file it left behind reads back the same attempts
            with AttemptLog(path, _RUN) as again:
                assert len(again.contents.attempts) == len(log.contents.attempts)


# -- preprocessing configs (TOML) -------------------------------------------------------------------


def _preset_text() -> bytes:
    from rlff.preprocess.pipeline import _presets

    return _presets().joinpath("thesis.toml").read_bytes()


TOML_SEED = _preset_text()


_TOML_VALUES = st.recursive(
    st.booleans() | st.integers(-(2**63), 2**63 - 1) | st.floats(allow_nan=True, allow_infinity=True)
    | st.sampled_from([1e308, -1e308, 1e-300, 0.0, -1.0, 0, -1]) | st.text(max_size=6),
    lambda children: st.lists(children, max_size=3),
    max_leaves=4,
)


@st.composite
def step_tables(draw: st.DrawFn) -> bytes:
    """[[step]] tables of real step names with parameters of the steps (or not) set to any value."""
    from rlff.preprocess import STEPS
    from rlff.preprocess.pipeline import _parameters

    names = sorted(STEPS) + ["nope"]
    blocks = []
    for _ in range(draw(st.integers(0, 3))):
        name = draw(st.sampled_from(names))
        known = sorted(_parameters(name)) if name in STEPS else []
        keys = draw(st.lists(st.sampled_from(known + ["enabled", "bogus"]), max_size=3, unique=True))
        lines = ["[[step]]", f"name = {json.dumps(name)}"]
        lines += [f"{key} = {toml_value(draw(_TOML_VALUES))}" for key in keys]
        blocks.append("\n".join(lines))
    return ("\n\n".join(blocks) + "\n").encode()


@FUZZ
@given(st.one_of(damaged(TOML_SEED), step_tables(), damaged_toml(tomllib.loads(TOML_SEED.decode()))))
def test_preprocess_toml(content):
    from rlff.preprocess.pipeline import Pipeline

    with file_with(content, "steps.toml") as path:
        check_reader(Pipeline.from_toml, path)


# -- robot files: description TOML, trajectory JSON and CSV ----------------------------------------


def _robot_seed() -> bytes:
    from importlib import resources

    return (resources.files("rlff") / "robots" / "comau_smart5_six.toml").read_bytes()


ROBOT_SEED = _robot_seed()


@FUZZ
@given(st.one_of(damaged(ROBOT_SEED), damaged_toml(tomllib.loads(ROBOT_SEED.decode()))))
def test_robot_toml(content):
    from rlff.robot.description import load_robot

    with file_with(content, "robot.toml") as path:
        robot = check_reader(load_robot, path)
        if robot is not None:
            lower, upper, speed = robot.limits()
            assert np.all(np.isfinite(lower)) and np.all(np.isfinite(upper)) and np.all(np.isfinite(speed))


def _trajectory():
    from rlff.trajectory.joint import JointTrajectory

    time = np.linspace(0.0, 0.4, 5)
    positions = np.column_stack([np.sin(time), np.cos(time), time])
    return JointTrajectory(("joint_1", "joint_2", "joint_3"), time, positions, np.gradient(positions, time, axis=0))


def _export_seed(kind: str) -> bytes:
    from rlff.robot import export

    return seed_file(lambda path: getattr(export, f"write_{kind}")(_trajectory(), path), f"t.{kind}")


TRAJECTORY_JSON_SEED = _export_seed("json")
TRAJECTORY_CSV_SEED = _export_seed("csv")


def _assert_finite_trajectory(trajectory) -> None:
    if trajectory is not None:
        for array in (trajectory.time, trajectory.positions, trajectory.velocities, trajectory.accelerations):
            assert np.all(np.isfinite(array))


@FUZZ
@given(json_bytes(json.loads(TRAJECTORY_JSON_SEED)))
def test_robot_trajectory_json(content):
    from rlff.robot.export import read_json

    with file_with(content, "trajectory.json") as path:
        _assert_finite_trajectory(check_reader(read_json, path))


@FUZZ
@given(st.data())
def test_robot_trajectory_csv(data):
    from rlff.robot.export import read_csv

    with file_with(data.draw(damaged(TRAJECTORY_CSV_SEED)), "trajectory.csv") as path:
        _assert_finite_trajectory(check_reader(read_csv, path))


# -- skeleton text: Kinect SDK, MSR Action3D, joint-position CSV -----------------------------------


def _skeleton_frames(count: int = 6) -> np.ndarray:
    """Frames (count, 20, 3) of a still body whose joints all differ."""
    rng = np.random.default_rng(2)
    return rng.uniform(-1.0, 1.0, (20, 3))[None] + 0.01 * np.arange(count)[:, None, None]


def _kinect_text() -> bytes:
    frames = _skeleton_frames()
    return "".join(
        f"{number} " + " ".join(f"{v:.4f}" for v in frame.ravel()) + "\n" for number, frame in enumerate(frames)
    ).encode()


def _msr_text() -> bytes:
    frames = _skeleton_frames()
    return "".join(f"{x:.4f} {y:.4f} {z:.4f} 1\n" for frame in frames for x, y, z in frame).encode()


def _joint_csv() -> bytes:
    frames = _skeleton_frames()
    header = ["time"] + [f"right_{joint}_{axis}" for joint in ("shoulder", "elbow", "wrist", "hand") for axis in "xyz"]
    rows = [[f"{k / 30:.4f}"] + [f"{v:.4f}" for v in frame[8:12].ravel()] for k, frame in enumerate(frames)]
    return ("\n".join(",".join(row) for row in [header, *rows]) + "\n").encode()


KINECT_SEED, MSR_SEED, JOINT_CSV_SEED = _kinect_text(), _msr_text(), _joint_csv()


def _assert_finite_recording(recording) -> None:
    if recording is None:
        return
    for arm in recording.arms:
        for joint in (arm.shoulder, arm.elbow, arm.hand):
            assert np.all(np.isfinite(joint.time)) and np.all(np.isfinite(joint.position))


@pytest.mark.parametrize(
    ("reader", "seed", "name"),
    [("read_kinect_text", KINECT_SEED, "skeleton.txt"), ("read_msr_text", MSR_SEED, "a06_s01_e01_skeleton.txt"),
     ("read_joint_csv", JOINT_CSV_SEED, "joints.csv")],
)
@FUZZ
@given(data=st.data())
def test_skeleton_text(reader, seed, name, data):
    from rlff.capture import skeleton_text

    with file_with(data.draw(damaged(seed)), name) as path:
        _assert_finite_recording(check_reader(getattr(skeleton_text, reader), path))


def test_fuzz_seeds_are_good_files():
    """The undamaged seeds load, so the fuzz starts from files the readers accept."""
    from rlff.capture import skeleton_text
    from rlff.learn.log import AttemptLog
    from rlff.model import Model
    from rlff.preprocess.pipeline import Pipeline
    from rlff.robot.description import load_robot
    from rlff.robot.export import read_csv, read_json

    for seed, name, read in [
        (CSV_SEED, "d.csv", read_dataset), (THESIS_SEED, "d.txt", read_dataset), (NPZ_SEED, "d.npz", read_dataset),
        (PARQUET_SEED, "d.parquet", read_dataset), (TOML_SEED, "s.toml", Pipeline.from_toml),
        (ROBOT_SEED, "r.toml", load_robot), (TRAJECTORY_JSON_SEED, "t.json", read_json),
        (TRAJECTORY_CSV_SEED, "t.csv", read_csv), (KINECT_SEED, "k.txt", skeleton_text.read_kinect_text),
        (MSR_SEED, "m.txt", skeleton_text.read_msr_text), (JOINT_CSV_SEED, "j.csv", skeleton_text.read_joint_csv),
    ]:
        with file_with(seed, name) as path:
            assert read(path) is not None, name
    with file_with(LOG_SEED, "a.jsonl") as path:
        with AttemptLog(path, _RUN) as log:
            assert len(log.contents.attempts) == 2
    rng = np.random.default_rng(1)
    X = np.column_stack([rng.uniform(0, 3, 60), np.repeat([1.0, 2.0, 3.0], 20), rng.normal(5, 1, 60)])
    with file_with(b"", "m.json") as path:
        Model.fit(X, components=2).save(path)
        assert Model.load(path).n_components == 2
    with pytest.raises(InputError):
        read_dataset(Path("/nonexistent/d.csv"))


# -- what the fuzz found, as fixed cases -----------------------------------------------------------


def _refused(read, content: bytes, name: str, message: str) -> None:
    with file_with(content, name) as path, pytest.raises(InputError) as caught:
        read(path)
    assert str(path) in str(caught.value) and message in str(caught.value), str(caught.value)


def test_csv_rows_longer_than_the_header_are_refused():
    # pandas took the first field as row labels and shifted every column by one
    _refused(read_dataset, b"angle,velocity\nt0,0.1,1.0\nt0,0.2,2.0\n", "d.csv", "more fields than the header's 2 columns")


def test_npz_damage_and_wrong_members_name_the_member():
    _refused(read_dataset, NPZ_SEED[: len(NPZ_SEED) // 2], "d.npz", "an NPZ cut short or damaged")
    for key, value, message in [
        ("lengths", np.array(["6", "6"]), "member 'lengths' must be a 1-D array of integers"),
        ("lengths", np.array([12]), "member 'lengths' has 1 entries for 2 ids"),
        ("rlff", np.array("[1]"), "member 'rlff' must hold a JSON object"),
        ("column:angle", np.zeros((2, 6)), "member 'column:angle' must be a 1-D array of numbers"),
    ]:
        parts = _npz_parts()
        parts[key] = value
        buffer = io.BytesIO()
        np.savez(buffer, **parts)
        _refused(read_dataset, buffer.getvalue(), "d.npz", message)


def test_parquet_null_ids_and_damaged_metadata_are_refused():
    import pyarrow as pa
    import pyarrow.parquet as pq

    for table, message in [
        (pa.table({"trajectory": [1.0, None, 2.0, 2.0], "angle": [0.0, 1.0, 2.0, 3.0]}), "empty trajectory id at row 2"),
        (pa.table({"trajectory": ["a", "a"], "angle": [0.0, 1.0]}).replace_schema_metadata({"rlff": "{"}),
         "damaged rlff entry in the Parquet metadata"),
        (pa.table({"trajectory": ["a", "a"], "angle": [0.0, 1.0]}).replace_schema_metadata(
            {"rlff": json.dumps({"meta_keys": ["subject"]})}), "metadata column 'subject' listed in the Parquet metadata is missing"),
    ]:
        with file_with(b"", "d.parquet") as path:
            pq.write_table(table, path)
            _refused(read_dataset, path.read_bytes(), "d.parquet", message)


def test_model_json_whose_scale_overflows_is_refused(model_document):
    from rlff.model import Model

    document = json.loads(json.dumps(model_document))
    document["scale"]["std"] = [1e-300] * len(document["columns"])
    _refused(Model.load, json.dumps(document).encode(), "model.json", "overflow on its standardised scale")


@pytest.mark.parametrize("value", ["nan", "inf", "-inf"])
def test_preprocess_toml_refuses_non_finite_numbers(value):
    from rlff.preprocess.pipeline import Pipeline

    content = f'[[step]]\nname = "densify"\nstep = {value}\n'.encode()
    _refused(Pipeline.from_toml, content, "steps.toml", f"parameter 'step' = {value}")


def test_robot_toml_of_wrong_shapes_or_bytes_is_refused():
    from rlff.robot.description import load_robot

    joint = '[[joints]]\nname = "j"\nlower = 0\nupper = 1\nmax_velocity = 1\nmax_acceleration = 4\nmax_jerk = 40\n'
    _refused(load_robot, b"\x80name = 1\n", "robot.toml", "not a UTF-8 text file")
    _refused(load_robot, b'name = "a"\njoints = [1]\n', "robot.toml", "joint 1 must be a [[joints]] table")
    _refused(load_robot, f'name = "a"\ngeometry = 1\n{joint}'.encode(), "robot.toml", "[geometry] must be a table")


def test_robot_trajectory_csv_faults_name_the_file():
    from rlff.robot.export import read_csv

    header = "time,j_position,j_velocity,j_acceleration\n"
    _refused(read_csv, b"", "t.csv", "not a readable CSV")
    _refused(read_csv, b"time,j_position,j_acceleration\n0,0,0\n", "t.csv", "no column 'j_velocity'")
    _refused(read_csv, (header + "0,0,0,0\n0,nan,0,0\n").encode(), "t.csv", "positions hold NaN or inf")
    _refused(read_csv, (header + "0,x,0,0\n").encode(), "t.csv", "not a robot trajectory")


# -- the generated path CSV (rlff generate -> sim throw, robot export) -----------------------------

PATH_SEED = (
    "angle,velocity,time,pdf,exploration,gmr_mean,distance\n"
    + "".join(f"{0.7 + 0.2 * k!r},{3.0 + k!r},{0.05 * k!r},0.5,0.1,{3.0 + k!r},2.5\n" for k in range(8))
).encode()


@FUZZ
@given(st.data())
def test_generated_path_csv(data):
    from rlff.trajectory.path_csv import read_generated_path

    with file_with(data.draw(damaged(PATH_SEED)), "traj.csv") as path:
        generated = check_reader(read_generated_path, path)
        if generated is not None:
            assert np.all(np.isfinite(generated.angle)) and np.all(np.isfinite(generated.velocity))
            assert generated.time is None or np.all(np.isfinite(generated.time))


def _readers():
    """Every reader with the extension its files have."""
    from rlff.capture.bag import read_bag as read_skeleton_bag
    from rlff.capture.skeleton_text import read_joint_csv, read_kinect_text, read_msr_text
    from rlff.learn.log import AttemptLog
    from rlff.model import Model
    from rlff.preprocess.pipeline import Pipeline
    from rlff.robot.description import load_robot
    from rlff.robot.export import read_bag, read_csv, read_json
    from rlff.trajectory.path_csv import read_generated_path

    return [
        (read_dataset, ".csv"), (read_dataset, ".npz"), (read_dataset, ".parquet"), (read_dataset, ".txt"),
        (Model.load, ".json"), (lambda path: AttemptLog(path, _RUN), ".jsonl"), (Pipeline.from_toml, ".toml"),
        (load_robot, ".toml"), (read_json, ".json"), (read_csv, ".csv"), (read_bag, ".bag"),
        (read_kinect_text, ".txt"), (read_msr_text, ".txt"), (read_joint_csv, ".csv"),
        (read_skeleton_bag, ".bag"), (read_generated_path, ".csv"),
    ]


@pytest.mark.parametrize(("read", "suffix"), _readers())
def test_every_reader_refuses_a_folder_and_a_missing_file(tmp_path, read, suffix):
    folder = tmp_path / f"folder{suffix}"
    folder.mkdir()
    with pytest.raises(InputError) as caught:
        read(folder)
    assert str(folder) in str(caught.value)
    missing = tmp_path / "nowhere" / f"missing{suffix}"
    if suffix == ".jsonl":  # a new attempts log is created with its folder
        assert read(missing).contents.attempts == []
        return
    with pytest.raises(InputError) as caught:
        read(missing)
    assert str(missing) in str(caught.value)
