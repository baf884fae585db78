#!/usr/bin/env bash
# Set up rlff in ./.venv on a fresh machine.
#   scripts/setup.sh          the library and the `rlff` command (enough for `rlff demo`)
#   scripts/setup.sh --test   also the test tools and the Debian packages the tests use
#                             (ROS 1 for the live robot tests, Chromium for the report test)
# Safe to run again: every step skips what is already there.
set -euo pipefail
cd "$(dirname "$0")/.."

with_tests=0
[[ "${1:-}" == "--test" ]] && with_tests=1

python=${PYTHON:-python3}
if [[ ! -x .venv/bin/python ]]; then
  echo "setup: creating .venv with $($python --version)" >&2
  "$python" -m venv .venv
fi
.venv/bin/python -m pip install --quiet --upgrade pip
if (( with_tests )); then
  .venv/bin/python -m pip install --quiet -e ".[test]"
else
  .venv/bin/python -m pip install --quiet -e .
fi

# The GMR and DMM loops are compiled by numba once, into its cache beside the sources.
echo "setup: compiling the model kernels (the first time only: about a minute and a half)" >&2
.venv/bin/python -c "from rlff.model import compile_kernels; compile_kernels()"

if (( with_tests )); then
  # Debian packages, one per line in scripts/debian-packages.txt (comments with #).
  mapfile -t packages < <(sed -e 's/#.*//' -e 's/[[:space:]]*$//' -e '/^\s*$/d' scripts/debian-packages.txt)
  missing=()
  for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if (( ${#missing[@]} )); then
    sudo=""; (( $(id -u) == 0 )) || sudo="sudo"
    echo "setup: installing Debian packages: ${missing[*]}" >&2
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  fi
  # Further steps (each idempotent), in name order.
  for step in scripts/setup.d/*.sh; do
    [[ -e "$step" ]] || continue
    bash "$step"
  done
fi
# Every rlff command is a new Python process. pip byte-compiles what it installs, but not an
# editable install's sources nor the ROS messages generated above; where the environment keeps
# Python from writing bytecode (PYTHONDONTWRITEBYTECODE, set on the machine this was measured
# on) every process compiled the modules it imports from source again: compiled once here (the
# tests' processes spent 14 % less CPU). A source edited later is compiled in memory until the
# next set-up.
compiled=(src)
site=$(.venv/bin/python -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')
for generated in .venv/ros1/control_msgs "$site/control_msgs"; do
  if [[ -d "$generated" ]]; then compiled+=("$generated"); fi
done
.venv/bin/python -m compileall -q "${compiled[@]}"
echo "setup: done (.venv/bin/rlff)" >&2
