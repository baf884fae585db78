#!/usr/bin/env bash
# Make Debian's ROS 1 Python packages reachable from .venv and build control_msgs' action
# messages (Debian does not package control_msgs): rlff.robot.ros1.install does both, the way a
# wheel's user runs it (python -m rlff.robot.ros1.install), and says how. Safe to run again.
set -euo pipefail
cd "$(dirname "$0")/../.."

if [[ ! -d /usr/lib/python3/dist-packages/rospy ]]; then
  echo "10-ros: Debian's ROS 1 packages are not installed (scripts/debian-packages.txt); skipping" >&2
  exit 0
fi
.venv/bin/python -m rlff.robot.ros1.install | sed 's/^/10-ros: /' >&2
