"""Results kept by the content of their inputs: the learning loop's costly pure steps done once.

A run prepares the demonstrations (:mod:`rlff.learn.demos`) and fits their mixture before its
first throw; the demo's baskets, the reach checks and a benchmark's methods ask for the same
again and again with equal inputs. :class:`ByContent` keeps the last few results of such a step,
looked up by a digest of everything its inputs hold (:func:`content_digest`), so a run gives
the very same result as without it, only sooner.
"""

from __future__ import annotations

import hashlib
import threading
from collections import OrderedDict
from collections.abc import Callable, Hashable
from typing import TypeVar

from rlff.dataset import Dataset

T = TypeVar("T")


class ByContent:
    """The last ``size`` results of one pure function, by a key that digests its inputs' content.

    Hand-written rather than :func:`functools.lru_cache`: the inputs (datasets, robot mappings) are
    not hashable, and a key by identity would miss the same demonstrations read or filtered anew
    by each call. Results are shared, not copied: datasets (read-only columns), tuples and models,
    which nothing changes after they are made.
    """

    def __init__(self, size: int = 4):
        self._size = size
        self._results: OrderedDict[Hashable, object] = OrderedDict()
        self._lock = threading.Lock()  # joblib's and Dask's threads may share the module

    def get(self, key: Hashable, compute: Callable[[], T]) -> T:
        """The result kept for ``key``, or ``compute()``'s, kept (the oldest dropped beyond the size)."""
        with self._lock:
            if key in self._results:
                self._results.move_to_end(key)
                return self._results[key]  # type: ignore[return-value]
        result = compute()
        with self._lock:
            self._results[key] = result
            while len(self._results) > self._size:
                self._results.popitem(last=False)
        return result


def content_digest(demos: Dataset) -> str:
    """Digest of everything ``demos`` holds: every trajectory's id, columns (names and samples)
    and metadata, and the dataset's context columns. Two datasets with the same digest give the
    same result in every step kept by content. (Not :func:`rlff.learn.demos.fingerprint`: that one
    hashes only what a throw depends on and is written into attempts logs, so it must hash as it
    always did for old logs to resume.)"""
    digest = hashlib.sha256(repr(tuple(demos.context)).encode())
    for trajectory in demos:
        digest.update(trajectory.id.encode())
        digest.update(trajectory.samples_digest())
        digest.update(repr(sorted(trajectory.meta.items())).encode())
    return digest.hexdigest()
