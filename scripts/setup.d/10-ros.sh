#!/usr/bin/env bash
# Make Debian's ROS 1 Python packages reachable from .venv and build control_msgs' action
# messages (Debian does not package control_msgs). Safe to run again.
#
# The venv must keep its own numpy and friends: so never all of /usr/lib/python3/dist-packages,
# only a folder of symlinks to the ROS packages rlff uses (and what they import), appended LAST
# to the venv's sys.path by a .pth file.
set -euo pipefail
cd "$(dirname "$0")/../.."

dist=/usr/lib/python3/dist-packages
if [[ ! -d "$dist/rospy" ]]; then
  echo "10-ros: Debian's ROS 1 packages are not installed (scripts/debian-packages.txt); skipping" >&2
  exit 0
fi

ros_dir="$PWD/.venv/ros1"
mkdir -p "$ros_dir"
packages=(
  rospy actionlib actionlib_msgs trajectory_msgs sensor_msgs geometry_msgs std_msgs
  rosgraph rosgraph_msgs roslib rospkg roscpp genmsg genpy catkin catkin_pkg yaml _yaml
)
for p in "${packages[@]}"; do
  if [[ ! -e "$dist/$p" ]]; then
    echo "10-ros: $dist/$p is missing" >&2
    exit 1
  fi
  ln -sfn "$dist/$p" "$ros_dir/$p"
done

site=$(.venv/bin/python -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')
echo "$ros_dir" > "$site/rlff-ros1.pth"

.venv/bin/python -m rlff.robot.ros1.msgs "$ros_dir" >/dev/null
.venv/bin/python - <<'PY'
import rlff.robot.ros1  # Debian's ROS 1 before the ROS 2 wheels' packages of the same names
import numpy, rospy, actionlib
from control_msgs.msg import FollowJointTrajectoryAction
assert "/usr/lib/python3" not in numpy.__file__, numpy.__file__
assert FollowJointTrajectoryAction._md5sum == "bc4f9b743838566551c0390c65f1a248"
PY
echo "10-ros: ROS 1 reachable from .venv ($ros_dir)" >&2
