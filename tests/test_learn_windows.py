"""The window search of binary feedback: the lattice, the prior's masses, the order, and the
methods that use it against the real model and the real MuJoCo simulation."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import norm

from rlff.errors import InputError
from rlff.learn import learn
from rlff.learn.baselines import RANGE_ELASTICITY
from rlff.learn.windows import (
    MISREPORT,
    RETRIES,
    UNLIKE_PEOPLE,
    WindowSearch,
    lattice,
    window_masses,
    window_width,
    with_retries,
)


def test_the_window_is_the_hit_window_through_the_range_law():
    # 2 x 0.14 m at 1.75 m is 0.16 in log distance, over the elasticity 1.6: 0.1 in log speed
    assert window_width(1.75, 0.14) == pytest.approx(0.1)
    assert window_width(1.75, 0.14, elasticity=2.0) == pytest.approx(0.08)


def test_the_lattice_runs_in_the_sweeps_order_within_the_limits():
    np.testing.assert_allclose(lattice(0.1, 0.25, lowest=-0.35), [0, 0.1, -0.1, 0.2, -0.2, -0.3])
    # the GMR mean's own speed beyond the limit: the lattice starts at the first centre below it
    np.testing.assert_allclose(lattice(0.1, -0.15, lowest=-0.45), [-0.2, -0.3, -0.4])


def test_window_masses_are_the_prior_between_the_midpoints_the_ends_take_the_tails():
    x = np.linspace(-3.0, 3.0, 6001)
    centres = np.array([0.0, 0.1, -0.1])
    masses = window_masses(centres, x, norm.pdf(x, 0.0, 0.3))
    top = 1.0 - norm.cdf(0.05, 0.0, 0.3)  # everything above the midpoint to the top window
    np.testing.assert_allclose(masses, [norm.cdf(0.05, 0, 0.3) - norm.cdf(-0.05, 0, 0.3), top, top], atol=1e-6)
    assert masses.sum() == pytest.approx(1.0)


def test_the_fastest_window_comes_first_when_the_prior_says_the_basket_needs_more_than_the_robot():
    # limit 0.17 above the GMR mean's speed: the top window (0.1) holds P(x* > 0.05) under
    # N(0, 0.3), everything above its lower edge, and that beats any other window
    search = WindowSearch(1.75, 0.14, highest=0.17, floor=0.0)
    offsets = [search.offset(k)[0] for k in range(4)]
    np.testing.assert_allclose(offsets, [0.1, 0.0, -0.1, -0.2], atol=1e-9)
    first_mass = search.offset(0)[1]
    assert first_mass == pytest.approx(1.0 - norm.cdf(0.05, 0.0, 0.3), abs=1e-3)
    # far from the limit the GMR mean's own speed comes first, then the sweep's order
    free = WindowSearch(1.75, 0.14, highest=0.8, floor=0.0)
    np.testing.assert_allclose([free.offset(k)[0] for k in range(5)], [0, 0.1, -0.1, 0.2, -0.2], atol=1e-9)


def test_a_narrow_prior_below_the_limit_throws_its_own_centre_before_the_window_above():
    # a carried hit (N(0.007, 0.1)) 1.6 m away with the centred run's windows (0.068 wide): the
    # top window one step above the carry took the tail beyond the limit too (0.30 against the
    # carry's own 0.22) and went first wherever the limit lay in 0.08-0.12; that tail, 0.15, is
    # less than the carry's window holds, so it lifts the top window level with it, not above
    for highest in (0.05, 0.08, 0.1, 0.12, 0.15):
        search = WindowSearch(1.6, 0.0875, highest, None, scale=0.1, centre=0.007)
        assert search.offset(0)[0] == pytest.approx(0.007), highest
    lifted = WindowSearch(1.6, 0.0875, 0.1, None, scale=0.1, centre=0.007, floor=0.0)
    assert lifted.offset(1)[0] == pytest.approx(0.007 + lifted.width)  # next, with the carry's mass
    assert lifted.offset(1)[1] == pytest.approx(lifted.offset(0)[1])
    # the same with the prior given as a density on a grid
    gridded = WindowSearch(1.6, 0.0875, 0.1, lambda x: norm.logpdf(x, 0.007, 0.1), centre=0.007, floor=0.0)
    assert np.allclose(gridded.offsets, lifted.offsets)


def _first_pass(search: WindowSearch) -> np.ndarray:
    """The lattice's windows in the order of their first throw (retries left out)."""
    thrown = search.offsets[: search.masses.size]
    _, first_seen = np.unique(np.round(thrown, 9), return_index=True)
    return thrown[np.sort(first_seen)]


def test_after_the_lattice_come_the_half_shifted_windows_then_the_lattice_again():
    search = WindowSearch(1.75, 0.14, highest=0.5)
    width = search.width
    first = _first_pass(search)
    np.testing.assert_allclose(np.sort(first), np.sort(lattice(width, 0.5)))
    # the half-shifted windows: every centre + w/2 that stays within the limit, in the same order
    shifted = first[first + 0.5 * width <= 0.5 + 1e-12] + 0.5 * width
    passed = search.masses.size  # the lattice with its retries
    second = np.array([search.offset(passed + k)[0] for k in range(shifted.size)])
    np.testing.assert_allclose(second, shifted)
    assert search.offset(passed)[1] == 0.0  # past the first pass: no prior mass claimed
    assert search.offset(passed + shifted.size)[0] == first[0]  # then the lattice again
    assert search.offset(10_000)[0] == first[-1]  # past everything: the last window again


def test_a_likely_window_that_missed_is_thrown_again_before_the_unlikely_ones():
    # N(0, 0.3), w = 0.1: once the untried windows left hold less than MISREPORT of the GMR
    # mean's window, a miss there may have been a misreported hit
    search = WindowSearch(1.75, 0.14, highest=0.8, floor=0.0)
    thrown, masses = search.offsets[: search.masses.size], search.masses
    top = round(float(masses[0]), 4)
    again = [k for k in range(1, thrown.size) if np.any(np.isclose(thrown[:k], thrown[k]))]
    assert again, "no window thrown twice"
    retry = again[0]
    assert thrown[retry] == pytest.approx(0.0)  # the likeliest window comes round first
    assert np.all(np.round(masses[:retry], 4) >= MISREPORT * top)
    untried_after = [masses[k] for k in range(retry + 1, thrown.size)
                     if not np.any(np.isclose(thrown[:k], thrown[k]))]
    assert untried_after and max(untried_after) <= MISREPORT * top + 1e-4
    # every window is thrown in the first pass, none more than once again
    counts = [int(np.count_nonzero(np.isclose(thrown, x))) for x in lattice(search.width, search.highest)]
    assert min(counts) == 1 and max(counts) == 1 + RETRIES


def test_retries_follow_the_masses_and_stop_at_the_cap():
    first = np.array([0.0, 0.1, -0.1, 0.2])
    masses = np.array([0.4, 0.3, 0.2, 0.001])
    np.testing.assert_allclose(with_retries(first, masses, 0.0)[0], first)  # no misreports: no retries
    # 0.1: the 0.4 window (0.04 after its miss), the 0.3 (0.03) and the 0.2 (0.02) go again
    # before the 0.001 one; a second retry of the 0.4 window (0.004) would too, but the cap is 1
    offsets, thrown = with_retries(first, masses, 0.1, retries=1)
    np.testing.assert_allclose(offsets, [0.0, 0.1, -0.1, 0.0, 0.1, -0.1, 0.2])
    np.testing.assert_allclose(thrown, [0.4, 0.3, 0.2, 0.4, 0.3, 0.2, 0.001])
    np.testing.assert_allclose(with_retries(first, masses, 0.1, retries=2)[0],
                               [0.0, 0.1, -0.1, 0.0, 0.1, -0.1, 0.0, 0.1, -0.1, 0.2])


def test_the_second_pass_throws_at_the_limit_where_the_top_window_shifted_would_pass_it():
    # w = 0.1, limit 0.43: the top window 0.4 reaches to 0.45, so no band window; shifted by
    # w / 2 it would ask for 0.45, so the second pass throws the limit there, once
    search = WindowSearch(1.75, 0.14, highest=0.43)
    first = _first_pass(search)
    second = search.offsets[search.masses.size: search.masses.size + first.size]
    assert not np.any(np.isclose(first, 0.43))
    assert np.count_nonzero(np.isclose(second, 0.43)) == 1
    assert np.flatnonzero(np.isclose(second, 0.43))[0] == np.flatnonzero(np.isclose(first, 0.4))[0]
    assert second.max() == pytest.approx(0.43)


def test_a_prior_density_of_its_own_reorders_the_windows():
    # a ring at +-0.25 (two bumps): the windows near the bumps before the GMR mean's speed
    def ring(x):
        return np.logaddexp(norm.logpdf(x, 0.25, 0.05), norm.logpdf(x, -0.25, 0.05))

    search = WindowSearch(1.75, 0.14, highest=0.8, log_density=ring)
    first_two = sorted(search.offset(k)[0] for k in range(2))
    np.testing.assert_allclose(first_two, [-0.2, 0.2], atol=1e-9)  # 0.2 and 0.3 tie with 0.25: kept order
    assert search.offset(2)[0] != 0.0


def test_the_width_uses_the_baselines_elasticity():
    assert window_width(2.0, 0.1) == pytest.approx(0.2 / (RANGE_ELASTICITY * 2.0))


@pytest.fixture(scope="module")
def short_demos():
    from rlff.learn.scenarios import Scenario, demonstrations

    return demonstrations(20, Scenario("short", landings="none"))


@pytest.mark.parametrize("method", ["calibrate", "donut"])
def test_binary_runs_throw_the_windows_in_order_and_hit(short_demos, method):
    result = learn(short_demos, 1.4, budget=20, feedback="binary", update=method, seed=20)
    assert result.hit, result.misses
    offsets = [a.info["log_factor"] for a in result.history]
    assert len(set(offsets)) == len(offsets)  # no window twice in the first pass
    # every throw released at the speed its window asked for (the planner keeps the release)
    reference = result.history[0].info["speed"] / math.exp(offsets[0])
    for attempt in result.history:
        assert attempt.info["speed"] == pytest.approx(reference * math.exp(attempt.info["log_factor"]), rel=1e-3)


def test_the_runs_misreport_reaches_calibrates_window_search_and_donut_keeps_none(short_demos, monkeypatch):
    from dataclasses import replace

    import rlff.learn.windows

    monkeypatch.setattr(rlff.learn.windows, "UNLIKE_PEOPLE", 0.0)  # the prior alone: retries among the windows

    from rlff.learn.demos import angle_grid
    from rlff.learn.loop import METHODS
    from rlff.learn.method import Problem

    problem = Problem(demos=short_demos, target=1.4, feedback="binary", tolerance=0.14,
                      angles=angle_grid(short_demos), components=2, seed=0)
    fastest = 30.0  # rad/s, far above the people's: the whole lattice is within reach

    def first_pass(method_name: str, misreport: float) -> np.ndarray:
        search = METHODS[method_name](replace(problem, misreport=misreport)).windows(fastest)
        return np.round(search.offsets[: search.masses.size], 9)

    default, none, often = first_pass("calibrate", MISREPORT), first_pass("calibrate", 0.0), first_pass("calibrate", 0.5)
    assert np.unique(none).size == none.size  # no window twice
    assert none.size < default.size <= often.size  # retries, sooner and more of them the likelier a misreport
    assert set(default) == set(none) == set(often)  # the same windows
    donut = first_pass("donut", 0.5)
    assert np.unique(donut).size == donut.size


def test_a_misreport_outside_0_1_is_refused(short_demos):
    with pytest.raises(InputError, match="misreport"):
        learn(short_demos, 1.4, budget=1, misreport=1.0)


def test_a_resumed_binary_run_continues_with_the_next_window(short_demos, tmp_path):
    log = tmp_path / "attempts.jsonl"
    first = learn(short_demos, 1.4, budget=1, feedback="binary", seed=21, log_path=log)
    assert not first.hit  # the GMR mean's speed (window 0) misses this basket
    straight = learn(short_demos, 1.4, budget=3, feedback="binary", seed=21)
    resumed = learn(short_demos, 1.4, budget=3, feedback="binary", seed=21, log_path=log)
    assert resumed.resumed == 1
    assert [a.info["log_factor"] for a in resumed.history] == [a.info["log_factor"] for a in straight.history]
    assert resumed.hit == straight.hit


def test_a_centre_moves_the_lattice_and_the_prior_with_it():
    search = WindowSearch(1.75, 0.14, highest=0.8, centre=0.13, scale=0.15, floor=0.0)
    np.testing.assert_allclose([search.offset(k)[0] for k in range(5)], [0.13, 0.23, 0.03, 0.33, -0.07], atol=1e-9)
    assert search.offset(0)[1] == pytest.approx(norm.cdf(0.05, 0, 0.15) - norm.cdf(-0.05, 0, 0.15), abs=1e-6)
    # a centre beyond the speed limit: the fastest throw first
    beyond = WindowSearch(1.75, 0.14, highest=0.2, centre=0.35, scale=0.15, floor=0.0)
    assert beyond.offset(0)[0] == pytest.approx(0.2)
    assert beyond.offset(1)[0] == pytest.approx(0.1)


def test_the_band_between_the_top_window_and_the_limit_gets_a_window_of_its_own():
    # about 0.13 with w = 0.1, the top window is 0.13 (0.23 is beyond the limit 0.2): its upper
    # edge 0.18 leaves 0.18-0.2 uncovered, so a window at 0.2 joins with the mass of what it
    # would hit: that band and the half window above the limit, 0.2-0.25
    search = WindowSearch(1.75, 0.14, highest=0.2, centre=0.13, scale=0.15, floor=0.0)
    thrown = search.offsets[: search.masses.size]
    assert np.count_nonzero(np.isclose(_first_pass(search), 0.2)) == 1
    reach = norm.cdf(0.25, 0.13, 0.15) - norm.cdf(0.18, 0.13, 0.15)
    assert search.masses[np.flatnonzero(np.isclose(thrown, 0.2))[0]] == pytest.approx(reach)
    # the same with the prior given as a density on a grid
    gridded = WindowSearch(1.75, 0.14, highest=0.2, centre=0.13,
                           log_density=lambda x: norm.logpdf(x, 0.13, 0.15), floor=0.0)
    assert gridded.masses == pytest.approx(search.masses, abs=1e-4)
    assert np.allclose(gridded.offsets, search.offsets)
    # the top window keeps the tail beyond the limit as well: it stays first
    assert search.offset(0)[0] == pytest.approx(0.13)
    # about 0 the lattice ends within half a window of the limit (0.1 + 0.05 >= 0.12): no band
    near = WindowSearch(1.75, 0.14, highest=0.12, floor=0.0)
    assert not np.any(np.isclose(_first_pass(near), 0.12))


def test_a_limit_far_above_the_gmr_means_speed_is_within_the_search():
    # u0 a thirtieth of the limit (a GMR mean extrapolated to a throw that hardly moves at its
    # release) and the landings' law at e^3 u0: its window is the first, not one at e^1.2 u0
    search = WindowSearch(1.9, 0.14, highest=math.log(30.0), centre=3.0, scale=0.2)
    assert search.offset(0)[0] == pytest.approx(3.0)
    assert search.offsets.max() + 0.5 * search.width >= math.log(30.0)  # the windows cover the limit
    # a robot without a speed limit: as fast as the slowest throw is slow
    assert WindowSearch(1.9, 0.14, highest=math.inf).offsets.max() <= 1.2 + 1e-9


def test_a_search_without_misreports_throws_no_window_twice_in_its_first_pass():
    search = WindowSearch(1.75, 0.14, highest=0.8, misreport=0.0)
    first = search.offsets[: search.masses.size]
    assert first.size == lattice(search.width, search.highest).size
    assert np.unique(np.round(first, 9)).size == first.size
    # the prior alone (no floor) throws the same windows, some of them twice
    prior = WindowSearch(1.75, 0.14, highest=0.8, floor=0.0)
    assert prior.masses.size > search.masses.size
    np.testing.assert_allclose(np.unique(np.round(prior.offsets[: prior.masses.size], 9)), np.unique(np.round(first, 9)))


def test_a_fifth_of_the_prior_on_every_window_throws_each_before_any_again_and_keeps_the_core_s_order():
    # N(0, 0.3), w = 0.1, 20 windows: a retry of the likeliest (0.8 x 0.13 x 0.05) is worth less
    # than the floor's 0.2 / 20 of an untried one; on an arm unlike the people the hit lay 2-3
    # standard deviations out, behind the retries (docs/learn.md)
    assert UNLIKE_PEOPLE == 0.2
    default, prior = WindowSearch(1.75, 0.14, highest=0.8), WindowSearch(1.75, 0.14, highest=0.8, floor=0.0)
    first = default.offsets[: default.masses.size]
    assert np.unique(np.round(first, 9)).size == first.size == lattice(default.width, default.highest).size
    assert default.masses.sum() == pytest.approx(1.0)
    # the likeliest windows, whose masses beat the floor's share, keep the prior's order
    np.testing.assert_allclose(first[:5], prior.offsets[:5])
    # with the floor alone the lattice goes in the sweep's order
    np.testing.assert_allclose(WindowSearch(1.75, 0.14, highest=0.8, floor=1.0).offsets[: first.size],
                               lattice(default.width, default.highest))
