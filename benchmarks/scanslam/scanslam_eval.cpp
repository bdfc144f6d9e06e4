// hymm-scanslam-eval: Scan-SLAM (DenseSlam, landmark_source = scan_landmarks) on a
// simulated scenario over many noise seeds, scored against the simulator's truth
// (hymm::app::runScanSlamStudy). Prints one CSV line per seed and a markdown table of
// medians and spreads; the vehicle NEES is averaged over the runs step by step and
// compared with the 95 % band of the run-averaged chi-square(3). -p S also prints that
// NEES (3 DOF, position, heading) in bins of S seconds: where the runs leave the band;
// --closure-profile S the same in bins of time relative to each run's loop closure;
// --subsets K how the share of steps in the band varies over sets of K of the runs.
//   hymm-scanslam-eval -c configs/ch5_scanslam.ini -s configs/sim/ch5_scanslam.ini -n 20
#include <hymm/app/ScanSlamStudy.h>
#include <hymm/core/config_utils.h>
#include <hymm/eval/nees.h>
#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/math/wrap2pi.h>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <map>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <numeric>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace
{
struct Spread
{
    double median = 0, lo = 0, hi = 0;  // lo/hi: 10th and 90th percentiles
};

Spread spread(std::vector<double> v)
{
    v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
    if (v.empty()) return {std::nan(""), std::nan(""), std::nan("")};
    std::sort(v.begin(), v.end());
    auto q = [&](double p) { return v[static_cast<size_t>(std::lround(p * static_cast<double>(v.size() - 1)))]; };
    return {q(0.5), q(0.1), q(0.9)};
}

std::string fmt(const Spread& s, double scale, int prec)
{
    char buf[128];
    std::snprintf(buf, sizeof buf, "%.*f (%.*f-%.*f)", prec, s.median * scale, prec, s.lo * scale,
                  prec, s.hi * scale);
    return buf;
}

/** A wide-search alignment is wrong when its error against the truth exceeds 1 m or
 *  3 sigma (Mahalanobis distance with the fused R). */
bool wrong(const hymm::app::ScanSlamRun::Observation& o)
{
    return o.error.head<2>().norm() > 1.0 || o.error.dot(o.R.ldlt().solve(o.error)) > 9.0;
}

/** (wide alignments fused, of them wrong, wide alignments gated). */
std::array<size_t, 3> wideCounts(const hymm::app::ScanSlamRun& r)
{
    std::array<size_t, 3> c{};
    for (const auto& o : r.observations)
        if (o.wide) o.updated ? (++c[0], c[1] += wrong(o)) : ++c[2];
    return c;
}

size_t counter(const hymm::app::ScanSlamRun& r, const std::string& key)
{
    for (const auto& [k, n] : r.counters)
        if (k == key) return n;
    return 0;
}
/** Converged alignments binned by `key` (edges ascending): count, share fused, mean
 *  3-DOF NEES of z against the truth with the fused R, share above the 99 % gate of
 *  chi-square(3), per-axis normalised squared errors and RMS errors. */
template <class Key>
void observationTable(const std::vector<hymm::app::ScanSlamRun>& runs, const char* name,
                      const std::vector<double>& edges, Key key)
{
    const double gate99 = 11.3449;
    std::printf("\n| %s | aligned | fused | NEES (3 DOF) | NEES fused: mean / median | > 99 %% gate | NEES x / y / phi | RMS x, y [m] / phi [deg] | sqrt(R) x, y [m] / phi [deg] |\n"
                "|---|---|---|---|---|---|---|---|---|\n", name);
    for (size_t b = 0; b + 1 < edges.size(); ++b)
    {
        size_t n = 0, fused = 0, out = 0;
        double nees = 0;
        std::vector<double> fused_nees;
        Eigen::Vector3d axis = Eigen::Vector3d::Zero(), sq = Eigen::Vector3d::Zero(), rd = Eigen::Vector3d::Zero();
        for (const auto& r : runs)
            for (const auto& o : r.observations)
            {
                const double k = key(o);
                if (k < edges[b] || k >= edges[b + 1]) continue;
                const double e = o.error.dot(o.R.ldlt().solve(o.error));
                ++n, fused += o.updated, out += e > gate99, nees += e;
                if (o.updated) fused_nees.push_back(e);
                for (int i = 0; i < 3; ++i)
                {
                    axis[i] += o.error[i] * o.error[i] / o.R(i, i);
                    sq[i] += o.error[i] * o.error[i];
                    rd[i] += std::sqrt(o.R(i, i));
                }
            }
        if (n == 0) continue;
        const double dn = static_cast<double>(n);
        const Spread fs = spread(fused_nees);
        const double fused_mean =
            std::accumulate(fused_nees.begin(), fused_nees.end(), 0.0) / std::max<double>(1, fused_nees.size());
        std::printf("| %g-%g | %zu | %.2f | %.2f | %.2f / %.2f | %.3f | %.2f / %.2f / %.2f | %.3f, %.3f / %.2f | %.3f, %.3f / %.2f |\n",
                    edges[b], edges[b + 1], n, fused / dn, nees / dn, fused_mean, fs.median, out / dn, axis[0] / dn, axis[1] / dn,
                    axis[2] / dn, std::sqrt(sq[0] / dn), std::sqrt(sq[1] / dn), std::sqrt(sq[2] / dn) * 180 / M_PI,
                    rd[0] / dn, rd[1] / dn, rd[2] / dn * 180 / M_PI);
    }
}
/** The scan odometry's fused alignments to their reference against the truth (none
 *  without [ScanOdometry]): the 3-DOF NEES and per axis the normalised squared error
 *  e_i^2 / R_ii (1 expected), the figures cov_scale (x, y) and heading_cov_scale (phi)
 *  calibrate. */
void odometryAlignmentTable(const std::vector<hymm::app::ScanSlamRun>& runs)
{
    size_t n = 0;
    double nees = 0;
    Eigen::Vector3d axis = Eigen::Vector3d::Zero();
    for (const auto& r : runs)
        for (const auto& a : r.odometry_alignments)
        {
            nees += a.error.dot(a.cov.ldlt().solve(a.error));
            for (int i = 0; i < 3; ++i) axis[i] += a.error[i] * a.error[i] / a.cov(i, i);
            ++n;
        }
    if (n == 0) return;
    const double dn = static_cast<double>(n);
    std::printf("\n| scan odometry: alignments to the reference against the truth | count | NEES (3 DOF) | e^2 / R x / y / phi |\n"
                "|---|---|---|---|\n| all runs | %zu | %.2f | %.2f / %.2f / %.2f |\n",
                n, nees / dn, axis[0] / dn, axis[1] / dn, axis[2] / dn);
}
/** The run counters whose name starts with `prefix`, summed over the runs, keyed by the
 *  name without its first `strip` characters. */
std::map<std::string, size_t> sumCounters(const std::vector<hymm::app::ScanSlamRun>& runs, const std::string& prefix,
                                          size_t strip)
{
    std::map<std::string, size_t> out;
    for (const auto& r : runs)
        for (const auto& [k, n] : r.counters)
            if (k.rfind(prefix, 0) == 0) out[k.substr(strip)] += n;
    return out;
}

void printCounts(const std::string& title, const std::map<std::string, size_t>& counts)
{
    std::cout << "\n" << title << " (sum over the runs):";
    for (const auto& [k, n] : counts) std::cout << " " << k << "=" << n;
    std::cout << "\n";
}

/** How alike the errors of two fused alignments of the same template are, by the
 *  distance between the true sensor positions (the change of viewpoint): per axis, the
 *  correlation of the normalised errors e_i / sqrt(R_ii) over all such pairs (0:
 *  independent, as the EKF assumes; 1: the same error again). Local alignments only (the
 *  wide search's start is another). Pairs more than `pass_gap_s` apart in time (another
 *  pass of the template; an approximation of the view_corr state model's "earlier
 *  passes", which it separates by the viewpoint, view_corr_drop_lengths L) in a second
 *  table. */
void errorCorrelationTables(const std::vector<hymm::app::ScanSlamRun>& runs, double pass_gap_s)
{
    const std::vector<double> edges{0, 0.5, 1, 2, 4, 8, 16, 1e9};
    const size_t nb = edges.size() - 1;
    /** Sums of one table (one per pass relation): per bin, the pairs and the products. */
    struct Sums
    {
        std::vector<Eigen::Vector3d> ab, aa, bb;
        std::vector<size_t> pairs;
    };
    std::array<Sums, 2> tables;  // [0]: the same pass, [1]: another pass
    for (Sums& t : tables)
    {
        t.ab = t.aa = t.bb = std::vector<Eigen::Vector3d>(nb, Eigen::Vector3d::Zero());
        t.pairs.assign(nb, 0);
    }
    for (const auto& r : runs)
    {
        std::map<long, std::vector<const hymm::app::ScanSlamRun::Observation*>> by_id;
        for (const auto& o : r.observations)
            if (o.updated && !o.wide) by_id[o.id].push_back(&o);
        for (const auto& [id, obs] : by_id)
            for (size_t a = 0; a < obs.size(); ++a)
                for (size_t b = a + 1; b < obs.size(); ++b)
                {
                    const double d = (obs[b]->sensor - obs[a]->sensor).norm();
                    const auto it = std::upper_bound(edges.begin(), edges.end(), d);
                    const size_t k = static_cast<size_t>(it - edges.begin()) - 1;
                    if (k >= nb) continue;
                    Sums& t = tables[std::abs(obs[b]->t - obs[a]->t) > pass_gap_s ? 1 : 0];
                    ++t.pairs[k];
                    for (int i = 0; i < 3; ++i)
                    {
                        const double ua = obs[a]->error[i] / std::sqrt(obs[a]->R(i, i));
                        const double ub = obs[b]->error[i] / std::sqrt(obs[b]->R(i, i));
                        t.ab[k][i] += ua * ub, t.aa[k][i] += ua * ua, t.bb[k][i] += ub * ub;
                    }
                }
    }
    for (size_t other = 0; other < 2; ++other)
    {
        const Sums& t = tables[other];
        std::printf("\n| change of viewpoint between two fused alignments of one template [m], %s %g s) | pairs | "
                    "error correlation x / y / phi |\n|---|---|---|\n",
                    other ? "another pass (more than" : "the same pass (within", pass_gap_s);
        for (size_t k = 0; k < nb; ++k)
        {
            if (t.pairs[k] == 0) continue;
            Eigen::Vector3d c;
            for (int i = 0; i < 3; ++i) c[i] = t.ab[k][i] / std::sqrt(t.aa[k][i] * t.bb[k][i]);
            std::printf("| %g-%g | %zu | %.2f / %.2f / %.2f |\n", edges[k], edges[k + 1], t.pairs[k], c[0], c[1],
                        c[2]);
        }
    }
}

/** The alignment tables of --observations: by travel and by view change since creation,
 *  and the correlation between alignments of one template. */
void observationTables(const std::vector<hymm::app::ScanSlamRun>& runs)
{
    using O = hymm::app::ScanSlamRun::Observation;
    observationTable(runs, "sensor travel since creation [m]", {0, 2, 5, 10, 15, 20, 30, 1e9},
                     [](const O& o) { return o.travel_m; });
    observationTable(runs, "view change since creation [deg]", {0, 5, 10, 20, 40, 90, 180},
                     [](const O& o) { return o.view_change * 180 / M_PI; });
    errorCorrelationTables(runs, 30);
}
// Steps every run has (the runs share the frame times).
size_t commonSteps(const std::vector<hymm::app::ScanSlamRun>& runs)
{
    size_t n = runs.front().steps.size();
    for (const auto& r : runs) n = std::min(n, r.steps.size());
    return n;
}

/** The vehicle NEES averaged over the runs `pick` (indices into runs), step by step over
 *  the steps every run has. */
std::vector<double> averagedNees(const std::vector<hymm::app::ScanSlamRun>& runs, const std::vector<size_t>& pick)
{
    std::vector<double> avg(commonSteps(runs), 0.0);
    for (size_t j : pick)
        for (size_t i = 0; i < avg.size(); ++i) avg[i] += runs[j].steps[i].nees / static_cast<double>(pick.size());
    return avg;
}

/** The position (2 DOF) and heading (1 DOF) parts of a step's vehicle NEES. */
std::pair<double, double> positionHeadingNees(const hymm::app::ScanSlamRun::Step& st)
{
    Eigen::Vector3d e = st.truth - st.estimate;
    e[2] = mrpt::math::wrapToPi(e[2]);
    return {hymm::eval::nees(e.head<2>(), st.cov.topLeftCorner<2, 2>()).value,
            hymm::eval::nees(e.tail<1>(), st.cov.bottomRightCorner<1, 1>()).value};
}

// Run-averaged vehicle NEES in bins of `bin_s` seconds: the whole 3-DOF NEES, its position
// (2 DOF) and heading (1 DOF) parts, each averaged over the runs step by step and then over
// the bin; and the share of the bin's steps inside the 3-DOF band. Shows where a run
// leaves the band (before or after the loop closure, position or heading).
void neesProfile(const std::vector<hymm::app::ScanSlamRun>& runs, double bin_s)
{
    const size_t n = commonSteps(runs);
    const double k = static_cast<double>(runs.size());
    const auto band = hymm::eval::averageNeesBounds(3, static_cast<int>(runs.size()), 0.95);
    std::cout << "\n| t [s] | NEES (3 DOF) | position (2 DOF) | heading (1 DOF) | steps inside the band |\n"
                 "|---|---|---|---|---|\n";
    double t0 = runs.front().steps.front().t, sum3 = 0, sum2 = 0, sum1 = 0;
    size_t m = 0, in = 0;
    for (size_t i = 0; i < n; ++i)
    {
        double a3 = 0, a2 = 0, a1 = 0;
        for (const auto& r : runs)
        {
            const auto& st = r.steps[i];
            const auto [pos, heading] = positionHeadingNees(st);
            a3 += st.nees / k;
            a2 += pos / k;
            a1 += heading / k;
        }
        sum3 += a3, sum2 += a2, sum1 += a1, ++m;
        in += (a3 >= band.lower && a3 <= band.upper) ? 1 : 0;
        const double t = runs.front().steps[i].t;
        if (t - t0 >= bin_s - 1e-9 || i + 1 == n)
        {
            const double md = static_cast<double>(m);
            std::printf("| %.0f-%.0f | %.2f | %.2f | %.2f | %.2f |\n", t0, t, sum3 / md, sum2 / md, sum1 / md,
                        static_cast<double>(in) / md);
            t0 = t, sum3 = sum2 = sum1 = 0, m = in = 0;
        }
    }
}

// How much the share of steps inside the band depends on which seeds a set holds: the
// share for random k-run subsets of the runs (1000 draws without replacement; the
// generator's seed is fixed, the draws are std::shuffle's, so they repeat with the same
// standard library) and for the disjoint blocks of k consecutive seeds (runs beyond the
// last whole block are in no block); then the same with every NEES times a constant
// (0.7 ... 1.5), the runs' errors unchanged: not a refiltered run, whose gains, gates and
// closures would change too, but where a constant calibration would put these runs.
void subsetTable(const std::vector<hymm::app::ScanSlamRun>& runs, int k, long first_seed)
{
    const size_t n = commonSteps(runs), nr = runs.size();
    std::vector<double> run_mean;
    double total = 0;
    size_t total_count = 0;
    for (const auto& r : runs)
    {
        double sum = 0;
        size_t count = 0;
        for (size_t i = 0; i < n; ++i)
            if (std::isfinite(r.steps[i].nees)) sum += r.steps[i].nees, ++count;
        run_mean.push_back(count > 0 ? sum / static_cast<double>(count) : std::nan(""));
        total += sum, total_count += count;
    }
    const double mean = total_count > 0 ? total / static_cast<double>(total_count) : std::nan("");
    const Spread per_run = spread(run_mean);
    const auto band = hymm::eval::averageNeesBounds(3, k, 0.95);
    const std::vector<double> scales{0.7, 0.8, 0.9, 1.0, 1.1, 1.2, 1.3, 1.4, 1.5};
    // The steps inside the band and the share above it, a step NaN in one of the runs
    // counting in neither.
    std::vector<double> scaled(n);
    const auto share = [&](const std::vector<double>& avg, double scale) {
        size_t above = 0, finite = 0;
        for (size_t i = 0; i < n; ++i)
        {
            scaled[i] = scale * avg[i];
            above += scaled[i] > band.upper, finite += std::isfinite(scaled[i]);
        }
        return std::make_pair(hymm::eval::fractionInsideBounds(scaled, band),
                              finite > 0 ? static_cast<double>(above) / static_cast<double>(finite) : std::nan(""));
    };
    // Every scale reads the same draws and blocks.
    std::vector<std::vector<double>> shares(scales.size()), aboves(scales.size());
    std::vector<size_t> idx(nr);
    std::iota(idx.begin(), idx.end(), 0);
    std::mt19937 gen(1);
    for (int d = 0; d < 1000; ++d)
    {
        std::shuffle(idx.begin(), idx.end(), gen);
        const std::vector<double> avg = averagedNees(runs, {idx.begin(), idx.begin() + k});
        for (size_t s = 0; s < scales.size(); ++s)
        {
            const auto [in, above] = share(avg, scales[s]);
            shares[s].push_back(in);
            aboves[s].push_back(above);
        }
    }
    std::vector<std::vector<double>> block_avgs;
    for (size_t b = 0; b + static_cast<size_t>(k) <= nr; b += static_cast<size_t>(k))
    {
        std::vector<size_t> pick(static_cast<size_t>(k));
        std::iota(pick.begin(), pick.end(), b);
        block_avgs.push_back(averagedNees(runs, pick));
    }
    std::printf("\nvehicle NEES over every step of the %zu runs: mean %.2f (3 expected); each run's mean: "
                "median %.2f (10th-90th %.2f-%.2f); %d-run sets, band [%.3f, %.3f]\n\n",
                nr, mean, per_run.median, per_run.lo, per_run.hi, k, band.lower, band.upper);
    std::cout << "| NEES | share of the steps inside the band: median (10th-90th) over 1000 random sets | "
                 "sets at >= 0.9 | steps above the band: 90th percentile | consecutive blocks of seeds |\n"
                 "|---|---|---|---|---|\n";
    for (size_t s = 0; s < scales.size(); ++s)
    {
        const auto hit = std::count_if(shares[s].begin(), shares[s].end(), [](double v) { return v >= 0.9; });
        std::string blocks;
        for (size_t b = 0; b < block_avgs.size(); ++b)
        {
            const long lo = first_seed + static_cast<long>(b) * k;
            char buf[64];
            std::snprintf(buf, sizeof buf, "%s%ld-%ld: %.2f", b == 0 ? "" : ", ", lo, lo + k - 1,
                          share(block_avgs[b], scales[s]).first);
            blocks += buf;
        }
        const Spread sh = spread(shares[s]);
        std::printf("| x %.1f | %.2f (%.2f-%.2f) | %.2f | %.2f | %s |\n", scales[s], sh.median, sh.lo, sh.hi,
                    static_cast<double>(hit) / 1000.0, spread(aboves[s]).hi, blocks.c_str());
    }
}

// Vehicle NEES averaged over the runs that close their loop, in bins of `bin_s` seconds of
// time relative to each run's closure (its first fused wide answer): the runs close at
// different times, so the absolute-time profile smears what a closure does to the
// filter. Each bin averages the runs' mean NEES over the bin (3 DOF, position, heading)
// and gives how many runs reach it; the band is that of the run count.
void closureProfile(const std::vector<hymm::app::ScanSlamRun>& runs, double bin_s)
{
    struct Bin
    {
        double s3 = 0, s2 = 0, s1 = 0;
        size_t steps = 0, runs = 0;
        const hymm::app::ScanSlamRun* last = nullptr;  //!< the run that reached it last
    };
    std::map<long, Bin> bins;
    for (const auto& r : runs)
    {
        if (r.closure_t < 0) continue;
        for (const auto& st : r.steps)
        {
            auto& b = bins[static_cast<long>(std::floor((st.t - r.closure_t) / bin_s))];
            const auto [pos, heading] = positionHeadingNees(st);
            b.s3 += st.nees, b.s2 += pos, b.s1 += heading, ++b.steps;
            if (b.last != &r) ++b.runs, b.last = &r;
        }
    }
    std::cout << "\n| t - closure [s] | runs | NEES (3 DOF) | position (2 DOF) | heading (1 DOF) | 95 % band |\n"
                 "|---|---|---|---|---|---|\n";
    for (const auto& [k, b] : bins)
    {
        if (b.runs < 2) continue;
        const auto band = hymm::eval::averageNeesBounds(3, static_cast<int>(b.runs), 0.95);
        const double n = static_cast<double>(b.steps);
        std::printf("| %+.0f..%+.0f | %zu | %.2f | %.2f | %.2f | %.2f-%.2f |\n", k * bin_s, (k + 1) * bin_s,
                    b.runs, b.s3 / n, b.s2 / n, b.s1 / n, band.lower, band.upper);
    }
}
}  // namespace

int main(int argc, char** argv)
{
    try
    {
        TCLAP::CmdLine cmd("hymm-scanslam-eval: Scan-SLAM over many simulated seeds", ' ', "0.1");
        TCLAP::ValueArg<std::string> config("c", "config", "hymm-slam .ini", true, "", "FILE", cmd);
        TCLAP::ValueArg<std::string> scenario("s", "scenario", "simulator .ini", true, "", "FILE", cmd);
        TCLAP::ValueArg<int> seeds("n", "seeds", "number of seeds", false, 20, "N", cmd);
        TCLAP::ValueArg<int> first("f", "first-seed", "first seed", false, 1, "N", cmd);
        TCLAP::ValueArg<double> duration("d", "duration", "run length [s] (0: the scenario's laps)",
                                         false, 0, "S", cmd);
        TCLAP::SwitchArg obs_table("o", "observations",
                                   "also print the converged alignments' errors against the truth, "
                                   "binned by the sensor's travel and view change since the landmark was made",
                                   cmd);
        TCLAP::ValueArg<double> profile("p", "nees-profile",
                                        "also print the run-averaged vehicle NEES (3 DOF, position, heading) "
                                        "in bins of this many seconds",
                                        false, 0, "S", cmd);
        TCLAP::ValueArg<double> closure_profile(
            "", "closure-profile",
            "also print the vehicle NEES of the runs that close their loop in bins of this many "
            "seconds of time relative to each run's closure",
            false, 0, "S", cmd);
        TCLAP::ValueArg<int> subsets(
            "", "subsets",
            "also print how the share of steps inside the band varies over sets of this many of the "
            "runs (random sets and consecutive blocks), as estimated and with the NEES times 0.7 ... 1.5",
            false, 0, "K", cmd);
        if (!cmd.parse(argc, argv)) return 0;
        if (seeds.getValue() < 1) throw std::invalid_argument("--seeds must be >= 1");
        if (subsets.getValue() < 0 || (subsets.getValue() > 0 && subsets.getValue() >= seeds.getValue()))
            throw std::invalid_argument("--subsets must be between 1 and --seeds - 1 (0: none)");
        const auto cfg = hymm::core::openConfigFile(config.getValue());
        auto sc = hymm::sim::Scenario::fromFile(scenario.getValue());
        if (duration.getValue() > 0) sc.run.duration_s = duration.getValue();

        std::vector<hymm::app::ScanSlamRun> runs;
        std::cout << "seed,steps,closure_t,dr_rmse,path_rmse,path_rmse_before,path_rmse_after,lm_before,lm_xy_before,"
                     "lm_phi_deg_before,lm_after,lm_xy_after,lm_phi_deg_after,lm_nees_after,"
                     "template_outline_m,created,updated,gated,out_of_view,align_failed,"
                     "ms_per_step,x_real_time,view_changed,prediction_uncertain,wide_fused,wide_wrong,wide_gated,"
                     "veh_nees_before,veh_nees_after\n";
        for (int k = 0; k < seeds.getValue(); ++k)
        {
            sc.run.seed = first.getValue() + k;
            auto r = hymm::app::runScanSlamStudy(sc, *cfg);
            double secs = 0;
            for (const auto& s : r.steps) secs += s.seconds;
            size_t failed = 0;
            for (const auto& [key, n] : r.counters)
                if (key.find("align_failed") != std::string::npos) failed += n;
            const auto wc = wideCounts(r);
            // The run's own mean vehicle NEES before and from the closure on (the whole run
            // when there is none): which runs carry the run-averaged excess.
            double nb = 0, na = 0;
            size_t kb = 0, ka = 0;
            for (size_t i = 0; i < r.steps.size(); ++i)
                if (r.closure_t >= 0 && i >= r.closure_step)
                    na += r.steps[i].nees, ++ka;
                else
                    nb += r.steps[i].nees, ++kb;
            std::printf("%ld,%zu,%.1f,%.4f,%.4f,%.4f,%.4f,%zu,%.4f,%.4f,%zu,%.4f,%.4f,%.3f,%.4f,%zu,%zu,%zu,%zu,%zu,%.3f,%.1f,%zu,%zu,%zu,%zu,%zu,%.2f,%.2f\n",
                        sc.run.seed, r.steps.size(), r.closure_t, r.dead_reckoning_rmse_m,
                        r.path_rmse_m, r.path_rmse_before_m,
                        r.path_rmse_after_m, r.before_closure.landmarks, r.before_closure.rmse_xy_m,
                        r.before_closure.rmse_phi * 180 / M_PI, r.after_closure.landmarks,
                        r.after_closure.rmse_xy_m, r.after_closure.rmse_phi * 180 / M_PI,
                        r.after_closure.mean_nees, r.template_outline_mean_m,
                        counter(r, "scan_landmarks.created"), counter(r, "scan_landmarks.updated"),
                        counter(r, "scan_landmarks.gated"), counter(r, "scan_landmarks.out_of_view"),
                        failed, 1e3 * secs / static_cast<double>(r.steps.size()),
                        r.duration_s / secs, counter(r, "scan_landmarks.view_changed"),
                        counter(r, "scan_landmarks.prediction_uncertain"), wc[0], wc[1], wc[2],
                        nb / static_cast<double>(std::max<size_t>(kb, 1)),
                        ka > 0 ? na / static_cast<double>(ka) : std::nan(""));
            std::fflush(stdout);
            runs.push_back(std::move(r));
        }
        // Vehicle NEES averaged over the runs, step by step (runs share the frame times).
        const size_t n_steps = commonSteps(runs);
        std::vector<size_t> all(runs.size());
        std::iota(all.begin(), all.end(), 0);
        const std::vector<double> avg = averagedNees(runs, all);
        const auto band = hymm::eval::averageNeesBounds(3, static_cast<int>(runs.size()), 0.95);
        const double inside = hymm::eval::fractionInsideBounds(avg, band);
        size_t above = 0;
        for (double v : avg) above += v > band.upper;

        auto col = [&](auto f) {
            std::vector<double> v;
            for (const auto& r : runs) v.push_back(f(r));
            return spread(v);
        };
        using R = hymm::app::ScanSlamRun;
        std::vector<double> step_ms;
        for (const auto& r : runs)
            for (const auto& s : r.steps) step_ms.push_back(1e3 * s.seconds);
        std::cout << "\n| quantity (median, 10th-90th percentile over " << runs.size() << " seeds) | value |\n|---|---|\n"
                  << "| loop closure at [s] | " << fmt(col([](const R& r) { return r.closure_t; }), 1, 1) << " |\n"
                  << "| dead-reckoning path RMSE, whole run [m] | " << fmt(col([](const R& r) { return r.dead_reckoning_rmse_m; }), 1, 3) << " |\n"
                  << "| Scan-SLAM path RMSE, whole run [m] | " << fmt(col([](const R& r) { return r.path_rmse_m; }), 1, 3) << " |\n"
                  << "| path RMSE before the closure [m] | " << fmt(col([](const R& r) { return r.path_rmse_before_m; }), 1, 3) << " |\n"
                  << "| path RMSE after the closure [m] | " << fmt(col([](const R& r) { return r.path_rmse_after_m; }), 1, 3) << " |\n"
                  << "| landmarks before / after | " << fmt(col([](const R& r) { return double(r.before_closure.landmarks); }), 1, 0)
                  << " / " << fmt(col([](const R& r) { return double(r.after_closure.landmarks); }), 1, 0) << " |\n"
                  << "| landmark position RMSE before / after [m] | " << fmt(col([](const R& r) { return r.before_closure.rmse_xy_m; }), 1, 3)
                  << " / " << fmt(col([](const R& r) { return r.after_closure.rmse_xy_m; }), 1, 3) << " |\n"
                  << "| landmark heading RMSE before / after [deg] | " << fmt(col([](const R& r) { return r.before_closure.rmse_phi; }), 180 / M_PI, 3)
                  << " / " << fmt(col([](const R& r) { return r.after_closure.rmse_phi; }), 180 / M_PI, 3) << " |\n"
                  << "| landmark mean NEES (3 DOF) after | " << fmt(col([](const R& r) { return r.after_closure.mean_nees; }), 1, 2) << " |\n"
                  << "| vehicle NEES, run-averaged: steps inside the 95 % band [" << band.lower << ", " << band.upper
                  << "] | " << inside << " (above: " << static_cast<double>(above) / static_cast<double>(n_steps) << ") |\n"
                  << "| template points' mean distance to the true outlines [m] | " << fmt(col([](const R& r) { return r.template_outline_mean_m; }), 1, 3) << " |\n"
                  << "| CPU time per step [ms] (all steps) | " << fmt(spread(step_ms), 1, 2) << " |\n"
                  << "| x real time, CPU (per run) | " << fmt(col([](const R& r) {
                         double s = 0;
                         for (const auto& st : r.steps) s += st.seconds;
                         return r.duration_s / s;
                     }), 1, 1) << " |\n";
        std::cout << "| wide-search alignments fused per run (loop closures) / of them wrong (> 1 m or > 3 sigma) | "
                  << fmt(col([](const R& r) { return double(wideCounts(r)[0]); }), 1, 0) << " / "
                  << fmt(col([](const R& r) { return double(wideCounts(r)[1]); }), 1, 0) << " |\n";
        {
            // The wide-search alignments against the truth: NEES with the fused R, xy error.
            std::vector<double> nees, err;
            for (const auto& r : runs)
                for (const auto& o : r.observations)
                    if (o.wide) nees.push_back(o.error.dot(o.R.ldlt().solve(o.error))), err.push_back(o.error.head<2>().norm());
            if (!nees.empty())
                std::cout << "| wide-search alignments (all runs): count / NEES (3 DOF) median, 10th-90th / xy error [m] median, max | "
                          << nees.size() << " / " << fmt(spread(nees), 1, 2) << " / " << fmt(spread(err), 1, 3) << ", "
                          << *std::max_element(err.begin(), err.end()) << " |\n";
        }
        // Counter groups summed over the runs (ScanLandmarkMap::Stats): wide-search
        // outcomes, duplicate merging, template augmentation from the dense map (6.2).
        auto wide = sumCounters(runs, "scan_landmarks.wide.", 20);
        if (!wide.empty()) printCounts("wide-search outcomes", wide);
        auto merge = sumCounters(runs, "scan_landmarks.merge", 15);
        if (merge["merge_candidates"] > 0) printCounts("duplicate merging", merge);
        auto aug = sumCounters(runs, "scan_landmarks.augment", 15);
        if (aug["augmented"] + aug["augment_empty"] > 0) printCounts("template augmentation", aug);
        odometryAlignmentTable(runs);
        if (obs_table.getValue()) observationTables(runs);
        if (profile.getValue() > 0) neesProfile(runs, profile.getValue());
        if (closure_profile.getValue() > 0) closureProfile(runs, closure_profile.getValue());
        if (subsets.getValue() > 0) subsetTable(runs, subsets.getValue(), first.getValue());
        return 0;
    }
    catch (const std::exception& e)
    {
        std::cerr << "hymm-scanslam-eval: error: " << mrpt::exception_to_str(e) << "\n";
        return 1;
    }
}
