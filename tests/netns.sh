#!/usr/bin/env bash
# Runs a command inside a fresh, loopback-only network namespace, so that DDS
# discovery and data never leave this machine. Needs root (or unprivileged user
# namespaces, tried second).
#   tests/netns.sh CMD [ARGS...]
set -euo pipefail
[ $# -gt 0 ] || { echo "usage: $0 CMD [ARGS...]" >&2; exit 2; }
# DDS's well-known ports (7400 + 250 * domain + ...) for domains above ~101
# fall inside Linux's default ephemeral range (32768-60999): a socket bound to
# port 0 could take a discovery port and a participant would then never be
# found. The namespace's own ephemeral range is moved above the ports of
# domains 0-214.
setup='ip link set lo up && ip link set lo multicast on && ip route add 224.0.0.0/4 dev lo &&
  echo "61000 65535" > /proc/sys/net/ipv4/ip_local_port_range && exec "$@"'
if [ "$(id -u)" = 0 ]; then
  exec unshare --net -- bash -c "$setup" netns "$@"
else
  exec unshare --user --map-root-user --net -- bash -c "$setup" netns "$@"
fi
