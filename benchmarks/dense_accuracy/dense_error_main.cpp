/**
 * @file dense_error_main.cpp
 * @brief Where the error of the dense points comes from (thesis Sec. 3.6).
 *
 * A point stored in a region keeps its local coordinates; its global position is
 * x = L1 + D l with the CURRENT vertex estimates. Its distance to the true surfaces
 * therefore has two parts: the error of the vertex estimates (the feature map's own)
 * and the error of the local coordinates written at fusion time (vehicle pose relative to
 * the vertices, plus the laser noise). This program runs hymm-slam's pipeline on a
 * simulated rawlog and renders the points layer of every region whose three vertices are
 * real landmarks twice: at the estimated vertices (what the map shows) and at the true
 * positions of the same landmarks (only the local part left). Regions with a virtual
 * vertex have no true vertex and are left out of both.
 *
 *   hymm-dense-error -c slam.ini -r run.rawlog --gt-landmarks L.csv --gt-objects O.txt
 */
#include <hymm/dense/outline_metrics.h>
#include <hymm/denseslam/DenseSlam.h>
#include <hymm/io/RawlogReader.h>
#include <hymm/app/slam_outputs.h>
#include <hymm/eval/LandmarkEvaluator.h>
#include <hymm/core/config_utils.h>
#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/maps/CSimplePointsMap.h>

#include <cmath>
#include <iomanip>
#include <iostream>
#include <map>

namespace
{
using hymm::dense::Polygon;

void print(const char* what, const hymm::dense::OutlineMetrics& m)
{
    std::cout << std::left << std::setw(34) << what << std::right << std::fixed << std::setprecision(3)
              << " points " << std::setw(7) << m.points << "  mean " << m.mean_distance_m << " m  p95 "
              << m.p95_distance_m << " m\n";
}

int run(int argc, char** argv)
{
    TCLAP::CmdLine cmd("hymm-dense-error: landmark-map vs local part of the dense-point error", ' ', "0.1");
    TCLAP::ValueArg<std::string> config("c", "config", "hymm-slam .ini", true, "", "FILE", cmd);
    TCLAP::ValueArg<std::string> rawlog("r", "rawlog", "simulated rawlog", true, "", "FILE", cmd);
    TCLAP::ValueArg<std::string> gtl("", "gt-landmarks", "true landmarks (id,x,y[,radius])", true, "", "FILE", cmd);
    TCLAP::ValueArg<std::string> gto("", "gt-objects", "true object outlines", true, "", "FILE", cmd);
    if (!cmd.parse(argc, argv)) return 0;

    const auto cfg = hymm::core::openConfigFile(config.getValue());
    auto slam = hymm::denseslam::DenseSlam::fromConfig(*cfg);
    if (!slam.options().denseLayer("points")) throw std::invalid_argument("the config must enable the points layer");
    hymm::io::RawlogReader reader(rawlog.getValue());
    hymm::io::RawlogEntry e;
    while (reader.next(e)) slam.processEntry(e);
    slam.refreshRegions();

    const auto gt = hymm::io::loadGroundTruth("", gtl.getValue());
    const auto outlines = hymm::app::loadObjectOutlines(gto.getValue());
    std::vector<Polygon> surfaces = outlines;
    for (const auto& t : hymm::app::trueTrunks(gt.landmarks)) surfaces.push_back(hymm::dense::circlePolygon(t.centre, t.radius));

    // Estimated landmark -> true position (ids when the run used them, else nearest).
    const auto est = hymm::app::estimatedLandmarks(slam.ekf());
    hymm::eval::LandmarkEvaluator::Options lo;
    lo.association = hymm::app::landmarkAssociationFor(slam);
    const auto lr = hymm::eval::LandmarkEvaluator(lo).evaluate(est, gt.landmarks);
    std::map<long, Eigen::Vector2d> truth;
    for (const auto& m : lr.matches)
        truth[est[m.estimate].id] = Eigen::Vector2d(gt.landmarks[m.truth].x, gt.landmarks[m.truth].y);

    const auto& part = *slam.partition();
    const auto& hybrid = *slam.hybridMap();
    mrpt::maps::CSimplePointsMap at_est, at_true;
    size_t used = 0, skipped = 0;
    double vertex_err = 0;
    for (long id : part.regionIds())
    {
        const auto& r = part.region(id);
        const auto* local = hybrid.localMap(id);
        const auto* layer = local ? local->layer(hymm::dense::PointsLayer::kKind) : nullptr;
        if (!layer) continue;
        hymm::ltr::TriangleFrame::Vertices tv;
        bool ok = true;
        for (size_t k = 0; k < 3 && ok; ++k)
        {
            const auto it = truth.find(r.vertex_ids[k]);
            ok = it != truth.end();
            if (ok) tv[k] = it->second;
        }
        if (!ok)
        {
            ++skipped;
            continue;
        }
        ++used;
        for (size_t k = 0; k < 3; ++k) vertex_err += (tv[k] - r.current[k]).norm() / 3;
        const hymm::ltr::TriangleFrame ref(r.reference);
        layer->renderInto(part.referenceToCurrent(id), at_est);
        layer->renderInto(hymm::ltr::AffineRegionMap(ref, hymm::ltr::TriangleFrame(tv)), at_true);
    }
    std::cout << "regions with real vertices " << used << " (with a virtual or unmatched vertex: " << skipped
              << "), mean vertex error " << std::setprecision(3) << (used ? vertex_err / used : NAN) << " m\n";
    print("points at estimated vertices", hymm::dense::evaluateOutlines(hymm::dense::pointsOf(at_est), surfaces));
    print("same points at true vertices", hymm::dense::evaluateOutlines(hymm::dense::pointsOf(at_true), surfaces));
    return 0;
}
}  // namespace

int main(int argc, char** argv)
{
    try
    {
        return run(argc, argv);
    }
    catch (const std::exception& ex)
    {
        std::cerr << "hymm-dense-error: " << ex.what() << "\n";
        return 1;
    }
}
