"""Saying once that the model's kernels are being compiled for this machine.

numba compiles rlff's GMR and DMM kernels at their first call after an install (a minute and a
half of CPU, minutes on a busy machine: :func:`rlff.model.compile_kernels` says what was
measured) and caches the machine code beside the sources (``cache=True``, or under
``NUMBA_CACHE_DIR``); later processes load it in well under a second. A command that waits for
the compiler without a word looks stuck, so the ``rlff`` command asks to be told
(:func:`tell_with`) when the first of rlff's kernels starts compiling: numba's ``numba:compile``
event, which fires only for a kernel that is not in the cache (a cold cache), never for one loaded
from it. The modules that define the kernels call :func:`listen` once numba is imported.
"""

from __future__ import annotations

from collections.abc import Callable

NOTICE = ("note: compiling the model's kernels for this machine (the first run after installing "
          "rlff only: a minute or more of CPU; cached after)")

_sink: Callable[[str], None] | None = None
_said = False
_listening = False


def tell_with(sink: Callable[[str], None] | None) -> None:
    """Say :data:`NOTICE` through ``sink`` the first time one of rlff's kernels is compiled in
    this process (None: say nothing, the library's default)."""
    global _sink
    _sink = sink


def listen() -> None:
    """Have numba report the compiling of rlff's kernels to :func:`tell_with`'s sink (once per
    process; a second call does nothing)."""
    global _listening
    if _listening:
        return
    from numba.core import event

    class _FirstCompile(event.Listener):
        def on_start(self, ev: event.Event) -> None:
            global _said
            dispatcher = (ev.data or {}).get("dispatcher")
            module = getattr(getattr(dispatcher, "py_func", None), "__module__", "") or ""
            if _sink is not None and not _said and module.startswith("rlff."):
                _said = True
                _sink(NOTICE)

        def on_end(self, ev: event.Event) -> None:
            pass

    event.register("numba:compile", _FirstCompile())
    _listening = True
