"""The model stage: Gaussian mixture, regression on it (GMR), the Donut Mixture Model, the model file.

``mixture``         GaussianMixture: k-means++ and EM in log space, BIC/AIC, K by a criterion
``regression``      conditioning a mixture on any input columns (batch weights, means, covariances)
``donut``           the DMM density, the exploration factor, the global mode, continuity along a path
``climb``           the DMM's global mode, compiled: every start of every input climbed to its top
``fastexp``         the compiled exponential the GMR and DMM kernels share
``compile_notice``  the one note a command gives while numba compiles the kernels (a cold cache)
``model``           Model: a mixture over named columns with roles, model.json, generated paths

The names a user needs are imported from here (and from ``rlff``) lazily, so that importing the
package for one of its modules loads nothing else.
"""

from __future__ import annotations

from rlff._lazy import lazy_exports

_EXPORTS = {
    "Model": "rlff.model.model",
    "GeneratedPath": "rlff.model.model",
    "ComponentSelection": "rlff.model.model",
    "compile_kernels": "rlff.model.model",
}

__all__ = sorted(_EXPORTS)


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
