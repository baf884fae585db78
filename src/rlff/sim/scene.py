"""The MuJoCo scene of a throw: arm, ball, basket, ground; compiled once per setting and cached.

The arm is built from its lengths as capsules with reasonable masses (about 80 kg moving); only
the ball collides (with the ground and the basket), which keeps a step cheap. Every joint has a
velocity servo whose command is clamped to the joint's speed limit (the throw adds a position
correction, ``POSITION_GAIN``, to the trajectory's velocity), large armature for a stable
implicit integration, and the links carry full gravity compensation so that the arm does not sag.
The joints' position limits are also MuJoCo joint limits.
The ball (a tennis ball) is held at the flange by a weld constraint that the throw switches off
at release.

Contacts are speculative (MuJoCo's continuous collision detection): a contact the ball would make
before the next step is found at this step and the solver stops the ball on the surface. Without
it a ball falling about 12 mm per 2 ms step sank through the 1 cm basket floor onto the ground and
was scored a miss; with it the verdict at 2 ms agrees with a 0.25 ms step (docs/sim.md).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import mujoco
import numpy as np

from rlff.sim.arm import BALL_MASS, BALL_RADIUS, Arm
from rlff.sim.basket import WALL, Basket

#: Link masses (kg) from the base to the flange: reasonable for a 6 kg payload arm of this size.
LINK_MASSES = (40.0, 25.0, 12.0, 6.0, 2.5, 0.5)
#: Rotor inertia reflected at each joint (kg m^2): stabilises the stiff servos.
ARMATURE = (2.0, 2.0, 1.0, 0.1, 0.1, 0.05)
#: Velocity servo gains (N m s/rad) and torque limits (N m), generous on purpose.
SERVO_GAIN = (4000.0, 4000.0, 2000.0, 200.0, 200.0, 100.0)
TORQUE_LIMIT = (8000.0, 8000.0, 4000.0, 500.0, 500.0, 200.0)
#: Share of a joint's speed limit the servo may command: the servo's small overshoot stays below
#: the limit.
SPEED_MARGIN = 0.998
#: Position correction of the velocity command (1/s): ``v_ref + POSITION_GAIN * (q_ref - q)``.
POSITION_GAIN = 40.0


@dataclass(frozen=True)
class Scene:
    """A compiled scene and the indices a throw needs.

    Attributes
    ----------
    model : mujoco.MjModel
    arm : Arm
    basket : Basket
    pedestal : float
        Height of the robot's base above the ground (m).
    joint_qpos, joint_dof : ndarray of shape (6,)
        Addresses of the arm joints in ``qpos`` and ``qvel``, in ``arm.joint_names`` order.
    ball_qpos, ball_dof : int
        Address of the ball's free joint in ``qpos`` (7 values) and ``qvel`` (6 values).
    ball_body, ball_geom, ground_geom, flange_site, grip : int
        Object ids; ``grip`` is the weld equality holding the ball.
    basket_geoms : frozenset of int
    """

    model: mujoco.MjModel
    arm: Arm
    basket: Basket
    pedestal: float
    joint_qpos: np.ndarray
    joint_dof: np.ndarray
    ball_qpos: int
    ball_dof: int
    ball_body: int
    ball_geom: int
    ground_geom: int
    flange_site: int
    grip: int
    basket_geoms: frozenset[int]


@lru_cache(maxsize=32)
def build_scene(arm: Arm, basket: Basket, pedestal: float = 0.0, timestep: float = 0.002) -> Scene:
    """Compile (or take from the cache) the scene for one arm, basket and pedestal.

    Parameters
    ----------
    arm : Arm
    basket : Basket
    pedestal : float
        Height of the robot's base above the ground (m), >= 0.
    timestep : float
        Simulation step (s).
    """
    model = mujoco.MjModel.from_xml_string(scene_xml(arm, basket, pedestal, timestep))
    name = mujoco.mj_name2id
    joints = [name(model, mujoco.mjtObj.mjOBJ_JOINT, j) for j in arm.joint_names]
    ball_joint = name(model, mujoco.mjtObj.mjOBJ_JOINT, "ball")
    basket_geoms = frozenset(
        name(model, mujoco.mjtObj.mjOBJ_GEOM, f"basket_{part}")
        for part in ("floor", "near", "far", "left", "right")
    )
    return Scene(
        model=model,
        arm=arm,
        basket=basket,
        pedestal=float(pedestal),
        joint_qpos=np.array([model.jnt_qposadr[j] for j in joints]),
        joint_dof=np.array([model.jnt_dofadr[j] for j in joints]),
        ball_qpos=int(model.jnt_qposadr[ball_joint]),
        ball_dof=int(model.jnt_dofadr[ball_joint]),
        ball_body=name(model, mujoco.mjtObj.mjOBJ_BODY, "ball"),
        ball_geom=name(model, mujoco.mjtObj.mjOBJ_GEOM, "ball"),
        ground_geom=name(model, mujoco.mjtObj.mjOBJ_GEOM, "ground"),
        flange_site=name(model, mujoco.mjtObj.mjOBJ_SITE, "flange"),
        grip=name(model, mujoco.mjtObj.mjOBJ_EQUALITY, "grip"),
        basket_geoms=basket_geoms,
    )


def scene_xml(arm: Arm, basket: Basket, pedestal: float = 0.0, timestep: float = 0.002) -> str:
    """The MJCF text of the scene (x forward, z up, the robot's base at (0, 0, pedestal))."""
    j1, j2, j3, j4, j5, j6 = (_joint(arm, i) for i in range(6))
    m1, m2, m3, m4, m5, m6 = LINK_MASSES
    g = arm.geometry
    up, fwd = g.shoulder_height, g.shoulder_forward
    a, fore, flange, r = g.elbow_offset, g.forearm, g.flange, BALL_RADIUS
    # the ball's body starts where the flange holds it in the zero pose: the weld keeps that offset
    ball_x = fwd + fore + flange + r
    ball_z = pedestal + up + g.upper_arm + a
    d, h, half = basket.distance, basket.rim_height, 0.5 * basket.opening
    # the basket stands on its bearing line, its walls facing the robot; the side camera and the
    # light turn with it, so that the throw is seen side on at any bearing
    (cx, cy), (ux, uy), yaw = basket.centre, basket.direction, np.radians(basket.bearing)
    view = max(d + 1.5, 3.0)
    cam_along, cam_across = 0.5 * (d - 1.0), -1.1 * view
    actuators = "\n    ".join(
        f'<velocity name="{n}" joint="{n}" kv="{kv}" ctrlrange="{-v * SPEED_MARGIN} {v * SPEED_MARGIN}" '
        f'forcerange="{-f} {f}"/>'
        for n, v, kv, f in zip(arm.joint_names, (j.max_velocity for j in arm.joints), SERVO_GAIN,
                                TORQUE_LIMIT, strict=True)
    )
    return f"""
<mujoco model="throw">
  <compiler angle="radian" autolimits="true"/>
  <option timestep="{timestep}" integrator="implicitfast" gravity="0 0 -9.81">
    <flag speculative="enable"/>
  </option>
  <visual><global offwidth="960" offheight="720"/></visual>
  <default>
    <joint solreflimit="{2 * timestep} 1"/>
    <geom contype="0" conaffinity="0" rgba="0.95 0.55 0.1 1"/>
    <default class="hit"><geom contype="1" conaffinity="1" condim="3" priority="1"
      solref="0.005 1" friction="0.8 0.005 0.0001" rgba="0.45 0.3 0.15 1"/></default>
  </default>
  <asset>
    <texture name="grid" type="2d" builtin="checker" rgb1="0.82 0.82 0.8" rgb2="0.7 0.7 0.68"
      width="256" height="256"/>
    <material name="floor" texture="grid" texrepeat="8 8"/>
  </asset>
  <worldbody>
    <light pos="{0.5 * d * ux + 2 * uy} {0.5 * d * uy - 2 * ux} 4" dir="{-0.4 * uy} {0.4 * ux} -1" directional="true"/>
    <camera name="side" pos="{cam_along * ux - cam_across * uy} {cam_along * uy + cam_across * ux} {1.4 + 0.5 * pedestal}"
      xyaxes="{ux} {uy} 0 {-0.05 * uy} {0.05 * ux} 1"/>
    <geom name="ground" class="hit" type="plane" size="0 0 0.05" material="floor" rgba="1 1 1 1"/>
    <geom name="pedestal" type="box" pos="0 0 {0.5 * pedestal}" size="0.3 0.3 {max(0.5 * pedestal, 1e-3)}"
      rgba="0.3 0.3 0.35 1"/>
    <body name="basket" pos="{cx} {cy} 0" euler="0 0 {yaw}">
      <geom name="basket_floor" class="hit" type="box" pos="0 0 {0.5 * WALL}" size="{half} {half} {0.5 * WALL}"/>
      <geom name="basket_near" class="hit" type="box" pos="{-half - 0.5 * WALL} 0 {0.5 * h}"
        size="{0.5 * WALL} {half + WALL} {0.5 * h}"/>
      <geom name="basket_far" class="hit" type="box" pos="{half + 0.5 * WALL} 0 {0.5 * h}"
        size="{0.5 * WALL} {half + WALL} {0.5 * h}"/>
      <geom name="basket_left" class="hit" type="box" pos="0 {half + 0.5 * WALL} {0.5 * h}"
        size="{half} {0.5 * WALL} {0.5 * h}"/>
      <geom name="basket_right" class="hit" type="box" pos="0 {-half - 0.5 * WALL} {0.5 * h}"
        size="{half} {0.5 * WALL} {0.5 * h}"/>
    </body>
    <body name="link_1" pos="0 0 {pedestal}" gravcomp="1">
      <joint name="{j1[0]}" type="hinge" axis="0 0 1" range="{j1[1]} {j1[2]}" armature="{ARMATURE[0]}"/>
      <geom type="cylinder" size="0.2 0.08" pos="0 0 0.08" mass="{0.5 * m1}"/>
      <geom type="capsule" size="0.12" fromto="0 0 0.1 {fwd} 0 {up}" mass="{0.5 * m1}"/>
      <body name="link_2" pos="{fwd} 0 {up}" gravcomp="1">
        <joint name="{j2[0]}" type="hinge" axis="0 1 0" range="{j2[1]} {j2[2]}" armature="{ARMATURE[1]}"/>
        <geom type="capsule" size="0.08" fromto="0 0 0 0 0 {g.upper_arm}" mass="{m2}"/>
        <body name="link_3" pos="0 0 {g.upper_arm}" gravcomp="1">
          <joint name="{j3[0]}" type="hinge" axis="0 1 0" range="{j3[1]} {j3[2]}" armature="{ARMATURE[2]}"/>
          <geom type="capsule" size="0.07" fromto="0 0 0 {0.5 * fore} 0 {a}" mass="{m3}"/>
          <body name="link_4" pos="{0.5 * fore} 0 {a}" gravcomp="1">
            <joint name="{j4[0]}" type="hinge" axis="1 0 0" range="{j4[1]} {j4[2]}" armature="{ARMATURE[3]}"/>
            <geom type="capsule" size="0.05" fromto="0 0 0 {0.5 * fore} 0 0" mass="{m4}"/>
            <body name="link_5" pos="{0.5 * fore} 0 0" gravcomp="1">
              <joint name="{j5[0]}" type="hinge" axis="0 1 0" range="{j5[1]} {j5[2]}" armature="{ARMATURE[4]}"/>
              <geom type="capsule" size="0.04" fromto="0 0 0 {0.6 * flange} 0 0" mass="{m5}"/>
              <body name="link_6" pos="{flange} 0 0" gravcomp="1">
                <joint name="{j6[0]}" type="hinge" axis="1 0 0" range="{j6[1]} {j6[2]}" armature="{ARMATURE[5]}"/>
                <geom type="cylinder" size="0.04 0.01" euler="0 1.5708 0" pos="-0.01 0 0" mass="{m6}"
                  rgba="0.3 0.3 0.35 1"/>
                <site name="flange"/>
              </body>
            </body>
          </body>
        </body>
      </body>
    </body>
    <body name="ball" pos="{ball_x} 0 {ball_z}">
      <freejoint name="ball"/>
      <geom name="ball" type="sphere" size="{r}" mass="{BALL_MASS}" contype="1" conaffinity="1"
        condim="3" friction="0.8 0.005 0.0001" rgba="0.8 0.95 0.2 1"/>
    </body>
  </worldbody>
  <equality>
    <weld name="grip" body1="ball" body2="link_6" solref="{2 * timestep} 1"/>
  </equality>
  <actuator>
    {actuators}
  </actuator>
</mujoco>
"""


def _joint(arm: Arm, i: int) -> tuple[str, float, float]:
    joint = arm.joints[i]
    return joint.name, joint.lower, joint.upper
