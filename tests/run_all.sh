#!/usr/bin/env bash
# Every test of skyground, from a fresh clone: builds, sets up the rclpy venv,
# runs the Rust tests and the rclpy harness. DDS only ever runs inside a
# loopback-only network namespace (tests/netns.sh) with test-owned domain ids.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
# One-shot builds gain nothing from incremental caches, which cost gigabytes of disk.
export CARGO_INCREMENTAL="${CARGO_INCREMENTAL:-0}"

step() { printf '\n==> %s\n' "$*"; }

step "Rust toolchain checks (fmt, clippy)"
cargo fmt --all -- --check
cargo clippy --workspace --all-targets --locked -- -D warnings

step "build (debug: tests; the codec and algorithms build optimized even here)"
cargo build --workspace --all-targets --locked

step "cjval (CityJSON 2.0 validator for the models and completeness.city.json; installed once into .tools)"
[ -x .tools/bin/cjval ] || cargo install --locked cjval --version 0.10.0 --features build-binary --root .tools
export SKYGROUND_CJVAL="$root/.tools/bin/cjval"

step "rclpy peer venv (.venv, pinned ros-kilted wheels)"
tests/setup_venv.sh

export SKYGROUND_BIN_DIR="$root/target/debug"
export SKYGROUND_SAMPLES_CMD="$root/target/debug/skyground msgs samples"
export SKYGROUND_ROS_SHARE="$root/.venv/share"
export SKYGROUND_SAMPLE_BAG_CMD="$root/target/debug/examples/sample_bag"
export SKYGROUND_REAL_DATA="${SKYGROUND_REAL_DATA:-$root/../shared/data/real}"
[ -d "$SKYGROUND_REAL_DATA" ] || echo "NOTE: $SKYGROUND_REAL_DATA not found: tests that need real data will say SKIPPED"
# Other projects' test files: every command on each (nodes/tests/conformance),
# laspy on what classify writes (tests/python/test_conformance_las.py), and
# the fuzz seeds (core/tests/fuzz_decoders.rs, this many seconds per decoder).
export SKYGROUND_CONFORMANCE_DATA="${SKYGROUND_CONFORMANCE_DATA:-$root/../shared/data/conformance}"
[ -d "$SKYGROUND_CONFORMANCE_DATA" ] || echo "NOTE: $SKYGROUND_CONFORMANCE_DATA not found: the conformance suite will say SKIPPED"
export SKYGROUND_CONFORMANCE_TABLE="$root/target/conformance.md"
export SKYGROUND_FUZZ_SECONDS="${SKYGROUND_FUZZ_SECONDS:-15}"

step "Rust tests (inside a loopback-only network namespace)"
tests/netns.sh cargo test --workspace --offline --locked

step "conformance table (files x commands) and fuzzing report"
[ -f "$SKYGROUND_CONFORMANCE_TABLE" ] && cat "$SKYGROUND_CONFORMANCE_TABLE"
[ -f target/tmp/fuzz-report.md ] && cat target/tmp/fuzz-report.md

step "rclpy harness (pytest, inside a loopback-only network namespace)"
tests/netns.sh "$root/.venv/bin/python" -m pytest -q -p no:cacheprovider tests/python "$@"
