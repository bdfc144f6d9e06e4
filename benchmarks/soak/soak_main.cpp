/**
 * @file soak_main.cpp
 * @brief hymm-soak: the DenseSLAM pipeline over many laps of a simulated world, with
 *        what it holds and costs at the end of every lap.
 *
 *   hymm-soak [--scenario configs/sim/ch3_objects.ini] [--slam configs/ch3_slam.ini]
 *             [--laps 20] [--layers points,occupancy,particles,sog] [--no-delayed]
 *             [--set Section.key=value ...] [--seed N] [--csv FILE] [--profile]
 *
 * Simulates the scenario in memory with [Scenario] laps = --laps (duration_s = 0) and
 * feeds each frame (odometry increment with its covariance, laser scan, landmark
 * readings: what its rawlog carries) to DenseSlam built from --slam with [DenseSlam]
 * dense_layers = --layers and [DelayedDenseStore] enabled = true (unless --no-delayed);
 * --set changes any other key (repeatable; the result is read as strictly as hymm-slam
 * reads a file). A step is one frame: processOdometry + processFrame, timed on the wall
 * clock and in this thread's CPU time (which the other processes on a shared machine
 * do not inflate); the simulation is not timed. At the end of every lap (the simulator's path
 * follower counts the laps) one row: process RSS (/proc/self/status VmRSS), median and
 * p95 time per step of the lap, the EKF's active covariance (smallest eigenvalue of its
 * symmetric part, largest |P - P^T|) and the smallest eigenvalue of the Schur complement
 * P_pp - P_pa P_aa^-1 P_ap over the passive blocks (>= 0 iff the joint covariance of the
 * block with the active states is PSD), regions, and the items stored per dense layer,
 * fallback tiles and delayed-store returns, scan landmarks' templates and their points (the
 * CSV also: the points and SOG components of the fullest region). --profile adds the pipeline's and the dense
 * map's CTimeLogger sections, per lap, in ms per step.
 * Exit code 0; 1 on error (bad arguments, a config the pipeline rejects).
 */
#include <hymm/core/StrictConfigFile.h>
#include <hymm/core/command_line.h>
#include <hymm/denseslam/DenseSlam.h>
#include <hymm/sim/Simulator.h>
#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPosePDFGaussian.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{
using hymm::denseslam::DenseSlam;

/** VmRSS of this process [kB], 0 if /proc is not readable. */
size_t rssKb()
{
    std::ifstream f("/proc/self/status");
    std::string line;
    while (std::getline(f, line))
        if (line.rfind("VmRSS:", 0) == 0) return std::stoul(line.substr(6));
    return 0;
}

/** CPU time of this thread [ms]: the other processes on a shared machine do not count. */
double threadCpuMs()
{
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return 1e3 * static_cast<double>(ts.tv_sec) + 1e-6 * static_cast<double>(ts.tv_nsec);
}

double percentile(std::vector<double> v, double q)
{
    if (v.empty()) return std::nan("");
    const size_t k = std::min(v.size() - 1, static_cast<size_t>(std::floor(q * static_cast<double>(v.size() - 1) + 0.5)));
    std::nth_element(v.begin(), v.begin() + static_cast<long>(k), v.end());
    return v[k];
}

std::string trim(const std::string& s)
{
    const auto a = s.find_first_not_of(" \t\r");
    if (a == std::string::npos) return "";
    return s.substr(a, s.find_last_not_of(" \t\r") - a + 1);
}

/** Sets `key = value` in [section] of .ini text: replaces the key's line, or adds it
 *  after the section header, or appends the section. */
std::string setKey(const std::string& text, const std::string& section, const std::string& key,
                   const std::string& value)
{
    std::istringstream in(text);
    std::vector<std::string> lines;
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    long header = -1, end = static_cast<long>(lines.size());
    for (long i = 0; i < static_cast<long>(lines.size()); ++i)
    {
        const std::string t = trim(lines[static_cast<size_t>(i)]);
        if (t.size() > 1 && t.front() == '[' && t.back() == ']')
        {
            if (header >= 0)
            {
                end = i;
                break;
            }
            if (t.substr(1, t.size() - 2) == section) header = i;
        }
    }
    const std::string entry = key + " = " + value;
    if (header < 0)
        lines.insert(lines.end(), {"", "[" + section + "]", entry});
    else
    {
        bool done = false;
        for (long i = header + 1; i < end && !done; ++i)
        {
            const std::string t = trim(lines[static_cast<size_t>(i)]);
            const auto eq = t.find('=');
            if (eq != std::string::npos && t[0] != '#' && t[0] != ';' && trim(t.substr(0, eq)) == key)
            {
                lines[static_cast<size_t>(i)] = entry;
                done = true;
            }
        }
        if (!done) lines.insert(lines.begin() + header + 1, entry);
    }
    std::string out;
    for (const auto& l : lines) out += l + "\n";
    return out;
}

std::string readFile(const std::string& path)
{
    std::ifstream f(path);
    if (!f) throw std::runtime_error("cannot read " + path);
    std::ostringstream s;
    s << f.rdbuf();
    return s.str();
}

/** One row of the table: the state at the end of a lap. */
struct LapRow
{
    long lap = 0;
    size_t steps = 0;
    double sim_t = 0;  //!< [s] simulated time at the end of the lap
    double wall_s = 0;  //!< [s] summed step times of the lap
    double rss_mb = 0;
    double median_ms = 0, p95_ms = 0, max_ms = 0;
    double cpu_median_ms = 0, cpu_p95_ms = 0;  //!< this thread's CPU time per step
    size_t landmarks = 0, passive_blocks = 0;
    double p_min_eig = 0, p_asym = 0, passive_min_eig = 0;
    size_t regions = 0, regions_with_content = 0;
    std::map<std::string, size_t> items;  //!< per layer kind
    size_t max_region_points = 0;  //!< points of the fullest region (or fallback tile)
    size_t max_region_sog = 0;     //!< SOG components of the fullest region
    size_t fallback_tiles = 0;
    size_t delayed_points = 0, delayed_scans = 0;
    double dense_mb = 0;  //!< HybridMetricMap::memoryBytes()
    size_t scan_templates = 0, template_points = 0;  //!< scan landmarks (thesis ch. 5)
    std::map<std::string, double> profile_ms;  //!< section -> ms per step in this lap
    std::map<std::string, size_t> scan_counters;  //!< ScanLandmarkMap::Stats, whole run so far
};

/** The scan-landmark counters that changed during the run, one column per lap (the
 *  increase in that lap). */
void printScanCounters(std::ostream& o, const std::vector<LapRow>& rows)
{
    if (rows.empty() || rows.back().scan_counters.empty()) return;
    o << "\nScan-landmark counters, increase per lap:\n\n| counter |";
    for (const auto& r : rows) o << ' ' << r.lap << " |";
    o << "\n|---|";
    for (size_t i = 0; i < rows.size(); ++i) o << "---|";
    o << '\n';
    for (const auto& [name, total] : rows.back().scan_counters)
    {
        if (total == 0) continue;
        o << "| " << name << " |";
        size_t before = 0;
        for (const auto& r : rows)
        {
            const auto it = r.scan_counters.find(name);
            const size_t now = it == r.scan_counters.end() ? 0 : it->second;
            o << ' ' << now - before << " |";
            before = now;
        }
        o << '\n';
    }
}

/** Covariance health: active P, and each passive block's Schur complement. */
void covarianceHealth(const hymm::ekf::EkfSlam& ekf, LapRow& r)
{
    const Eigen::MatrixXd P = ekf.cov();
    r.p_asym = (P - P.transpose()).cwiseAbs().maxCoeff();
    const Eigen::MatrixXd S = 0.5 * (P + P.transpose());
    r.p_min_eig = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(S, Eigen::EigenvaluesOnly).eigenvalues()(0);
    const auto& passive = ekf.passive();
    r.passive_blocks = passive.numBlocks();
    r.passive_min_eig = std::nan("");
    if (passive.numBlocks() == 0) return;
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(S);
    double lo = std::numeric_limits<double>::infinity();
    for (const long id : passive.ids())
    {
        const Eigen::MatrixXd C = passive.crossCov(id);  // d x n_a
        const Eigen::MatrixXd Ppp = passive.cov(id);
        Eigen::MatrixXd schur = Ppp - C * ldlt.solve(C.transpose());
        schur = 0.5 * (schur + schur.transpose());
        lo = std::min(lo, Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(schur, Eigen::EigenvaluesOnly).eigenvalues()(0));
    }
    r.passive_min_eig = lo;
}

std::map<std::string, double> profileTotals(const DenseSlam& slam, DenseSlam& mutable_slam)
{
    std::map<std::string, double> out;
    std::map<std::string, mrpt::system::CTimeLogger::TCallStats> s;
    mutable_slam.profiler().getStats(s);
    for (const auto& [k, v] : s) out[k] = v.total_t;
    if (slam.hybridMap())
    {
        s.clear();
        slam.hybridMap()->profiler().getStats(s);
        for (const auto& [k, v] : s) out[k] = v.total_t;
    }
    return out;
}

const char* const kKinds[] = {"points", "occupancy", "particles", "sog", "property"};

void printHeader(std::ostream& o)
{
    o << "| lap | steps | RSS [MB] | step median [ms] | step p95 [ms] | CPU/step median [ms] | CPU/step p95 [ms] "
         "| landmarks | passive blocks | P min eig | max abs(P - P^T) | passive Schur min eig | regions (with content) "
         "| points (fullest region) | occupancy cells | particles | SOG components | property cells | fallback tiles "
         "| delayed-store returns (scans) | dense map [MB] | scan templates (points) |\n"
      << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
}

std::string item(const LapRow& r, const char* kind)
{
    const auto it = r.items.find(kind);
    return it == r.items.end() ? "-" : std::to_string(it->second);
}

void printRow(std::ostream& o, const LapRow& r)
{
    char buf[512];
    std::snprintf(buf, sizeof(buf), "| %ld | %zu | %.1f | %.2f | %.2f | %.2f | %.2f | %zu | %zu | %.3g | %.1e | %.3g | %zu (%zu) | ",
                  r.lap, r.steps, r.rss_mb, r.median_ms, r.p95_ms, r.cpu_median_ms, r.cpu_p95_ms, r.landmarks,
                  r.passive_blocks, r.p_min_eig, r.p_asym, r.passive_min_eig, r.regions, r.regions_with_content);
    o << buf << item(r, "points") << " (" << r.max_region_points << ") | ";
    for (const char* k : {"occupancy", "particles", "sog", "property"}) o << item(r, k) << " | ";
    std::snprintf(buf, sizeof(buf), "%zu | %zu (%zu) | %.1f | %zu (%zu) |\n", r.fallback_tiles, r.delayed_points,
                  r.delayed_scans, r.dense_mb, r.scan_templates, r.template_points);
    o << buf << std::flush;
}

void printCsvHeader(std::ostream& o, const std::vector<std::string>& sections)
{
    o << "lap,steps,sim_t_s,wall_s,rss_mb,step_median_ms,step_p95_ms,step_max_ms,cpu_median_ms,cpu_p95_ms,"
         "landmarks,passive_blocks,p_min_eig,p_max_asym,passive_schur_min_eig,regions,regions_with_content,"
         "max_region_points,max_region_sog";
    for (const char* k : kKinds) o << ',' << k;
    o << ",fallback_tiles,delayed_points,delayed_scans,dense_mb,scan_templates,template_points";
    for (const auto& s : sections) o << ",ms_per_step:" << s;
    o << '\n';
}

void printCsvRow(std::ostream& o, const LapRow& r, const std::vector<std::string>& sections)
{
    o << r.lap << ',' << r.steps << ',' << r.sim_t << ',' << r.wall_s << ',' << r.rss_mb << ',' << r.median_ms << ','
      << r.p95_ms << ',' << r.max_ms << ',' << r.cpu_median_ms << ',' << r.cpu_p95_ms << ',' << r.landmarks << ','
      << r.passive_blocks << ',' << r.p_min_eig << ',' << r.p_asym << ',' << r.passive_min_eig << ',' << r.regions
      << ',' << r.regions_with_content << ',' << r.max_region_points << ',' << r.max_region_sog;
    for (const char* k : kKinds)
    {
        const auto it = r.items.find(k);
        o << ',' << (it == r.items.end() ? 0 : it->second);
    }
    o << ',' << r.fallback_tiles << ',' << r.delayed_points << ',' << r.delayed_scans << ',' << r.dense_mb << ','
      << r.scan_templates << ',' << r.template_points;
    for (const auto& s : sections)
    {
        const auto it = r.profile_ms.find(s);
        o << ',' << (it == r.profile_ms.end() ? 0.0 : it->second);
    }
    o << '\n' << std::flush;
}
}  // namespace

int main(int argc, char** argv)
{
    try
    {
        TCLAP::CmdLine cmd("hymm-soak: DenseSLAM over many laps of a simulated world, per-lap memory and cost",
                           ' ', "0.1");
        TCLAP::ValueArg<std::string> scenario("s", "scenario", "simulator .ini", false,
                                              "configs/sim/ch3_objects.ini", "FILE", cmd);
        TCLAP::ValueArg<std::string> slam_ini("c", "slam", "hymm-slam .ini", false, "configs/ch3_slam.ini", "FILE",
                                              cmd);
        TCLAP::ValueArg<long> laps("l", "laps", "laps of the loop", false, 20, "N", cmd);
        TCLAP::ValueArg<std::string> layers("", "layers", "[DenseSlam] dense_layers", false,
                                            "points,occupancy,particles,sog", "LIST", cmd);
        TCLAP::SwitchArg no_delayed("", "no-delayed", "leave [DelayedDenseStore] as the config has it", cmd);
        TCLAP::MultiArg<std::string> sets("", "set", "Section.key=value (repeatable)", false, "KEY=VALUE", cmd);
        TCLAP::ValueArg<long> seed("", "seed", "noise seed (default: the scenario's)", false, 0, "N", cmd);
        TCLAP::ValueArg<std::string> csv("", "csv", "also write the rows as CSV", false, "", "FILE", cmd);
        TCLAP::SwitchArg profile("", "profile", "CTimeLogger sections per lap (ms per step, in the CSV)", cmd);
        if (const auto code = hymm::core::parseCommandLine(cmd, argc, argv)) return *code;
        if (laps.getValue() < 1) throw std::invalid_argument("--laps must be >= 1");

        auto sc = hymm::sim::Scenario::fromFile(scenario.getValue());
        sc.run.laps = laps.getValue();
        sc.run.duration_s = 0;
        if (seed.isSet()) sc.run.seed = seed.getValue();

        std::string text = readFile(slam_ini.getValue());
        text = setKey(text, "DenseSlam", "dense_layers", layers.getValue());
        if (!no_delayed.getValue()) text = setKey(text, "DelayedDenseStore", "enabled", "true");
        if (profile.getValue())
        {
            text = setKey(text, "DenseSlam", "enable_profiler", "true");
            text = setKey(text, "HybridMetricMap", "enable_profiler", "true");
        }
        for (const auto& s : sets.getValue())
        {
            const auto dot = s.find('.'), eq = s.find('=');
            if (dot == std::string::npos || eq == std::string::npos || eq < dot)
                throw std::invalid_argument("--set '" + s + "': expected Section.key=value");
            text = setKey(text, s.substr(0, dot), trim(s.substr(dot + 1, eq - dot - 1)), trim(s.substr(eq + 1)));
        }
        const auto cfg = hymm::core::StrictConfigFile::fromText(text, slam_ini.getValue() + " (with --set)");
        std::optional<DenseSlam> slam;
        cfg.load([&](const mrpt::config::CConfigFileBase& c) { slam.emplace(DenseSlam::fromConfig(c)); });
        cfg.checkAllSectionsKnown();
        if (!slam->hybridMap()) throw std::invalid_argument("--layers must switch on a dense layer");

        std::cout << "# hymm-soak: " << sc.run.laps << " laps of " << scenario.getValue() << " (seed " << sc.run.seed
                  << "), " << slam_ini.getValue() << ", dense_layers = " << layers.getValue()
                  << ", delayed store " << (slam->delayedStore() ? "on" : "off");
        for (const auto& s : sets.getValue()) std::cout << ", " << s;
        std::cout << "\n\n";
        printHeader(std::cout);
        std::ofstream csv_out;
        if (csv.isSet())
        {
            csv_out.open(csv.getValue());
            if (!csv_out) throw std::runtime_error("cannot write " + csv.getValue());
        }
        std::vector<std::string> sections;

        hymm::sim::Simulator sim(sc);
        if (!sim.follower().path()) throw std::invalid_argument("the scenario has no loop to drive laps of");
        const double lap_length = sim.follower().path()->length();
        hymm::sim::SimFrame f;
        long lap = 0;
        std::vector<double> step_ms, cpu_ms;
        std::map<std::string, double> prof_before;
        std::vector<LapRow> rows;
        const auto finishLap = [&](double sim_t) {
            LapRow r;
            r.lap = lap + 1;
            r.steps = step_ms.size();
            r.sim_t = sim_t;
            for (double ms : step_ms) r.wall_s += ms / 1e3;
            r.rss_mb = static_cast<double>(rssKb()) / 1024.0;
            r.median_ms = percentile(step_ms, 0.5);
            r.p95_ms = percentile(step_ms, 0.95);
            r.max_ms = step_ms.empty() ? 0 : *std::max_element(step_ms.begin(), step_ms.end());
            r.cpu_median_ms = percentile(cpu_ms, 0.5);
            r.cpu_p95_ms = percentile(cpu_ms, 0.95);
            r.landmarks = slam->ekf().numLandmarks();
            covarianceHealth(slam->ekf(), r);
            r.regions = slam->partition()->size();
            const auto* h = slam->hybridMap();
            r.regions_with_content = h->size();
            r.items = h->sizeByKind();
            for (const long id : h->regionIds())
            {
                if (const auto* pl = h->localMap(id)->layer("points"))
                    r.max_region_points = std::max(r.max_region_points, pl->size());
                if (const auto* sl = h->localMap(id)->layer("sog"))
                    r.max_region_sog = std::max(r.max_region_sog, sl->size());
            }
            r.fallback_tiles = h->fallbackTiles();
            if (const auto* st = slam->delayedStore())
            {
                r.delayed_points = st->numStoredPoints();
                r.delayed_scans = st->numStoredScans();
            }
            r.dense_mb = static_cast<double>(h->memoryBytes()) / (1024.0 * 1024.0);
            if (const auto* src = slam->scanLandmarks())
            {
                r.scan_templates = src->map().templates().size();
                for (const auto& [id, tpl] : src->map().templates()) r.template_points += tpl.sog.size();
                for (const auto& [name, n] : src->map().stats().list()) r.scan_counters[name] = n;
            }
            if (profile.getValue())
            {
                const auto now = profileTotals(*slam, *slam);
                for (const auto& [k, v] : now)
                    r.profile_ms[k] = 1e3 * (v - prof_before[k]) / std::max<double>(1.0, static_cast<double>(r.steps));
                prof_before = now;
                if (sections.empty())
                    for (const auto& kv : now) sections.push_back(kv.first);
            }
            printRow(std::cout, r);
            rows.push_back(r);
            if (csv_out.is_open())
            {
                if (r.lap == 1) printCsvHeader(csv_out, sections);
                printCsvRow(csv_out, r, sections);
            }
            step_ms.clear();
            cpu_ms.clear();
        };
        double last_t = 0;
        while (sim.next(f))
        {
            const long this_lap = std::min(sc.run.laps - 1, static_cast<long>(std::floor(sim.follower().progress() / lap_length)));
            if (this_lap > lap)
            {
                finishLap(last_t);
                lap = this_lap;
            }
            mrpt::obs::CSensoryFrame frame;
            if (f.scan) frame.insert(f.scan);
            if (f.detections) frame.insert(f.detections);
            const mrpt::poses::CPosePDFGaussian odo(
                mrpt::poses::CPose2D(f.odometry_mean[0], f.odometry_mean[1], f.odometry_mean[2]),
                mrpt::math::CMatrixDouble33(f.odometry_cov));
            const auto t0 = std::chrono::steady_clock::now();
            const double c0 = threadCpuMs();
            slam->processOdometry(odo);
            slam->processFrame(frame);
            cpu_ms.push_back(threadCpuMs() - c0);
            step_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
            last_t = f.t;
        }
        finishLap(last_t);
        printScanCounters(std::cout, rows);
        // The per-lap sections are in the CSV; no dump of the whole run at exit.
        slam->profiler().clear();
        slam->hybridMap()->profiler().clear();
        return 0;
    }
    catch (const std::exception& e)
    {
        std::cerr << "hymm-soak: " << e.what() << "\n";
        return 1;
    }
}
