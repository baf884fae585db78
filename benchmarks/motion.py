"""Motion planning of generated throws: limits, rest, release, landing and planning time.

Run: ``.venv/bin/python benchmarks/motion.py [--seed S] [--distances N] [--repeats R]``. Two sources of
demonstrations, each through the documented chain with default options (thesis preprocessing
preset, ``fit`` with K by BIC, ``generate`` with its defaults: continuity on, the grid ending at
the typical release):

- simulated people: ``rlff data synth throws --seed S`` (default 7; the tests use seed 2);
- real people: every MSR Action3D recording in ``../shared/data/msr-action3d-throws``.

For N basket distances over each model's distance range (default 10), the generated throw is
mapped to the Comau and planned (:func:`rlff.robot.plan.plan`, 2 ms period), exported in every
format (json, csv, ros1-bag, ros2-bag, comau), read back and counted against the limits. Peers,
measured side by side on the same throws:

- ``previous path``: the code path before the planner, the mapped points resampled at 2 ms
  (cubic Hermite), which exports wrote until issue 12;
- ``toppra``: toppra's time-optimal parametrisation of the same mapped path under the same
  velocity and acceleration limits (the planner's 99 %), release velocity kept (``sd_end`` = 1 with the path
  parametrised by the model's own time), constant-acceleration parametrizer; it keeps the
  model's path but neither limits jerk nor brakes after the release.

The simulated landing compares MuJoCo executing the planned throw (released at its release
time) with MuJoCo executing the unplanned mapped throw (released at its end), and each with the
closed-form landing of the model's exact release state (joint positions and velocities of the
last mapped point, no arm dynamics): the servos follow neither reference perfectly, and the
unplanned one, with its jerks, worse. Targets: 0 limit violations, last velocity 0, release
position and speed within 1 % of the model's, landing within 2 cm of the unplanned throw's,
median planning time <= 5 ms.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np

from rlff.ballistics import crossing_distance
from rlff.cli import main as rlff_main
from rlff.errors import InputError
from rlff.model import Model
from rlff.robot import RobotMapping, load_robot
from rlff.robot.export import read_bag, read_csv, read_json
from rlff.robot.formats import FORMATS, export_trajectory
from rlff.robot.plan import plan
from rlff.sim import Basket, simulate_throw
from rlff.sim.arm import Arm
from rlff.sim.reach import PLANE_JOINTS
from rlff.trajectory.check import violation_counts
from rlff.trajectory.joint import JointTrajectory
from rlff.trajectory.planner import MARGIN, plan_throw
from rlff.trajectory.resample import resample

MSR = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "msr-action3d-throws"
PERIOD = 0.002
TARGET_MS = 5.0


def _run(*args: str) -> None:
    """``rlff ARGS`` in this process, its tables and notes kept off the benchmark's output."""
    captured = io.StringIO()
    with contextlib.redirect_stdout(captured), contextlib.redirect_stderr(captured):
        code = rlff_main(list(args))
    if code != 0:
        raise SystemExit(f"rlff {' '.join(args)} failed with exit code {code}:\n{captured.getvalue()}")


def fitted_model(folder: Path, source: str, seed: int) -> Model:
    """Import or synthesise demonstrations, preprocess (thesis preset) and fit with defaults."""
    demos = folder / f"{source}.csv"
    if source == "synth":
        _run("data", "synth", "throws", "--seed", str(seed), "-o", str(demos))
    else:
        _run("data", "import", *map(str, sorted(MSR.glob("*.txt"))), "--format", "msr", "-o", str(demos))
    _run("data", "preprocess", str(demos), "--preset", "thesis", "-o", str(folder / f"{source}-clean.csv"))
    _run("fit", str(folder / f"{source}-clean.csv"), "-o", str(folder / f"{source}-model.json"))
    return Model.load(folder / f"{source}-model.json")


def executable_distances(model: Model, count: int) -> tuple[np.ndarray, str]:
    """``count`` distances from the model's shortest to the farthest whose default throw the robot can
    release: beyond it the model asks joint_2 to let go faster than its speed limit, which every
    robot output refuses without ``--clip`` (the mapping's velocity_scale, not the planner, sets
    where), and a note saying so."""
    robot = load_robot()
    mapping = RobotMapping.for_robot(robot)
    limit = robot.joint(mapping.joint).max_velocity
    low, high = model.input_range["distance"]
    candidates = np.linspace(low, high, 61)
    release = [abs(mapping.velocity_scale * model.generate({"distance": float(d)}, continuity=True).velocity[-1])
               for d in candidates]
    fast = np.flatnonzero(np.array(release) > limit)
    if fast.size == 0:
        return np.linspace(low, high, count), f"the model's distances {low:g} .. {high:g} m"
    farthest = candidates[max(int(fast[0]) - 1, 0)]
    return (np.linspace(low, farthest, count),
            f"model's distances {low:g} .. {high:g} m; from {candidates[fast[0]]:.2f} m on it asks a release "
            f"faster than {mapping.joint}'s {limit:g} rad/s (refused without --clip)")


def toppra_peer(points: JointTrajectory, joints) -> tuple[JointTrajectory | None, float]:
    """toppra's time-optimal parametrisation of the mapped path (velocity and acceleration limits,
    release velocity kept), sampled at 2 ms; and its planning time (ms). None if toppra fails."""
    import toppra
    import toppra.algorithm
    import toppra.constraint

    toppra.setup_logging("ERROR")
    limits = MARGIN * np.array([[j.max_velocity, j.max_acceleration] for j in joints])  # as the planner
    start = time.perf_counter()
    path = toppra.SplineInterpolator(points.time, points.positions,
                                     bc_type=((1, points.velocities[0]), (1, points.velocities[-1])))
    constraints = [toppra.constraint.JointVelocityConstraint(np.column_stack([-limits[:, 0], limits[:, 0]])),
                   toppra.constraint.JointAccelerationConstraint(np.column_stack([-limits[:, 1], limits[:, 1]]))]
    algorithm = toppra.algorithm.TOPPRA(constraints, path, gridpoints=points.time,
                                        parametrizer="ParametrizeConstAccel")
    result = algorithm.compute_trajectory(0.0, 1.0)
    elapsed = (time.perf_counter() - start) * 1000
    if result is None:
        return None, elapsed
    clock = np.append(np.arange(0.0, result.duration, PERIOD), result.duration)
    clock = clock[np.append(np.diff(clock) > 1e-9, True)]
    return JointTrajectory(points.joint_names, clock, result(clock), result(clock, 1), result(clock, 2)), elapsed


def ideal_landing(arm: Arm, points: JointTrajectory, basket: Basket) -> float:
    """Where the ball lands (m, closed-form flight) when let go exactly at the model's release:
    the last mapped point's joint positions and velocities, no arm dynamics."""
    q = {name: points.positions[-1, points.joint_index(name)] for name in PLANE_JOINTS}
    rates = np.array([points.velocities[-1, points.joint_index(name)] for name in PLANE_JOINTS])
    plane = arm.in_plane(q["joint_2"], q["joint_3"], q["joint_5"])
    velocity = plane.jacobian @ rates
    return float(crossing_distance(plane.ball[0], plane.ball[1], velocity[0], velocity[1], basket.rim_height))


def peak_jerk(traj: JointTrajectory, column: int) -> float:
    """Largest |jerk| (rad/s^3) of one joint from the sampled accelerations."""
    return float(np.max(np.abs(np.diff(traj.accelerations[:, column]) / np.diff(traj.time))))


def read_back(fmt: str, path: Path, mapping: RobotMapping) -> tuple[JointTrajectory | None, float]:
    """The exported trajectory read back (None for the Comau program) and its last speed (rad/s)."""
    if fmt == "comau":
        last = path.read_text().splitlines()[-1]
        percent = float(last.split(",")[mapping.robot.comau_program.get("velocity_slot", 6)].strip("')"))
        return None, percent / 100 * mapping.robot.joint(mapping.joint).max_velocity
    traj = {"json": read_json, "csv": read_csv}.get(fmt, lambda p: read_bag(p)[0])(path)
    return traj, float(np.max(np.abs(traj.velocities[-1])))


def best_of(repeats: int, call):
    """``call()``'s result and its best wall time (ms) over ``repeats`` runs: the machine is shared."""
    best, result = np.inf, None
    for _ in range(repeats):
        start = time.perf_counter()
        result = call()
        best = min(best, (time.perf_counter() - start) * 1000)
    return result, best


def measure(model: Model, distances: np.ndarray, folder: Path, repeats: int) -> dict[str, list]:
    robot = load_robot()
    mapping = RobotMapping.for_robot(robot)
    driven = robot.index(mapping.joint)
    rows: dict[str, list] = {key: [] for key in (
        "violations", "last_speed", "export_violations", "export_last", "position_error", "speed_error",
        "landing_change", "plan_ms", "pipeline_ms", "toppra_ms", "toppra_failed", "toppra_violations",
        "toppra_jerk", "previous_violations", "previous_last", "previous_jerk", "planned_jerk",
        "peak_acceleration", "duration", "refused", "planned_vs_ideal", "unplanned_vs_ideal")}
    arm = Arm.from_robot(robot)
    for number, distance in enumerate(distances):
        path = model.generate({"distance": float(distance)}, exploration="auto", exploration_scale=1.0,
                              continuity=True)
        try:
            result, elapsed = best_of(repeats, lambda p=path: plan(mapping, p.angle, p.velocity, p.time,
                                                                   period=PERIOD))
        except InputError as exc:  # refused, as `rlff robot export` would: counted, not exported
            rows["refused"].append(f"{distance:.2f} m: {exc}")
            continue
        rows["pipeline_ms"].append(elapsed)
        points = result.points
        rows["plan_ms"].append(best_of(repeats, lambda p=points: plan_throw(p, robot.joints, period=PERIOD))[1])
        planned = result.trajectory
        counts = violation_counts(planned, robot.joints)
        rows["violations"].append(sum(counts.values()))
        rows["last_speed"].append(float(np.max(np.abs(planned.velocities[-1]))))
        rows["planned_jerk"].append(peak_jerk(planned, driven))
        rows["peak_acceleration"].append(float(np.max(np.abs(planned.accelerations[:, driven]))))
        rows["duration"].append(planned.duration)
        release = int(np.flatnonzero(planned.time == planned.release_time)[0])
        asked_q, asked_v = points.positions[-1, driven], points.velocities[-1, driven]
        travel = abs(points.positions[-1, driven] - points.positions[0, driven])
        rows["position_error"].append(100 * abs(planned.positions[release, driven] - asked_q) / travel)
        rows["speed_error"].append(100 * abs(planned.velocities[release, driven] - asked_v) / abs(asked_v))
        for fmt in FORMATS:
            out = folder / f"throw-{number}.{fmt}"
            export_trajectory(planned, mapping, fmt, out)
            back, last = read_back(fmt, out, mapping)
            rows["export_violations"].append(0 if back is None else sum(violation_counts(back, robot.joints).values()))
            rows["export_last"].append(last)
        # peers: the previous code path (points resampled at 2 ms) and toppra
        unplanned, _ = mapping.to_robot(path.angle, path.velocity, path.time, clip=True)
        previous = resample(unplanned, PERIOD)
        rows["previous_violations"].append(sum(violation_counts(previous, robot.joints).values()))
        rows["previous_last"].append(float(np.max(np.abs(previous.velocities[-1]))))
        rows["previous_jerk"].append(peak_jerk(previous, driven))
        peer, elapsed = min((toppra_peer(points, robot.joints) for _ in range(repeats)), key=lambda run: run[1])
        rows["toppra_ms"].append(elapsed)
        rows["toppra_failed"].append(peer is None)
        if peer is not None:
            counts = violation_counts(peer, robot.joints)
            rows["toppra_violations"].append(sum(v for k, v in counts.items() if k != "end moving"))
            rows["toppra_jerk"].append(peak_jerk(peer, driven))
        basket = Basket(float(distance))
        landed = simulate_throw(planned, basket, robot=robot, check_reach=False).landing_x
        before = simulate_throw(unplanned, basket, robot=robot, check_reach=False, check_motion=False).landing_x
        ideal = ideal_landing(arm, points, basket)
        rows["landing_change"].append(100 * abs(landed - before))
        rows["planned_vs_ideal"].append(100 * abs(landed - ideal))
        rows["unplanned_vs_ideal"].append(100 * abs(before - ideal))
    return rows


def report(name: str, distances: np.ndarray, rows: dict[str, list]) -> None:
    median = statistics.median
    toppra_ok = [ms for ms, failed in zip(rows["toppra_ms"], rows["toppra_failed"], strict=True) if not failed]
    print(f"\n{name}: {len(distances)} throws at {distances[0]:.2f} .. {distances[-1]:.2f} m, "
          f"{len(distances) - len(rows['refused'])} planned and exported in {len(FORMATS)} formats "
          f"({len(rows['export_last'])} files), {len(rows['refused'])} refused")
    for refusal in rows["refused"]:
        print(f"  refused (as robot export would, without --clip): {refusal}")
    print(f"{'':<44}{'rlff planner':>14}{'previous path':>15}{'toppra':>10}")
    print(f"{'limit violations (values, all throws)':<44}{sum(rows['violations']):>14d}"
          f"{sum(rows['previous_violations']):>15d}{sum(rows['toppra_violations']):>10d}")
    print(f"{'... in the exported files read back':<44}{sum(rows['export_violations']):>14d}")
    print(f"{'largest last speed (rad/s), files too':<44}{max(rows['last_speed'] + rows['export_last']):>14.3g}"
          f"{max(rows['previous_last']):>15.3f}{'(release)':>10}")
    print(f"{'peak jerk of joint_2, median (rad/s^3)':<44}{median(rows['planned_jerk']):>14.0f}"
          f"{median(rows['previous_jerk']):>15.0f}"
          f"{median(rows['toppra_jerk']) if rows['toppra_jerk'] else float('nan'):>10.0f}")
    print(f"{'peak acceleration of joint_2, max (rad/s^2)':<44}{max(rows['peak_acceleration']):>14.2f}")
    print(f"{'release position error, max (% of travel)':<44}{max(rows['position_error']):>14.2g}")
    print(f"{'release speed error, max (%)':<44}{max(rows['speed_error']):>14.2g}")
    print(f"{'MuJoCo landing, planned vs unplanned, max (cm)':<44}{max(rows['landing_change']):>14.2f}")
    print(f"{'MuJoCo landing vs the model release, max (cm)':<44}{max(rows['planned_vs_ideal']):>14.2f}"
          f"{max(rows['unplanned_vs_ideal']):>15.2f}")
    print(f"{'planning time, best of R, median (ms)':<44}{median(rows['plan_ms']):>14.2f}{'':>15}"
          f"{median(toppra_ok) if toppra_ok else float('nan'):>10.2f}")
    print(f"{'  with mapping and check, median (ms)':<44}{median(rows['pipeline_ms']):>14.2f}")
    if toppra_ok:
        print(f"{'  toppra / rlff planner':<44}{median(toppra_ok) / median(rows['plan_ms']):>14.2f}")
    if any(rows["toppra_failed"]):
        print(f"toppra found no parametrisation for {sum(rows['toppra_failed'])} throws (release unreachable)")
    print(f"planned duration (approach + throw + braking): median {median(rows['duration']):.3f} s")
    verdicts = {
        "0 violations": sum(rows["violations"]) + sum(rows["export_violations"]) == 0,
        "ends at rest": max(rows["last_speed"] + rows["export_last"]) == 0,
        "release within 1 %": max(rows["position_error"] + rows["speed_error"]) <= 1,
        "landing within 2 cm of the unplanned throw's": max(rows["landing_change"]) <= 2,
        f"median planning <= {TARGET_MS:g} ms": median(rows["plan_ms"]) <= TARGET_MS,
    }
    print("targets: " + "; ".join(f"{name} {'met' if ok else 'MISSED'}" for name, ok in verdicts.items()))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=7, help="Seed of the simulated people.")
    parser.add_argument("--distances", type=int, default=10, help="Basket distances per source.")
    parser.add_argument("--repeats", type=int, default=3, help="Timings per throw (the best counts).")
    args = parser.parse_args()
    sources = [("synth", f"simulated people (data synth throws --seed {args.seed})")]
    if MSR.is_dir():
        sources.append(("msr", f"MSR Action3D recordings ({len(list(MSR.glob('*.txt')))} files)"))
    else:
        print(f"{MSR} is absent: the MSR source is skipped")
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(scratch)
        for source, name in sources:
            model = fitted_model(folder, source, args.seed)
            distances, note = executable_distances(model, args.distances)
            (folder / source).mkdir()
            report(f"{name}; {note}", distances, measure(model, distances, folder / source, args.repeats))


if __name__ == "__main__":
    main()
