"""How the simulated whole-arm people's throws land when the Comau throws them through the
robot file's ``[whole_arm]`` defaults.

Run: ``.venv/bin/python benchmarks/wholearm_mapping.py [--seed S] [--joints joint_2,joint_3[,joint_5]]
[--figure docs/figures/whole-arm-throw.png]``.
The people are ``rlff.synthetic.throws.whole_arm_demonstrations(seed=S)`` (default seed 1: the
defaults were tuned on seed 0), every person at every basket (1-4 m, bearings 0-90 deg, rims 0.3,
0.6 and 1.0 m); a camera's noise and dropped frames are left out, so that what is measured is the
mapping, not the capture. Each throw, from the start of the elbow's extension to its release, is
mapped to the robot (:meth:`rlff.robot.mapping.ArmMapping.path_to_robot`), planned
(:func:`rlff.robot.plan.plan_path`, the approach turning joint_1 to the bearing) and thrown in
MuJoCo at its own basket. Per distance it prints, side by side: the person's own landing and the
robot's, each over the target distance (medians), the robot's share within +-30 % of the target,
the share of throws whose release is beyond a speed limit (clipped into it here; refused without
``--clip``), and the farthest landing of the throw with every velocity scaled by one factor until
the first joint reaches its limit (closed form at a 0.3 m rim: what a speed calibration can reach
with that throw's shape). ``--figure`` draws one of the throws (the first person's at the 3 m
basket on the 30 deg line): each joint's trajectory and the arm, the flight and the basket seen
side on in the basket's vertical plane.
"""

from __future__ import annotations

import argparse
import statistics

import numpy as np

from rlff.robot import load_robot, mapping_for
from rlff.robot.plan import plan_path
from rlff.sim import Basket, simulate_throw
from rlff.sim.arm import Arm
from rlff.sim.reach import release_reach
from rlff.synthetic.throws import whole_arm_demonstrations


def extension(trajectory, columns):
    """The throw's columns from the elbow's start of extension to the release (elbow rising)."""
    release = int(np.argmin(np.abs(trajectory["time"] - trajectory.meta["release_time"])))
    start = int(np.argmin(trajectory["angle"][: release + 1]))
    path = {name: trajectory[name][start:release + 1] for name in columns}
    rising = np.concatenate([[True], np.diff(path["angle"]) > 0])
    return {name: values[rising] for name, values in path.items()}


def draw(path, robot, planned, outcome, basket) -> None:
    """The figure of one whole-arm throw: joint positions over time, and the arm and flight side on."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from rlff.ballistics import position_at

    traj = planned.trajectory
    figure, (joints, side) = plt.subplots(1, 2, figsize=(12, 4.6), gridspec_kw={"width_ratios": [1, 1.35]})
    for name in ("joint_1", "joint_2", "joint_3", "joint_5"):
        joints.plot(traj.time, traj.positions[:, traj.joint_index(name)], label=name)
    joints.axvline(traj.release_time, color="0.4", linestyle="--", linewidth=1)
    joints.text(traj.release_time, joints.get_ylim()[1], " release", va="top", fontsize=9, color="0.3")
    joints.set(xlabel="time (s)", ylabel="position (rad)",
               title="planned: joint_1 turns to the bearing, then the throw")
    joints.legend(loc="lower right", fontsize=9)
    arm = Arm.from_robot(robot)
    shoulder = np.array([arm.geometry.shoulder_forward, arm.geometry.shoulder_height])
    release = int(np.argmin(np.abs(traj.time - traj.release_time)))
    first = int(np.flatnonzero(np.abs(traj.positions[:, traj.joint_index("joint_1")] -
                                      traj.positions[-1, traj.joint_index("joint_1")]) < 1e-9)[0])
    for share in np.linspace(0.0, 1.0, 6):
        row = first + round(share * (release - first))
        q = [traj.positions[row, traj.joint_index(n)] for n in ("joint_2", "joint_3", "joint_5")]
        plane = arm.in_plane(*q)
        chain = np.array([[0.0, 0.0], [0.0, 0.45], shoulder, plane.elbow, plane.wrist, plane.ball])
        side.plot(chain[:, 0], chain[:, 1], "-o", color="#4d6a8a", alpha=0.25 + 0.75 * share, markersize=3)
    times = np.linspace(0.0, outcome.flight_time, 60)
    flight = position_at(outcome.release.position, outcome.release.velocity, times)
    side.plot(flight[:, :2] @ basket.direction, flight[:, 2], color="#2e7d32" if outcome.hit else "#c62828", label="flight (ball centre)")
    half = 0.5 * basket.opening
    side.add_patch(matplotlib.patches.Rectangle((basket.distance - half, 0.0), basket.opening, basket.rim_height,
                                                fill=False, color="#8c5a2b", linewidth=2))
    side.plot([outcome.landing_x], [basket.rim_height], "v", color="k",
              label=f"MuJoCo: {'hit' if outcome.hit else 'miss'}, {outcome.landing_x:.2f} m")
    side.set(xlabel=f"along the {basket.bearing:g} deg line (m)", ylabel="height (m)", aspect="equal",
             title=f"arm ({', '.join(planned_joints(planned))}) to the release, and the flight")
    side.legend(loc="upper right", fontsize=9)
    figure.tight_layout()
    figure.savefig(path, dpi=110)
    plt.close(figure)


def planned_joints(planned) -> list[str]:
    """The joints that move in a planned throw, in the robot's order."""
    spread = np.ptp(planned.trajectory.positions, axis=0)
    return [name for name, moved in zip(planned.trajectory.joint_names, spread > 1e-6, strict=True) if moved]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--joints", default="joint_2,joint_3")
    parser.add_argument("--figure", help="PNG of one whole-arm throw to write")
    args = parser.parse_args()
    joints = tuple(args.joints.split(","))
    robot = load_robot()
    mapping = mapping_for(robot, joints)
    wrist = "wrist" in mapping.human_columns
    people = whole_arm_demonstrations(seed=args.seed, joints=("shoulder", "elbow", "wrist") if wrist else
                                      ("shoulder", "elbow"), noise=0.0, dropped_frames=0.0, glitches=0.0)
    columns = ["angle", "velocity", "shoulder", "shoulder_velocity"] + (["wrist", "wrist_velocity"] if wrist else [])
    rows: dict[float, list[tuple[float, float, bool, float]]] = {}
    drawn = False
    for throw in people:
        target = float(throw.meta["target"])
        bearing = float(throw["bearing"][0]) if "bearing" in throw.columns else 0.0
        height = float(throw["height"][0]) if "height" in throw.columns else 0.3
        planned = plan_path(mapping, extension(throw, columns), bearing=bearing, clip=True, start=mapping.pose())
        clipped = any(c.point == len(planned.points) - 1 for c in planned.clipped_points.changes)
        outcome = simulate_throw(planned.trajectory, Basket(target, height, bearing=bearing), robot=robot,
                                 check_reach=False)
        if args.figure and target == 3.0 and bearing == 30.0 and not drawn:
            draw(args.figure, robot, planned, outcome, Basket(target, height, bearing=bearing))
            drawn = True
        rows.setdefault(target, []).append((float(throw.meta["landing"]) / target, outcome.landing_x / target,
                                            clipped, release_reach(robot, planned.points.positions[-1], planned.points.velocities[-1])))
    print(f"whole-arm people (seed {args.seed}) thrown by the Comau with {', '.join(mapping.driven_joints)} "
          f"(time_scale {mapping.time_scale:g}); medians over throws")
    print(f"{'target (m)':>10} {'throws':>7} {'person/target':>14} {'robot/target':>13} {'robot +-30 %':>13} "
          f"{'release clipped':>16} {'scaled reach (m)':>17}")
    for target in sorted(rows):
        person, robot_ratio, clipped, reach = zip(*rows[target], strict=True)
        within = np.mean(np.abs(np.array(robot_ratio) - 1) <= 0.3)
        print(f"{target:>10.2f} {len(person):>7} {statistics.median(person):>14.2f} {statistics.median(robot_ratio):>13.2f} "
              f"{within:>13.0%} {np.mean(clipped):>16.0%} {statistics.median(reach):>17.2f}")


if __name__ == "__main__":
    main()
