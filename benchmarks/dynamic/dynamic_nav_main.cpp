// hymm-dynamic-nav: navigation effect of the motion layers (thesis Sec. 6.3) over N
// simulated runs (a Monte Carlo evaluation, not a timing benchmark).
//   hymm-dynamic-nav --scenario configs/sim/ch6_parked_car.ini --slam configs/ch6_parked_car.ini
//                    --runs 20 [--first 1] --work /tmp/nav [--out result.json]
//                    [--variant "name Section.key=value ..."]...
// Every seed is simulated once and its rawlog run through DenseSlam in each variant of
// the pipeline configuration: "off" ([DynamicSlam] enabled = false), "on" (the file as
// it is) and any --variant (the file with those keys overridden). Per run: path RMSE,
// final and largest position error, mean vehicle NEES (3 DOF) against the simulator's
// true path, and the motion hook's counts. Prints median [min, max] per variant, the
// per-seed difference of each variant against "off" and the seeds where it differs.
#include <hymm/app/slam_config.h>
#include <hymm/app/slam_outputs.h>
#include <hymm/core/StrictConfigFile.h>
#include <hymm/core/command_line.h>
#include <hymm/denseslam/DenseSlam.h>
#include <hymm/eval/MetricsJson.h>
#include <hymm/eval/TrajectoryEvaluator.h>
#include <hymm/eval/run_metrics.h>
#include <hymm/io/RawlogReader.h>
#include <hymm/io/trajectory_io.h>
#include <hymm/sim/Scenario.h>
#include <hymm/sim/run_scenario.h>
#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/exceptions.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <stdexcept>

namespace
{
struct Variant
{
    std::string name;
    std::vector<std::array<std::string, 3>> set;  //!< section, key, value
};

/** "name Section.key=value ..." */
Variant parseVariant(const std::string& text)
{
    std::istringstream in(text);
    Variant v;
    if (!(in >> v.name)) throw std::invalid_argument("--variant: empty");
    for (std::string kv; in >> kv;)
    {
        const auto dot = kv.find('.'), eq = kv.find('=');
        if (dot == std::string::npos || eq == std::string::npos || eq < dot)
            throw std::invalid_argument("--variant '" + text + "': expected Section.key=value, got '" + kv + "'");
        v.set.push_back({kv.substr(0, dot), kv.substr(dot + 1, eq - dot - 1), kv.substr(eq + 1)});
    }
    return v;
}

struct Outcome
{
    double rmse = 0, final_error = 0, max_error = 0, nees_mean = 0;
    double flagged = 0, pruned = 0, blocked = 0, dropped = 0;
};

Outcome runVariant(const std::string& slam_text, const Variant& v, const std::string& base)
{
    mrpt::config::CConfigFileMemory cfg(slam_text);
    for (const auto& [s, k, val] : v.set) cfg.write(s, k, val);
    auto slam = hymm::denseslam::DenseSlam::fromConfig(cfg);
    hymm::io::RawlogReader reader(base + ".rawlog");
    hymm::io::RawlogEntry e;
    while (reader.next(e)) slam.processEntry(e);

    hymm::io::GroundTruth gt;
    gt.path = hymm::io::readTum(base + "_gt_path.tum");
    const auto path = hymm::app::estimatedPoses(slam);
    Outcome o;
    hymm::eval::TrajectoryEvaluator::Options to;
    to.association = hymm::eval::TrajectoryEvaluator::Association::Nearest;
    to.time_tolerance = 1e-3;
    const auto traj = hymm::eval::TrajectoryEvaluator(to).evaluate(hymm::eval::stampedPoses(path), gt.path);
    o.rmse = traj.position_rmse;
    o.final_error = traj.errors.empty() ? std::nan("") : traj.errors.back().position();
    for (const auto& err : traj.errors) o.max_error = std::max(o.max_error, err.position());
    double sum = 0;
    size_t n = 0;
    for (double x : hymm::eval::vehicleNeesSeries(path, gt))
        if (std::isfinite(x))
        {
            sum += x;
            ++n;
        }
    o.nees_mean = n ? sum / static_cast<double>(n) : std::nan("");
    if (const auto* h = slam.motionHook())
    {
        o.flagged = static_cast<double>(h->stats().landmarks_flagged);
        o.pruned = static_cast<double>(h->stats().landmarks_pruned);
        o.blocked = static_cast<double>(h->stats().creations_blocked);
        o.dropped = static_cast<double>(h->stats().flagged_dropped);
    }
    return o;
}

/** "median [min, max]" */
std::string spread(std::vector<double> v)
{
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    const double med = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
    std::ostringstream s;
    s << std::fixed << std::setprecision(3) << med << " [" << v.front() << ", " << v.back() << "]";
    return s.str();
}

using Field = double Outcome::*;
const std::vector<std::pair<const char*, Field>> kFields = {
    {"path_rmse_m", &Outcome::rmse},         {"final_error_m", &Outcome::final_error},
    {"max_error_m", &Outcome::max_error},     {"vehicle_nees_mean", &Outcome::nees_mean},
    {"landmarks_flagged", &Outcome::flagged}, {"landmarks_pruned", &Outcome::pruned},
    {"creations_blocked", &Outcome::blocked}, {"flagged_observations_dropped", &Outcome::dropped}};

void report(const std::vector<Variant>& variants, const std::vector<long>& seeds,
            const std::vector<std::vector<Outcome>>& out, hymm::eval::MetricsJson& j)
{
    auto column = [&](size_t vi, Field f) {
        std::vector<double> c;
        for (const auto& o : out[vi]) c.push_back(o.*f);
        return c;
    };
    for (size_t vi = 0; vi < variants.size(); ++vi)
    {
        std::cout << variants[vi].name << ":";
        auto& jv = j.object(variants[vi].name);
        for (const auto& [name, f] : kFields)
        {
            std::cout << "  " << name << " " << spread(column(vi, f));
            jv.set(name, column(vi, f));
        }
        std::cout << "\n";
        if (vi == 0) continue;
        // Per seed against the first variant ("off"): which seeds differ, and by how much.
        std::vector<double> d_rmse, d_final;
        std::ostringstream differ;
        for (size_t s = 0; s < seeds.size(); ++s)
        {
            d_rmse.push_back(out[vi][s].rmse - out[0][s].rmse);
            d_final.push_back(out[vi][s].final_error - out[0][s].final_error);
            if (std::abs(d_rmse.back()) > 1e-6 || std::abs(d_final.back()) > 1e-6)
                differ << " " << seeds[s] << "(" << std::showpos << std::fixed << std::setprecision(3)
                       << d_rmse.back() << std::noshowpos << ")";
        }
        std::cout << "  minus " << variants[0].name << ": path_rmse " << spread(d_rmse) << ", final "
                  << spread(d_final) << "\n  seeds that differ (path_rmse difference, m):"
                  << (differ.str().empty() ? " none" : differ.str()) << "\n";
        jv.set("path_rmse_minus_off_m", d_rmse);
        jv.set("final_error_minus_off_m", d_final);
    }
}
}  // namespace

int main(int argc, char** argv)
{
    try
    {
        TCLAP::CmdLine cmd("hymm-dynamic-nav: path error with and without the motion layers", ' ', "0.1");
        TCLAP::ValueArg<std::string> sc("", "scenario", "simulator scenario .ini", true, "", "FILE", cmd);
        TCLAP::ValueArg<std::string> sl("", "slam", "pipeline .ini", true, "", "FILE", cmd);
        TCLAP::ValueArg<int> runs("", "runs", "number of seeds (first..first+N-1)", false, 20, "N", cmd);
        TCLAP::ValueArg<int> first("", "first", "first seed", false, 1, "SEED", cmd);
        TCLAP::ValueArg<std::string> work("", "work", "folder for the runs", true, "", "DIR", cmd);
        TCLAP::ValueArg<std::string> out("", "out", "JSON result file", false, "", "FILE", cmd);
        TCLAP::MultiArg<std::string> var("", "variant", "\"name Section.key=value ...\"", false, "TEXT", cmd);
        if (const auto code = hymm::core::parseCommandLine(cmd, argc, argv)) return *code;
        if (runs.getValue() < 1) throw std::invalid_argument("--runs must be >= 1");

        hymm::sim::Scenario scenario = hymm::sim::Scenario::fromFile(sc.getValue());
        const hymm::core::StrictConfigFile slam_file(sl.getValue());
        hymm::app::loadSlamConfig(slam_file);  // every error before the first run
        std::ifstream slam_in(sl.getValue());
        const std::string slam_text((std::istreambuf_iterator<char>(slam_in)), std::istreambuf_iterator<char>());
        std::vector<Variant> variants = {{"off", {{"DynamicSlam", "enabled", "false"}}}, {"on", {}}};
        for (const auto& t : var.getValue()) variants.push_back(parseVariant(t));

        std::vector<long> seeds;
        std::vector<std::vector<Outcome>> res(variants.size());
        for (long seed = first.getValue(); seed < first.getValue() + runs.getValue(); ++seed)
        {
            const std::string dir = work.getValue() + "/seed_" + std::to_string(seed);
            std::filesystem::create_directories(dir);
            scenario.run.seed = seed;
            hymm::sim::runScenario(scenario, dir, false);
            seeds.push_back(seed);
            for (size_t vi = 0; vi < variants.size(); ++vi)
                res[vi].push_back(runVariant(slam_text, variants[vi], dir + "/" + scenario.run.name));
            std::cerr << "seed " << seed << ": path_rmse";
            for (size_t vi = 0; vi < variants.size(); ++vi)
                std::cerr << " " << variants[vi].name << " " << res[vi].back().rmse;
            std::cerr << "\n";
        }
        hymm::eval::MetricsJson j;
        j.set("runs", static_cast<unsigned long>(seeds.size()));
        report(variants, seeds, res, j);
        if (!out.getValue().empty()) j.save(out.getValue());
        return 0;
    }
    catch (const std::exception& e)
    {
        std::cerr << "hymm-dynamic-nav: error: " << mrpt::exception_to_str(e) << "\n";
        return 1;
    }
}
