"""A method of one's own written as a module in a folder, as a user names it on the command line
(``--update MODULE:CLASS``): the module's text and a folder holding it."""

from __future__ import annotations

import re
from pathlib import Path

#: A module defining the docs' example method, ``Faster`` (name ``faster``), a helper that is no
#: method, and a class that is no Method subclass.
MODULE = '''
from rlff.learn import Method, Proposal, scale_speed


class Faster(Method):
    """The demonstrations' mean throw for the basket, 8 % faster after each miss."""

    name = "faster"
    feedbacks = ("binary", "distance")

    def __init__(self, problem):
        super().__init__(problem)
        path = problem.demonstrations_model().generate({"distance": problem.target}, problem.angles,
                                                       exploration=0.0)
        self.mean = Proposal.of_outputs(path.angle, path.gmr_means, path.output_names, problem.target)

    def propose(self, history):
        return scale_speed(self.mean, 1.08 ** len(history))


def helper():
    return 1


class Plain:
    pass
'''


def write_module(folder: Path) -> str:
    """Write :data:`MODULE` into ``folder`` under a name of its own (one per test: a process
    imports a module once) and return that name."""
    name = "own_" + re.sub(r"\W", "_", folder.name)
    (folder / f"{name}.py").write_text(MODULE)
    return name
