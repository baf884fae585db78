"""rlff.fileio (atomic writes, outputs that are inputs), rlff.csvtable (exact fast CSV) and the
stated limits of rlff.limits."""

from __future__ import annotations

import os
import re
import resource
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rlff.csvtable import per_group_text, write_csv_columns
from rlff.dataset import Dataset, Trajectory, read_csv, write_csv
from rlff.errors import InputError
from rlff.fileio import (
    atomic_path,
    atomic_write,
    check_outputs,
    prepare_output,
    require_distinct,
    write_text,
)
from rlff.limits import MAX_MAGNITUDE, apart, check_count, check_period, check_range

# -- atomic writes -------------------------------------------------------------------------------


def test_a_failed_write_leaves_the_old_file_and_no_temporary(tmp_path):
    target = tmp_path / "out.txt"
    target.write_text("old\n")
    with pytest.raises(RuntimeError), atomic_write(target) as handle:
        handle.write("half of the new")
        raise RuntimeError("killed half-way")
    assert target.read_text() == "old\n"
    assert [p.name for p in tmp_path.iterdir()] == ["out.txt"]


@pytest.mark.skipif(not os.path.isdir("/proc/self"), reason="needs Linux's /proc, where no one can create a file")
def test_a_folder_the_system_refuses_is_named_by_the_output_not_the_temporary(tmp_path):
    # the message named a hidden ".m.o5q8w160.tmp.json" the user never gave
    with pytest.raises(InputError, match=r"^/proc/m.json: cannot write the output there \(") as error:
        write_text("/proc/m.json", "{}")
    assert ".tmp" not in str(error.value)


def test_a_writer_refused_mid_write_is_named_by_the_output(tmp_path):
    target = tmp_path / "out.txt"
    with pytest.raises(InputError, match=r"out.txt: cannot write the output there \(No space left on device\)"):
        with atomic_path(target) as temp:
            raise OSError(28, "No space left on device", str(temp))
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(OSError, match="other.txt"):  # an error about another file stays as it is
        with atomic_path(target):
            raise OSError(2, "No such file or directory", str(tmp_path / "other.txt"))


def test_the_new_file_appears_whole_and_keeps_the_old_mode(tmp_path):
    target = tmp_path / "out.txt"
    target.write_text("old\n")
    target.chmod(0o600)
    with atomic_write(target) as handle:
        handle.write("new\n")
        assert target.read_text() == "old\n"  # nothing visible until the block ends
    assert target.read_text() == "new\n" and target.stat().st_mode & 0o777 == 0o600


def test_a_new_file_gets_the_umask_mode(tmp_path):
    mask = os.umask(0o022)
    try:
        write_text(tmp_path / "new.txt", "x")
    finally:
        os.umask(mask)
    assert (tmp_path / "new.txt").stat().st_mode & 0o777 == 0o644


def test_a_linked_output_stays_a_link_and_its_target_gets_the_text(tmp_path):
    target = tmp_path / "data" / "real.csv"
    target.parent.mkdir()
    target.write_text("old")
    link = tmp_path / "out.csv"
    link.symlink_to(target)
    write_text(link, "new")
    assert link.is_symlink() and target.read_text() == "new"


@pytest.mark.parametrize("writer", ["text", "seeking", "removing first"])
def test_a_pipe_as_output_gets_the_bytes_and_stays_a_pipe(tmp_path, writer):
    """``-o /dev/stdout`` or a FIFO: renamed over, it became a plain file (as root, ``-o
    /dev/null`` replaced the system's /dev/null). A FIFO stands in for the device here; the
    writers are those of rlff's outputs: plain text, a CSV writer that seeks back and truncates,
    and a bag writer that wants no file where it writes."""
    import stat
    import threading

    fifo = tmp_path / "pipe.csv"
    os.mkfifo(fifo)
    received = []
    reader = threading.Thread(target=lambda: received.append(fifo.read_bytes()))
    reader.start()
    if writer == "text":
        write_text(fifo, "through the pipe")
    elif writer == "seeking":
        write_csv_columns(fifo, {"a": np.arange(3.0)})
    else:
        with atomic_path(fifo) as temp:
            temp.unlink()
            temp.write_bytes(b"through the pipe")
    reader.join(10)
    assert stat.S_ISFIFO(fifo.lstat().st_mode) and len(received) == 1
    if writer == "seeking":
        assert received[0].decode().splitlines() == ["a", "0", "1", "2"]
    else:
        assert received[0] == b"through the pipe"


def test_a_link_to_a_missing_file_creates_the_file_and_keeps_the_link(tmp_path):
    link = tmp_path / "out.csv"
    link.symlink_to(tmp_path / "made.csv")
    with atomic_path(link) as temp:  # a bag writer: it removes its file, then writes
        temp.unlink()
        temp.write_bytes(b"bag")
    assert link.is_symlink() and (tmp_path / "made.csv").read_bytes() == b"bag"


def test_atomic_path_keeps_the_suffix_for_writers_that_read_it(tmp_path):
    with atomic_path(tmp_path / "figure.png") as temp:
        assert temp.parent == tmp_path and temp.suffix == ".png" and temp.name.startswith(".")
        temp.write_bytes(b"png")
    assert (tmp_path / "figure.png").read_bytes() == b"png"


def test_a_folder_output_replaces_the_old_folder_whole(tmp_path):
    target = tmp_path / "bag"
    target.mkdir()
    (target / "old.db3").write_text("old")
    with atomic_path(target, folder=True) as temp:
        assert not temp.exists() and temp.name == "bag"  # the final name, in a hidden folder
        assert temp.parent.parent == tmp_path and temp.parent.name.startswith(".bag.")
        temp.mkdir()
        (temp / "new.db3").write_text("new")
        assert (target / "old.db3").exists()
    assert sorted(p.name for p in target.iterdir()) == ["new.db3"]
    assert [p.name for p in tmp_path.iterdir()] == ["bag"]
    with pytest.raises(RuntimeError), atomic_path(tmp_path / "broken", folder=True) as temp:
        temp.mkdir()
        raise RuntimeError("the writer failed")
    assert [p.name for p in tmp_path.iterdir()] == ["bag"]  # nothing left of it


@pytest.mark.parametrize(
    ("make", "output", "message"),
    [
        (lambda d: (d / "x").mkdir(), "x", "is a folder; give a file name"),
        (lambda d: (d / "f").write_text(""), "f/out.csv", "is a file, not a folder"),
    ],
)
def test_outputs_that_cannot_be_files_are_refused(tmp_path, make, output, message):
    make(tmp_path)
    with pytest.raises(InputError, match=message):
        write_text(tmp_path / output, "x")


def test_an_output_folder_that_is_no_folder_is_refused_saying_what_it_is(tmp_path):
    """A frames folder (rlff.sim.render) given a device or a FIFO had been called 'a file'."""
    os.mkfifo(tmp_path / "pipe")
    (tmp_path / "file").write_text("")
    (tmp_path / "link").symlink_to(tmp_path / "nowhere")
    for path, kind in (("/dev/null", "a device"), (tmp_path / "pipe", r"a FIFO \(named pipe\)"),
                       (tmp_path / "file", "a file"), (tmp_path / "link", rf"a broken link \(to {tmp_path}/nowhere\)")):
        with pytest.raises(InputError, match=rf"^{path}: is {kind}, not a folder; give a folder for the output$"):
            prepare_output(path, folder=True)


def test_missing_folders_of_an_output_are_created(tmp_path):
    write_text(tmp_path / "a" / "b" / "c.txt", "x")
    assert (tmp_path / "a" / "b" / "c.txt").read_text() == "x"


# -- writes the system refuses partway: a full disk, a quota, a file-size limit ------------------

#: Bytes a refused command may write to any file (``ulimit -f``, 1 KB blocks there): every output
#: below is larger, so the system refuses its write partway with EFBIG, as a full disk (ENOSPC)
#: or a used-up quota (EDQUOT) would; none of them names a file.
FILE_SIZE_LIMIT = 1024
EFBIG_LINE = "cannot write {where} (File too large); a limit on the size of a file, the shell's (ulimit -f)"


def _limited(*args: str, limit: int = FILE_SIZE_LIMIT, cwd=None) -> subprocess.CompletedProcess:
    """``rlff -q ARGS`` in a process that may write no file beyond ``limit`` bytes (``ulimit -f``)."""
    def set_limit() -> None:
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))

    return subprocess.run([sys.executable, "-m", "rlff", "-q", *args], capture_output=True, text=True, cwd=cwd,
                          timeout=600, preexec_fn=set_limit)


@pytest.fixture(scope="module")
def refused_inputs(tmp_path_factory):
    """A dataset and a throw for the robot, whose outputs are larger than FILE_SIZE_LIMIT."""
    from rlff.cli import main
    from rosrig import throw_csv

    folder = tmp_path_factory.mktemp("refused")
    data = folder / "data.csv"
    assert main(["-q", "data", "synth", "thesis", "--trajectories", "5", "--points", "20", "-o", str(data)]) == 0
    return {"data": data, "throw": throw_csv(folder, "throw.csv", 0.0, 0.3, 0.5)}


@pytest.mark.parametrize(
    ("command", "output"),
    [
        (["fit", "{data}", "-k", "2", "-o", "{out}"], "model.json"),  # Python's own write
        (["data", "synth", "thesis", "-o", "{out}"], "thesis.parquet"),  # pyarrow's, whose message is its own
        (["robot", "export", "{throw}", "-f", "ros2-bag", "-o", "{out}"], "bag"),  # SQLite's, no errno
    ],
    ids=["json", "parquet", "ros2-bag"],
)
def test_an_output_the_system_refuses_partway_is_named_with_the_reason(refused_inputs, tmp_path, command, output):
    # `ulimit -f 2; rlff fit c.csv -o m.json` said "rlff: error: File too large", naming no file
    # (a write's error carries none), and a ROS 2 bag "internal error: OperationalError: disk I/O error"
    out = tmp_path / output
    old = b"the previous output\n"
    if output != "bag":
        out.write_bytes(old)
    result = _limited(*[part.format(out=out, **refused_inputs) for part in command])
    assert result.returncode == 2, result.stderr
    line = result.stderr.strip().splitlines()[-1]
    if output == "bag":
        assert line.startswith(f"rlff: error: {out}: cannot write the output there (disk I/O error, said by SQLite)"), line
        assert not out.exists()
    else:
        assert line.startswith(f"rlff: error: {out}: " + EFBIG_LINE.format(where="the output there")), line
        assert out.read_bytes() == old  # left as it was
    assert sorted(p.name for p in tmp_path.iterdir()) == ([] if output == "bag" else [output])  # no temporary left


def test_an_output_through_a_temporary_file_names_the_output(refused_inputs, tmp_path):
    # a pipe or a device (-o /dev/stdout) gets the bytes of a temporary file in the system's folder
    fifo = tmp_path / "pipe.json"
    os.mkfifo(fifo)
    result = _limited("robot", "export", str(refused_inputs["throw"]), "-f", "json", "-o", str(fifo))
    assert result.returncode == 2, result.stderr
    line = result.stderr.strip().splitlines()[-1]
    assert line.startswith(f"rlff: error: {fifo}: cannot write the output through the temporary folder "), line
    assert "(File too large); a limit on the size of a file" in line


@pytest.mark.slow
def test_an_attempts_log_refused_partway_is_named_with_the_reason(tmp_path):
    # the learning loop appends each attempt to its log in place: the same refusal named no file
    from rlff.cli import main

    demos, log = tmp_path / "demos.csv", tmp_path / "attempts.jsonl"
    assert main(["-q", "data", "synth", "throws", "--subjects", "4", "-o", str(demos)]) == 0
    learn = ["learn", str(demos), "--preset", "thesis", "--basket", "1.4", "--update", "failure", "--log", str(log)]
    assert main(["-q", *learn, "--budget", "1"]) == 0
    logged = log.stat().st_size
    result = _limited(*learn, "--budget", "3", limit=logged + 100)  # room for the lock file, not an attempt
    assert result.returncode == 2, result.stderr
    line = result.stderr.strip().splitlines()[-1]
    # resumed with another budget, the run rewrites the log whole (its header records the budget)
    # with its next attempt, through a temporary file: "the output there"; in place, "there"
    assert (line.startswith(f"rlff: error: {log}: " + EFBIG_LINE.format(where="the output there"))
            or line.startswith(f"rlff: error: {log}: " + EFBIG_LINE.format(where="there"))), line
    assert log.stat().st_size == logged and not list(tmp_path.glob(".*attempts*"))  # as it was, no temporary left


# -- outputs that are inputs ---------------------------------------------------------------------


def test_an_output_equal_to_an_input_under_any_name_is_refused(tmp_path, monkeypatch):
    data = tmp_path / "data.csv"
    data.write_text("x")
    (tmp_path / "hard.csv").hardlink_to(data)
    (tmp_path / "soft.csv").symlink_to(data)
    monkeypatch.chdir(tmp_path)
    for spelling in ("data.csv", "./data.csv", str(data), "hard.csv", "soft.csv", "sub/../data.csv"):
        (tmp_path / "sub").mkdir(exist_ok=True)
        with pytest.raises(InputError, match="is the input DATA"):
            check_outputs({"DATA": data}, {"-o": spelling})
    check_outputs({"DATA": data}, {"-o": "other.csv", "--report": None})


def test_two_outputs_that_are_one_file_are_refused(tmp_path):
    with pytest.raises(InputError, match="-o and --report are the same file"):
        check_outputs({}, {"-o": tmp_path / "a.csv", "--report": tmp_path / "x" / ".." / "a.csv"})


def test_the_same_input_twice_is_refused(tmp_path):
    (tmp_path / "a.bag").write_text("")
    with pytest.raises(InputError, match="given twice"):
        require_distinct([tmp_path / "a.bag", tmp_path / "." / "a.bag"], "recording")
    require_distinct([tmp_path / "a.bag", tmp_path / "b.bag"], "recording")


# -- CSV -----------------------------------------------------------------------------------------


finite = st.floats(allow_nan=False, allow_infinity=False, width=64)


@settings(max_examples=60, deadline=None)
@given(st.lists(finite, min_size=1, max_size=50))
def test_csv_floats_read_back_bit_for_bit(tmp_path_factory, values):
    path = tmp_path_factory.mktemp("csv") / "x.csv"
    column = np.array(values)
    write_csv_columns(path, {"x": column})
    back = pd.read_csv(path)["x"].to_numpy(float)
    assert np.array_equal(back.view(np.int64), column.view(np.int64)) or np.array_equal(back, column)


def test_csv_extremes_and_text_cells(tmp_path):
    column = np.array([0.1, 1.0, -0.0, 5e-324, 1.7976931348623157e308, 2.0**53 + 2, 1 / 3])
    ids = per_group_text(["plain", 'with "quotes", a comma', "line\nbreak", None], [2, 2, 2, 1])
    path = write_csv_columns(tmp_path / "t.csv", {"id": ids, "x": column, "count": np.arange(7)})
    back = pd.read_csv(path, keep_default_na=False)
    assert np.array_equal(back["x"].to_numpy(float), column)
    assert back["id"].tolist() == ["plain", "plain", 'with "quotes", a comma', 'with "quotes", a comma',
                                   "line\nbreak", "line\nbreak", ""]
    assert back["count"].tolist() == list(range(7))
    plain = write_csv_columns(tmp_path / "p.csv", {"trajectory": per_group_text(["a", "b"], [1, 1]), "x": [0.5, 2.0]})
    assert plain.read_text() == "trajectory,x\na,0.5\nb,2\n"  # unquoted, as pandas wrote it


def test_a_dataset_round_trips_exactly_through_csv(tmp_path):
    rng = np.random.default_rng(3)
    trajectories = [
        Trajectory(f"t,{k}", {"angle": rng.normal(size=30), "distance": np.full(30, 1.0 + k / 3),
                               "velocity": rng.normal(size=30) * 1e-7},
                   {"subject": f"s{k}", "hit": k % 2 == 0, "landing": 1 / (k + 3)})
        for k in range(4)
    ]
    dataset = Dataset(trajectories)
    write_csv(dataset, tmp_path / "d.csv")
    back = read_csv(tmp_path / "d.csv")
    assert back.ids == dataset.ids
    for ours, theirs in zip(dataset, back, strict=True):
        for name in dataset.columns:
            assert np.array_equal(ours[name], theirs[name])
        assert theirs.meta == ours.meta


# -- limits --------------------------------------------------------------------------------------


def test_counts_above_the_maximum_name_both_numbers():
    with pytest.raises(InputError, match=r"grid: 100,000,000 is more than the 5,000,000 allowed \(fewer\)"):
        check_count("grid", 1e8, 5_000_000, "fewer")
    with pytest.raises(InputError, match="inf is more than"):
        check_count("grid", float("inf"), 10)
    assert check_count("grid", 10, 10) == 10


@pytest.mark.parametrize("value", [-1.0, 0.1, 21.0, float("nan"), 1e308])
def test_ranges_refuse_values_outside(value):
    # NaN was "nan m is outside the range"
    with pytest.raises(InputError, match="is not a number" if value != value else "outside the range 0.3 to 20 m"):
        check_range("basket distance", value, (0.3, 20.0))


@pytest.mark.parametrize(("value", "message"), [(0.0, "period must be a positive controller period (s), got 0.0"),
                                              (1e-6, "period 1e-06 s is shorter than 0.0001 s"),
                                              (10.0, "period 10 s is longer than 1 s: a controller period is in "
                                                     "seconds (milliseconds? 2 ms is 0.002)")])
def test_a_bad_period_names_the_parameter_not_a_command_line_option(value, message):
    # it said "--period ..." to a library caller of rlff.robot.plan (the CLI passes its option)
    with pytest.raises(InputError, match=rf"^{re.escape(message)}"):
        check_period(value)
    with pytest.raises(InputError, match=rf"^--{re.escape(message)}"):
        check_period(value, "--period")


def test_values_and_limits_print_with_enough_digits_to_differ():
    assert apart(2.7925268031909276, 2.792526803190927) == ("2.792526803190928", "2.792526803190927")
    assert apart(3.1, 2.792) == ("3.1", "2.792")
    assert apart(2.7925, 2.79249) == ("2.7925", "2.79249")


def test_data_values_beyond_the_magnitude_limit_are_refused():
    with pytest.raises(InputError, match=r"'angle' has the value 1e\+308, beyond the ±1e\+100"):
        Trajectory("t", {"angle": [0.0, 1e308]})
    with pytest.raises(InputError, match="non-finite"):
        Dataset.from_columns({"angle": np.array([0.0, np.inf])}, ["t"], [2])
    Trajectory("t", {"angle": [0.0, MAX_MAGNITUDE]})


def test_model_generate_refuses_a_grid_beyond_the_limit_before_working():
    from rlff.limits import MAX_GRID_POINTS
    from rlff.model import Model
    from rlff.model.mixture import GaussianMixture

    mixture = GaussianMixture.from_parameters(
        np.array([1.0]), np.array([[0.5, 2.0, 1.0]]), np.eye(3)[None] * 0.1
    )
    model = Model(mixture, ("angle", "distance"), ("velocity",), {"angle": (0.0, 1.0), "distance": (1.0, 3.0)})
    grid = np.broadcast_to(np.float64(0.5), (MAX_GRID_POINTS + 1,))  # no memory for the grid itself
    with pytest.raises(InputError, match=r"2,000,001 is more than the 2,000,000 allowed"):
        model.generate({"distance": 2.0}, grid)
