#!/usr/bin/env bash
# Seed corpora for the file-reader targets from the conformance files
# (../shared/data/conformance, or $SKYGROUND_CONFORMANCE_DATA), by extension;
# files over 256 KB are left out (slow executions, no deeper paths).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
data="${SKYGROUND_CONFORMANCE_DATA:-$here/../../shared/data/conformance}"
seed() {  # target ext...
  local target=$1; shift
  mkdir -p "$here/corpus/$target"
  for ext in "$@"; do
    find "$data" -maxdepth 1 -type f -iname "*.$ext" -size -256k -exec cp {} "$here/corpus/$target/" \;
  done
}
seed las_read las laz
seed city_model json jsonl
seed obj_scene obj
seed ply_mesh ply
seed ply_decode ply
seed geojson_footprints geojson
