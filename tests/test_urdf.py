"""The robot as URDF: written by ``rlff robot urdf``, read back by yourdfpy, used as a robot file."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
import yourdfpy

from rlff.errors import InputError
from rlff.robot import RobotMapping, load_robot
from rlff.robot.description import RobotFileWarning
from rlff.sim.arm import Arm


@pytest.fixture
def urdf_file(rlff, tmp_path):
    out = tmp_path / "comau.urdf"
    result = rlff("robot", "urdf", "-o", str(out))
    assert result.code == 0, result.stderr
    assert f"wrote {out}" in result.stderr
    return out


def test_yourdfpy_reads_the_same_joints_and_limits(urdf_file):
    robot = load_robot()
    model = yourdfpy.URDF.load(str(urdf_file), load_meshes=False)
    movable = [joint for joint in model.robot.joints if joint.type != "fixed"]
    assert [joint.name for joint in movable] == list(robot.joint_names)
    for joint, expected in zip(movable, robot.joints, strict=True):
        assert joint.type == "revolute"
        assert (joint.limit.lower, joint.limit.upper, joint.limit.velocity) == (
            expected.lower, expected.upper, expected.max_velocity)
    assert {link.name for link in model.robot.links} == {"base_link", *(f"link_{i}" for i in range(1, 7)), "flange"}


def test_the_urdf_chain_is_the_arm_of_the_simulation(urdf_file):
    """Elbow, wrist and flange where rlff's own kinematics (checked against MuJoCo) put them."""
    robot = load_robot()
    arm = Arm.from_robot(robot)
    model = yourdfpy.URDF.load(str(urdf_file), load_meshes=False)
    rng = np.random.default_rng(17)
    for _ in range(5):
        q2, q3, q5 = (rng.uniform(robot.joint(n).lower, robot.joint(n).upper) for n in ("joint_2", "joint_3", "joint_5"))
        model.update_cfg({"joint_1": 0.0, "joint_2": q2, "joint_3": q3, "joint_4": 0.0, "joint_5": q5, "joint_6": 0.3})
        pose = arm.in_plane(q2, q3, q5)
        for link, point in (("link_3", None), ("link_5", pose.wrist)):
            origin = model.get_transform(link, "base_link")[:3, 3]
            assert origin[1] == pytest.approx(0.0, abs=1e-12)
            if point is not None:
                np.testing.assert_allclose(origin[[0, 2]], point, atol=1e-9)
        elbow = model.get_transform("link_3", "base_link")[:3, 3]
        g = robot.geometry
        shoulder = np.array([g.shoulder_forward, g.shoulder_height])
        np.testing.assert_allclose(elbow[[0, 2]], shoulder + g.upper_arm * np.array([math.sin(q2), math.cos(q2)]),
                                   atol=1e-9)
    model.update_cfg(dict.fromkeys(robot.joint_names, 0.0))
    np.testing.assert_allclose(model.get_transform("flange", "base_link")[:3, 3], [0.892, 0.0, 1.17], atol=1e-12)
    # joint 1 turns the whole arm about the vertical axis, to the left for a positive angle
    model.update_cfg({"joint_1": math.pi / 2})
    np.testing.assert_allclose(model.get_transform("flange", "base_link")[:3, 3], [0.0, 0.892, 1.17], atol=1e-12)


def test_a_robot_file_may_take_its_joints_from_a_urdf(urdf_file, tmp_path, rlff):
    builtin = load_robot()
    # what a URDF cannot say (acceleration and jerk limits) comes from the robot file's tables
    tables = "".join(f'[[joints]]\nname = "{j.name}"\nmax_acceleration = {j.max_acceleration!r}\n'
                     f'max_jerk = {j.max_jerk!r}\n' + ("max_velocity = 2.0\n" if j.name == "joint_2" else "") + "\n"
                     for j in builtin.joints)
    robot_file = tmp_path / "robot.toml"
    robot_file.write_text(f'urdf = "{urdf_file.name}"\n\n' + tables +
                          '[throwing]\njoint = "joint_2"\nangle_offset = -1.65\nangle_scale = 0.71\n'
                          'velocity_scale = 0.25\n\n[throwing.start_pose]\njoint_1 = 0.0\njoint_3 = -1.373\n'
                          'joint_4 = 0.0\njoint_5 = -0.198\njoint_6 = 0.0\n')
    robot = load_robot(robot_file)
    assert robot.name == "comau_smart5_six" and robot.joint_names == builtin.joint_names
    assert robot.joint("joint_2").max_velocity == 2.0  # the robot file's table adds to the URDF's
    assert robot.joint("joint_3") == builtin.joint("joint_3")
    mapping = RobotMapping.for_robot(robot)
    np.testing.assert_allclose(mapping.pose(0.5), RobotMapping.for_robot(builtin).pose(0.5))
    shown = rlff("robot", "show", "--robot", str(robot_file), "--json")
    assert shown.code == 0, shown.stderr
    assert '"joint": "joint_2"' in shown.stdout
    # and the bare URDF is a robot too: joints with position and speed limits, no mapping
    bare = load_robot(urdf_file)
    assert [(j.name, j.lower, j.upper, j.max_velocity) for j in bare.joints] == [
        (j.name, j.lower, j.upper, j.max_velocity) for j in builtin.joints]
    assert bare.joint("joint_1").max_acceleration is None and not bare.throwing
    shown = rlff("robot", "show", "--robot", str(urdf_file))  # its missing limits shown as such
    assert shown.code == 0, shown.stderr
    assert "no acceleration or jerk limits" in shown.stdout and "        -" in shown.stdout
    with pytest.raises(InputError, match=r"comau.urdf has no \[throwing\] table.*a URDF states the joints"):
        RobotMapping.for_robot(bare)


def test_bad_urdf_files_are_errors_that_name_the_joint(tmp_path):
    broken = tmp_path / "broken.urdf"
    broken.write_text('<robot name="r"><joint name="j1" type="revolute"><parent link="a"/><child link="b"/>'
                      '</joint></robot>')
    with pytest.raises(InputError, match=r"broken.urdf: joint 'j1': no <limit>"):
        load_robot(broken)
    broken.write_text('<robot name="r"><joint name="j1" type="revolute"><limit lower="0" upper="x" velocity="1"/>'
                      '</joint></robot>')
    with pytest.raises(InputError, match=r"joint 'j1': <limit upper> must be a finite number, got 'x'"):
        load_robot(broken)
    # the joint's own checks, loaded directly: named with the file, as a robot file's are (it was not)
    broken.write_text('<robot name="r">' + _joint("a", "revolute", 'lower="-1" upper="1"')
                      + _joint("b", "revolute", 'lower="1.8" upper="-1"') + "</robot>")
    with pytest.raises(InputError, match=r"^\S*broken.urdf: joint 2 \(b\): lower limit 1.8 is not below upper -1.0$"):
        load_robot(broken)
    broken.write_text("<robot")
    with pytest.raises(InputError, match="not valid XML"):
        load_robot(broken)
    robot_file = tmp_path / "robot.toml"
    robot_file.write_text('urdf = "missing.urdf"\n')
    with pytest.raises(InputError, match="cannot read URDF file .*missing.urdf"):
        load_robot(robot_file)


def _joint(name: str, kind: str, limit: str) -> str:
    return (f'<joint name="{name}" type="{kind}"><parent link="base_link"/><child link="{name}_link"/>'
            f'<limit {limit} velocity="1.5" effort="10"/></joint><link name="{name}_link"/>')


def test_continuous_joints_are_limited_to_a_turn_and_said_so(tmp_path, rlff):
    """A continuous joint became revolute -pi..pi without a word (tester H): the limits rlff plans
    with are said as the URDF loads, unless a robot file gives its own."""
    urdf = tmp_path / "cont.urdf"
    urdf.write_text('<robot name="cont"><link name="base_link"/>' + _joint("a", "continuous", "")
                    + _joint("b", "revolute", 'lower="-1" upper="1"') + _joint("c", "continuous", "") + "</robot>")
    said = (f"{urdf}: a and c are continuous in URDF: rlff limits them to -pi..pi rad (a full turn) and plans and "
            "checks with that; give lower and upper in a robot file's [[joints]] tables beside urdf = ... to use others")
    with pytest.warns(RobotFileWarning) as caught:
        robot = load_robot(urdf)
    assert [str(w.message) for w in caught] == [said] and robot.warnings == (said,)
    assert (robot.joint("a").lower, robot.joint("a").upper) == (-math.pi, math.pi)
    shown = rlff("robot", "show", "--robot", str(urdf))
    assert shown.code == 0 and shown.stderr == f"warning: {said}\n", shown.stderr
    robot_file = tmp_path / "robot.toml"
    tables = {"a": "lower = -2.0\nupper = 2.0\n", "b": "", "c": "upper = 1.0\n"}  # c: one bound of two
    robot_file.write_text('urdf = "cont.urdf"\n' + "".join(f'[[joints]]\nname = "{name}"\nmax_acceleration = 5.0\n'
                                                            f"max_jerk = 40.0\n{more}" for name, more in tables.items()))
    with pytest.warns(RobotFileWarning) as caught:
        robot = load_robot(robot_file)
    assert [str(w.message) for w in caught] == [
        f"{urdf}: c is continuous in URDF: rlff limits it to -pi..pi rad (a full turn) and plans and checks with that; "
        f"give lower and upper in {robot_file}'s [[joints]] tables to use others"]
    assert (robot.joint("a").lower, robot.joint("a").upper) == (-2.0, 2.0)
    robot_file.write_text(robot_file.read_text().replace("upper = 1.0", "lower = -1.0\nupper = 1.0"))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert load_robot(robot_file).warnings == ()


def test_unknown_joint_beside_a_urdf_is_an_error(urdf_file, tmp_path):
    robot_file = tmp_path / "robot.toml"
    robot_file.write_text(f'urdf = "{urdf_file.name}"\n[[joints]]\nname = "joint_9"\nmax_velocity = 1.0\n')
    with pytest.raises(InputError, match=r"\[\[joints\]\] names 'joint_9', which comau.urdf does not have"):
        load_robot(robot_file)


def test_urdf_of_a_robot_without_geometry_is_refused(tmp_path, rlff):
    robot_file = tmp_path / "bare.toml"
    robot_file.write_text('name = "bare"\n[[joints]]\nname = "a"\nlower = -1.0\nupper = 1.0\nmax_velocity = 1.0\n'
                          'max_acceleration = 1.0\nmax_jerk = 1.0\n')
    result = rlff("robot", "urdf", "-o", str(tmp_path / "bare.urdf"), "--robot", str(robot_file))
    assert result.code == 2
    assert "has no [geometry] table" in result.stderr
    assert not (tmp_path / "bare.urdf").exists()


def test_a_mapped_robot_s_urdf_is_the_controller_s_and_draws_the_arm_its_joint_states_describe(rlff, tmp_path):
    """With [ros.joints] the URDF carries the controller's names, zeros and senses: RViz fed the
    controller's joint states (offset + sign x rlff's) draws every link where rlff's URDF at rlff's
    angles does. It kept rlff's names, so the UR-named states of `robot serve` moved nothing."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).parent))
    from rosrig import UR_NAMES, ur_file

    mapped = ur_file(tmp_path / "ur.toml")
    robot = load_robot(mapped)
    joints = robot.ros.joints
    assert rlff("robot", "urdf", "--robot", str(mapped), "-o", str(tmp_path / "ur.urdf")).code == 0
    assert rlff("robot", "urdf", "-o", str(tmp_path / "own.urdf")).code == 0
    theirs = yourdfpy.URDF.load(str(tmp_path / "ur.urdf"), load_meshes=False)
    own = yourdfpy.URDF.load(str(tmp_path / "own.urdf"), load_meshes=False)
    movable = [joint for joint in theirs.robot.joints if joint.type != "fixed"]
    assert [joint.name for joint in movable] == list(UR_NAMES)
    for joint, mine in zip(movable, robot.joints, strict=True):  # the limits in the controller's convention
        ends = sorted(joints.positions_to_controller([mine.name], [[mine.lower], [mine.upper]])[:, 0])
        assert (joint.limit.lower, joint.limit.upper) == pytest.approx(tuple(ends), abs=1e-12)
    rng = np.random.default_rng(5)
    for _ in range(20):
        q = np.array([rng.uniform(j.lower, j.upper) for j in robot.joints])
        own.update_cfg(dict(zip(robot.joint_names, q, strict=True)))
        theirs.update_cfg(dict(zip(UR_NAMES, joints.positions_to_controller(robot.joint_names, q), strict=True)))
        for link in ("link_2", "link_3", "link_5", "flange"):
            np.testing.assert_allclose(theirs.get_transform(link, "base_link"), own.get_transform(link, "base_link"),
                                       atol=1e-9)
