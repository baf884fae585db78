"""The thesis' figures, as PNG and SVG, from plain values, datasets and models.

One module per family of figures:

- :mod:`.data`: the dataset in 3-D and as one panel per distance (thesis fig. 4.1, 4.16-4.17, 4.44);
- :mod:`.preprocess`: each cleaning step before and after (fig. 4.16-4.43);
- :mod:`.mixture`: k-means and EM per K (fig. 2.3-2.4), BIC against K (eq. 2.2), the components
  at a distance as ellipses (fig. 4.2-4.3, 4.47-4.48);
- :mod:`.donut`: a Gaussian and its donuts (fig. 2.5), the DMM density with the chosen throw
  (fig. 2.7, 4.4);
- :mod:`.outputs`: the throws for several distances, demonstrated and new (fig. 4.7, 4.50);
- :mod:`.learning`: miss against attempt per method;
- :mod:`.throw`: a side view of a simulated throw.

Every public function takes the values to draw and an output stem, writes ``STEM.png`` and
``STEM.svg`` and returns a :class:`SavedFigure` (the paths and the matplotlib figure, for
inspection). matplotlib's object API is used, never pyplot's global state.
"""

from rlff.plots._figure import SavedFigure

__all__ = ["SavedFigure"]
