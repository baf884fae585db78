"""Binary feedback without a direction: the release speed's hit windows, most probable first.

A miss told only "miss" says neither short nor long, so a search on the release speed can only
rule out the speeds that would have hit had the law been what the miss disproved: a window of
log speeds around the speed tried. This module tiles the log speed factor x = log(u / u0)
(u the release speed, u0 the GMR mean's for the basket) with such windows, each as wide as the
hit window seen through the range law (2 tolerance / Z in log distance over the elasticity,
:data:`RANGE_ELASTICITY`, the same prior the sweep baseline has), from a centre
(the GMR mean's own speed, x = 0, or where the demonstrations' landings point when they are
known, :mod:`rlff.learn.landings`) up to the robot's speed limit and down to the slowest throw
any search tries, and throws them in the order of the probability a prior puts on each:

- a prior density over x* (where the hit is): normal about the centre (its masses in closed
  form), or any density given on a fine grid of x (``donut``: the DMM's);
- every window collects the prior's mass between the midpoints to its neighbours; the fastest
  window also collects all the mass beyond it, and the slowest all below it: the basket is
  within the robot's reach (the loop refuses one that is not before the first throw), so the
  belief that it needs a faster throw than the robot can make is belief in the fastest throw
  (lifting the centre's neighbour no higher than the centre where that tail is less than the
  centre holds, :func:`tail_capped`);
- windows of equal mass go in the sweep's order (the centre, then +w, -w, +2w, ... about it);
- :data:`UNLIKE_PEOPLE` of the mass is spread evenly over all windows (the robot may be unlike
  the people the prior is drawn from).

Where the lattice's top window ends more than half a window below the limit, one window at the
limit covers the band between, with the prior's mass of what it would hit: that band and the
half window above the limit.

A miss may be a hit reported wrongly (the ball rattled out, the observer or the sensor got it
wrong): a window that missed keeps :data:`MISREPORT` of its mass rather than none, so the
likeliest windows are thrown once more (:data:`RETRIES`) where the untried ones left are
:data:`MISREPORT` times less likely (:func:`with_retries`). After every window of the lattice,
the same windows shifted by half a window (the gaps a steeper range law than the prior's
leaves; the first shifted past the limit at the limit), then the lattice again. The order is a
deterministic function of the number of attempts (every attempt before the hit missed), so a
resumed run makes the attempts the uninterrupted one would have.

The search is hand-written: it is the project's own method (an ordering of the lattice by a
prior over hit windows), a dozen lines of numpy around a cumulative sum.
"""

from __future__ import annotations

import numpy as np
from scipy.stats import norm

#: Elasticity of the landing distance in the release speed the searches assume (a drag-free
#: throw's range goes as speed^2, brought down by the release height).
RANGE_ELASTICITY = 1.6
#: Standard deviation (log speed) of the default prior over the hit's log speed factor, centred on
#: the GMR mean's speed: one standard deviation is 35 % more or less speed, 0.3 x 1.6 = 0.48 in
#: log distance (chosen on seeds 0-15 among 0.15-0.6, checked on seeds 20-35).
PRIOR_SCALE = 0.3
#: Slowest log speed factor any search tries (a throw at 30 % of the demonstrations' speed; the
#: sweep's too), unless the arm's kinematics say a basket needs slower throws (:func:`lowest_for`).
LOWEST = -1.2
#: Slowest speed :func:`lowest_for` goes down to, as a share of the speed at :data:`LOWEST`.
_SLOWEST_SHARE = 0.01
#: Points of the grid the prior is integrated on, per unit of log speed.
_GRID_DENSITY = 400
#: Probability the search gives a hit being reported as a miss. Set a priori (a ball that
#: rattles out of the basket one time in twenty) among 0.02 / 0.05 / 0.1, the largest that left
#: every emulated run with true reports as it was. With 20 % of hits reported as misses
#: (``--feedback false-miss:0.2``) a hit window that was reported a miss came round only after
#: the whole lattice and its shifted copy (20-30 throws); emulated on measured hit curves (seeds
#: 0-95, no labels), the mean attempts fall from 4.87 / 4.61 / 3.62 / 4.67 / 4.38 to
#: 4.44 / 3.87 / 2.91 / 4.05 / 3.75 (``short`` / ``wide`` / ``overshooting`` / ``near`` /
#: ``mixed``; 0.1: 4.31 / 3.82 / 2.83 / 3.95 / 3.63, and one run of 192 in ``short`` and in
#: ``overshooting`` a throw later with true reports). Held out: docs/learn.md.
MISREPORT = 0.05
#: Throws of one window again in the first pass, at most. Without a cap a narrow prior throws its
#: likeliest windows again and again before the unlikely ones (0.15 about a centre 0.07 below
#: the limit: the windows there over 200 times each), and an unlikely window is more often the
#: hit than a prior says where the robot differs from the people (docs/learn.md).
RETRIES = 1


#: Share of the prior over the hit's window spread evenly over every window: the belief that the
#: robot is unlike the people, so that any window may hold the hit. Without it, on an arm whose
#: robot file nobody tuned (a tester's UR5e-like file) the hit lay 0.6-0.95 in log speed above
#: the GMR mean's speed, 2-3 prior standard deviations, and the likeliest windows were thrown
#: twice (:data:`MISREPORT`) before the window that hit: ``calibrate`` needed 12.2 attempts
#: against the sweep's 7.1 (emulated on measured hit curves, seeds 0-31, five demonstrators).
#: With 0.2 (among 0.05 / 0.1 / 0.2 / 0.3: 9.8 / 8.8 / 7.4 / 7.3) every window comes before a
#: retry there; on the Comau no run with true reports changes (tuning seeds 0-31 and held-out
#: 100-107), and with a fifth of the hits reported as misses the mean goes 4.7 -> 5.1 (docs/learn.md).
UNLIKE_PEOPLE = 0.2


def window_width(target: float, tolerance: float, elasticity: float = RANGE_ELASTICITY) -> float:
    """Width (log speed) of the hit window: 2 ``tolerance`` / ``target`` over ``elasticity``."""
    return 2.0 * tolerance / (elasticity * target)


def lattice(width: float, highest: float, lowest: float = LOWEST) -> np.ndarray:
    """Window centres k ``width`` within [``lowest``, ``highest``], in the sweep's order.

    Returns
    -------
    ndarray of shape (W,)
        0, +w, -w, +2w, -2w, ... (log speed factors), one side only past the other's end.
    """
    top = int(np.floor(highest / width + 1e-9))  # negative when even u0 is beyond the limit
    bottom = int(np.floor(-lowest / width + 1e-9))
    reach = max(abs(top), bottom)
    steps = [k for j in range(reach + 1) for k in ((0,) if j == 0 else (j, -j)) if -bottom <= k <= top]
    return np.asarray(steps, dtype=float) * width


def reachable_top(highest: float, width: float) -> float:
    """The largest log speed factor a search tries: ``highest`` (log of the speed limit over u0;
    a robot without a speed limit: as fast as the slowest throw is slow, -:data:`LOWEST`), with
    room for one window above the slowest.

    The limit is not cut to that range: where the GMR mean is extrapolated to a throw that
    hardly moves at its release, the hit lies far above it (``short`` with exact landings, seed
    4106, 1.9 m: u0 = 0.29 rad/s, the hit at the limit, 11.2; cut at -:data:`LOWEST`, e^1.2 u0,
    ``calibrate`` threw at most 0.98 and missed for 20 attempts).
    """
    top = highest if np.isfinite(highest) else -LOWEST
    return float(max(top, LOWEST + width))


def lowest_for(landing, reference: float, target: float, tolerance: float, width: float) -> float:
    """The slowest log speed factor (over ``reference``) a search of windows ``width`` wide must
    go down to for a basket at ``target`` (m): :data:`LOWEST`, or lower where the arm's kinematics
    (``landing``) say that even throws that slow come down beyond the basket's far edge, so that a
    window lies below the speed x_far whose ball comes down at that edge: one window below it.

    A near basket on an arm whose throws mostly carry the ball out by the release's own reach
    needs throws far slower than the people's: on a tester's slow arm throwing with joint 3, at
    0.4 m, the slowest window of the lattice (at most 30 % of the GMR mean's speed) came down at
    0.58 m, 5 mm beyond the far edge, and the run missed 12 times at +0.18 to +0.31 m.

    Parameters
    ----------
    landing : callable or None
        ``landing(u) -> m``: where a throw released at speed u (rad/s, the demonstrations' units)
        comes down by the arm's kinematics, increasing in u (``Problem.landing``); None: no
        kinematics known, :data:`LOWEST`.
    reference : float
        u0 (rad/s), the speed the search's log factors are over.
    target, tolerance : float
        Basket distance and the hit window's half-width (m).
    width : float
        The search's window width (log speed).
    """
    far = target + tolerance
    if landing is None or not landing(reference * np.exp(LOWEST + width)) > far:
        return LOWEST
    low, high = LOWEST + width + np.log(_SLOWEST_SHARE), LOWEST + width
    if landing(reference * np.exp(low)) > far:  # every throw lands beyond: the slowest of all
        return float(low - width)
    for _ in range(30):  # bisection on the speed whose ball comes down at the far edge
        middle = 0.5 * (low + high)
        low, high = (middle, high) if landing(reference * np.exp(middle)) <= far else (low, middle)
    return float(low - width)


def limit_band(centres: np.ndarray, width: float, highest: float) -> tuple[float, float] | None:
    """The log speeds between the top window's upper edge and ``highest`` (the lattice's steps
    seldom end at the limit), which one more window, at the limit, covers; None when there are
    none."""
    band = (float(np.max(centres)) + 0.5 * width, highest)
    return band if band[1] - band[0] > 1e-9 else None


def limit_reach(band: tuple[float, float], width: float, highest: float) -> tuple[float, float]:
    """The hits x* (log speed) the window at the limit would make: the ``band`` below it that no
    lattice window covers (:func:`limit_band`) and the half window above ``highest``, where a hit
    the robot could only just not make were it any farther lies within the hit window of the
    throw at the limit.

    With the band alone, a hit at the limit came late where the prior gave the band little mass:
    `short` without labels at 1.9 m, where the hit lies 0.05 below the limit, took 10-14 attempts
    on 7 of the tuning seeds 0-95 (emulated on measured hit curves, as
    ``benchmarks/learning_orders.py`` does), 2 with the half window above; the mean at that
    basket 1.95 -> 1.62, over both baskets 2.85 -> 2.74 (16-run blocks in which ``calibrate``
    beats the sweep with p < 0.05: 7 -> 10 of 12); `overshooting`, `near` and `mixed` within 0.02.
    Held out (15 `short` blocks of 16 real runs): 2.94 -> 2.88, won 11 -> 12 of 15; the real MSR
    throws at the edge of reach, 2.2 and 2.24 m: 7 and 8 attempts -> 5 and 6 (docs/learn.md).
    """
    return band[0], highest + 0.5 * width


def half_shifted(first: np.ndarray, width: float, highest: float) -> np.ndarray:
    """The second pass, shape (V,): the windows of ``first`` shifted up by half a window (the
    gaps a range law steeper than the prior's leaves), in ``first``'s order; the first one
    shifted beyond ``highest`` is thrown at the limit instead, unless ``first`` has a window
    there, and the others beyond are left out.

    Without the throw at the limit, an arm a little slower than its robot file whose hit lay
    between the top window and the limit was never hit (``short`` without labels, arm at 95 %
    of the commanded speed, seed 5204 at 1.9 m: 20 misses; the throw at the limit hits).
    """
    shifted = first + 0.5 * width
    beyond = np.flatnonzero(shifted > highest + 1e-12)
    keep = shifted <= highest + 1e-12
    if beyond.size and not np.any(np.isclose(first, highest)):
        keep[beyond[0]] = True
        shifted[beyond[0]] = highest
    return shifted[keep]


def with_retries(first: np.ndarray, masses: np.ndarray, misreport: float = MISREPORT,
                 retries: int = RETRIES) -> tuple[np.ndarray, np.ndarray]:
    """The first pass over the lattice with its windows thrown again where a miss may have been a
    misreported hit: the likeliest window next, each window's mass times ``misreport`` for every
    miss it had, a window at most ``retries`` times again, until every window has been thrown.

    Parameters
    ----------
    first : array of shape (W,)
        Window centres (log speed) in the order of their masses, the likeliest first.
    masses : array of shape (W,)
        Their prior masses, in the same order (compared to 4 decimals, as the first pass's order
        is: equal masses keep ``first``'s order, and an untried window goes before a retry of
        equal mass).
    misreport : float
        Probability that a hit is reported as a miss (0: no window twice).
    retries : int
        Most throws of one window after its first.

    Returns
    -------
    offsets : array of shape (N,), N >= W
        The windows' centres in the order thrown.
    thrown : array of shape (N,)
        Each one's prior mass.
    """
    rounded = np.round(masses, 4)
    misses = np.zeros(first.size, dtype=int)
    order: list[int] = []
    while np.any(misses == 0):
        # untried windows first among equals (their mass is at least the smallest positive float)
        belief = np.where(misses == 0, np.maximum(rounded, np.finfo(float).tiny),
                          np.where(misses > retries, -1.0, rounded * misreport**misses))
        best = int(np.argmax(belief))  # the earliest among equals
        order.append(best)
        misses[best] += 1
    return first[order], masses[order]


def tail_capped(masses: np.ndarray, centres: np.ndarray, beyond: float) -> np.ndarray:
    """The lattice's ``masses`` (shape (W,), ``centres``' order, the first the prior's centre)
    with the top window lifted by the prior's tail no higher than the centre window, where the
    top window is the centre's neighbour and that tail (``beyond``: the mass above the top
    window's upper edge, hits no window of the lattice makes) is less than the centre holds.

    The tail counts as belief in the fastest window: the basket is within reach, so a prior that
    puts the hit beyond the limit is off there. A window next to the centre, though, collects the
    prior's whole upper side above the centre's window, and a narrow prior whose limit lies about
    a window above its centre then throws that neighbour first on a belief beyond the limit
    smaller than the one in the centre itself: a carried hit (0.1 about the carried offset, the
    limit 0.12 above it) in the centred run's windows (0.068 wide) had 0.30 there against the
    carry's own 0.22, and its first throw at 1.6 m came down 0.24 m long where the carried speed
    hit (the throw after). Where the centre's window holds less than the tail (the edge of reach:
    the real MSR throws at 2.2 m, whose top window held 0.42, about 0.27 of it beyond the
    window against the centre's 0.16, docs/learn.md), or the top window lies
    farther up (the labels' prior in ``mixed`` at 1.9 m, two windows below the limit, where the
    hit lies above the centre), the top window still goes first.
    """
    top = int(np.argmax(centres))
    if top == 0 or not beyond < masses[0]:
        return masses
    sorted_centres = np.sort(centres)
    if sorted_centres[-2] != centres[0]:  # not the centre's neighbour
        return masses
    capped = masses.copy()
    capped[top] = min(masses[top], max(masses[top] - beyond, masses[0]))
    return capped


def window_masses(centres: np.ndarray, x: np.ndarray, density: np.ndarray) -> np.ndarray:
    """Prior mass of each window, shape (W,): the density integrated between the midpoints to
    the neighbouring centres, the outermost windows reaching to the ends of the grid.

    Parameters
    ----------
    centres : array of shape (W,)
        Window centres (log speed), any order.
    x : array of shape (G,)
        Increasing grid (log speed) on which ``density`` is given.
    density : array of shape (G,)
        Prior density over the hit's log speed factor (any scale, >= 0).
    """
    sorted_centres = np.sort(centres)
    edges = 0.5 * (sorted_centres[1:] + sorted_centres[:-1])  # (W - 1,)
    cumulative = _cumulative(x, density)
    at_edges = np.r_[0.0, np.interp(edges, x, cumulative), cumulative[-1]]
    masses = np.diff(at_edges)
    total = cumulative[-1]
    masses = masses / total if total > 0 else np.full(masses.shape, 1.0 / masses.size)
    return masses[np.searchsorted(sorted_centres, centres)]


def _cumulative(x: np.ndarray, density: np.ndarray) -> np.ndarray:
    """The integral of ``density`` from ``x[0]`` to each point of ``x`` (trapezoids), shape (G,)."""
    return np.r_[0.0, np.cumsum(0.5 * (density[1:] + density[:-1]) * np.diff(x))]


def normal_masses(centres: np.ndarray, scale: float, mean: float = 0.0) -> np.ndarray:
    """Mass of each window under N(``mean``, ``scale``^2), shape (W,): the exact form of
    :func:`window_masses` for the default prior."""
    sorted_centres = np.sort(centres)
    edges = np.r_[-np.inf, 0.5 * (sorted_centres[1:] + sorted_centres[:-1]), np.inf]
    masses = np.diff(norm.cdf(edges, mean, scale))
    return masses[np.searchsorted(sorted_centres, centres)]


class WindowSearch:
    """The hit windows of the release speed, in the order of their prior probability.

    Parameters
    ----------
    target : float
        Basket distance Z (m).
    tolerance : float
        Half-width of the hit window around Z (m).
    highest : float
        Largest log speed factor the robot can make, log(max speed / u0) (may be inf).
    log_density : callable, optional
        Log prior density over the hit's log speed factor, taking an array of shape (G,);
        default normal about ``centre`` with standard deviation ``scale``.
    scale : float
        Standard deviation (log speed) of the default prior.
    centre : float
        Log speed factor the lattice is laid about (its first window's centre) and the default
        prior's mean: 0, the GMR mean's speed, or where the demonstrations' landings point
        (:mod:`rlff.learn.landings`); at most ``highest``.
    elasticity : float
        Elasticity of the landing in the release speed that sizes the windows (the range law's
        prior; a whole-arm throw's comes from the arm's kinematics).
    misreport : float
        Probability the search gives a hit being reported as a miss (:func:`with_retries`; 0:
        no window twice in the first pass).
    floor : float, optional
        Share of the mass spread evenly over the windows; default :data:`UNLIKE_PEOPLE`.
    lowest : float
        Slowest log speed factor of the lattice's range: :data:`LOWEST`, or lower where the
        basket needs it (:func:`lowest_for`).
    """

    def __init__(self, target: float, tolerance: float, highest: float, log_density=None,
                 scale: float = PRIOR_SCALE, elasticity: float = RANGE_ELASTICITY, centre: float = 0.0,
                 misreport: float = MISREPORT, floor: float | None = None, lowest: float = LOWEST):
        self.width = window_width(target, tolerance, elasticity)
        self.highest = reachable_top(highest, self.width)
        #: Slowest log speed factor of the lattice's range.
        self.lowest = lowest
        #: Log speed factor the lattice is laid about (a centre beyond the limit: the limit).
        self.centre = float(np.clip(centre, lowest + self.width, self.highest))
        centres = self.centre + lattice(self.width, self.highest - self.centre, lowest - self.centre)
        # the speeds between the top window's upper edge and the limit (the lattice's steps
        # seldom end at the limit): one more window, at the limit, with the prior's mass of what
        # it would hit, that band and the half window above the limit (:func:`limit_reach`); the
        # whole tail beyond stays with the top window too (given to the limit's window alone it
        # threw the limit first more often: 3.14 attempts against 2.65 on seeds 0-7 without labels),
        # but lifts the centre's neighbour no higher than the centre where it is less than the
        # centre holds (:func:`tail_capped`)
        band = limit_band(centres, self.width, self.highest)
        reach = limit_reach(band, self.width, self.highest) if band else None
        above = float(np.max(centres)) + 0.5 * self.width  # the top window's upper edge
        if log_density is None:
            masses = normal_masses(centres, scale, self.centre)
            beyond = float(norm.sf(above, self.centre, scale))
            if reach:
                masses = np.r_[masses, np.diff(norm.cdf(reach, self.centre, scale))]
        else:
            x = np.linspace(lowest - 1.0, self.highest + 2.0,
                            int(_GRID_DENSITY * (self.highest - lowest + 3.0)) + 1)
            log_p = np.asarray(log_density(x), dtype=float)
            density = np.exp(log_p - np.max(log_p))
            masses = window_masses(centres, x, density)
            cumulative = _cumulative(x, density)
            beyond = float(1.0 - np.interp(above, x, cumulative) / cumulative[-1])
            if reach:
                masses = np.r_[masses, np.diff(np.interp(reach, x, cumulative)) / cumulative[-1]]
        masses[:centres.size] = tail_capped(masses[:centres.size], centres, beyond)
        if reach:
            centres = np.r_[centres, self.highest]
        floor = UNLIKE_PEOPLE if floor is None else floor
        masses = (1.0 - floor) * masses + floor / masses.size
        # equal masses (a symmetric prior's +-kw, equal up to the integration's error) keep the
        # sweep's order
        rank = np.argsort(-np.round(masses, 4), kind="stable")
        first = centres[rank]
        retried, thrown = with_retries(first, masses[rank], misreport)
        #: Log speed factors of the attempts, in order, shape (N,).
        self.offsets = np.r_[retried, half_shifted(first, self.width, self.highest), first]
        #: Prior mass of the window of each attempt of the first pass (with its retries), shape (M,).
        self.masses = thrown

    def offset(self, attempt: int) -> tuple[float, float]:
        """Log speed factor of attempt ``attempt`` (0-based), and its window's prior mass (0 once
        past the first pass over the lattice and its retries)."""
        index = min(attempt, self.offsets.size - 1)
        mass = float(self.masses[index]) if index < self.masses.size else 0.0
        return float(self.offsets[index]), mass
