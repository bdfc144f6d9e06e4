#!/usr/bin/env bash
# Every dense layer of thesis chapter 4 (points, occupancy with per-region resolution,
# particles, sum of Gaussians, property) on the chapter-4 simulated loop, against the
# simulator's true outlines: after the first loop closure (the simulation cut at 110 s,
# as benchmarks/dense_accuracy/run.sh does: the same seed gives the same run, so the
# shorter run is an exact prefix of the whole one) and at the end of the 10 laps.
# Each hymm-slam run is repeated with coarsening off (configs/ch4_layers.ini with
# [OccupancyLayer] coarse_cell_size_m = 0, nothing else changed) to measure what
# coarsening saves (Sec. 4.1.3) and which regions it picks. A third run simulates the
# same scenario with a noise-free laser (the laser draws from its own random stream, so
# the odometry, the landmark detections and hence the feature map and path are the
# same; checked): what is left of the layers' error then comes from the feature map and
# the representations, the rest is laser noise. Needs python3 for the tables.
#   benchmarks/dense_layers/run.sh [OUT_DIR] [BUILD_DIR]
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
out="${1:-$root/out/dense_layers}"
bin="${2:-$root/build}/bin"
mkdir -p "$out"
out="$(cd "$out" && pwd)"

scen="$root/configs/sim/ch4_objects.ini"
slam_on="$root/configs/ch4_layers.ini"
slam_off="$out/ch4_layers_no_coarsening.ini"
sed 's/^coarse_cell_size_m = .*/coarse_cell_size_m = 0/' "$slam_on" > "$slam_off"
grep -q '^coarse_cell_size_m = 0$' "$slam_off"

simulate() {  # dir duration_s(0 = whole run) [exact] -> prints the rawlog base name
    local d="$1"
    mkdir -p "$d"
    if [ "$2" = 0 ]; then cp "$scen" "$d/scenario.ini"
    else sed "s/^\[Scenario\]/[Scenario]\nduration_s = $2/" "$scen" > "$d/scenario.ini"; fi
    if [ "${3:-}" = exact ]; then  # zero noise in [LaserSimulator] only
        awk '/^\[/ { laser = ($0 == "[LaserSimulator]") }
             laser && /^std_(range_m|bearing_deg) *=/ { sub(/=.*/, "= 0") } { print }' \
            "$d/scenario.ini" > "$d/scenario_exact.ini"
        [ "$(grep -c '= 0$' "$d/scenario_exact.ini")" -ge 2 ] || { echo "no laser noise keys" >&2; exit 1; }
        mv "$d/scenario_exact.ini" "$d/scenario.ini"
    fi
    "$bin/hymm-simul" -c "$d/scenario.ini" -o "$d" > /dev/null
    local base; base="$(ls "$d"/*.rawlog)"; echo "${base%.rawlog}"
}

slam() {  # base config out_dir [extra hymm-slam args]; wall time and peak memory in out_dir.time
    local base="$1" cfg="$2" d="$3"; shift 3
    local timer=()
    if [ -x /usr/bin/time ]; then timer=(/usr/bin/time -f "%e s wall, %M kB max RSS" -o "$d.time")
    else echo "n/a (no GNU time)" > "$d.time"; fi
    "${timer[@]}" "$bin/hymm-slam" -c "$cfg" -r "$base.rawlog" -o "$d" -q "$@" \
        --gt-path "${base}_gt_path.tum" --gt-landmarks "${base}_gt_landmarks.csv" \
        --gt-objects "${base}_gt_objects.txt"
}

# Lap time is ~85 s (254 m at 3 m/s): at 110 s the vehicle has re-observed the first
# landmarks (loop closed).
for run in after:110 end:0; do
    name="${run%%:*}"; dur="${run##*:}"
    base="$(simulate "$out/$name/sim" "$dur")"
    slam "$base" "$slam_on" "$out/$name/on"
    slam "$base" "$slam_off" "$out/$name/off" --no-png
    # Coarsening changes only the occupancy grids: the regions must be the same.
    cmp -s "$out/$name/on/regions.txt" "$out/$name/off/regions.txt" \
        || { echo "regions differ between coarsening on and off ($name)" >&2; exit 1; }
    base="$(simulate "$out/$name/sim_exact" "$dur" exact)"
    slam "$base" "$slam_on" "$out/$name/exact" --no-png
    cmp -s "$out/$name/on/landmarks.csv" "$out/$name/exact/landmarks.csv" \
        && cmp -s "$out/$name/on/path.tum" "$out/$name/exact/path.tum" \
        || { echo "the noise-free laser changed the feature map ($name)" >&2; exit 1; }
done

python3 - "$out" <<'PY'
import csv, json, os, sys
out = sys.argv[1]
runs = [("after", "after closure (110 s)"), ("end", "end (10 laps)")]
def metrics(name, mode): return json.load(open(os.path.join(out, name, mode, "metrics.json")))
def regions(name, mode):
    return {int(r["id"]): r for r in csv.DictReader(open(os.path.join(out, name, mode, "occupancy_regions.csv")))}
def kib(b): return "%.0f KiB" % (b / 1024.0)
def f3(x): return "n/a" if x is None else "%.3f m" % x
what = {"points": "returns", "occupancy": "cells P > 0.8", "particles": "particles w > 0.8",
        "sog": "Gaussian means", "property": "cells with a value", "classic_grid": "cells P > 0.8"}
rows = ["| run | landmark err (aligned) | layer | stored items | evaluated (%s) | mean | p95 | coverage | memory | mean < 0.3 m | aligned mean | aligned p95 |" % "what",
        "|---|---|---|---|---|---|---|---|---|---|---|---|"]
for name, label in runs:
    m = metrics(name, "on"); d = m["dense"]; first = True
    for layer in ["points", "occupancy", "particles", "sog", "property", "classic_grid"]:
        x = d.get(layer)
        if x is None: continue
        items = "%d" % x["items"] if "items" in x else ""
        mem = kib(x["memory_bytes"]) if "memory_bytes" in x else ""
        ok = "" if x.get("mean_distance_m") is None else ("yes" if x["mean_distance_m"] < 0.3 else "**no**")
        al = x.get("aligned", {})
        lm = "%.2f m (%.2f m)" % (m["landmarks"]["mean_error_m"],
                                  d.get("landmark_alignment", {}).get("landmark_mean_error_aligned_m", float("nan")))
        rows.append("| %s | %s | %s | %s | %d (%s) | %s | %s | %.1f%% | %s | %s | %s | %s |" % (
            label if first else "", lm if first else "",
            layer, items, x["points"], what[layer], f3(x.get("mean_distance_m")),
            f3(x.get("p95_distance_m")), 100 * x["coverage"], mem, ok,
            f3(al.get("mean_distance_m")), f3(al.get("p95_distance_m"))))
        first = False
rows += ["", "Same runs with a noise-free laser (identical feature map and path):", "",
         "| run | layer | mean, laser noise 0.1 m / 1 deg | mean, noise-free laser | p95, noisy | p95, noise-free |",
         "|---|---|---|---|---|---|"]
for name, label in runs:
    d, e = metrics(name, "on")["dense"], metrics(name, "exact")["dense"]; first = True
    for layer in ["points", "occupancy", "particles", "sog"]:
        rows.append("| %s | %s | %s | %s | %s | %s |" % (label if first else "", layer,
            f3(d[layer]["mean_distance_m"]), f3(e[layer]["mean_distance_m"]),
            f3(d[layer]["p95_distance_m"]), f3(e[layer]["p95_distance_m"])))
        first = False
rows += ["", "| run | particles | w > 0.8 | w < 0.5 | Gaussians | property cells | property note |",
         "|---|---|---|---|---|---|---|"]
for name, label in runs:
    d = metrics(name, "on")["dense"]; p = d["particles"]
    rows.append("| %s | %d | %.1f%% | %.1f%% | %d | %d | %s |" % (
        label, p["particles"], 100 * p["weight_fraction_above_0_8"], 100 * p["weight_fraction_below_0_5"],
        d["sog"]["gaussians"], d["property"]["cells"], d["property"].get("note", "")))
rows += ["", "| run | occupancy memory, coarsening off | on | saved | regions coarse / fine | "
         "occupied cells (P > 0.8), coarse-ending regions | fine regions | free cells (P < 0.2), coarse-ending | fine |",
         "|---|---|---|---|---|---|---|---|---|"]
for name, label in runs:
    on, off = metrics(name, "on")["dense"], metrics(name, "off")["dense"]
    ron, roff = regions(name, "on"), regions(name, "off")
    assert set(ron) == set(roff)
    coarse = [i for i in ron if ron[i]["coarse"] == "1"]
    fine = [i for i in ron if ron[i]["coarse"] == "0"]
    # Fractions from the fine grids of the run without coarsening (same regions, same scans).
    def frac(ids, key):
        cells = sum(int(roff[i]["cells"]) for i in ids)
        return "n/a" if cells == 0 else "%.2f%%" % (100.0 * sum(int(roff[i][key]) for i in ids) / cells)
    m_off, m_on = off["memory_bytes_by_kind"]["occupancy"], on["memory_bytes_by_kind"]["occupancy"]
    rows.append("| %s | %s | %s | %.1f%% | %d / %d | %s | %s | %s | %s |" % (
        label, kib(m_off), kib(m_on), 100.0 * (m_off - m_on) / m_off, len(coarse), len(fine),
        frac(coarse, "occupied"), frac(fine, "occupied"), frac(coarse, "free"), frac(fine, "free")))
rows.append("")
for name, label in runs:
    for mode, what in [("on", "coarsening on"), ("off", "coarsening off"), ("exact", "noise-free laser")]:
        rows.append("hymm-slam %s, %s: %s" % (label, what, open(os.path.join(out, name, mode + ".time")).read().strip()))
open(os.path.join(out, "summary.md"), "w").write("\n".join(rows) + "\n")
print("\n".join(rows))
PY

# Figures for docs/results.md from the end of the run (pure python: PNG crop of the SOG
# ellipses around the centre-top box, as Fig. 4.13 shows one object).
python3 - "$out" <<'PY'
import os, shutil, struct, sys, zlib
out = sys.argv[1]; src = os.path.join(out, "end", "on"); fig = os.path.join(out, "figures")
os.makedirs(fig, exist_ok=True)

def read_png(path, max_rows):
    # 8-bit RGB / grey, non-interlaced (what OpenCV writes); rows 0..max_rows-1 only.
    data = open(path, "rb").read(); pos = 8; idat = b""
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8]); body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR": w, h, depth, ctype, _, _, lace = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT": idat += body
        pos += 12 + n
    assert depth == 8 and ctype in (0, 2) and lace == 0, path
    bpp = 3 if ctype == 2 else 1; stride = w * bpp; raw = zlib.decompress(idat)
    rows, prev = [], bytearray(stride)
    for y in range(min(h, max_rows)):
        f = raw[y * (stride + 1)]; line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0; b = prev[i]; c = prev[i - bpp] if i >= bpp else 0
            if f == 1: line[i] = (line[i] + a) & 255
            elif f == 2: line[i] = (line[i] + b) & 255
            elif f == 3: line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c; pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line); prev = line
    return w, h, bpp, rows

def write_png(path, w, h, bpp, rows):
    chunk = lambda k, b: struct.pack(">I", len(b)) + k + b + struct.pack(">I", zlib.crc32(k + b) & 0xffffffff)
    raw = b"".join(b"\x00" + bytes(r) for r in rows)
    open(path, "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2 if bpp == 3 else 0, 0, 0, 0))
                           + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))

# Frame of sog_ellipses.png: savePolylinesPng covers the current triangles (last six
# numbers of each regions.txt line) and the ellipses plus 1 m at 0.05 m per pixel;
# ellipses reach past the triangles by centimetres, well inside the crop's margin.
xs, ys = [], []
for line in open(os.path.join(src, "regions.txt")).read().split("\n")[3:]:
    v = line.split()
    if len(v) < 6: continue
    cur = [float(t) for t in v[-6:]]; xs += cur[0::2]; ys += cur[1::2]
res, x_min, y_max = 0.05, min(xs) - 1.0, max(ys) + 1.0
box = (-22.0, 33.0, -10.0, 43.0)  # [m] around [Object_top_1] (8 x 5 m box at -16, 38)
c0, c1 = int((box[0] - x_min) / res), int((box[2] - x_min) / res)
r0, r1 = int((y_max - box[3]) / res), int((y_max - box[1]) / res)
w, h, bpp, rows = read_png(os.path.join(src, "sog_ellipses.png"), r1)
crop = [r[c0 * bpp:c1 * bpp] for r in rows[r0:r1]]
# The true outline of the object in green (simulator ground truth).
gt = os.path.join(out, "end", "sim", "ch4_objects_gt_objects.txt")
ids = [l.split()[2] for l in open(gt) if l.startswith("# object") and l.split()[3] == "top_1"]
rec = [l.split() for l in open(gt) if not l.startswith("#") and l.split() and l.split()[0] == ids[0]][0]
poly = list(zip([float(t) for t in rec[3::2]], [float(t) for t in rec[4::2]]))
def plot(x, y):
    c, r = int((x - x_min) / res) - c0, int((y_max - y) / res) - r0
    if 0 <= r < len(crop) and 0 <= c < c1 - c0: crop[r][3 * c:3 * c + 3] = bytes((0, 160, 0))
for (xa, ya), (xb, yb) in zip(poly, poly[1:] + poly[:1]):
    n = int(max(abs(xb - xa), abs(yb - ya)) / (res / 2)) + 1
    for k in range(n + 1): plot(xa + (xb - xa) * k / n, ya + (yb - ya) * k / n)
big = []  # 2x: one pixel is 2.5 cm
for r in crop:
    line = bytearray(b"".join(bytes(r[3 * c:3 * c + 3]) * 2 for c in range(c1 - c0)))
    big += [line, line]
write_png(os.path.join(fig, "ch4_layers_sog_ellipses.png"), 2 * (c1 - c0), 2 * (r1 - r0), bpp, big)
for f in ["particles", "sog_surface"]:
    shutil.copy(os.path.join(src, f + ".png"), os.path.join(fig, "ch4_layers_%s.png" % f))
for f in sorted(os.listdir(fig)):
    print("figure %s: %d kB" % (os.path.join(fig, f), os.path.getsize(os.path.join(fig, f)) // 1024))
PY
