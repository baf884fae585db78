"""Two people in view, both tracked all the time: the one whose arm moves is the thrower."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))
import bagfactory as bf  # noqa: E402
from rlff.capture.importer import import_recordings  # noqa: E402
from rlff.errors import InputError  # noqa: E402


class _Bystander(bf.Simulation):
    """The thrower as user 1 (with dropped frames), a reflection as user 2 when asked for, and a
    person standing still as user 3 in every frame."""

    def frames(self):
        rng = np.random.default_rng(99)
        shoulder = bf.SHOULDER + np.array([0.3, 1.2, 0.0])
        elbow, hand = shoulder + np.array([0.0, 0.0, -0.3]), shoulder + np.array([0.05, 0.0, -0.58])
        for t, users in super().frames():
            still = {name: p + rng.normal(0.0, 0.002, 3) for name, p in bf._body(shoulder, elbow, hand).items()}
            yield t, {**users, "3": still}


def _import(tmp_path: Path, reflection: bool):
    simulation = bf.standard_simulation(seed=3, n_throws=3)
    session = _Bystander(simulation.throws, simulation.starts, simulation.duration, seed=3, second_user=reflection)
    dataset, report = import_recordings([bf.write_ros1_bag(tmp_path / "two_people.bag", session)], "bag")
    (file,) = report.files
    return dataset, file


def test_a_bystander_tracked_longer_than_the_thrower_is_dropped_and_the_throws_kept(tmp_path):
    dataset, file = _import(tmp_path, reflection=False)
    assert file.user == "1" and file.arm == "right"
    assert len(dataset) == 3
    (note,) = [note for note in file.notes if "tracked user" in note]
    assert "dropped tracked user 3 (tracked about as steadily as user 1, but its hand sweeps 0.0" in note
    assert "not the thrower" in note and "kept user 1" in note


def test_a_reflection_is_dropped_by_its_score_even_though_its_hand_sweeps_furthest(tmp_path):
    dataset, file = _import(tmp_path, reflection=True)
    assert file.user == "1" and len(dataset) == 3
    reflection, bystander = sorted(note for note in file.notes if "tracked user" in note)
    assert "dropped tracked user 2 (second skeleton, e.g. a reflection)" in reflection
    assert "dropped tracked user 3 (tracked about as steadily as user 1" in bystander


class _TwoThrowers(bf.Simulation):
    """The thrower as user 1, and as user 2 a second person 1.2 m to its side, a little smaller,
    throwing the same throws 0.3 s later (two people taking turns, or a pair in a drill)."""

    delay = 0.3

    def frames(self):
        shoulder, elbow, hand = self.arm_positions(self.angle(np.maximum(self.frame_times - self.delay, 0.0)))
        side = np.array([0.0, 1.2, 0.0])
        for t, users in super().frames():
            k = int(np.argmin(np.abs(self.frame_times - t)))
            root = shoulder[k] + side
            yield t, {**users, "2": bf._body(root, root + 0.85 * (elbow[k] - shoulder[k]),
                                             root + 0.85 * (hand[k] - shoulder[k]))}


def test_a_second_person_who_throws_too_is_warned_of_and_imported_with_user(tmp_path):
    simulation = bf.standard_simulation(seed=3, n_throws=3)
    session = _TwoThrowers(simulation.throws, simulation.starts, simulation.duration, seed=3, second_user=False)
    path = bf.write_ros1_bag(tmp_path / "pair.bag", session)
    first, report = import_recordings([path], "bag")
    (file,) = report.files
    assert file.user == "1" and len(first) == 3
    (warning,) = [w for w in file.warnings if "tracked user 2" in w]
    assert "its hand swept as a throwing hand does: if user 2 threw too, its throws are not imported" in warning
    assert warning.endswith("import them with --user 2") and "not the thrower" not in warning
    second, report = import_recordings([path], "bag", user="2")
    (file,) = report.files
    assert file.user == "2" and len(second) == 3
    assert any("kept tracked user 2 (--user), left out user 1" in note for note in file.notes)
    np.testing.assert_allclose([t.meta["start_time"] for t in second],
                               [t.meta["start_time"] + session.delay for t in first], atol=0.07)
    with pytest.raises(InputError, match=r"pair\.bag: no tracked user 3 \(--user; its users: 1, 2\)"):
        import_recordings([path], "bag", user="3")


def test_a_recording_imported_once_per_user_gives_throws_that_merge(tmp_path):
    # the docs say to import a pair's recording once per thrower: both imports named their throws
    # pair_t1..., subject pair, and merging them was refused as two throws under one id
    from rlff.dataset import merge_datasets

    simulation = bf.standard_simulation(seed=3, n_throws=3)
    session = _TwoThrowers(simulation.throws, simulation.starts, simulation.duration, seed=3, second_user=False)
    path = bf.write_ros1_bag(tmp_path / "pair.bag", session)
    first, _ = import_recordings([path], "bag", user="1")
    second, _ = import_recordings([path], "bag", user="2")
    assert [t.id for t in first] == ["pair_u1_t1", "pair_u1_t2", "pair_u1_t3"]
    assert [t.id for t in second] == ["pair_u2_t1", "pair_u2_t2", "pair_u2_t3"]
    assert {t.meta["subject"] for t in first} == {"pair_u1"} and {t.meta["subject"] for t in second} == {"pair_u2"}
    merged = merge_datasets([("u1.csv", first), ("u2.csv", second)])
    assert len(merged.dataset) == 6 and merged.kept_once == []
    # without --user, the ids and subject are the file's, as before
    default, _ = import_recordings([path], "bag")
    assert [t.id for t in default] == ["pair_t1", "pair_t2", "pair_t3"]
    assert {t.meta["subject"] for t in default} == {"pair"}
