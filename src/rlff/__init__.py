"""rlff: robot learning from failed demonstrations.

Fit a Gaussian Mixture Model to (joint angle, basket distance, joint velocity) samples, condition
it on the angle and the distance (Gaussian Mixture Regression), turn every conditional Gaussian
into a donut (Donut Mixture Model) and take, for every angle, the velocity of highest density.

The public names are imported lazily so that ``import rlff`` stays cheap for the command line.
"""

from __future__ import annotations

import importlib
from typing import Any

__version__ = "0.1.0"

# public name -> module that defines it
_EXPORTS = {
    "RlffError": "rlff.errors",
    "InputError": "rlff.errors",
    "GaussianMixture": "rlff.model.mixture",
    "select_components": "rlff.model.mixture",
    "condition": "rlff.model.regression",
    "predict": "rlff.model.regression",
    "Conditional": "rlff.model.regression",
    "donut_pdf": "rlff.model.donut",
    "dmm_pdf": "rlff.model.donut",
    "dmm_mode": "rlff.model.donut",
    "exploration_factor": "rlff.model.donut",
    "DonutMode": "rlff.model.donut",
    "Model": "rlff.model.model",
    "GeneratedPath": "rlff.model.model",
    "Dataset": "rlff.dataset",
    "Trajectory": "rlff.dataset",
}

__all__ = sorted(_EXPORTS) + ["__version__"]


def __getattr__(name: str) -> Any:
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'rlff' has no attribute {name!r}")
    return getattr(importlib.import_module(module), name)
