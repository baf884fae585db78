"""A method of one's own named as ``MODULE:CLASS``, as ``rlff learn --update`` and ``rlff bench
learning --methods`` take it.

The module is imported with :mod:`importlib` from ``sys.path`` and then the current folder, as
``python -m`` finds a module there: ``faster:Faster`` is the class ``Faster`` of ``faster.py``
in the folder the command runs in. The folder stays on ``sys.path``, so that the benchmark's
local workers (which start with the parent's ``sys.path``) import the class by its module and
name as they import any method class; a Dask cluster's workers need the module themselves.
"""

from __future__ import annotations

import importlib
import os
import sys

from rlff.errors import InputError
from rlff.learn.method import Method

#: How a method of one's own is named, for messages.
EXAMPLE = "faster:Faster (the class Faster of faster.py in the current folder)"


def import_method(spec: str) -> type[Method]:
    """The class ``spec`` (``"MODULE:CLASS"``) names, checked to be an :class:`rlff.learn.Method`
    subclass; what else a method needs (a ``name``, its ``feedbacks``, ``propose``) the loop
    checks as it checks any class (:func:`rlff.learn.loop.method_of`).

    Raises
    ------
    InputError
        ``spec`` is not MODULE:CLASS, the module is not found or fails to import (its error
        named), it has no such attribute (its Method subclasses listed), or that is no Method
        subclass.
    """
    module_name, _, class_name = spec.partition(":")
    if not (module_name and class_name):
        raise InputError(f"{spec}: a method of your own is MODULE:CLASS, e.g. {EXAMPLE}")
    if module_name.endswith(".py"):
        raise InputError(f"{spec}: MODULE is a module's name, not its file: {module_name[:-3]}:{class_name}")
    folder = os.getcwd()
    if folder not in sys.path and "" not in sys.path:
        sys.path.append(folder)
    importlib.invalidate_caches()  # a module written since the last import in this process
    try:
        module = importlib.import_module(module_name)
    except ModuleNotFoundError as exc:
        if exc.name is None or not (module_name + ".").startswith(exc.name + "."):
            raise InputError(f"{spec}: importing {module_name} failed: {exc}") from exc
        raise InputError(f"{spec}: no module {module_name!r} on the Python path (sys.path) or in the current "
                         f"folder {folder}: give MODULE:CLASS of your method's module, e.g. {EXAMPLE}") from None
    except Exception as exc:  # the module's own error (python -c 'import MODULE' shows its traceback)
        raise InputError(f"{spec}: importing {module_name} ({getattr(exc, 'filename', None) or 'its module'}) "
                         f"failed: {type(exc).__name__}: {exc}") from exc
    found = getattr(module, class_name, None)
    if found is None:
        own = [name for name, value in vars(module).items()
               if isinstance(value, type) and issubclass(value, Method) and value.__module__ == module.__name__]
        listed = f"its Method subclasses: {', '.join(own)}" if own else "it defines no rlff.learn.Method subclass"
        raise InputError(f"{spec}: module {module_name} ({module.__file__}) has no {class_name!r}; {listed}")
    if not (isinstance(found, type) and issubclass(found, Method)):
        raise InputError(f"{spec}: {class_name} of {module_name} is {type(found).__name__} {found!r:.60}, not a "
                         "subclass of rlff.learn.Method: give your method's class")
    return found
