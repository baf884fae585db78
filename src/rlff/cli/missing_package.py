"""What to say when a command needs a package rlff declares and this Python does not have it.

A ``ModuleNotFoundError`` that reaches the error boundary (:mod:`rlff.cli`) for one of rlff's
dependencies, or one of an extra's (``rlff[cluster]``), is an installation that lacks it, not a
bug: :func:`missing_package_line` names the package and the ``pip install`` that adds it. The
dependencies are read from rlff's installed metadata, so the line follows pyproject.toml.
"""

from __future__ import annotations

import importlib.metadata
import re
import sys

#: Import names of the declared distributions whose import name is not their own name.
IMPORT_NAMES = {"scikit-learn": "sklearn", "pillow": "PIL"}


def _import_name(distribution: str) -> str:
    normalized = re.sub(r"[-_.]+", "-", distribution).lower()
    return IMPORT_NAMES.get(normalized, normalized.replace("-", "_"))


def declared_packages() -> dict[str, tuple[str, str | None]]:
    """rlff's declared distributions by import name: ``{import name: (distribution, extra)}``,
    extra None for a dependency of rlff itself, else the extra that brings it (``cluster`` before
    ``test``, which only the test suite installs). Empty when rlff's metadata is not installed."""
    try:
        lines = importlib.metadata.requires("rlff") or []
    except importlib.metadata.PackageNotFoundError:
        return {}
    found: dict[str, tuple[str, str | None]] = {}
    for line in lines:
        requirement, _, marker = line.partition(";")
        distribution = re.match(r"\s*([A-Za-z0-9][A-Za-z0-9._-]*)", requirement).group(1)
        extra = re.search(r"extra\s*==\s*['\"]([^'\"]+)['\"]", marker)
        extra_name = extra.group(1) if extra else None
        name = _import_name(distribution)
        known = found.get(name)
        if known is None or extra_name is None or (known[1] == "test" and extra_name != "test"):
            found[name] = (distribution, extra_name)
    return found


def missing_package_line(exc: ModuleNotFoundError) -> str | None:
    """One line saying which declared package ``exc`` found missing and how to install it; None
    when the missing module is none of rlff's declared packages (then it is a bug)."""
    top = (exc.name or "").split(".")[0]
    known = declared_packages().get(top)
    if known is None:
        return None
    distribution, extra = known
    if extra is None:
        return (f"error: this command needs the Python package {distribution} (No module named "
                f"{top!r}), which rlff depends on but is not installed in this Python ({sys.executable}): "
                f"install it with `pip install {distribution}`, or reinstall rlff (`pip install rlff`)")
    return (f"error: this command needs the Python package {distribution} (No module named {top!r}), "
            f"from rlff's optional '{extra}' extra, which is not installed in this Python ({sys.executable}): "
            f"install it with `pip install 'rlff[{extra}]'`")
