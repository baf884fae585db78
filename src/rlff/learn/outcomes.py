"""Where the robot's hit is not: what demonstrations that all missed say about the release speed.

Without landings the demonstrations still record whether each ball went in (``hit`` metadata, as
the synthetic people and a labelled capture give it). When every one of them missed, the mean of
the demonstrations is a mean of failures: the thesis' reason for the Donut Mixture Model, whose
density is low where the failed demonstrations agree and high on a ring about them. This module
states that reasoning where it reaches the ball, in the release speed of the range law
L = c u^b (:mod:`rlff.learn.landings`):

- demonstration i, released at speed u_i and aimed at Z_i, would have hit had the law been one
  of those through (u_i, Z_i +- tolerance); seen from the robot's basket Z that law asks for the
  log speed factor x = log(u_i / u0) + log(Z / (Z_i -+ tolerance)) / b (u0 the GMR mean's release
  speed for Z);
- its miss multiplies a normal prior about where the people's law puts the robot's hit (the
  middle of their windows, :data:`FAILURES_SCALE`) by one minus the probability of that window,
  blurred by :data:`DEMO_BLUR` (each person's own release moves their law a little);
- that product is one belief (the failures carry over to the robot), the window search's normal
  prior about the GMR mean (:data:`rlff.learn.windows.PRIOR_SCALE`) the other (they say nothing
  about it); the prior mixes the two, :data:`TRANSFER_WEIGHT` on the first;
- the mixture is blurred by :data:`MAPPING_BLUR`: the robot does not land where the person did
  (the human-to-robot mapping changes the arm and the release), by the same amount for all.

The result is a density over the robot's hit x* with a hole where the failures would have
hit, which :class:`rlff.learn.windows.WindowSearch` turns into an order of the speed windows:
the ring about the failures first. Binary feedback, no landings, the `short` demonstrators
(every throw short), mean attempts: the failures alone took the normal prior's 3.66 to 2.94 on
the tuning seeds 0-39 (emulated on measured hit curves, ``benchmarks/learning_orders.py``) and
3.7 to 3.5 on held-out seeds 100-123 (real runs, the median 4 to 2); the mixture takes the
failures alone's 3.16 to 2.85 on seeds 0-95 and 3.5 to 3.35 on 100-123; centring the failures'
belief on the people's aim instead of the GMR mean takes it to 2.33 on seeds 0-95 (held out:
docs/learn.md). Where some
demonstrations hit, the robot's hit is not ruled out by anything and the normal prior stays
(docs/learn.md has where this loses: a robot whose hit lies in the failures' region).

Hand-written: a product of normal window probabilities on a grid (the project's own method),
blurred by scipy's ``gaussian_filter1d``.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from scipy.ndimage import gaussian_filter1d
from scipy.stats import norm

from rlff.dataset import Dataset
from rlff.learn.landings import demonstration_release_speeds
from rlff.learn.method import demo_labels
from rlff.learn.windows import PRIOR_SCALE

#: Blur (log speed) of one demonstration's would-have-hit window: each person's release style
#: moves their own law (chosen among 0.02-0.06 on seeds 0-39).
DEMO_BLUR = 0.03
#: Blur (log speed) of the whole prior: how far the robot's hit may lie from the person's for the
#: same throw (chosen among 0.1-0.3 on seeds 0-39; 0.15-0.2 within 0.1 attempts of each other).
MAPPING_BLUR = 0.15
#: Weight of the belief that the failures carry over to the robot, against the normal prior alone
#: (the robot's hit wherever the mapping puts it, the failures saying nothing about it): the
#: prior is the mixture of the two. All on the failures (1.0) threw the ruled-out middle last,
#: after windows far below it, where the robot's hit often lies (the mapping moves it by as much
#: as the failures' spread): `short` 3.16 attempts on seeds 0-95 (emulated on measured hit
#: curves), 2.85 with 0.6, 2.90 with 0.7, 3.09 with 0.4 (`overshooting` and `mixed`, where
#: all of a seed's demonstrations missed, 1.93 -> 1.81 and 2.51 -> 2.40; chosen on seeds 0-63,
#: checked on 64-95).
TRANSFER_WEIGHT = 0.6
#: Standard deviation (log speed) of the failures' belief about where the people's law puts the
#: robot's hit (the middle of their would-have-hit windows): a person who misses misses by little,
#: so under that belief the hit lies just outside their windows. It was the normal prior's 0.3
#: about the GMR mean's speed, which put more of the ring below the failures than above them where
#: the windows' middle lay above u0 (`short` at 1.4 m, held-out seed 15006: the middle at +0.15,
#: the hit at +0.24, thrown ninth after four windows from -0.25 to -0.63). Centred on the middle:
#: `short` 2.93 -> 2.56 attempts on seeds 0-95 (emulated on measured hit curves); with 0.2 2.33
#: (0.15: 2.33, 0.25: 2.39, 0.4: 2.73); `overshooting` and `mixed` 1.80 / 2.42 -> 1.78 / 2.35.
FAILURES_SCALE = 0.2
#: The grid (log speed factors) the prior is computed on.
_GRID = np.linspace(-3.0, 3.0, 2401)


def all_missed(demos: Dataset) -> bool:
    """True when every demonstration (at least 3) is recorded as a miss (``hit`` False)."""
    outcomes = [t.meta.get("hit") for t in demos]
    return len(outcomes) >= 3 and all(outcome is False for outcome in outcomes)


def outcomes_prior(demos: Dataset, angles: np.ndarray, target: float, tolerance: float, reference: float,
                   elasticity: float = 1.6) -> Callable[[np.ndarray], np.ndarray]:
    """Log prior density over the robot's hit log speed factor x* = log(u* / ``reference``) from
    the demonstrations' outcomes: a miss rules its would-have-hit window out, a hit (``hit``
    True) makes it likelier. ``calibrate`` uses it where every demonstration missed
    (:func:`all_missed`); with hits among them the same reasoning loses (docs/learn.md).

    Parameters
    ----------
    demos : Dataset
        The demonstrations (``angle`` rad, ``velocity`` rad/s; the basket each aimed at as its
        label; ``hit`` metadata, a demonstration without it counted as a miss).
    angles : array of shape (T,)
        The loop's angle grid (rad); its last tenth is the release part.
    target : float
        The robot's basket Z (m).
    tolerance : float
        Half-width of the hit window (m); the people's basket is taken as wide as the robot's.
    reference : float
        u0, the GMR mean's release speed for Z (rad/s).
    elasticity : float
        b of the range law.

    Returns
    -------
    callable
        ``log_density(x)`` for an array of log speed factors, unnormalised (any scale).
    """
    shift = np.log(np.maximum(demonstration_release_speeds(demos, angles), 1e-9) / reference)  # (S,)
    aimed = demo_labels(demos)  # (S,)
    low = shift + np.log(target / (aimed + tolerance)) / elasticity
    high = shift + np.log(target / np.maximum(aimed - tolerance, 1e-3)) / elasticity
    inside = (norm.cdf((high[:, None] - _GRID) / DEMO_BLUR)
              - norm.cdf((low[:, None] - _GRID) / DEMO_BLUR))  # (S, G): would it have hit at x
    hit = np.array([t.meta.get("hit") is True for t in demos])  # (S,)
    likelihood = np.where(hit[:, None], inside, 1.0 - inside)
    normal = norm.pdf(_GRID, 0.0, PRIOR_SCALE)  # (G,), integrates to 1
    # the failures' belief: about where the people's law puts the robot's hit (the middle of
    # their would-have-hit windows), not the GMR mean's speed, which interpolates their speeds
    # and lies elsewhere where their speed grows with distance more slowly than the law says.
    # Not :func:`rlff.learn.landings.aims_shift` (the labels themselves through the law): the
    # windows' middle, (log Z - log(Z_i^2 - t^2) / 2) / b with t the tolerance, sits a little
    # above log(Z / Z_i) / b, and with aims_shift 15 of 272 held-out `short` runs (17 blocks of
    # 16) took one throw more and none fewer
    people_aim = float(np.mean(0.5 * (low + high)))
    log_p = (norm.logpdf(_GRID, people_aim, FAILURES_SCALE)
             + np.sum(np.log(np.clip(likelihood, 1e-6, 1.0)), axis=0))
    failures = np.exp(log_p - log_p.max())
    failures /= np.trapezoid(failures, _GRID)
    mixture = TRANSFER_WEIGHT * failures + (1.0 - TRANSFER_WEIGHT) * normal
    density = gaussian_filter1d(mixture, MAPPING_BLUR / (_GRID[1] - _GRID[0]), mode="constant")
    log_density = np.log(np.maximum(density, 1e-300))
    return lambda x: np.interp(x, _GRID, log_density)
