"""The MuJoCo scene: kinematics against the planar formulas, a still arm, caching, the basket."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rlff.errors import InputError
from rlff.robot import load_robot
from rlff.robot.description import Robot
from rlff.sim import Basket
from rlff.sim.arm import BALL_RADIUS, Arm
from rlff.sim.scene import build_scene

ARM = Arm.from_robot(load_robot())


def _ball_in_mujoco(scene, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Ball centre (3,) and its Jacobian (3, 6) over the arm joints, from MuJoCo."""
    model = scene.model
    data = mujoco.MjData(model)
    data.qpos[scene.joint_qpos] = q
    mujoco.mj_forward(model, data)
    flange = model.site_bodyid[scene.flange_site]
    ball = data.xpos[flange] + data.xmat[flange].reshape(3, 3)[:, 0] * BALL_RADIUS
    jacobian = np.zeros((3, model.nv))
    mujoco.mj_jac(model, data, jacobian, None, ball, flange)
    return ball, jacobian[:, scene.joint_dof]


@settings(max_examples=25, deadline=None)
@given(q2=st.floats(-1.48, 2.71), q3=st.floats(-2.967, 0.0), q5=st.floats(-2.27, 2.27),
       pedestal=st.sampled_from([0.0, 0.4]))
def test_planar_kinematics_match_mujoco(q2, q3, q5, pedestal):
    scene = build_scene(ARM, Basket(2.0), pedestal)
    ball, jacobian = _ball_in_mujoco(scene, np.array([0.0, q2, q3, 0.0, q5, 0.3]))
    plane = ARM.in_plane(q2, q3, q5, pedestal)
    np.testing.assert_allclose(ball[[0, 2]], plane.ball, atol=1e-9)
    assert abs(ball[1]) < 1e-9
    np.testing.assert_allclose(jacobian[[0, 2]][:, [1, 2, 4]], plane.jacobian, atol=1e-9)


def test_zero_pose_puts_the_flange_where_the_robot_file_says():
    # the robot file: with every joint at 0 the flange is at x = 0.892, z = 1.17, pointing forward
    plane = ARM.in_plane(0.0, 0.0, 0.0)
    np.testing.assert_allclose(plane.ball, [0.15 + 0.647 + 0.095 + BALL_RADIUS, 0.45 + 0.59 + 0.13], atol=1e-12)


def test_the_arm_holds_its_pose_without_sagging():
    scene = build_scene(ARM, Basket(2.0))
    data = mujoco.MjData(scene.model)
    pose = np.array([0.0, -1.0, -1.4, 0.0, -0.2, 0.0])
    data.qpos[scene.joint_qpos] = pose
    for _ in range(500):  # one second with zero velocity commands
        mujoco.mj_step(scene.model, data)
    assert np.max(np.abs(data.qpos[scene.joint_qpos] - pose)) < 1e-3


def test_scene_settings_follow_the_issue():
    model = build_scene(ARM, Basket(2.0)).model
    assert model.opt.integrator == mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    ball = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "ball")
    assert model.body_mass[ball] == pytest.approx(0.057)
    assert model.geom_size[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, "ball")][0] == pytest.approx(0.033)
    assert np.all(model.dof_armature[:6] > 0)
    # velocity servos limited to each joint's speed limit (with a small margin)
    limits = np.array([j.max_velocity for j in ARM.joints])
    assert np.all(model.actuator_ctrlrange[:, 1] <= limits)
    assert np.all(model.actuator_ctrlrange[:, 1] > 0.99 * limits)
    assert np.all(model.jnt_limited[:6])


def test_the_scene_is_compiled_once_per_setting():
    assert build_scene(ARM, Basket(2.0), 0.0) is build_scene(ARM, Basket(2.0), 0.0)
    assert build_scene(ARM, Basket(2.0), 0.0) is not build_scene(ARM, Basket(2.5), 0.0)


def test_basket_walls_stand_around_the_opening():
    basket = Basket(2.0, rim_height=0.4, opening=0.3)
    model = build_scene(ARM, basket).model
    near = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, "basket_near")
    far = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, "basket_far")
    # inner faces of the near and far walls 0.3 m apart, tops at the rim
    inner = model.geom_pos[far][0] - model.geom_size[far][0] - (model.geom_pos[near][0] + model.geom_size[near][0])
    assert inner == pytest.approx(0.3)
    assert model.geom_pos[near][2] + model.geom_size[near][2] == pytest.approx(0.4)
    assert basket.holds(np.array([2.1, 0.0, 0.1]), BALL_RADIUS)
    assert not basket.holds(np.array([2.2, 0.0, 0.1]), BALL_RADIUS)


@pytest.mark.parametrize("field, value", [("distance", 0.0), ("rim_height", -0.3), ("opening", float("nan"))])
def test_a_bad_basket_is_refused(field, value):
    values = {"distance": 2.0, "rim_height": 0.3, "opening": 0.35, field: value}
    with pytest.raises(InputError, match=field):
        Basket(**values)


@pytest.mark.parametrize(("values", "message"), [
    ({"distance": 0.1}, "basket distance: 0.1 m is outside the range 0.3 to 20 m"),
    ({"rim_height": -0.3}, "basket rim_height must be a positive number of metres, got -0.3"),
    ({"rim_height": 0.01}, "basket rim_height 0.01 m is no higher than a ball resting on"),
    ({"opening": 0.01}, "basket opening 0.01 m is no wider than the ball"),
    ({"distance": 1.0, "opening": 3.0}, "basket opening 3 m reaches back past the robot from a basket 1 m away"),
])
def test_a_bad_basket_names_the_parameter_not_a_command_line_option(values, message):
    # it said "basket rim_height (--height)" to a library caller, who passes no options
    with pytest.raises(InputError) as caught:
        Basket(**{"distance": 2.0, **values})
    assert str(caught.value).startswith(message) and "--" not in str(caught.value), str(caught.value)


def test_a_robot_without_geometry_cannot_be_simulated():
    robot = load_robot()
    bare = Robot(robot.name, robot.joints, None, source="bare.toml")
    with pytest.raises(InputError, match=r"bare\.toml.*geometry"):
        Arm.from_robot(bare)
