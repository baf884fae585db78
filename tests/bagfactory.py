"""Realistic skeleton-tracker bags written with the rosbags writers from simulated throws.

The motion is known exactly: the elbow's included angle follows a curve made of minimum-jerk
transitions (the classic model of human point-to-point motion: smooth up to the acceleration) (rest -> wind-up -> hold -> extension -> follow-through -> rest), and the 3-D joint
positions are built from it (upper arm fixed, forearm rotating in a vertical plane), so a test can
compare what rlff reads back with the true angle, velocity, throw boundaries and release.

The bags look like a Kinect + NiTE2tf recording: /tf at 30 Hz with the 15 skeleton frames of each
tracked user relative to ``openni_depth_frame`` (x forward, y left, z up), a compressed camera
stream interleaved on /camera/rgb/image_color/compressed (real JPEG bytes), lz4 or bz2 chunks,
a second skeleton (a reflection) flickering in and out, and dropped frames and joints.
"""

from __future__ import annotations

import io
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw

TF_TOPIC = "/tf"
IMAGE_TOPIC = "/camera/rgb/image_color/compressed"
PARENT = "openni_depth_frame"
SKELETON = (
    "head", "neck", "torso", "left_shoulder", "left_elbow", "left_hand", "right_shoulder",
    "right_elbow", "right_hand", "left_hip", "left_knee", "left_foot", "right_hip", "right_knee",
    "right_foot",
)
UPPER_ARM = 0.30
FOREARM = 0.28
#: Where the thrower's right shoulder is, in the camera frame (m).
SHOULDER = np.array([2.6, -0.25, 0.35])
#: Horizontal direction of the throw in the camera frame.
FORWARD = np.array([-0.3, 1.0, 0.0]) / np.linalg.norm([-0.3, 1.0, 0.0])
UP = np.array([0.0, 0.0, 1.0])


@dataclass(frozen=True)
class ThrowSpec:
    """One simulated throw: angles (rad) and durations (s) of its phases."""

    rest: float = 2.6
    wound: float = 0.7
    straight: float = 3.0
    wind_up: float = 0.5
    hold: float = 0.1
    extension: float = 0.3
    follow_through: float = 0.4

    @property
    def duration(self) -> float:
        return self.wind_up + self.hold + self.extension + self.follow_through

    @property
    def peak_velocity(self) -> float:
        """Peak angular velocity of the extension (rad/s): minimum jerk peaks at 1.875 x mean."""
        return 1.875 * (self.straight - self.wound) / self.extension


@dataclass
class Simulation:
    """A simulated session: the true motion on a fine clock and the throws' boundaries."""

    throws: list[ThrowSpec]
    starts: list[float]
    duration: float
    rate_hz: float = 30.0
    t0: float = 1_700_000_000.0
    seed: int = 0
    noise: float = 0.002
    drop_frames: float = 0.03
    drop_joints: float = 0.03
    second_user: bool = True
    glitches: int = 0
    frame_times: np.ndarray = field(init=False)

    def __post_init__(self) -> None:
        self.frame_times = np.arange(0.0, self.duration, 1.0 / self.rate_hz)

    @property
    def ends(self) -> list[float]:
        return [start + spec.duration for start, spec in zip(self.starts, self.throws, strict=True)]

    def moving_spans(self, rest_velocity: float = 0.5) -> list[tuple[float, float]]:
        """Per throw, first and last instant (s) the elbow moves faster than ``rest_velocity``.

        These are the boundaries a throw finder with that rest threshold should report: the
        minimum-jerk phases creep in and out of rest, so their nominal ends are not observable.
        """
        spans = []
        for start, end in zip(self.starts, self.ends, strict=True):
            t = np.linspace(start, end, 20001)
            moving = t[np.abs(self.velocity(t)) >= rest_velocity]
            spans.append((float(moving[0]), float(moving[-1])))
        return spans

    def angle(self, t: np.ndarray) -> np.ndarray:
        """True included elbow angle (rad) at times ``t`` (s from the session start)."""
        return self._curve(np.asarray(t, dtype=float), derivative=False)

    def velocity(self, t: np.ndarray) -> np.ndarray:
        """True angular velocity (rad/s)."""
        return self._curve(np.asarray(t, dtype=float), derivative=True)

    def _curve(self, t: np.ndarray, derivative: bool) -> np.ndarray:
        rest = self.throws[0].rest
        out = np.zeros_like(t) if derivative else np.full_like(t, rest)
        for start, spec in zip(self.starts, self.throws, strict=True):
            phases = [
                (spec.wind_up, spec.rest, spec.wound),
                (spec.hold, spec.wound, spec.wound),
                (spec.extension, spec.wound, spec.straight),
                (spec.follow_through, spec.straight, spec.rest),
            ]
            begin = start
            for length, a, b in phases:
                inside = (t >= begin) & (t < begin + length)
                phase = (t[inside] - begin) / length
                if derivative:
                    out[inside] = (b - a) / length * 30 * phase**2 * (1 - phase) ** 2
                else:
                    out[inside] = a + (b - a) * phase**3 * (10 - 15 * phase + 6 * phase**2)
                begin += length
        return out

    def arm_positions(self, angle: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Shoulder, elbow, hand positions of shape (T, 3) for included angles of shape (T,)."""
        upper = np.cos(np.radians(20)) * UP + np.sin(np.radians(20)) * FORWARD
        back = -FORWARD - (-FORWARD @ upper) * upper
        back /= np.linalg.norm(back)
        flexion = np.pi - np.asarray(angle)[:, None]
        elbow = SHOULDER + UPPER_ARM * upper
        forearm = np.cos(flexion) * upper + np.sin(flexion) * back
        count = flexion.shape[0]
        return np.tile(SHOULDER, (count, 1)), np.tile(elbow, (count, 1)), elbow + FOREARM * forearm

    def hand_velocity(self, t: float) -> np.ndarray:
        """True hand velocity (m/s) at time ``t`` (analytic derivative of the hand position)."""
        upper = np.cos(np.radians(20)) * UP + np.sin(np.radians(20)) * FORWARD
        back = -FORWARD - (-FORWARD @ upper) * upper
        back /= np.linalg.norm(back)
        flexion = np.pi - float(self.angle(np.array([t]))[0])
        rate = -float(self.velocity(np.array([t]))[0])
        return FOREARM * rate * (-np.sin(flexion) * upper + np.cos(flexion) * back)

    def frames(self) -> Iterator[tuple[float, dict[str, dict[str, np.ndarray]]]]:
        """(time since start, {user: {joint: position}}) per published tf frame, with the defects.

        User 1 is the thrower (with dropped frames and joints, tracker noise and optional
        one-frame glitches); user 2 is a reflection that appears for 5-20 frames every few seconds.
        """
        rng = np.random.default_rng(self.seed)
        angle = self.angle(self.frame_times)
        shoulder, elbow, hand = self.arm_positions(angle)
        glitch_frames = set(rng.choice(len(self.frame_times), self.glitches, replace=False).tolist()) if self.glitches else set()
        reflection = np.zeros(len(self.frame_times), dtype=bool)
        if self.second_user:
            index = int(rng.integers(10, 60))
            while index < len(reflection):
                length = int(rng.integers(5, 20))
                reflection[index : index + length] = True
                index += length + int(rng.integers(40, 120))
        for k, t in enumerate(self.frame_times):
            if rng.random() < self.drop_frames:
                continue
            body = _body(shoulder[k], elbow[k], hand[k])
            for joint in body:
                body[joint] = body[joint] + rng.normal(0.0, self.noise, 3)
            if k in glitch_frames:
                body["right_hand"] = body["right_hand"] + rng.normal(0.0, 0.25, 3)
            for joint in list(body):
                if rng.random() < self.drop_joints:
                    del body[joint]
            users = {"1": body}
            if reflection[k]:
                mirrored = {name: p * np.array([1.0, -1.0, 1.0]) + np.array([1.5, 0.3, 0.0]) + rng.normal(0, 0.05, 3)
                            for name, p in _body(shoulder[k], elbow[k], hand[k]).items()}
                users["2"] = mirrored
            yield float(t), users


def _body(shoulder: np.ndarray, elbow: np.ndarray, hand: np.ndarray) -> dict[str, np.ndarray]:
    """The 15 NiTE frames of a body whose right arm is given."""
    offsets = {
        "head": [0, 0.25, 0.25], "neck": [0, 0.25, 0.05], "torso": [0, 0.25, -0.25],
        "left_shoulder": [0, 0.5, 0], "left_elbow": [0, 0.55, -0.3], "left_hand": [0.05, 0.55, -0.55],
        "left_hip": [0, 0.4, -0.55], "left_knee": [0, 0.4, -1.0], "left_foot": [0, 0.4, -1.4],
        "right_hip": [0, 0.1, -0.55], "right_knee": [0, 0.1, -1.0], "right_foot": [0, 0.1, -1.4],
    }
    body = {name: shoulder + np.asarray(offset, dtype=float) for name, offset in offsets.items()}
    body.update(right_shoulder=shoulder.copy(), right_elbow=elbow.copy(), right_hand=hand.copy())
    return body


def standard_simulation(seed: int = 0, n_throws: int = 3, **kwargs) -> Simulation:
    """Several throws of varied shape separated by rest, 1 s of rest at both ends."""
    rng = np.random.default_rng(seed)
    throws, starts = [], []
    t = 1.0
    for _ in range(n_throws):
        spec = ThrowSpec(
            wound=float(rng.uniform(0.6, 0.9)), straight=float(rng.uniform(2.8, 3.05)),
            wind_up=float(rng.uniform(0.4, 0.6)), extension=float(rng.uniform(0.25, 0.4)),
            follow_through=float(rng.uniform(0.3, 0.5)),
        )
        throws.append(spec)
        starts.append(t)
        t += spec.duration + float(rng.uniform(1.0, 1.6))
    return Simulation(throws, starts, t + 0.5, seed=seed, **kwargs)


# -- writing --------------------------------------------------------------------------------------


def _ros1_typestore(tf_type: str):
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    store = get_typestore(Stores.ROS1_NOETIC)
    store.register(get_types_from_msg("geometry_msgs/TransformStamped[] transforms", tf_type))
    return store


def jpeg_frames(
    count: int, size: tuple[int, int] = (96, 72), quality: int = 80, seed: int = 0, grain: float = 1.0
) -> list[bytes]:
    """Real JPEG images (a lit gradient, sensor grain of ``grain`` x full scale, the frame number).

    ``grain`` near 0.1 gives the size of a Kinect RGB frame of a room (about 50 kB at 640x480);
    1.0 is pure noise, which compresses worst.
    """
    rng = np.random.default_rng(seed)
    frames = []
    rows, columns = np.mgrid[0 : size[1], 0 : size[0]]
    scene = np.stack([rows / size[1], columns / size[0], (rows + columns) / sum(size)], axis=-1) * 255
    for index in range(count):
        noisy = (1 - grain) * scene + grain * rng.uniform(0, 255, scene.shape)
        image = Image.fromarray(np.clip(noisy, 0, 255).astype(np.uint8))
        ImageDraw.Draw(image).text((4, 4), str(index), fill=(255, 255, 255))
        buffer = io.BytesIO()
        image.save(buffer, format="JPEG", quality=quality)
        frames.append(buffer.getvalue())
    return frames


def nite_frame(joint: str, user: str) -> str:
    """The tf frame NiTE / openni_tracker publish a user's joint as: ``right_elbow_1``."""
    return f"{joint}_{user}"


def _tf_message(store, tf_type: str, stamp_ns: int, users: dict[str, dict[str, np.ndarray]],
                frame_name: Callable[[str, str], str] = nite_frame, parent: str | Callable[[str], str] = PARENT):
    types = store.types
    time = types["builtin_interfaces/msg/Time"](sec=stamp_ns // 10**9, nanosec=stamp_ns % 10**9)
    transforms = []
    for user, body in users.items():
        for joint, position in body.items():
            frame_id = parent if isinstance(parent, str) else parent(joint)
            header = types["std_msgs/msg/Header"](seq=0, stamp=time, frame_id=frame_id)
            transform = types["geometry_msgs/msg/Transform"](
                translation=types["geometry_msgs/msg/Vector3"](x=float(position[0]), y=float(position[1]), z=float(position[2])),
                rotation=types["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0),
            )
            transforms.append(types["geometry_msgs/msg/TransformStamped"](header=header, child_frame_id=frame_name(joint, user), transform=transform))
    return types[tf_type](transforms=transforms)


def _image_message(store, stamp_ns: int, data: bytes, ros2: bool = False):
    types = store.types
    time = types["builtin_interfaces/msg/Time"](sec=stamp_ns // 10**9, nanosec=stamp_ns % 10**9)
    header = types["std_msgs/msg/Header"](stamp=time, frame_id="camera_rgb_optical_frame") if ros2 else \
        types["std_msgs/msg/Header"](seq=0, stamp=time, frame_id="camera_rgb_optical_frame")
    return types["sensor_msgs/msg/CompressedImage"](header=header, format="jpeg", data=np.frombuffer(data, dtype=np.uint8))


def write_ros1_bag(
    path: Path,
    simulation: Simulation,
    *,
    compression: str | None = "lz4",
    tf_type: str = "tf2_msgs/msg/TFMessage",
    images: list[bytes] | None = None,
    image_every: int = 2,
    chunk_bytes: int = 64 * 1024,
    tf_topic: str = TF_TOPIC,
    frame_name: Callable[[str, str], str] = nite_frame,
    names: Callable[[int], tuple[Callable[[str, str], str], str | Callable[[str], str]]] | None = None,
) -> Path:
    """Write the simulation as a ROS 1 bag; images (JPEG bytes, cycled) interleaved with /tf.

    Returns the path. ``compression`` is ``"lz4"``, ``"bz2"`` or None; ``frame_name(joint, user)``
    names a joint's tf frame (NiTE's ``right_elbow_1`` by default); ``names(frame)``, when given,
    gives the ``frame``-th tf message's (0-based) frame namer and parent frame (a name, or a
    function of the joint) instead.
    """
    from rosbags.rosbag1 import Writer

    store = _ros1_typestore(tf_type)
    writer = Writer(path)
    if compression:
        writer.set_compression(getattr(Writer.CompressionFormat, compression.upper()))
    writer.chunk_threshold = chunk_bytes
    t0 = int(simulation.t0 * 1e9)
    with writer:
        tf_conn = writer.add_connection(tf_topic, tf_type, typestore=store, callerid="/nite2tf")
        image_conn = None
        if images:
            image_conn = writer.add_connection(IMAGE_TOPIC, "sensor_msgs/msg/CompressedImage", typestore=store, callerid="/camera")
        frame = 0
        for t, users in simulation.frames():
            stamp = t0 + int(round(t * 1e9))
            if image_conn is not None and frame % image_every == 0:
                data = images[(frame // image_every) % len(images)]
                writer.write(image_conn, stamp - 5_000_000, store.serialize_ros1(_image_message(store, stamp - 5_000_000, data), image_conn.msgtype))
            namer, parent = (frame_name, PARENT) if names is None else names(frame)
            message = _tf_message(store, tf_type, stamp, users, namer, parent)
            writer.write(tf_conn, stamp + 2_000_000, store.serialize_ros1(message, tf_type))
            frame += 1
    return path


def write_marker_bag(path: Path, simulation: Simulation, topic: str = "/skeleton_markers") -> Path:
    """Write the thrower's joints as skeleton_markers draws them in rviz: one
    ``visualization_msgs/Marker`` of POINTS per frame, and no /tf. Returns the path."""
    from rosbags.rosbag1 import Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS1_NOETIC)
    types = store.types
    kind = "visualization_msgs/msg/Marker"
    t0 = int(simulation.t0 * 1e9)
    with Writer(path) as writer:
        connection = writer.add_connection(topic, kind, typestore=store)
        for index, (t, users) in enumerate(simulation.frames()):
            stamp = t0 + int(round(t * 1e9))
            time = types["builtin_interfaces/msg/Time"](sec=stamp // 10**9, nanosec=stamp % 10**9)
            point, zero = types["geometry_msgs/msg/Point"], types["geometry_msgs/msg/Point"](x=0.0, y=0.0, z=0.0)
            marker = types[kind](
                header=types["std_msgs/msg/Header"](seq=index, stamp=time, frame_id=PARENT), ns="skeleton", id=0,
                type=8, action=0,
                pose=types["geometry_msgs/msg/Pose"](
                    position=zero, orientation=types["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0)),
                scale=types["geometry_msgs/msg/Vector3"](x=0.07, y=0.07, z=0.07),
                color=types["std_msgs/msg/ColorRGBA"](r=0.0, g=1.0, b=0.0, a=1.0),
                lifetime=types["builtin_interfaces/msg/Duration"](sec=0, nanosec=0), frame_locked=False,
                points=[point(x=float(p[0]), y=float(p[1]), z=float(p[2])) for p in users["1"].values()], colors=[],
                text="", mesh_resource="", mesh_use_embedded_materials=False,
            )
            writer.write(connection, stamp, store.serialize_ros1(marker, kind))
    return path


def write_ros2_bag(path: Path, simulation: Simulation, *, images: list[bytes] | None = None) -> Path:
    """Write the simulation as a ROS 2 bag folder (sqlite3 storage, CDR, definitions stored)."""
    from rosbags.rosbag2 import Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS2_HUMBLE)
    t0 = int(simulation.t0 * 1e9)
    with Writer(path, version=9) as writer:
        tf_conn = writer.add_connection(TF_TOPIC, "tf2_msgs/msg/TFMessage", typestore=store)
        image_conn = writer.add_connection(IMAGE_TOPIC, "sensor_msgs/msg/CompressedImage", typestore=store) if images else None
        types = store.types
        for index, (t, users) in enumerate(simulation.frames()):
            stamp = t0 + int(round(t * 1e9))
            time = types["builtin_interfaces/msg/Time"](sec=stamp // 10**9, nanosec=stamp % 10**9)
            transforms = [
                types["geometry_msgs/msg/TransformStamped"](
                    header=types["std_msgs/msg/Header"](stamp=time, frame_id=PARENT),
                    child_frame_id=f"{joint}_{user}",
                    transform=types["geometry_msgs/msg/Transform"](
                        translation=types["geometry_msgs/msg/Vector3"](x=float(p[0]), y=float(p[1]), z=float(p[2])),
                        rotation=types["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0),
                    ),
                )
                for user, body in users.items()
                for joint, p in body.items()
            ]
            message = types["tf2_msgs/msg/TFMessage"](transforms=transforms)
            writer.write(tf_conn, stamp, store.serialize_cdr(message, "tf2_msgs/msg/TFMessage"))
            if image_conn is not None and index % 2 == 0:
                image = _image_message(store, stamp, images[index // 2 % len(images)], ros2=True)
                writer.write(image_conn, stamp, store.serialize_cdr(image, "sensor_msgs/msg/CompressedImage"))
    return path
