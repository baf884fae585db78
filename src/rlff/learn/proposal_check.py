"""The one gate a method's proposal passes on its way into the loop.

Every throw of a run follows one angle grid, ``problem.angles`` (rad, shape (T,), its last angle
the release: :func:`rlff.learn.demos.angle_grid`), and drives the joints of ``problem.outputs``:
the elbow's velocity, and for a whole-arm throw the other joints' positions and velocities
along the same samples (``Proposal.arm``). A method of one's own may return anything from
``propose``; what it returns is checked here before anything is planned or thrown, for the
first throw of a whole-arm reach check (``propose([])``) as for every attempt of a run:

- a :class:`~rlff.learn.method.Proposal`, not a dict or None (which had ended a whole-arm run
  with an AttributeError from inside the reach check);
- ``arm`` holding exactly the columns of ``problem.outputs`` after ``velocity`` (a missing
  ``shoulder_velocity`` had ended a run with a KeyError, a ``wrist`` the run does not drive had
  been thrown without a word);
- every column of the grid's shape, every value finite;
- ``angle`` the grid itself, in its order, within :data:`ANGLE_TOLERANCE` of its spacing (a
  reversed grid had been thrown as a swing from the release back to the start, 2.5 m short, a
  truncated one let go where the demonstrations do not, both without a word);
- ``query`` and ``exploration`` numbers, ``info`` a dict the attempts log can keep as JSON (an
  array in ``info`` had failed the log's write after the arm had thrown, so the throw was made
  and not recorded, and a resumed run threw it again).

A method's own exception from ``propose`` passes as it is, with a note naming the attempt and
the method. What the loop changes in a proposal that passed, it says (:func:`changed_words`): a
release against the grid's direction is thrown at rest, a release far beyond the arm's speed
saturated at it.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from numbers import Real

import numpy as np

from rlff.errors import InputError
from rlff.learn.attempt import Attempt
from rlff.learn.demos import CRAWL, forward_velocity
from rlff.learn.method import Method, Problem, Proposal

#: How far (a share of the grid's spacing) a proposal's angle may lie from the grid's and still
#: be taken for it: a float32 copy of the grid (about 1e-7 rad off) passes, a neighbouring
#: sample or a grid shifted by a tenth of its spacing does not. Every built-in method returns
#: the grid itself.
ANGLE_TOLERANCE = 1e-3
#: A release asked for this many times the arm's top speed (``problem.max_speed``) is taken for
#: velocities in another unit (deg/s is 57 times rad/s) in what the loop says of it. No built-in
#: method asks for more than the demonstrations' speeds or the arm's limit.
UNIT_LIKE_FACTOR = 20.0


def proposed(method: Method, problem: Problem, history: Sequence[Attempt], attempt: int) -> Proposal:
    """``method.propose(history)``, the throw of ``attempt`` (1, 2, ...) of a run of ``problem``,
    checked (:func:`require_on_grid`).

    Raises
    ------
    InputError
        What came is no :class:`Proposal`, or one off the grid: one line naming the attempt,
        the method, what came and what is expected.
    """
    try:
        proposal = method.propose(history)
    except Exception as exc:
        exc.add_note(f"raised by {method.name}'s propose at attempt {attempt}")
        raise
    if not isinstance(proposal, Proposal):
        raise InputError(f"attempt {attempt}: {method.name}'s propose returned {type(proposal).__name__} "
                         f"{short_repr(proposal)}: it must return an rlff.learn.Proposal ({_expected(problem)})")
    what = f"attempt {attempt}: the throw {method.name} proposed"
    require_on_grid(proposal, problem, what)
    require_loggable(proposal, what)
    return proposal


def require_loggable(proposal: Proposal, what: str) -> None:
    """Refuse ``proposal`` unless the attempts log can keep what it says of itself: ``query`` a
    number (m; NaN: no model queried), ``exploration`` a finite number, ``info`` a dict of string
    keys whose values JSON holds (numbers finite; lists, not arrays).

    Raises
    ------
    InputError
        ``what`` (``attempt 2: the throw faster proposed``), then the field, what it holds and
        what to give.
    """
    for name, value, allowed in (("query", proposal.query, "a distance in m, NaN when no model was queried"),
                                 ("exploration", proposal.exploration, "the mean DMM exploration factor, 0 without")):
        number = isinstance(value, Real) and not isinstance(value, bool)
        if not number or math.isinf(value) or (name == "exploration" and math.isnan(value)):
            raise InputError(f"{what}: its {name} is {type(value).__name__} {short_repr(value)}: give one number, "
                             f"{allowed}")
    info = proposal.info
    if not isinstance(info, Mapping):
        raise InputError(f"{what}: its info is {type(info).__name__} {short_repr(info)}: give a dict (its keys "
                         "strings), which the attempts log keeps as JSON")
    for key, value in info.items():
        try:
            json.dumps({key: value}, allow_nan=False)
            if not isinstance(key, str):
                raise TypeError("keys must be strings")
        except (TypeError, ValueError) as exc:
            raise InputError(f"{what}: its info[{key!r}] is {type(value).__name__} {short_repr(value)}, which the "
                             f"attempts log cannot keep as JSON ({exc}): give strings as keys and numbers (finite), "
                             "strings, lists and dicts as values (an array's .tolist())") from None


def changed_words(proposal: Proposal, problem: Problem) -> dict[str, str]:
    """What the loop changes in ``proposal``, a throw of ``problem`` that passed
    :func:`proposed`, before it plans it, in words by kind (``"against"``, ``"units"``; empty:
    nothing that changes the throw).

    - A release moving against the grid's direction (``problem.angles`` runs the other way): the
      loop throws every such sample at rest (:func:`rlff.learn.demos.forward_velocity`), so the
      ball is let go standing still (a path with no forward motion at all goes as a crawl).
    - A release speed :data:`UNIT_LIKE_FACTOR` times ``problem.max_speed`` or more: saturated at
      the arm's limit like any faster throw; that many times over is velocities in deg/s.
    """
    velocity = np.asarray(proposal.velocity, dtype=float)
    # what the loop throws, compared with what was asked: a sample moving (not at rest) that it
    # changes ran against the grid; a release so changed to a motion is the crawl
    thrown = forward_velocity(proposal.angle, velocity)
    against = (thrown != velocity) & (velocity != 0)
    said = {}
    if against[-1]:
        words = (f"the path was thrown as a crawl at {CRAWL:g} rad/s, the ball let go at that" if thrown[-1] != 0
                 else "those were thrown at rest, so the ball left the hand standing still")
        said["against"] = (f"its velocity runs against problem.angles' direction ({_span(problem.angles)}) at "
                           f"{np.count_nonzero(against)} of {velocity.size} samples, the release among them: {words}; "
                           "check the velocity's sign")
    release = abs(float(velocity[-1]))
    if math.isfinite(problem.max_speed) and release >= UNIT_LIKE_FACTOR * problem.max_speed:
        said["units"] = (f"it asks for a release at {release:.4g} rad/s, {release / problem.max_speed:.0f} times "
                         f"the fastest the arm makes (problem.max_speed, {problem.max_speed:.4g} rad/s): saturated "
                         "at the arm's limit; velocities in deg/s? Give rad/s")
    return said


def require_on_grid(proposal: Proposal, problem: Problem, what: str) -> None:
    """Refuse ``proposal`` unless it follows ``problem``: its ``arm`` the columns of
    ``problem.outputs`` after ``velocity``; ``angle``, ``velocity`` and every arm column arrays
    of the shape of ``problem.angles`` (T,), finite; ``angle`` the grid in its order, each
    value within :data:`ANGLE_TOLERANCE` of the spacing.

    Raises
    ------
    InputError
        ``what`` (``attempt 2: the throw faster proposed``), then the first fault found: the arm
        columns, the shapes, the first value that is not finite, the order or the first angle
        off the grid, each with what the grid expects.
    """
    grid = problem.angles
    wanted = tuple(problem.outputs[1:])
    if set(proposal.arm) != set(wanted):
        held = ", ".join(map(str, proposal.arm)) or "nothing"
        if wanted:
            raise InputError(f"{what}: its arm holds {held}; this run's throw drives {', '.join(wanted)} besides the "
                             "elbow (problem.outputs after velocity): give arm those, each an array along "
                             "problem.angles")
        raise InputError(f"{what}: its arm holds {held}; this run's throw drives one joint, the elbow's angle and "
                         "velocity alone: leave arm empty (its default)")
    columns = {"angle": proposal.angle, "velocity": proposal.velocity, **proposal.arm}
    arrays = {}
    for name, values in columns.items():
        try:
            arrays[name] = np.asarray(values, dtype=float)
        except (TypeError, ValueError):
            raise InputError(f"{what}: {name} is {type(values).__name__} {short_repr(values)}, not numbers: "
                             f"{_expected(problem)}") from None
    shaped = [f"{name} of shape {array.shape}" for name, array in arrays.items() if array.shape != grid.shape]
    if shaped:
        raise InputError(f"{what}: {', '.join(shaped)}, where problem.angles, the angle grid every throw "
                         f"follows, has shape {grid.shape}, {_span(grid)}: give every column a value at each "
                         "angle of the grid")
    for name, array in arrays.items():
        bad = np.flatnonzero(~np.isfinite(array))
        if bad.size:
            raise InputError(f"{what}: {name} at sample {bad[0]} is {array[bad[0]]} ({bad.size} of {array.size} "
                             "not finite): every value of a proposal must be a finite number")
    tolerance = ANGLE_TOLERANCE * abs(float(grid[1] - grid[0]))
    off = np.abs(arrays["angle"] - grid) > tolerance
    if not off.any():
        return
    if np.all(np.abs(arrays["angle"] - grid[::-1]) <= tolerance):
        raise InputError(f"{what}: angle runs {_span(arrays['angle'])}, the grid reversed: problem.angles runs "
                         f"{_span(grid)}, the release last; give the throw in the grid's order")
    first = int(np.argmax(off))
    raise InputError(f"{what}: angle at sample {first} is {arrays['angle'][first]:.6g} rad, where problem.angles "
                     f"has {grid[first]:.6g} rad ({_span(grid)}, {grid.size} samples): give the throw at the "
                     "grid's angles")


def _span(angles: np.ndarray) -> str:
    """``from 0.75 to 1.515 rad``: the first and last of ``angles`` (rad)."""
    return f"from {angles[0]:.4g} to {angles[-1]:.4g} rad"


def _expected(problem: Problem) -> str:
    """What a proposal of ``problem`` holds, in words: angle and velocity along the grid, and the
    arm's columns of a whole-arm throw."""
    arm = problem.outputs[1:]
    return (f"angle and velocity, arrays of shape (T,) in rad and rad/s, T = {problem.angles.size}: angle is "
            "problem.angles" + (f"; arm: {', '.join(arm)} along the same samples" if arm else ""))


def short_repr(value) -> str:
    """``repr(value)`` cut to 60 characters, for an error message."""
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."
