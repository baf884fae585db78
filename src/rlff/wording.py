"""Words in messages, for every stage and the CLI: a count with its noun in the right number, a
bad CSV cell as the file shows it, the nearest of the names a misspelt one may mean."""

from __future__ import annotations

import difflib
import math
from collections.abc import Sequence
from typing import Any


def plural(count: int, noun: str, many: str | None = None) -> str:
    """``"1 attempt"``, ``"3 attempts"``: the count and the noun in the right number (``many``:
    an irregular plural)."""
    return f"{count} {noun if count == 1 else (many or noun + 's')}"


def bad_cell(value: Any) -> str:
    """What is wrong with a CSV cell pandas read where a finite number belongs, the cell as the
    file shows it: text quoted, ``inf`` as written, not numpy's ``np.float64(inf)`` (pandas reads
    an empty cell and ``nan`` alike, as NaN)."""
    if isinstance(value, str):
        return f"a non-numeric or non-finite value {value!r}"
    number = float(value)
    return "an empty or nan value" if math.isnan(number) else f"a non-finite value {number:g}"


def did_you_mean(word: str, choices: Sequence[str]) -> str:
    """`` (did you mean 'x'?)`` with the choice nearest to a misspelt ``word`` (difflib), or
    ``""`` when none is close."""
    near = difflib.get_close_matches(word, list(choices), n=1)
    return f" (did you mean {near[0]!r}?)" if near else ""


def nearest_hint(word: str, choices: Sequence[str], otherwise: str) -> str:
    """:func:`did_you_mean`, or `` (otherwise)`` when no choice is close (e.g. the list of the
    choices)."""
    return did_you_mean(word, choices) or f" ({otherwise})"


def signed(value: float, digits: int = 2) -> str:
    """``value`` with its sign to ``digits`` decimals, ``+0.23``, ``-0.07``; one that rounds to
    zero is ``0.00``: a landing 3 mm short of the centre printed as ``-0.00`` beside ``+0.01``."""
    text = f"{value:+.{digits}f}"
    return text[1:] if float(text) == 0 else text


def signed_metres(value: float, digits: int = 2, unmeasured: str = "landing not measured") -> str:
    """A signed miss in words: ``+0.23 m`` (:func:`signed`), or ``unmeasured`` for NaN (an
    operator who typed hit or miss measured no landing)."""
    return unmeasured if value != value else f"{signed(value, digits)} m"


def attempt_outcome(hit: bool, miss: float) -> str:
    """An attempt's outcome in a list of signed misses (m): ``+0.23``, ``-0.07 hit``, or
    ``hit (not measured)`` and ``miss (not measured)`` where the landing was not measured."""
    if miss != miss:  # NaN
        return f"{'hit' if hit else 'miss'} (not measured)"
    return signed(miss) + (" hit" if hit else "")


def numbered(numbers: Sequence[int]) -> str:
    """``1-3, 5``: ascending ``numbers`` (attempts, lines) with each run of consecutive ones as a span."""
    spans: list[list[int]] = []
    for number in numbers:
        if spans and number == spans[-1][1] + 1:
            spans[-1][1] = number
        else:
            spans.append([number, number])
    return ", ".join(f"{low}" if low == high else f"{low}-{high}" for low, high in spans)
