#!/usr/bin/env bash
# Side-by-side accuracy and speed of MRPT's kf-slam (CRangeBearingKFSLAM2D) and
# hymm-slam on the same rawlogs from MRPT's simul-landmarks, measured in one run.
#
#   benchmarks/kfslam_compare/run.sh [WORK_DIR]
#
# Needs MRPT's apps: `scripts/setup --peers` installs them (mrpt-apps, mrpt-common).
# Accuracy over noise regimes and seeds: sweep.py (same directory).
# Cases: kf-slam_demo.rawlog (shipped with MRPT, 70 landmarks) and simul_large
# (~1000 landmarks mapped, ~120 observations per step, generated here).
# Both programs get known landmark IDs and the rawlog's own noise figures.
# Path error: kf-slam's path is read from its "Mean pose" log lines (1 mm / 0.01 deg
# printed resolution); landmark error for kf-slam is the figure kf-slam itself prints
# against the ground truth. Per-step time: median of the last 20 steps, from kf-slam's
# log timestamps and from hymm-slam's timing.csv.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
work="${1:-$root/build/kfslam_compare}"
bin="${HYMM_BIN:-$root/build/bin}"
for tool in kf-slam simul-landmarks; do
    command -v "$tool" >/dev/null || { echo "error: $tool not found; run scripts/setup --peers" >&2; exit 1; }
done
for tool in hymm-slam hymm-eval; do
    [[ -x "$bin/$tool" ]] || { echo "error: $bin/$tool not built; run scripts/build" >&2; exit 1; }
done
mkdir -p "$work"
share=/usr/share/mrpt
kf_ini_template="$share/config_files/kf-slam/EKF-SLAM_test_2d.ini"

median_last20() { tail -n 20 | sort -g | awk '{a[NR]=$1} END {print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}'; }

run_case() {
    local name="$1" rawlog="$2" gt_lm="$3" gt_path="$4"
    local d="$work/$name"
    rm -rf "$d" && mkdir -p "$d"
    # kf-slam: no GUI, no per-step map dumps (they would dominate its time).
    sed -e 's/^SHOW_3D_LIVE.*/SHOW_3D_LIVE=false/' \
        -e "s|^logOutput_dir.*|logOutput_dir=$d/kf_log|" \
        -e 's/^SAVE_LOG_FREQUENCY.*/SAVE_LOG_FREQUENCY=100000000/' \
        -e "s|^ground_truth_file=.*|ground_truth_file=$gt_lm|" \
        -e "s|^ground_truth_file_robot=.*|ground_truth_file_robot=|" \
        "$kf_ini_template" > "$d/kf-slam.ini"
    local t0=$(date +%s.%N)
    kf-slam "$d/kf-slam.ini" "$rawlog" > "$d/kf-slam.log" 2>&1
    local t1=$(date +%s.%N)
    # Path from the "Mean pose: (x,y,phi_deg)" lines, printed after each step; row 0 is
    # the start pose (the origin for both programs), as in the ground-truth file.
    awk -F'[(),]' 'BEGIN {print "0 0 0 0 0 0 0 1"} /Mean pose:/ {n++; printf "%d %s %s 0 0 0 %.12f %.12f\n", n, $2, $3, sin($4*3.14159265358979/360), cos($4*3.14159265358979/360)}' \
        "$d/kf-slam.log" > "$d/kf_path.tum"
    local kf_lm_err=$(awk '/Mean Error:/ {print $(NF-1)}' "$d/kf-slam.log" | tail -n 1)
    local kf_nlm=$(awk '/# of landmarks in the map:/ {v=$NF} END {print v}' "$d/kf-slam.log")
    local kf_step=$(awk '/ Step [0-9]+ - / {split($1,a,":"); t=a[2]*60+substr(a[3],1,7); if (p!="") print t-p; p=t}' \
        "$d/kf-slam.log" | median_last20)
    "$bin/hymm-eval" -p "$d/kf_path.tum" --gt-path "$gt_path" -o "$d/kf_metrics.json"

    cat > "$d/hymm.ini" <<INI
[DenseSlam]
landmark_source = bearing_range
use_landmark_ids = true
[EkfSlam]
[TreeExtractor]
INI
    local t2=$(date +%s.%N)
    "$bin/hymm-slam" -q -c "$d/hymm.ini" -r "$rawlog" -o "$d/hymm" --gt-path "$gt_path" --gt-landmarks "$gt_lm"
    local t3=$(date +%s.%N)
    local hy_step=$(awk -F, 'NR>1 {print $4}' "$d/hymm/timing.csv" | median_last20)
    local hy_nlm=$(awk -F, 'END {print $2}' "$d/hymm/timing.csv")
    local hy_obs=$(awk -F, 'NR>1 {print $3}' "$d/hymm/timing.csv" | median_last20)
    jget() { grep -o "\"$2\": [-0-9.e]*" "$1" | head -n 1 | awk '{print $2}'; }
    printf "| %s | %s | %s | %.4f | %.4f | %.4f | %.4f | %.1f | %.1f | %.2f | %.4f | %.1fx |\n" \
        "$name" "$kf_nlm" "$hy_nlm" \
        "$(jget "$d/kf_metrics.json" position_rmse_m)" "$(jget "$d/hymm/metrics.json" position_rmse_m)" \
        "$kf_lm_err" "$(jget "$d/hymm/metrics.json" mean_error_m)" \
        "$(awk -v a="$t0" -v b="$t1" 'BEGIN {print b - a}')" "$(awk -v a="$t2" -v b="$t3" 'BEGIN {print b - a}')" "$hy_obs" \
        "$kf_step" "$(awk -v a="$kf_step" -v b="$hy_step" 'BEGIN {print a / b}')" | tee -a "$work/results.md"
    echo "    hymm-slam per-step median (last 20): $hy_step s" | tee -a "$work/results.md"
}

{
    echo "kf-slam vs hymm-slam ($(date -u +%Y-%m-%d), $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2))"
    echo
    echo "| case | kf-slam landmarks | hymm landmarks | kf-slam path RMSE [m] | hymm path RMSE [m] | kf-slam landmark mean err [m] | hymm landmark mean err [m] | kf-slam run [s] | hymm run [s] | obs/step | kf-slam step [s] | speed-up per step |"
    echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
} > "$work/results.md"
cat "$work/results.md"

run_case demo "$share/datasets/kf-slam_demo.rawlog" \
    "$share/datasets/kf-slam_demo_ground_truth.txt" "$share/datasets/kf-slam_demo_ground_truth_robot_path.txt"

( cd "$work" && cp "$root/benchmarks/kfslam_compare/simul_large.ini" . && simul-landmarks simul_large.ini > simul_large.log 2>&1 )
run_case simul_large "$work/simul_large.rawlog" \
    "$work/simul_large.rawlog_ground_truth.txt" "$work/simul_large.rawlog_ground_truth_robot_path.txt"
echo "results: $work/results.md"
