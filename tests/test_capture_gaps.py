"""A sample lost where a real throw's elbow extends fastest: warned of and marked, not bridged silently.

The MSR high throw ``a06_s01_e03`` (15 Hz) peaks at 14.7 rad/s. With the elbow's sample at its
peak lost (a joint at zero in MSR text, a ``nan`` in a CSV, a dropped Kinect row) the gap is
0.13 s, under the long-gap rule's 3 spacings (0.2 s): the fits on either side wrote a peak of
7.8 rad/s without a word. Regular copies thinned to 10 and 7.5 Hz are sparse, not gappy: no
warning there, nor on the throws whole, nor on a 30 Hz recording that lost one sample.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))
import thinned as th  # noqa: E402
from rlff.capture import import_recordings  # noqa: E402
from rlff.dataset import read_csv  # noqa: E402

#: The real throw, and the frame (0-based, 15 Hz) whose elbow extends fastest.
THROW = "a06_s01_e03_skeleton3D.txt"
FASTEST = 19
ELBOW_LINE = 8  # MSR line 9 (0-based 8) of a frame: elbow B, the throwing arm's
PEAK_GAP = "where the elbow extends fastest"


def _peak_gap_warnings(report) -> list[str]:
    return [warning for warning in report.warnings if PEAK_GAP in warning]


@pytest.mark.realdata
def test_an_elbow_sample_lost_at_the_peak_of_a_real_throw_is_warned_of_and_marked(msr_dir, tmp_path, rlff):
    source = msr_dir / THROW
    lines = source.read_text().splitlines()
    zero = list(lines)
    zero[FASTEST * 20 + ELBOW_LINE] = "0 0 0 0"  # the tracker's way of writing a joint it lost
    frames = th.msr_frames(source)
    time = np.arange(len(frames)) / 15.0
    blank = frames.copy()
    blank[FASTEST, 9] = np.nan  # the right elbow, Kinect order
    kept = np.r_[0:FASTEST, FASTEST + 1:len(frames)]
    copies = {
        "msr": (tmp_path / "zero.txt", "msr"),
        "csv": (th.write_joint_csv(tmp_path / "blank.csv", blank, time), "csv"),
        "kinect-text": (th.write_copy(tmp_path, "dropped", frames[kept], time[kept], "kinect-text"), "kinect-text"),
    }
    copies["msr"][0].write_text("\n".join(zero) + "\n")
    whole, whole_report = import_recordings([source], "msr")
    assert [t.peak_velocity for t in whole_report.files[0].throws] == [pytest.approx(14.73, abs=0.01)]
    assert not _peak_gap_warnings(whole_report)
    for what, (path, format) in copies.items():
        dataset, report = import_recordings([path], format, up="y" if format == "csv" else None)
        (throw,) = report.files[0].throws
        assert throw.peak_velocity < 0.6 * 14.73, what  # what the fits on either side write
        (warning,) = _peak_gap_warnings(report)
        joints = "every joint's" if what == "kinect-text" else "the elbow's"
        assert warning.startswith(
            f"{path}: throw 1: its extension has a 0.13 s gap in {joints} samples at t=1.20 s, where the elbow "
            "extends fastest (they are 0.0683 s apart elsewhere: 1 sample lost): 1.75 rad of its 2.28 rad extension "
            "(77%) are bridged from the fits on either side, which see one side of the gap only; the elbow moved at "
            f"least 13.1 rad/s across it, and the peak written, {throw.peak_velocity:.3g} rad/s, is likely too low "
            "(peak_confidence low); check the throw before fitting on it"), (what, warning)
        assert throw.peak_confidence == "low" and dataset.trajectories[0].meta["peak_confidence"] == "low", what
    assert whole.trajectories[0].meta["peak_confidence"] == "high"
    # the mark rides along in the dataset a user gets, and reads back
    result = rlff("data", "import", str(copies["msr"][0]), "--format", "msr", "-o", str(tmp_path / "demos.csv"))
    assert result.code == 0 and PEAK_GAP in result.stderr
    assert [t.meta["peak_confidence"] for t in read_csv(tmp_path / "demos.csv")] == ["low"]


@pytest.mark.realdata
@pytest.mark.slow
def test_whole_and_regularly_thinned_real_throws_have_no_gap_at_the_peak(msr_dir, tmp_path):
    # sparse is not gappy: every spacing of a regular copy is the copy's own (at 10 Hz, one and
    # two 15 Hz frames in turn; at 7.5 Hz two, now and then three and one where rounding falls)
    whole = sorted(msr_dir.glob("*_skeleton3D.txt"))
    _, report = import_recordings(whole, "msr")
    assert report.n_throws >= 49 and not _peak_gap_warnings(report)
    assert {throw.peak_confidence for file in report.files for throw in file.throws} == {"high"}
    for source in sorted(msr_dir.glob("a06_*_skeleton3D.txt")):
        frames = th.msr_frames(source)
        time = np.arange(len(frames)) / 15.0
        for rate in (10.0, 7.5):
            for phase in (0.0, 0.25, 0.5, 0.75):
                kept = th.thinned_indices(len(frames), 15.0, rate, "regular", phase, np.random.default_rng(0))
                path = th.write_copy(tmp_path, f"{source.stem}_{rate:g}_{phase:g}", frames[kept], time[kept], "kinect-text")
                _, copy = import_recordings([path], "kinect-text")
                assert copy.files[0].throws, path.name
                assert not _peak_gap_warnings(copy), copy.warnings
                assert {throw.peak_confidence for throw in copy.files[0].throws} == {"high"}, path.name


def test_a_30_hz_recording_that_lost_a_sample_at_the_peak_keeps_its_fit(tmp_path):
    # one lost sample at 30 Hz is 0.067 s: the 0.25 s fits keep 7 samples, and the peak moves a few percent
    frames, time, movements = th.session(3, rate=30.0)
    throw = next(movement for movement in movements if movement.is_throw)
    fastest = int(np.argmin(np.abs(time - throw.peak_time)))
    kept = np.r_[0:fastest, fastest + 1:len(time)]
    whole = th.write_joint_csv(tmp_path / "whole.csv", frames, time)
    lost = th.write_joint_csv(tmp_path / "lost.csv", frames[kept], time[kept])
    _, whole_report = import_recordings([whole], "csv", up="y")
    _, report = import_recordings([lost], "csv", up="y")
    assert not _peak_gap_warnings(report)
    (reference,) = [t for t in whole_report.files[0].throws if abs(t.release - throw.peak_time) < 0.5]
    (first,) = [t for t in report.files[0].throws if abs(t.release - throw.peak_time) < 0.5]
    assert first.peak_confidence == "high"
    assert first.peak_velocity == pytest.approx(reference.peak_velocity, rel=0.1)
