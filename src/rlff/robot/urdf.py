"""The robot as URDF: written from its description, and read back as the joints of a robot file.

``robot_urdf`` writes the kinematic chain of the robot file's convention (see
``rlff/robots/comau_smart5_six.toml``; the MuJoCo scene of :mod:`rlff.sim.scene` follows the same
one) so that RViz, MoveIt and ros2_control load the robot rlff plans for: one revolute joint per
robot joint with its position and speed limits, and every link drawn as a cylinder from its joint
to the next. A URDF has no acceleration or jerk limits (ros2_control reads those from its own
joint-limits parameters), nor effort figures rlff knows: effort is written as 0, "not stated".

``urdf_joints`` reads the movable joints of a URDF (of rlff's or any other) back as the
``[[joints]]`` tables of a robot file, so that a robot file may name a URDF for its joints and
add its ``[throwing]`` table beside it (:func:`rlff.robot.description.load_robot`).

URDF is plain XML: the standard library's ElementTree writes and reads it. A URDF library
(yourdfpy, urchin) would add meshes and scene graphs rlff does not use; the tests read the file
with yourdfpy to show it loads as URDF tools load it.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from rlff.errors import InputError
from rlff.robot.description import Robot

#: Radius (m) of the cylinders that draw the links.
LINK_RADIUS = 0.06
#: Joint types of a URDF that move, and so become joints of the robot.
MOVABLE = ("revolute", "continuous", "prismatic")


def robot_urdf(robot: Robot) -> str:
    """The URDF text of a six-joint arm of the robot-file convention.

    Links ``base_link``, ``link_1`` .. ``link_6`` and ``flange`` (the flange face, fixed to
    ``link_6``); joints named as in the robot file, in its order. With a ``[ros.joints]`` map the
    joints are the controller's (:class:`rlff.robot.joint_map.JointMap`): its names, and its zeros
    and senses, so that the joint states its controller publishes draw the arm where it is (RViz).
    Controller position q_c = offset + sign q turns the link by q = sign (q_c - offset) about the
    axis: the joint's axis is sign times rlff's, its origin turned by -sign offset about it, its
    limits offset + sign times rlff's.

    Raises
    ------
    InputError
        The robot has no ``[geometry]`` table or not six joints.
    """
    if robot.geometry is None:
        raise InputError(f"{robot.source}: the robot has no [geometry] table, so its links cannot be drawn")
    if len(robot.joints) != 6:
        raise InputError(f"{robot.source}: the URDF export knows the 6-joint arm of the robot-file convention, "
                         f"got {len(robot.joints)} joints")
    g = robot.geometry
    # (origin of the joint in its parent link (m), axis, segment drawn in the joint's own link (m))
    chain = [
        ((0.0, 0.0, 0.0), (0, 0, 1), (g.shoulder_forward, 0.0, g.shoulder_height)),
        ((g.shoulder_forward, 0.0, g.shoulder_height), (0, 1, 0), (0.0, 0.0, g.upper_arm)),
        ((0.0, 0.0, g.upper_arm), (0, 1, 0), (0.0, 0.0, g.elbow_offset)),
        ((0.0, 0.0, g.elbow_offset), (1, 0, 0), (g.forearm, 0.0, 0.0)),
        ((g.forearm, 0.0, 0.0), (0, 1, 0), (g.flange, 0.0, 0.0)),
        ((0.0, 0.0, 0.0), (1, 0, 0), (0.0, 0.0, 0.0)),
    ]
    root = ET.Element("robot", name=robot.name)
    root.append(ET.Comment(f" written by rlff from {robot.source}; units: m, rad, rad/s; effort 0: not stated "))
    ET.SubElement(root, "link", name="base_link")
    parent = "base_link"
    joint_map = robot.ros.joints
    for number, (joint, (origin, axis, segment)) in enumerate(zip(robot.joints, chain, strict=True), start=1):
        link = f"link_{number}"
        offset, sign = joint_map.offset_and_sign(joint.name)
        # every axis of the chain is a coordinate axis: turning the origin about it is one rpy angle
        turn = tuple(-sign * offset * component for component in axis)
        lower, upper = sorted(float(v) for v in joint_map.positions_to_controller([joint.name], [[joint.lower],
                                                                                               [joint.upper]])[:, 0])
        element = ET.SubElement(root, "joint", name=joint_map.controller_name(joint.name), type="revolute")
        ET.SubElement(element, "parent", link=parent)
        ET.SubElement(element, "child", link=link)
        ET.SubElement(element, "origin", xyz=_triple(origin), rpy=_triple(turn) if offset else "0 0 0")
        ET.SubElement(element, "axis", xyz=_triple(tuple(sign * component for component in axis)))
        ET.SubElement(element, "limit", lower=repr(lower), upper=repr(upper),
                      velocity=repr(joint.max_velocity), effort="0")
        _link(root, link, segment)
        parent = link
    flange = ET.SubElement(root, "joint", name="flange_fixed", type="fixed")
    ET.SubElement(flange, "parent", link=parent)
    ET.SubElement(flange, "child", link="flange")
    ET.SubElement(flange, "origin", xyz=_triple((g.flange, 0.0, 0.0)), rpy="0 0 0")
    ET.SubElement(root, "link", name="flange")
    ET.indent(root)
    return '<?xml version="1.0"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def _link(root: ET.Element, name: str, segment: tuple[float, float, float]) -> None:
    """A link drawn as a cylinder from its frame's origin to ``segment`` (m), if that is not 0."""
    link = ET.SubElement(root, "link", name=name)
    length = math.dist((0.0, 0.0, 0.0), segment)
    if length == 0:
        return
    # a URDF cylinder lies along its z axis around its origin: turn z onto the segment, centre it
    x, y, z = (value / length for value in segment)
    pitch = math.atan2(math.hypot(x, y), z)
    yaw = math.atan2(y, x) if (x or y) else 0.0
    middle = tuple(0.5 * value for value in segment)
    for kind in ("visual", "collision"):
        element = ET.SubElement(link, kind)
        ET.SubElement(element, "origin", xyz=_triple(middle), rpy=_triple((0.0, pitch, yaw)))
        geometry = ET.SubElement(element, "geometry")
        ET.SubElement(geometry, "cylinder", radius=repr(LINK_RADIUS), length=repr(length))


def _triple(values: tuple[float, float, float]) -> str:
    return " ".join(repr(float(v)) for v in values)


def urdf_joints(path: str | Path) -> tuple[str, list[dict[str, Any]], tuple[str, ...]]:
    """The robot name and the movable joints of a URDF file as robot-file ``[[joints]]`` tables.

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    name : str
        The ``<robot name>``.
    joints : list of dict
        ``{"name", "lower", "upper", "max_velocity"}`` (rad, rad/s) per movable joint, in the
        file's order (the controller order).
    continuous : tuple of str
        The joints of type ``continuous``, which have no position limits: their tables hold
        -pi..pi (:func:`continuous_warning`).

    Raises
    ------
    InputError
        Unreadable or not URDF, no movable joint, or a joint without its limits (named).
    """
    path = Path(path)
    try:
        root = ET.parse(path).getroot()
    except OSError as exc:
        raise InputError(f"cannot read URDF file {path}: {exc.strerror}") from None
    except ET.ParseError as exc:
        raise InputError(f"{path}: not valid XML: {exc}") from None
    if root.tag != "robot":
        raise InputError(f"{path}: not a URDF (root element <{root.tag}>, expected <robot>)")
    joints, continuous = [], []
    for element in root.iter("joint"):
        kind = element.get("type")
        if kind not in MOVABLE:
            continue
        name = element.get("name") or ""
        where = f"{path}: joint {name!r}"
        limit = element.find("limit")
        if limit is None:
            raise InputError(f"{where}: no <limit> (position and velocity limits are needed)")
        table: dict[str, Any] = {"name": name}
        bounds = ("lower", "upper", "velocity") if kind != "continuous" else ("velocity",)
        for key in bounds:
            text = limit.get(key)
            try:
                value = float(text) if text is not None else math.nan
            except ValueError:
                value = math.nan
            if not math.isfinite(value):
                raise InputError(f"{where}: <limit {key}> must be a finite number, got {text!r}")
            table["max_velocity" if key == "velocity" else key] = value
        if kind == "continuous":  # no position limit: a full turn either way is what a robot file can say
            table["lower"], table["upper"] = -math.pi, math.pi
            continuous.append(name)
        joints.append(table)
    if not joints:
        raise InputError(f"{path}: the URDF has no movable joint ({', '.join(MOVABLE)})")
    return root.get("name") or path.stem, joints, tuple(continuous)


def continuous_warning(path: str | Path, names: Sequence[str], remedy: str) -> tuple[str, ...]:
    """The warning (one line, as :func:`rlff.robot.description.implausible_limits`') that the
    continuous joints ``names`` of the URDF ``path`` are limited to -pi..pi; ``remedy`` says where
    to give other limits; nothing for no such joint."""
    if not names:
        return ()
    these = (f"{names[0]} is" if len(names) == 1 else f"{', '.join(names[:-1])} and {names[-1]} are")
    return (f"{path}: {these} continuous in URDF: rlff limits {'it' if len(names) == 1 else 'them'} to -pi..pi rad "
            f"(a full turn) and plans and checks with that; {remedy} to use others",)


def merge_urdf(document: dict[str, Any], folder: Path, source: str) -> tuple[dict[str, Any], tuple[str, ...]]:
    """A robot file's contents with the joints of the URDF its ``urdf`` field names, and the
    warning for its continuous joints the robot file gives no position limits
    (:func:`continuous_warning`).

    ``urdf`` is a path relative to ``folder`` (the robot file's). ``[[joints]]`` tables in the
    robot file then add to (or override) the fields of the URDF joint of the same name, e.g.
    limits a URDF cannot state; one naming a joint the URDF does not have is an error.
    """
    value = document.get("urdf")
    if not isinstance(value, str) or not value:
        raise InputError(f"{source}: field 'urdf' must be a file name, got {value!r}")
    name, joints, continuous = urdf_joints(folder / value)
    by_name = {joint["name"]: joint for joint in joints}
    for table in document.get("joints", []):
        joint = by_name.get(table.get("name")) if isinstance(table, dict) else None
        if joint is None:
            raise InputError(f"{source}: [[joints]] names {table.get('name') if isinstance(table, dict) else table!r}, "
                             f"which {value} does not have (joints: {', '.join(by_name)})")
        joint.update(table)
    stated = {table.get("name") for table in document.get("joints", []) if {"lower", "upper"} <= table.keys()}
    merged = {key: item for key, item in document.items() if key != "urdf"}
    merged.setdefault("name", name)
    merged["joints"] = joints
    return merged, continuous_warning(folder / value, [joint for joint in continuous if joint not in stated],
                                      f"give lower and upper in {source}'s [[joints]] tables")
