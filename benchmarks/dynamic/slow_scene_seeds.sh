#!/usr/bin/env bash
# The slow-motion scene (thesis 6.3.3, Fig. 6.10) over N noise seeds: per seed, simulate
# the scenario (default configs/sim/ch6_dynamic_slow.ini), run hymm-slam (default
# configs/ch6_dynamic_slow.ini)
# with the simulator's object truth, and print the slow layer's scores from metrics.json:
# precision, recall, static false-positive fraction, per changed area detected/recall, and
# the path's position RMSE (whether a setting reaches the filter).
#   benchmarks/dynamic/slow_scene_seeds.sh BUILD_DIR WORK_DIR [N=20] [SLAM_INI] [FIRST_SEED=1] [SCENARIO_INI]
# (SCENARIO_INI: another slow scene with the same moving objects, e.g.
# configs/sim/ch6_dynamic_slow_short.ini)
set -euo pipefail
build="$1"; work="$2"; n="${3:-20}"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
slam="${4:-$root/configs/ch6_dynamic_slow.ini}"; first="${5:-1}"
scenario="${6:-$root/configs/sim/ch6_dynamic_slow.ini}"
# Object ids follow the section names' order: car 0, east 1, middle 2, new_left 3,
# new_right 4, west 5 (the moving ones are scored per object).
declare -A area=([object_0]=car [object_2]=removed_middle [object_3]=added_left [object_4]=added_right)
printf "seed precision recall static_fp"
for o in object_0 object_2 object_3 object_4; do printf " %s" "${area[$o]}"; done
echo " path_rmse"
for s in $(seq "$first" $((first + n - 1))); do
    d="$work/seed_$s"
    rm -rf "$d/sim"  # one scenario's rawlog per folder: WORK may hold another's
    "$build/bin/hymm-simul" -c "$scenario" -s "$s" -o "$d/sim" >/dev/null
    S="$(ls "$d"/sim/*.rawlog)"; S="${S%.rawlog}"
    "$build/bin/hymm-slam" -c "$slam" -r "$S.rawlog" --gt-path "${S}_gt_path.tum" \
        --gt-landmarks "${S}_gt_landmarks.csv" --gt-objects "${S}_gt_objects.txt" \
        -o "$d/out" --no-png >/dev/null
    python3 - "$d/out/metrics.json" "$s" <<'PY'
import json, sys
m = json.load(open(sys.argv[1]))
def get(k):
    cur = m
    for part in k.split('.'):
        if not isinstance(cur, dict) or part not in cur:
            return m.get(k)
        cur = cur[part]
    return cur
def val(k):
    v = get(k)
    if v is None: v = m.get(k)
    return v
row = [sys.argv[2]]
for k in ("dynamic.slow.precision", "dynamic.slow.recall", "dynamic.slow.static_fp_fraction"):
    v = val(k); row.append("nan" if v is None else "%.3f" % v)
for o in ("object_0", "object_2", "object_3", "object_4"):
    det = val("dynamic.slow.object.%s.detected" % o); rec = val("dynamic.slow.object.%s.recall" % o)
    # recall 1 with nothing detected: the area holds no covered cell (no region there)
    row.append("uncovered" if (not det and rec == 1) else "%s/%.3f" % ("yes" if det else "no", rec))
row.append("%.4f" % m["path"]["position_rmse_m"])
print(" ".join(row))
PY
done
