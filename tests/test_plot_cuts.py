"""``rlff plot cuts``: where the import cut a recording, drawn from a real bag written and read back."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest
from matplotlib.colors import to_hex

import bagfactory as bf


def test_plot_cuts_says_the_import_s_parts_and_the_drawing(rlff, tmp_path):
    # a 26-minute recording of 600 throws: 64 s without a word, 10 s of import and the rest drawing
    bag = bf.write_ros1_bag(tmp_path / "session.bag", bf.standard_simulation(seed=5, n_throws=10), compression=None)
    result = rlff("plot", "cuts", str(bag), "-o", str(tmp_path / "cuts"), "--json")
    assert result.code == 0, result.stderr
    assert json.loads(result.stdout)["files"] == [str(tmp_path / "cuts.png"), str(tmp_path / "cuts.svg")]
    said = [re.sub(r" \d+:\d\d:\d\d$", "", line) for line in result.stderr.splitlines()
            if re.search(r" \d+/2 \(\d+ %\) \d+:\d\d:\d\d$", line)]
    assert said == ["importing 0/2 (0 %)", "session.bag: cutting throws 0/2 (20 %)",
                    "session.bag: labelling throw 3 of 10 0/2 (30 %)", "session.bag: labelling throw 7 of 10 0/2 (40 %)",
                    "session.bag: done 1/2 (50 %)", "drawing cuts (.png, .svg) 2/2 (100 %)"], result.stderr


def test_the_figure_shows_each_throw_where_the_import_cut_it(rlff, tmp_path):
    simulation = bf.standard_simulation(seed=4, n_throws=3, second_user=False)
    bag = bf.write_ros1_bag(tmp_path / "session_2m.bag", simulation, compression=None)
    report = tmp_path / "import.json"
    imported = rlff("data", "import", str(bag), "-o", str(tmp_path / "d.csv"), "--json")
    assert imported.code == 0, imported.stderr
    report.write_text(imported.stdout)
    throws = json.loads(imported.stdout)["files"][0]["throws"]
    assert len(throws) == 3

    result = rlff("plot", "cuts", str(bag), "-o", str(tmp_path / "cuts"), "--json")
    assert result.code == 0, result.stderr
    assert (tmp_path / "cuts.png").stat().st_size > 0 and (tmp_path / "cuts.svg").is_file()

    from rlff.capture import import_recordings
    from rlff.capture.importer import arm_motion, read_recording
    from rlff.plots.capture import throw_cuts

    _, again = import_recordings([bag])
    motion = again.files[0].motion  # the arm the throws were cut from, as arm_motion gives it
    assert np.array_equal(motion.angle, arm_motion(read_recording(bag, "bag"))[0].angle)
    assert "motion" not in again.to_dict()["files"][0]  # kept out of the JSON report
    figure = throw_cuts(again.files[0], tmp_path / "again").figure
    (axes,) = figure.axes
    spans = sorted(patch.get_x() for patch in axes.patches)  # axvspan: one rectangle per throw
    assert np.allclose(spans, [throw["start"] for throw in throws])
    # the angle is drawn on the recording's clock from its first sample, as the report's times
    (line, *_) = axes.lines
    assert line.get_xdata()[0] == 0.0 and np.allclose(line.get_ydata(), motion.angle)
    assert "3 throws" in axes.get_title()


def test_a_thesis_matrix_has_no_recording_to_show(rlff, tmp_path):
    matrix = tmp_path / "th.txt"
    assert rlff("-q", "data", "synth", "thesis", "-o", str(matrix)).code == 0
    result = rlff("plot", "cuts", str(matrix), "-f", "thesis", "-o", str(tmp_path / "c"))
    assert result.code == 2 and "holds throws already cut" in result.stderr


def test_the_throws_are_labelled_with_the_manifests_baskets(rlff, tmp_path):
    # the figure checks an import: its baskets must be the ones the import with that manifest gives
    bag = bf.write_ros1_bag(tmp_path / "session.bag", bf.standard_simulation(seed=4, n_throws=3, second_user=False),
                            compression=None)
    manifest = tmp_path / "baskets.csv"
    manifest.write_text("file,throw,distance\nsession.bag,1,1.5\nsession.bag,2,3.25\nsession.bag,3,2.0\n")
    result = rlff("plot", "cuts", str(bag), "--manifest", str(manifest), "-o", str(tmp_path / "cuts"))
    assert result.code == 0, result.stderr

    from rlff.capture import import_recordings
    from rlff.plots.capture import throw_cuts

    _, report = import_recordings([bag], manifest=manifest)
    (axes,) = throw_cuts(report.files[0], tmp_path / "again").figure.axes
    labels = [text.get_text().split("\n")[-1] for text in axes.texts if text.get_text().startswith("session")]
    assert labels == ["1.5 m", "3.25 m", "2 m"]
    # the command reads the manifest as the import does: a basket out of range is refused
    manifest.write_text("file,throw,distance\nsession.bag,1,200\n")
    refused = rlff("plot", "cuts", str(bag), "--manifest", str(manifest), "-o", str(tmp_path / "c"))
    assert refused.code == 2 and "baskets.csv" in refused.stderr and "200" in refused.stderr, refused.stderr


def test_the_session_manifest_s_rows_for_other_recordings_are_one_note(rlff, tmp_path):
    # the docs say to pass the import's --manifest: a manifest of the session gave a warning per row
    # of every other recording, burying the figure's own warnings
    bag = bf.write_ros1_bag(tmp_path / "session.bag", bf.standard_simulation(seed=4, n_throws=3, second_user=False),
                            compression=None)
    rows = "".join(f"session.bag,{k},2.0\n" for k in (1, 2, 3))
    for index in range(2, 6):
        (tmp_path / f"session{index}.bag").write_bytes(b"")
        rows += f"session{index}.bag,1,1.5\n"
    manifest = tmp_path / "baskets.csv"
    manifest.write_text("file,throw,distance\n" + rows)
    result = rlff("plot", "cuts", str(bag), "--manifest", str(manifest), "-o", str(tmp_path / "cuts"))
    assert result.code == 0, result.stderr
    assert "warning" not in result.stderr, result.stderr
    (note,) = [line for line in result.stderr.splitlines() if "not given" in line]
    assert note.endswith(f"manifest {manifest}: 4 rows name 4 recordings not given (session2.bag, session3.bag, "
                         "session4.bag and 1 more): not used")


def test_lost_tracking_is_shaded_and_what_the_import_says_is_said(rlff, msr_dir, tmp_path):
    # a recording whose tracking was lost said "0 throws" and nothing of the frames dropped or
    # of why no throw was found; the stretch without tracking was an unmarked gap in the line
    recording = msr_dir / "a20_s02_e02_skeleton3D.txt"
    result = rlff("plot", "cuts", str(recording), "--format", "msr", "-o", str(tmp_path / "cuts"))
    assert result.code == 0, result.stderr
    assert "a20_s02_e02_skeleton3D.txt: dropped 29 frames with all arm joints at zero (tracking lost)" in result.stderr
    assert f"warning: {recording}: no throw found (user 1, left arm)" in result.stderr

    from rlff.capture import import_recordings
    from rlff.plots.capture import LOST_COLOUR, throw_cuts

    _, report = import_recordings([recording], "msr")
    motion = report.files[0].motion
    ((begin, end),) = motion.lost_spans()
    saved = throw_cuts(report.files[0], tmp_path / "again")
    (axes,) = saved.figure.axes
    (lost,) = [patch for patch in axes.patches if patch.get_label() == "tracking lost"]
    assert to_hex(lost.get_facecolor()) == to_hex(LOST_COLOUR)
    assert (lost.get_x(), lost.get_width()) == pytest.approx((begin - motion.time[0], end - begin))
    assert axes.get_title().endswith(f"0 throws, 1 movement not taken; tracking lost 1 time for {end - begin:.2f} s "
                                     "(grey)")
    # why no throw was found, under the axes
    assert saved.figure.get_supxlabel().startswith("import: no throw found (user 1, left arm); the best candidate")
    assert saved.warnings == tuple(report.files[0].warnings)


def test_frames_dropped_at_the_end_of_a_real_recording_are_shaded(rlff, msr_dir, tmp_path):
    # a20_s02_e01 loses its thrower for its last 32 frames (2.13 s at 15 Hz): the note counted them,
    # and the figure ended at the last tracked sample as if the recording did
    recording = msr_dir / "a20_s02_e01_skeleton3D.txt"
    result = rlff("plot", "cuts", str(recording), "--format", "msr", "-o", str(tmp_path / "cuts"))
    assert result.code == 0, result.stderr
    assert "a20_s02_e01_skeleton3D.txt: dropped 32 frames with all arm joints at zero (tracking lost)" in result.stderr

    from rlff.capture import import_recordings
    from rlff.plots.capture import LOST_COLOUR, throw_cuts

    _, report = import_recordings([recording], "msr")
    file = report.files[0]
    last = float(file.motion.time[-1] - file.motion.time[0])  # 23 frames tracked from frame 0
    assert last == pytest.approx(23 / 15)
    (axes,) = throw_cuts(file, tmp_path / "again").figure.axes
    (lost,) = [patch for patch in axes.patches if patch.get_label() == "tracking lost"]
    assert to_hex(lost.get_facecolor()) == to_hex(LOST_COLOUR)
    assert (lost.get_x(), lost.get_width()) == pytest.approx((last, 32 / 15))
    assert axes.get_xlim()[1] == pytest.approx(55 / 15)  # the recording's last frame
    assert axes.get_title().endswith("tracking lost 1 time for 2.13 s (grey)")
    assert "frames_span" not in report.to_dict()["files"][0]  # the JSON report is unchanged


def test_frames_dropped_at_the_start_are_shaded_before_the_first_tracked_sample(msr_dir, tmp_path):
    # the tracker finds the thrower 0.6 s into the file and loses them 0.33 s before its end: the
    # report's times count from the file's first frame (a video's times: a manifest's start and end
    # are read against them), and the stretch before the first tracked sample is drawn from 0
    from rlff.capture import import_recordings
    from rlff.plots.capture import throw_cuts

    lines = (msr_dir / "a06_s01_e03_skeleton3D.txt").read_text().splitlines()
    count = len(lines) // 20
    arm_lines = (0, 7, 9, 11, 1, 8, 10, 12)  # both arms' shoulder, elbow, wrist, hand
    for frame in [*range(9), *range(count - 5, count)]:
        for line in arm_lines:
            lines[frame * 20 + line] = "0 0 0 0"
    late = tmp_path / "late.txt"
    late.write_text("\n".join(lines) + "\n")
    _, report = import_recordings([late], "msr")
    file = report.files[0]
    assert file.clock_origin == 0.0 and len(file.throws) == 1
    (axes,) = throw_cuts(file, tmp_path / "cuts").figure.axes
    lost = sorted((patch.get_x(), patch.get_width()) for patch in axes.patches if patch.get_hatch() == "//")
    last_tracked = (count - 1 - 5) / 15
    assert np.allclose(lost, [(0.0, 9 / 15), (last_tracked, 5 / 15)])
    assert axes.get_xlim() == pytest.approx((0.0, (count - 1) / 15))
    assert axes.get_title().endswith("tracking lost 2 times for 0.93 s (grey)")
    (kept,) = [patch for patch in axes.patches if patch.get_label() == "throw kept"]
    assert kept.get_x() == pytest.approx(file.throws[0].start)  # the throws' times are the report's


def test_blank_rows_at_the_end_of_a_csv_are_shaded(tmp_path):
    # a CSV whose last rows the exporter left blank (no joint tracked): the arm's tracks end before
    # the file does, and the figure says where
    import thinned as th
    from rlff.capture import import_recordings
    from rlff.plots.capture import throw_cuts

    frames, time, _ = th.session(5, rate=30.0)
    frames[-30:] = np.nan
    path = th.write_joint_csv(tmp_path / "blank_end.csv", frames, time)
    _, report = import_recordings([path], "csv", up="y")
    file = report.files[0]
    (axes,) = throw_cuts(file, tmp_path / "cuts").figure.axes
    (lost,) = [patch for patch in axes.patches if patch.get_label() == "tracking lost"]
    end = float(time[-31] - file.clock_origin)
    assert (lost.get_x(), lost.get_width()) == pytest.approx((end, 30 / 30), abs=1e-9)


def test_a_long_recording_is_drawn_in_rows_each_labelling_its_own_throws(tmp_path):
    # a 25-minute session on one axis: 286 labels overlapped into a band
    from rlff.capture import import_recordings
    from rlff.plots.capture import throw_cuts

    bag = bf.write_ros1_bag(tmp_path / "long.bag", bf.standard_simulation(seed=5, n_throws=45, second_user=False),
                            compression=None)
    _, report = import_recordings([bag])
    (cut,) = report.files
    assert len(cut.throws) >= 40
    rows = throw_cuts(cut, tmp_path / "cuts").figure.axes
    assert len(rows) >= 2
    labelled = []
    for axes in rows:
        begin, end = axes.get_xlim()
        assert end - begin >= 60.0  # rows of a minute at least (ROW_SECONDS)
        for text in axes.texts:
            if text.get_text().startswith("long_t"):
                labelled.append(text.get_text().split("\n")[0])
                assert begin <= text.xy[0] <= end  # each label in the row its throw starts in
    assert sorted(labelled) == sorted(throw.id for throw in cut.throws)  # every throw labelled once
