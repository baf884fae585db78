"""The demonstrations as the learning loop learns from them.

Before its first throw :func:`rlff.learn.learn` reduces the demonstrations to the columns it
learns from (:func:`learning_demos`), keeps those the robot can execute (:func:`usable_demos`),
chooses the number of mixture components by BIC (:func:`loop_components`) and lays out the angle
grid every throw follows (:func:`angle_grid`).

The same preparation serves basket after basket: the demo's choice of a learning basket and its
whole-arm part (:func:`rlff.learn.loop.learnable_basket`, then :func:`rlff.learn.learn`, for
every basket) and a benchmark's methods ask for it again and again with the same
demonstrations. So the two costly steps (the limits check maps every demonstration to the robot;
BIC fits a mixture per candidate K) keep their last few results, looked up by a digest of
everything their inputs hold (:class:`rlff.learn.memo.ByContent`): equal inputs give the very same result, so a
run is as it was without the store, only its start-up is shorter.
"""

from __future__ import annotations

import hashlib
import math
from collections.abc import Sequence

import numpy as np

from rlff.dataset import Dataset, check_units, joint_outputs
from rlff.errors import InputError
from rlff.learn.memo import ByContent, content_digest
from rlff.learn.method import COLUMNS, ONE_JOINT_OUTPUTS
from rlff.limits import DISTANCE_RANGE
from rlff.wording import plural

#: Quantiles of the demonstrations' last angles where a one-joint run's throws may let go, and how
#: a note says each: the first where most demonstrations still cover the whole path, the later ones
#: only for a basket beyond or near the edge of its reach (:func:`rlff.learn.loop.release_quantile`).
RELEASE_WORDS = {
    0.25: "where the demonstrations let go",
    0.5: "where half of the demonstrations had let go",
    0.75: "where three quarters of the demonstrations had let go",
    1.0: "where the last of the demonstrations let go",
}
RELEASE_QUANTILES = tuple(RELEASE_WORDS)
#: Quantile of the demonstrations' last angles where generated throws release by default.
RELEASE_QUANTILE = RELEASE_QUANTILES[0]
#: Most mixture components the loop uses.
MAX_COMPONENTS = 4
#: Fewest points of a generated throw.
MIN_POINTS = 30
#: Most demonstration samples the mixture is refitted to at every attempt.
MAX_SAMPLES = 600

_USABLE = ByContent()
_COMPONENTS = ByContent()


def _mapping_digest(mapping) -> str:
    """Digest of what a throw through ``mapping`` depends on (:func:`rlff.learn.log.robot_record`)."""
    from rlff.learn.log import robot_record

    return robot_record(mapping)["digest"]


def fingerprint(demos: Dataset) -> str:
    """Short hash of the demonstrations' samples and labels: a log resumes only for the same data.

    The one-joint columns, then any other joint's columns in name order (a one-joint set hashes
    as it always did)."""
    digest = hashlib.sha256()
    for trajectory in demos:
        columns = COLUMNS + tuple(sorted(set(trajectory.columns) - set(COLUMNS)))
        digest.update(trajectory.id.encode())
        digest.update(np.ascontiguousarray(trajectory.to_array(columns)).tobytes())
        digest.update(repr(trajectory.meta.get("landing")).encode())
    return digest.hexdigest()[:16]


def learning_demos(demos: Dataset, human_columns: Sequence[str] = ("angle",), rim_height: float | None = None,
                    max_samples: int = MAX_SAMPLES, driven_joints: Sequence[str] = ()) -> Dataset:
    """The demonstrations reduced to the columns the loop learns from, thinned if dense.

    The columns are ``angle``, ``distance``, ``velocity`` and, for a whole-arm throw, every
    other driven joint's position and velocity (``human_columns``: the mapping's, ``"angle"``
    first). Demonstrations labelled with a rim ``height`` (m) are kept only at the height
    nearest ``rim_height``. Densified demonstrations (a sample every 0.01 rad) repeat
    themselves; the mixture is refitted at every attempt, so every k-th sample of each throw is
    kept (its release sample always) until the set has at most ``max_samples`` samples. A
    throw's ``measured_share`` (the share of its samples that stand for a measurement, which BIC
    counts) grows by what thinning dropped: the kept samples still rest on the same
    measurements, up to one each. ``driven_joints`` (the robot joints, in the order of
    ``human_columns``) name the joint whose column is missing in the error.
    """
    columns = COLUMNS + joint_outputs(human_columns)[1:]
    demos.require(COLUMNS)
    missing = [c for c in columns if c not in demos.columns]
    if missing:
        human = missing[0].removesuffix("_velocity")
        joint = dict(zip(human_columns, driven_joints, strict=False)).get(human)
        follows = f"which {joint} follows" if joint else f"which the throw driving {', '.join(human_columns)} needs"
        leave = f"leave {joint} out of --joints (or drop --joints: the elbow alone)" if joint else "drop --joints"
        raise InputError(f"the demonstrations have no column {missing[0]!r}, {follows}; columns: "
                         f"{', '.join(demos.columns)}. Capture the {human} too (rlff data import; simulated: "
                         f"rlff data synth throws --whole-arm --joints shoulder,elbow,wrist) or {leave}")
    if rim_height is not None and "height" in demos.columns:
        demos = _at_nearest_height(demos, rim_height)
    if len(demos) < 2:
        raise InputError(f"learning needs at least 2 demonstrations, got {len(demos)}")
    step = max(1, math.ceil(demos.n_samples / max_samples))
    thinned = []
    for t in demos:
        keep = np.unique(np.r_[np.arange(0, len(t), step), len(t) - 1])
        meta = dict(t.meta)
        if "measured_share" in meta:
            meta["measured_share"] = min(1.0, float(meta["measured_share"]) * len(t) / keep.size)
        thinned.append(t.replace(data={c: t[c][keep] for c in columns}, meta=meta))
    return Dataset(thinned, context=("distance",))


def _at_nearest_height(demos: Dataset, rim_height: float) -> Dataset:
    """The demonstrations whose ``height`` label (m) is the one nearest ``rim_height`` (m)."""
    heights = np.array([float(t["height"][0]) for t in demos])
    nearest = heights[int(np.argmin(np.abs(heights - rim_height)))] if heights.size else rim_height
    return demos.replace([t for t, h in zip(demos, heights, strict=True) if h == nearest])


def require_units(demos: Dataset) -> None:
    """:class:`InputError` when the demonstrations' basket distances, joint angles or velocities
    are not metres, radians and rad/s (:func:`rlff.dataset.check_units`: a velocity in deg/s by
    the angle's change over the ``time`` column, or, without one, by a peak faster than a
    person's joint turns), or their landings (``landing`` metadata) are farther than
    :data:`rlff.limits.DISTANCE_RANGE`'s top either way.

    In centimetres, the landings had put every throw the calibration made behind the arm's base
    (-2.05 m from a basket at 1.75 m); in deg/s, the velocities sent every throw to the speed
    limit, the same throw each time, 0.33 m long. Both runs missed to their end."""
    check_units(demos, lambda column: f"the demonstrations' column {column!r}")
    high = DISTANCE_RANGE[1]
    landings = np.array([float(t.meta.get("landing", np.nan)) for t in demos])
    far = np.isfinite(landings) & (np.abs(landings) > high)
    if far.any():
        first = int(np.flatnonzero(far)[0])
        raise InputError(f"{np.count_nonzero(far)} of the {len(demos)} demonstrations' landings (metadata "
                         f"'landing') lie beyond {high:g} m (throw {demos[first].id} at {landings[first]:.4g}): "
                         "centimetres? landings are in metres from the thrower; leave the metadata out where "
                         "they are not known")


def drives_whole_arm(mapping) -> bool:
    """Whether ``mapping`` is the ``[whole_arm]`` table's (any joints but the ``[throwing]``
    table's one joint alone, :func:`rlff.robot.mapping_for`), even with one joint driven."""
    from rlff.robot.mapping import ArmMapping

    return isinstance(mapping, ArmMapping)


def usable_demos(demos: Dataset, mapping, rim_height: float) -> tuple[Dataset, list[str]]:
    """The demonstrations as :func:`rlff.learn.learn` learns from them through ``mapping`` at a rim
    of ``rim_height`` (m): :func:`learning_demos`, then :func:`demos_within_limits`, and the notes
    on what was left out (:func:`rlff.learn.loop.learnable_basket` judges the reach on the same set).
    Kept by content (module notes)."""
    def compute() -> tuple[Dataset, tuple[str, ...]]:
        measured, placeholders = measured_landings(demos)
        usable, notes = demos_within_limits(
            learning_demos(measured, mapping.human_columns, rim_height, driven_joints=mapping.driven_joints), mapping)
        return usable, tuple(placeholders + notes)

    usable, notes = _USABLE.get((content_digest(demos), _mapping_digest(mapping), float(rim_height)), compute)
    return usable, list(notes)


def measured_landings(demos: Dataset) -> tuple[Dataset, list[str]]:
    """The demonstrations without the ``landing`` metadata that are no landing (0 m or nearer:
    :func:`rlff.learn.method.recorded_landings`), and a note saying how many there were. A table
    that writes 0 or -1 for "not measured" had those taken as throws that came down at the
    thrower's feet by the speed law of the known landings, and the first throw went 0.58 m long
    where the same table with blanks hit at the second."""
    landed = np.array([float(t.meta.get("landing", np.nan)) for t in demos])
    dropped = landed <= 0  # NaN (not measured) stays as it is
    if not dropped.any():
        return demos, []
    values = sorted({float(v) for v in landed[dropped]}, reverse=True)
    trajectories = [t.replace(meta={k: v for k, v in t.meta.items() if k != "landing"}) if drop else t
                    for t, drop in zip(demos, dropped, strict=True)]
    count = int(dropped.sum())
    note = (f"{count} of the {len(demos)} demonstrations' landings (metadata 'landing') {'is' if count == 1 else 'are'} "
            f"{', '.join(f'{v:g}' for v in values[:3])}{', ...' if len(values) > 3 else ''} m, where no ball "
            "comes down: taken as not measured (leave a landing blank where it was not measured)")
    return demos.replace(trajectories), [note]


def demos_within_limits(demos: Dataset, mapping) -> tuple[Dataset, list[str]]:
    """The demonstrations whose paths map inside the driven joints' position ranges, and a note
    naming those left out.

    Speeds beyond the robot's limits are allowed (the robot saturates when it executes a throw
    that fast), but a path outside a joint's range is not a throw this robot can make: it is
    left out with a note (one of the 45 cleaned real MSR throws maps beyond joint_2's range with
    the whole arm, and refusing them all for it left nothing to learn from). When fewer than two are
    left the mapping does not fit the data: :class:`InputError` naming the first. A whole-arm
    throw checks every driven joint.
    """
    kept, beyond = [], []
    for demo in demos:
        angle = demo["angle"]
        path = {column: demo[column] for column in demo.columns if column != "distance"}
        path["velocity"] = forward_velocity(angle, demo["velocity"])
        try:
            _, report = mapping.path_to_robot(path, clip=True)
        except InputError as exc:
            raise InputError(
                f"demonstration {demo.id!r} is not one throw up to its release ({exc}); clean "
                "the demonstrations first (rlff data preprocess --preset thesis, or --config STEPS.toml; in "
                "Python rlff.preprocess.Pipeline.preset('thesis').run(demos))"
            ) from None
        if not report.count("position"):
            kept.append(demo)
        elif drives_whole_arm(mapping):
            joints = sorted({c.joint for c in report.changes if c.quantity == "position"})
            beyond.append((demo.id, f"maps outside {', '.join(joints)}'s range ({report.summary()})",
                           "the robot file's [whole_arm] mapping"))
        else:
            positions = mapping.angle_offset + mapping.angle_scale * angle[[0, -1]]
            beyond.append((demo.id, f"maps to {mapping.joint} positions {positions[0]:.3f} .. "
                           f"{positions[1]:.3f} rad ({report.summary()})", "the robot file's [throwing] mapping"))
    if not beyond:
        return demos, []
    name, why, where = beyond[0]
    if len(kept) < 2:
        verb = "is" if len(beyond) == 1 else "are"
        raise InputError(f"demonstration {name!r} is beyond the robot's joint limits: its path {why}; "
                         f"{len(beyond)} of {plural(len(demos), 'demonstration')} {verb} beyond them, which leaves too "
                         f"few to learn from; check {where}")
    names = ", ".join(repr(n) for n, _, _ in beyond[:3]) + (", ..." if len(beyond) > 3 else "")
    whose = "its" if len(beyond) == 1 else "the first's"
    note = (f"left out {plural(len(beyond), 'demonstration')} of {len(demos)} beyond the robot's joint "
            f"limits: {names} ({whose} path {why}); learning from the other {len(kept)}")
    return demos.replace(kept), [note]


def angle_grid(demos: Dataset, release: float = RELEASE_QUANTILE) -> np.ndarray:
    """The angle grid (rad) of generated throws, shape (T,).

    From the median first angle to the release angle, with the median number of samples of a
    demonstration (at least ``MIN_POINTS``). The release is the ``release`` quantile of the
    demonstrations' last angles; the default, :data:`RELEASE_QUANTILE`, is early enough that most
    demonstrations cover the whole path, so the mixture's velocity at the release rests on most of
    them rather than on the few that went farthest.
    """
    first = float(np.median([t["angle"][0] for t in demos]))
    last = float(np.quantile([t["angle"][-1] for t in demos], release))
    count = int(np.median([len(t) for t in demos]))
    if first == last:
        raise InputError("the demonstrations do not move: first and last angles coincide")
    return np.linspace(first, last, max(count, MIN_POINTS))


def loop_components(demos: Dataset, seed: int, outputs: tuple[str, ...] = ONE_JOINT_OUTPUTS) -> int:
    """Number of mixture components, chosen once by BIC on the demonstrations (kept by content,
    module notes).

    At most ``MAX_COMPONENTS``: the loop asks the mixture for distances beyond the
    demonstrations, where many small components make the regression wiggle.
    """
    from rlff.model import Model

    def compute() -> int:
        model = Model.fit(demos, inputs=("angle", "distance"), outputs=outputs,
                          components="auto", max_components=MAX_COMPONENTS, seed=seed)
        return int(model.n_components)

    return _COMPONENTS.get((content_digest(demos), int(seed), tuple(outputs)), compute)


def typical_throw(mapping, demos: Dataset, release: float = RELEASE_QUANTILE) -> dict[str, np.ndarray]:
    """The demonstrations' typical whole-arm throw along the loop's angle grid (let go at the
    ``release`` quantile of their last angles, :func:`angle_grid`): the median of each column of
    :func:`joint_outputs` (T,), the elbow's velocity forward."""
    angles = angle_grid(demos, release)
    typical = {"angle": angles}
    for column in joint_outputs(mapping.human_columns):
        typical[column] = np.median([np.interp(angles, t["angle"], t[column]) for t in demos], axis=0)
    typical["velocity"] = forward_velocity(angles, typical["velocity"])
    return typical


#: The speed (rad/s) a proposal with no forward motion at all is thrown at (:func:`forward_velocity`).
CRAWL = 0.1


def forward_velocity(angle: np.ndarray, velocity: np.ndarray, crawl: float = CRAWL) -> np.ndarray:
    """Velocity (rad/s), shape (T,), with any sample against the direction of motion set to 0.

    A mixture's output may dip just below zero where a throw starts from rest; a joint cannot
    move backwards along a path that goes forwards. A proposal with no forward motion at all
    (a DMM mode on the wrong side of zero everywhere) is executed as a crawl at ``crawl``
    rad/s: the robot moves along the path and the ball drops, a miss like any other.
    """
    direction = math.copysign(1.0, float(angle[-1] - angle[0]))
    speed = np.maximum(direction * np.asarray(velocity, dtype=float), 0.0)
    if not np.any(speed > 0):
        speed = np.full(speed.shape, crawl)
    return direction * speed
