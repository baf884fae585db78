"""The DMM mode of every input climbed on its own: what following the tops along a path is checked
against (tests/test_donut.py, benchmarks/mode_following.py)."""

from __future__ import annotations

import numpy as np

from rlff.model.donut import dmm_mode
from rlff.model.regression import Conditional


def each_alone(conditional: Conditional, exploration: np.ndarray) -> np.ndarray:
    """The highest P_DMM (N,) of every input climbed on its own (a batch of one: nothing to follow)."""
    tops = np.empty(len(conditional))
    for i in range(len(conditional)):
        single = Conditional(
            conditional.weights[i : i + 1], conditional.means[i : i + 1], conditional.covariances,
            conditional.mean[i : i + 1], conditional.covariance[i : i + 1],
        )
        tops[i] = dmm_mode(single, exploration[i : i + 1]).max_pdf[0]
    return tops
