"""The demonstrations as the loop learns from them: the preparation is kept by content, never by
the object, and a dataset that differs in anything gets its own."""

from __future__ import annotations

import numpy as np
import pytest

from rlff.dataset import Dataset
from rlff.learn.demos import loop_components, usable_demos
from rlff.learn.memo import content_digest
from rlff.robot import RobotMapping, load_robot


@pytest.fixture(scope="module")
def clean() -> Dataset:
    from rlff.preprocess import Pipeline
    from rlff.synthetic.throws import simulate_throws

    raw = simulate_throws(5, subjects=3, distances=(1.0, 1.5), throws_per_distance=2)
    return Pipeline.preset("thesis").run(raw)[0]


def _copy(demos: Dataset, **meta) -> Dataset:
    """A new dataset with the same samples; ``meta`` changes the first trajectory's metadata."""
    first, *rest = demos
    return demos.replace([first.replace(meta={**first.meta, **meta}), *rest])


def test_the_same_content_read_anew_gets_the_same_preparation(clean):
    mapping = RobotMapping.for_robot(load_robot())
    usable, notes = usable_demos(clean, mapping, 0.3)
    again, again_notes = usable_demos(_copy(clean), RobotMapping.for_robot(load_robot()), 0.3)
    assert again is usable and again_notes == notes
    assert loop_components(usable, 2) == loop_components(_copy(usable), 2)


def test_demonstrations_that_differ_in_their_metadata_are_prepared_on_their_own(clean):
    mapping = RobotMapping.for_robot(load_robot())
    usable, _ = usable_demos(clean, mapping, 0.3)
    relabelled = _copy(clean, hit=not clean[0].meta.get("hit"), landing=1.23)
    assert content_digest(relabelled) != content_digest(clean)
    other, _ = usable_demos(relabelled, mapping, 0.3)
    assert other is not usable
    assert other[0].meta["landing"] == 1.23 and usable[0].meta.get("landing") != 1.23
    # another rim height is another preparation too
    assert usable_demos(clean, mapping, 0.6)[0] is not usable


def test_every_method_of_a_run_starts_from_one_fit_of_the_demonstrations(clean):
    from rlff.learn.demos import angle_grid, learning_demos
    from rlff.learn.method import Problem, labelled_demos, training_set

    demos = learning_demos(clean)
    problem = Problem(demos, 1.4, "binary", 0.14, angle_grid(demos), 2, 0)
    model = problem.demonstrations_model()
    # the same demonstrations read anew, another basket: the same fit
    again = Problem(_copy(demos), 1.9, "distance", 0.14, angle_grid(demos), 2, 0)
    assert again.demonstrations_model() is model
    # what it is: the plain fit of the labelled demonstrations
    data, _ = training_set(labelled_demos(demos), [1.0] * len(demos))
    np.testing.assert_array_equal(problem.fit(data).mixture.means_, model.mixture.means_)
    # other labels, components or seed: another fit
    assert Problem(_copy(demos, landing=1.23), 1.4, "binary", 0.14, angle_grid(demos), 2, 0).demonstrations_model() \
        is not model
    assert Problem(demos, 1.4, "binary", 0.14, angle_grid(demos), 3, 0).demonstrations_model() is not model
    assert Problem(demos, 1.4, "binary", 0.14, angle_grid(demos), 2, 1).demonstrations_model() is not model
