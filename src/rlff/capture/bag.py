"""Skeleton tracks from ROS 1 and ROS 2 bags: the /tf transforms of the arm joints.

A skeleton tracker (openni_tracker, NiTE2tf) publishes every joint as a tf frame named
``{joint}_{user}``, e.g. ``right_elbow_1``, relative to the camera frame. This module reads the
/tf connections of a bag with rosbags, in one streaming pass (one chunk in memory at a time),
decoding only those connections (``tf/tfMessage`` or ``tf2_msgs/TFMessage``) with the message
definitions stored in the bag; camera images in the same bag are never deserialised.

Arm frames are matched by name without the user number, so every tracked user is found
(``right_elbow_1``, ``right_elbow_2``...) and both arms when the bag has the other side's
frames (``right`` swapped for ``left`` in the names). The torso's frames (:data:`TORSO_NAMES`:
``neck``, the hips, ``torso``) of the same user give the torso's axis when the bag has them; they
are named as the arm frames are, with the same prefix and the same ending before the user number
(``kinect1/neck_1`` beside ``kinect1/right_shoulder_1``, ``neck`` beside ``right_shoulder``).

Bags are opened by :mod:`rlff.capture.bag_stream`, which also reads a ROS 1 bag damaged at the
end up to the damage, and one with a damaged chunk before its end past that chunk, with a warning.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from rlff.capture.angles import median_spacing
from rlff.capture.bag_stream import MissingTopic, open_stream
from rlff.capture.repeated_frames import FROZEN_ENTRY_SPEED, frozen_samples, repeated_track_samples
from rlff.capture.skeleton import FARTHEST, ArmTrack, JointTrack, Recording
from rlff.capture.tf_decode import TfCollector
from rlff.errors import InputError
from rlff.wording import plural

#: Default frames of the throwing arm (NiTE / openni_tracker names, user 1).
DEFAULT_FRAMES = ("right_shoulder_1", "right_elbow_1", "right_hand_1")
DEFAULT_TOPIC = "/tf"
#: NiTE / openni_tracker torso joints: the neck is the torso's top; its bottom is the hip centre
#: (the middle of both hips), or the ``torso`` frame (on the spine, the same axis) when the hips
#: are missing. Their frames are named as the shoulder's (:func:`torso_stems`).
TORSO_NAMES = ("neck", "left_hip", "right_hip", "torso")
#: The NiTE name of a shoulder frame, within a frame name that may add a prefix and an ending.
_SHOULDER = re.compile(r"(?:left|right)_shoulder")
#: Message types of /tf in ROS 1 (tf) and ROS 1/2 (tf2), as rosbags names them.
TF_TYPES = ("tf2_msgs/msg/TFMessage", "tf/msg/tfMessage")
IMAGE_TYPES = ("sensor_msgs/msg/CompressedImage",)
#: Message types that draw a skeleton in rviz (skeleton_markers and the like), which rlff does not read.
MARKER_TYPES = ("visualization_msgs/msg/Marker", "visualization_msgs/msg/MarkerArray")
#: Up in a ROS camera-link frame (x forward, y left, z up: REP 103).
ROS_UP = np.array([0.0, 0.0, 1.0])


def read_bag(
    path: str | Path,
    *,
    topic: str = DEFAULT_TOPIC,
    frames: Sequence[str] = DEFAULT_FRAMES,
) -> Recording:
    """Read the arm joints of every tracked user from a bag's /tf.

    Parameters
    ----------
    path : path of a ROS 1 ``.bag`` file or a ROS 2 bag folder (or a file inside it)
    topic : the tf topic
    frames : (shoulder, elbow, hand) frame names; a trailing number is the tracker's user id
        and matches any user.

    Returns
    -------
    Recording
        Positions (m) in the joints' common parent frame, z up; times are the transforms'
        header stamps (s), or the bag's receive time where a stamp is zero.

    Raises
    ------
    InputError
        Not a bag, a bag without ``topic`` (the topics there are listed), a topic that is not
        tf, the frames missing (the frames there are listed, and those never tracked: every
        transform at exactly (0, 0, 0)), joints relative to different parent frames, a frame
        relative to two parent frames (:func:`_frames`), or a bag so damaged that no /tf message
        could be read. A torso frame never tracked is read as absent (the hip centre then comes
        from the ``torso`` frame), with a note.
    """
    path = Path(path)
    if len(frames) != 3:
        raise InputError(f"frames: expected shoulder, elbow and hand frame names, got {list(frames)}")
    names = [name.lstrip("/") for name in frames]
    stems = [re.sub(r"\d+$", "", name) for name in names]
    sides = _sides(stems)
    torso = torso_stems(stems[0])
    pattern = re.compile(
        "^(?:" + "|".join(re.escape(stem) for stem in [*(s for side in sides.values() for s in side), *(torso or ())])
        + r")(\d*)$"
    )
    wanted: dict[str, bool] = {}

    def keep(child: str) -> bool:
        decision = wanted.get(child)
        if decision is None:
            decision = wanted[child] = pattern.match(child.lstrip("/")) is not None
        return decision

    count = 0
    try:
        with open_stream(path, [topic], TF_TYPES) as stream:
            collector = TfCollector(keep, stream.deserialize)
            for message in stream.messages:
                count += 1
                collector.add(message.raw, message.msgtype, message.digest, message.time_ns)
            collected = collector.finish()
            warnings = stream.warnings
    except MissingTopic as missing:
        raise InputError(f"{missing}{_tf_elsewhere(missing.topics)}") from None
    if collector.skipped:
        warnings.append(f"{path}: skipped {collector.skipped} damaged {topic} messages that could not be decoded")
    if count == 0:
        raise InputError(f"{path}: no message could be read on {topic}" + (f" ({warnings[0]})" if warnings else ""))
    notes: list[str] = []
    frames = _frames(path, collected, notes)
    arms = _arm_tracks(path, frames, sides, torso, notes, warnings)
    if not arms:
        present = sorted({name.lstrip("/") for name in wanted})
        never = sorted(name for name, (_, _, position) in frames.items() if np.all(position == 0.0))
        raise InputError(
            f"{path}: no tracked user has all of the frames {', '.join(stem + 'N' for stem in stems)} on {topic} "
            f"(looked for {', '.join(names)}); frames there: {', '.join(present) if present else 'none'}"
            + (f"; never tracked, every transform at exactly (0, 0, 0): {', '.join(never)}" if never else "")
            + _frames_hint(stems, [name for name in present if name not in never])
        )
    if not any(arm.neck is not None for arm in arms):
        notes.append(f"{path.name}: {_no_torso(torso, names[0])}")
    preferred = re.search(r"(\d+)$", names[0])
    if preferred and not any(arm.user == preferred.group(1) for arm in arms):
        notes.append(f"{path}: no user {preferred.group(1)}; found users {', '.join(sorted({a.user for a in arms}))}")
    return Recording(str(path), arms, ROS_UP, notes, warnings)


def _tf_elsewhere(topics: dict[str, str]) -> str:
    """What to do about a bag without the tf topic asked for, from its ``topics`` (name -> type):
    the tf topic it has under another name, or that skeleton markers are not read."""
    tf = sorted(name for name, kind in topics.items() if kind in TF_TYPES)
    if tf:
        return f"; give --topic {tf[0]}"
    markers = sorted(name for name, kind in topics.items() if kind in MARKER_TYPES)
    if markers:
        return (f"; rlff reads a skeleton from tf (tf/tfMessage or tf2_msgs/TFMessage, a frame per joint as openni_tracker "
                f"and NiTE publish it), not from the visualization markers that draw one ({', '.join(markers)}): record "
                "the tracker's /tf in the bag")
    return ""


def _sides(stems: list[str]) -> dict[str, list[str]]:
    """Frame-name stems of each arm: the given side, and the other when the names say which side."""
    for this, other in (("right", "left"), ("left", "right")):
        if all(this in stem for stem in stems):
            return {this: stems, other: [stem.replace(this, other) for stem in stems]}
    return {"right": stems}


def torso_stems(shoulder_stem: str) -> tuple[str, ...] | None:
    """The torso's frame names without the user number (:data:`TORSO_NAMES`), named as the
    shoulder's frame ``shoulder_stem`` is (without its user number): ``kinect1/right_shoulder_``
    gives ``kinect1/neck_``, ...; ``right_shoulder`` gives ``neck``, .... None when the shoulder's
    frame does not carry NiTE's name (``left_shoulder``, ``right_shoulder``): the torso's frames
    cannot be named after it."""
    match = _SHOULDER.search(shoulder_stem)
    if match is None:
        return None
    before, after = shoulder_stem[:match.start()], shoulder_stem[match.end():]
    return tuple(before + name + after for name in TORSO_NAMES)


def _no_torso(torso: tuple[str, ...] | None, shoulder: str) -> str:
    """What to say of a bag whose torso frames were not found: the names looked for, or why none."""
    if torso is None:
        return (f"torso frames not looked for: the shoulder frame {shoulder} does not carry NiTE's name "
                "(right_shoulder, left_shoulder), after which the neck and hip frames are named")
    neck, left, right, spine = (stem + "N" for stem in torso)
    return f"no torso frames matched: looked for {neck} with {left} and {right}, or with {spine}"


def _frames_hint(stems: list[str], present: list[str]) -> str:
    """``; give --frames A,B,C`` with the frames of the bag named as ``stems`` are (the shoulder,
    elbow and hand without the user number) but for a prefix and an ending (``kinect1/right_elbow_1``,
    ``right_elbow``); empty when the bag has none such."""
    joints = [stem.rstrip("_") for stem in stems]
    there = set(present)
    for name in present:
        at = name.find(joints[0])
        if at < 0:
            continue
        before, after = name[:at], name[at + len(joints[0]):]
        frames = [before + joint + after for joint in joints]
        if all(frame in there for frame in frames):
            return f"; give --frames {','.join(frames)}"
    return ""


def _frames(
    path: Path, collected: dict[tuple[str, str], tuple[np.ndarray, np.ndarray]], notes: list[str],
) -> dict[str, tuple[str, np.ndarray, np.ndarray]]:
    """Per child frame, named without a leading slash: (its parent frame, also without one; stamps
    (T,) in s; translations (T, 3) in m), unsorted, from the collector's (child, parent) pairs. A
    frame written with and without the slash is one frame, as tf2 reads it: its transforms are
    read together, with a note.

    Raises
    ------
    InputError
        A child frame published relative to two parent frames (two trackers publishing frames of
        the same names): its positions are in two frames, which no one track can hold.
    """
    parents: dict[str, set[str]] = {}
    spellings: dict[str, set[str]] = {}
    times: dict[str, list[np.ndarray]] = {}
    positions: dict[str, list[np.ndarray]] = {}
    for (child, parent), (time, position) in collected.items():
        name = child.lstrip("/")
        parents.setdefault(name, set()).add(parent.lstrip("/"))
        spellings.setdefault(name, set()).add(child)
        times.setdefault(name, []).append(time)
        positions.setdefault(name, []).append(position)
    both = sorted(name for name, spelt in spellings.items() if len(spelt) > 1)
    if both:
        notes.append(f"{path.name}: {plural(len(both), 'frame')} published both with and without a leading slash "
                     f"(/{both[0]} and {both[0]}{', ...' if len(both) > 1 else ''}), one frame each as tf2 reads them: "
                     "their transforms read together")
    for name in sorted(parents):
        if len(parents[name]) > 1:
            raise InputError(
                f"{path}: frame {name} is published relative to {len(parents[name])} parent frames "
                f"({', '.join(sorted(parents[name]))}): two trackers publish frames of the same names, and a track "
                "needs one parent; keep one tracker's transforms in the bag (rosbag filter), or publish each "
                "tracker's frames under a prefix of its own and pick one with --frames"
            )
    return {name: (parents[name].pop(), np.concatenate(times[name]), np.concatenate(positions[name]))
            for name in parents}


def _arm_tracks(
    path: Path,
    frames: dict[str, tuple[str, np.ndarray, np.ndarray]],
    sides: dict[str, list[str]],
    torso: tuple[str, ...] | None,
    notes: list[str],
    warnings: list[str],
) -> list[ArmTrack]:
    """Arm tracks for every (user, side) with all three frames (:func:`_frames`), in user order,
    each with the user's torso from the frames named ``torso`` (:func:`torso_stems`) when the bag
    has them; a user whose tracker gave each skeleton several times keeps each once
    (:func:`_skeletons_once`), and a joint a frozen tracker held is left out where it was
    (:func:`_frozen_left_out`). An arm left out because one of its frames is in the bag but was
    never tracked is a warning (it may be the throwing arm); one whose frame the bag lacks, a note."""
    users = sorted({_user_of(name) for name in frames}, key=lambda user: (len(user), user))
    arms = []
    by_name = {name: (parent, _joint_track(name, time, position, notes, path))
               for name, (parent, time, position) in frames.items()}
    # a frame without a transform that is a position was never tracked: left out, as a frame not published
    never = {name for name, (_, track) in by_name.items() if not track.time.size}
    by_name = {name: (parent, track) for name, (parent, track) in by_name.items() if name not in never}
    for user in users:
        _skeletons_once(path, user, by_name, notes)
        _frozen_left_out(path, user, by_name, notes)
        neck, hip = _torso(by_name, torso, user) if torso is not None else (None, None)
        for side, stems in sides.items():
            frame_names = [stem + user for stem in stems]
            missing = [name for name in frame_names if name not in by_name]
            if missing:
                if len(missing) < len(frame_names):  # part of an arm: say why it is not used
                    _arm_left_out(path, f"user {user or '1'}, {side} arm", missing, never, notes, warnings)
                continue
            parents = {by_name[name][0] for name in frame_names}
            if len(parents) > 1:
                raise InputError(
                    f"{path}: frames {', '.join(frame_names)} are relative to different parent frames "
                    f"({', '.join(sorted(parents))}); they need one common parent"
                )
            joints = [by_name[name][1] for name in frame_names]
            if neck is not None and by_name[neck.name][0] != by_name[frame_names[0]][0]:
                notes.append(f"{path.name}: user {user or '1'}: torso frames relative to another parent, not used")
                arms.append(ArmTrack(user or "1", side, *joints))
            else:
                arms.append(ArmTrack(user or "1", side, *joints, neck=neck, hip=hip))
    return arms


def _arm_left_out(
    path: Path, arm: str, missing: list[str], never: set[str], notes: list[str], warnings: list[str],
) -> None:
    """Say why ``arm`` (``user 1, right arm``) is left out: its ``missing`` frames, those of them
    in the bag but ``never`` tracked (a warning, as the text readers give for a joint never
    tracked) apart from those the bag does not have (a note: another tracker's names)."""
    absent = [name for name in missing if name not in never]
    untracked = [name for name in missing if name in never]
    why = ([f"no frame {', '.join(absent)}"] if absent else []) + (
        [f"frame {', '.join(untracked)} {'is' if len(untracked) == 1 else 'are'} in the bag but was never "
         "tracked (not one transform a position)"] if untracked else [])
    if untracked:
        warnings.append(f"{path}: {arm} left out: {'; '.join(why)}")
    else:
        notes.append(f"{path.name}: {arm} left out: {'; '.join(why)}")


def _frozen_left_out(path: Path, user: str, by_name: dict[str, tuple[str, JointTrack]], notes: list[str]) -> None:
    """Leave out, in place, the transforms of ``user``'s frames that a frozen tracker repeated
    (:func:`~rlff.capture.repeated_frames.frozen_samples`: a joint's translation again, exactly,
    with new stamps while it moved), as the text readers do, with a note per frame: read as
    positions, they stopped the joint dead and its catching up made a throw peak too fast."""
    for name in [name for name in by_name if _user_of(name) == user]:
        parent, track = by_name[name]
        held = frozen_samples(track.position, track.time)
        if held.any():
            by_name[name] = (parent, JointTrack(track.name, track.time[~held], track.position[~held]))
            notes.append(f"{path.name}: frame {name}: {plural(int(held.sum()), 'transform')} repeating its translation "
                         "of the one before exactly while it was moving (a frozen tracker): left out of its track, the "
                         "motion bridged across")


def _user_of(name: str) -> str:
    """The tracker's user number a frame name ends with (``right_elbow_1``: ``1``; empty without one)."""
    return re.search(r"(\d*)$", name.lstrip("/")).group(1)


def _skeletons_once(path: Path, user: str, by_name: dict[str, tuple[str, JointTrack]], notes: list[str]) -> None:
    """Leave out, in place, the repeats of a tracker that gave each of ``user``'s skeletons several
    times with new stamps (a node publishing its last skeleton on a timer faster than the camera),
    as the text readers do (:func:`~rlff.capture.repeated_frames.repeated_track_samples`), with a note."""
    names = [name for name in by_name if _user_of(name) == user]
    tracks = [by_name[name][1] for name in names]
    found = repeated_track_samples([t.time for t in tracks], [t.position for t in tracks], FROZEN_ENTRY_SPEED)
    if found is None:
        return
    keep, rows, kept_rows, times = found
    for name, track, kept in zip(names, tracks, keep, strict=True):
        by_name[name] = (by_name[name][0], JointTrack(track.name, track.time[kept], track.position[kept]))
    notes.append(f"{path.name}: user {user or '1'}: {int((~kept_rows).sum())} of {rows.size} skeletons repeat the one "
                 f"before in every joint, in motion too, with new stamps: the tracker gives each skeleton {times} times "
                 f"({1 / median_spacing(rows):.3g} Hz of {1 / median_spacing(rows[kept_rows]):.3g} Hz skeletons); the "
                 "repeats left out, the skeletons read at their own rate")


def _torso(
    by_name: dict[str, tuple[str, JointTrack]], stems: tuple[str, ...], user: str,
) -> tuple[JointTrack | None, JointTrack | None]:
    """The user's neck and hip centre tracks from the frames ``stems`` + ``user`` (None, None
    without a neck or anything below it)."""
    neck_name, left_name, right_name, torso_name = (stem + user for stem in stems)
    if neck_name not in by_name:
        return None, None
    neck = by_name[neck_name][1]
    if left_name in by_name and right_name in by_name and by_name[left_name][0] == by_name[right_name][0]:
        left, right = by_name[left_name][1], by_name[right_name][1]
        inside = (left.time >= right.time[0]) & (left.time <= right.time[-1])
        if inside.sum() >= 2:
            stamps = left.time[inside]
            other = np.column_stack([np.interp(stamps, right.time, right.position[:, k]) for k in range(3)])
            return neck, JointTrack(f"hip centre {user}", stamps, 0.5 * (left.position[inside] + other))
    if torso_name in by_name:
        return neck, by_name[torso_name][1]
    return None, None


def never_tracked(count: int) -> str:
    """What a frame whose ``count`` transforms all lie at exactly (0, 0, 0) is, in words."""
    every = "its one transform is" if count == 1 else f"every one of its {count} transforms is"
    return (f"{every} at exactly (0, 0, 0), the camera's origin: a joint the tracker never detected, read as a frame "
            "the bag does not have")


def _joint_track(name: str, time: np.ndarray, position: np.ndarray, notes: list[str], path: Path) -> JointTrack:
    """A joint track with its samples in time order, repeated stamps dropped (keeping the last)
    and the transforms that are no position left out, each kind with a note, as the text readers
    leave out a joint not tracked in a frame: at exactly (0, 0, 0) (the camera's origin: a joint
    the tracker did not detect, as NiTE gives one it has no confidence in), a nan or inf, or a
    coordinate beyond :data:`~rlff.capture.skeleton.FARTHEST`. Without a sample when no transform was a position (a joint
    never detected: :func:`_arm_tracks` leaves such a frame out, saying so)."""
    at_origin = np.all(position == 0.0, axis=1)
    finite = np.all(np.isfinite(position), axis=1)
    far = finite & np.any(np.abs(position) > FARTHEST, axis=1)
    if at_origin.all():
        notes.append(f"{path.name}: frame {name}: {never_tracked(int(at_origin.sum()))}")
        return JointTrack(name, time[:0], position[:0])
    if (at_origin | ~finite | far).all():
        notes.append(f"{path.name}: frame {name}: none of its {plural(time.size, 'transform')} is a position (at exactly "
                     f"(0, 0, 0), nan or inf, or beyond {FARTHEST:g} m): a joint the tracker never gave, read as a frame "
                     "the bag does not have")
        return JointTrack(name, time[:0], position[:0])
    if at_origin.any():
        notes.append(f"{path.name}: frame {name}: left out {int(at_origin.sum())} transforms at exactly (0, 0, 0), the "
                     "camera's origin (a joint the tracker did not detect)")
    if not finite.all():
        notes.append(f"{path.name}: frame {name}: left out {plural(int((~finite).sum()), 'transform')} with a nan or inf "
                     "in its translation, taken as not tracked there (as a nan in text)")
    if far.any():
        notes.append(f"{path.name}: frame {name}: left out {plural(int(far.sum()), 'transform')} with a coordinate beyond "
                     f"{FARTHEST:g} m of its parent frame, farther than a depth camera sees: taken as not tracked there")
    kept = ~(at_origin | ~finite | far)
    time, position = time[kept], position[kept]
    order = np.argsort(time, kind="stable")
    time, position = time[order], position[order]
    keep = np.ones(time.size, dtype=bool)
    keep[:-1] = np.diff(time) > 0
    if not keep.all():
        notes.append(f"{path.name}: frame {name}: dropped {int((~keep).sum())} transforms repeating a time stamp")
    return JointTrack(name, time[keep], position[keep])


# -- camera frames ---------------------------------------------------------------------------------


def image_topics(path: str | Path) -> list[str]:
    """Topics of compressed camera images in a bag (a damaged ROS 1 bag is scanned for them)."""
    with open_stream(Path(path), [], None) as stream:
        for _ in stream.messages:  # a scan learns the topics as it reads; an indexed bag knows them
            pass
        return sorted(topic for topic, kind in stream.topics.items() if kind in IMAGE_TYPES)


def images_near(path: str | Path, topic: str, times: Sequence[float]) -> tuple[list[tuple[float, bytes] | None], list[str]]:
    """The compressed image closest in time to each of ``times``.

    Parameters
    ----------
    path : the bag
    topic : a topic of ``sensor_msgs/CompressedImage``
    times : stamps (s, the clock of the /tf stamps)

    Returns
    -------
    frames : list, one per time: (stamp, encoded bytes) or None when the topic is empty
    warnings : problems met while reading
    """
    wanted = np.asarray(times, dtype=float)
    best: list[tuple[float, float, bytes] | None] = [None] * wanted.size
    with open_stream(Path(path), [topic], IMAGE_TYPES) as stream:
        for message in stream.messages:
            image = stream.deserialize(message.raw, message.msgtype)
            stamp = image.header.stamp.sec + image.header.stamp.nanosec * 1e-9 or message.time_ns * 1e-9
            error = np.abs(wanted - stamp)
            for index in np.flatnonzero([b is None or e < b[0] for b, e in zip(best, error, strict=True)]):
                best[index] = (float(error[index]), stamp, bytes(image.data))
        warnings = list(stream.warnings)
    return [None if b is None else (b[1], b[2]) for b in best], warnings
