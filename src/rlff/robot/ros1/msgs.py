"""Build control_msgs' FollowJointTrajectory action messages for Debian's ROS 1.

Debian packages rospy, actionlib and trajectory_msgs but not control_msgs, so the set-up
(``scripts/setup.d/10-ros.sh``) generates its Python messages here, with ROS' own generators:
genmsg parses the definitions, genpy writes the classes. The action definition ships with rlff
(``definitions/``); an action is expanded into its seven messages the way actionlib defines it.
Debian ships only the generated Python of the messages it depends on (no ``.msg`` files), so
their definitions are read back from those classes (``_full_text``), which keeps their MD5 sums.

Run as ``python -m rlff.robot.ros1.msgs OUTDIR``: writes the ``control_msgs`` package into OUTDIR.
"""

from __future__ import annotations

import importlib
import shutil
import sys
import tempfile
from importlib import resources
from pathlib import Path

PACKAGE = "control_msgs"
ACTION = "FollowJointTrajectory"

# Messages the action depends on, taken from Debian's generated classes (with their own deps).
_DEPENDENCIES = ("trajectory_msgs/JointTrajectory", "actionlib_msgs/GoalStatus", "std_msgs/Header")
_SEPARATOR = "\n" + "=" * 80 + "\n"


def expand_action(name: str, text: str) -> dict[str, str]:
    """The seven message definitions of action ``name`` from its ``.action`` text.

    Returns a mapping of message name (``{name}Goal``, ``{name}ActionGoal``, ...) to its text.
    """
    parts: list[list[str]] = [[]]
    for line in text.splitlines():
        if line.strip() == "---":
            parts.append([])
        else:
            parts[-1].append(line)
    if len(parts) != 3:
        raise ValueError(f"action {name}: expected goal, result and feedback separated by '---'")
    goal, result, feedback = ("\n".join(part) + "\n" for part in parts)
    return {
        f"{name}Goal": goal,
        f"{name}Result": result,
        f"{name}Feedback": feedback,
        f"{name}ActionGoal": f"Header header\nactionlib_msgs/GoalID goal_id\n{name}Goal goal\n",
        f"{name}ActionResult": f"Header header\nactionlib_msgs/GoalStatus status\n{name}Result result\n",
        f"{name}ActionFeedback": f"Header header\nactionlib_msgs/GoalStatus status\n{name}Feedback feedback\n",
        f"{name}Action": (f"{name}ActionGoal action_goal\n{name}ActionResult action_result\n"
                          f"{name}ActionFeedback action_feedback\n"),
    }


def installed_definitions(full_type: str) -> dict[str, str]:
    """Definitions of ``pkg/Type`` and every message it embeds, from the installed class."""
    package, name = full_type.split("/")
    cls = getattr(importlib.import_module(f"{package}.msg"), name)
    own, *embedded = cls._full_text.split(_SEPARATOR)
    definitions = {full_type: own}
    for block in embedded:
        header, _, body = block.partition("\n")
        definitions[header.removeprefix("MSG: ").strip()] = body
    return definitions


def build(outdir: Path) -> Path:
    """Generate the ``control_msgs`` Python package into ``outdir``; returns its folder."""
    import genpy.generate_initpy
    import genpy.generator

    outdir = Path(outdir)
    with tempfile.TemporaryDirectory() as scratch:
        root = Path(scratch)
        definitions: dict[str, str] = {}
        for full_type in _DEPENDENCIES:
            definitions.update(installed_definitions(full_type))
        source = resources.files("rlff.robot.ros1") / "definitions"
        for entry in source.iterdir():
            if entry.name.endswith(".msg"):
                definitions[f"{PACKAGE}/{entry.name[:-4]}"] = entry.read_text(encoding="utf-8")
        action = (source / f"{ACTION}.action").read_text(encoding="utf-8")
        for name, text in expand_action(ACTION, action).items():
            definitions[f"{PACKAGE}/{name}"] = text
        for full_type, text in definitions.items():
            package, name = full_type.split("/")
            (root / package).mkdir(exist_ok=True)
            (root / package / f"{name}.msg").write_text(text, encoding="utf-8")
        search_path = {package.name: [str(package)] for package in root.iterdir()}
        files = sorted(str(path) for path in (root / PACKAGE).glob("*.msg"))
        target = outdir / PACKAGE
        staging = outdir / f".{PACKAGE}.partial"
        shutil.rmtree(staging, ignore_errors=True)
        (staging / "msg").mkdir(parents=True)
        code = genpy.generator.MsgGenerator().generate_messages(PACKAGE, files, str(staging / "msg"), search_path)
        if code:
            raise RuntimeError(f"genpy failed (code {code}) on {PACKAGE}")
        genpy.generate_initpy.write_modules(str(staging / "msg"))
        (staging / "__init__.py").write_text("", encoding="utf-8")
        shutil.rmtree(target, ignore_errors=True)
        staging.rename(target)
    return target


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    if len(args) != 1:
        print("usage: python -m rlff.robot.ros1.msgs OUTDIR", file=sys.stderr)
        return 2
    print(f"built {build(Path(args[0]))}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
