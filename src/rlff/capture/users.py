"""Several tracked users in one recording: keep the person who throws, report the others.

A skeleton tracker sometimes sees a second "user" in a reflection or a shadow (thesis 4.2.1):
it flickers in and out, for a few frames at a time, with bones that change length. The person
who throws is tracked for most of the recording with a steady skeleton. Each user is scored by
the number of arm samples divided by (1 + 10 x the relative spread of the upper arm's length);
the best one is kept.
"""

from __future__ import annotations

import numpy as np

from rlff.capture.skeleton import ArmTrack, Recording

#: A user's track is broken into appearances where it has no sample for longer than this (s).
_APPEARANCE_GAP_S = 0.5


def bone_spread(arm: ArmTrack) -> float:
    """Relative spread of the upper arm's length: median absolute deviation / median."""
    shoulder = np.column_stack(
        [np.interp(arm.elbow.time, arm.shoulder.time, arm.shoulder.position[:, axis]) for axis in range(3)]
    )
    length = np.linalg.norm(shoulder - arm.elbow.position, axis=1)
    median = float(np.median(length))
    if median <= 0:
        return np.inf
    return float(np.median(np.abs(length - median)) / median)


def _appearances(arm: ArmTrack) -> int:
    return 1 + int(np.sum(np.diff(arm.elbow.time) > _APPEARANCE_GAP_S))


def consistency(arms: list[ArmTrack]) -> float:
    """Score of one user's arms: samples / (1 + 10 x bone spread), best arm."""
    return max(arm.n_samples / (1.0 + 10.0 * bone_spread(arm)) for arm in arms)


def keep_consistent_user(recording: Recording) -> tuple[list[ArmTrack], list[str]]:
    """The arms of the most consistent user, and a note for every user dropped.

    Parameters
    ----------
    recording : Recording

    Returns
    -------
    arms : list of ArmTrack
        Both sides of the kept user, as far as the recording has them.
    notes : list of str
        One per dropped user: samples, appearances, time span.
    """
    users = recording.users()
    by_user = {user: [arm for arm in recording.arms if arm.user == user] for user in users}
    if len(users) <= 1:
        return recording.arms, []
    scores = {user: consistency(arms) for user, arms in by_user.items()}
    kept = max(users, key=lambda user: scores[user])
    origin = min(arm.elbow.time[0] for arm in recording.arms)
    notes = []
    for user in users:
        if user == kept:
            continue
        arm = max(by_user[user], key=lambda a: a.n_samples)
        notes.append(
            f"{recording.source}: dropped tracked user {user} (second skeleton, e.g. a reflection): "
            f"{arm.n_samples} samples in {_appearances(arm)} appearances between "
            f"t={arm.elbow.time[0] - origin:.2f} and {arm.elbow.time[-1] - origin:.2f} s; kept user {kept} "
            f"({max(a.n_samples for a in by_user[kept])} samples)"
        )
    return by_user[kept], notes
