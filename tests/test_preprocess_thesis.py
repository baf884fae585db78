"""The thesis preset end to end: simulated demonstrations with injected faults, and real recordings."""

from __future__ import annotations

import numpy as np
import pytest

from rlff.dataset import Dataset
from rlff.preprocess import Pipeline
from rlff.synthetic.throws import THESIS_DISTANCES, simulate_throws


@pytest.fixture(scope="module")
def faulty():
    """Thesis recording plan with many glitches and 2.75 m thrown too slowly, and its cleaning."""
    raw = simulate_throws(11, subjects=6, glitches=0.02, inconsistent_distance=2.75)
    cleaned, report = Pipeline.preset("thesis").run(raw)
    return raw, cleaned, report


def _step(report, name):
    (step,) = [s for s in report.steps if s.step == name]
    return step


def test_thesis_preset_removes_the_glitches_and_says_so(faulty):
    raw, cleaned, report = faulty
    glitch_samples = sum(int(np.count_nonzero(t["angle"] < 0.3)) for t in raw)
    assert sum(t.meta["glitches"] for t in raw) > 50
    spikes = _step(report, "spike_filter")
    assert sum(change.removed for change in spikes.samples) == glitch_samples
    assert all(t.meta["glitches"] > 0 for t in raw if t.id in {c.trajectory for c in spikes.samples})
    assert all(np.count_nonzero(t["angle"] < 0.3) == 0 for t in spikes.after)
    assert min(t["angle"].min() for t in cleaned) > 0.5


def test_thesis_preset_rejects_the_inconsistent_distance_and_only_it(faulty):
    raw, cleaned, report = faulty
    (rejection,) = _step(report, "reject_contexts").contexts
    assert rejection.context == {"distance": 2.75}
    assert "breaks the increasing trend of velocity with distance" in rejection.reason
    assert cleaned.contexts == tuple((d,) for d in THESIS_DISTANCES if d != 2.75)
    # ten throws per basket at most, none invented
    assert all(len(group) <= 10 for group in cleaned.by_context().values())
    assert set(cleaned.ids) <= set(raw.ids)


def test_estimated_release_is_near_the_true_release(faulty):
    raw, _, _ = faulty
    steps = [s for s in Pipeline.preset("thesis").steps if s.name not in ("rescale", "reject_shapes", "reject_contexts")]
    cut, _ = Pipeline(steps).run(raw)
    error = np.array([t.meta["cut_angle"] - t.meta["release_angle"] for t in cut])
    assert abs(np.median(error)) < 0.15
    assert np.median(np.abs(error)) < 0.35


def _fit(dataset: Dataset):
    from rlff.model import Model

    return Model.fit(dataset, inputs=("angle", "distance"), outputs=("velocity",), components=3, seed=0)


def _gmr_levels(model, distances: np.ndarray, angles: np.ndarray) -> np.ndarray:
    """Mean GMR velocity over ``angles`` at each distance (rad/s)."""
    return np.array([
        model.condition(np.column_stack([angles, np.full(angles.size, d)])).mean[:, 0].mean() for d in distances
    ])


@pytest.mark.slow
def test_gmm_velocity_grows_with_distance_after_cleaning_not_before(faulty):
    raw, cleaned, _ = faulty
    angles = np.linspace(np.median([t["angle"][0] for t in cleaned]), np.median([t["angle"][-1] for t in cleaned]), 20)
    distances = np.array([1.5, 2.0, 2.5, 3.0, 3.5])
    model = _fit(cleaned)
    after = _gmr_levels(model, distances, angles)
    before = _gmr_levels(_fit(raw), distances, angles)
    assert np.all(np.diff(after) > 0.2), after
    # on the raw recordings the model learns rest and wind-up, not the throw: no usable trend
    assert np.ptp(after) > 5 * np.ptp(before), (after, before)
    assert after.min() > 3 * max(before.max(), 0.1)
    # the generated (DMM) throws after cleaning grow with the distance too
    generated = [np.mean(model.generate({"distance": d}, angles).velocity) for d in distances]
    assert np.all(np.diff(generated) > 0), generated


@pytest.mark.realdata
def test_real_msr_recordings_go_through_the_thesis_preset(msr_dir):
    capture = pytest.importorskip("rlff.capture")
    dataset, _ = capture.import_recordings(sorted(msr_dir.glob("a06_*_skeleton3D.txt")), "msr")
    cleaned, report = Pipeline.preset("thesis").run(dataset)
    assert len(cleaned) >= 15
    assert set(cleaned.ids) <= set(dataset.ids)
    assert all(np.all(np.diff(t["angle"]) > 0) for t in cleaned)
    # every throw has its own estimated distance: no basket is judged on a single throw
    assert _step(report, "reject_contexts").contexts == []
    assert "not judged" in _step(report, "reject_contexts").notes[0]
    binned = Pipeline([(s.name, {**s.params, "bin_width": 0.5} if s.name == "reject_contexts" else s.params)
                       for s in Pipeline.preset("thesis").steps if s.enabled])
    rebinned, _ = binned.run(dataset)
    assert 0 < len(rebinned) <= len(cleaned)
