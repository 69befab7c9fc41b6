#!/usr/bin/env bash
# Runs a command inside a fresh, loopback-only network namespace, so that DDS
# discovery and data never leave this machine. Needs root (or unprivileged user
# namespaces, tried second).
#   tests/netns.sh CMD [ARGS...]
set -euo pipefail
[ $# -gt 0 ] || { echo "usage: $0 CMD [ARGS...]" >&2; exit 2; }
setup='ip link set lo up && ip link set lo multicast on && ip route add 224.0.0.0/4 dev lo && exec "$@"'
if [ "$(id -u)" = 0 ]; then
  exec unshare --net -- bash -c "$setup" netns "$@"
else
  exec unshare --user --map-root-user --net -- bash -c "$setup" netns "$@"
fi
