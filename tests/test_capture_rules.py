"""The time-based rules of capture (issue 14): lost tracking, glitches, the extension rule, rejections, manifests."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))
import thinned as th  # noqa: E402
from rlff.capture import import_recordings  # noqa: E402
from rlff.capture.angles import align_arm, lost_tracking_gap  # noqa: E402
from rlff.capture.label import read_manifest  # noqa: E402
from rlff.capture.segment import find_throws, steepest_rise  # noqa: E402
from rlff.capture.skeleton import ArmTrack, JointTrack  # noqa: E402
from rlff.errors import InputError  # noqa: E402


def _arm(time: np.ndarray, angle: np.ndarray) -> ArmTrack:
    """A right arm whose elbow angle is ``angle`` (rad) at ``time`` (s): upper arm fixed, forearm in a plane."""
    time, angle = np.asarray(time, dtype=float), np.asarray(angle, dtype=float)
    shoulder = np.tile([0.0, 0.0, 0.3], (time.size, 1))
    elbow = np.zeros((time.size, 3))
    hand = 0.28 * np.column_stack([np.sin(angle), np.zeros(time.size), np.cos(angle)])
    return ArmTrack("1", "right", JointTrack("s", time, shoulder), JointTrack("e", time, elbow), JointTrack("h", time, hand))


def test_a_gap_is_lost_tracking_only_when_long_in_seconds_and_against_the_usual_spacing():
    assert lost_tracking_gap(np.arange(40) / 30.0) == 0.5
    assert lost_tracking_gap(np.arange(40) / 4.0) == 0.75
    at_4_hz = np.r_[np.arange(10) * 0.25, 2.25 + 0.6 + np.arange(10) * 0.25]  # a 0.6 s gap at 4 Hz is sampling
    assert len(align_arm(_arm(at_4_hz, np.full(at_4_hz.size, 2.6))).runs()) == 1
    at_30_hz = np.r_[np.arange(30) / 30.0, 1.6 + np.arange(30) / 30.0]  # 0.63 s at 30 Hz is lost tracking
    motion = align_arm(_arm(at_30_hz, np.full(at_30_hz.size, 2.6)))
    assert [(run.start, run.stop) for run in motion.runs()] == [(0, 30), (30, 60)]
    assert motion.lost_spans() == [(pytest.approx(29 / 30), pytest.approx(1.6))]


def test_steepest_rise_on_the_lines_between_samples():
    time, values = np.array([0.0, 1.0, 2.0, 3.0]), np.array([0.0, 0.0, 2.0, 2.5])
    begin, rise = steepest_rise(time, values, 0.5)
    assert rise == pytest.approx(1.0) and begin == pytest.approx(1.25)  # the middle of the one steep chord
    begin, rise = steepest_rise(time, values, 1.5)
    assert rise == pytest.approx(2.25) and begin == pytest.approx(1.0)
    assert steepest_rise(time[:2], values[:2], 5.0) == (pytest.approx(-2.0), 0.0)  # shorter than the window: centred


@pytest.mark.parametrize(("rate", "seed"), [(30.0, 28), (15.0, 0)])
@pytest.mark.parametrize("digits", [6, 3])
def test_epoch_time_stamps_cut_the_throws_where_stamps_from_0_do(tmp_path, rate, seed, digits):
    # float64 keeps 1.7e9 s to 2.4e-7 s: 3 steps at 30 Hz span min_motion (0.1 s), 2 steps at 15 Hz the
    # velocity fit's half-window, each a hair over or under it; the cuts moved by up to 0.13 s
    frames, time, _ = th.session(seed, rate=rate)
    cuts = []
    for origin in (0.0, 1_700_000_123.456):
        path = th.write_joint_csv(tmp_path / f"from_{origin:.0f}.csv", frames, np.round(time + origin, digits))
        file = th.import_copy(path, "csv")
        assert file.clock_origin == pytest.approx(origin + time[0], abs=1e-3)
        cuts.append([(throw.start, throw.end, throw.release) for throw in file.throws])
    assert len(cuts[1]) == len(cuts[0]) >= 3
    np.testing.assert_allclose(cuts[1], cuts[0], atol=1e-5)


def test_a_glitch_between_agreeing_neighbours_goes_but_a_sparse_wind_up_stays():
    time = np.arange(45) / 15.0
    angle = np.full(time.size, 2.6)
    angle[20] = 1.2  # one sample away from two that agree: a glitch
    motion = align_arm(_arm(time, angle))
    assert motion.glitches.tolist() == [pytest.approx(20 / 15)] and motion.time.size == 44
    assert find_throws(motion)[0] == []
    # at 4 Hz the wound-up elbow may be a single sample between two rest samples: it is a throw
    time = np.arange(16) * 0.25
    angle = np.full(time.size, 2.7)
    angle[6], angle[7] = 0.8, 2.9
    motion = align_arm(_arm(time, angle))
    assert motion.glitches.size == 0
    (cut,), _ = find_throws(motion)
    assert (cut.extension_start, cut.extension_end) == (6, 7)


def test_every_candidate_not_taken_comes_back_with_its_rule_time_and_reason(tmp_path):
    time = np.arange(0, 12, 1 / 30)
    angle = np.full(time.size, 2.6)
    small = (time >= 2.0) & (time < 2.6)
    angle[small] = 2.6 - 0.45 * np.sin(np.pi * (time[small] - 2.0) / 0.6)  # dips by 0.45 rad and comes back
    slow_down, slow_up = (time >= 4.0) & (time < 5.0), (time >= 5.0) & (time < 8.0)
    angle[slow_down] = 2.6 - 1.2 * (time[slow_down] - 4.0)
    angle[slow_up] = 1.4 + 1.2 * (time[slow_up] - 5.0) / 3.0  # 1.2 rad in 3 s: 0.2 rad per 0.5 s
    _, rejections = find_throws(align_arm(_arm(time, angle)))
    assert [r.rule for r in rejections] == ["min_extension", "extension_window"]
    small_one, slow_one = rejections
    assert 2.3 <= small_one.time <= 2.6 and "rises by 0.45 rad, less than 0.60" in small_one.reason
    assert 5.0 <= slow_one.time <= 8.0 and "at most 0.20 rad within 0.5 s" in slow_one.reason
    # the import names the rule that stopped the best candidate when no throw is found
    frames = np.zeros((time.size, 20, 3))
    arm = _arm(time, angle)
    frames[:, 8], frames[:, 9], frames[:, 11] = arm.shoulder.position, arm.elbow.position, arm.hand.position
    frames[:, 10] = 0.9 * arm.hand.position
    frames[:, 4:8] = [0.4, 0.0, 0.0]
    path = th.write_kinect_text(tmp_path / "slow.txt", frames + [0.0, 0.0, 2.5], np.arange(time.size))
    dataset, report = import_recordings([path], "kinect-text")
    (file,) = report.files
    assert len(dataset) == 0 and [r.rule for r in file.rejected] == ["min_extension", "extension_window"]
    (warning,) = file.warnings
    assert "no throw found" in warning and "stopped by rule 'extension_window'" in warning
    assert sum("is not a throw" in note for note in file.notes) == 2


def test_manifest_rows_at_fault_are_named(tmp_path):
    path = tmp_path / "manifest.csv"
    path.write_text("file,throw,distance\nline1.bag,1,2.0\nother.bag,,3.0\nline1.bag,1,2.5\n")
    with pytest.raises(InputError, match=r"manifest .*manifest.csv, line 4: line1.bag \(throw 1\) is listed again with distance 2.5 m; line 2 gives 2 m"):
        read_manifest(path)
    path.write_text("file,distance\nline1.bag,2.0\nline1.bag,3.0\n")
    with pytest.raises(InputError, match=r"line 3: line1.bag \(the whole file\) is listed again"):
        read_manifest(path)
    path.write_text("file,start,end,distance\nline1.bag,12,10,2.0\n")
    with pytest.raises(InputError, match=r"line 2: start 12 s is after end 10 s"):
        read_manifest(path)
    path.write_text("file,throw,distance\nline1.bag,0,2.0\n")
    with pytest.raises(InputError, match=r"line 2: throw 0 does not exist"):
        read_manifest(path)
    path.write_text("file,throw,distance\nline1.bag,1,2.0\nline1.bag,2,2.0\nline1.bag,2,2.0\n")
    assert len(read_manifest(path)) == 3  # the same row twice, same distance: no conflict


def test_a_manifest_column_rlff_does_not_read_is_named_not_lost(tmp_path):
    # the baskets' bearings and heights under other names were dropped without a word
    path = tmp_path / "manifest.csv"
    path.write_text("file,throw,distance,bearing_deg,rim_height,notes\nline1.bag,1,2.0,30,1.0,ok\n")
    with pytest.raises(InputError, match=r"manifest .*manifest.csv: unknown columns 'bearing_deg' \(did you mean "
                                         r"'bearing'\?\), 'rim_height' \(did you mean 'height'\?\), 'notes'; a manifest's "
                                         r"columns are file, distance, throw, start, end, subject, bearing, height: "
                                         r"rename or drop them$"):
        read_manifest(path)
    # a measured outcome: rlff estimates the landing
    path.write_text("file,throw,distance,Hit,landing\nline1.bag,1,2.0,1,2.05\n")
    with pytest.raises(InputError, match=r"manifest .*manifest.csv: columns 'hit', 'landing': rlff reads no measured "
                                         r"outcome from a manifest \(a throw's landing is estimated from the hand's "
                                         r"release.*\); drop them$"):
        read_manifest(path)
    path.write_text("file,throw,distance,hit\nline1.bag,1,2.0,1\n")
    with pytest.raises(InputError, match=r"column 'hit': rlff reads no measured outcome.*; drop it$"):
        read_manifest(path)
    # a separator ending the header (as spreadsheets write it) is no column
    path.write_text("file,throw,distance,bearing,height,\nline1.bag,1,2.0,30,1.0,\n")
    (row,) = read_manifest(path)
    assert (row.bearing, row.height) == (30.0, 1.0)


def test_a_manifest_throw_number_beyond_the_throws_found_is_an_error(tmp_path):
    frames, time, _ = th.session(7)
    recording = th.write_kinect_text(tmp_path / "session.txt", frames, np.rint(time * 30).astype(int))
    manifest = tmp_path / "manifest.csv"
    manifest.write_text("file,throw,distance\nsession.txt,1,2.0\nsession.txt,9,3.0\n")
    with pytest.raises(InputError, match=r"manifest .*, line 3: throw 9 of session.txt does not exist \(5 throws found there\)"):
        import_recordings([recording], "kinect-text", manifest=manifest)
    manifest.write_text("file,throw,distance\nsession.txt,1,2.0\nsession.txt,5,3.0\n")
    dataset, report = import_recordings([recording], "kinect-text", manifest=manifest)
    # throws 2-4, which no row names, are left out: never labelled by the estimate beside the manifest's
    assert [t.meta.get("target") for t in dataset] == [2.0, 3.0] and report.estimated_distances == 0
    assert [r.reason.startswith("no row of manifest") for r in report.files[0].rejected if r.rule == "manifest"] == [True] * 3
    (warning,) = [w for w in report.warnings if "does not name every throw" in w]
    assert "throws 2, 3 and 4 (t=" in warning and "were left out: no row names them" in warning


def test_more_throws_found_than_a_manifest_lists_are_named_file_by_file_never_labelled_by_an_estimate(tmp_path):
    # a subject who pumps before a throw: the import finds 5 throws where the manifest lists 2, and
    # throws 3-5 got estimated baskets beside the manifest's, with one warning naming no file
    frames, time, _ = th.session(7)
    recording = th.write_kinect_text(tmp_path / "pumps.txt", frames, np.rint(time * 30).astype(int))
    manifest = tmp_path / "baskets.csv"
    manifest.write_text("file,throw,distance\npumps.txt,1,2.0\npumps.txt,2,2.5\n")
    dataset, report = import_recordings([recording], "kinect-text", manifest=manifest)
    assert [t.meta["distance_source"] for t in dataset] == ["manifest", "manifest"] and report.estimated_distances == 0
    starts = [f"{t.meta['start_time']:.2f}" for t in dataset]
    left_out = [r for r in report.files[0].rejected if r.rule == "manifest"]
    assert len(left_out) == 3
    assert left_out[0].reason == "no row of manifest " + str(manifest) + " names it (its rows for pumps.txt list " \
        "throws 1 and 2); its basket is not known"
    (warning,) = [w for w in report.warnings if "throws found" in w]
    assert warning.startswith(f"{recording}: 5 throws found, where manifest {manifest} lists 2 (throws 1 and 2, "
                              f"lines 2, 3): throws 1 and 2 (t={', '.join(starts)} s) took its rows' baskets by number; "
                              "throws 3, 4 and 5 (t=")
    assert "were left out: no row names them; if the file holds 2 throws, the cut found more" in warning
    assert "name its throws by time in the manifest (start and end columns)" in warning


def test_a_bag_arm_with_a_frame_missing_is_left_out_with_a_note(tmp_path):
    import bagfactory as bf
    from rlff.capture.bag import read_bag

    class WithoutLeftHand(bf.Simulation):
        def frames(self):
            for t, users in super().frames():
                users["1"].pop("left_hand", None)
                yield t, users

    base = bf.standard_simulation(seed=4, n_throws=1, second_user=False)
    simulation = WithoutLeftHand(base.throws, base.starts, base.duration, seed=4, second_user=False)
    recording = read_bag(bf.write_ros1_bag(tmp_path / "one_arm.bag", simulation, compression=None))
    assert [arm.side for arm in recording.arms] == ["right"]
    assert any("user 1, left arm left out: no frame left_hand_1" in note for note in recording.notes)
