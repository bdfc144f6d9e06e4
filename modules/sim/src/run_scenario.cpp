#include "hymm/sim/run_scenario.h"
#include <hymm/core/output_files.h>

#include <hymm/io/OdometryRawlogWriter.h>
#include <hymm/io/trajectory_io.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "hymm/sim/Simulator.h"
#include "hymm/sim/WorldPlot.h"
#include "hymm/sim/ground_truth_io.h"

namespace hymm::sim
{
namespace
{
hymm::io::StampedPose2D stamped(double t, const Eigen::Vector3d& p)
{
    return {t, p[0], p[1], p[2]};
}

void writeLandmarks(const std::string& path, const World& world)
{
    std::vector<hymm::io::LandmarkRecord> recs;
    for (const auto& lm : world.landmarks())
        recs.push_back({lm.id, lm.position.x(), lm.position.y(), {lm.radius}});
    hymm::io::writeLandmarksCsv(path, recs, "id,x,y,radius");
}

void writeText(const std::string& path, const std::string& text)
{
    hymm::core::writeFileAtomically(path, text);
}
}  // namespace

std::string RunSummary::toString() const
{
    std::ostringstream ss;
    ss << "scenario " << name << ": " << frames << " frames over " << duration_s << " s, "
       << path_length_m << " m driven, " << scans << " scans, " << detections
       << " landmark readings; world: " << landmarks << " landmarks, " << objects << " objects\n";
    for (const auto& f : files) ss << "  wrote " << f << "\n";
    return ss.str();
}

namespace
{
/** What a run records frame by frame for its ground-truth files. */
struct RunRecord
{
    std::vector<hymm::io::StampedPose2D> gt, dr;
    std::vector<double> frame_t, frame_stamps;
};

/** The ground-truth files, the effective config and (with `plot`) the figure of a
 *  finished run; sum.files names the first six, the others are appended. */
void writeRunFiles(RunSummary& sum, const Scenario& scenario, const World& world, const RunRecord& rec,
                   const std::string& base, const WorldPlot* plot)
{
    hymm::io::writeTum(sum.files[1], rec.gt);
    hymm::io::writeTum(sum.files[2], rec.dr);
    writeLandmarks(sum.files[3], world);
    writeObjectOutlines(sum.files[4], world, rec.frame_t, rec.frame_stamps);
    writeText(sum.files[5], "; Effective configuration of the HYMM simulator run '" +
                                scenario.run.name + "' (hymm-simul --config this file)\n" +
                                scenario.toIniText());
    if (scenario.laser.enabled && scenario.laser.intensity)
    {
        sum.files.push_back(base + "_gt_properties.txt");
        writeSurfaceProperties(sum.files.back(), world);
    }
    if (plot)
    {
        sum.files.push_back(base + ".png");
        plot->save(sum.files.back(), world,
                   "HYMM simulator: " + scenario.run.name + " (seed " + std::to_string(scenario.run.seed) + ")");
    }
}
}  // namespace

RunSummary runScenario(const Scenario& scenario, const std::string& out_dir, bool png)
{
    std::error_code ec;
    std::filesystem::create_directories(out_dir, ec);
    if (ec || !std::filesystem::is_directory(out_dir))
        throw std::runtime_error("cannot create output folder '" + out_dir + "': " + ec.message());
    const std::string base = out_dir + "/" + scenario.run.name;

    Simulator sim(scenario);
    RunSummary sum;
    sum.name = scenario.run.name;
    sum.landmarks = sim.world().landmarks().size();
    sum.objects = sim.world().objects().size();
    sum.files = {base + ".rawlog",           base + "_gt_path.tum",    base + "_dr_path.tum",
                 base + "_gt_landmarks.csv", base + "_gt_objects.txt", base + "_config.ini"};

    // Best gzip compression: the samples are committed to the repository.
    hymm::io::OdometryRawlogWriter rawlog(sum.files[0], 9);
    WorldPlot plot(scenario.plot);
    RunRecord rec;
    SimFrame f;
    while (sim.next(f))
    {
        rawlog.writeFrame(f.stamp, mrpt::poses::CPose2D(f.odometry_mean[0], f.odometry_mean[1],
                                                        f.odometry_mean[2]),
                          f.odometry_cov, {f.scan, f.detections});
        const double stamp = mrpt::Clock::toDouble(f.stamp);
        if (!rec.gt.empty())
            sum.path_length_m +=
                std::hypot(f.true_pose[0] - rec.gt.back().x, f.true_pose[1] - rec.gt.back().y);
        rec.gt.push_back(stamped(stamp, f.true_pose));
        rec.dr.push_back(stamped(stamp, f.dr_pose));
        rec.frame_t.push_back(f.t);
        rec.frame_stamps.push_back(stamp);
        sum.scans += f.scan ? 1 : 0;
        sum.detections += f.detections ? f.detections->sensedData.size() : 0;
        if (png) plot.add(f.true_pose, f.scan.get());
    }
    rawlog.close();
    sum.frames = rawlog.frames();
    sum.duration_s = rec.frame_t.empty() ? 0 : rec.frame_t.back();
    writeRunFiles(sum, scenario, sim.world(), rec, base, png ? &plot : nullptr);
    return sum;
}

RunSummary runScenarioFile(const std::string& config_path, const std::string& out_dir,
                           std::optional<long> seed, bool png)
{
    Scenario scenario = Scenario::fromFile(config_path);
    if (seed)
    {
        if (*seed < 0 || *seed > 0xFFFFFFFFL)
            throw std::invalid_argument("--seed " + std::to_string(*seed) +
                                        ": must be in [0, 2^32)");
        scenario.run.seed = *seed;
    }
    return runScenario(scenario, out_dir, png);
}

}  // namespace hymm::sim
