"""Several tracked users in one recording: keep the person who throws, report the others.

A skeleton tracker sometimes sees a second "user" in a reflection or a shadow (thesis 4.2.1):
it flickers in and out, for a few frames at a time, with bones that change length. The person
who throws is tracked for most of the recording with a steady skeleton. Each user is scored by
the number of arm samples divided by (1 + 10 x the relative spread of the upper arm's length).

A bystander is tracked as long and as steadily as the thrower, sometimes longer. Among the users
scoring at least half the best score, the one whose hand sweeps furthest around its shoulder
(norm of the 5-95 percentile range of hand - shoulder, either arm) is kept: the thrower's hand
sweeps about half a metre or more, a bystander's stays near the body. A reflection flickers and
its bones stretch, so it stays far below half the score (4-7 % in the simulated sessions) and its
hand, which mirrors the thrower's plus noise, does not decide.

A tracker that loses the person and finds them again gives them a new user id. A user who is
never tracked at the same time as the kept one (at most 5 % of their samples overlap it) and
whose upper arm has the same length (within 15 %) is taken as the kept person re-acquired: their
samples are joined to the kept user's, and the join is reported.

One thrower is imported per recording. A steady user dropped for a hand that sweeps less, but
still about as far as the thrower's (:data:`THROWER_SHARE`), may have thrown too (two people
taking turns): that is a warning, not a note, and ``user`` (``rlff data import --user``) imports
that user's throws instead.
"""

from __future__ import annotations

import numpy as np

from rlff.capture.angles import positions_at, sweep
from rlff.capture.skeleton import ArmTrack, JointTrack, Recording
from rlff.errors import InputError

#: A user's track is broken into appearances where it has no sample for longer than this (s).
_APPEARANCE_GAP_S = 0.5
#: Re-acquired person: largest share of samples overlapping the kept user, largest bone difference.
_MAX_OVERLAP = 0.05
_MAX_BONE_DIFFERENCE = 0.15
#: Users scoring at least this share of the best score are told apart by how their hand moves.
_COMPARABLE_SCORE = 0.5
#: A dropped steady user whose hand sweeps at least this share of the kept thrower's sweep moved
#: as a thrower does: in the 56 MSR recordings the other hand sweeps 0.37 m at the median, the
#: throwing hand 1.24 m; the test sessions' bystanders under a fifth of the thrower's sweep, a
#: second thrower about as much as the first.
THROWER_SHARE = 0.5


def upper_arm_lengths(arm: ArmTrack) -> np.ndarray:
    """Upper-arm length (m) at each elbow sample, shape (T,)."""
    return np.linalg.norm(positions_at(arm.shoulder, arm.elbow.time) - arm.elbow.position, axis=1)


def hand_sweep(arms: list[ArmTrack]) -> float:
    """How far one user's hand sweeps around its shoulder (m), the arm that moves most: see :func:`sweep`."""
    return max(sweep(arm.hand.position - positions_at(arm.shoulder, arm.hand.time)) for arm in arms)


def bone_spread(arm: ArmTrack) -> float:
    """Relative spread of the upper arm's length: median absolute deviation / median."""
    length = upper_arm_lengths(arm)
    median = float(np.median(length))
    if median <= 0:
        return np.inf
    return float(np.median(np.abs(length - median)) / median)


def _appearances(arm: ArmTrack) -> int:
    return 1 + int(np.sum(np.diff(arm.elbow.time) > _APPEARANCE_GAP_S))


def consistency(arms: list[ArmTrack]) -> float:
    """Score of one user's arms: samples / (1 + 10 x bone spread), best arm."""
    return max(arm.n_samples / (1.0 + 10.0 * bone_spread(arm)) for arm in arms)


def _overlap(arm: ArmTrack, other: ArmTrack) -> float:
    """Share of ``other``'s elbow samples within an appearance of ``arm``."""
    index = np.clip(np.searchsorted(arm.elbow.time, other.elbow.time), 1, len(arm.elbow) - 1)
    before, after = arm.elbow.time[index - 1], arm.elbow.time[index]
    inside = (before <= other.elbow.time) & (other.elbow.time <= after) & (after - before <= _APPEARANCE_GAP_S)
    return float(np.mean(inside))


def _same_person(kept: ArmTrack, other: ArmTrack) -> bool:
    """``other`` is ``kept`` re-acquired under a new id: never tracked together, same upper arm."""
    bone, other_bone = float(np.median(upper_arm_lengths(kept))), float(np.median(upper_arm_lengths(other)))
    return _overlap(kept, other) <= _MAX_OVERLAP and abs(other_bone - bone) <= _MAX_BONE_DIFFERENCE * bone


def _joined(first: JointTrack, second: JointTrack) -> JointTrack:
    time = np.concatenate([first.time, second.time])
    order = np.argsort(time, kind="stable")
    keep = np.ones(time.size, dtype=bool)
    keep[1:] = np.diff(time[order]) > 0
    position = np.concatenate([first.position, second.position])
    return JointTrack(first.name, time[order][keep], position[order][keep])


def _join(kept: ArmTrack, other: ArmTrack) -> ArmTrack:
    optional = {}
    for name in ("wrist", "neck", "hip"):
        mine, theirs = getattr(kept, name), getattr(other, name)
        optional[name] = _joined(mine, theirs) if mine is not None and theirs is not None else None
    return ArmTrack(
        kept.user, kept.side, _joined(kept.shoulder, other.shoulder), _joined(kept.elbow, other.elbow),
        _joined(kept.hand, other.hand), **optional,
    )


def keep_consistent_user(recording: Recording, user: str | None = None) -> tuple[list[ArmTrack], list[str], list[str]]:
    """The arms of the thrower: the steadiest user, or of the steady ones the one whose hand moves most.

    Parameters
    ----------
    recording : Recording
    user : str, optional
        The tracked user to keep instead (its id, as the recording numbers its users).

    Returns
    -------
    arms : list of ArmTrack
        Both sides of the kept user, as far as the recording has them.
    notes : list of str
        One per other user: joined (re-acquired) or dropped (why, samples, appearances, time span).
    warnings : list of str
        A dropped user whose hand swept as a thrower's does: its throws are not imported.

    Raises
    ------
    InputError
        ``user`` is not a user of the recording.
    """
    users = recording.users()
    by_user = {name: [arm for arm in recording.arms if arm.user == name] for name in users}
    if user is not None:
        if str(user) not in by_user:
            raise InputError(f"{recording.source}: no tracked user {user} (--user; its users: {', '.join(users)})")
        others = [name for name in users if name != str(user)]
        notes = [f"{recording.source}: kept tracked user {user} (--user), left out user{'s' if len(others) > 1 else ''} "
                 f"{', '.join(others)}"] if others else []
        return by_user[str(user)], notes, []
    if len(users) <= 1:
        return recording.arms, [], []
    scores = {name: consistency(arms) for name, arms in by_user.items()}
    steady = [name for name in users if scores[name] >= _COMPARABLE_SCORE * max(scores.values())]
    sweeps = {name: hand_sweep(by_user[name]) for name in steady}
    kept = max(steady, key=lambda name: (sweeps[name], scores[name]))
    origin = min(arm.elbow.time[0] for arm in recording.arms)
    arms = {arm.side: arm for arm in by_user[kept]}
    notes, warnings = [], []
    for name in sorted(users, key=lambda name: -scores[name]):
        if name == kept:
            continue
        others = {arm.side: arm for arm in by_user[name]}
        shared = [side for side in others if side in arms]
        if shared and all(_same_person(arms[side], others[side]) for side in shared):
            arms.update({side: _join(arms[side], others[side]) for side in shared})
            notes.append(
                f"{recording.source}: tracked user {name} is user {kept} found again (never tracked together, "
                f"same upper arm): {others[shared[0]].n_samples} samples joined"
            )
            continue
        arm = max(by_user[name], key=lambda a: a.n_samples)
        thrower_like = name in sweeps and sweeps[name] >= THROWER_SHARE * sweeps[kept]
        why = (
            f"tracked about as steadily as user {kept}, but its hand sweeps {sweeps[name]:.2f} m around its "
            f"shoulder against {sweeps[kept]:.2f} m" + ("" if thrower_like else ": not the thrower")
            if name in sweeps else "second skeleton, e.g. a reflection"
        )
        dropped = (
            f"{recording.source}: dropped tracked user {name} ({why}): "
            f"{arm.n_samples} samples in {_appearances(arm)} appearances between "
            f"t={arm.elbow.time[0] - origin:.2f} and {arm.elbow.time[-1] - origin:.2f} s; kept user {kept} "
            f"({max(a.n_samples for a in by_user[kept])} samples)"
        )
        if thrower_like:
            warnings.append(f"{dropped}; its hand swept as a throwing hand does: if user {name} threw too, its "
                            f"throws are not imported (one thrower per recording): import them with --user {name}")
        else:
            notes.append(dropped)
    return list(arms.values()), notes, warnings
