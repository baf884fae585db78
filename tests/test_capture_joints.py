"""Whole-arm capture: the shoulder's elevation against the torso and the wrist's angle beside the
elbow's, on the elbow's samples, with their velocities, in every format; the one-joint import."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

sys.path.insert(0, str(Path(__file__).parent))
import bagfactory as bf  # noqa: E402
from rlff.capture import import_recordings  # noqa: E402
from rlff.capture.angles import align_arm, elevation  # noqa: E402
from rlff.capture.skeleton_text import read_joint_csv, read_kinect_text, read_msr_text  # noqa: E402
from rlff.errors import InputError  # noqa: E402

#: A person leaning forward by this much (rad): the torso's axis is not the vertical.
LEAN = 0.25
#: Camera frame of the text formats: y up; the person throws towards the camera (-z), x sideways.
UP, FORWARD, SIDE = np.array([0.0, 1.0, 0.0]), np.array([0.0, 0.0, -1.0]), np.array([1.0, 0.0, 0.0])


def _known_arm(t: np.ndarray) -> dict[str, np.ndarray]:
    """Joint angles (rad) of a slow, smooth arm motion: shoulder, elbow, wrist, and their rates."""
    return {
        "shoulder": 1.5 + 0.5 * np.sin(1.2 * t), "shoulder_velocity": 0.6 * np.cos(1.2 * t),
        "angle": 1.8 + 0.8 * np.sin(0.9 * t + 0.3), "velocity": 0.72 * np.cos(0.9 * t + 0.3),
        "wrist": 2.7 + 0.3 * np.sin(1.5 * t), "wrist_velocity": 0.45 * np.cos(1.5 * t),
    }


def _msr_frames(t: np.ndarray, torso: bool = True) -> np.ndarray:
    """MSR frames of shape (T, 20, 3) of a leaning person whose right arm (arm B) makes
    :func:`_known_arm`, in the plane of the torso's axis and the forward direction."""
    angles = _known_arm(t)
    down = -(np.cos(LEAN) * UP + np.sin(LEAN) * FORWARD)
    ahead = np.cos(LEAN) * FORWARD - np.sin(LEAN) * UP  # perpendicular to the torso, forwards

    def direction(phi: np.ndarray) -> np.ndarray:
        """Unit vectors at ``phi`` from the torso's downward axis towards the front, shape (T, 3)."""
        return np.cos(phi)[:, None] * down + np.sin(phi)[:, None] * ahead

    upper = angles["shoulder"]
    forearm = upper + np.pi - angles["angle"]
    hand = forearm + np.pi - angles["wrist"]
    hip = np.array([0.2, -0.3, 3.0]) + 0.02 * np.sin(t)[:, None] * SIDE
    neck = hip - 0.5 * down
    frames = np.tile(neck[:, None, :], (1, 20, 1)) + 0.01 * np.arange(20)[None, :, None] * UP
    shoulder = neck + 0.18 * SIDE
    elbow = shoulder + 0.30 * direction(upper)
    wrist = elbow + 0.25 * direction(forearm)
    frames[:, 1], frames[:, 8], frames[:, 10], frames[:, 12] = shoulder, elbow, wrist, wrist + 0.08 * direction(hand)
    left = neck - 0.18 * SIDE  # arm A hangs along the torso
    frames[:, 0], frames[:, 7], frames[:, 9], frames[:, 11] = left, left + 0.3 * down, left + 0.55 * down, left + 0.63 * down
    frames[:, 2], frames[:, 6] = (neck, hip) if torso else (neck, neck)
    return frames


def _write_msr(path: Path, frames: np.ndarray) -> Path:
    lines = [f"{x:.7f} {y:.7f} {z:.7f} 1" for frame in frames for x, y, z in frame]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_elevation_exact_cases():
    shoulder = np.zeros((5, 3))
    down = np.array([0.0, 0.0, -1.0])
    elbow = np.array([[0, 0, -1], [1, 0, 0], [0, 0, 2], [1, 0, 1], [0, -1, -1]], dtype=float)
    np.testing.assert_allclose(elevation(shoulder, elbow, down), [0.0, np.pi / 2, np.pi, 3 * np.pi / 4, np.pi / 4], atol=1e-12)
    # against a torso leaning forward by 0.3 rad, an arm straight down is raised by 0.3 rad
    lean = np.array([np.sin(-0.3), 0.0, -np.cos(0.3)])
    assert elevation(shoulder[:1], elbow[:1], lean)[0] == pytest.approx(0.3)


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 10_000))
def test_elevation_does_not_depend_on_the_frame_and_up_is_its_supplement(seed):
    rng = np.random.default_rng(seed)
    shoulder, elbow, down = rng.normal(size=(3, 6, 3))
    rotation, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    shift = rng.normal(size=3)
    moved = [p @ rotation.T + shift for p in (shoulder, elbow)]
    expected = elevation(shoulder, elbow, down)
    np.testing.assert_allclose(elevation(*moved, down @ rotation.T), expected, atol=1e-9)
    np.testing.assert_allclose(elevation(shoulder, elbow, -down), np.pi - expected, atol=1e-9)


def test_msr_text_of_a_known_arm_gives_its_shoulder_wrist_and_their_velocities(tmp_path):
    t = np.arange(60) / 15.0
    recording = read_msr_text(_write_msr(tmp_path / "known_skeleton3D.txt", _msr_frames(t)))
    motion = align_arm(recording.arm("1", "right"), up=recording.up)
    truth = _known_arm(motion.time)
    assert motion.torso == "neck -> hip centre"
    assert set(motion.joints) == {"shoulder", "wrist"} and not any(motion.joint_glitches.values())
    for name in ("angle", "shoulder", "wrist"):
        got = motion.angle if name == "angle" else motion.joints[name]
        np.testing.assert_allclose(got, truth[name], atol=1e-5, err_msg=name)
    # one local fit for all joints (15 Hz: quadratic over 0.27 s); exact up to its curvature error
    np.testing.assert_allclose(motion.velocity, truth["velocity"], atol=0.02)
    for name in ("shoulder", "wrist"):
        np.testing.assert_allclose(motion.joint_velocities[name], truth[f"{name}_velocity"], atol=0.02, err_msg=name)


def test_without_torso_points_the_vertical_stands_in_and_the_import_says_so(tmp_path):
    t = np.arange(60) / 15.0
    recording = read_msr_text(_write_msr(tmp_path / "no_torso_skeleton3D.txt", _msr_frames(t, torso=False)))
    motion = align_arm(recording.arm("1", "right"), up=recording.up)
    assert motion.torso == "vertical"
    # the leaning torso is not seen: the elevation is measured from the vertical, LEAN less
    np.testing.assert_allclose(motion.joints["shoulder"], _known_arm(motion.time)["shoulder"] - LEAN, atol=1e-5)


def test_kinect_text_takes_the_torso_from_the_shoulder_centre_and_hip_centre(tmp_path):
    t = np.arange(90) / 30.0
    msr = _msr_frames(t)
    kinect = np.zeros_like(msr)
    for ours, theirs in {0: 6, 2: 2, 4: 0, 5: 7, 6: 9, 7: 11, 8: 1, 9: 8, 10: 10, 11: 12}.items():
        kinect[:, ours] = msr[:, theirs]
    lines = [" ".join([str(k), *(f"{v:.7f}" for v in frame.ravel())]) for k, frame in enumerate(kinect)]
    path = tmp_path / "kinect.txt"
    path.write_text("\n".join(lines) + "\n")
    (right,) = [arm for arm in read_kinect_text(path).arms if arm.side == "right"]
    motion = align_arm(right, up=UP)
    assert motion.torso == "neck -> hip centre"
    truth = _known_arm(motion.time)
    np.testing.assert_allclose(motion.joints["shoulder"], truth["shoulder"], atol=1e-5)
    np.testing.assert_allclose(motion.joints["wrist"], truth["wrist"], atol=1e-5)


def _throws_csv(path: Path, lean: float | None, bend: float = 0.3) -> Path:
    """The bag factory's throws as a CSV of joint positions (z up), with a wrist bent by ``bend``
    (rad) and, unless ``lean`` is None, a torso (neck, hip) leaning forward by ``lean``."""
    import pandas as pd

    simulation = bf.standard_simulation(seed=4, n_throws=2, noise=0.0, second_user=False)
    t = simulation.frame_times
    shoulder, elbow, fore_end = simulation.arm_positions(simulation.angle(t))
    wrist = fore_end
    along = (wrist - elbow) / np.linalg.norm(wrist - elbow, axis=1, keepdims=True)
    across = np.cross(np.cross(along, bf.UP), along)
    across /= np.linalg.norm(across, axis=1, keepdims=True)
    hand = wrist + 0.08 * (np.cos(bend) * along + np.sin(bend) * across)
    columns = {"time": t}
    points = {"right_shoulder": shoulder, "right_elbow": elbow, "right_wrist": wrist, "right_hand": hand}
    if lean is not None:
        neck = shoulder + np.array([0.0, 0.18, 0.05])
        points.update(neck=neck, hip=neck - 0.55 * (np.cos(lean) * bf.UP + np.sin(lean) * bf.FORWARD))
    for name, values in points.items():
        columns.update({f"{name}_{axis}": values[:, k] for k, axis in enumerate("xyz")})
    pd.DataFrame(columns).to_csv(path, index=False)
    return path


def test_csv_import_writes_every_joint_on_the_elbows_samples(tmp_path):
    # the factory's upper arm points 20 degrees from straight up, forwards; the torso leans 5
    path = _throws_csv(tmp_path / "throws.csv", lean=np.radians(5))
    dataset, report = import_recordings([path], "csv")
    assert len(dataset) == 2
    assert dataset.columns == (
        "time", "angle", "velocity", "shoulder", "shoulder_velocity", "wrist", "wrist_velocity", "distance"
    )
    for trajectory in dataset:
        np.testing.assert_allclose(trajectory["shoulder"], np.radians(165), atol=1e-6)
        np.testing.assert_allclose(trajectory["shoulder_velocity"], 0.0, atol=1e-6)
        np.testing.assert_allclose(trajectory["wrist"], np.pi - 0.3, atol=1e-6)
    assert not any("no torso points" in note for note in report.notes)
    # the one-joint dataset: the same throws and samples, the elbow alone
    elbow, _ = import_recordings([path], "csv", joints=("elbow",))
    assert elbow.columns == ("time", "angle", "velocity", "distance")
    for alone, whole in zip(elbow, dataset, strict=True):
        assert alone.meta == whole.meta
        for name in alone.columns:
            np.testing.assert_array_equal(alone[name], whole[name])
    # one joint's name alone is that joint (it was read letter by letter: "joint 'e'")
    assert import_recordings([path], "csv", joints="elbow")[0].equals(elbow)


def test_a_csv_without_time_stamps_read_at_a_wrong_rate_is_warned_of(tmp_path):
    # a mocap export's time column left out of --columns: its frames were taken as 30 Hz and the
    # throws came out four times too slow with only the generic "no time column" warning
    import pandas as pd

    timed = _throws_csv(tmp_path / "timed.csv", lean=0.0)  # recorded at 30 Hz
    frames = tmp_path / "frames.csv"
    pd.read_csv(timed).drop(columns="time").to_csv(frames, index=False)
    _, right = import_recordings([frames], "csv")  # 30 Hz assumed, and so it was
    assert not any("rate they were recorded at" in warning for warning in right.warnings)
    _, slow = import_recordings([frames], "csv", rate_hz=7.5)
    (warning,) = [warning for warning in slow.warnings if "rate they were recorded at" in warning]
    assert "slower than a throw" in warning and "were read at --rate 7.5 Hz" in warning
    # time stamps give the rate: a --rate is ignored, and nothing is said of it
    _, stamped = import_recordings([timed], "csv", rate_hz=7.5)
    assert not any("rate they were recorded at" in warning for warning in stamped.warnings)


def test_a_csv_without_torso_columns_measures_against_the_vertical_with_a_note(tmp_path):
    path = _throws_csv(tmp_path / "throws.csv", lean=None)
    dataset, report = import_recordings([path], "csv", joints=("shoulder", "elbow"))
    assert "wrist" not in dataset.columns
    np.testing.assert_allclose(dataset[0]["shoulder"], np.radians(160), atol=1e-6)
    assert any("no torso points (neck and hip centre)" in note for note in report.notes)


def test_a_torso_glitch_is_bridged_in_the_shoulder_and_leaves_the_elbow_alone(tmp_path):
    frames_path = _throws_csv(tmp_path / "throws.csv", lean=0.0)
    clean = align_arm(read_joint_csv(frames_path).arms[0])
    import pandas as pd

    table = pd.read_csv(frames_path)
    spikes = [40, 95, 150]
    table.loc[spikes, "hip_y"] += 0.4  # the hip jumps sideways for one frame, three times
    table.to_csv(frames_path, index=False)
    motion = align_arm(read_joint_csv(frames_path).arms[0])
    assert motion.joint_glitches["shoulder"] == len(spikes) and not motion.glitches.size
    np.testing.assert_array_equal(motion.angle, clean.angle)
    np.testing.assert_allclose(motion.joints["shoulder"], clean.joints["shoulder"], atol=1e-9)
    _, report = import_recordings([frames_path], "csv")
    assert any("3 glitch samples of the shoulder angle bridged" in note for note in report.notes)


def test_joints_asked_for_that_a_format_lacks_are_errors_and_mixed_files_keep_the_common_ones(tmp_path):
    bag = bf.write_ros1_bag(tmp_path / "nite.bag", bf.standard_simulation(seed=3, n_throws=1))
    with pytest.raises(InputError, match=r"nite\.bag: no wrist angle \(the format has no hand point beside the wrist\)"):
        import_recordings([bag], "bag", joints=("shoulder", "elbow", "wrist"))
    with pytest.raises(InputError, match="joint 'knee': not one of shoulder, elbow, wrist"):
        import_recordings([bag], "bag", joints=("knee", "elbow"))
    with pytest.raises(InputError, match="the elbow must be one"):
        import_recordings([bag], "bag", joints=("shoulder",))
    csv = _throws_csv(tmp_path / "throws.csv", lean=0.0)
    dataset, report = import_recordings([bag, csv])
    assert dataset.columns == ("time", "angle", "velocity", "shoulder", "shoulder_velocity", "distance")
    assert any("wrist left out: not every recording carries it" in note for note in report.notes)
    assert report.joints == ["angle", "shoulder"] and report.to_dict()["notes"] == report.general
    # the bag's torso: NiTE's neck and the middle of its hips (upright), the upper arm 20 degrees
    # from straight up, with the factory's tracker noise
    from_bag = [t for t in dataset if t.meta["source"] == str(bag)]
    assert from_bag and not any("no torso points" in note for note in report.files[0].notes)
    for trajectory in from_bag:
        assert np.median(np.abs(trajectory["shoulder"] - np.radians(160))) < 0.03


@pytest.mark.realdata
def test_real_high_throws_raise_the_arm_in_the_wind_up_and_release_above_the_horizontal(msr_dir):
    files = sorted(msr_dir.glob("a06_*_skeleton3D.txt"))
    dataset, report = import_recordings(files, "msr")
    assert dataset.columns == (
        "time", "angle", "velocity", "shoulder", "shoulder_velocity", "wrist", "wrist_velocity", "distance"
    )
    assert not any("no torso points" in note for note in report.notes)
    above, rising = 0, 0
    for trajectory in dataset:
        time, shoulder = trajectory["time"], trajectory["shoulder"]
        assert np.all((shoulder >= 0.0) & (shoulder <= np.pi))
        assert np.all((trajectory["wrist"] > 1.5) & (trajectory["wrist"] <= np.pi))
        release = np.interp(trajectory.meta["release_time"], time, shoulder)
        above += release > np.pi / 2
        # the wind-up: from the arm low at the throw's start to its highest by the release
        rising += shoulder[0] < 1.2 and release - shoulder[0] > 1.0
        assert release > 1.6, trajectory.id  # at least about horizontal at release
    assert above == len(dataset) == len(files)
    assert rising >= 0.75 * len(dataset)


def test_a_manifest_gives_the_baskets_bearing_and_height(tmp_path):
    path = _throws_csv(tmp_path / "throws.csv", lean=0.0)
    manifest = tmp_path / "baskets.csv"
    manifest.write_text("file,throw,distance,bearing,height\nthrows.csv,1,2.0,30,1.0\nthrows.csv,2,2.5,,\n")
    dataset, report = import_recordings([path], "csv", manifest=manifest)
    assert dataset.context == ("distance", "bearing", "height")
    first, second = dataset
    assert (first["bearing"][0], first["height"][0]) == (30.0, 1.0)
    assert (second["bearing"][0], second["height"][0]) == (0.0, 0.3)  # the default basket
    assert any("1 throws without a manifest bearing stand for the default basket's (0)" in n for n in report.notes)
    # the first throw's landing is where it crosses its 1 m rim: nearer than the floor
    plain_manifest = tmp_path / "plain.csv"
    plain_manifest.write_text("file,throw,distance\nthrows.csv,1,2.0\nthrows.csv,2,2.5\n")
    plain, _ = import_recordings([path], "csv", manifest=plain_manifest)
    assert plain.context == ("distance",)
    assert first.meta["landing"] < plain[0].meta["landing"]
    assert second.meta["landing"] == plain[1].meta["landing"]
    manifest.write_text("file,throw,distance,bearing\nthrows.csv,1,2.0,200\n")
    with pytest.raises(InputError, match=r"baskets\.csv, line 2: column 'bearing' 200: out of range -180 to 180 deg"):
        import_recordings([path], "csv", manifest=manifest)
