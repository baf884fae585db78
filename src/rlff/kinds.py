"""What an rlff file is, read from its ``format`` field: for the errors of a reader given one kind
of rlff file where another goes (a model where demonstrations go said only "unknown dataset
extension '.json'")."""

from __future__ import annotations

import re
from pathlib import Path

#: The ``format`` field of each JSON document or log rlff writes, and what to call that file.
KINDS = {
    "rlff-model": "an rlff model (rlff fit writes it)",
    "rlff-joint-trajectory": "a robot trajectory (rlff robot export -f json writes it)",
    "rlff-attempts": "an attempts log (rlff learn --log writes it)",
    "rlff-run": "a run summary (rlff demo's run.json)",
    "rlff-preprocess-report": "a cleaning report (rlff data preprocess --report writes it)",
}
#: Bytes read from a file's start to find its ``format`` (rlff writes it first).
_HEAD = 4096
_FORMAT = re.compile(rb'"format"\s*:\s*"(rlff-[a-z-]+)"')


def rlff_kind(path: str | Path) -> str | None:
    """What the rlff file ``path`` is (:data:`KINDS`' words), or None: not an rlff JSON document or
    log, or not readable."""
    try:
        with open(path, "rb") as handle:
            head = handle.read(_HEAD)
    except OSError:
        return None
    found = _FORMAT.search(head)
    return KINDS.get(found.group(1).decode()) if found else None
