"""Steps 6-9 (thesis 4.3.2-4.3.3): make the throws regular enough for a mixture model.

6. append a stop point, 10 % beyond the last angle with zero velocity (the thesis found that it
   anchors the mixture badly, so the preset leaves it off);
7. rescale each trajectory so that all end at the mean final angle;
8. densify: anchor points at 1/4, 1/2, 3/4 between samples, a spline through them, resampled at
   a fixed angle step;
9. cut at the release, at a fixed angle or at a point estimated from the velocity profile.

The angle must be monotonic for steps 8 and 9 (steps 2-3 make it so).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Literal

import numpy as np
from scipy.interpolate import Akima1DInterpolator, PchipInterpolator, make_interp_spline

from rlff.dataset import ARM_JOINT_COLUMNS, MIN_FILE_SAMPLES, Dataset, Trajectory
from rlff.dataset import velocity_column as velocity_of
from rlff.errors import InputError
from rlff.limits import MAX_DENSIFY_SAMPLES, check_count
from rlff.preprocess.report import StepReport

#: Samples per second of a recording that BIC counts as independent measurements (``densify``'s
#: ``independent_rate``, Hz). A skeleton tracker's joint positions are smoothed over frames and a
#: human throw carries little motion above about 15 Hz, so frames closer than 1/30 s repeat
#: what their neighbours measured. Counting every frame made the model depend on the camera: the
#: same 26 MSR throws, resampled from 15 Hz, got K = 2 at 15 Hz and K = 8 (the top of the
#: range, one thin band a throw) at 60-120 Hz, and the generated throw for 1.5 m went from 12.7
#: to 31.1 rad/s, faster than any demonstration. 30 Hz leaves a Kinect's recordings (the
#: thesis') and slower ones as they were.
INDEPENDENT_RATE = 30.0


def _direction(values: np.ndarray) -> float:
    """+1 when the trajectory's angle goes up overall, -1 when it goes down (0 if flat)."""
    return float(np.sign(values[-1] - values[0]))


def stop_point(
    dataset: Dataset,
    *,
    column: str = "angle",
    velocity_column: str = "velocity",
    extension: float = 0.10,
) -> tuple[Dataset, StepReport]:
    """Append a sample at rest, ``extension`` (10 %) beyond each trajectory's last angle.

    The new angle is ``last * (1 + extension)`` (the thesis' choice; beyond the last angle in the
    direction of motion for negative angles), its velocity 0. A ``time`` column gets the time of
    a uniform deceleration from the last velocity (one median time step when that velocity is not
    towards the new point); the other joints (``shoulder``, ``wrist``) stay where they were, at
    rest (their velocities 0 too); other columns repeat their last value.
    """
    dataset.require([column, velocity_column])
    if not extension > 0:
        raise InputError(
            f"extension {extension}: must be positive (the stop point's distance beyond the last {column}, "
            "a share of it: 0.10 is 10 %)"
        )
    params = {"column": column, "velocity_column": velocity_column, "extension": extension}
    report = StepReport("stop_point", params, dataset)
    out = []
    for trajectory in dataset:
        values = trajectory[column]
        last = float(values[-1])
        direction = _direction(values) or 1.0
        stop = last + direction * extension * abs(last)
        added = {name: np.append(trajectory[name], trajectory[name][-1]) for name in trajectory.columns}
        added[column] = np.append(values, stop)
        added[velocity_column] = np.append(trajectory[velocity_column], 0.0)
        for joint in ARM_JOINT_COLUMNS:
            if joint != column and velocity_of(joint) in added:
                added[velocity_of(joint)][-1] = 0.0
        if "time" in trajectory.columns:
            time = trajectory["time"]
            speed = float(trajectory[velocity_column][-1]) * np.sign(stop - last)
            step = float(np.median(np.diff(time))) if time.size > 1 else 0.1
            duration = 2.0 * abs(stop - last) / speed if speed > 0 and stop != last else step
            added["time"] = np.append(time, time[-1] + max(duration, 1e-9))
        out.append(trajectory.replace(data=added))
        report.change_samples(trajectory.id, 0, 1, f"stop point at {column} {stop:.4g} with zero {velocity_column}")
    report.after = dataset.replace(out)
    return report.after, report


#: Largest factor :func:`rescale` moves a trajectory by (and smallest, its inverse): a throw that
#: needs more covers less than half of the others' extension, cut short or begun late. Real throws
#: end within 0.81-1.29 of the mean final angle (the MSR throws; the simulated people 0.96-1.13),
#: and a whole-arm person's short throw, whose shoulder does the work, 0.95-1.7; an MSR throw whose
#: extension the tracker ended at 1.38 rad needed 2.5, and a tester's throw cut at the top of its
#: extension 3.9: stretched, they became slow sweeps that no person threw.
MAX_RESCALE = 2.0


def rescale(
    dataset: Dataset,
    *,
    column: str = "angle",
    mode: Literal["scale", "stretch"] = "scale",
    reference: Literal["mean", "min", "max"] = "mean",
    scale_velocity: bool = False,
    velocity_column: str = "velocity",
    max_factor: float = MAX_RESCALE,
) -> tuple[Dataset, StepReport]:
    """Rescale each trajectory's ``column`` so that all end at the same value.

    Parameters
    ----------
    dataset : Dataset
    column : str
    mode : {"scale", "stretch"}
        "scale" multiplies the whole trajectory by ``end / last`` (the thesis, whose angles start
        near zero); "stretch" keeps each trajectory's first value and stretches the rest, which
        suits angles that start far from zero (rlff's elbow angle starts near 0.7 rad).
    reference : {"mean", "min", "max"}
        The common end: the mean (thesis), smallest or largest of the last values.
    scale_velocity : bool
        Multiply the velocity by the same factor (the thesis did not: only positions move).
    velocity_column : str
    max_factor : float
        Largest factor a trajectory is moved by, and 1 / ``max_factor`` the smallest (>= 1;
        inf: any). Default :data:`MAX_RESCALE`.

    The common end is taken over the trajectories kept. A trajectory whose factor is not positive
    and finite is removed with the reason: stretched, a throw that starts beyond the common end
    would run backwards while its velocity stays forward (a negative factor), one whose last
    value is its first has none. So is one whose factor lies beyond ``max_factor`` (a throw cut
    short, whose shape rescaling would make up), judged first against the median end (which one
    such throw cannot move as it moves the mean, or become as the min or max); the common end is
    then taken without it.
    """
    dataset.require([column] + ([velocity_column] if scale_velocity else []))
    if not (isinstance(max_factor, (int, float)) and not isinstance(max_factor, bool) and max_factor >= 1):
        raise InputError(f"rescale max_factor {max_factor!r}: must be a number >= 1 (inf: any factor)")
    params = {"column": column, "mode": mode, "reference": reference,
              "scale_velocity": scale_velocity, "velocity_column": velocity_column, "max_factor": max_factor}
    report = StepReport("rescale", params, dataset)
    if not len(dataset):
        report.after = dataset
        return dataset, report
    # a throw cut short (or long) is judged against the median end first, which it cannot move
    # as it moves the mean, or become as the min or the max
    median = float(np.median([t[column][-1] for t in dataset]))
    kept = []
    for trajectory in dataset:
        pivot = 0.0 if mode == "scale" else float(trajectory[column][0])
        factor, problem = _rescale_factor(trajectory[column], pivot, median, mode, column, max_factor)
        if problem and factor > 0 and math.isfinite(factor):  # beyond max_factor of the median end
            report.remove(trajectory.id, problem.replace(f"to end at {median:.4g}", f"to end at {median:.4g} (the median end)"))
        else:
            kept.append(trajectory)
    while kept:  # the common end of the trajectories kept, until none is refused by it
        end = float({"mean": np.mean, "min": np.min, "max": np.max}[reference]([t[column][-1] for t in kept]))
        pivots = [0.0 if mode == "scale" else float(t[column][0]) for t in kept]
        factors = [_rescale_factor(t[column], pivot, end, mode, column, max_factor) for t, pivot in zip(kept, pivots, strict=True)]
        refused = [(t, problem) for t, (_, problem) in zip(kept, factors, strict=True) if problem]
        if not refused:
            break
        for trajectory, problem in refused:
            report.remove(trajectory.id, problem)
        kept = [t for t, (_, problem) in zip(kept, factors, strict=True) if not problem]
    if not kept:
        report.after = dataset.replace([])
        return report.after, report
    out = []
    for trajectory, pivot, (factor, _) in zip(kept, pivots, factors, strict=True):
        changes = {column: pivot + (trajectory[column] - pivot) * factor}
        if scale_velocity:
            changes[velocity_column] = trajectory[velocity_column] * factor
        out.append(trajectory.with_columns(**changes))
    report.params["end"] = end
    moved = [factor for factor, _ in factors]
    report.notes.append(
        f"{column} {'scaled' if mode == 'scale' else 'stretched'} to end at {end:.4g} "
        f"(factors {min(moved):.3g} to {max(moved):.3g})"
    )
    report.after = dataset.replace(out)
    return report.after, report


def _rescale_factor(values: np.ndarray, pivot: float, end: float, mode: str, column: str,
                    max_factor: float) -> tuple[float, str]:
    """The factor about ``pivot`` that moves the last of ``values`` (shape (T,)) to ``end``, and
    why there is no sensible one (else ""): a factor that is not positive and finite would
    reverse the motion, flatten it to one value or blow it up; one beyond ``max_factor`` (or
    below its inverse) would make up a throw's shape."""
    first, last = float(values[0]), float(values[-1])
    cannot = f"cannot {mode} {column} to end at {end:.4g}"
    if last == pivot:
        return math.nan, f"{cannot}: its last {column} is {'its first' if mode == 'stretch' else '0'}"
    factor = (end - pivot) / (last - pivot)
    if factor > 0 and math.isfinite(factor):
        if 1.0 / max_factor <= factor <= max_factor:
            return factor, ""
        return factor, (
            f"{cannot}: it runs {first:.4g} -> {last:.4g}, and {'stretching' if factor > 1 else 'shrinking'} it "
            f"{factor:.3g} times (more than max_factor {max_factor:g}) would make up its shape: a throw cut "
            f"{'short' if (factor > 1) == (last > first) else 'long'} (its extension lost?)"
        )
    effect = "reverse the motion" if factor < 0 else "flatten it" if factor == 0 else "blow it up"
    fixed = f"its first {column}" if mode == "stretch" else "0"
    return factor, (
        f"{cannot}: it runs {first:.4g} -> {last:.4g} and a {mode} keeps {fixed} fixed, so the "
        f"factor {factor:.3g} would {effect}"
    )


def densify(
    dataset: Dataset,
    *,
    column: str = "angle",
    step: float = 0.01,
    anchors: Sequence[float] = (0.25, 0.5, 0.75),
    spline: Literal["cubic", "pchip", "akima"] = "cubic",
    independent_rate: float = INDEPENDENT_RATE,
) -> tuple[Dataset, StepReport]:
    """Resample each trajectory at a fixed step of ``column`` through a spline with anchor points.

    Between each two consecutive samples, anchor points are inserted at the fractions
    ``anchors`` (linear in every column: the thesis' "average points" at 1/4, 1/2, 3/4 of the
    position and the velocity), which keeps the spline from arching between sparse samples. Every
    other column is then interpolated as a function of ``column`` (``spline``; ``time`` with a
    monotone PCHIP so that it keeps increasing) and sampled where ``column`` is a multiple of
    ``step``, plus both ends; in the direction the trajectory moves.

    Trajectories whose ``column`` is not strictly monotonic, or that have a single sample, are
    removed with that reason (run ``crop`` and ``longest_monotonic`` first). Each trajectory's
    ``measured_share`` metadata becomes the share of its samples that stand for an independent
    measurement (times any share it had), which ``Model.fit`` uses for BIC: the samples before,
    but at most ``independent_rate`` per second of its ``time`` (Hz; 0 or inf: every sample
    counts), over the samples after.
    """
    dataset.require([column])
    if not (isinstance(step, (int, float)) and 0 < step < math.inf):  # nan and inf too
        raise InputError(f"densify step {step!r}: must be a positive finite number")
    if not (isinstance(independent_rate, (int, float)) and independent_rate >= 0):  # nan too
        raise InputError(f"densify independent_rate {independent_rate!r}: must be a rate >= 0 (Hz; 0: every "
                         "sample counts)")
    fractions = np.asarray(anchors, dtype=float)
    if np.any((fractions <= 0) | (fractions >= 1)) or np.any(np.diff(fractions) <= 0):
        raise InputError(f"anchors {list(anchors)}: must increase strictly within (0, 1)")
    # the samples it would make, all trajectories together, before anything is allocated
    spans = [float(np.ptp(t[column])) for t in dataset if len(t) > 1]
    check_count(f"densify step {step:g} of {column}: samples", sum(spans) / step + 2 * len(spans),
                MAX_DENSIFY_SAMPLES, "use a larger step")
    params = {"column": column, "step": step, "anchors": [float(f) for f in fractions], "spline": spline,
              "independent_rate": independent_rate}
    report = StepReport("densify", params, dataset)
    out = []
    for trajectory in dataset:
        values = trajectory[column]
        steps = np.diff(values)
        if values.size < 2 or not (np.all(steps > 0) or np.all(steps < 0)):
            report.remove(trajectory.id, f"{column} is not strictly monotonic: cannot resample it")
            continue
        resampled = _densify_one(trajectory, column, step, fractions, spline, dataset.context, independent_rate)
        out.append(resampled)
        report.change_samples(
            trajectory.id, len(trajectory), len(resampled),
            f"resampled every {step:g} of {column} through a {spline} spline with anchors",
        )
    report.after = dataset.replace(out)
    return report.after, report


def _densify_one(
    trajectory: Trajectory, column: str, step: float, fractions: np.ndarray, spline: str,
    context: Sequence[str], independent_rate: float,
) -> Trajectory:
    values = trajectory[column]
    descending = values[-1] < values[0]
    # anchors: linear between consecutive samples, every column at once, shape (T-1, A) -> flat
    between = np.arange(values.size - 1)[:, None] + fractions[None, :]
    position = np.sort(np.concatenate([np.arange(values.size), between.ravel()]))
    sample_index = np.arange(values.size)
    dense = {name: np.interp(position, sample_index, trajectory[name]) for name in trajectory.columns}
    x = dense[column][::-1] if descending else dense[column]
    low, high = float(x[0]), float(x[-1])
    grid = np.arange(np.ceil(low / step), np.floor(high / step) + 1) * step
    # multiples of the step strictly inside, by a margin, so that no two samples nearly coincide
    margin = 1e-3 * step
    grid = np.concatenate([[low], grid[(grid > low + margin) & (grid < high - margin)], [high]])
    result = {}
    for name in trajectory.columns:
        if name == column:
            result[name] = grid
        elif name in context:
            result[name] = np.full(grid.size, trajectory[name][0])
        else:
            y = dense[name][::-1] if descending else dense[name]
            result[name] = _interpolator(x, y, "pchip" if name == "time" else spline)(grid)
    if descending:
        result = {name: array[::-1] for name, array in result.items()}
    # the share of samples that stand for a measurement (for BIC, see Model.fit): the rest are
    # interpolated; the share survives later cuts of the trajectory
    share = float(trajectory.meta.get("measured_share", 1.0)) * min(1.0, values.size / grid.size)
    share = min(share, independent_samples(trajectory, independent_rate) / grid.size)
    return trajectory.replace(data=result, meta={**trajectory.meta, "measured_share": share})


def independent_samples(trajectory: Trajectory, rate: float) -> float:
    """The most independent measurements ``trajectory`` can hold: one per 1 / ``rate`` seconds of
    its ``time``, and one more for the first (inf without a time column, or with a rate of 0 or
    inf)."""
    if not (0 < rate < math.inf) or "time" not in trajectory.columns:
        return math.inf
    return 1.0 + rate * float(np.ptp(trajectory["time"]))


def _interpolator(x: np.ndarray, y: np.ndarray, kind: str) -> Callable[[np.ndarray], np.ndarray]:
    """``y(x)`` through every point (x strictly increasing, at least 2 points)."""
    if x.size < 4 or kind == "pchip":
        return PchipInterpolator(x, y)
    if kind == "akima":
        return Akima1DInterpolator(x, y)
    return make_interp_spline(x, y, k=3)


def cut_release(
    dataset: Dataset,
    *,
    mode: Literal["estimated", "angle"] = "estimated",
    angle: float = 0.9,
    column: str = "angle",
    velocity_column: str = "velocity",
    after_peak: float = 0.0,
    top: float = 0.0,
    direction: Literal["auto", "increasing", "decreasing"] = "auto",
) -> tuple[Dataset, StepReport]:
    """Keep each trajectory up to the ball's release, dropping the follow-through.

    Parameters
    ----------
    dataset : Dataset
    mode : {"estimated", "angle"}
        "angle": cut at a fixed ``angle`` (the thesis used 0.9 rad in its own angle convention;
        rlff's elbow angle grows from about 0.7 to 3 rad, so a fixed cut must be chosen on that
        scale). "estimated": cut where the velocity peaks, where the acceleration turns from
        positive to negative (the thesis' suggested improvement: the ball leaves the hand near the
        peak of the extension's speed), or later, see ``after_peak``; with ``top``, the middle of
        the velocity's top.
    angle : float
        Cut angle for mode "angle"; samples beyond it (in the direction of motion) are dropped.
    column, velocity_column : str
    after_peak : float
        Mode "estimated": cut at the first sample after the peak whose speed has dropped by this
        fraction of the peak (0: at the peak).
    top : float
        Mode "estimated": the samples about the fastest one whose speed is within this share of
        it are the velocity's top, and the peak is the top's middle (in angle); 0 (default): the
        fastest sample itself. A camera sees the extension's fastest 0.2 s in a few frames,
        nearly equal in speed, so which of them is fastest is the tracker's noise: at 10 Hz the
        cut angles of the real MSR throws spread over 1.0-3.0 rad (1.3-2.7 at 15 Hz). 0.1 is
        measured better for recordings sparser than 15 Hz (docs/data.md, "Sparse recordings").
    direction : {"auto", "increasing", "decreasing"}
        Which way ``column`` moves in the throw's extension: "beyond" the fixed angle and the
        speed of mode "estimated" are counted that way. "auto": the way the dataset's throws
        share, each throw voting with the way its angle moves at its fastest sample (the
        extension; a throw's first and last angle do not tell, since an uncropped throw starts
        with its wind-up and may end lower than it started). A tie is an error asking for it.

    The cut angle goes into each trajectory's metadata as ``cut_angle``. Trajectories left
    with fewer than 2 samples (they start beyond the fixed angle, or their velocity peaks at their
    first sample) are removed with that reason. A fixed angle that no throw goes beyond cuts
    nothing, and the report warns of it.
    """
    dataset.require([column, velocity_column])
    if not 0.0 <= after_peak < 1.0:
        raise InputError(f"after_peak {after_peak}: must be in [0, 1)")
    if not 0.0 <= top < 1.0:
        raise InputError(f"top {top}: the share of the peak speed the velocity's top spans, must be in [0, 1)")
    report = StepReport("cut_release", {}, dataset)
    cut = sum("cut_angle" in t.meta for t in dataset)
    if cut:  # cleaning cleaned data again changes it (a rescale, a shape rejected) without a word
        report.warnings.append(
            f"{cut} of {len(dataset)} throws were cut at their release before (their cut_angle): the data look "
            "cleaned already, and cleaning them again removes and reshapes more; give the demonstrations as "
            "imported or simulated")
    sign = _throw_direction(dataset, column, velocity_column, direction, report)
    report.params = {"mode": mode, "angle": angle, "column": column, "velocity_column": velocity_column,
                     "after_peak": after_peak, "top": top, "direction": direction,
                     "throws": "increasing" if sign > 0 else "decreasing"}
    out = []
    for trajectory in dataset:
        values = trajectory[column]
        if mode == "angle":
            keep = int(np.count_nonzero(np.cumprod(sign * (values - angle) <= 0)))
            why = f"cut at {column} {angle:g}"
            if keep == 0:
                crop_first = "" if _monotonic(values) else "; crop it to its extension first (step crop)"
                report.remove(trajectory.id, f"{why}: it starts beyond it, at {values[0]:.4g} ({column} "
                              f"{'increasing' if sign > 0 else 'decreasing'} in the throws){crop_first}")
                continue
        else:
            speed = sign * trajectory[velocity_column]
            peak = _middle_of_top(values, speed, top)
            below = np.flatnonzero(speed[peak:] <= (1.0 - after_peak) * speed.max()) if after_peak else [0]
            keep = peak + int(below[0] if len(below) else speed.size - 1 - peak) + 1
            peak_words = f"middle of the {velocity_column}'s top" if top else f"{velocity_column} peak"
            why = f"cut at the estimated release ({peak_words}{' + drop' if after_peak else ''})"
        if keep < MIN_FILE_SAMPLES:
            report.remove(trajectory.id, f"{why} leaves {keep} sample{'s' if keep != 1 else ''}, fewer than {MIN_FILE_SAMPLES}")
            continue
        kept = trajectory.take(slice(0, keep))
        out.append(kept.replace(meta={**kept.meta, "cut_angle": float(values[keep - 1])}))
        report.change_samples(trajectory.id, len(trajectory) - keep, 0, f"{why}: {column} {values[keep - 1]:.4g}")
    if mode == "angle":
        _warn_unreached(dataset, column, angle, sign, report)
    report.after = dataset.replace(out)
    return report.after, report


def _warn_unreached(dataset: Dataset, column: str, angle: float, sign: float, report: StepReport) -> None:
    """Warn in ``report`` when no throw of ``dataset`` goes beyond the fixed cut ``angle`` (rad), in
    the throws' direction ``sign`` (+1 or -1): nothing was cut, which ``angle = 52`` (degrees by
    mistake) did without a word."""
    if not len(dataset):
        return
    furthest = sign * max(float(np.max(sign * t[column])) for t in dataset)
    if sign * (furthest - angle) > 0:
        return
    degrees = f" ({angle:g} deg is {math.radians(angle):.4g} rad)" if abs(angle) > 2 * math.pi else ""
    report.warnings.append(
        f"no throw's {column} goes beyond the cut angle {angle:g} (the furthest is {furthest:.4g}): nothing was "
        f"cut; angles are in rad{degrees}")


def _monotonic(values: np.ndarray) -> bool:
    steps = np.diff(values)
    return bool(np.all(steps > 0) or np.all(steps < 0))


def _throw_direction(dataset: Dataset, column: str, velocity_column: str, direction: str,
                     report: StepReport) -> float:
    """+1 when ``column`` grows in the throws' extension, -1 when it falls: as given, or (``"auto"``)
    the majority of the trajectories' votes, each the sign of the change of ``column`` about its
    fastest sample (largest absolute ``velocity_column``). Dissenters get a note in ``report``;
    a tie, or no vote at all (no motion), counts as increasing (rlff's convention), with a note."""
    if direction not in ("auto", "increasing", "decreasing"):
        raise InputError(f"direction {direction!r}: must be \"auto\", \"increasing\" or \"decreasing\"")
    if direction != "auto":
        return 1.0 if direction == "increasing" else -1.0
    votes = {}
    for trajectory in dataset:
        values = trajectory[column]
        if values.size < 2:
            continue
        fastest = int(np.argmax(np.abs(trajectory[velocity_column])))
        vote = float(np.sign(np.gradient(values)[fastest]))
        if vote:
            votes[trajectory.id] = vote
    up = sum(vote > 0 for vote in votes.values())
    down = len(votes) - up
    if up == down and votes:  # a pipeline step does not stop a run: rlff's own convention, said
        report.notes.append(
            f"cannot tell which way {column} moves in the throws ({up} trajectories move it up at their fastest "
            f"sample, {down} down): cut as increasing, rlff's convention for the extension; give direction = "
            "\"decreasing\" if yours falls"
        )
        return 1.0
    sign = 1.0 if up >= down else -1.0
    odd = [name for name, vote in votes.items() if vote != sign]
    if odd:
        report.notes.append(
            f"{len(odd)} {'trajectories' if len(odd) > 1 else 'trajectory'} ({', '.join(odd[:3])}"
            f"{', ...' if len(odd) > 3 else ''}) move {column} the other way at their fastest sample; "
            f"cut as the other {max(up, down)}, {column} {'increasing' if sign > 0 else 'decreasing'}"
        )
    return sign


def _middle_of_top(values: np.ndarray, speed: np.ndarray, top: float) -> int:
    """Index of the sample nearest the middle (in ``values``, the angle) of the run of samples
    about the fastest whose ``speed`` is within ``top`` of the fastest's; shapes (T,)."""
    fastest = int(np.argmax(speed))
    if top == 0 or speed[fastest] <= 0:  # the fastest sample; or no motion forward, no top
        return fastest
    within = speed >= (1.0 - top) * speed[fastest]
    outside = np.flatnonzero(~within)
    first = int(outside[outside < fastest].max(initial=-1)) + 1
    last = int(outside[outside > fastest].min(initial=speed.size)) - 1
    middle = 0.5 * (values[first] + values[last])
    return first + int(np.argmin(np.abs(values[first : last + 1] - middle)))

