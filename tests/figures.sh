#!/usr/bin/env bash
# Re-measures the headline figures of docs/performance.md and
# docs/classification.md and prints them as rows of those pages' tables, so
# a page can be checked against today's code.
#
# NOT run by CI (tests/run_all.sh does not call it): the demo alone takes
# minutes of both cores, the classification group trains four models. Run it
# by hand, on a quiet machine, after `cargo build --release --bin skyground`.
#
#   tests/figures.sh                 # every group
#   tests/figures.sh demo detect     # some of: demo | detect | classify
#
# Env: SKYGROUND_BIN (default target/release/skyground), SKYGROUND_REAL_DATA
# (default ../shared/data/real; the classify group says SKIPPED without it),
# FIGURES_KEEP=1 keeps the scratch directory (else removed at the end; its
# log is printed when a command fails).
set -euo pipefail

root="$(cd "$(dirname "$0")/.." && pwd)"
bin="${SKYGROUND_BIN:-$root/target/release/skyground}"
real="${SKYGROUND_REAL_DATA:-$root/../shared/data/real}"
if [ "$#" -gt 0 ]; then groups=("$@"); else groups=(demo detect classify); fi
for g in "${groups[@]}"; do
  case "$g" in
    demo | detect | classify) ;;
    *) echo "unknown group '$g' (demo | detect | classify)" >&2; exit 2 ;;
  esac
done

[ -x "$bin" ] || { echo "no $bin: cargo build --release --bin skyground (or set SKYGROUND_BIN)" >&2; exit 2; }
command -v python3 >/dev/null || { echo "python3 is needed to read the JSON outputs" >&2; exit 2; }

work="$(mktemp -d "${TMPDIR:-/tmp}/skyground-figures.XXXXXX")"
log="$work/figures.log"
status=0
finish() {
  if [ "$status" != 0 ] && [ -f "$log" ]; then
    echo "--- last lines of $log:" >&2
    tail -n 30 "$log" >&2
  fi
  if [ "${FIGURES_KEEP:-0}" = 1 ]; then
    echo "scratch directory (kept): $work" >&2
  else
    rm -rf "$work"
  fi
}
trap finish EXIT

# The JSON outputs as table rows (python3: no jq needed).
cat >"$work/rows.py" <<'EOF'
import json, sys

def pct(v):
    return "-" if v is None else f"{v * 100:.2f} %"

def num(v, d=3):
    return "-" if v is None else f"{v:,.{d}f}"

def demo(path):
    j = json.load(open(path))
    rows = [
        ("coverage (`coverage_before` → `coverage_after`)",
         f"{pct(j['coverage_before'])} → {pct(j['coverage_after'])}"),
        ("walls (`walls_before` → `walls_after`)",
         f"{pct(j['walls_before'])} → {pct(j['walls_after'])}"),
        ("mean GT→cloud distance (`mean_gt_dist_*`)",
         f"{num(j['mean_gt_dist_before'])} → {num(j['mean_gt_dist_after'])} m"),
        ("LoD2 models' mean distance to the truth (`model_dist_*`)",
         f"{num(j['model_dist_before'])} → {num(j['model_dist_after'])} m"),
        ("rounds, metres driven (`rounds`, `path_length_m`)",
         f"{j['rounds']}, {num(j['path_length_m'], 0)} m"),
        ("stops reached / given up / unreachable; set-downs",
         f"{j['targets_reached']} / {j['targets_given_up']} / {j['targets_unreachable']}; {j['set_downs']}"),
        ("robot (simulated) seconds (`sim_time_s`)", f"{num(j['sim_time_s'], 0)} s"),
        ("mission wall (`wall_time_s`)", f"{num(j['wall_time_s'], 1)} s"),
        ("respawns (`restarts`)", str(j["restarts"] or "none")),
    ]
    if not j["finished"]:
        print(f"note: the mission did not finish ({j['ended_because']})")
    print("| figure | value |\n|---|---|")
    for k, v in rows:
        print(f"| {k} | {v} |")

def detect(path):
    gt = json.load(open(path))["gt"]
    print("| prior, footprints | recall | precision | command |\n|---|---|---|---|")
    print(f"| reference prior, derived footprints | {gt['recall']:.3f} | {gt['precision']:.3f} | tests/figures.sh detect |")

def classify(path, name, trained_on):
    j = json.load(open(path))
    per = {m["class"]: m for m in (j.get("report") or {}).get("per_class", [])}
    b, v, g = per.get(6), per.get(5), j.get("ground")
    has_b = bool(b and b["support"])
    building = f"{b['f1']:.3f} ({b['precision']:.3f} / {b['recall']:.3f})" if has_b else ""
    if v and v["support"]:
        veg = f"{v['f1']:.3f}" + (f" ({v['support']:,} points)" if v["support"] < 1000 else "")
    else:
        veg = "(no vegetation class)" if has_b else ""
    ground = f"{g['total_error'] * 100:.1f} %" if (g and has_b) else ""
    share = j["building_share"] * 100
    share = f"{share:.2f} %" if share < 1 else f"{share:.1f} %"
    print(f"| {name} | {trained_on} | {building} | {veg} | {share} | {ground} |")

{"demo": demo, "detect": detect, "classify": classify}[sys.argv[1]](*sys.argv[2:])
EOF
rows() { python3 "$work/rows.py" "$@"; }

# run CMD...: runs a command with its output in the log; says which failed.
run() {
  "$@" >>"$log" 2>&1 || { echo "FAILED (exit $?): $*"; return 1; }
}

# docs/performance.md, "The reference demo": report.json of a default mission.
fig_demo() {
  echo "## The reference demo (docs/performance.md): skyground demo --out $work/demo"
  # A mission that did not finish exits non-zero but still writes its report.
  "$bin" demo --out "$work/demo" >>"$log" 2>&1 || echo "note: demo exited $?"
  [ -f "$work/demo/report.json" ] || { echo "FAILED: no report.json"; return 1; }
  rows demo "$work/demo/report.json"
}

# docs/performance.md, "Detection": the simulated reference prior, derived footprints.
fig_detect() {
  echo "## Detection (docs/performance.md): skyground aerial --scene reference, then detect --gt"
  run "$bin" aerial --scene reference --out "$work/aerial" || return 1
  "$bin" detect --in "$work/aerial/aerial.las" --out "$work/detect" --gt "$work/aerial" \
    --json >"$work/detect.json" 2>>"$log" || { echo "FAILED: detect"; return 1; }
  rows detect "$work/detect.json"
}

# One row of docs/classification.md's held-out table: FILE scored by MODEL.
classify_row() {
  local file="$1" model="$2" trained_on="$3"
  local out="$work/classify_$((++n_scored)).json" args=(classify --in "$real/$file" --json)
  [ "$model" = shipped ] || args+=(--model "$model")
  "$bin" "${args[@]}" >"$out" 2>>"$log" || { echo "FAILED: classify $file"; return 1; }
  rows classify "$out" "$file" "$trained_on"
}

# docs/classification.md, "Held-out scores": every file scored by a model
# that never saw it, trained as core/tests/classify_real.rs trains them.
fig_classify() {
  echo "## Held-out classification (docs/classification.md): skyground classify --json [--model M]"
  [ -d "$real" ] || { echo "SKIPPED: $real not found (set SKYGROUND_REAL_DATA)"; return 0; }
  local mont=ign_montpellier_150x100m.laz stb=ign_stbarth_100x100m.laz
  local bc=lasr_bcts_forest_1.laz mixed=lidr_mixedconifer.laz m="$work/models"
  n_scored=0
  mkdir -p "$m"
  # Leave one tile out; the forests' rows by models trained without them.
  # (--out always: train's default path is the shipped model.)
  run "$bin" train --in "$real/$stb" --vegetation-in "$real/$bc" --out "$m/no_mont.json.gz" || return 1
  run "$bin" train --in "$real/$mont" --vegetation-in "$real/$bc" --out "$m/no_stb.json.gz" || return 1
  run "$bin" train --in "$real/$mont" "$real/$stb" --out "$m/no_forest.json.gz" || return 1
  run "$bin" train --in "$real/$mont" "$real/$stb" --vegetation-in "$real/$mixed" \
    --out "$m/other_forest.json.gz" || return 1
  echo "| file (held out) | scored by a model trained on | building F1 (P / R) | vegetation F1 | labelled building | ground total error |"
  echo "|---|---|---|---|---|---|"
  local no_forest="Montpellier + St Barth + simulated (no forest)"
  classify_row "$stb" "$m/no_stb.json.gz" "Montpellier + BC forest + simulated" &&
    classify_row "$mont" "$m/no_mont.json.gz" "St Barth + BC forest + simulated" &&
    classify_row ahn3_delft_1.laz shipped shipped &&
    classify_row ahn3_delft_2.laz shipped shipped &&
    classify_row sample_c.las shipped shipped &&
    classify_row "$mixed" shipped shipped &&
    classify_row "$mixed" "$m/no_forest.json.gz" "$no_forest" &&
    classify_row "$bc" "$m/no_forest.json.gz" "$no_forest" &&
    classify_row "$bc" "$m/other_forest.json.gz" "Montpellier + St Barth + lidr_mixedconifer + simulated" &&
    classify_row laspy_nebraska_ftus.las shipped "shipped (its forest without echoes)"
}

for g in "${groups[@]}"; do
  "fig_$g" || status=1
  echo
done
exit "$status"
