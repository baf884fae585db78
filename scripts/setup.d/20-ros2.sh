#!/usr/bin/env bash
# Live ROS 2 (Kilted) in .venv from PyPI wheels: install the `ros2` extra, then build
# control_msgs' FollowJointTrajectory against the wheels and make their libraries load without
# LD_LIBRARY_PATH (rlff.robot.ros2.install says how). Safe to run again: a few seconds when
# everything is in place; about 30 s the first time.
set -euo pipefail
cd "$(dirname "$0")/../.."

.venv/bin/python -m pip install --quiet -e ".[ros2]"
.venv/bin/python -m rlff.robot.ros2.install | sed 's/^/20-ros2: /' >&2
