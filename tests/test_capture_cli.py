"""``rlff data import`` on what goes wrong: no throw, an existing output, estimated baskets, a y-up CSV, a bad manifest,
an up axis given to files of other conventions."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))
import bagfactory as bf  # noqa: E402
import thinned as th  # noqa: E402
from rlff.dataset import read_csv  # noqa: E402


@pytest.fixture(scope="module")
def session(tmp_path_factory) -> Path:
    """A simulated session (5 throws, a lowered forearm) as Kinect text at 6 Hz, irregular."""
    frames, time, _ = th.session(9)
    kept = th.thinned_indices(len(frames), 30.0, 6.0, "irregular", 0.0, np.random.default_rng(9))
    folder = tmp_path_factory.mktemp("import")
    return th.write_kinect_text(folder / "session.txt", frames[kept], np.rint(time[kept] * 30).astype(int))


@pytest.fixture(scope="module")
def still(tmp_path_factory) -> Path:
    """A person standing still: no throw."""
    frames, _, _ = th.session(9)
    folder = tmp_path_factory.mktemp("still")
    return th.write_kinect_text(folder / "still.txt", np.repeat(frames[:1], 60, axis=0), np.arange(60))


def test_no_throw_exits_2_naming_the_rule_and_keeps_an_existing_output(rlff, still, session, tmp_path):
    out = tmp_path / "demos.csv"
    assert rlff("data", "import", str(session), "-o", str(out)).code == 0
    before = out.read_bytes()
    result = rlff("data", "import", str(still), "-o", str(out))
    assert result.code == 2
    assert "no throw found" in result.stderr and "never rises by 0.30 rad" in result.stderr
    assert out.read_bytes() == before
    result = rlff("data", "import", str(still), "--allow-empty", "-o", str(out))
    assert result.code == 0 and "left as it was" in result.stderr and out.read_bytes() == before
    fresh = tmp_path / "empty.csv"
    assert rlff("data", "import", str(still), "--allow-empty", "-o", str(fresh)).code == 0
    assert fresh.read_text().splitlines()[0].startswith("trajectory")


def test_json_lists_every_candidate_not_taken_and_the_estimated_baskets(rlff, session, tmp_path):
    out = tmp_path / "demos.csv"
    result = rlff("data", "import", str(session), "--json", "-o", str(out))
    assert result.code == 0, result.stderr
    payload = json.loads(result.stdout)
    (file,) = payload["files"]
    assert payload["throws"] == 5 == payload["estimated_distances"]
    (lowered,) = [r for r in file["rejected"] if r["rule"] == "direction"]
    assert lowered["time"] > 0 and "down" in lowered["reason"] and "back" in lowered["reason"]
    assert f"movement at t={lowered['time']:.2f} s is not a throw" in result.stderr
    assert ("warning: 5 of 5 throws have an estimated basket distance (no manifest row, no distance in the file "
            "name: session.txt (5))") in result.stderr  # the files it concerns are named
    dataset = read_csv(out)
    assert {t.meta["release_confidence"] for t in dataset} == {"low"}
    assert all(4.0 <= t.meta["native_rate_hz"] <= 12.0 and 0.0 < t.meta["largest_gap"] < 0.75 for t in dataset)
    # resampled onto an even grid no coarser than 15 Hz
    assert all(np.allclose(np.diff(t["time"]), np.diff(t["time"])[0]) and np.diff(t["time"])[0] <= 1 / 15 + 1e-9 for t in dataset)
    for trajectory in dataset:
        assert trajectory.meta["start_time"] <= trajectory.meta["start_time"] + trajectory.meta["release_time"] <= trajectory.meta["end_time"]


def test_a_camera_frame_csv_without_up_suggests_up_y(rlff, msr_dir, tmp_path):
    frames = th.msr_frames(msr_dir / "a06_s01_e01_skeleton3D.txt")
    csv = th.write_joint_csv(tmp_path / "camera.csv", frames, np.arange(len(frames)) / 15.0)
    result = rlff("data", "import", str(csv), "-o", str(tmp_path / "x.csv"))
    assert "warning:" in result.stderr and "the upper arm hangs along -y" in result.stderr and "try --up y" in result.stderr
    result = rlff("data", "import", str(csv), "--up", "y", "-o", str(tmp_path / "x.csv"))
    assert result.code == 0 and "1 throw from 1 file" in result.stdout and "--up" not in result.stderr
    # standing still in a y-up frame: no throw, exit 2, and the hint in the no-throw warning
    still = th.write_joint_csv(tmp_path / "still.csv", np.repeat(frames[:1], 40, axis=0), np.arange(40) / 15.0)
    result = rlff("data", "import", str(still), "-o", str(tmp_path / "y.csv"))
    assert result.code == 2 and "no throw found" in result.stderr and "try --up y" in result.stderr


def _z_up_csv(path: Path, msr: Path, flip: bool = False, torso: bool = True) -> Path:
    """An MSR file as a joint CSV in a z-up frame (camera y up -> z), 15 Hz, with the torso's neck
    and hip centre unless ``torso`` is False; ``flip`` negates z (a file whose up is -z)."""
    import pandas as pd

    joints = {"right_shoulder": 1, "right_elbow": 8, "right_wrist": 10, "right_hand": 12,
              "left_shoulder": 0, "left_elbow": 7, "left_wrist": 9, "left_hand": 11, "neck": 2, "hip": 6}
    values = np.loadtxt(msr)[:, :3].reshape(-1, 20, 3)
    frames = np.stack([values[..., 0], -values[..., 2], values[..., 1] * (-1 if flip else 1)], axis=-1)
    columns = {"time": np.arange(len(frames)) / 15.0}
    for name, index in joints.items():
        if torso or name not in ("neck", "hip"):
            columns.update({f"{name}_{axis}": frames[:, index, i] for i, axis in enumerate("xyz")})
    pd.DataFrame(columns).to_csv(path, index=False, float_format="%.6f")
    return path


def test_the_up_hint_follows_the_torso_not_a_raised_throwing_arm(rlff, msr_dir, tmp_path):
    """An overhand thrower's upper arm is raised much of the time: six of the 26 MSR high throws as
    z-up CSVs were told "the upper arm hangs along z: ... try --up -z", and --up -z gave wrong throws."""
    sources = sorted(msr_dir.glob("a06_*_skeleton3D.txt"))
    assert len(sources) == 26
    upright = [_z_up_csv(tmp_path / f"{p.name[:11]}.csv", p) for p in sources]
    result = rlff("data", "import", *map(str, upright), "-o", str(tmp_path / "x.csv"))
    assert result.code == 0 and "--up" not in result.stderr, result.stderr
    result = rlff("data", "import", *map(str, sources), "-o", str(tmp_path / "m.csv"))
    assert result.code == 0 and "--up" not in result.stderr, result.stderr
    # without the torso the arm alone speaks, only when it hangs along another axis often enough
    bare = [_z_up_csv(tmp_path / f"bare_{p.name[:11]}.csv", p, torso=False) for p in sources]
    result = rlff("data", "import", *map(str, bare), "-o", str(tmp_path / "b.csv"))
    assert result.code == 0 and "--up" not in result.stderr, result.stderr
    # a file whose up really is -z is still told so, by its torso or (less sure) by its arm
    flipped = _z_up_csv(tmp_path / "flipped.csv", msr_dir / "a06_s06_e02_skeleton3D.txt", flip=True)
    result = rlff("data", "import", str(flipped), "-o", str(tmp_path / "f.csv"))
    assert ("the torso (hip centre to neck) points along -z: -z is up in this file, not z; try --up -z"
            in result.stderr)
    flipped = _z_up_csv(tmp_path / "flipped_bare.csv", msr_dir / "a06_s01_e01_skeleton3D.txt", flip=True, torso=False)
    result = rlff("data", "import", str(flipped), "-o", str(tmp_path / "g.csv"))
    assert "the upper arm hangs along z (within 30 degrees) in 44% of the samples" in result.stderr
    assert "-z may be up in this file (a camera frame); if so, try --up -z" in result.stderr


def test_a_manifest_listing_a_throw_twice_is_exit_2_with_the_row(rlff, session, tmp_path):
    manifest = tmp_path / "baskets.csv"
    manifest.write_text("file,throw,distance\nsession.txt,1,2.0\nsession.txt,1,2.5\n")
    result = rlff("data", "import", str(session), "--manifest", str(manifest), "-o", str(tmp_path / "x.csv"))
    assert result.code == 2 and "line 3: session.txt (throw 1) is listed again" in result.stderr
    assert not (tmp_path / "x.csv").exists()


def test_the_output_format_follows_its_extension_and_learn_reads_it(rlff, session, tmp_path):
    """-o x.parquet writes Parquet (it wrote CSV text under any name), an unknown extension fails
    before the import, and learn reads the file by its extension too."""
    from rlff.formats import read_parquet

    as_csv, as_parquet = tmp_path / "demos.csv", tmp_path / "demos.parquet"
    assert rlff("data", "import", str(session), "-o", str(as_csv)).code == 0
    assert rlff("data", "import", str(session), "-o", str(as_parquet)).code == 0
    assert as_parquet.read_bytes()[:4] == b"PAR1"
    written, expected = read_parquet(as_parquet), read_csv(as_csv)
    assert written.ids == expected.ids
    for a, b in zip(written, expected, strict=True):
        np.testing.assert_array_equal(a["angle"], b["angle"])
    result = rlff("data", "import", str(session), "-o", str(tmp_path / "demos.xlsx"))
    assert result.code == 2 and "unknown dataset extension '.xlsx'" in result.stderr
    assert not (tmp_path / "demos.xlsx").exists()
    learned = rlff("learn", str(as_parquet), "--preset", "thesis", "--basket", "1.2", "--budget", "1", "--json")
    assert learned.code == 0, learned.stderr
    assert json.loads(learned.stdout)["attempts"] == 1


def test_a_recording_that_stops_in_a_wind_up_says_so(rlff, tmp_path):
    # it said only "never rises by 0.30 rad or more (it stays within 0.77-2.96 rad)", as for a
    # person standing still, where the recording ended as the extension began
    frames, time, truth = th.session(9)
    keep = time < truth[0].start + th._WIND_UP + th._HOLD + 0.08  # 0.08 s into the first extension
    cut = th.write_kinect_text(tmp_path / "cut.txt", frames[keep], np.arange(int(keep.sum())))
    result = rlff("data", "import", str(cut), "-o", str(tmp_path / "demos.csv"))
    assert result.code == 2
    assert ("never rises by 0.30 rad or more (it stays within" in result.stderr
            and "still rising where the recording ends: it may stop before the throw's extension" in result.stderr)


@pytest.fixture(scope="module")
def bag(tmp_path_factory) -> Path:
    """Two simulated throws as a NiTE tf bag (z up)."""
    simulation = bf.standard_simulation(seed=4, n_throws=2, second_user=False)
    return bf.write_ros1_bag(tmp_path_factory.mktemp("bag") / "line.bag", simulation, compression=None)


def test_one_up_for_files_of_other_conventions_is_warned_of(rlff, bag, session, tmp_path):
    # a z-up bag read with the --up y of the camera-frame files beside it changed its landings
    # and baskets without a word
    result = rlff("data", "import", str(bag), str(session), "--up", "y", "-o", str(tmp_path / "x.csv"))
    assert result.code == 0, result.stderr
    (line,) = [line for line in result.stderr.splitlines() if "is applied to every file" in line]
    assert line == ("warning: --up y is applied to every file of this import, but 1 bag file (line.bag) is in a frame "
                    "with z up (REP 103, as skeleton trackers publish tf) and is read with y up: its releases, landings "
                    "and estimated baskets change with it; import each format apart, with its own --up or none")
    # the Kinect text's own convention is y up; without --up each format keeps its own
    assert "session.txt" not in line
    alone = rlff("data", "import", str(bag), str(session), "-o", str(tmp_path / "y.csv"))
    assert alone.code == 0 and "is applied to every file" not in alone.stderr


def test_every_throw_taken_for_the_arm_coming_down_with_an_up_given_asks_about_the_up_axis(rlff, bag, tmp_path):
    result = rlff("data", "import", str(bag), "--up", "x", "-o", str(tmp_path / "x.csv"))
    assert result.code == 2 and "no throw found" in result.stderr
    assert ("both its extensions went down at the release, as the arm coming down to rest does, and as every throw "
            "does with a wrong up axis: is x up in this file? (up was taken as x, --up x)") in result.stderr
    assert rlff("data", "import", str(bag), "-o", str(tmp_path / "z.csv")).code == 0


def test_import_batches_that_share_a_recording_join_with_data_merge(rlff, bag, session, tmp_path):
    # a lab's day: two import batches, the second re-importing a recording of the first.
    # `data import batch1.csv batch2.csv` read the datasets as joint positions and asked for
    # --columns right_elbow_x=...; the batches appended by hand said "time does not increase ...
    # sort them", and sorting did not help
    batch1, batch2 = tmp_path / "batch1.csv", tmp_path / "batch2.csv"
    assert rlff("data", "import", str(session), "-o", str(batch1)).code == 0
    assert rlff("data", "import", str(session), str(bag), "-o", str(batch2)).code == 0
    result = rlff("data", "import", str(batch1), str(batch2), "-o", str(tmp_path / "all.csv"))
    assert result.code == 2
    assert result.stderr.strip().splitlines()[-1] == (
        f"rlff: error: {batch1} and {batch2} are rlff datasets (trajectory, angle, velocity columns: throws already "
        f"imported), not recordings: join them with `rlff data merge {batch1} {batch2} -o all.csv` (docs/data.md)")
    result = rlff("data", "import", str(batch1), str(bag), "-o", str(tmp_path / "all.csv"))
    assert result.code == 2 and (f"{batch1} is an rlff dataset" in result.stderr
                                 and "import the recordings alone (-o new.csv), then join" in result.stderr)

    # the bag has no hand beside the wrist: the second batch has no wrist columns, the first has
    result = rlff("data", "merge", str(batch1), str(batch2), "-o", str(tmp_path / "all.csv"))
    assert result.code == 2 and result.stderr.strip() == (
        f"rlff: error: {batch2} and {batch1} have different columns ({batch2} lacks wrist, wrist_velocity): datasets "
        "merge only with the same columns (import every batch with the same --joints)")
    for batch, recordings in ((batch1, [session]), (batch2, [session, bag])):
        assert rlff("data", "import", *map(str, recordings), "--joints", "elbow,shoulder", "-o", str(batch)).code == 0

    joined = tmp_path / "joined.csv"  # appended by hand: the shared throw twice under its id
    joined.write_text(batch1.read_text() + "".join(batch2.read_text().splitlines(keepends=True)[1:]))
    result = rlff("fit", str(joined), "-o", str(tmp_path / "m.json"))
    assert result.code == 2 and "appears twice (lines" in result.stderr and "rlff data merge" in result.stderr

    merged = tmp_path / "all.csv"
    result = rlff("data", "merge", str(batch1), str(batch2), "-o", str(merged))
    assert result.code == 0, result.stderr
    first, second = read_csv(batch1), read_csv(batch2)
    assert result.stdout.strip() == (f"{len(second)} throws from 2 datasets, {len(first)} throws held twice kept once "
                                     f"-> {merged}")
    assert f"{first.ids[0]}: in {batch1} and again in {batch2}, the same throw: kept once" in result.stderr
    assert read_csv(merged).equals(second)
    assert rlff("fit", str(merged), "-o", str(tmp_path / "m.json")).code == 0
    # the same id for two different throws is the user's call: refused, naming what differs
    relabelled = tmp_path / "relabelled.csv"
    relabelled.write_text(batch1.read_text().replace(str(session), str(session.parent / "elsewhere" / session.name)))
    result = rlff("data", "merge", str(batch1), str(relabelled), "-o", str(tmp_path / "x.csv"))
    assert result.code == 2 and f"is in {batch1} and in {relabelled} with metadata 'source'" in result.stderr
    assert not (tmp_path / "x.csv").exists()
