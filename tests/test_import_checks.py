"""``data import`` checks what it is given: units, basket distances, manifest rows, the count and
the JSON report of a failed import."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))
import bagfactory as bf  # noqa: E402
from rlff.capture import import_recordings  # noqa: E402
from rlff.capture.label import LandingSettings, distance_from_name, read_manifest  # noqa: E402
from rlff.errors import InputError  # noqa: E402


def _joint_csv(path: Path, seed: int = 4, scale: float = 1.0, n_throws: int = 1) -> Path:
    """A joint CSV of a simulated right arm (z up), its positions multiplied by ``scale``."""
    import pandas as pd

    simulation = bf.standard_simulation(seed=seed, n_throws=n_throws, noise=0.0, second_user=False)
    points = simulation.arm_positions(simulation.angle(simulation.frame_times))
    frame = pd.DataFrame({"time": simulation.frame_times})
    for joint, values in zip(("shoulder", "elbow", "hand"), points, strict=True):
        for axis, column in zip("xyz", values.T, strict=True):
            frame[f"right_{joint}_{axis}"] = column * scale
    path.parent.mkdir(parents=True, exist_ok=True)
    frame.to_csv(path, index=False)
    return path


@pytest.mark.parametrize(("scale", "units"), [(1000.0, "millimetres"), (100.0, "centimetres")])
def test_a_recording_not_in_metres_is_refused_with_its_upper_arm(tmp_path, scale, units):
    path = _joint_csv(tmp_path / "arm.csv", scale=scale)
    with pytest.raises(InputError) as error:
        import_recordings([path])
    message = str(error.value)
    assert message.startswith(f"{path}: the median upper arm") and "\n" not in message
    assert f"look like {units}" in message and "rlff reads metres" in message and "0.1-1 m" in message
    length = float(message.split(" measures ")[1].split()[0])
    assert 0.1 * scale <= length <= scale  # the simulated upper arm, in the file's units
    dataset, _ = import_recordings([_joint_csv(tmp_path / "metres.csv")])
    assert len(dataset) == 1


def test_an_estimated_landing_beyond_any_basket_is_left_out_with_a_warning(tmp_path):
    path = _joint_csv(tmp_path / "arm.csv")
    # a release 5 km up (standing for one too fast to be real) comes down about 35 m away
    dataset, report = import_recordings([path], up="z", landing=LandingSettings(shoulder_height=5000.0))
    assert len(dataset) == 0 and report.n_throws == 0
    assert report.files[0].rejected[-1].rule == "landing"
    assert any("farther than any basket (20 m)" in warning for warning in report.warnings)


def test_an_estimated_landing_at_the_nearest_basket_or_beyond_is_labelled_with_a_basket(tmp_path):
    path = _joint_csv(tmp_path / "arm.csv")
    # a rim 1.5 m up catches the ball 0.36 m out, rounded to 0.25 m where no basket stands: it was left out
    dataset, report = import_recordings([path], up="z", landing=LandingSettings(target_height=1.5))
    (throw,) = report.files[0].throws
    assert 0.3 <= throw.landing < 0.375 and throw.distance == 0.5
    assert float(dataset[0]["distance"][0]) == 0.5 and not report.files[0].rejected
    # nearer than 0.3 m, it is left out, saying so
    dataset, report = import_recordings([path], up="z", landing=LandingSettings(target_height=1.7))
    assert len(dataset) == 0 and report.files[0].rejected[-1].rule == "landing"
    (warning,) = [warning for warning in report.warnings if "left out" in warning]
    assert warning.endswith("m) is nearer than any basket (0.3 m): the hand came down near the body")
    assert "labelled" not in warning


def test_a_manifest_distance_out_of_range_names_its_line(tmp_path):
    manifest = tmp_path / "baskets.csv"
    manifest.write_text("file,throw,distance\narm.csv,1,2.0\narm.csv,2,25\n")
    with pytest.raises(InputError, match=r"^manifest .*baskets.csv, line 3: column 'distance': 25 m is outside the range 0.3 to 20 m$"):
        read_manifest(manifest)
    # in centimetres, as the dataset's and the learning's checks ask
    manifest.write_text("file,throw,distance\narm.csv,1,2.0\narm.csv,2,200\n")
    with pytest.raises(InputError, match=r"^manifest .*baskets.csv, line 3: column 'distance': 200 m is outside the range "
                                         r"0.3 to 20 m \(centimetres\? the distance is in metres\)$"):
        read_manifest(manifest)


def test_a_distance_out_of_range_in_a_file_name_names_the_file(tmp_path):
    assert distance_from_name("d1_250cm.bag") == 2.5
    for name, distance in (("d1_30m.bag", "30"), ("d1_2500cm.bag", "25"), ("line_0.1m.csv", "0.1")):
        with pytest.raises(InputError, match=rf"^{name}: the basket distance in the file name \({distance} m\) is outside the range 0.3 to 20 m"):
            distance_from_name(name)
    path = _joint_csv(tmp_path / "arm_30m.csv")
    with pytest.raises(InputError, match="arm_30m.csv: the basket distance in the file name"):
        import_recordings([path])


def test_a_manifest_row_for_no_recording_given_is_a_warning(tmp_path):
    path = _joint_csv(tmp_path / "session.csv")
    manifest = tmp_path / "baskets.csv"
    manifest.write_text("file,throw,distance\nsession.csv,1,2.0\nsesion.csv,1,1.0\n")
    dataset, report = import_recordings([path], manifest=manifest, up="z")
    assert [t.meta["target"] for t in dataset] == [2.0]
    assert report.warnings == [f"manifest {manifest}, line 3: sesion.csv is none of the recordings given; the row is not used"]
    assert report.to_dict()["warnings"] == report.warnings


def test_manifest_rows_for_recordings_not_given_are_one_note(tmp_path):
    # the manifest of a whole session, one of its recordings imported: every other recording's row
    # was a warning of its own (26 of them for one file of a 30-throw session), burying the real ones
    path = _joint_csv(tmp_path / "rec" / "session1.csv")
    for name in ("session2.csv", "session3.csv", "session4.csv", "session5.csv"):
        (tmp_path / "rec" / name).write_text("time\n")  # beside the recording given
    (tmp_path / "session6.csv").write_text("time\n")  # beside the manifest
    manifest = tmp_path / "baskets.csv"
    manifest.write_text("file,throw,distance\nsession1.csv,1,2.0\nsession2.csv,1,1.0\nsession2.csv,2,1.5\n"
                        "session3,1,1.0\nsession4.csv,1,1.0\nsession5.csv,1,1.0\nsession6.csv,1,3.0\nsesion1.csv,1,1.0\n")
    dataset, report = import_recordings([path], manifest=manifest, up="z")
    assert [t.meta["target"] for t in dataset] == [2.0]
    # a file found nowhere (misspelt) is still a warning of its own
    assert report.warnings == [f"manifest {manifest}, line 9: sesion1.csv is none of the recordings given; the row is not used"]
    assert report.general == [f"manifest {manifest}: 6 rows name 5 recordings not given (session2.csv, session3, "
                              "session4.csv and 2 more): not used"]
    assert report.to_dict()["notes"] == report.general
    # a manifest that names none of the recordings given labels nothing: one warning
    other = _joint_csv(tmp_path / "rec" / "other.csv")
    _, report = import_recordings([other], manifest=manifest, up="z")
    assert report.warnings == [
        f"manifest {manifest}, line 9: sesion1.csv is none of the recordings given; the row is not used",
        f"manifest {manifest} names none of the recordings given: its 7 rows for 6 other recordings (session1.csv, "
        "session2.csv, session3 and 3 more) are not used; give the manifest of these recordings",
    ]
    assert report.general == []


def test_manifest_rows_with_folders_tell_same_named_recordings_apart(tmp_path):
    first = _joint_csv(tmp_path / "d1" / "x.csv", seed=4)
    second = _joint_csv(tmp_path / "d2" / "x.csv", seed=5)
    manifest = tmp_path / "baskets.csv"
    manifest.write_text("file,throw,distance\nd1/x.csv,1,2.0\nd2/x.csv,1,3.0\n")
    dataset, report = import_recordings([first, second], manifest=manifest, up="z")
    assert [(t.meta["source"], t.meta["target"]) for t in dataset] == [(str(first), 2.0), (str(second), 3.0)]
    assert report.warnings == []
    # a row without a folder names both: against a row with one, two distances for one throw
    manifest.write_text("file,throw,distance\nx.csv,1,2.0\nd1/x.csv,1,3.0\n")
    with pytest.raises(InputError, match=r"line 3: d1/x.csv \(throw 1\) is listed again with distance 3 m; line 2 gives 2 m"):
        read_manifest(manifest)


def test_the_rows_of_a_thesis_matrix_are_counted(rlff, tmp_path):
    matrix, out = tmp_path / "th.txt", tmp_path / "thi.csv"
    assert rlff("data", "synth", "thesis", "-o", str(matrix)).code == 0
    result = rlff("data", "import", str(matrix), "--format", "thesis", "-o", str(out))
    assert result.code == 0 and result.stdout.startswith("11 throws from 1 file"), result.stdout
    result = rlff("data", "import", str(matrix), "--format", "thesis", "-o", str(out), "--json")
    payload = json.loads(result.stdout)
    assert payload["throws"] == 11 and payload["files"][0]["trajectories"] == 11


def test_json_reports_an_import_without_a_throw_before_exit_2(rlff, tmp_path):
    import pandas as pd

    path = _joint_csv(tmp_path / "still.csv")
    frame = pd.read_csv(path)
    frame.iloc[:, 1:] = np.tile(frame.iloc[0, 1:].to_numpy(), (len(frame), 1))  # the arm never moves
    frame.to_csv(path, index=False)
    out = tmp_path / "o.csv"
    result = rlff("data", "import", str(path), "--up", "z", "-o", str(out), "--json")
    assert result.code == 2 and not out.exists()
    payload = json.loads(result.stdout)
    assert payload["throws"] == 0 and payload["written"] is False and "no throw found" in payload["error"]
    assert "no throw found" in payload["files"][0]["warnings"][0]


def test_a_column_map_without_a_csv_recording_is_refused(tmp_path):
    # --columns was ignored without a word for bags and text
    simulation = bf.standard_simulation(seed=2, n_throws=1, second_user=False)
    bag = bf.write_ros1_bag(tmp_path / "session_2m.bag", simulation, compression=None)
    with pytest.raises(InputError, match=r"a column map \(--columns\) is for CSV recordings, and none is given "
                                         r"\(formats: bag\)"):
        import_recordings([bag], columns={"time": "stamp"})


def test_a_tsv_recording_is_read_as_csv(tmp_path):
    csv = _joint_csv(tmp_path / "joints.csv")
    tsv = tmp_path / "joints.tsv"
    tsv.write_text(csv.read_text().replace(",", "\t"))
    from_csv, _ = import_recordings([csv])
    from_tsv, _ = import_recordings([tsv])
    (a,), (b,) = from_csv, from_tsv
    assert np.allclose(a["angle"], b["angle"]) and a.meta["landing"] == pytest.approx(b.meta["landing"])


def test_a_manifest_time_span_without_a_throw_is_said_to_label_nothing(tmp_path):
    # such a row was ignored without a word; the throw then got a landing estimate instead
    csv = _joint_csv(tmp_path / "arm.csv", n_throws=2)
    manifest = tmp_path / "baskets.csv"
    manifest.write_text("file,start,end,distance\narm.csv,0,3,1.5\narm.csv,20,25,2.5\n")
    dataset, report = import_recordings([csv], manifest=manifest)
    (warning,) = [w for w in report.warnings if "the row is not used" in w]
    assert warning.startswith(f"manifest {manifest}, line 3: no throw of arm.csv peaks within 20-25 s (its throws peak at t = ")
    # the throw no row names is left out, not labelled by the landing estimate beside the manifest's basket
    assert [t.meta["distance_source"] for t in dataset] == ["manifest"]
    assert [r.rule for r in report.files[0].rejected if r.rule == "manifest"] == ["manifest"]
    (left_out,) = [w for w in report.warnings if "does not name every throw" in w]
    assert "throw 2 (t=" in left_out and "was left out: no row names it" in left_out


def test_a_thesis_matrix_is_told_from_a_tsv_recording_by_its_header(rlff, tmp_path):
    # .tsv is a thesis matrix's suffix as well as a tab-separated CSV's
    for name in ("th.tsv", "th.txt"):
        matrix = tmp_path / name
        assert rlff("-q", "data", "synth", "thesis", "-o", str(matrix)).code == 0
        result = rlff("data", "import", str(matrix), "-o", str(tmp_path / f"{name}.csv"))
        assert result.code == 0, result.stderr
        assert "11 throws from 1 file" in result.stdout


@pytest.mark.parametrize(("format", "said"), [
    (None, "is a folder, not a ROS 2 bag (no metadata.yaml in it): give the recordings in it: {dir}/*.txt (2 .txt files)"),
    ("msr", "is a folder, and --format msr reads files: give the recordings in it: {dir}/*.txt (2 .txt files)"),
    ("kinect-text", "is a folder, and --format kinect-text reads files: give the recordings in it: {dir}/*.txt "
                    "(2 .txt files)"),
    ("csv", "is a folder, and --format csv reads files: give the recordings themselves (the folder holds no .csv file)"),
    ("bag", "is a folder, not a ROS 2 bag (no metadata.yaml in it): give the recordings themselves (the folder holds "
            "no .bag file)"),
])
def test_a_folder_of_recordings_is_said_to_be_one_with_its_files_to_give(tmp_path, format, said):
    # it said "not a readable ROS 2 bag (Expected metadata file '<folder>' does not exist.)"
    folder = tmp_path / "msr"
    folder.mkdir()
    for name in ("a06_s01_e01_skeleton3D.txt", "a06_s01_e02_skeleton3D.txt", "README.md"):
        (folder / name).write_text("0.1 0.2 2.5 1\n")
    with pytest.raises(InputError) as error:
        import_recordings([folder], format)
    assert str(error.value) == f"{folder}: " + said.format(dir=folder)


def test_a_folder_of_ros2_bags_is_told_to_give_the_bags_and_a_bag_folder_passes(tmp_path):
    from rlff.capture.importer import refuse_folder

    bag = tmp_path / "session" / "take1"
    bag.mkdir(parents=True)
    (bag / "metadata.yaml").write_text("rosbag2_bagfile_information: {}\n")
    refuse_folder(bag)  # a ROS 2 bag: rosbags reads it (and says what is wrong with it)
    refuse_folder(bag, "bag")
    with pytest.raises(InputError, match=r"take1: is a folder, and --format msr reads files"):
        refuse_folder(bag, "msr")
    with pytest.raises(InputError) as error:
        refuse_folder(bag.parent)
    assert str(error.value) == (f"{bag.parent}: is a folder, not a ROS 2 bag (no metadata.yaml in it): give the ROS 2 "
                                f"bags in it: {bag.parent}/*/ (1 bag folder)")


def _throws(duration: float, peak: float) -> list:
    from rlff.capture.importer import ThrowInfo

    return [ThrowInfo("t1", 0.5, 0.5 + duration, 0.8, peak, (0.7, 3.0), 2.0, "manifest", None, 60.0, 0.02, "high")]


@pytest.mark.parametrize(("duration", "peak", "alone", "said"), [
    # a tester's 60 Hz Kinect file read at --rate 60: short, slow; was said 'faster than a throw'
    (0.49, 7.35, True, None),
    (0.43, 19.1, True, "they last a median 0.43 s wind-up to follow-through and peak at 19.1 rad/s, shorter than a "
                       "throw that fast (at least 0.5 s above 10 rad/s)"),
    (0.33, 22.5, False, "they last a median 0.33 s wind-up to follow-through, shorter than a throw (at least 0.5 s)"),
    (1.0, 40.0, True, "elbows peak at a median 40 rad/s, faster than a throw (at most 35 rad/s)"),
    (0.3, 40.0, True, "they last a median 0.3 s wind-up to follow-through, shorter than a throw (at least 0.5 s), and "
                      "their elbows peak at a median 40 rad/s, faster than a throw (at most 35 rad/s)"),
])
def test_throws_at_a_wrong_rate_are_said_to_be_short_or_fast_by_the_rule_they_break(duration, peak, alone, said):
    from rlff.capture.importer import _implausible

    assert _implausible(_throws(duration, peak), alone=alone) == said


def test_the_notes_of_many_files_are_summed_up_by_kind_and_a_few_said_in_full():
    from rlff.capture.importer import NOTES_IN_FULL, FileReport, ImportReport

    def file(name: str, times: list[float]) -> FileReport:
        notes = [f"{name}: throwing arm: right (the hand that sweeps furthest)"]
        notes += [f"{name}: elbow: movement at t={t:.2f} s is not a throw (peak 2.1 rad/s (below 3))" for t in times]
        return FileReport(source=f"/data/{name}", format="msr", notes=notes)

    files = [file(f"a{i:02d}.txt", [1.5 + i, 7.25]) for i in range(8)]  # 24 notes
    files.append(FileReport(source="/data/odd.txt", format="msr", notes=["odd.txt: read at 30 Hz (no time stamps)"]))
    report = ImportReport(files=files, general=["wrist left out: odd.txt has no hand"])
    assert len(report.notes) > NOTES_IN_FULL
    assert report.summary_notes() == [
        "throwing arm: right (the hand that sweeps furthest): 8 files",
        "16 notes like this in 8 files (--json lists each file's): a00.txt: elbow: movement at t=1.50 s is not a "
        "throw (peak 2.1 rad/s (below 3))",
        "odd.txt: read at 30 Hz (no time stamps)",
        "wrist left out: odd.txt has no hand",
    ]
    # one file, or few notes: each note as it is
    assert ImportReport(files=files[:1]).summary_notes() == files[0].notes
    few = ImportReport(files=files[:2], general=["all fine"])
    assert few.summary_notes() == few.notes == files[0].notes + files[1].notes + ["all fine"]


@pytest.mark.parametrize(("missing", "said"), [
    ("zzz.txt", "zzz.txt: no such file or folder"),
    ("a06_s04*.txt", "a06_s04*.txt: no file matches this pattern (the shell passed it on as it is)"),
])
def test_a_missing_recording_is_named_before_any_is_read(tmp_path, missing, said):
    # found only after every file before it was read (30 MSR files, then "zzz.txt: no such file")
    first = tmp_path / "a.txt"
    first.write_text("not a recording\n")
    read = []
    with pytest.raises(InputError) as caught:
        import_recordings([first, tmp_path / missing], "msr", progress=lambda path, stage, share: read.append(path))
    assert str(caught.value).startswith(f"{tmp_path / missing}: ") and said in str(caught.value)
    assert read == []
