#!/usr/bin/env python3
"""hymm-slam against MRPT's kf-slam filter over simul-landmarks noise regimes.

    nice -n 10 benchmarks/kfslam_compare/sweep.py [--work DIR] [--jobs 2] [--seeds 3] [--no-ff]
                                                   [--kinds KIND,KIND] [--steps 126]
                                                   [--only NAME,NAME] [--table-only]

For every regime and seed: simul-landmarks writes the rawlog (known landmark IDs), then
three runs on it:
  kf-sample  MRPT's CRangeBearingKFSLAM2D with kf-slam's shipped EKF-SLAM_test_2d.ini
             (odometry used, sensor model 0.03 m / 0.1 deg whatever the truth is);
  kf-true    the same with the true sensor noise of the regime (odometry used, with the
             covariance the rawlog carries, which simul-landmarks sets to the true noise);
  kf-true-ff kf-true that also processes the rawlog's first frame (taken at the start
             pose), which kf-slam's reader skips and hymm-slam uses: the same data for both;
  hymm       hymm-slam with configs/simul_landmarks.ini (noise figures from the rawlog).
Both filters are scored by hymm-eval (path RMSE over every step, landmark mean error by
ID, landmark NEES with the marginal covariances; no alignment) and hymm-slam's vehicle
NEES comes from its own metrics. kf-slam's filter runs through hymm-kfslam-run (same
class, same ini, same action/observation pairs as the kf-slam app; it writes the path,
map and per-call times kf-slam only prints). Per-step time: median of the last 10 steps,
i.e. at the final map size. Stdlib only.
"""
import argparse
import concurrent.futures as cf
import json
import math
import os
import shutil
import statistics
import subprocess
import sys
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
KF_SAMPLE = "/usr/share/mrpt/config_files/kf-slam/EKF-SLAM_test_2d.ini"
PATH_SIDE = 5.0  # square path of simul-landmarks with squarePathLength=30: 25 steps of 0.2 m

# Base regime; every other regime changes one factor (odometry noise, heading noise,
# sensor range, range noise, bearing noise, number of landmarks).
BASE = dict(odo=0.02, odo_phi_deg=0.01, range=5.0, std_range=0.03, std_yaw_deg=0.3, lms=300)
REGIMES = [
    ("base", {}),
    ("odo 0.005", dict(odo=0.005)),
    ("odo 0.05", dict(odo=0.05)),
    ("odo 0.05 + heading 1 deg", dict(odo=0.05, odo_phi_deg=1.0)),
    ("range 3 m", dict(range=3.0)),
    ("range 10 m", dict(range=10.0)),
    ("range noise 0.01", dict(std_range=0.01)),
    ("range noise 0.1", dict(std_range=0.1)),
    ("bearing 0.1 deg", dict(std_yaw_deg=0.1)),
    ("bearing 1 deg", dict(std_yaw_deg=1.0)),
    ("100 landmarks", dict(lms=100)),
    ("1000 landmarks at 3 m", dict(lms=1000, range=3.0)),
]


def regime_params(over):
    p = dict(BASE)
    p.update(over)
    return p


def simul_ini(p, seed, steps):
    # Field: the path's square grown by the sensor range, so every landmark can be seen.
    lo, hi = -p["range"], PATH_SIDE + p["range"]
    return f"""[Params]
random_seed={seed}
nSteps={steps}
circularPath=0
squarePathLength=30
loadLandmarksFromFile=
odometryNoiseXY_std={p['odo']}
odometryNoisePhi_std_deg={p['odo_phi_deg']}
minSensorDistance=0
maxSensorDistance={p['range']}
fieldOfView_deg=180
stdRange={p['std_range']}
stdYaw_deg={p['std_yaw_deg']}
stdPitch_deg=0.0
outFile=run.rawlog
outDir=.
show_in_3d=false

[RANDOMSET_1]
nLandmarks={p['lms']}
min_x={lo}
max_x={hi}
min_y={lo}
max_y={hi}
min_z=0
max_z=0
"""


def kf_ini(out_dir, std_range=None, std_yaw_deg=None):
    lines = []
    for line in open(KF_SAMPLE):
        key = line.split("=")[0].strip()
        if key == "SHOW_3D_LIVE":
            line = "SHOW_3D_LIVE=false\n"
        elif key == "logOutput_dir":
            line = f"logOutput_dir={out_dir}\n"
        elif key == "std_sensor_range" and std_range is not None:
            line = f"std_sensor_range={std_range}\n"
        elif key == "std_sensor_yaw_deg" and std_yaw_deg is not None:
            line = f"std_sensor_yaw_deg={std_yaw_deg}\n"
        lines.append(line)
    return "".join(lines)


def run(cmd, cwd, log):
    """Runs cmd; returns its CPU time (user + system) in seconds, which, unlike wall time,
    does not depend on what else the shared machine is running."""
    with open(log, "w") as f:
        proc = subprocess.Popen(cmd, cwd=cwd, stdout=f, stderr=subprocess.STDOUT)
        _, status, ru = os.wait4(proc.pid, 0)
        proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed (exit {proc.returncode}), see {log}")
    return ru.ru_utime + ru.ru_stime


def median_last(values, k=10):
    return statistics.median(values[-k:]) if values else float("nan")


def read_timing(path, col):
    with open(path) as f:
        rows = [l.strip().split(",") for l in f.readlines()[1:] if l.strip()]
    return [float(r[col]) for r in rows], (int(rows[-1][1]) if rows else 0)


def evaluate(bin_dir, d, path, lms):
    out = os.path.join(d, "eval.json")
    run([os.path.join(bin_dir, "hymm-eval"), "-p", path, "-l", lms, "--gt-path",
         os.path.join(d, "..", "run.rawlog_ground_truth_robot_path.txt"), "--gt-landmarks",
         os.path.join(d, "..", "run.rawlog_ground_truth.txt"), "-o", out], d, os.path.join(d, "eval.log"))
    with open(out) as f:
        j = json.load(f)
    return dict(path_rmse=j["path"]["position_rmse_m"], lm_err=j["landmarks"]["mean_error_m"],
                lm_nees=j["landmarks"].get("mean_nees", float("nan")), lm_n=j["landmarks"]["matched"])


def job(kind, case_dir, bin_dir, p, hymm_ini):
    d = os.path.join(case_dir, kind)
    os.makedirs(d, exist_ok=True)
    rawlog = os.path.join(case_dir, "run.rawlog")
    if kind.startswith("kf-"):
        ini = os.path.join(d, "kf.ini")
        with open(ini, "w") as f:
            if kind in ("kf-true", "kf-true-ff"):
                f.write(kf_ini(d, p["std_range"], p["std_yaw_deg"]))
            else:
                f.write(kf_ini(d))
        first = ["--first-frame"] if kind == "kf-true-ff" else []
        cpu = run([os.path.join(bin_dir, "hymm-kfslam-run")] + first + ["-c", ini, "-r", rawlog, "-o", d], d,
                   os.path.join(d, "run.log"))
        times, nlm = read_timing(os.path.join(d, "timing.csv"), 3)
        r = evaluate(bin_dir, d, os.path.join(d, "path.tum"), os.path.join(d, "landmarks.csv"))
    else:
        cpu = run([os.path.join(bin_dir, "hymm-slam"), "-q", "-c", hymm_ini, "-r", rawlog, "-o", d,
                    "--gt-path", os.path.join(case_dir, "run.rawlog_ground_truth_robot_path.txt"),
                    "--gt-landmarks", os.path.join(case_dir, "run.rawlog_ground_truth.txt")], d,
                   os.path.join(d, "run.log"))
        times, nlm = read_timing(os.path.join(d, "timing.csv"), 3)
        r = evaluate(bin_dir, d, os.path.join(d, "path.tum"), os.path.join(d, "landmarks.csv"))
        with open(os.path.join(d, "metrics.json")) as f:
            r["veh_nees"] = json.load(f)["vehicle_nees"]["mean"]
    r.update(step=median_last(times), total=sum(times), cpu=cpu, nlm=nlm)
    return kind, r


def aligned_landmark_error(lm_csv, gt_txt):
    """Mean landmark error after the least-squares SE(2) fit of the map onto the truth
    (matched by ID). It removes the common offset of the whole map, which is set by the
    noise of the first frame(s) that anchor it and dominates the unaligned error."""
    gt = {}
    for line in open(gt_txt):
        v = line.split()
        if len(v) >= 7 and not line.startswith("%"):
            gt[int(float(v[6]))] = (float(v[0]), float(v[1]))
    est, tru = [], []
    for line in open(lm_csv):
        v = line.strip().split(",")
        if len(v) < 3 or line.startswith("#") or not v[0].lstrip("-").isdigit():
            continue
        if int(v[0]) in gt:
            est.append((float(v[1]), float(v[2])))
            tru.append(gt[int(v[0])])
    n = len(est)
    if n < 2:
        return float("nan")
    me = [sum(p[k] for p in est) / n for k in (0, 1)]
    mt = [sum(p[k] for p in tru) / n for k in (0, 1)]
    sxx = sum((e[0] - me[0]) * (t[0] - mt[0]) + (e[1] - me[1]) * (t[1] - mt[1]) for e, t in zip(est, tru))
    sxy = sum((e[0] - me[0]) * (t[1] - mt[1]) - (e[1] - me[1]) * (t[0] - mt[0]) for e, t in zip(est, tru))
    th = math.atan2(sxy, sxx)
    c, si = math.cos(th), math.sin(th)
    err = 0.0
    for e, t in zip(est, tru):
        dx, dy = e[0] - me[0], e[1] - me[1]
        err += math.hypot(c * dx - si * dy + mt[0] - t[0], si * dx + c * dy + mt[1] - t[1])
    return err / n


def fmt_mm(vals):
    if not vals:
        return "-"
    m = statistics.mean(vals)
    return f"{1000 * m:.1f} ({1000 * min(vals):.1f}-{1000 * max(vals):.1f})"


def fmt_ms(vals):
    return f"{1000 * statistics.median(vals):.2f}"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--work", default=os.path.join(ROOT, "build", "kfslam_sweep"))
    ap.add_argument("--bin", default=os.environ.get("HYMM_BIN", os.path.join(ROOT, "build", "bin")))
    ap.add_argument("--config", default=os.path.join(ROOT, "configs", "simul_landmarks.ini"))
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--steps", type=int, default=126)
    ap.add_argument("--only", default="", help="comma-separated regime names (default: all)")
    ap.add_argument("--no-ff", action="store_true", help="skip the kf-true-ff runs")
    ap.add_argument("--kinds", default="",
                    help="comma-separated runs to make (default: all; kf-true and hymm are required)")
    ap.add_argument("--table-only", action="store_true",
                    help="rewrite the table from the results of an earlier sweep in --work")
    a = ap.parse_args()
    if a.table_only:
        with open(os.path.join(a.work, "results.json")) as f:
            raw = json.load(f)
        results = {(k.split("|")[0], int(k.split("|")[1])): v for k, v in raw.items()}
        names = {k[0] for k in results}
        done = [r for r in REGIMES if r[0] in names]
        a.seeds = 1 + max(k[1] for k in results)
        with open(os.path.join(a.work, "wall_s")) as f:
            wall = float(f.read())
        write_table(a, done, results, wall)
        return
    for tool in ("simul-landmarks",):
        if shutil.which(tool) is None:
            sys.exit(f"error: {tool} not found; run scripts/setup --peers")
    for tool in ("hymm-slam", "hymm-eval", "hymm-kfslam-run"):
        if not os.access(os.path.join(a.bin, tool), os.X_OK):
            sys.exit(f"error: {a.bin}/{tool} not built; run scripts/build")
    if not os.path.exists(KF_SAMPLE):
        sys.exit(f"error: {KF_SAMPLE} missing; run scripts/setup --peers")
    only = [s.strip() for s in a.only.split(",") if s.strip()]
    # In the order given by --only (the costly ones can go first).
    regimes = [next(r for r in REGIMES if r[0] == n) for n in only] if only else list(REGIMES)
    os.makedirs(a.work, exist_ok=True)
    t_start = time.monotonic()

    results = {}  # (regime, seed) -> {kind: metrics}; earlier regimes of this --work are kept
    done = []
    if only and os.path.exists(os.path.join(a.work, "results.json")):
        with open(os.path.join(a.work, "results.json")) as f:
            for k, v in json.load(f).items():
                name, s = k.split("|")
                if name not in only:
                    results[(name, int(s))] = v
        done = [r for r in REGIMES if r[0] in {k[0] for k in results}]
        t_start -= float(open(os.path.join(a.work, "wall_s")).read()) if os.path.exists(
            os.path.join(a.work, "wall_s")) else 0.0
    kinds = ("kf-sample", "kf-true", "hymm") if a.no_ff else ("kf-sample", "kf-true", "kf-true-ff", "hymm")
    if a.kinds:
        kinds = tuple(k.strip() for k in a.kinds.split(",") if k.strip())
        unknown = set(kinds) - {"kf-sample", "kf-true", "kf-true-ff", "hymm"}
        if unknown or not {"kf-true", "hymm"} <= set(kinds):
            sys.exit(f"error: --kinds {a.kinds}: runs are kf-sample, kf-true, kf-true-ff, hymm; "
                     "kf-true and hymm are required")
    with cf.ThreadPoolExecutor(max_workers=a.jobs) as pool:
        for name, over in regimes:
            ri = [r[0] for r in REGIMES].index(name)  # directory names follow REGIMES
            p = regime_params(over)
            futures = {}
            for s in range(a.seeds):
                seed = 1000 + 17 * s
                case = os.path.join(a.work, f"r{ri:02d}_s{s}")
                shutil.rmtree(case, ignore_errors=True)
                os.makedirs(case)
                with open(os.path.join(case, "simul.ini"), "w") as f:
                    f.write(simul_ini(p, seed, a.steps))
                run(["simul-landmarks", "simul.ini"], case, os.path.join(case, "simul.log"))
                for kind in kinds:
                    futures[pool.submit(job, kind, case, a.bin, p, a.config)] = s
            for fut in cf.as_completed(futures):
                s = futures[fut]
                kind, r = fut.result()
                results.setdefault((name, s), {})[kind] = r
                print(f"{name} seed {s} {kind}: {r}", flush=True)
            done.append((name, over))
            write_table(a, done, results, time.monotonic() - t_start)
            with open(os.path.join(a.work, "wall_s"), "w") as f:
                f.write(f"{time.monotonic() - t_start:.1f}\n")


def write_table(a, regimes, results, wall):
    lines = [
        f"kf-slam filter (MRPT CRangeBearingKFSLAM2D) vs hymm-slam, {a.seeds} seeds, {a.steps} steps, "
        f"{time.strftime('%Y-%m-%d')}, sweep wall time {wall / 60:.1f} min on {os.cpu_count()} cores "
        f"({a.jobs} jobs)",
        "",
        "Errors in mm: mean over seeds (min-max). NEES: mean over seeds (vehicle: 3 DOF, expected 3; "
        "landmarks: 2 DOF, expected 2). Step: median over seeds of the median of the last 10 steps; "
        "whole run: median over seeds of the ratio of the programs' CPU times (user + system, whole "
        "process: rawlog reading, filter, outputs), or of summed step times where marked *. Step "
        "times are wall clock and inflated by other load on the machine.",
        "",
        "| regime | landmarks kf / hymm | path RMSE kf-sample | path RMSE kf-true | path RMSE kf-true-ff | path RMSE hymm | "
        "lm err kf-sample | lm err kf-true | lm err kf-true-ff | lm err hymm | lm NEES kf-true | "
        "vehicle NEES hymm | lm NEES hymm | aligned lm err kf-sample | aligned lm err kf-true | "
        "aligned lm err hymm | step kf-true [ms] | step hymm [ms] | whole run kf-true / hymm |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for ri, (name, over) in enumerate(regimes):
        p = regime_params(over)
        rs = [results[(name, s)] for s in range(a.seeds)]
        # Whole-run CPU time of each process where measured (wall-clock step sums otherwise).
        ck = "cpu" if all("cpu" in r["hymm"] for r in rs) else "total"
        ri_all = [r[0] for r in REGIMES].index(name)
        for s, r in enumerate(rs):
            case = os.path.join(a.work, f"r{ri_all:02d}_s{s}")
            for kind in r:
                r[kind]["lm_err_al"] = aligned_landmark_error(
                    os.path.join(case, kind, "landmarks.csv"), os.path.join(case, "run.rawlog_ground_truth.txt"))
        col = lambda k, m: [r[k][m] for r in rs if k in r]
        desc = (f"{name} (odo {p['odo']} m, {p['odo_phi_deg']} deg; range {p['range']} m; "
                f"{p['std_range']} m / {p['std_yaw_deg']} deg)")
        ratio = statistics.median([r["kf-true"][ck] / r["hymm"][ck] for r in rs])
        lines.append(
            f"| {desc} | {statistics.median(col('kf-true', 'nlm')):.0f} / {statistics.median(col('hymm', 'nlm')):.0f} | {fmt_mm(col('kf-sample', 'path_rmse'))} | "
            f"{fmt_mm(col('kf-true', 'path_rmse'))} | {fmt_mm(col('kf-true-ff', 'path_rmse'))} | "
            f"{fmt_mm(col('hymm', 'path_rmse'))} | "
            f"{fmt_mm(col('kf-sample', 'lm_err'))} | {fmt_mm(col('kf-true', 'lm_err'))} | "
            f"{fmt_mm(col('kf-true-ff', 'lm_err'))} | "
            f"{fmt_mm(col('hymm', 'lm_err'))} | {statistics.mean(col('kf-true', 'lm_nees')):.2f} | "
            f"{statistics.mean(col('hymm', 'veh_nees')):.2f} | {statistics.mean(col('hymm', 'lm_nees')):.2f} | "
            f"{fmt_mm(col('kf-sample', 'lm_err_al'))} | {fmt_mm(col('kf-true', 'lm_err_al'))} | "
            f"{fmt_mm(col('hymm', 'lm_err_al'))} | "
            f"{fmt_ms(col('kf-true', 'step'))} | {fmt_ms(col('hymm', 'step'))} | {ratio:.0f}x{'' if ck == 'cpu' else '*'} |")
    text = "\n".join(lines) + "\n"
    with open(os.path.join(a.work, "results.md"), "w") as f:
        f.write(text)
    with open(os.path.join(a.work, "results.json"), "w") as f:
        json.dump({f"{k[0]}|{k[1]}": v for k, v in results.items()}, f, indent=1)
    print(text)


if __name__ == "__main__":
    main()
