#!/usr/bin/env bash
# hymm-soak over N noise seeds, one line per seed: at two laps (default 10 and the last)
# the RSS, the CPU per step (median), the landmarks, the scan templates and the points
# stored, and the growth per lap between them; then the median and range of each growth.
# Extra arguments go to hymm-soak (a config, --set, --layers, ...).
#   benchmarks/soak/soak_seeds.sh BUILD_DIR WORK_DIR N LAPS [MID_LAP=LAPS/2] -- [hymm-soak args]
set -euo pipefail
build="$1"; work="$2"; n="$3"; laps="$4"; shift 4
mid=$((laps / 2))
if [ $# -gt 0 ] && [ "$1" != "--" ]; then mid="$1"; shift; fi
if [ $# -gt 0 ] && [ "$1" = "--" ]; then shift; fi
mkdir -p "$work"
for s in $(seq 1 "$n"); do
    "$build/bin/hymm-soak" --laps "$laps" --seed "$s" --csv "$work/seed_$s.csv" "$@" \
        >"$work/seed_$s.txt" 2>&1 || { echo "seed $s: hymm-soak failed (see $work/seed_$s.txt)" >&2; exit 1; }
done
python3 - "$work" "$n" "$mid" "$laps" <<'PY'
import csv, statistics, sys
work, n, mid, last = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
keys = [("rss_mb", "RSS [MB]"), ("cpu_median_ms", "CPU/step [ms]"), ("landmarks", "landmarks"),
        ("scan_templates", "templates"), ("points", "points")]
print("| seed | " + " | ".join(f"{h} lap {mid} -> {last} (per lap)" for _, h in keys) + " |")
print("|---" * (len(keys) + 1) + "|")
growth = {k: [] for k, _ in keys}
for s in range(1, n + 1):
    rows = {int(r["lap"]): r for r in csv.DictReader(open(f"{work}/seed_{s}.csv"))}
    if mid not in rows or last not in rows:
        sys.exit(f"seed {s}: the CSV has no lap {mid} or {last}")
    cells = []
    for k, _ in keys:
        a, b = float(rows[mid][k]), float(rows[last][k])
        g = (b - a) / (last - mid)
        growth[k].append(g)
        cells.append(f"{a:.4g} -> {b:.4g} ({g:+.3g})")
    print(f"| {s} | " + " | ".join(cells) + " |")
print("| median [min, max] per lap | " + " | ".join(
    f"{statistics.median(growth[k]):+.3g} [{min(growth[k]):+.3g}, {max(growth[k]):+.3g}]" for k, _ in keys) + " |")
PY
