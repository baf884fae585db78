"""Completing the ROS 2 Kilted wheels in the venv: control_msgs, and libraries that load as they are.

Run as ``python -m rlff.robot.ros2.install`` (``scripts/setup.d/20-ros2.sh`` does, after
installing the ``ros2`` extra). Three steps, each skipped when already done:

1. The wheels' shared libraries find each other only through ``LD_LIBRARY_PATH``, which a
   ``.pth`` bootstrapper sets by re-running every Python of the venv (so a Python started with
   ``_ROS_WHEELS_BOOTSTRAP_COMPLETE`` inherited, or with ``-S``, cannot import rclpy). Each
   library of a ``ros-*`` distribution gets an RPATH to the venv's ``lib`` folder and to the
   wheels' vendored-library folders (``ros_*.libs``) instead, with patchelf, and the
   bootstrapper's ``.pth`` is removed: every Python of the venv starts once, as usual.
2. control_msgs is not among the wheels. Its FollowJointTrajectory action and the tolerance
   messages it uses (the definitions of the release that goes with Kilted, kept in
   ``definitions/``) are built by cmake and ``rosidl_generate_interfaces`` against the wheels
   and installed into the venv: the real type ``control_msgs/action/FollowJointTrajectory``,
   with the C, C++ and Python type supports any ROS 2 node expects.
3. A fresh interpreter, with the bootstrapper's marker set and no library path, imports rclpy
   and the action: the check that the venv works with no environment to source.

Nothing is downloaded: cmake, g++ and the Python headers come from Debian
(``scripts/debian-packages.txt``), everything else from the wheels already installed.
"""

from __future__ import annotations

import hashlib
import importlib.metadata
import json
import os
import shutil
import subprocess
import sys
import sysconfig
import tempfile
from collections.abc import Iterable
from importlib import resources
from pathlib import Path

PACKAGE = "control_msgs"
#: control_msgs release whose definitions ``definitions/`` holds (the Kilted-era 6.x line).
VERSION = "6.8.0"
BOOTSTRAPPER = "ros_wheels_bootstrapper.pth"
_ELF_MAGIC = b"\x7fELF"

_PACKAGE_XML = """<?xml version="1.0"?>
<package format="3">
  <name>control_msgs</name>
  <version>{version}</version>
  <description>control_msgs' FollowJointTrajectory action and tolerance messages, built by rlff</description>
  <maintainer email="rlff@example.com">rlff</maintainer>
  <license>Apache-2.0</license>
  <buildtool_depend>ament_cmake</buildtool_depend>
  <buildtool_depend>rosidl_default_generators</buildtool_depend>
  <depend>action_msgs</depend>
  <depend>builtin_interfaces</depend>
  <depend>std_msgs</depend>
  <depend>trajectory_msgs</depend>
  <exec_depend>rosidl_default_runtime</exec_depend>
  <member_of_group>rosidl_interface_packages</member_of_group>
  <export><build_type>ament_cmake</build_type></export>
</package>
"""

# The wheels' exported *__rosidl_generator_py targets carry the include folders of the machine
# that built them (its Python and NumPy headers) in INTERFACE_INCLUDE_DIRECTORIES, which stops
# the generate step; the loop swaps the folders that do not exist here for this interpreter's.
_CMAKE_LISTS = """cmake_minimum_required(VERSION 3.16)
project(control_msgs)
find_package(ament_cmake REQUIRED)
find_package(rosidl_default_generators REQUIRED)
find_package(action_msgs REQUIRED)
find_package(builtin_interfaces REQUIRED)
find_package(std_msgs REQUIRED)
find_package(trajectory_msgs REQUIRED)
rosidl_generate_interfaces(${{PROJECT_NAME}}
  {files}
  DEPENDENCIES action_msgs builtin_interfaces std_msgs trajectory_msgs)
get_property(_imported DIRECTORY PROPERTY IMPORTED_TARGETS)
foreach(_target IN LISTS _imported)
  if(_target MATCHES "__rosidl_generator_py$")
    get_target_property(_folders ${{_target}} INTERFACE_INCLUDE_DIRECTORIES)
    set(_kept "")
    foreach(_folder IN LISTS _folders)
      if(EXISTS "${{_folder}}")
        list(APPEND _kept "${{_folder}}")
      endif()
    endforeach()
    list(APPEND _kept "${{RLFF_PYTHON_INCLUDE}}" "${{RLFF_NUMPY_INCLUDE}}")
    set_target_properties(${{_target}} PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${{_kept}}")
  endif()
endforeach()
ament_package()
"""

_CHECK = """
import rclpy, rclpy.action
from control_msgs.action import FollowJointTrajectory
from control_msgs.msg import JointTolerance
assert 'index' in FollowJointTrajectory.Feedback.get_fields_and_field_types()
print(FollowJointTrajectory.__module__)
"""


def _site() -> Path:
    return Path(sysconfig.get_paths()["purelib"])


def _prefix() -> Path:
    return Path(sys.prefix)


def _is_elf(path: Path) -> bool:
    try:
        with open(path, "rb") as handle:
            return handle.read(4) == _ELF_MAGIC
    except OSError:
        return False


def ros_libraries() -> list[Path]:
    """Every ELF file installed by a ``ros-*`` distribution (libraries and Python extensions)."""
    found = set()
    for dist in importlib.metadata.distributions():
        name = (dist.metadata["Name"] or "").lower()
        if not name.startswith("ros-"):
            continue
        for entry in dist.files or ():
            if ".so" in entry.name:
                path = Path(dist.locate_file(entry)).resolve()
                if path.is_file() and not path.is_symlink() and _is_elf(path):
                    found.add(path)
    return sorted(found)


def library_folders() -> list[Path]:
    """Where the wheels' libraries live: the venv's ``lib`` and the ``ros_*.libs`` folders."""
    return [(_prefix() / "lib").resolve(), *sorted(p.resolve() for p in _site().glob("ros_*.libs") if p.is_dir())]


def _patchelf(*args: str) -> str:
    tool = shutil.which("patchelf", path=str(Path(sys.executable).parent)) or shutil.which("patchelf")
    if tool is None:
        raise RuntimeError("patchelf is not installed (the ros2 extra installs it)")
    return subprocess.run([tool, *args], check=True, capture_output=True, text=True).stdout.strip()


def patch_rpaths(files: Iterable[Path], folders: list[Path]) -> int:
    """Add ``$ORIGIN``-relative entries for ``folders`` to each file's RPATH; returns files changed.

    DT_RPATH (not RUNPATH) on purpose: it also serves the libraries a library loads and the
    type supports that rcutils opens by name at run time.
    """
    changed = 0
    for path in files:
        current = [entry for entry in _patchelf("--print-rpath", str(path)).split(":") if entry]
        wanted = ["$ORIGIN/" + os.path.relpath(folder, path.parent) for folder in folders]
        missing = [entry for entry in wanted if entry not in current]
        if missing:
            _patchelf("--force-rpath", "--set-rpath", ":".join(current + missing), str(path))
            changed += 1
    return changed


def _wheels_fingerprint() -> str:
    versions = sorted(f"{d.metadata['Name']}=={d.version}" for d in importlib.metadata.distributions()
                      if (d.metadata["Name"] or "").lower().startswith("ros-"))
    return hashlib.sha256("\n".join(versions).encode()).hexdigest()[:16]


def _definitions() -> dict[str, str]:
    """``{"msg/JointTolerance.msg": text, "action/FollowJointTrajectory.action": text, ...}``."""
    folder = resources.files("rlff.robot.ros2") / "definitions"
    texts = {}
    for entry in sorted(folder.iterdir(), key=lambda e: e.name):
        kind = {"msg": "msg", "action": "action"}.get(entry.name.rsplit(".", 1)[-1])
        if kind:
            texts[f"{kind}/{entry.name}"] = entry.read_text(encoding="utf-8")
    return texts


def build_interfaces(prefix: Path, jobs: int = 2) -> list[Path]:
    """Generate, build and install control_msgs into ``prefix``; returns the files installed."""
    import numpy

    cmake = shutil.which("cmake")
    if cmake is None:
        raise RuntimeError("cmake is not installed (scripts/debian-packages.txt lists it)")
    definitions = _definitions()
    env = dict(os.environ, AMENT_PREFIX_PATH=str(prefix), CMAKE_PREFIX_PATH=str(prefix),
               CMAKE_BUILD_PARALLEL_LEVEL=str(jobs), _ROS_WHEELS_BOOTSTRAP_COMPLETE="1")
    with tempfile.TemporaryDirectory(prefix="rlff-control-msgs-") as scratch:
        source, build = Path(scratch) / "src", Path(scratch) / "build"
        for name, text in definitions.items():
            (source / name).parent.mkdir(parents=True, exist_ok=True)
            (source / name).write_text(text, encoding="utf-8")
        (source / "package.xml").write_text(_PACKAGE_XML.format(version=VERSION), encoding="utf-8")
        (source / "CMakeLists.txt").write_text(_CMAKE_LISTS.format(files="\n  ".join(definitions)),
                                               encoding="utf-8")
        steps = (
            [cmake, "-S", str(source), "-B", str(build), "-DBUILD_TESTING=OFF", "-DCMAKE_BUILD_TYPE=Release",
             f"-DCMAKE_INSTALL_PREFIX={prefix}", f"-DCMAKE_PREFIX_PATH={prefix}",
             f"-DPython3_EXECUTABLE={sys.executable}",
             f"-DRLFF_PYTHON_INCLUDE={sysconfig.get_paths()['include']}",
             f"-DRLFF_NUMPY_INCLUDE={numpy.get_include()}"],
            [cmake, "--build", str(build)],
            [cmake, "--install", str(build)],
        )
        for step in steps:
            done = subprocess.run(step, env=env, capture_output=True, text=True)
            if done.returncode:
                raise RuntimeError(f"{' '.join(step[:2])} failed ({done.returncode}):\n"
                                   f"{done.stdout[-4000:]}\n{done.stderr[-4000:]}")
        manifest = (build / "install_manifest.txt").read_text(encoding="utf-8").split()
    return [Path(line) for line in manifest]


def check() -> str:
    """Import rclpy and the action in a fresh interpreter with no library path; its output."""
    env = {key: value for key, value in os.environ.items() if key not in ("LD_LIBRARY_PATH", "PYTHONPATH")}
    env["_ROS_WHEELS_BOOTSTRAP_COMPLETE"] = "1"  # as if the bootstrapper had run: it must not matter
    done = subprocess.run([sys.executable, "-c", _CHECK], env=env, capture_output=True, text=True)
    if done.returncode:
        raise RuntimeError(f"the venv cannot import rclpy and control_msgs.action:\n{done.stderr[-4000:]}")
    return done.stdout.strip()


def install(force: bool = False) -> list[str]:
    """Run the three steps (see the module docstring); returns what was done, one line each."""
    prefix, site = _prefix(), _site()
    stamp = prefix / "share" / "rlff" / "ros2-install.json"
    wanted = {"wheels": _wheels_fingerprint(), "control_msgs": VERSION,
              "definitions": hashlib.sha256(json.dumps(_definitions(), sort_keys=True).encode()).hexdigest()[:16]}
    done = []
    previous = json.loads(stamp.read_text()) if stamp.is_file() else {}
    folders = library_folders()
    if force or previous.get("wheels") != wanted["wheels"]:
        changed = patch_rpaths(ros_libraries(), folders)
        done.append(f"RPATH of {changed} wheel libraries set to the venv's library folders")
    bootstrapper = site / BOOTSTRAPPER
    if bootstrapper.exists():
        bootstrapper.unlink()
        done.append(f"removed {bootstrapper.name}: the libraries no longer need LD_LIBRARY_PATH")
    if force or previous != wanted or not (site / PACKAGE / "action").is_dir():
        installed = build_interfaces(prefix)
        libraries = [path for path in installed if ".so" in path.name and _is_elf(path)]
        patch_rpaths(libraries, folders)
        done.append(f"built and installed {PACKAGE} {VERSION} ({len(installed)} files, "
                    f"{len(libraries)} libraries)")
    done.append(f"checked: {check()} imports with no environment to source")
    stamp.parent.mkdir(parents=True, exist_ok=True)
    stamp.write_text(json.dumps(wanted, indent=1) + "\n")
    return done


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    if args not in ([], ["--force"]):
        print("usage: python -m rlff.robot.ros2.install [--force]", file=sys.stderr)
        return 2
    for line in install(force=bool(args)):
        print(line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
