/**
 * @file scan_matcher_eval.cpp
 * @brief Matcher comparison (evaluation run, not a timing benchmark): convergence rate
 *        versus initial error, accuracy and covariance consistency (NEES) over many
 *        simulated template/scan pairs with known truth; convergence basin, agreement
 *        and time on consecutive real scans (Intel, Malaga rawlogs under HYMM_DATASETS).
 *
 *   hymm-scan-matcher-eval [--trials N] [--seed S] [--real-pairs M] [--raw-cov]
 *                          [--std-range M] [--std-bearing-deg D]   (laser; default Table 5.1)
 *
 * Every matcher runs with its default options (including its measured cov_inflation);
 * --raw-cov reports the matchers' own covariances (cov_inflation = 1) instead.
 */
#include <hymm/scanslam/CorrelativeMatcher.h>
#include <hymm/scanslam/IcpMatcher.h>
#include <hymm/scanslam/SogMatcher.h>
#include <mrpt/math/distributions.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose2D.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "scan_pairs.h"

using namespace hymm::scanslam;
using hymm::bench::ScanPair;

namespace
{
std::vector<std::unique_ptr<ScanMatcher>> matchers(bool raw_cov)
{
    std::vector<std::unique_ptr<ScanMatcher>> out;
    SogMatcher::Options so;
    IcpMatcher::Options io;
    CorrelativeMatcher::Options co;
    if (raw_cov) so.cov_inflation = io.cov_inflation = co.cov_inflation = 1.0;
    out.push_back(std::make_unique<SogMatcher>(so));
    out.push_back(std::make_unique<IcpMatcher>(io));
    out.push_back(std::make_unique<CorrelativeMatcher>(co));
    SogMatcher::Options sum = so;
    sum.objective = SogMatcher::Objective::sum;
    if (!raw_cov) sum.cov_inflation = 1.0;
    out.push_back(std::make_unique<SogMatcher>(sum));  // the thesis' literal Eq. 5.13
    return out;
}

double median(std::vector<double> v)
{
    if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
    std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
    return v[v.size() / 2];
}

struct Level
{
    double xy_m;
    double phi_rad;
};

void simulated(int trials, uint32_t seed, bool raw_cov, double std_range, double std_bearing)
{
    const auto ms = matchers(raw_cov);
    const std::vector<Level> levels{{0.05, 0.5 * M_PI / 180}, {0.1, 1 * M_PI / 180},
                                    {0.2, 2 * M_PI / 180},  {0.4, 4 * M_PI / 180},
                                    {0.8, 8 * M_PI / 180}};
    mrpt::random::CRandomGenerator rng(seed);
    std::vector<ScanPair> pairs;
    while (static_cast<int>(pairs.size()) < trials)
    {
        auto p = hymm::bench::randomPair(rng, seed + 17 * static_cast<uint32_t>(pairs.size()), 30,
                                          std_range, std_bearing);
        if (p) pairs.push_back(*p);
    }
    size_t npts = 0, nscan = 0;
    for (const auto& p : pairs) npts += p.tpl.sog.size(), nscan += p.scan.size();
    std::printf("laser noise %.3f m, %.2f deg; simulated pairs: %d (template points mean %.0f, scan points mean %.0f)\n",
                std_range, std_bearing * 180 / M_PI, trials, double(npts) / trials, double(nscan) / trials);
    std::printf("initial error: |dxy| and |dphi| fixed, random directions; converged: "
                "|e_xy| < 0.3 m and |e_phi| < 3 deg\n\n");
    std::printf("%-14s", "matcher");
    for (const auto& l : levels) std::printf(" conv@%.2fm/%.1fdeg", l.xy_m, l.phi_rad * 180 / M_PI);
    std::printf("\n");
    const double lo95 = mrpt::math::chi2inv(0.025, 3), hi95 = mrpt::math::chi2inv(0.975, 3);
    for (const auto& m : ms)
    {
        const std::string name = m->name() + ((m.get() == ms.back().get()) ? "-sum" : "");
        std::printf("%-14s", name.c_str());
        std::vector<double> nees, exy, ephi, times;
        for (size_t li = 0; li < levels.size(); ++li)
        {
            mrpt::random::CRandomGenerator r2(seed + 1000 + static_cast<uint32_t>(li));
            int conv = 0;
            for (const auto& p : pairs)
            {
                const double a = r2.drawUniform(-M_PI, M_PI);
                const double sg = r2.drawUniform(0, 1) < 0.5 ? -1 : 1;
                const Vec3 z0 = p.truth + Vec3(levels[li].xy_m * std::cos(a),
                                               levels[li].xy_m * std::sin(a), sg * levels[li].phi_rad);
                const auto t0 = std::chrono::steady_clock::now();
                const AlignResult res = m->align(p.tpl.sog, p.scan, z0);
                const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                if (!res.ok) continue;
                const Vec3 e = poseDifference(res.z, p.truth);
                const bool ok = e.head<2>().norm() < 0.3 && std::abs(e.z()) < 3 * M_PI / 180;
                conv += ok;
                if (li == 1 && ok)
                {
                    nees.push_back(e.dot(res.R.ldlt().solve(e)));
                    exy.push_back(e.head<2>().norm());
                    ephi.push_back(std::abs(e.z()));
                    times.push_back(dt);
                }
            }
            std::printf(" %17.1f%%", 100.0 * conv / trials);
        }
        double mean = 0;
        int inside = 0;
        for (double v : nees) mean += v, inside += (v > lo95 && v < hi95);
        mean /= std::max<size_t>(1, nees.size());
        const double n = static_cast<double>(nees.size());
        std::printf("\n%-14s  at 0.1 m/1 deg: median |e_xy| %.4f m, median |e_phi| %.3f deg, "
                    "mean NEES %.2f (99%% band of the mean [%.2f, %.2f], n=%zu), "
                    "inside 95%% chi2(3) %.1f%%, median time %.2f ms\n",
                    "", median(exy), median(ephi) * 180 / M_PI, mean,
                    mrpt::math::chi2inv(0.005, 3 * static_cast<unsigned>(n)) / n,
                    mrpt::math::chi2inv(0.995, 3 * static_cast<unsigned>(n)) / n, nees.size(),
                    100.0 * inside / std::max(1.0, n), 1e3 * median(times));
    }
}

/** Consecutive scans of a rawlog with the odometry increment between them. */
struct RealPair
{
    PointSet a, b;
    Vec3 odo;  //!< pose of sensor b in sensor a's frame, from odometry
};

std::vector<RealPair> readRealPairs(const std::string& path, size_t max_pairs, double std_range,
                                    double std_bearing)
{
    std::vector<RealPair> out;
    mrpt::obs::CRawlog log;
    if (!log.loadFromRawLogFile(path)) return out;
    mrpt::poses::CPose2D odo_acc;  // odometry since the previous scan
    std::optional<std::pair<PointSet, mrpt::poses::CPose2D>> prev;  // points, sensor mount
    size_t stride = 0;
    for (size_t i = 0; i < log.size() && out.size() < max_pairs; ++i)
    {
        if (log.getType(i) == mrpt::obs::CRawlog::etActionCollection)
        {
            const auto acts = log.getAsAction(i);
            if (auto odo = acts->getBestMovementEstimation())
                odo_acc = odo_acc + odo->poseChange->getMeanVal();
        }
        else if (log.getType(i) == mrpt::obs::CRawlog::etSensoryFrame)
        {
            const auto sf = log.getAsObservations(i);
            const auto scan = sf->getObservationByClass<mrpt::obs::CObservation2DRangeScan>();
            if (!scan) continue;
            PointSet pts = fromScan(*scan, {std_range, std_bearing});
            const mrpt::poses::CPose2D mount(scan->sensorPose);
            // Every other scan: motions large enough to matter.
            if (prev && (++stride % 2 == 0))
            {
                // a - b is b^-1 (+) a: the inverse of the first scan's mounting.
                const mrpt::poses::CPose2D sb = (mrpt::poses::CPose2D() - prev->second) + odo_acc + mount;
                RealPair p;
                p.a = prev->first;
                p.b = pts;
                p.odo = Vec3(sb.x(), sb.y(), sb.phi());
                out.push_back(std::move(p));
                prev.reset();
            }
            if (!prev)
            {
                prev = std::make_pair(pts, mount);
                odo_acc = mrpt::poses::CPose2D();
            }
        }
    }
    return out;
}

void real(const std::string& label, const std::string& path, size_t max_pairs, double sr,
          double sb, size_t min_points)
{
    const auto pairs = readRealPairs(path, max_pairs, sr, sb);
    if (pairs.empty())
    {
        std::printf("%s: no pairs read from %s\n", label.c_str(), path.c_str());
        return;
    }
    const auto ms = matchers(false);
    mrpt::random::CRandomGenerator rng(5);
    std::printf("\n%s (%zu consecutive-scan pairs; template: largest segment of the first "
                "scan, >= %zu points; initial guess: odometry)\n",
                label.c_str(), pairs.size(), min_points);
    std::printf("%-14s %8s %10s %12s %12s %12s %12s\n", "matcher", "ok", "basin0.3m",
                "|d| to sog", "from odo", "med sd_xy", "time ms");
    std::vector<std::vector<std::optional<Vec3>>> results(ms.size());
    for (size_t mi = 0; mi + 1 < ms.size(); ++mi)
    {
        int ok = 0, tried = 0, back = 0, basin_tried = 0;
        std::vector<double> times, sds, dsog, moved;
        for (const auto& p : pairs)
        {
            Segmenter::Options so;
            so.min_points = min_points;
            so.max_range_gap_m = 0.3;
            const auto segs = Segmenter(so).segment(p.a);
            if (segs.empty())
            {
                results[mi].push_back(std::nullopt);
                continue;
            }
            size_t best = 0;
            for (size_t k = 1; k < segs.size(); ++k)
                if (segs[k].size() > segs[best].size()) best = k;
            const ScanTemplate tpl = ScanTemplate::fromSegment(p.a, segs[best]);
            const Vec3 z0 = compose(inverse(p.odo), tpl.frame_in_sensor);
            ++tried;
            const auto t0 = std::chrono::steady_clock::now();
            const AlignResult r = ms[mi]->align(tpl.sog, p.b, z0);
            times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
            results[mi].push_back(r.ok ? std::optional<Vec3>(r.z) : std::nullopt);
            if (!r.ok) continue;
            ++ok;
            sds.push_back(std::sqrt(r.R(0, 0) + r.R(1, 1)));
            moved.push_back(poseDifference(r.z, z0).head<2>().norm());
            const size_t pi = results[mi].size() - 1;  // this pair's index
            if (mi > 0 && results[0][pi])
                dsog.push_back(poseDifference(r.z, *results[0][pi]).head<2>().norm());
            // Basin: from the matcher's own solution displaced by 0.3 m / 3 deg, back
            // within 2 cm / 0.2 deg.
            const double a = rng.drawUniform(-M_PI, M_PI);
            const Vec3 z1 = r.z + Vec3(0.3 * std::cos(a), 0.3 * std::sin(a), 3 * M_PI / 180);
            const AlignResult r1 = ms[mi]->align(tpl.sog, p.b, z1);
            ++basin_tried;
            if (r1.ok)
            {
                const Vec3 e = poseDifference(r1.z, r.z);
                back += e.head<2>().norm() < 0.02 && std::abs(e.z()) < 0.2 * M_PI / 180;
            }
        }
        std::printf("%-14s %7.1f%% %9.1f%% %10.3f m %10.3f m %10.3f m %12.2f\n",
                    ms[mi]->name().c_str(), 100.0 * ok / std::max(1, tried),
                    100.0 * back / std::max(1, basin_tried), mi == 0 ? 0.0 : median(dsog),
                    median(moved), median(sds), 1e3 * median(times));
    }
}
}  // namespace

int main(int argc, char** argv)
{
    int trials = 200;
    uint32_t seed = 1;
    size_t real_pairs = 200;
    bool raw_cov = false;
    double std_range = 0.1, std_bearing_deg = 1.0;  // thesis Table 5.1
    for (int i = 1; i < argc; ++i)
    {
        const std::string a = argv[i];
        if (a == "--trials" && i + 1 < argc)
            trials = std::atoi(argv[++i]);
        else if (a == "--seed" && i + 1 < argc)
            seed = static_cast<uint32_t>(std::atoi(argv[++i]));
        else if (a == "--real-pairs" && i + 1 < argc)
            real_pairs = static_cast<size_t>(std::atoi(argv[++i]));
        else if (a == "--std-range" && i + 1 < argc)
            std_range = std::atof(argv[++i]);
        else if (a == "--std-bearing-deg" && i + 1 < argc)
            std_bearing_deg = std::atof(argv[++i]);
        else if (a == "--raw-cov")
            raw_cov = true;
        else
        {
            std::fprintf(stderr, "usage: %s [--trials N] [--seed S] [--real-pairs M] [--raw-cov] [--std-range M] [--std-bearing-deg D]\n", argv[0]);
            return 2;
        }
    }
    if (trials < 1)
    {
        std::fprintf(stderr, "--trials must be >= 1\n");
        return 2;
    }
    if (std_range <= 0 || std_bearing_deg <= 0)
    {
        std::fprintf(stderr, "laser noise must be > 0\n");
        return 2;
    }
    simulated(trials, seed, raw_cov, std_range, std_bearing_deg * M_PI / 180);
    const char* ds = std::getenv("HYMM_DATASETS");
    if (!ds)
    {
        std::printf("\nHYMM_DATASETS not set: real scan pairs skipped\n");
        return 0;
    }
    const std::string root = ds;
    real("Intel (180 beams, 1 deg)", root + "/intel_mrpt_rawlog/intel.rawlog", real_pairs, 0.03,
         0.25 * M_PI / 180, 30);
    real("Malaga (361 beams, 0.5 deg)",
         root + "/malaga_2006_telecom_mrpt/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog",
         real_pairs, 0.03, 0.25 * M_PI / 180, 60);
    return 0;
}
