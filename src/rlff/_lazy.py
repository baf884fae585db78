"""Names of a package loaded on first use (PEP 562), for ``rlff``, ``rlff.model`` and ``rlff.robot``.

A package that re-exports its stages' names imports them only when a user reaches for one, so that
``import rlff`` (every ``rlff`` command pays for it) or importing one submodule loads nothing else.
Written by hand rather than taken from a library (``lazy_loader``): PEP 562's module
``__getattr__`` and ``__dir__`` are a dozen lines, not worth a dependency.
"""

from __future__ import annotations

import importlib
import sys
from collections.abc import Callable, Mapping
from typing import Any


def lazy_exports(module_name: str, table: Mapping[str, str]) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """The module-level ``__getattr__`` and ``__dir__`` of package ``module_name`` whose public
    names ``table`` maps to the modules that define them (``{"Model": "rlff.model.model"}``).

    ``__getattr__(name)`` imports the defining module and returns its ``name``; a name not in
    ``table`` is an :class:`AttributeError` that names the package. ``__dir__()`` lists the
    package's own names and ``table``'s, sorted, so that ``dir()``, tab completion and ``help()``
    show the names not loaded yet.

    Use as ``__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)`` in the package's ``__init__``.
    """

    def __getattr__(name: str) -> Any:
        module = table.get(name)
        if module is None:
            raise AttributeError(f"module {module_name!r} has no attribute {name!r}")
        return getattr(importlib.import_module(module), name)

    def __dir__() -> list[str]:
        return sorted({*vars(sys.modules[module_name]), *table})

    return __getattr__, __dir__
