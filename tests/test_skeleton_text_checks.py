"""What the text and CSV skeleton readers refuse or report: time that goes back (or jitters), a
time column under another name, column-map typos, where a non-finite value is, a BOM, ';' and tab
separators."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from rlff.capture import import_recordings
from rlff.capture.importer import READ_SHARE
from rlff.capture.skeleton_text import read_joint_csv, read_kinect_text, read_msr_text
from rlff.errors import InputError

_POINTS = [f"{side}_{joint}_{axis}" for side in ("right", "left") for joint in ("shoulder", "elbow", "hand") for axis in "xyz"]


def _positions(count: int) -> np.ndarray:
    """Positions of shape (count, 18) for ``_POINTS``: arms that move a little, never all at zero."""
    base = np.tile([0.0, 0.3, 2.6, 0.05, 0.1, 2.6, 0.02, -0.25, 2.6], 2) + np.repeat([0.0, 0.4], 9)
    return base + 0.01 * np.sin(np.arange(count))[:, None]


def _write_csv(path: Path, time: list[float] | None, sep: str = ",", decimal: str = ".", time_name: str = "time") -> Path:
    """A joint CSV: a header line, then one row per frame (line 2 is the first frame)."""
    values = _positions(len(time) if time is not None else 6)
    header = ([time_name] if time is not None else []) + _POINTS
    rows = [sep.join(header)]
    for index, row in enumerate(values):
        cells = ([f"{time[index]:g}"] if time is not None else []) + [f"{v:.6f}" for v in row]
        rows.append(sep.join(cell.replace(".", decimal) for cell in cells))
    path.write_text("\n".join(rows) + "\n")
    return path


def _kinect_lines(numbers: list[int]) -> list[str]:
    frames = np.tile(np.linspace(0.1, 2.5, 60), (len(numbers), 1)) + 0.01 * np.arange(len(numbers))[:, None]
    return [" ".join([str(n), *(f"{v:.6f}" for v in frame)]) for n, frame in zip(numbers, frames, strict=True)]


def _msr_lines(frames: int) -> list[str]:
    return [f"{0.1 + 0.01 * j:.6f} {0.2 + 0.001 * f:.6f} 2.5 1" for f in range(frames) for j in range(20)]


def test_csv_time_that_goes_back_names_the_line_and_what_to_do(tmp_path):
    # a clock reset (two recordings appended) was sorted into one, noting only the repeated stamps
    path = _write_csv(tmp_path / "reset.csv", [0.0, 0.1, 0.2, 0.0, 0.1, 0.2])
    with pytest.raises(InputError, match=r"reset.csv, line 5: time stamp 0 after 0.2 goes back.*split the file.*sort"):
        read_joint_csv(path)
    # stamps of two recordings interleaved
    path = _write_csv(tmp_path / "interleaved.csv", [0.0, 0.1, 0.2, 0.05, 0.15, 0.25])
    with pytest.raises(InputError, match=r"interleaved.csv, line 5: time stamp 0.05 after 0.2 goes back"):
        read_joint_csv(path)


def _edit_columns(path: Path, drop: tuple[str, ...] = (), rename: dict[str, str] | None = None,
                  add: tuple[str, ...] = ()) -> Path:
    """The CSV at ``path`` without the columns ``drop``, with ``rename``'s names, and with the
    columns ``add`` (0.5 on every row) after the others."""
    lines = [line.split(",") for line in path.read_text().splitlines()]
    keep = [index for index, name in enumerate(lines[0]) if name not in drop]
    header = [(rename or {}).get(lines[0][index], lines[0][index]) for index in keep] + list(add)
    rows = [[row[index] for index in keep] + ["0.5"] * len(add) for row in lines[1:]]
    path.write_text("\n".join(",".join(row) for row in [header, *rows]) + "\n")
    return path


def test_an_arm_wrist_or_torso_lacking_some_of_its_columns_is_named_with_them(tmp_path):
    # a CSV without right_elbow_z was read as the left arm's alone, with no word of the column:
    # "no throw found (user 1, left arm)", or the wrong arm's throws written
    time = [0.1 * index for index in range(6)]
    path = _edit_columns(_write_csv(tmp_path / "no_elbow_z.csv", time), drop=("right_elbow_z",))
    recording = read_joint_csv(path)
    assert [arm.side for arm in recording.arms] == ["left"]
    assert recording.warnings == [
        f"{path}: the right arm lacks right_elbow_z: left out, its throws not imported; add or rename the column, or "
        "map the file's with --columns (docs/capture.md, \"A CSV of joint positions\")"]
    # the arm asked for: "no right arm (arms there: left)"
    with pytest.raises(InputError, match=r"no_elbow_z.csv: the right arm lacks right_elbow_z; add or rename the "
                                         r"column, or map the file's with --columns"):
        read_joint_csv(path, arm="right")
    with pytest.raises(InputError, match=r"no_elbow_z.csv: the right arm lacks right_elbow_z; "):
        import_recordings([path], "csv", arm="right")
    assert len(read_joint_csv(path, arm="left").arms) == 1  # the other arm asked for: read, with the warning
    # a misspelt header: the nearest column rlff does not read
    path = _edit_columns(_write_csv(tmp_path / "misspelt.csv", time), rename={"right_elbow_x": "right_elbo_x"})
    assert any("the right arm lacks right_elbow_x (did you mean 'right_elbo_x'?): left out" in warning
               for warning in read_joint_csv(path).warnings)
    # a wrist with two of its axes, a torso without neck_z: both were left out without a word
    path = _edit_columns(_write_csv(tmp_path / "partial.csv", time),
                         add=("right_wrist_x", "right_wrist_y", "neck_x", "neck_y", "hip_x", "hip_y", "hip_z"))
    recording = read_joint_csv(path)
    assert recording.warnings == [
        f"{path}: the right wrist lacks right_wrist_z: the arm read without its wrist; add or rename the column, or "
        "map the file's with --columns (docs/capture.md, \"A CSV of joint positions\")",
        f"{path}: the torso lacks neck_z: left out, the shoulder's elevation measured against the vertical; add or "
        "rename the column, or map the file's with --columns (docs/capture.md, \"A CSV of joint positions\")"]
    assert all(arm.wrist is None and arm.neck is None for arm in recording.arms)
    assert read_joint_csv(_write_csv(tmp_path / "whole.csv", time)).warnings == []  # groups whole or absent: no word


def test_csv_rows_out_of_order_are_named_as_such_not_as_another_time_unit(tmp_path):
    # shuffled rows at 15 Hz were "steps by 4.2 per frame (median) ...: it looks like milliseconds
    # (divide the column by 1,000)": the median of the steps forward, between rows far apart
    time = np.random.default_rng(0).permutation(200) / 15.0
    path = _write_csv(tmp_path / "shuffled.csv", list(time))
    with pytest.raises(InputError, match=r"shuffled.csv, line 3: time stamp .* goes back \(two recordings appended, "
                                         r"or rows out of order\?\): split the file at this line, or sort its rows by "
                                         r"time stamp$"):
        read_joint_csv(path)
    # the same rows in order, in milliseconds, are named as milliseconds still
    path = _write_csv(tmp_path / "ms.csv", list(np.sort(time) * 1000))
    with pytest.raises(InputError, match=r"it looks like milliseconds \(divide the column by 1,000\)$"):
        read_joint_csv(path)


def test_a_csv_with_a_header_and_no_rows_holds_no_frames(tmp_path):
    # under pandas 3 it was "internal error: ValueError: output array is read-only"
    path = _write_csv(tmp_path / "header.csv", [0.0, 0.1])
    path.write_text(path.read_text().splitlines()[0] + "\n")
    with pytest.raises(InputError, match=r"header.csv: no frames \(a header and no rows below it\)$"):
        read_joint_csv(path)
    with pytest.raises(InputError, match=r"header.csv: no frames"):
        import_recordings([path])


def test_nan_spelt_in_any_case_is_a_blank_cell(tmp_path):
    # under pandas 3 a column with text has dtype str, not object: "NAN" was a non-numeric value
    path = _write_csv(tmp_path / "upper.csv", [0.0, 0.1, 0.2, 0.3, 0.4, 0.5])
    lines = path.read_text().splitlines()
    hand_x = 1 + _POINTS.index("right_hand_x")  # after the time
    for line, spelt in ((3, "NAN"), (5, "Nan")):
        cells = lines[line - 1].split(",")
        cells[hand_x] = spelt
        lines[line - 1] = ",".join(cells)
    path.write_text("\n".join(lines) + "\n")
    recording = read_joint_csv(path)
    assert len(recording.arms[0].hand) == 4 and len(recording.arms[0].elbow) == 6
    assert any("2 frames with a nan or blank value in a joint rlff reads" in note for note in recording.notes)


def test_time_stamps_a_little_back_are_clock_jitter_put_in_order_with_a_note(tmp_path):
    # 0.4 ms back at 120 Hz was "time stamp goes back (two recordings appended ...)": unimportable
    time = [0.0, 0.1, 0.2, 0.197, 0.3, 0.4, 0.398, 0.5]
    recording = read_joint_csv(_write_csv(tmp_path / "jitter.csv", time))
    elbow = recording.arms[0].elbow
    np.testing.assert_array_equal(elbow.time, sorted(time))
    np.testing.assert_allclose(elbow.position[3], _positions(len(time))[2, 3:6], atol=1e-6)  # line 4's frame, after line 5's
    assert any(note.startswith("jitter.csv: 2 time stamps went back, by at most 0.003 s, under 25% of the median step "
                               "(clock jitter; the first on line 5): the rows put in time stamp order")
               for note in recording.notes), recording.notes
    # a quarter of a step back or more is no jitter
    path = _write_csv(tmp_path / "back.csv", [0.0, 0.1, 0.2, 0.175, 0.3, 0.4])
    with pytest.raises(InputError, match=r"back.csv, line 5: time stamp 0.175 after 0.2 goes back"):
        read_joint_csv(path)
    # measured from the latest stamp before, not only the row before
    path = _write_csv(tmp_path / "creep.csv", [0.0, 0.1, 0.2, 0.185, 0.17, 0.3, 0.4])
    with pytest.raises(InputError, match=r"creep.csv, line 6: time stamp 0.17 after 0.185 goes back"):
        read_joint_csv(path)
    # frame numbers count frames: one back is a whole frame
    kinect = tmp_path / "numbers.txt"
    kinect.write_text("\n".join(_kinect_lines([0, 1, 2, 4, 3, 5])) + "\n")
    with pytest.raises(InputError, match=r"numbers.txt, line 5: frame number 3 after 4 goes back"):
        read_kinect_text(kinect)


def test_a_repeated_time_stamp_or_frame_number_is_dropped_with_a_note(tmp_path):
    recording = read_joint_csv(_write_csv(tmp_path / "repeat.csv", [0.0, 0.1, 0.1, 0.2, 0.3, 0.4]))
    assert len(recording.arms[0].elbow) == 5
    assert any("dropped 1 repeated time stamp (kept the first; the first repeat is on line 4)" in note for note in recording.notes)
    path = tmp_path / "repeat.txt"
    path.write_text("\n".join(_kinect_lines([0, 1, 2, 2, 3])) + "\n")
    recording = read_kinect_text(path)
    assert any("dropped 1 repeated frame number (kept the first; the first repeat is on line 4)" in note for note in recording.notes)


def test_kinect_frame_numbers_that_go_back_name_the_line(tmp_path):
    # frame numbers out of order were re-sorted without a word
    path = tmp_path / "back.txt"
    path.write_text("# header\n" + "\n".join(_kinect_lines([0, 2, 4, 8, 6, 10])) + "\n")
    with pytest.raises(InputError, match=r"back.txt, line 6: frame number 6 after 8 goes back.*split the file.*sort"):
        read_kinect_text(path)


def test_a_csv_without_a_time_column_says_the_rate_it_assumes(tmp_path):
    # a time column under another name was ignored and 30 Hz assumed without a word
    path = _write_csv(tmp_path / "stamp.csv", [0.0, 0.05, 0.1, 0.15, 0.2, 0.25], time_name="Timestamp")
    recording = read_joint_csv(path)
    assert recording.arms[0].elbow.time[1] == pytest.approx(1 / 30)
    (warning,) = recording.warnings
    assert "no time column: frames taken as 30 Hz; give --rate or map the time column" in warning
    assert "--columns time=Timestamp" in warning
    spaced = read_joint_csv(_write_csv(tmp_path / "spaced.csv", [0.0, 0.05, 0.1, 0.15, 0.2, 0.25], time_name="Time (s)"))
    assert "--columns 'time=Time (s)'" in spaced.warnings[0]  # quoted, to paste into a shell
    _, report = import_recordings([path], "csv")
    assert any("no time column" in warning for warning in report.warnings)
    plain = read_joint_csv(_write_csv(tmp_path / "plain.csv", None))
    assert any("no time column: frames taken as 30 Hz" in warning for warning in plain.warnings)
    assert not read_joint_csv(tmp_path / "plain.csv", rate_hz=15.0).warnings
    # --rate with a time column: the time column wins, and the note says so
    timed = read_joint_csv(_write_csv(tmp_path / "timed.csv", [0.0, 0.1, 0.2, 0.3, 0.4, 0.5]), rate_hz=15.0)
    assert timed.arms[0].elbow.time[1] == pytest.approx(0.1)
    assert any("--rate 15 Hz is ignored: the time column 'time' gives the time" in note for note in timed.notes)


def test_column_map_typos_are_errors_with_the_nearest_name(tmp_path):
    path = _write_csv(tmp_path / "joints.csv", [0.0, 0.1, 0.2, 0.3, 0.4, 0.5])
    with pytest.raises(InputError, match=r"joints.csv: column map \(--columns\): unknown name 'rigth_hand_q'.*did you mean 'right_hand_[xyz]'"):
        read_joint_csv(path, {"rigth_hand_q": "Foo"})
    with pytest.raises(InputError, match=r"joints.csv: column map \(--columns\): right_elbow_x=right_elbw_x: no column 'right_elbw_x'.*did you mean 'right_elbow_x'"):
        read_joint_csv(path, {"right_elbow_x": "right_elbw_x"})
    with pytest.raises(InputError, match=r"no column 'Zzz' in the file \(columns: time, right_shoulder_x"):
        read_joint_csv(path, {"time": "Zzz"})


def test_a_missing_axis_column_is_not_answered_with_another_axis_of_the_joint(tmp_path):
    # a file without HandRight.X was told "did you mean 'HandRight.Z'?", which maps z as x
    names = [f"{joint}Right.{axis}" for joint in ("Shoulder", "Elbow", "Hand") for axis in "XYZ"]
    values = _positions(6)[:, :9]
    kept = [index for index, name in enumerate(names) if name != "HandRight.X"]
    path = tmp_path / "export.csv"
    path.write_text("\n".join([",".join(["Timestamp", *(names[i] for i in kept)])]
                              + [",".join([f"{0.1 * k:g}", *(f"{row[i]:.6f}" for i in kept)]) for k, row in enumerate(values)])
                    + "\n")
    mapping = {"time": "Timestamp", **{f"right_{joint.lower()}_{axis.lower()}": f"{joint}Right.{axis}"
                                       for joint in ("Shoulder", "Elbow", "Hand") for axis in "XYZ"}}
    with pytest.raises(InputError) as error:
        read_joint_csv(path, mapping)
    assert str(error.value) == (f"{path}: column map (--columns): right_hand_x=HandRight.X: no column 'HandRight.X' in "
                                "the file; its columns for HandRight: HandRight.Y, HandRight.Z")
    # the same column in another case is the fix, and is said so
    with pytest.raises(InputError, match=r"right_hand_y=HandRight\.y: no column 'HandRight\.y' in the file "
                                         r"\(did you mean 'HandRight\.Y'\?\)$"):
        read_joint_csv(path, {**mapping, "right_hand_x": "HandRight.Y", "right_hand_y": "HandRight.y"})
    # a misspelt joint is matched within its axis, never to another axis
    with pytest.raises(InputError, match=r"no column 'ElbowRigth\.Y' in the file \(did you mean 'ElbowRight\.Y'\?\)$"):
        read_joint_csv(path, {**mapping, "right_elbow_y": "ElbowRigth.Y"})
    with pytest.raises(InputError, match=r"no column 'HandRigth\.X' in the file \(columns: Timestamp, ShoulderRight\.X"):
        read_joint_csv(path, {**mapping, "right_hand_x": "HandRigth.X"})


@pytest.mark.parametrize("separator, spaced", [(" ", True), (",", False), ("\t", False)])
def test_a_csv_without_a_header_row_says_so(tmp_path, separator, spaced):
    # its first row of numbers was read as its names: "columns present: 0 -0.18587 ..."
    path = tmp_path / "joints.csv"
    rows = [separator.join([str(k), *(f"{v:.6f}" for v in row)]) for k, row in enumerate(_positions(6))]
    path.write_text("\n".join(rows) + "\n")
    with pytest.raises(InputError) as error:
        read_joint_csv(path)
    message = str(error.value)
    assert message.startswith(f"{path}: no header row of names: the first line holds numbers ({rows[0][:40] + '...'!r}), "
                              "where a CSV of joint positions names its columns, separated by ',', ';' or a tab (time, "
                              "right_shoulder_x, ... or the file's own names mapped with --columns; docs/capture.md, "
                              '"A CSV of joint positions"); add that line'), message
    assert message.endswith(", and put ',' between the columns (the line has 19 numbers separated by spaces)") == spaced


def test_one_column_given_for_two_names_is_refused_naming_both(tmp_path):
    # an OpenPose export (no hand point) mapped with its wrist as the hand and as the wrist was
    # imported with a wrist segment 0 m long: the wrist angle 0.0 on every row
    names = [f"R{joint}_{axis}" for joint in ("Shoulder", "Elbow", "Wrist") for axis in "xyz"]
    path = tmp_path / "openpose.csv"
    path.write_text("\n".join([",".join(["t", *names])] + [",".join([f"{0.1 * k:g}", *(f"{v:.6f}" for v in row)])
                                                           for k, row in enumerate(_positions(6)[:, :9])]) + "\n")
    mapping = {"time": "t", **{f"right_{joint.lower()}_{axis}": f"R{joint}_{axis}"
                               for joint in ("Shoulder", "Elbow") for axis in "xyz"}}
    hand = {f"right_hand_{axis}": f"RWrist_{axis}" for axis in "xyz"}
    assert read_joint_csv(path, {**mapping, **hand}).arms  # the wrist as the hand alone is read
    with pytest.raises(InputError) as error:
        read_joint_csv(path, {**mapping, **hand, **{f"right_wrist_{axis}": f"RWrist_{axis}" for axis in "xyz"}})
    assert str(error.value).startswith(
        f"{path}: column map (--columns): the file's column 'RWrist_x' is given for two names, "
        "right_wrist_x=RWrist_x and right_hand_x=RWrist_x: one point read as two joints makes the segment between "
        "them 0 m long (a wrist angle of 0 on every row); give each name a column of its own, or leave one out")
    # a name mapped to the column another name reads under its own
    own = _write_csv(tmp_path / "joints.csv", [0.1 * k for k in range(6)])
    with pytest.raises(InputError, match=r"the file's column 'right_hand_x' is given for two names, right_wrist_x="
                                         r"right_hand_x and right_hand_x \(its own column, not mapped\):"):
        read_joint_csv(own, {"right_wrist_x": "right_hand_x"})


def test_a_missing_column_of_one_side_is_never_answered_with_the_other_sides_joint(tmp_path):
    # a right-arm export mapped with the left arm too was told "did you mean 'RShoulder.X'?",
    # which would read the right shoulder as the left one
    joints = ("Shoulder", "Elbow", "Hand")
    names = [f"{side}{joint}.{axis}" for side in "RL" for joint in joints for axis in "XYZ"]
    values = _positions(6)
    both = tmp_path / "both.csv"
    both.write_text("\n".join([",".join(["time", *names])] + [",".join([f"{0.1 * k:g}", *(f"{v:.6f}" for v in row)])
                                                              for k, row in enumerate(values)]) + "\n")
    right = tmp_path / "right.csv"
    right.write_text("\n".join(",".join(line.split(",")[:10]) for line in both.read_text().splitlines()) + "\n")
    mapping = {f"{side}_{joint.lower()}_{axis.lower()}": f"{side[0].upper()}{joint}.{axis}"
               for side in ("right", "left") for joint in joints for axis in "XYZ"}
    with pytest.raises(InputError) as error:
        read_joint_csv(right, mapping)
    assert str(error.value) == (f"{right}: column map (--columns): left_shoulder_x=LShoulder.X: no column 'LShoulder.X' "
                                "in the file; the file has no column of the left side (it may hold one arm: leave the "
                                "left_... names out of --columns; columns: time, " + ", ".join(names[:9]) + ")")
    # a misspelt joint of one side is matched within that side
    with pytest.raises(InputError, match=r"no column 'LShouldr\.X' in the file \(did you mean 'LShoulder\.X'\?\)$"):
        read_joint_csv(both, {**mapping, "left_shoulder_x": "LShouldr.X"})
    # a file with a left arm but no left shoulder: the right one is still no answer
    lines = [line.split(",") for line in both.read_text().splitlines()]
    no_shoulder = tmp_path / "no_shoulder.csv"
    no_shoulder.write_text("\n".join(",".join(cells[:10] + cells[13:]) for cells in lines) + "\n")
    with pytest.raises(InputError) as error:
        read_joint_csv(no_shoulder, mapping)
    assert "did you mean" not in str(error.value) and "no column 'LShoulder.X' in the file (columns: time, " \
        "RShoulder.X" in str(error.value)


def test_a_non_finite_value_is_located_by_its_file_line(tmp_path):
    # MSR: line 201 was "frame 201" (it is frame 11); Kinect: line 13 (frame number 20) was "frame 11"
    lines = _msr_lines(12)
    lines[200] = "inf 0.2 2.5 1"
    msr = tmp_path / "a06_s01_e01_skeleton3D.txt"
    msr.write_text("\n".join(lines) + "\n")
    with pytest.raises(InputError, match=r"skeleton3D.txt, line 201 \(frame 11, joint 1\): value 1 is 'inf', not a finite number"):
        read_msr_text(msr)
    # nan is a joint the tracker did not give: left out of that joint's track alone (joint 1 is
    # the left shoulder), and where no joint rlff reads has it (joint 20, the head) no loss at all
    lines[200] = "nan 0.2 2.5 1"
    lines[199] = "nan nan nan 0"
    msr.write_text("\n".join(lines) + "\n")
    recording = read_msr_text(msr)
    left = next(arm for arm in recording.arms if arm.side == "left")
    assert len(left.shoulder) == 11 and len(left.elbow) == 12 and len(recording.arms[0].elbow) == 12
    assert any("1 frame with a nan or blank value in a joint rlff reads (the first at t=0.67 s)" in note
               for note in recording.notes)
    lines = _kinect_lines(list(range(0, 40, 2)))
    fields = lines[10].split()
    lines[10] = " ".join([fields[0], "inf", *fields[2:]])
    kinect = tmp_path / "kin_nan.txt"
    kinect.write_text("# joints\n\n" + "\n".join(lines) + "\n")
    with pytest.raises(InputError, match=r"kin_nan.txt, line 13 \(frame number 20\): value 2 is 'inf', not a finite number"):
        read_kinect_text(kinect)


def test_a_csv_line_is_counted_past_blank_lines(tmp_path):
    # a blank line between two takes put every later line number one too low
    path = _write_csv(tmp_path / "takes.csv", [0.0, 0.1, 0.2, 0.0, 0.1, 0.2])
    lines = path.read_text().splitlines()
    path.write_text("\n".join([*lines[:4], "", *lines[4:]]) + "\n")
    with pytest.raises(InputError, match=r"takes.csv, line 6: time stamp 0 after 0.2 goes back"):
        read_joint_csv(path)
    lines = _write_csv(path, [0.0, 0.1, 0.2, 0.3, 0.4, 0.5]).read_text().splitlines()
    cells = lines[5].split(",")
    lines[5] = ",".join([*cells[:3], "x", *cells[4:]])
    path.write_text("\n".join([lines[0], "", *lines[1:4], "", "", *lines[4:]]) + "\n")
    with pytest.raises(InputError, match=r"takes.csv, line 9: column 'right_shoulder_z' has a non-numeric or "
                                         r"non-finite value 'x'"):
        read_joint_csv(path)


def test_a_byte_order_mark_is_read_past(tmp_path):
    msr = tmp_path / "bom_skeleton3D.txt"
    msr.write_text("\n".join(_msr_lines(3)) + "\n", encoding="utf-8-sig")
    assert len(read_msr_text(msr).arms[0].elbow) == 3
    kinect = tmp_path / "bom.txt"
    kinect.write_text("\n".join(_kinect_lines([0, 1, 2])) + "\n", encoding="utf-8-sig")
    assert len(read_kinect_text(kinect).arms[0].elbow) == 3


@pytest.mark.parametrize(("sep", "decimal", "name"), [(";", ",", "';'"), (";", ".", "';'"), ("\t", ".", "tab"), ("\t", ",", "tab")])
def test_semicolon_and_tab_separated_csv_are_read(tmp_path, sep, decimal, name):
    # they gave "no arm with ... columns", listing one merged column
    time = [0.0, 0.1, 0.2, 0.3, 0.4, 0.5]
    expected = read_joint_csv(_write_csv(tmp_path / "comma.csv", time))
    recording = read_joint_csv(_write_csv(tmp_path / "other.csv", time, sep=sep, decimal=decimal))
    np.testing.assert_array_equal(recording.arms[0].elbow.position, expected.arms[0].elbow.position)
    np.testing.assert_array_equal(recording.arms[0].elbow.time, expected.arms[0].elbow.time)
    assert any(f"columns separated by {name}" in note for note in recording.notes)


def test_the_import_tells_each_file_s_stages(tmp_path):
    # one long file sat at "0/1" for a minute: the bar moved only when a file was done
    paths = [_write_csv(tmp_path / f"take{n}.csv", [0.0, 0.1, 0.2, 0.3, 0.4, 0.5]) for n in (1, 2)]
    told = []
    import_recordings(paths, "csv", progress=lambda path, stage, share: told.append((Path(path).name, stage, share)))
    assert told == [(name, stage, share) for name in ("take1.csv", "take2.csv")
                    for stage, share in (("reading", 0.0), ("cutting throws", READ_SHARE), ("done", 1.0))]
