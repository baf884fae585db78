"""Offscreen pictures of a throw: PNG frames from the side camera and an animated GIF (Pillow).

Rendering needs an OpenGL backend without a display: EGL (Debian libegl1 + libegl-mesa0) or
OSMesa (libosmesa6). MuJoCo picks its backend from ``MUJOCO_GL`` when it is first imported, so
:mod:`rlff.sim` sets it (EGL if its library is found, else OSMesa) before importing MuJoCo unless
the user chose one. Without a backend the frames are skipped with a note, never an error.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import mujoco
import numpy as np
from PIL import Image

from rlff.fileio import atomic_path, prepare_output

#: Frames per second of the recording, and the picture size (pixels).
FPS = 30
WIDTH, HEIGHT = 480, 360


class FrameRecorder:
    """Collects frames of a running simulation and writes them out.

    Parameters
    ----------
    renderer : mujoco.Renderer
    folder : Path
        Where ``frame_0000.png`` ... and ``throw.gif`` go (created if missing).
    fps : int
        Frames per second of simulated time.
    """

    def __init__(self, renderer: mujoco.Renderer, folder: Path, fps: int = FPS) -> None:
        self.renderer = renderer
        self.folder = folder
        self.fps = fps
        self.images: list[np.ndarray] = []

    def capture(self, data: mujoco.MjData) -> None:
        """Render the current state from the side camera."""
        self.renderer.update_scene(data, camera="side")
        # shadows and reflections cost most of a software-rendered frame and show little here
        for flag in (mujoco.mjtRndFlag.mjRND_SHADOW, mujoco.mjtRndFlag.mjRND_REFLECTION):
            self.renderer.scene.flags[flag] = False
        self.images.append(self.renderer.render().copy())

    def finish(self) -> tuple[Path, ...]:
        """Write the PNG frames and the GIF; returns their paths (the GIF last).

        Frames of an earlier, longer throw in the same folder are removed so that the folder
        shows one throw.
        """
        prepare_output(self.folder, folder=True)
        self.folder.mkdir(exist_ok=True)
        pictures = [Image.fromarray(image) for image in self.images]
        paths = []
        for number, picture in enumerate(pictures):
            path = self.folder / f"frame_{number:04d}.png"
            with atomic_path(path) as temp:
                picture.save(temp)
            paths.append(path)
        for stale in self.folder.glob("frame_*.png"):  # left by a longer earlier throw
            if stale.stem[len("frame_"):].isdigit() and int(stale.stem[len("frame_"):]) >= len(pictures):
                stale.unlink()
        if pictures:
            gif = self.folder / "throw.gif"
            with atomic_path(gif) as temp:
                pictures[0].save(temp, save_all=True, append_images=pictures[1:], duration=round(1000 / self.fps), loop=0)
            paths.append(gif)
        self.renderer.close()
        return tuple(paths)


def open_recorder(model: mujoco.MjModel, folder: Path) -> tuple[FrameRecorder | None, str]:
    """A recorder for ``model``, or ``None`` and the reason when no OpenGL backend works."""
    try:
        with warnings.catch_warnings():  # glfw without a display warns before it fails: the note says it
            warnings.simplefilter("ignore")
            renderer = mujoco.Renderer(model, HEIGHT, WIDTH)
    except Exception as exc:  # the backends fail with many kinds of errors (ImportError, FatalError, ...)
        return None, (f"frames skipped: no OpenGL backend for offscreen rendering ({type(exc).__name__}: {exc}); "
                      "install libegl1 or libosmesa6 and set MUJOCO_GL=egl or osmesa")
    return FrameRecorder(renderer, folder), ""
