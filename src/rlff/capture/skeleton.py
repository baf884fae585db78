"""What every recording reader returns: timed 3-D positions of the arm joints of each tracked user.

A reader (ROS bag, Kinect SDK text, MSR Action3D text, CSV) turns a file into a
:class:`Recording`: one :class:`ArmTrack` per (user, side) that the file holds, each made of
three :class:`JointTrack` (shoulder, elbow, hand; optionally the wrist, and the torso's neck and
hip centre) with their own time stamps, because a tf stream publishes every joint on its own and
may drop some of them.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from rlff.errors import InputError

#: Arm sides a reader may report.
SIDES = ("right", "left")
#: The farthest (m) a joint's coordinate lies from the sensor (a bag: its parent frame) as a
#: position: a depth camera sees a few metres (a Kinect up to 4.5 m); beyond (1e30 from a tracker's
#: bad arithmetic) it is no position, a joint not tracked there. Every reader leaves such a joint
#: out of its track in that frame, with a note.
FARTHEST = 100.0


@dataclass(frozen=True)
class JointTrack:
    """Positions of one joint over time.

    Parameters
    ----------
    name : str
        The joint's name in the file (a tf frame, a column, a joint index).
    time : array of shape (T,)
        Time stamps (s), strictly increasing.
    position : array of shape (T, 3)
        Position (m) in the recording's frame.
    """

    name: str
    time: np.ndarray
    position: np.ndarray

    def __post_init__(self) -> None:
        time = np.asarray(self.time, dtype=float)
        position = np.asarray(self.position, dtype=float).reshape(-1, 3)
        if time.shape != (position.shape[0],):
            raise InputError(
                f"joint {self.name!r}: {time.size} time stamps for {position.shape[0]} positions"
            )
        if time.size > 1 and np.any(np.diff(time) <= 0):
            raise InputError(f"joint {self.name!r}: time stamps do not increase")
        object.__setattr__(self, "time", time)
        object.__setattr__(self, "position", position)

    def __len__(self) -> int:
        return self.time.size


@dataclass(frozen=True)
class ArmTrack:
    """One arm of one tracked user.

    Parameters
    ----------
    user : str
        The tracker's user id ("1" for formats with a single skeleton).
    side : str
        "right" or "left".
    shoulder, elbow, hand : JointTrack
        The joints that define the elbow angle (upper arm shoulder→elbow, forearm elbow→hand).
    wrist : JointTrack, optional
        When the format has one: used as the forearm's end for the angle, since the hand joint
        also moves with the wrist's flexion; the hand is still used for the release speed.
    neck, hip : JointTrack, optional
        The torso's top (neck, shoulder centre) and bottom (hip centre) when the format has them:
        the torso's downward axis, neck -> hip, against which the shoulder's elevation is measured.
    """

    user: str
    side: str
    shoulder: JointTrack
    elbow: JointTrack
    hand: JointTrack
    wrist: JointTrack | None = None
    neck: JointTrack | None = None
    hip: JointTrack | None = None

    @property
    def label(self) -> str:
        """A short name for reports: "user 1, right arm"."""
        return f"user {self.user}, {self.side} arm"

    @property
    def forearm_end(self) -> JointTrack:
        """The joint at the far end of the forearm for the angle: the wrist when known, else the hand."""
        return self.wrist if self.wrist is not None else self.hand

    @property
    def n_samples(self) -> int:
        """Samples of the sparsest of the three joints."""
        return min(len(self.shoulder), len(self.elbow), len(self.hand))

    @property
    def untracked(self) -> JointTrack | None:
        """The first joint the elbow angle and the release need (shoulder, elbow, forearm's end,
        hand) with fewer than 2 samples: a joint the tracker never gave; None when there is none."""
        for track in (self.shoulder, self.elbow, self.forearm_end, self.hand):
            if len(track) < 2:
                return track
        return None


@dataclass
class Recording:
    """All arm tracks read from one file, with what the reader noticed.

    Parameters
    ----------
    source : str
        The file (or ROS 2 bag folder) it came from.
    arms : list of ArmTrack
        Every (user, side) the file holds.
    up : array of shape (3,)
        Unit vector pointing up in the recording's frame (against gravity).
    notes : list of str
        Things the reader dropped or repaired (all-zero frames, duplicate frames), for the report.
    warnings : list of str
        Problems the user should look at (a bag damaged at the end, read up to the damage).
    assumed_rate : float, optional
        The frame rate (Hz) the time was made from, for a file without time stamps (Kinect and
        MSR text, a CSV without a time column); None when the samples carry their own time.
    frames_span : (float, float), optional
        Time (s) of the file's first and last frame, tracked or not (a frame whose arm joints are
        all zero is dropped from the tracks but not from the span), for text and CSV; None for a
        bag, whose tf stream has no frame where the tracker lost the user.
    """

    source: str
    arms: list[ArmTrack]
    up: np.ndarray
    notes: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    assumed_rate: float | None = None
    frames_span: tuple[float, float] | None = None

    def users(self) -> list[str]:
        """User ids in order of first appearance."""
        return list(dict.fromkeys(arm.user for arm in self.arms))

    def arm(self, user: str, side: str) -> ArmTrack | None:
        """The arm track of ``user`` on ``side``, or None."""
        for arm in self.arms:
            if arm.user == user and arm.side == side:
                return arm
        return None
