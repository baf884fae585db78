"""Words in messages: a count with its noun in the right number, for every stage and the CLI."""

from __future__ import annotations


def plural(count: int, noun: str, many: str | None = None) -> str:
    """``"1 attempt"``, ``"3 attempts"``: the count and the noun in the right number (``many``:
    an irregular plural)."""
    return f"{count} {noun if count == 1 else (many or noun + 's')}"
