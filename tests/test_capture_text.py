"""Skeleton text formats (Kinect SDK v1, MSR Action3D, CSV), the angle and the throw labels."""

from __future__ import annotations

import os
import re
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

sys.path.insert(0, str(Path(__file__).parent))
import bagfactory as bf  # noqa: E402
from rlff.ballistics import crossing_distance  # noqa: E402
from rlff.capture import import_recordings  # noqa: E402
from rlff.capture.angles import align_arm, derivative_window, included_angle, local_derivative  # noqa: E402
from rlff.capture.label import LandingSettings, distance_from_name, manifest_entry, read_manifest  # noqa: E402
from rlff.capture.segment import SegmentSettings, find_throws  # noqa: E402
from rlff.capture.skeleton_text import read_joint_csv, read_kinect_text, read_msr_text  # noqa: E402
from rlff.errors import InputError  # noqa: E402


def _kinect_frames(simulation: bf.Simulation) -> np.ndarray:
    """Frames of shape (T, 20, 3): the right arm of the simulation at Kinect indices 8-11 (y up)."""
    angle = simulation.angle(simulation.frame_times)
    shoulder, elbow, hand = simulation.arm_positions(angle)
    to_kinect = np.array([[0, -1, 0], [0, 0, 1], [1, 0, 0]], dtype=float)  # ROS (x fwd, z up) -> Kinect (y up)
    frames = np.tile(np.array([0.1, 0.2, 2.5]), (len(angle), 20, 1))
    frames[:, 4:8] += np.array([0.4, 0.0, 0.0])  # the left arm hangs still
    frames[:, 8], frames[:, 9], frames[:, 11] = shoulder @ to_kinect.T, elbow @ to_kinect.T, hand @ to_kinect.T
    frames[:, 10] = frames[:, 9] + 0.9 * (frames[:, 11] - frames[:, 9])  # wrist on the forearm
    return frames


def _write_kinect(path: Path, frames: np.ndarray, numbers: np.ndarray) -> Path:
    lines = [" ".join([str(int(n)), *(f"{v:.6f}" for v in frame.ravel())]) for n, frame in zip(numbers, frames, strict=True)]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_included_angle_exact_cases():
    elbow = np.zeros((4, 3))
    shoulder = np.tile([1.0, 0.0, 0.0], (4, 1))
    hand = np.array([[0.0, 2.0, 0.0], [-3.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, np.sqrt(3) / 2, 0.0]])
    np.testing.assert_allclose(included_angle(shoulder, elbow, hand), [np.pi / 2, np.pi, 0.0, np.pi / 3], atol=1e-12)


def test_local_derivative_is_exact_on_cubics_even_or_not_and_the_chord_when_sparse():
    t = np.arange(40) / 30.0
    values = 2 * t**3 - t**2 + 3 * t
    np.testing.assert_allclose(local_derivative(t, values, 0.2), 6 * t**2 - 2 * t + 3, atol=1e-9)
    uneven = np.cumsum(np.random.default_rng(0).uniform(0.5, 1.5, 60)) / 30.0
    cubic = 2 * uneven**3 - uneven**2 + 3 * uneven
    np.testing.assert_allclose(local_derivative(uneven, cubic, 0.3), 6 * uneven**2 - 2 * uneven + 3, atol=1e-8)
    # at 4 Hz no window of 0.35 s holds 3 samples: the 3-point derivative on the uneven spacing
    sparse = np.array([0.0, 0.2, 0.5, 0.8, 1.1])
    assert derivative_window(sparse) == 0.35 and derivative_window(t) == 0.25 and derivative_window(t[::2]) == pytest.approx(4 / 15)
    quadratic = sparse**2
    np.testing.assert_allclose(local_derivative(sparse, quadratic, 0.35)[1:-1], 2 * sparse[1:-1], atol=1e-12)


@pytest.mark.parametrize("phase", [0.0, 0.5])
@pytest.mark.parametrize("width", [0.4, 0.5])
def test_a_throws_peak_speed_comes_out_about_the_same_at_15_to_120_hz(width, phase):
    """An elbow extension of 2.2 rad whose speed is a smooth bump ``width`` s wide (8.8-11 rad/s at
    its peak), sampled at 15, 30, 60 and 120 Hz, ``phase`` of a frame late: the fit over 0.25 s
    flattens the peak about alike at every rate (to 69-92 %), at 15 Hz within 15 % of 120 Hz's. The
    quadratic fit of 5 samples that 15 Hz had before gave 42-52 % of the peak there."""
    peak = 2.2 * 2 / width

    def angle(t):  # the integral of a raised-cosine speed bump centred on t = 1 s
        u = np.clip(t - 1.0 + width / 2, 0.0, width)
        return 0.8 + peak * 0.5 * (u + width / (2 * np.pi) * np.sin(2 * np.pi * u / width))

    found = {}
    for rate in (15, 30, 60, 120):
        t = (np.arange(2 * rate) + phase) / rate
        found[rate] = float(local_derivative(t, angle(t), derivative_window(t)).max()) / peak
    assert all(0.65 < share < 1.0 for share in found.values()), found
    assert found[15] == pytest.approx(found[120], rel=0.15), found
    assert found[30] == pytest.approx(found[120], rel=0.1) and found[60] == pytest.approx(found[120], rel=0.05), found


def test_kinect_text_gives_the_true_angle_drops_repeats_and_lost_frames(tmp_path):
    simulation = bf.standard_simulation(seed=2, n_throws=2, noise=0.0, second_user=False, drop_frames=0.0, drop_joints=0.0)
    frames = _kinect_frames(simulation)
    numbers = np.arange(len(frames))
    frames[30] = 0.0  # tracking lost
    order = np.r_[np.arange(50), 49, np.arange(50, len(frames))]  # frame 49 written twice
    path = _write_kinect(tmp_path / "kinect.txt", frames[order], numbers[order])
    recording = read_kinect_text(path)
    assert any("1 frames with all arm joints at zero" in note for note in recording.notes)
    assert any("1 repeated frame number " in note for note in recording.notes)
    right = recording.arm("1", "right")
    assert len(right.elbow) == len(frames) - 1
    motion = align_arm(right)
    # the wrist lies on the forearm, so the angle is exact where frames exist
    truth = simulation.angle(motion.time)
    on_frame = np.isin(np.round(motion.time * 30), numbers[numbers != 30])
    np.testing.assert_allclose(motion.angle[on_frame], truth[on_frame], atol=1e-5)
    dataset, report = import_recordings([path], "kinect-text")
    assert len(dataset) == 2 and report.files[0].arm == "right"
    for one in (path, str(path)):  # one recording, not in a list: not read as the characters of its path
        assert [t.id for t in import_recordings(one, "kinect-text")[0]] == [t.id for t in dataset]
    # read at ten times its rate, its throws fail other rules first: the file's warning asks about the rate
    dataset, report = import_recordings([path], "kinect-text", rate_hz=300.0)
    assert len(dataset) == 0
    assert any(w.startswith(f"{path}: ") and w.endswith("was it recorded at the 300 Hz it was read at? (--rate)")
               for w in report.warnings), report.warnings


def test_the_import_of_one_recording_tells_each_throw_it_labels_and_the_share_done(tmp_path):
    # a 100-minute recording is one file: told only as it was read, cut and done, its progress bar
    # sat still while the labelling of its hundreds of throws took most of the time
    from rlff.capture.importer import CUT_SHARE, READ_SHARE

    simulation = bf.standard_simulation(seed=2, n_throws=4, noise=0.0, second_user=False, drop_frames=0.0, drop_joints=0.0)
    frames = _kinect_frames(simulation)
    path = _write_kinect(tmp_path / "session.txt", frames, np.arange(len(frames)))
    told = []
    dataset, _ = import_recordings(path, "kinect-text", progress=lambda *said: told.append(said))
    assert len(dataset) == 4
    assert {where for where, _, _ in told} == {str(path)}
    labelled = READ_SHARE + CUT_SHARE
    assert [(stage, pytest.approx(share)) for _, stage, share in told] == [
        ("reading", 0.0), ("cutting throws", READ_SHARE),
        *[(f"labelling throw {n} of 4", labelled + (1 - labelled) * (n - 1) / 4) for n in range(1, 5)],
        ("done", 1.0),
    ]


def test_an_arm_never_tracked_is_left_out_with_a_warning_and_no_arm_at_all_names_the_file(tmp_path):
    # an MSR or Kinect file writes nan for a joint it did not track; the right (throwing) arm never
    # was: the import went on with no word of which file stopped it ("joint 'line 2' has 0 samples")
    simulation = bf.standard_simulation(seed=2, n_throws=2, noise=0.0, second_user=False, drop_frames=0.0, drop_joints=0.0)
    frames = _kinect_frames(simulation)
    frames[:, 5:8] += np.array([[0.0, -0.3, 0.0], [0.0, -0.55, 0.0], [0.0, -0.6, 0.0]])  # the left arm hangs down
    frames[:, 8:12] = np.nan
    path = _write_kinect(tmp_path / "untracked.txt", frames, np.arange(len(frames)))
    dataset, report = import_recordings([path], "kinect-text")
    assert report.files[0].arm == "left" and len(dataset) == 0
    assert f"{path}: user 1, right arm left out: the right shoulder (joint 9) was never tracked (0 samples)" \
        in report.warnings
    frames[:, 4:8] = np.nan
    _write_kinect(path, frames, np.arange(len(frames)))
    with pytest.raises(InputError, match=re.escape(
            f"{path}: user 1, right arm: the right shoulder (joint 9) was never tracked (0 samples) and no other arm "
            "was: no arm to cut throws from; leave the file out")):
        import_recordings([path], "kinect-text")
    with pytest.raises(InputError, match=re.escape(f"{path}: user 1, left arm: the left shoulder (joint 5) was never "
                                                   "tracked (0 samples): no arm to cut throws from")):
        import_recordings([path], "kinect-text", arm="left")


def test_kinect_text_with_a_wrong_number_of_columns_names_the_file_and_line(tmp_path):
    path = tmp_path / "short.txt"
    path.write_text("0 " + " ".join(["0.5"] * 60) + "\n1 " + " ".join(["0.5"] * 57) + "\n")
    with pytest.raises(InputError, match=r"short.txt, line 2: 58 columns, expected 61 \(frame number then 20 joints"):
        read_kinect_text(path)


def test_kinect_text_with_a_tracking_state_per_joint_or_a_header_says_what_to_drop(tmp_path):
    # both were "cannot tell the format; give --format", and with --format kinect-text "81 columns,
    # expected 61" or "non-numeric value", with no word of what the file held
    frames = np.tile(np.linspace(0.1, 2.5, 60).reshape(20, 3), (4, 1, 1))
    with_state = tmp_path / "state.txt"
    with_state.write_text("".join(" ".join([str(n), *(f"{v:.4f} {v:.4f} {v:.4f} 2" for v in frame[:, 0])]) + "\n"
                                  for n, frame in enumerate(frames)))
    with pytest.raises(InputError) as error:
        import_recordings([with_state])
    assert str(error.value) == (f"{with_state}: cannot tell the format: its rows hold 81 numbers, a frame number and 20 "
                                "joints x 4 values (x y z and a tracking state, as some Kinect SDK v1 exporters write "
                                "them): drop each joint's 4th value (rlff reads x y z), and it reads as Kinect text")
    with pytest.raises(InputError, match=r"state.txt, line 1: 81 columns, expected 61 \(frame number then 20 joints x "
                                         r"\(x y z\)\); 81 are a frame number .*: drop each joint's 4th value"):
        read_kinect_text(with_state)
    header = tmp_path / "header.txt"
    names = ["frame", *(f"j{j}_{axis}" for j in range(20) for axis in "xyz")]
    header.write_text(" ".join(names) + "\n" + "".join(" ".join([str(n), *(f"{v:.4f}" for v in frame.ravel())]) + "\n"
                                                       for n, frame in enumerate(frames)))
    with pytest.raises(InputError, match=r"header.txt: cannot tell the format: its first line is a header \('frame j0_x "
                                         r".*'\) above rows of 61 numbers, Kinect SDK v1 text \(a frame number, 20 "
                                         r"joints x \(x y z\)\): drop the header line$"):
        import_recordings([header])
    with pytest.raises(InputError, match=r"header.txt, line 1: a header line \('frame j0_x .*'\), where rlff reads "
                                         r"numbers only \(frame number then 20 joints x \(x y z\)\): drop the line$"):
        read_kinect_text(header)


def test_kinect_v2_text_is_said_to_be_one_with_the_way_to_import_it(tmp_path):
    # "76 columns, expected 61 (frame number then 20 joints x (x y z))" named no Kinect v2, nor
    # what would import the file
    frames = np.tile(np.linspace(0.1, 2.5, 75).reshape(25, 3), (4, 1, 1))
    path = tmp_path / "kinect_v2.txt"
    path.write_text("".join(" ".join([str(n), *(f"{v:.5f}" for v in frame.ravel())]) + "\n"
                            for n, frame in enumerate(frames)))
    route = ("which rlff does not read (its Kinect text is Kinect SDK v1's, 20 joints): write the arm's joints as a "
             "CSV with a header row naming them (Kinect v2's joints 8-11, from 0, are the right shoulder, elbow, wrist "
             "and hand, 4-7 the left's) and import that with --format csv --columns ... --up y (docs/capture.md, "
             "\"A CSV of joint positions\")")
    with pytest.raises(InputError) as error:
        read_kinect_text(path)
    assert str(error.value) == (f"{path}, line 1: 76 columns, expected 61 (frame number then 20 joints x (x y z)); 76 "
                                "look like Kinect v2 joint text (a frame number and 25 joints x (x y z)), " + route)
    with pytest.raises(InputError) as error:
        import_recordings([path])
    assert str(error.value) == (f"{path}: cannot tell the format: its rows hold 76 numbers, a frame number and 25 "
                                "joints x (x y z): it looks like Kinect v2 joint text, " + route)
    path.write_text("".join(" ".join([str(n), *(f"{v:.5f} {v:.5f} {v:.5f} 2" for v in frame[:, 0])]) + "\n"
                            for n, frame in enumerate(frames)))
    with pytest.raises(InputError, match=r"line 1: 101 columns, expected 61 .*; 101 look like Kinect v2 joint text "
                                         r"\(a frame number and 25 joints x 4 values \(x y z and a tracking state\)\)"):
        read_kinect_text(path)


def test_a_file_read_as_a_format_it_is_not_names_the_one_it_looks_like(tmp_path):
    simulation = bf.standard_simulation(seed=2, n_throws=1, noise=0.0, second_user=False, drop_frames=0.0, drop_joints=0.0)
    path = _write_kinect(tmp_path / "kinect.txt", _kinect_frames(simulation), np.arange(len(simulation.frame_times)))
    for wrong, said in (("msr", "line 1: 61 columns, expected 4"), ("thesis", ""), ("csv", "--columns")):
        with pytest.raises(InputError, match=re.escape("(read as --format " + wrong + "; it looks like kinect-text: "
                                                       "give --format kinect-text, or leave --format out)")) as e:
            import_recordings([path], wrong)
        assert said in str(e.value)
    assert len(import_recordings([path])[0]) == 1  # as it is, with the format guessed


def test_msr_text_with_a_missing_joint_line_says_so(tmp_path):
    path = tmp_path / "a06_s01_e01_skeleton3D.txt"
    path.write_text("0.1 0.2 2.5 1\n" * 39)
    with pytest.raises(InputError, match=r"a06_s01_e01_skeleton3D.txt: 39 joint lines, not a multiple of 20.*missing 1 joints"):
        read_msr_text(path)
    path.write_text("0.1 0.2 2.5\n" * 20)
    with pytest.raises(InputError, match=r"line 1: 3 columns, expected 4 \(x y z confidence\)"):
        read_msr_text(path)


def test_csv_with_a_column_map_and_missing_columns(tmp_path):
    simulation = bf.standard_simulation(seed=4, n_throws=1, noise=0.0)
    shoulder, elbow, hand = simulation.arm_positions(simulation.angle(simulation.frame_times))
    import pandas as pd

    frame = pd.DataFrame({"stamp": simulation.frame_times})
    for name, values in (("ShoulderRight", shoulder), ("ElbowRight", elbow), ("HandRight", hand)):
        for axis, column in zip("xyz", values.T, strict=True):
            frame[f"{name}.{axis.upper()}"] = column
    path = tmp_path / "joints.csv"
    frame.to_csv(path, index=False)
    mapping = {"time": "stamp"}
    for ours, theirs in (("shoulder", "ShoulderRight"), ("elbow", "ElbowRight"), ("hand", "HandRight")):
        mapping.update({f"right_{ours}_{axis}": f"{theirs}.{axis.upper()}" for axis in "xyz"})
    recording = read_joint_csv(path, mapping)
    motion = align_arm(recording.arms[0])
    np.testing.assert_allclose(motion.angle, simulation.angle(motion.time), atol=1e-9)
    with pytest.raises(InputError) as error:
        read_joint_csv(path, {"time": "stamp"})
    assert "right_shoulder_x" in str(error.value) and "ElbowRight.X" in str(error.value)


def _simulated_csv(path: Path, time_scale: float = 1.0) -> Path:
    """The right arm of a simulated throw as a joint CSV, its time multiplied by ``time_scale``."""
    import pandas as pd

    simulation = bf.standard_simulation(seed=4, n_throws=1, noise=0.0)
    points = simulation.arm_positions(simulation.angle(simulation.frame_times))
    frame = pd.DataFrame({"time": simulation.frame_times * time_scale})
    for joint, values in zip(("shoulder", "elbow", "hand"), points, strict=True):
        for axis, column in zip("xyz", values.T, strict=True):
            frame[f"right_{joint}_{axis}"] = column
    frame.to_csv(path, index=False)
    return path


def test_a_csv_with_spaces_after_its_commas_reads_as_without(tmp_path):
    path = _simulated_csv(tmp_path / "plain.csv")
    plain = read_joint_csv(path)
    spaced_path = tmp_path / "spaced.csv"
    spaced_path.write_text(path.read_text().replace(",", ", "))  # "time, right_shoulder_x, ..."
    spaced = read_joint_csv(spaced_path)
    np.testing.assert_array_equal(spaced.arms[0].elbow.position, plain.arms[0].elbow.position)
    np.testing.assert_array_equal(spaced.arms[0].elbow.time, plain.arms[0].elbow.time)


@pytest.mark.parametrize(("scale", "unit"), [(1e3, "milliseconds"), (1e6, "microseconds"), (1e9, "nanoseconds")])
def test_a_time_column_in_another_unit_is_named(tmp_path, scale, unit):
    path = _simulated_csv(tmp_path / "joints.csv", time_scale=scale)
    with pytest.raises(InputError, match=rf"the time column 'time' steps by .* outside 1-1000 Hz; rlff reads seconds: "
                                         rf"it looks like {unit} \(divide the column by {scale:,.0f}\)$"):
        read_joint_csv(path)
    read_joint_csv(_simulated_csv(tmp_path / "seconds.csv"))  # the same in seconds is read


def test_a_time_column_that_counts_frames_is_named(tmp_path):
    path = _simulated_csv(tmp_path / "frames.csv", time_scale=30.0)  # 0, 1, 2, ... at 30 Hz
    with pytest.raises(InputError, match=r"the time column 'time' steps by 1 per frame in whole numbers: a frame "
                                         r"number\? rlff reads seconds"):
        read_joint_csv(path)


def test_blank_cells_are_a_joint_not_tracked_there_and_a_blank_arm_is_left_out(tmp_path):
    import pandas as pd

    path = _simulated_csv(tmp_path / "clean.csv")
    frame = pd.read_csv(path)
    frame.loc[[3, 4, 40], ["right_hand_x", "right_hand_y", "right_hand_z"]] = np.nan  # written as blanks
    for axis in "xyz":  # a left arm the tracker hardly saw
        frame[f"left_shoulder_{axis}"], frame[f"left_elbow_{axis}"], frame[f"left_hand_{axis}"] = 0.1, 0.2, 0.3
    frame.loc[5:, [c for c in frame.columns if c.startswith("left_")]] = np.nan
    blank = tmp_path / "blank.csv"
    frame.to_csv(blank, index=False)
    recording = read_joint_csv(blank)
    (arm,) = recording.arms
    assert arm.side == "right" and len(arm.hand) == len(frame) - 3 and len(arm.elbow) == len(frame)
    assert any(w.endswith("blank.csv: the left arm is blank or nan in 96% of the rows: left out") for w in recording.warnings)
    assert any("3 frames with a nan or blank value in a joint rlff reads" in note for note in recording.notes)
    dataset, _ = import_recordings([blank])
    clean, _ = import_recordings([path])
    assert len(dataset) == len(clean) == 1


def test_a_joint_at_exactly_the_sensors_origin_is_a_joint_not_tracked_there(tmp_path):
    # OpenPose-style "not detected": a joint written as (0, 0, 0) in one frame was read as a real
    # position: the hand and wrist at the origin during a rest passed for a frozen tracker, and the
    # elbow at the origin mid-extension made a throw peak far above its speed
    import thinned as th

    frames, time, movements = th.session(7, rate=15.0)
    clean = th.write_joint_csv(tmp_path / "clean.csv", frames, time)
    throws = [movement for movement in movements if movement.is_throw]
    zeroed = frames.copy()
    rest = int(round((throws[0].start - 0.5) * 15))
    zeroed[rest:rest + 4, [10, 11]] = 0.0  # the right wrist and hand, 4 frames at rest
    zeroed[int(np.argmin(np.abs(time - throws[1].peak_time))), 9] = 0.0  # the right elbow at the peak
    zero = th.write_joint_csv(tmp_path / "zero.csv", zeroed, time)
    reference, _ = import_recordings([clean], up="y")
    dataset, report = import_recordings([zero], up="y")
    assert [t.meta["start_time"] for t in dataset] == pytest.approx([t.meta["start_time"] for t in reference], abs=0.07)
    assert all(t["velocity"].max() < 1.05 * r["velocity"].max() for t, r in zip(dataset, reference, strict=True))
    assert not any("frozen" in note for note in report.notes)
    (note,) = [note for note in report.notes if "(0, 0, 0)" in note]
    assert note.startswith(f"zero.csv: 5 frames with a joint at exactly (0, 0, 0), the sensor's origin (how trackers such "
                           f"as OpenPose write a joint they did not detect; the first at t={time[rest]:.2f} s): taken as "
                           "not tracked there, left out of that joint's track")
    hand = read_joint_csv(zero, up="y").arm("1", "right").hand
    assert len(hand) == len(time) - 4 and not np.any(np.all(hand.position == 0.0, axis=1))


@pytest.mark.parametrize("form", ["kinect-text", "msr", "csv"])
def test_a_coordinate_far_beyond_what_a_camera_sees_is_a_joint_not_tracked_there(tmp_path, form):
    # a text elbow at 1e30 m was read as a position (any finite coordinate passed) where a bag's
    # transform beyond 100 m is a joint not tracked there: now the text readers take it so too
    import pandas as pd

    simulation = bf.standard_simulation(seed=2, n_throws=2, noise=0.0, second_user=False, drop_frames=0.0, drop_joints=0.0)
    frames = _kinect_frames(simulation)
    numbers = np.arange(len(frames))

    def write(name: str, frames: np.ndarray) -> Path:
        if form == "kinect-text":
            return _write_kinect(tmp_path / f"{name}.txt", frames, numbers)
        if form == "msr":  # Kinect joints to MSR lines: right arm 8-11 to 1, 8, 10, 12; torso 2, 0 to 2, 6
            msr = np.tile(frames[:, 2:3], (1, 20, 1))
            msr[:, [1, 8, 10, 12, 0, 7, 9, 11, 2, 6]] = frames[:, [8, 9, 10, 11, 4, 5, 6, 7, 2, 0]]
            lines = [f"{x:.6f} {y:.6f} {z:.6f} 1" for x, y, z in msr.reshape(-1, 3)]
            path = tmp_path / f"{name}.txt"
            path.write_text("\n".join(lines) + "\n")
            return path
        table = pd.DataFrame({"time": numbers / 30.0})
        for joint, index in zip(("shoulder", "elbow", "wrist", "hand"), (8, 9, 10, 11), strict=True):
            for axis, column in zip("xyz", frames[:, index].T, strict=True):
                table[f"right_{joint}_{axis}"] = column
        table.to_csv(tmp_path / f"{name}.csv", index=False)
        return tmp_path / f"{name}.csv"

    rate = 30.0 if form != "csv" else None
    reference, reference_report = import_recordings([write("own", frames)], form, rate_hz=rate, up="y")
    far = frames.copy()
    far[10:13, 9] = [1e30, 0.0, 0.0]  # the right elbow, 3 frames at rest
    path = write("far", far)
    reader = {"kinect-text": read_kinect_text, "msr": read_msr_text}.get(form)
    recording = reader(path, rate) if reader else read_joint_csv(path, up="y")
    elbow = recording.arm("1", "right").elbow
    assert len(elbow) == len(frames) - 3 and np.abs(elbow.position).max() < 10.0
    assert f"{path.name}: 3 frames with a joint's coordinate beyond 100 m, farther than a depth camera sees (the first " \
           "at t=0.33 s): taken as not tracked there, left out of that joint's track" in recording.notes
    dataset, report = import_recordings([path], form, rate_hz=rate, up="y")
    assert len(dataset) == len(reference) == (1 if form == "msr" else 2)  # an MSR file holds one throw
    assert [t.peak_velocity for t in report.files[0].throws] == pytest.approx(
        [t.peak_velocity for t in reference_report.files[0].throws])


def test_a_frozen_tracker_mid_throw_is_dropped_and_bridged_and_a_still_arm_is_not(tmp_path):
    import pandas as pd

    path = _simulated_csv(tmp_path / "clean.csv")
    clean = read_joint_csv(path)
    assert not any("frozen" in note for note in clean.notes)  # the noise-free rests are not frozen frames
    frame = pd.read_csv(path)
    hand = frame[["right_hand_x", "right_hand_y", "right_hand_z"]].to_numpy()
    fastest = int(np.argmax(np.linalg.norm(np.diff(hand, axis=0), axis=1)))
    joints = [c for c in frame.columns if c != "time"]
    frame.loc[fastest + 1:fastest + 5, joints] = frame.loc[fastest, joints].to_numpy()  # held for 5 frames
    frozen_path = tmp_path / "frozen.csv"
    frame.to_csv(frozen_path, index=False)
    frozen = read_joint_csv(frozen_path)
    (note,) = [note for note in frozen.notes if "frozen" in note]
    assert note.startswith("frozen.csv: 5 frames where a joint repeats its value of the frame before exactly")
    kept = frozen.arms[0].hand.time  # the hand moved; the shoulder and elbow of this arm stand still
    assert len(kept) == len(clean.arms[0].hand.time) - 5 and len(frozen.arms[0].elbow) == len(clean.arms[0].elbow)
    assert not np.isin(frame["time"].to_numpy()[fastest + 1:fastest + 6], kept).any()
    # the hand's speed across the held frames was never measured: the import says so
    dataset, report = import_recordings([frozen_path])
    assert any("its extension has a 0.20 s gap in the hand's samples" in w and "not measured" in w
               for w in report.warnings), report.warnings
    assert "low" in {t.meta["peak_confidence"] for t in dataset}  # the throw's peak is marked as bridged
    clean_dataset, clean_report = import_recordings([path])
    assert not any("gap in the" in w for w in clean_report.warnings)
    assert {t.meta["peak_confidence"] for t in clean_dataset} == {"high"}


def test_a_stream_that_gives_each_skeleton_twice_reads_as_the_skeletons_at_their_own_rate(tmp_path):
    # a 30 Hz output of a 15 Hz skeleton: the repeats were left out in motion only, the usual
    # spacing (and the velocity fit's window) came from the 30 Hz stamps, and the peaks came out
    # up to 23 % lower than those of the same skeletons at 15 Hz
    import thinned as th

    frames, time, _ = th.session(7, rate=15.0)
    frames[:12] = frames[0]  # a still that repeats at 15 Hz too (the first skeleton held): kept at 15 Hz
    own = th.write_joint_csv(tmp_path / "own.csv", frames, time)
    doubled = th.write_joint_csv(tmp_path / "doubled.csv", np.repeat(frames, 2, axis=0), np.arange(2 * len(time)) / 30.0)
    reference, _ = import_recordings([own], up="y")
    dataset, report = import_recordings([doubled], up="y")
    assert len(dataset) == len(reference) == 5
    for trajectory, expected in zip(dataset, reference, strict=True):
        np.testing.assert_allclose(trajectory["velocity"], expected["velocity"], atol=1e-9)
    (note,) = [note for note in report.notes if "every joint" in note]
    assert note == (f"doubled.csv: {len(time)} of {2 * len(time)} frames repeat the frame before in every joint, in "
                    "motion too: the tracker gives each skeleton 2 times (30 Hz of 15 Hz skeletons); the repeats left "
                    "out, the skeletons read at their own rate")
    assert not any("frozen" in note for note in report.notes)
    # the samples are the skeletons' own, the held one included
    np.testing.assert_array_equal(read_joint_csv(doubled, up="y").arms[0].elbow.time,
                                  read_joint_csv(own, up="y").arms[0].elbow.time)
    # a noise-free recording whose rests repeat, with a tracker that froze once mid-throw, is no such stream
    import pandas as pd

    still = pd.read_csv(_simulated_csv(tmp_path / "still.csv"))
    joints = [c for c in still.columns if c != "time"]
    fastest = int(np.argmax(np.abs(np.diff(still["right_hand_x"].to_numpy()))))
    still.loc[fastest + 1:fastest + 2, joints] = still.loc[fastest, joints].to_numpy()
    still.to_csv(tmp_path / "still.csv", index=False)
    notes = read_joint_csv(tmp_path / "still.csv").notes
    assert not any("every joint" in note for note in notes) and any("frozen" in note for note in notes)


@pytest.mark.parametrize("lost", [3, 5])
def test_frames_lost_mid_throw_leave_a_velocity_that_bridges_the_angle(tmp_path, lost):
    # every joint lost for a few frames at the fastest extension (tracking dropped, not frozen):
    # the velocity written must carry the angle across the gap, not the slow hold on either side
    import pandas as pd

    path = _simulated_csv(tmp_path / "clean.csv")
    frame = pd.read_csv(path)
    hand = frame[["right_hand_x", "right_hand_y", "right_hand_z"]].to_numpy()
    fastest = int(np.argmax(np.linalg.norm(np.diff(hand, axis=0), axis=1)))
    dropped_path = tmp_path / "dropped.csv"
    frame.drop(index=range(fastest - lost // 2, fastest - lost // 2 + lost)).to_csv(dropped_path, index=False)
    clean, _ = import_recordings([path])
    dropped, report = import_recordings([dropped_path])
    (throw,), (reference,) = dropped.trajectories, clean.trajectories
    time, angle, velocity = throw.data["time"], throw.data["angle"], throw.data["velocity"]
    assert abs(np.trapezoid(velocity, time) - (angle[-1] - angle[0])) < 0.1
    assert 0.8 < velocity.max() / reference.data["velocity"].max() < 1.25
    (warning,) = [w for w in report.warnings if "gap in" in w]
    assert "gap in every joint's samples" in warning and f"(peak {velocity.max():.3g} rad/s)" in warning


def test_a_throw_that_begins_where_tracking_resumed_is_warned_of(tmp_path):
    import pandas as pd

    path = _simulated_csv(tmp_path / "clean.csv")
    frame = pd.read_csv(path)
    hand = frame[["right_hand_x", "right_hand_y", "right_hand_z"]].to_numpy()
    fastest = int(np.argmax(np.linalg.norm(np.diff(hand, axis=0), axis=1)))
    frame.loc[fastest - 3:, "time"] += 5.0  # the clock jumps (or tracking is lost) just before the release
    jumped = tmp_path / "jumped.csv"
    frame.to_csv(jumped, index=False)
    _, report = import_recordings([jumped])
    assert any("begins at t=" in w and "where tracking resumed after a 5.03 s gap, with the elbow already moving" in w
               and "check the throw before fitting on it" in w for w in report.warnings), report.warnings
    _, clean = import_recordings([path])
    assert not any("tracking resumed" in w for w in clean.warnings)


def test_bad_cells_of_the_csv_readers_are_shown_as_the_file_has_them(tmp_path):
    # numpy's repr leaked into the messages: "np.float64(nan)"
    from rlff.trajectory.path_csv import read_generated_path

    joints = tmp_path / "joints.csv"
    points = [f"right_{joint}_{axis}" for joint in ("shoulder", "elbow", "hand") for axis in "xyz"]
    joints.write_text(",".join(["time", *points]) + "\n0" + ",0.1" * 9 + "\n0.1,inf" + ",0.2" * 8 + "\n")
    with pytest.raises(InputError, match=r"line 3: column 'right_shoulder_x' has a non-finite value inf$"):
        read_joint_csv(joints, {})
    joints.write_text(",".join(["time", *points]) + "\n0" + ",0.1" * 9 + "\n" + ",0.2" * 9 + "\n")
    with pytest.raises(InputError, match=r"line 3: column 'time' has an empty or nan value$"):
        read_joint_csv(joints, {})  # a blank joint is a joint not tracked; a blank time is no time
    path = tmp_path / "cells.csv"
    path.write_text("time,angle,velocity\n0,0.1,0.2\n0.1,,0.3\n0.2,0.3,inf\n")
    with pytest.raises(InputError, match=r"column 'angle' row 2 has an empty or nan value$"):
        read_generated_path(path)
    path.write_text("time,angle,velocity\n0,0.1,0.2\n0.1,0.2,0.3\n0.2,0.3,inf\n")
    with pytest.raises(InputError, match=r"column 'velocity' row 3 has a non-finite value inf$"):
        read_generated_path(path)


def test_unknown_format_and_arm_are_input_errors(tmp_path):
    path = tmp_path / "x.txt"
    path.write_text("1 2\n")
    with pytest.raises(InputError, match="unknown format 'avi'"):
        import_recordings([path], "avi")
    with pytest.raises(InputError, match=r"x.txt: cannot tell the format"):
        import_recordings([path])
    with pytest.raises(InputError, match="unknown arm 'both'"):
        import_recordings([path], "msr", arm="both")


def test_a_missing_recording_is_named_missing_whatever_the_format(tmp_path):
    # with the format guessed it was "cannot tell the format; give --format"
    for format in ("auto", "msr"):
        with pytest.raises(InputError, match=r"nonexist.txt: no such file"):
            import_recordings([tmp_path / "nonexist.txt"], format)


@pytest.mark.parametrize("rate", [1e300, 1e-300, 0.5, 0.0, -1.0, float("nan")])
def test_a_frame_rate_outside_1_to_1000_hz_is_refused_before_any_file_is_read(tmp_path, rate):
    # 1e300 Hz made every time step 0 (a singular matrix), 1e-300 Hz times of 300 digits
    path = tmp_path / "x.txt"
    path.write_text("1 2\n")
    for read in (lambda: import_recordings([path], "msr", rate_hz=rate), lambda: read_msr_text(path, rate)):
        expected = r"frame rate: nan is not a number" if rate != rate else r"frame rate: .* Hz is outside the range 1 to 1000 Hz"
        with pytest.raises(InputError, match=expected):
            read()


def test_glitches_do_not_make_throws():
    """Single-frame spikes of the hand (a reflection mixed in) neither add nor remove throws."""
    simulation = bf.standard_simulation(seed=8, n_throws=4, second_user=False, glitches=12)
    angle = simulation.angle(simulation.frame_times)
    shoulder, elbow, hand = simulation.arm_positions(angle)
    rng = np.random.default_rng(1)
    spikes = rng.choice(len(hand), 12, replace=False)
    hand[spikes] += rng.normal(0, 0.25, (12, 3))
    from rlff.capture.skeleton import ArmTrack, JointTrack

    t = simulation.frame_times
    arm = ArmTrack("1", "right", JointTrack("s", t, shoulder), JointTrack("e", t, elbow), JointTrack("h", t, hand))
    motion = align_arm(arm)
    # every spike is removed as a glitch, in the rest and in the middle of an extension alike
    assert 8 <= motion.glitches.size <= 12 and set(np.round(motion.glitches, 6)) <= set(np.round(t[spikes], 6))
    cuts, _ = find_throws(motion)
    assert len(cuts) == 4
    for cut, (start, end) in zip(cuts, simulation.moving_spans(), strict=True):
        assert motion.time[cut.start] == pytest.approx(start, abs=0.1) and motion.time[cut.stop - 1] == pytest.approx(end, abs=0.1)


# derandomized in CI, as the fuzz tests: about 1 case in 5,000 has a boundary beyond 0.12 s (the
# known fault below), and a random draw of 15 would fail about one CI run in 300
@settings(max_examples=15, deadline=None, derandomize=os.environ.get("CI", "").lower() == "true")
@given(seed=st.integers(0, 10_000), n_throws=st.integers(1, 5))
def test_the_number_of_throws_is_recovered(seed, n_throws):
    _check_recovered(seed, n_throws)


@pytest.mark.parametrize(("seed", "n_throws", "rate_hz"), [
    (3782, 5, 30.0), (8680, 2, 30.0), (1425, 4, 30.0), (2, 3, 15.0), (7, 3, 15.0), (10, 3, 60.0), (32, 2, 60.0),
])
def test_jitter_in_the_hold_or_the_rest_does_not_move_the_start(seed, n_throws, rate_hz):
    """Found by random draws of the test above: a one-sample blip faster than 0.5 rad/s in the
    hold at the bottom of the wind-up ended the backward walk (3782 and 8680: the start 0.5 s
    late), and a blip that was not taken restarted the hold's clock, so three samples of rest
    jitter further back passed for wind-up (1425: 0.6 s early). At 15 and 60 Hz the first was
    common: one start in 20 (15 Hz) and one in 80 (60 Hz) came 0.6 s late."""
    _check_recovered(seed, n_throws, rate_hz)


@pytest.mark.xfail(strict=True, reason="known: a slow follow-through whose speed, fitted over "
                                       "settle_window, dips below 0.5 rad/s for one sample ends "
                                       "there, 0.13-0.15 s early (docs/capture.md)")
@pytest.mark.parametrize(("seed", "n_throws"), [(72, 4), (1455, 5)])
def test_a_dip_in_a_slow_follow_through_does_not_end_it(seed, n_throws):
    _check_recovered(seed, n_throws)


def _check_recovered(seed: int, n_throws: int, rate_hz: float = 30.0) -> None:
    """Every throw of a simulated session found, each boundary within 0.12 s of where the true
    elbow speed crosses 0.5 rad/s."""
    simulation = bf.standard_simulation(seed=seed, n_throws=n_throws, second_user=False, rate_hz=rate_hz)
    t = simulation.frame_times
    shoulder, elbow, hand = simulation.arm_positions(simulation.angle(t))
    noise = np.random.default_rng(seed).normal(0, 0.002, (3, *hand.shape))
    from rlff.capture.skeleton import ArmTrack, JointTrack

    arm = ArmTrack("1", "right", JointTrack("s", t, shoulder + noise[0]), JointTrack("e", t, elbow + noise[1]), JointTrack("h", t, hand + noise[2]))
    motion = align_arm(arm)
    cuts, _ = find_throws(motion)
    assert len(cuts) == n_throws
    assert all(a.stop <= b.start for a, b in zip(cuts, cuts[1:], strict=False))
    for cut, (start, end) in zip(cuts, simulation.moving_spans(), strict=True):
        assert abs(motion.time[cut.start] - start) <= 0.12 and abs(motion.time[cut.stop - 1] - end) <= 0.12


def test_release_and_landing_match_the_ballistics_of_the_true_hand_velocity():
    """The release velocity is the true hand's mean velocity over the 0.28 s of fastest extension."""
    simulation = bf.standard_simulation(seed=6, n_throws=1, noise=0.0, second_user=False)
    t = simulation.frame_times
    shoulder, elbow, hand = simulation.arm_positions(simulation.angle(t))
    from rlff.capture.label import estimate_release, landing_distance
    from rlff.capture.skeleton import ArmTrack, JointTrack

    arm = ArmTrack("1", "right", JointTrack("s", t, shoulder), JointTrack("e", t, elbow), JointTrack("h", t, hand))
    motion = align_arm(arm)
    (cut,), _ = find_throws(motion)
    settings_ = LandingSettings(shoulder_height=1.5, target_height=0.3)
    release = estimate_release(motion, cut, bf.UP, settings_)
    # a minimum-jerk extension is fastest in its middle, and symmetric about it
    spec, start = simulation.throws[0], simulation.starts[0]
    peak_time = start + spec.wind_up + spec.hold + spec.extension / 2
    assert release.time == pytest.approx(peak_time, abs=1 / 30 + 1e-9)
    width = SegmentSettings().steepest_window
    fine = np.array([release.time - width / 2, release.time + width / 2])
    _, _, ends = simulation.arm_positions(simulation.angle(fine))
    velocity = (ends[1] - ends[0]) / width
    vertical = velocity @ bf.UP
    horizontal = np.linalg.norm(velocity - vertical * bf.UP)
    # positions are linear between the 30 Hz samples: the chord differs from the truth by a few per cent
    assert release.speed_vertical == pytest.approx(vertical, rel=0.05, abs=0.05)
    assert release.speed_horizontal == pytest.approx(horizontal, rel=0.05, abs=0.05)
    assert release.confidence == "high"
    middle = simulation.arm_positions(simulation.angle(np.array([release.time])))[2][0]
    offset = middle - shoulder[0]
    assert release.height == pytest.approx(1.5 + offset @ bf.UP, abs=0.01)
    direction = (velocity - vertical * bf.UP) / horizontal
    expected = crossing_distance(offset @ direction, 1.5 + offset @ bf.UP, horizontal, vertical, 0.3)
    assert landing_distance(release, settings_) == pytest.approx(float(expected), rel=0.05)


def _true_and_estimated_landing(seed: int, rate_hz: float, noise: float, window: float | None) -> tuple[float, float, float]:
    """One simulated throw: the landing of a ball released at the extension's peak (the truth),
    the estimate from its sampled, noisy hand, and the angle (deg) between their release velocities."""
    from rlff.capture.label import estimate_release, landing_distance
    from rlff.capture.skeleton import ArmTrack, JointTrack

    simulation = bf.standard_simulation(seed=seed, n_throws=1, noise=0.0, second_user=False, rate_hz=rate_hz)
    t = simulation.frame_times
    shoulder, elbow, hand = simulation.arm_positions(simulation.angle(t))
    hand = hand + np.random.default_rng(seed).normal(0.0, noise, hand.shape)
    arm = ArmTrack("1", "right", JointTrack("s", t, shoulder), JointTrack("e", t, elbow), JointTrack("h", t, hand))
    motion = align_arm(arm)
    (cut,), _ = find_throws(motion)
    settings_ = LandingSettings(shoulder_height=1.5, target_height=0.3, release_window=window)
    release = estimate_release(motion, cut, bf.UP, settings_)
    spec, start = simulation.throws[0], simulation.starts[0]
    peak_time = start + spec.wind_up + spec.hold + spec.extension / 2
    assert release.time == pytest.approx(peak_time, abs=0.05)  # the steepest stretch, found on noisy angles
    velocity = simulation.hand_velocity(peak_time)
    vertical = velocity @ bf.UP
    horizontal = np.linalg.norm(velocity - vertical * bf.UP)
    offset = simulation.arm_positions(simulation.angle(np.array([peak_time])))[2][0] - shoulder[0]
    direction = (velocity - vertical * bf.UP) / horizontal
    truth = crossing_distance(offset @ direction, 1.5 + offset @ bf.UP, horizontal, vertical, 0.3)
    turn = np.degrees(abs(np.arctan2(release.speed_vertical, release.speed_horizontal) - np.arctan2(vertical, horizontal)))
    return float(truth), landing_distance(release, settings_), float(turn)


@pytest.mark.parametrize("rate_hz", [15.0, 30.0, 120.0])
def test_a_release_window_makes_the_landing_follow_the_ball_released_at_the_peak(rate_hz):
    """Over simulated throws of 0.25-0.4 s extensions with 5 mm of tracking noise, the hand's speed
    over 0.1 s about the release gives landings that follow where a ball let go at the extension's
    peak comes down, at every frame rate, and fall short of it by no more than that window's
    averaging explains. The default, the hand's mean over the whole 0.28 s stretch, comes out at a
    third of the truth and follows it loosely (docs/capture.md)."""
    windowed = np.array([_true_and_estimated_landing(seed, rate_hz, 0.005, 0.1) for seed in range(16)])
    default = np.array([_true_and_estimated_landing(seed, rate_hz, 0.005, None) for seed in range(16)])
    truth, estimate, turn = windowed.T
    assert np.corrcoef(truth, estimate)[0, 1] > 0.7
    assert np.corrcoef(truth, estimate)[0, 1] > np.corrcoef(truth, default[:, 1])[0, 1] + 0.2
    assert 0.55 < np.median(estimate / truth) < 1.0
    assert 0.25 < np.median(default[:, 1] / truth) < 0.4  # the default's price, as documented
    assert np.median(turn) < 5.0  # the long chord's direction is the path's at the peak


def test_a_release_window_must_be_a_time_within_a_second():
    for bad in (0.0, -0.1, 2.0, float("nan")):
        with pytest.raises(InputError, match="release window"):
            LandingSettings(release_window=bad)


@pytest.mark.parametrize(
    ("name", "distance"),
    [("user3_2.5m.bag", 2.5), ("throws-2_75m.bag", 2.75), ("x_250cm.txt", 2.5), ("4m.bag", 4.0), ("mm3.bag", None), ("s01_e01.txt", None),
     # passed over until 2026-12-07: labelled by the landing estimate, "no distance in the file name"
     ("u1_1900mm.txt", 1.9), ("x_2500MM.bag", 2.5)],
)
def test_distance_from_the_file_name(name, distance):
    assert distance_from_name(name) == distance


def test_manifest_by_throw_index_and_by_time(tmp_path):
    path = tmp_path / "manifest.csv"
    path.write_text("file,throw,start,end,distance,subject\nline1.bag,2,,,3.0,anna\nline1.bag,,10,20,2.0,\nother.bag,,,,1.5,bo\n")
    rows = read_manifest(path)
    assert manifest_entry(rows, "/data/line1.bag", 2, 5.0).distance == 3.0
    assert manifest_entry(rows, "/data/line1.bag", 1, 12.0).distance == 2.0
    assert manifest_entry(rows, "/data/line1.bag", 1, 25.0) is None
    assert manifest_entry(rows, "other.bag", 7, 0.0).subject == "bo"
    path.write_text("file,distance\nx.bag,far\n")
    with pytest.raises(InputError, match=r"manifest .*line 2: column 'distance' has a bad value 'far'"):
        read_manifest(path)
    # a blank line between two days' rows: the line as the file shows it
    path.write_text("file,distance\nx.bag,2\n\ny.bag,far\n")
    with pytest.raises(InputError, match=r"manifest .*line 4: column 'distance' has a bad value 'far'"):
        read_manifest(path)
    path.write_text("name,distance\nx.bag,2\n")
    with pytest.raises(InputError, match=r"no column 'file'"):
        read_manifest(path)


@pytest.mark.parametrize("text", ["file;throw;distance\nline1.bag;2;2,5\n\nline1.bag;1;1.75\n",
                                  "file\tthrow\tdistance\nline1.bag\t2\t2,5\n\nline1.bag\t1\t1.75\n",
                                  "file, throw, distance\nline1.bag, 2, 2.5\n\nline1.bag, 1, 1.75\n"])
def test_a_manifest_as_spreadsheets_write_it_reads_as_the_comma_one(tmp_path, text):
    path = tmp_path / "manifest.csv"
    path.write_text(text)
    rows = read_manifest(path)
    assert [(row.throw, row.distance) for row in rows] == [(2, 2.5), (1, 1.75)]
    path.write_text(text.replace("1.75", "far"))
    with pytest.raises(InputError, match=r"line 4: column 'distance' has a bad value 'far'"):
        read_manifest(path)


def test_thesis_matrix_files_pass_through(tmp_path):
    from rlff.dataset import Dataset, Trajectory
    from rlff.formats import write_thesis_matrix

    throws = Dataset(
        Trajectory(f"d{k}", {"angle": np.linspace(0.7, 3.0, 5), "distance": np.full(5, 2.0 + k), "velocity": np.arange(5.0)})
        for k in range(2)
    )
    first, second = tmp_path / "a.txt", tmp_path / "b.txt"
    write_thesis_matrix(throws, first)
    # other throws under the same ids (a copy of the first file would be refused as given twice)
    write_thesis_matrix(throws.replace(t.with_columns(velocity=t["velocity"] + 1.0) for t in throws), second)
    dataset, report = import_recordings([first, second], "thesis")
    assert len(dataset) == 4 and len({t.id for t in dataset}) == 4
    assert [f.format for f in report.files] == ["thesis", "thesis"]
    np.testing.assert_allclose(dataset[3]["distance"], 3.0)


def test_a_manifest_row_wider_than_its_header_is_named_not_shifted(tmp_path):
    path = tmp_path / "manifest.csv"
    path.write_text("file,distance\nsession.csv,1,5\n")  # a decimal comma in a comma file: three cells
    with pytest.raises(InputError, match=r"line 2: 3 cells, but the header names 2 columns; a decimal comma in a "
                                         r"comma-separated file\? write 1.5"):
        read_manifest(path)
    path.write_text("file;distance\nsession.csv;1.234,5\n")
    with pytest.raises(InputError, match=r"line 2: column 'distance' has a bad value '1.234,5'"):
        read_manifest(path)


def test_manifest_times_count_from_the_file_s_first_frame_when_its_first_frames_are_untracked(tmp_path):
    # the import's clock started at the first tracked sample: with 0.9 s of frames before it
    # dropped (every arm joint at zero), a manifest's start/end read off the video missed every
    # throw by 0.9 s and the throws took estimated baskets
    import thinned as th

    frames, time, _ = th.session(9)
    intact = th.write_kinect_text(tmp_path / "intact.txt", frames, np.arange(len(frames)))
    _, report = import_recordings([intact], "kinect-text")
    releases = [throw.release for throw in report.files[0].throws]  # from the file's first frame (frame 0)
    assert len(releases) >= 3
    frames[:27] = 0.0  # the tracker finds nobody in the first 0.9 s
    late = th.write_kinect_text(tmp_path / "late.txt", frames, np.arange(len(frames)))
    manifest = tmp_path / "baskets.csv"
    manifest.write_text("file,start,end,distance\n" + "".join(
        f"late.txt,{release - 0.2:.2f},{release + 0.2:.2f},{1.0 + 0.5 * number}\n"
        for number, release in enumerate(releases)))
    dataset, report = import_recordings([late], "kinect-text", manifest=manifest)
    file = report.files[0]
    assert file.clock_origin == 0.0  # frame 0's time: the file's first frame, tracked or not
    assert [throw.release for throw in file.throws] == pytest.approx(releases, abs=1e-9)
    assert [t.meta["distance_source"] for t in dataset] == ["manifest"] * len(releases)
    assert [float(t["distance"][0]) for t in dataset] == [1.0 + 0.5 * n for n in range(len(releases))]


def test_the_kinect_row_layouts_rlff_knows_are_named_in_one_place():
    # the reader's and the format guess's messages each kept their own map of these widths to words
    from rlff.capture.skeleton_text import KINECT_WIDTH, kinect_row_layout

    assert kinect_row_layout(81) == ("a frame number and 20 joints x 4 values (x y z and a tracking state, as some "
                                     "Kinect SDK v1 exporters write them)", "each joint's 4th value (rlff reads x y z)")
    assert kinect_row_layout(76) == ("a frame number and 25 joints x (x y z)", None)
    assert kinect_row_layout(101).drop is None and "25 joints x 4 values" in kinect_row_layout(101).holds
    assert kinect_row_layout(KINECT_WIDTH) is None and kinect_row_layout(58) is None
