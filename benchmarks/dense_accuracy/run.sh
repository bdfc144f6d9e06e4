#!/usr/bin/env bash
# Dense-map accuracy against the simulator's true outlines, before and after the first
# loop closure and at the end of the run, for HYMM's layers and the classic grid
# (issue evidence for thesis 3.9 / 4.1.3). Simulates the chapter-3 and chapter-4
# scenarios cut at fixed durations (the same seed gives the same run, so a shorter run
# is an exact prefix of the longer one), runs hymm-slam on each and tabulates
# metrics.json. Needs python3 for the table.
#   benchmarks/dense_accuracy/run.sh [OUT_DIR] [BUILD_DIR]
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
out="${1:-$root/out/dense_accuracy}"
bin="${2:-$root/build}/bin"
mkdir -p "$out"

run() {  # name scenario.ini slam.ini duration_s(0 = whole run)
    local name="$1" scen="$2" slam="$3" dur="$4"
    local d="$out/$name"
    mkdir -p "$d/sim"
    if [ "$dur" = 0 ]; then cp "$scen" "$d/scenario.ini"
    else sed "s/^\[Scenario\]/[Scenario]\nduration_s = $dur/" "$scen" > "$d/scenario.ini"; fi
    "$bin/hymm-simul" -c "$d/scenario.ini" -o "$d/sim" > /dev/null
    local base; base="$(ls "$d"/sim/*.rawlog)"; base="${base%.rawlog}"
    "$bin/hymm-slam" -c "$slam" -r "$base.rawlog" -o "$d" -q \
        --gt-path "${base}_gt_path.tum" --gt-landmarks "${base}_gt_landmarks.csv" \
        --gt-objects "${base}_gt_objects.txt"
}

# Lap time is ~85 s (254 m at 3 m/s): 75 s is before the vehicle is back at the start,
# 110 s after it re-observed the first landmarks.
run ch3_before "$root/configs/sim/ch3_objects.ini" "$root/configs/ch3_slam.ini" 75
run ch3_after  "$root/configs/sim/ch3_objects.ini" "$root/configs/ch3_slam.ini" 110
run ch3_end    "$root/configs/sim/ch3_objects.ini" "$root/configs/ch3_slam.ini" 0
run ch4_before "$root/configs/sim/ch4_objects.ini" "$root/configs/ch4_slam.ini" 75
run ch4_after  "$root/configs/sim/ch4_objects.ini" "$root/configs/ch4_slam.ini" 110
run ch4_end    "$root/configs/sim/ch4_objects.ini" "$root/configs/ch4_slam.ini" 0

python3 - "$out" <<'PY'
import json, sys, os
out = sys.argv[1]
rows = ["| run | landmark err [m] (aligned) | layer | cells/points | mean [m] | p95 [m] | coverage | aligned mean [m] | aligned p95 [m] |",
        "|---|---|---|---|---|---|---|---|---|"]
for name in ["ch3_before", "ch3_after", "ch3_end", "ch4_before", "ch4_after", "ch4_end"]:
    m = json.load(open(os.path.join(out, name, "metrics.json")))
    d = m["dense"]
    al = d.get("landmark_alignment", {})
    for layer in ["occupancy", "points", "classic_grid"]:
        if layer not in d: continue
        x = d[layer]
        a = x.get("aligned", {})
        rows.append("| %s | %.2f (%.2f) | %s | %d | %.3f | %.3f | %.1f%% | %.3f | %.3f |" % (
            name, m["landmarks"]["mean_error_m"], al.get("landmark_mean_error_aligned_m", float("nan")),
            layer, x["points"], x["mean_distance_m"], x["p95_distance_m"], 100 * x["coverage"],
            a.get("mean_distance_m", float("nan")), a.get("p95_distance_m", float("nan"))))
    occ, cl = d["occupancy"], d["classic_grid"]
    rows.append("| %s | rotation %.2f deg | classic / HYMM occupancy | | %.2fx | | | %.2fx | |" % (
        name, al.get("phi_deg", float("nan")), cl["mean_distance_m"] / occ["mean_distance_m"],
        cl["aligned"]["mean_distance_m"] / occ["aligned"]["mean_distance_m"] if "aligned" in occ else float("nan")))
open(os.path.join(out, "summary.md"), "w").write("\n".join(rows) + "\n")
print("\n".join(rows))
PY
