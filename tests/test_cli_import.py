"""``rlff data import`` end to end, as a user runs it."""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))
import bagfactory as bf  # noqa: E402
from rlff.dataset import read_csv  # noqa: E402

pytestmark = pytest.mark.slow  # every test starts the real command in a subprocess


@pytest.fixture(scope="module")
def bag(tmp_path_factory) -> Path:
    simulation = bf.standard_simulation(seed=11, n_throws=2)
    return bf.write_ros1_bag(tmp_path_factory.mktemp("cli") / "line1.bag", simulation, images=bf.jpeg_frames(4))


def test_import_a_bag_with_a_manifest_and_contact_sheets(cli, bag, tmp_path):
    manifest = tmp_path / "manifest.csv"
    manifest.write_text("file,throw,distance,subject\nline1.bag,1,2.0,anna\nline1.bag,2,3.25,anna\n")
    out = tmp_path / "demos.csv"
    result = cli("data", "import", str(bag), "--format", "bag", "--manifest", str(manifest),
                 "--contact-sheet", str(tmp_path / "sheets"), "--json", "-o", str(out))
    assert result.code == 0, result.stderr
    payload = json.loads(result.stdout)
    assert payload["throws"] == 2 and len(payload["contact_sheets"]) == 1
    assert Path(payload["contact_sheets"][0]).is_file()
    assert "dropped tracked user 2" in result.stderr
    dataset = read_csv(out)
    assert [t.meta["target"] for t in dataset] == [2.0, 3.25]
    assert all(t.meta["subject"] == "anna" and t.meta["distance_source"] == "manifest" for t in dataset)
    # NiTE frames hold the torso (neck, hips) but no wrist: the shoulder beside the elbow; the
    # simulated upper arm points 20 degrees from straight up, the torso upright
    assert set(dataset.columns) == {"time", "angle", "velocity", "shoulder", "shoulder_velocity", "distance"}
    for trajectory in dataset:
        assert np.median(np.abs(trajectory["shoulder"] - np.radians(160))) < 0.03
        assert np.median(np.abs(trajectory["shoulder_velocity"])) < 0.5


def test_import_msr_files_with_the_format_guessed(rlff, msr_dir, tmp_path):
    files = sorted(str(p) for p in msr_dir.glob("a06_s01_*.txt"))
    out = tmp_path / "msr.csv"
    result = rlff("data", "import", *files, "-o", str(out))
    assert result.code == 0, result.stderr
    assert "3 throws from 3 files" in result.stdout
    assert len(read_csv(out)) == 3


def test_an_import_of_many_files_says_each_kind_of_note_once(rlff, msr_dir, tmp_path):
    """Every file's "throwing arm" and "not a throw" notes buried the warnings (800 files: 2,273
    lines); many files say each kind once with its counts, one file says each note."""
    files = sorted(str(p) for p in msr_dir.glob("a06_*.txt"))
    result = rlff("data", "import", *files, "-o", str(tmp_path / "many.csv"))
    assert result.code == 0, result.stderr
    lines = result.stderr.splitlines()
    arms = [line for line in lines if "throwing arm" in line]
    assert arms == [f"throwing arm: right (the hand that sweeps furthest): {len(files)} files"]
    not_throws = [line for line in lines if "is not a throw" in line]
    assert len(not_throws) == 1 and "notes like this in" in not_throws[0], not_throws
    assert len([line for line in lines if not line.startswith("warning:")]) < 20
    one = rlff("data", "import", files[0], "-o", str(tmp_path / "one.csv"))
    assert f"{Path(files[0]).name}: throwing arm: right (the hand that sweeps furthest)" in one.stderr


def test_the_hits_of_throws_with_a_known_basket_are_said_with_what_judged_them(rlff, bag, tmp_path):
    # a lab's 48 throws at known baskets all read as short misses, and nothing said the default
    # estimate, not the throwers, made them so
    manifest = tmp_path / "manifest.csv"
    manifest.write_text("file,throw,distance\nline1.bag,1,2.0\nline1.bag,2,3.25\n")
    default = rlff("data", "import", str(bag), "--manifest", str(manifest), "-o", str(tmp_path / "a.csv"))
    assert default.code == 0, default.stderr
    dataset = read_csv(tmp_path / "a.csv")
    hits = sum(bool(t.meta["hit"]) for t in dataset)
    short = sum(t.meta["landing"] < t.meta["target"] for t in dataset)
    assert (f"{hits} of 2 throws with a known basket hit it, judged by the landing estimate, {short} of them short: "
            "the default estimate came down at 0.3 of the true landing") in " ".join(default.stderr.split())
    window = rlff("data", "import", str(bag), "--manifest", str(manifest), "-o", str(tmp_path / "b.csv"),
                 "--release-window", "0.1")
    assert "with a known basket hit it, judged by the landing estimate (--release-window 0.1)" in window.stderr
    unlabelled = rlff("data", "import", str(bag), "-o", str(tmp_path / "c.csv"))
    assert "with a known basket" not in unlabelled.stderr


def test_the_manifest_among_the_recordings_is_left_out_of_them(rlff, bag, tmp_path):
    # data import *.csv --manifest manifest.csv took the manifest for a recording: "manifest.csv:
    # column map (--columns): ... no column ...", never saying it was the --manifest
    manifest = tmp_path / "manifest.csv"
    manifest.write_text("file,throw,distance\nline1.bag,1,2.0\nline1.bag,2,3.25\n")
    result = rlff("data", "import", str(bag), str(manifest), "--manifest", str(manifest), "-o", str(tmp_path / "a.csv"))
    assert result.code == 0, result.stderr
    assert f"note: {manifest} is the --manifest: left out of the recordings" in result.stderr
    assert [t.meta["target"] for t in read_csv(tmp_path / "a.csv")] == [2.0, 3.25]
    alone = rlff("data", "import", str(manifest), "--manifest", str(manifest), "-o", str(tmp_path / "b.csv"))
    assert alone.code == 2 and f"the only file given is the --manifest {manifest}: give the recordings too" in alone.stderr


def test_a_release_window_measures_the_hand_near_the_release(rlff, bag, tmp_path):
    # the hand's mean over the elbow's fastest 0.28 s is half its peak speed or less: the window
    # about the release gives the same throws farther landings, and says nothing else differently
    runs = {}
    for name, extra in (("default", ()), ("window", ("--release-window", "0.1"))):
        out = tmp_path / f"{name}.csv"
        result = rlff("data", "import", str(bag), "--format", "bag", "-o", str(out), *extra)
        assert result.code == 0, result.stderr
        runs[name] = read_csv(out)
    assert runs["default"].ids == runs["window"].ids
    for default, window in zip(runs["default"], runs["window"], strict=True):
        assert window.meta["landing"] > 1.5 * default.meta["landing"]
        np.testing.assert_array_equal(window["angle"], default["angle"])
    refused = rlff("data", "import", str(bag), "--format", "bag", "-o", str(tmp_path / "x.csv"), "--release-window", "5")
    assert refused.code == 2 and "release window 5" in refused.stderr


def test_a_recording_copied_under_another_name_is_refused(rlff, msr_dir, tmp_path):
    # the check of paths let it through, and every throw of it counted twice
    original = msr_dir / "a06_s01_e01_skeleton3D.txt"
    copy = tmp_path / "copy_of_e01.txt"
    copy.write_bytes(original.read_bytes())
    result = rlff("data", "import", str(original), str(msr_dir / "a06_s01_e02_skeleton3D.txt"), str(copy),
                 "-o", str(tmp_path / "x.csv"))
    assert result.code == 2 and not (tmp_path / "x.csv").exists()
    assert f"{original} and {copy} hold the same throw, sample for sample" in result.stderr
    assert "give each recording once" in result.stderr


def test_a_recording_copied_under_a_name_with_a_distance_is_refused(rlff, msr_dir, tmp_path):
    # the copy's throws were labelled 2.5 m, the original's estimated: they compared as other throws
    original = msr_dir / "a06_s01_e01_skeleton3D.txt"
    copy = tmp_path / "e01_2.5m.txt"
    copy.write_bytes(original.read_bytes())
    result = rlff("data", "import", str(copy), str(original), "-o", str(tmp_path / "x.csv"))
    assert result.code == 2 and not (tmp_path / "x.csv").exists()
    assert f"{copy} and {original} hold the same throw, sample for sample (e01_2.5m_t1 and " in result.stderr
    assert "their baskets aside" in result.stderr


def test_missing_frames_are_one_line_and_exit_code_2(rlff, bag, tmp_path):
    result = rlff("data", "import", str(bag), "--frames", "a_1,b_1,c_1", "-o", str(tmp_path / "x.csv"))
    assert result.code == 2
    assert "frames there:" in result.stderr and "right_elbow_1" in result.stderr
    assert "Traceback" not in result.stderr
    assert not (tmp_path / "x.csv").exists()


def test_a_text_file_with_wrong_columns_is_named(rlff, tmp_path):
    path = tmp_path / "bad.txt"
    path.write_text("1 2 3 4\n1 2 3\n")
    result = rlff("data", "import", str(path), "--format", "msr", "-o", str(tmp_path / "x.csv"))
    assert result.code == 2
    assert f"{path}, line 2: 3 columns, expected 4" in result.stderr


def test_the_progress_of_one_long_recording_moves_as_its_throws_are_labelled(rlff, tmp_path):
    # one recording of many throws showed "importing 0/1 (0 %)" until it was done; a log (stderr
    # no terminal) now follows it through its parts
    bag = bf.write_ros1_bag(tmp_path / "session.bag", bf.standard_simulation(seed=5, n_throws=10))
    result = rlff("data", "import", str(bag), "-o", str(tmp_path / "demos.csv"))
    assert result.code == 0, result.stderr
    said = [re.sub(r" \d+:\d\d:\d\d$", "", line) for line in result.stderr.splitlines()
            if re.search(r" \d+/1 \(\d+ %\) \d+:\d\d:\d\d$", line)]
    assert said == ["importing 0/1 (0 %)", "session.bag: cutting throws 0/1 (40 %)",
                    *[f"session.bag: labelling throw {n} of 10 0/1 ({50 + 5 * (n - 1)} %)" for n in (1, 3, 5, 7, 9)],
                    "session.bag: done 1/1 (100 %)"], result.stderr
    assert "10 throws from 1 file" in result.stdout


def test_quiet_keeps_the_warnings(rlff, tmp_path):
    # -q hid every warning: a throw labelled with an estimated basket said nothing at all
    simulation = bf.standard_simulation(seed=2, n_throws=1, second_user=False)
    session = bf.write_ros1_bag(tmp_path / "session.bag", simulation, compression=None)
    result = rlff("-q", "data", "import", str(session), "-o", str(tmp_path / "d.csv"))
    assert result.code == 0, result.stderr
    assert "warning: 1 of 1 throws have an estimated basket distance" in result.stderr
    assert "not a throw" not in result.stderr and "dropped" not in result.stderr  # the notes stay quiet


def test_the_msr_folder_instead_of_its_files_says_which_files_to_give(rlff, msr_dir, tmp_path):
    out = tmp_path / "x.csv"
    for format in ((), ("--format", "msr")):
        result = rlff("data", "import", str(msr_dir), *format, "-o", str(out))
        assert result.code == 2
        line = result.stderr.strip().splitlines()[-1]
        assert line.startswith(f"rlff: error: {msr_dir}: is a folder")
        assert line.endswith(f"give the recordings in it: {msr_dir}/*.txt ({len(list(msr_dir.glob('*.txt')))} .txt files)")
        assert not out.exists()
