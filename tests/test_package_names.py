"""The packages whose public names load on first use (``rlff``, ``rlff.model``, ``rlff.robot``)
list them: ``dir()``, tab completion and ``help()`` had missed every one of them."""

from __future__ import annotations

import importlib
import pydoc
import re

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
