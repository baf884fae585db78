"""The thesis' figures, as PNG and SVG, from plain values, datasets and models.

One module per family of figures: :mod:`.data` (the dataset in 3-D and per distance),
:mod:`.preprocess` (each cleaning step before and after), :mod:`.learning` (miss against attempt).
Every public function takes the values to draw and an output stem, writes ``STEM.png`` and
``STEM.svg`` and returns a :class:`SavedFigure` (the paths and the matplotlib figure, for
inspection). matplotlib's object API is used, never pyplot's global state.
"""

from rlff.plots._figure import SavedFigure

__all__ = ["SavedFigure"]
