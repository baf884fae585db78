"""What to say before a one-joint run that aims by the demonstrations where the kinematics would
likely do better (``aim="auto"``, docs/learn.md: "Aimed by the robot's kinematics, with one
joint")."""

from __future__ import annotations

from rlff.dataset import Dataset


def aim_hint(robot, demos: Dataset) -> str | None:
    """A note for a one-joint run of :func:`rlff.learn.learn` with ``aim="auto"`` (the
    demonstrations' aim) on ``robot`` (a :class:`rlff.robot.Robot`) from ``demos``; None when
    there is nothing to say.

    On a robot file of the user's with a ``[geometry]``: its ``[throwing]`` mapping was likely not
    tuned on that arm, and the kinematics' aim does not need it to be (4-7 more throws than the
    sweep on an untuned UR5e-like file, 1 aimed). On a built-in robot, whose mapping was tuned on
    simulated people, the same for recorded demonstrations (``distance_source`` metadata, which
    ``rlff data import`` writes): the real MSR throws took 1-4 throws a basket, 1 aimed. None for
    simulated people on a built-in robot, and for a file without ``[geometry]``, which cannot aim.
    The words name :func:`learn`'s parameters (``aim='kinematics'``); ``rlff learn`` says its
    options.
    """
    if robot.source == f"built-in robot {robot.name}":
        if not any("distance_source" in t.meta for t in demos):
            return None
        return (f"aim: recorded throws' speeds through the [throwing] mapping of {robot.name}, which was tuned on "
                "simulated people (aim='auto', one joint); aim='kinematics' starts where the arm's geometry sends the "
                "throw (the real MSR throws: a hit at attempt 1 at 1.2-2.2 m, against 1-4 attempts; docs/learn.md); "
                "aim='demonstrations' keeps this and says nothing")
    if robot.geometry is None:
        return None
    return (f"aim: the demonstrations' speeds through the [throwing] mapping of {robot.source} (aim='auto', one "
            "joint); unless that mapping was tuned on this arm, aim='kinematics' starts where its geometry sends the "
            "throw, often at once (docs/learn.md); aim='demonstrations' keeps this and says nothing")
