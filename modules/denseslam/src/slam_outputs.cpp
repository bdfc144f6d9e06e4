#include "hymm/denseslam/slam_outputs.h"

#include <hymm/core/trajectory_io.h>
#include <hymm/dense/map_images.h>
#include <hymm/sim/ground_truth_io.h>
#include <hymm/eval/LandmarkEvaluator.h>
#include <hymm/eval/TrajectoryEvaluator.h>
#include <hymm/eval/metrics_report.h>
#include <hymm/eval/nees.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/filesystem.h>

#include <cmath>
#include <fstream>
#include <iomanip>
#include <stdexcept>

namespace hymm::denseslam
{
namespace
{
bool endsWith(const std::string& s, const std::string& suffix)
{
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::vector<core::StampedPose2D> estimatedPath(const DenseSlam& slam)
{
    std::vector<core::StampedPose2D> out;
    out.reserve(slam.path().size());
    for (const auto& s : slam.path()) out.push_back({s.t, s.pose[0], s.pose[1], s.pose[2]});
    return out;
}

template <class T>
void writeSerialized(const T& obj, const std::string& file)
{
    mrpt::io::CFileGZOutputStream f;
    if (!f.open(file)) throw std::runtime_error("cannot write '" + file + "'");
    mrpt::serialization::archiveFrom(f) << obj;
}

// Accuracy against every true surface (`surfaces`: object outlines and trunk circles),
// coverage of the object outlines alone (trunks are landmarks, not dense content to cover).
void setOutlineMetrics(eval::MetricsJson& j, const std::vector<Eigen::Vector2d>& points,
                       const std::vector<dense::Polygon>& outlines,
                       const std::vector<dense::Polygon>& surfaces)
{
    const dense::OutlineMetrics acc = dense::evaluateOutlines(points, surfaces);
    const dense::OutlineMetrics cov = dense::evaluateOutlines(points, outlines);
    j.set("points", static_cast<unsigned long>(acc.points));
    j.set("mean_distance_m", acc.mean_distance_m);
    j.set("p95_distance_m", acc.p95_distance_m);
    j.set("coverage", cov.coverage);
    j.set("outline_samples", static_cast<unsigned long>(cov.outline_samples));
}

// A trunk of radius r as a closed polygon (a single point when r = 0); 32 sides keep
// the polygon within r (1 - cos(pi/32)) = 0.5% of r of the circle.
dense::Polygon circleOutline(const Eigen::Vector2d& c, double r)
{
    if (!(r > 0)) return {c, c};
    constexpr int kSides = 32;
    dense::Polygon p;
    for (int k = 0; k < kSides; ++k)
    {
        const double a = 2 * M_PI * k / kSides;
        p.emplace_back(c + r * Eigen::Vector2d(std::cos(a), std::sin(a)));
    }
    return p;
}

// Occupancy layer rendered at its own cell size.
void renderOccupancy(const DenseSlam& slam, mrpt::maps::COccupancyGridMap2D& grid)
{
    slam.hybridMap()->renderOccupancy(*slam.partition(),
                                      slam.hybridMap()->options().occupancy.cell_size_m, grid);
}

constexpr double kPointsPngResolution = 0.1;  //!< [m/pixel]
constexpr double kOccupiedProbability = 0.8;  //!< occupied cells for the outline metrics
}  // namespace

std::vector<dense::Polygon> loadObjectOutlines(const std::string& file)
{
    if (!mrpt::system::fileExists(file))
        throw std::runtime_error("ground-truth object file not found: '" + file + "'");
    std::vector<dense::Polygon> out;
    for (const auto& r : sim::readObjectOutlines(file))
        out.emplace_back(r.outline.begin(), r.outline.end());
    if (out.empty()) throw std::runtime_error("ground-truth object file '" + file + "' holds no outline");
    return out;
}

void writeDenseOutputs(const DenseSlam& slam, const std::string& dir, bool png)
{
    const std::string d = dir.empty() || dir.back() == '/' ? dir : dir + "/";
    const auto* partition = slam.partition();
    const auto* hybrid = slam.hybridMap();
    if (partition) partition->saveToFile(d + "regions.txt");
    if (hybrid && hybrid->options().enable_points)
    {
        mrpt::maps::CSimplePointsMap pts;
        hybrid->renderPoints(*partition, pts);
        writeSerialized(pts, d + "points.bin");
        if (!pts.save2D_to_text_file(d + "points.txt"))
            throw std::runtime_error("cannot write '" + d + "points.txt'");
        if (png) dense::savePointsPng(pts, d + "points.png", kPointsPngResolution, partition);
    }
    if (hybrid && hybrid->options().enable_occupancy)
    {
        mrpt::maps::COccupancyGridMap2D grid;
        renderOccupancy(slam, grid);
        writeSerialized(grid, d + "occupancy.gridmap");
        if (png) dense::saveOccupancyPng(grid, d + "occupancy.png", partition);
    }
    if (const auto* classic = slam.classicGrid())
    {
        mrpt::maps::COccupancyGridMap2D grid;
        classic->toOccupancyGridMap(grid);
        writeSerialized(grid, d + "classic_grid.gridmap");
        if (png) dense::saveOccupancyPng(grid, d + "classic_grid.png");
    }
}

std::vector<TrueTrunk> trueTrunks(const std::vector<core::LandmarkRecord>& landmarks)
{
    std::vector<TrueTrunk> out;
    out.reserve(landmarks.size());
    for (const auto& l : landmarks)
        out.push_back({Eigen::Vector2d(l.x, l.y), l.extra.empty() ? 0.0 : l.extra[0]});
    return out;
}

void writeDenseMetrics(eval::MetricsJson& j, const DenseSlam& slam,
                       const std::vector<dense::Polygon>& outlines,
                       const std::vector<TrueTrunk>& true_landmarks)
{
    if (!slam.partition() && !slam.classicGrid()) return;
    auto& dj = j.object("dense");
    const auto& st = slam.stats();
    if (const auto* partition = slam.partition())
    {
        dj.set("regions", static_cast<unsigned long>(partition->size()));
        dj.set("regions_created", static_cast<unsigned long>(st.regions_created));
        dj.set("regions_removed", static_cast<unsigned long>(st.regions_removed));
        dj.set("virtual_landmarks", static_cast<unsigned long>(slam.virtualLandmarkIds().size()));
        dj.set("returns_stored", static_cast<unsigned long>(st.returns_stored));
        dj.set("returns_outside", static_cast<unsigned long>(st.returns_outside));
        dj.set("memory_bytes", static_cast<unsigned long>(slam.hybridMap()->memoryBytes()));
    }
    if (outlines.empty()) return;
    std::vector<dense::Polygon> surfaces = outlines;
    for (const auto& t : true_landmarks) surfaces.push_back(circleOutline(t.centre, t.radius));
    const auto* hybrid = slam.hybridMap();
    if (hybrid && hybrid->options().enable_points)
    {
        mrpt::maps::CSimplePointsMap pts;
        hybrid->renderPoints(*slam.partition(), pts);
        setOutlineMetrics(dj.object("points"), dense::pointsOf(pts), outlines, surfaces);
    }
    if (hybrid && hybrid->options().enable_occupancy)
    {
        mrpt::maps::COccupancyGridMap2D grid;
        renderOccupancy(slam, grid);
        setOutlineMetrics(dj.object("occupancy"), dense::occupiedCellCentres(grid, kOccupiedProbability),
                          outlines, surfaces);
    }
    if (const auto* classic = slam.classicGrid())
    {
        mrpt::maps::COccupancyGridMap2D grid;
        classic->toOccupancyGridMap(grid);
        setOutlineMetrics(dj.object("classic_grid"),
                          dense::occupiedCellCentres(grid, kOccupiedProbability), outlines,
                          surfaces);
    }
}

std::vector<eval::LandmarkEstimate> estimatedLandmarks(const ekf::EkfSlam& ekf)
{
    std::vector<eval::LandmarkEstimate> out;
    for (long id : ekf.landmarkIds())
    {
        if (ekf.landmarkBlock(id).dim != 2) continue;
        eval::LandmarkEstimate e;
        e.id = id;
        e.position = ekf.landmarkMean(id);
        e.cov = ekf.landmarkCov(id);
        e.has_cov = true;
        out.push_back(e);
    }
    return out;
}
eval::LandmarkEvaluator::Association landmarkAssociationFor(const DenseSlam& slam)
{
    return slam.stats().observations_with_id > 0 ? eval::LandmarkEvaluator::Association::Id
                                                  : eval::LandmarkEvaluator::Association::Nearest;
}

std::vector<double> vehicleNeesSeries(const DenseSlam& slam, const GroundTruth& gt,
                                      double time_tolerance)
{
    const auto& path = slam.path();
    std::vector<double> out(path.size(), std::nan(""));
    if (gt.path.empty()) return out;
    eval::TrajectoryEvaluator::Options to;
    to.association = gt.path_has_timestamps ? eval::TrajectoryEvaluator::Association::Nearest
                                            : eval::TrajectoryEvaluator::Association::Index;
    to.time_tolerance = time_tolerance;
    const auto traj = eval::TrajectoryEvaluator(to).evaluate(estimatedPath(slam), gt.path);
    // Errors come in the order of the estimates; walk both sequences together.
    size_t i = 0;
    for (const auto& e : traj.errors)
    {
        while (i < path.size() && path[i].t != e.t) ++i;
        if (i == path.size()) break;
        const auto v = eval::nees(Eigen::Vector3d(e.dx, e.dy, e.dphi), path[i].cov);
        if (v.ok()) out[i] = v.value;
        ++i;
    }
    return out;
}

GroundTruth loadGroundTruth(const std::string& path_file, const std::string& landmarks_file)
{
    GroundTruth gt;
    if (!path_file.empty())
    {
        if (!mrpt::system::fileExists(path_file))
            throw std::runtime_error("ground-truth path file not found: '" + path_file + "'");
        if (endsWith(path_file, "_ground_truth_robot_path.txt"))
        {
            gt.path = eval::readSimulLandmarksPath(path_file);
            gt.path_has_timestamps = false;
        }
        else
        {
            gt.path = core::readTum(path_file);
        }
    }
    if (!landmarks_file.empty())
    {
        if (!mrpt::system::fileExists(landmarks_file))
            throw std::runtime_error("ground-truth landmark file not found: '" + landmarks_file + "'");
        gt.landmarks = endsWith(landmarks_file, "_ground_truth.txt")
                           ? eval::readSimulLandmarksLandmarks(landmarks_file)
                           : core::readLandmarksCsv(landmarks_file);
    }
    return gt;
}

void writeEstimatedPath(const DenseSlam& slam, const std::string& file)
{
    core::writeTum(file, estimatedPath(slam));
}

void writeEstimatedLandmarks(const ekf::EkfSlam& ekf, const std::string& file)
{
    std::vector<core::LandmarkRecord> recs;
    for (const auto& e : estimatedLandmarks(ekf))
        recs.push_back({e.id, e.position.x(), e.position.y(), {e.cov(0, 0), e.cov(0, 1), e.cov(1, 1)}});
    core::writeLandmarksCsv(file, recs, "id,x,y,cxx,cxy,cyy");
}

MapPlot makeMapPlot(const DenseSlam& slam, const GroundTruth* gt)
{
    MapPlot p;
    for (const auto& s : slam.path()) p.estimated_path.emplace_back(s.pose[0], s.pose[1]);
    for (const auto& e : estimatedLandmarks(slam.ekf())) p.estimated_landmarks.push_back({e.position, e.cov});
    if (const auto* hybrid = slam.hybridMap(); hybrid && hybrid->options().enable_points)
    {
        mrpt::maps::CSimplePointsMap pts;
        hybrid->renderPoints(*slam.partition(), pts);
        p.dense_points = dense::pointsOf(pts);
    }
    if (gt)
    {
        for (const auto& s : gt->path) p.true_path.emplace_back(s.x, s.y);
        for (const auto& l : gt->landmarks) p.true_landmarks.emplace_back(l.x, l.y);
    }
    return p;
}

eval::MetricsJson computeMetrics(const DenseSlam& slam, const GroundTruth& gt, double run_seconds)
{
    eval::MetricsJson j;
    j.set("run_seconds", run_seconds);
    j.set("steps", static_cast<unsigned long>(slam.path().size()));
    j.set("landmarks_estimated", static_cast<unsigned long>(slam.ekf().numLandmarks()));

    if (!gt.path.empty())
    {
        eval::TrajectoryEvaluator::Options to;
        to.association = gt.path_has_timestamps ? eval::TrajectoryEvaluator::Association::Interpolate
                                                : eval::TrajectoryEvaluator::Association::Index;
        const auto traj = eval::TrajectoryEvaluator(to).evaluate(estimatedPath(slam), gt.path);
        eval::writeTrajectoryMetrics(j.object("path"), traj);

        // Vehicle NEES per matched step (3 DOF), against the single-run 95% band.
        const std::vector<double> nees_series = vehicleNeesSeries(slam, gt);
        const auto band = eval::averageNeesBounds(3, 1, 0.95);
        double sum = 0;
        size_t n = 0;
        for (double v : nees_series)
            if (std::isfinite(v)) sum += v, ++n;
        auto& nj = j.object("vehicle_nees");
        nj.set("mean", n ? sum / n : std::nan(""));
        nj.set("steps", static_cast<unsigned long>(n));
        nj.set("band_lower", band.lower);
        nj.set("band_upper", band.upper);
        nj.set("fraction_inside_band", eval::fractionInsideBounds(nees_series, band));
    }
    if (!gt.landmarks.empty())
    {
        eval::LandmarkEvaluator::Options lo;
        lo.association = landmarkAssociationFor(slam);
        const auto lr = eval::LandmarkEvaluator(lo).evaluate(estimatedLandmarks(slam.ekf()), gt.landmarks);
        eval::writeLandmarkMetrics(j.object("landmarks"), lr);
        std::vector<double> lm_nees;
        for (const auto& m : lr.matches)
            if (m.has_nees && m.nees.ok()) lm_nees.push_back(m.nees.value);
        const auto band = eval::averageNeesBounds(2, 1, 0.95);
        auto& lj = j.object("landmark_nees");
        lj.set("band_lower", band.lower);
        lj.set("band_upper", band.upper);
        lj.set("fraction_inside_band", eval::fractionInsideBounds(lm_nees, band));
    }
    return j;
}

eval::MetricsJson evaluateResultFiles(const std::string& path_tum, const std::string& landmarks_csv,
                                      const GroundTruth& gt)
{
    eval::MetricsJson j;
    if (!path_tum.empty() && !gt.path.empty())
    {
        eval::TrajectoryEvaluator::Options to;
        to.association = gt.path_has_timestamps ? eval::TrajectoryEvaluator::Association::Interpolate
                                                : eval::TrajectoryEvaluator::Association::Index;
        const auto traj = eval::TrajectoryEvaluator(to).evaluate(core::readTum(path_tum), gt.path);
        eval::writeTrajectoryMetrics(j.object("path"), traj);
    }
    if (!landmarks_csv.empty() && !gt.landmarks.empty())
    {
        const auto recs = core::readLandmarksCsv(landmarks_csv);
        const bool has_cov = !recs.empty() && recs.front().extra.size() >= 3;
        const auto est = eval::landmarkEstimatesFromRecords(recs, has_cov ? 0 : -1);
        const auto lr = eval::LandmarkEvaluator(eval::LandmarkEvaluator::Options{}).evaluate(est, gt.landmarks);
        eval::writeLandmarkMetrics(j.object("landmarks"), lr);
    }
    return j;
}

void writeTiming(const std::vector<FrameTiming>& timing, const std::string& file)
{
    std::ofstream f(file);
    if (!f) throw std::runtime_error("cannot write '" + file + "'");
    f << "entry,landmarks,observations,seconds\n" << std::setprecision(9);
    for (const auto& t : timing)
        f << t.entry << ',' << t.landmarks << ',' << t.observations << ',' << t.seconds << '\n';
    if (!f) throw std::runtime_error("error writing '" + file + "'");
}

void writeSummary(const DenseSlam& slam, double run_seconds, size_t entries, const std::string& file)
{
    std::ofstream f(file);
    if (!f) throw std::runtime_error("cannot write '" + file + "'");
    const auto& s = slam.stats();
    const auto pose = slam.ekf().vehiclePose();
    f << std::fixed << std::setprecision(3) << "rawlog entries       " << entries << "\n"
      << "predictions          " << s.predictions << "\n"
      << "sensory frames       " << s.frames << "\n"
      << "observations         " << s.observations << " (associated " << s.associated
      << ", created " << s.created << ", gate rejects " << s.rejected_gate << ", ambiguous "
      << s.ambiguous << ", numeric rejects " << s.rejected_numeric << ")\n"
      << "skipped readings     " << s.skipped_invalid << "\n"
      << "laser scans          " << s.scans << " (landmarks extracted " << s.extracted << ")\n"
      << "landmarks in map     " << slam.ekf().numLandmarks() << "\n"
      << "final pose           " << pose[0] << " " << pose[1] << " " << pose[2] << "\n"
      << "run time [s]         " << run_seconds << "\n";
    if (const auto* p = slam.partition())
        f << "regions (LTR)        " << p->size() << " (created " << s.regions_created << ", removed "
          << s.regions_removed << ", partition updates " << s.partition_updates << ")\n"
          << "dense scans          " << s.dense_scans << " (returns stored " << s.returns_stored
          << ", outside regions " << s.returns_outside << ")\n"
          << "virtual landmarks    " << slam.virtualLandmarkIds().size() << " (created "
          << s.virtual_landmarks << ", apexes rejected " << s.virtual_rejected << ")\n";
    if (slam.classicGrid()) f << "classic grid         on\n";
    if (!f) throw std::runtime_error("error writing '" + file + "'");
}

}  // namespace hymm::denseslam
