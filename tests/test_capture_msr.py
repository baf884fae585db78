"""The real MSR Action3D throws: one throw per high-throw file, in a plausible human range; and the
rounding of their estimated landing distances to baskets."""

from __future__ import annotations

import numpy as np
import pytest

from rlff.capture import import_recordings
from rlff.capture.label import LandingSettings, basket_from_landing
from rlff.capture.skeleton_text import read_msr_text


@pytest.fixture(scope="module")
def imported():
    """All recordings imported once (conftest's ``msr_dir`` is per test; this skips the same way)."""
    from conftest import MSR_THROWS

    if not MSR_THROWS.is_dir():
        pytest.skip(f"{MSR_THROWS} is absent")
    return import_recordings(sorted(MSR_THROWS.glob("*_skeleton3D.txt")), "msr")


def test_a_landing_estimate_is_rounded_to_the_nearest_basket():
    settings = LandingSettings()
    assert basket_from_landing(1.62, settings) == (1.5, "landing estimate, rounded to 0.25 m")
    assert basket_from_landing(1.63, settings)[0] == 1.75
    assert basket_from_landing(2.374, settings)[0] == 2.25
    assert basket_from_landing(1.63, LandingSettings(distance_step=0.1)) == (1.6, "landing estimate, rounded to 0.1 m")
    assert basket_from_landing(0.7, LandingSettings(distance_step=0.1))[0] == 0.7  # not 0.7000000000000001
    assert basket_from_landing(1.63, LandingSettings(distance_step=0.0)) == (1.63, "landing estimate")
    assert np.isnan(basket_from_landing(np.nan, settings)[0])
    # within the range of baskets (0.3-20 m), never rounded out of it: 0.25 m holds no basket
    assert basket_from_landing(0.3, settings)[0] == 0.5 and basket_from_landing(0.37, settings)[0] == 0.5
    assert basket_from_landing(0.29, settings)[0] == 0.25  # nearer than any basket: the import leaves it out
    assert basket_from_landing(19.99, LandingSettings(distance_step=0.3))[0] == 19.8  # not 20.1
    assert basket_from_landing(0.3, LandingSettings(distance_step=0.1))[0] == 0.3


@pytest.mark.realdata
def test_one_throw_per_high_throw_file_in_a_human_range(imported):
    dataset, report = imported
    high_throws = [f for f in report.files if "a06_" in f.source]
    assert len(high_throws) == 26
    for file_report in high_throws:
        assert len(file_report.throws) == 1, file_report.source
        assert file_report.arm == "right"  # arm B, the throwing arm of every a06 file
        (throw,) = file_report.throws
        low, high = throw.angle_range
        assert 0.3 < low < 2.2 and 2.6 < high <= np.pi  # wound up, then nearly straight
        assert 3.0 < throw.peak_velocity < 30.0  # rad/s: an elbow extension in 0.1-0.6 s
        assert 0.3 < throw.end - throw.start < 3.0
        assert throw.start <= throw.release <= throw.end
        assert throw.distance_source == "landing estimate, rounded to 0.25 m" and 0.5 < throw.landing < 5.0
        assert abs(throw.distance - throw.landing) <= 0.125 and (throw.distance / 0.25).is_integer()
    by_id = {t.id: t for t in dataset}
    for file_report in high_throws:
        trajectory = by_id[file_report.throws[0].id]
        assert trajectory.meta["subject"].startswith("s") and "target" not in trajectory.meta
        assert np.all(trajectory["distance"] == file_report.throws[0].distance)
        assert trajectory.meta["landing"] == file_report.throws[0].landing
        assert trajectory["time"][0] == 0.0 and np.allclose(np.diff(trajectory["time"]), 1 / 15)
        assert trajectory["velocity"].max() > 3.0


@pytest.mark.realdata
def test_a_throw_starts_where_its_wind_up_starts(imported):
    """The elbow falls into the wind-up before it extends. A blip of jitter in the hold at the
    bottom used to end the backward walk there, cutting off three wind-ups (``a06_s05_e02``
    started at 0.65 rad, 0.66 s after its angle began to fall from 2.62)."""
    dataset, _ = imported
    wind_ups = {}
    for trajectory in dataset:
        if "a06_" in trajectory.meta["source"]:
            angle = trajectory["angle"]
            lowest = int(np.argmin(angle))
            wind_ups[trajectory.id] = float(angle[: lowest + 1].max() - angle[lowest])
    assert len(wind_ups) == 26
    # one throw (a06_s08_e03) rises 0.3 rad out of its wind-up and falls again before extending:
    # the walk stops at that rise, a movement of its own
    assert sum(fall >= 0.45 for fall in wind_ups.values()) == 25, wind_ups
    assert wind_ups["a06_s05_e02_skeleton3D_t1"] > 1.9


@pytest.mark.realdata
def test_all_zero_frames_of_subject_02_are_dropped_and_reported(msr_dir):
    recording = read_msr_text(msr_dir / "a20_s02_e01_skeleton3D.txt")
    assert any("all arm joints at zero" in note for note in recording.notes)
    arm = recording.arm("1", "right")
    assert np.all(np.any(arm.elbow.position != 0, axis=1))


@pytest.mark.realdata
def test_the_import_runs_through_the_thesis_preprocessing(imported):
    preprocess = pytest.importorskip("rlff.preprocess")
    if not hasattr(preprocess, "Pipeline"):
        pytest.skip("rlff.preprocess.Pipeline is not built yet")
    dataset, _ = imported
    high_throws = dataset.replace(t for t in dataset if "a06_" in t.meta["source"])
    cleaned, report = preprocess.Pipeline.preset("thesis").run(high_throws)
    assert len(cleaned) > 0 and set(cleaned.columns) >= {"angle", "distance", "velocity"}
    # every throw survives the per-trajectory cleaning (the later steps compare baskets)
    (sparse,) = [step for step in report.steps if step.step == "min_points"]
    assert len(sparse.after) == 26


@pytest.mark.realdata
@pytest.mark.parametrize(("rate", "seen"), [(3.75, "slower than a throw"), (60.0, "shorter than a throw")])
def test_msr_files_read_at_a_wrong_rate_are_warned_of(imported, rate, seen):
    from conftest import MSR_THROWS

    _, at_15_hz = imported
    assert not any("rate they were recorded at" in warning for warning in at_15_hz.warnings)
    _, report = import_recordings(sorted(MSR_THROWS.glob("a06_*_skeleton3D.txt")), "msr", rate_hz=rate)
    (warning,) = [warning for warning in report.warnings if "rate they were recorded at" in warning]
    assert seen in warning and f"were read at --rate {rate:g} Hz" in warning


@pytest.mark.realdata
def test_a_second_throw_in_an_msr_file_is_warned_of_and_named_in_a_manifest_error(tmp_path):
    from conftest import MSR_THROWS
    from rlff.errors import InputError

    if not MSR_THROWS.is_dir():
        pytest.skip(f"{MSR_THROWS} is absent")
    two = tmp_path / "a06_s01_e98_skeleton3D.txt"  # two performances appended: a session
    two.write_text("".join((MSR_THROWS / f"a06_s01_e0{n}_skeleton3D.txt").read_text() for n in (1, 2)))
    dataset, report = import_recordings([two], "msr")
    assert len(dataset) == 1
    (warning,) = [w for w in report.warnings if "left out: an MSR file holds one throw" in w]
    assert warning.startswith(f"{two}: a throw at t=") and "into one file per throw" in warning
    # the kept throw keeps its number in the file: a row for the other never labels it
    (kept,) = dataset.ids
    number = int(kept.rsplit("_t", 1)[1])
    other = 3 - number
    manifest = tmp_path / "baskets.csv"
    manifest.write_text(f"file,throw,distance\n{two.name},{other},2.0\n")
    with pytest.raises(InputError, match=rf"throw {other} of a06_s01_e98_skeleton3D.txt was left out: one throw per "
                                         rf"MSR file \(the one with the fastest release, throw {number}, is kept\)"):
        import_recordings([two], "msr", manifest=manifest)
    manifest.write_text(f"file,throw,distance\n{two.name},{number},2.0\n")
    labelled, _ = import_recordings([two], "msr", manifest=manifest)
    assert labelled.ids == dataset.ids and float(labelled[0]["distance"][0]) == 2.0
    # a time span holding only the throw left out says so
    left = next(r.time for f in report.files for r in f.rejected if r.rule == "one throw per MSR file")
    manifest.write_text(f"file,start,end,distance\n{two.name},{left - 0.5:.2f},{left + 0.5:.2f},2.0\n")
    _, spanned = import_recordings([two], "msr", manifest=manifest)
    assert any(f"the throw at t={left:.2f} s was left out (one throw per MSR file)" in w for w in spanned.warnings)
    manifest.write_text(f"file,throw,distance\n{two.name},3,2.0\n")
    with pytest.raises(InputError, match=r"throw 3 of a06_s01_e98_skeleton3D.txt does not exist \(2 throws found there\)"):
        import_recordings([two], "msr", manifest=manifest)


@pytest.mark.realdata
def test_one_file_of_a_set_recorded_at_another_rate_is_named(tmp_path):
    """A set where one file was recorded at 60 Hz (four times the frames of the same motion), all
    read at MSR's 15 Hz: the set's medians look like throws, so the file is named on its own."""
    from conftest import MSR_THROWS

    if not MSR_THROWS.is_dir():
        pytest.skip(f"{MSR_THROWS} is absent")
    sources = sorted(MSR_THROWS.glob("a06_*_skeleton3D.txt"))[:6]
    for source in sources[1:]:
        (tmp_path / source.name).write_text(source.read_text())
    frames = np.loadtxt(sources[0]).reshape(-1, 20, 4)
    fine = np.linspace(0, len(frames) - 1, 4 * (len(frames) - 1) + 1)
    dense = np.stack([[np.interp(fine, np.arange(len(frames)), frames[:, j, c]) for c in range(4)]
                      for j in range(20)]).transpose(2, 0, 1)  # (T, 20, 4) at 60 Hz
    odd = tmp_path / sources[0].name
    odd.write_text("\n".join(" ".join(f"{v:.6f}" for v in row) for row in dense.reshape(-1, 4)) + "\n")
    _, report = import_recordings(sorted(tmp_path.glob("*.txt")), "msr")
    (warning,) = [w for w in report.warnings if "unlike a throw at the rate read" in w]
    assert warning.startswith("1 of 6 msr files hold throws unlike a throw") and odd.name in warning
    assert not any(source.name in warning for source in sources[1:])
