"""The packages whose public names load on first use (``rlff``, ``rlff.model``, ``rlff.robot``)
list them: ``dir()``, tab completion and ``help()`` had missed every one of them."""

from __future__ import annotations

import importlib
import pydoc
import re
import sys
from pathlib import Path

import pytest

import rlff

LAZY_PACKAGES = ("rlff", "rlff.model", "rlff.robot")


@pytest.mark.parametrize("name", LAZY_PACKAGES)
def test_dir_lists_the_names_loaded_on_first_use(name):
    # 'Model' in dir(rlff) and 'load_robot' in dir(rlff.robot) were False
    package = importlib.import_module(name)
    listed = dir(package)
    assert set(package._EXPORTS) <= set(listed) and set(package.__all__) <= set(listed)
    assert listed == sorted(listed) and "__getattr__" in listed  # the module's own names stay
    for public in package.__all__:
        assert getattr(package, public) is not None


@pytest.mark.parametrize(("name", "shown"), [
    ("rlff", ["class Model(", "class Dataset(", "dmm_mode("]),
    ("rlff.model", ["class Model(", "class GeneratedPath(", "compile_kernels("]),
    ("rlff.robot", ["class Robot(", "load_robot(", "mapping_for("]),
])
def test_help_documents_the_names_loaded_on_first_use(name, shown):
    text = pydoc.render_doc(importlib.import_module(name), renderer=pydoc.plaintext)
    for entry in shown:
        assert entry in text, f"help({name}) leaves out {entry}"


def test_the_package_docstring_s_chain_imports_what_it_names():
    block = rlff.__doc__.split("::", 1)[1]
    imports = [line.strip() for line in block.splitlines() if line.strip().startswith("from rlff")]
    assert len(imports) == 6
    exec("\n".join(re.sub(r"\s+#.*", "", line) for line in imports), {})


@pytest.mark.parametrize("name", LAZY_PACKAGES)
def test_an_unknown_name_is_an_attribute_error_that_names_the_package(name):
    package = importlib.import_module(name)
    with pytest.raises(AttributeError, match=rf"^module '{re.escape(name)}' has no attribute 'no_such_name'$"):
        package.no_such_name  # noqa: B018
    assert not hasattr(package, "no_such_name")


def test_lazy_exports_load_a_name_on_first_use_and_list_it_before(monkeypatch):
    # the one helper the three packages share (they had each kept a copy of these lines)
    import types

    from rlff._lazy import lazy_exports

    package = types.ModuleType("fake_package")
    package.own = 1
    monkeypatch.setitem(sys.modules, "fake_package", package)
    monkeypatch.delitem(sys.modules, "colorsys", raising=False)
    package.__getattr__, package.__dir__ = lazy_exports("fake_package", {"rgb_to_hsv": "colorsys"})
    assert dir(package) == sorted({*vars(package), "rgb_to_hsv"}) and "own" in dir(package)
    assert "colorsys" not in sys.modules  # listed, not loaded
    assert package.rgb_to_hsv is importlib.import_module("colorsys").rgb_to_hsv
    with pytest.raises(AttributeError, match="^module 'fake_package' has no attribute 'hsv'$"):
        package.hsv  # noqa: B018


def test_the_model_package_docstring_lists_each_of_its_modules():
    # compile_notice (and climb) were left out of the list
    import rlff.model

    folder = Path(rlff.model.__file__).parent
    modules = {p.stem for p in folder.glob("*.py") if p.stem != "__init__"}
    listed = set(re.findall(r"^``(\w+)``", rlff.model.__doc__, flags=re.MULTILINE))
    assert listed == modules
