// The feature-map outputs of a run: path, landmarks, map figure, frame timing, and the
// run metrics against ground truth.
#include <hymm/app/slam_outputs.h>
#include <hymm/core/output_files.h>
#include <hymm/io/trajectory_io.h>
#include <hymm/sim/ground_truth_io.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/system/filesystem.h>

#include <fstream>
#include <iomanip>
#include <stdexcept>

#include "output_helpers.h"

namespace hymm::app
{
std::vector<eval::EstimatedPose> estimatedPoses(const DenseSlam& slam)
{
    std::vector<eval::EstimatedPose> out;
    out.reserve(slam.path().size());
    for (const auto& s : slam.path()) out.push_back({s.t, s.pose, s.cov});
    return out;
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

void writeEstimatedPath(const DenseSlam& slam, const std::string& file)
{
    io::writeTum(file, eval::stampedPoses(estimatedPoses(slam)));
}

void writeEstimatedLandmarks(const ekf::EkfSlam& ekf, const std::string& file)
{
    std::vector<io::LandmarkRecord> recs;
    for (const auto& e : estimatedLandmarks(ekf))
        recs.push_back({e.id, e.position.x(), e.position.y(), {e.cov(0, 0), e.cov(0, 1), e.cov(1, 1)}});
    io::writeLandmarksCsv(file, recs, "id,x,y,cxx,cxy,cyy");
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
    addScanLandmarksToPlot(slam, p);
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
    if (slam.options().readsPoints(denseslam::PointSourceInput::Scan))
    {
        const auto& st = slam.stats();
        const auto by = landmarksByFeature(slam);
        auto& ej = j.object("extraction");
        ej.set("scans", static_cast<unsigned long>(st.scans));
        ej.set("observations", static_cast<unsigned long>(st.extracted));
        ej.set("reflectors", static_cast<unsigned long>(valueOr0(st.point_features, "laser_reflectors")));
        ej.set("trees", static_cast<unsigned long>(valueOr0(st.point_features, "laser_trees")));
        ej.set("trees_duplicate", static_cast<unsigned long>(valueOr0(st.point_duplicates, "laser_trees")));
        ej.set("landmarks_reflector_only", static_cast<unsigned long>(by.reflector_only));
        ej.set("landmarks_tree_only", static_cast<unsigned long>(by.tree_only));
        ej.set("landmarks_reflector_and_tree", static_cast<unsigned long>(by.both));
    }
    writeScanSourceMetrics(j, slam);
    writeHllMetrics(j, slam);
    eval::writeRunMetrics(j, estimatedPoses(slam), estimatedLandmarks(slam.ekf()),
                          landmarkAssociationFor(slam), gt);
    return j;
}

void writeTiming(const std::vector<FrameTiming>& timing, const std::string& file)
{
    core::AtomicTextFile f(file);
    f << "entry,landmarks,observations,seconds\n" << std::setprecision(9);
    for (const auto& t : timing)
        f << t.entry << ',' << t.landmarks << ',' << t.observations << ',' << t.seconds << '\n';
    f.commit();
}

}  // namespace hymm::app
