// hymm-slam's outputs of the Scan-SLAM landmarks (landmark_source = scan_landmarks):
// the CSV of their frames, their part of the map figure, summary and metrics.
#include <hymm/app/slam_outputs.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace hymm::app
{
std::vector<ScanLandmarkEstimate> scanLandmarkEstimates(const DenseSlam& slam)
{
    std::vector<ScanLandmarkEstimate> out;
    const auto* src = slam.scanLandmarks();
    if (!src) return out;
    for (const auto& [id, tpl] : src->map().templates())
    {
        if (!slam.ekf().hasLandmark(id)) continue;
        ScanLandmarkEstimate e;
        e.id = id;
        e.pose = slam.ekf().landmarkBlockMean(id).head<3>();
        e.cov = slam.ekf().landmarkBlockCov(id).topLeftCorner<3, 3>();
        for (const auto& p : tpl.sog.points) e.points.push_back(scanslam::transformPoint(e.pose, p));
        out.push_back(std::move(e));
    }
    return out;
}

void writeScanLandmarks(const DenseSlam& slam, const std::string& file)
{
    std::ofstream f(file);
    if (!f) throw std::runtime_error("cannot write '" + file + "'");
    f << "id,x,y,phi,cxx,cxy,cxphi,cyy,cyphi,cphiphi,points\n" << std::setprecision(10);
    for (const auto& e : scanLandmarkEstimates(slam))
    {
        const auto& c = e.cov;
        f << e.id << ',' << e.pose.x() << ',' << e.pose.y() << ',' << e.pose.z() << ',' << c(0, 0)
          << ',' << c(0, 1) << ',' << c(0, 2) << ',' << c(1, 1) << ',' << c(1, 2) << ',' << c(2, 2)
          << ',' << e.points.size() << '\n';
    }
    if (!f) throw std::runtime_error("error writing '" + file + "'");
}

void addScanLandmarksToPlot(const DenseSlam& slam, MapPlot& plot)
{
    for (auto& e : scanLandmarkEstimates(slam))
        plot.pose_landmarks.push_back({e.pose, e.cov, std::move(e.points)});
}

void writeScanSourceMetrics(eval::MetricsJson& j, const DenseSlam& slam)
{
    if (const auto b = slam.turnBias())  // [DenseSlam] turn_bias_state, with or without scan sources
    {
        auto& t = j.object("turn_bias_state");
        t.set("deg_per_m", b->first * 180 / M_PI);
        t.set("std_deg_per_m", b->second * 180 / M_PI);
    }
    if (slam.scanSourceCounters().empty()) return;  // no scan source, no scan odometry
    auto& o = j.object("scan_sources");
    for (const auto& [k, n] : slam.scanSourceCounters()) o.set(k, static_cast<unsigned long>(n));
    o.set("scan_landmarks.templates", static_cast<unsigned long>(scanLandmarkEstimates(slam).size()));
    if (const auto* odo = slam.scanOdometry(); odo && odo->options().wheel_turn_bias)
    {
        o.set("scan_odometry.wheel_turn_bias_deg_per_m", odo->wheelTurnBias() * 180 / M_PI);
        o.set("scan_odometry.wheel_turn_bias_std_deg_per_m", odo->wheelTurnBiasStd() * 180 / M_PI);
    }
}

void writeScanSourceSummary(std::ostream& f, const DenseSlam& slam)
{
    if (const auto b = slam.turnBias())
    {
        std::ostringstream line;  // its own precision, f's unchanged
        line << std::setprecision(4) << "turn bias (state)    " << b->first * 180 / M_PI << " deg/m (std "
             << b->second * 180 / M_PI << ")\n";
        f << line.str();
    }
    if (slam.scanSourceCounters().empty()) return;
    f << "scan sources        ";
    for (const auto& [k, n] : slam.scanSourceCounters()) f << ' ' << k << '=' << n;
    f << "\n";
    // Where the run came back to a landmark it had left: the loop closures, local or wide.
    if (const auto* src = slam.scanLandmarks())
    {
        const auto& map = src->map();
        const auto& rv = map.revisits();
        std::ostringstream line;  // its own precision, f's unchanged
        line << std::fixed << std::setprecision(1) << "scan revisits        " << rv.size() << " (updates after "
             << map.options().revisit_gap_s << " s or more without one)";
        const size_t shown = std::min<size_t>(rv.size(), 8);
        for (size_t k = 0; k < shown; ++k)
            line << (k ? "; " : ": ") << "t+" << rv[k].t << " s landmark " << rv[k].id << ", unseen " << rv[k].unseen_s
                 << " s, " << (rv[k].wide ? "wide" : "local");
        if (shown < rv.size()) line << "; ...";
        f << line.str() << "\n";
    }
    // The heading the wheels lose per metre, as estimated at the end of the run.
    if (const auto* odo = slam.scanOdometry(); odo && odo->options().wheel_turn_bias)
    {
        std::ostringstream line;  // its own precision, f's unchanged
        line << std::setprecision(4) << "wheel turn bias      " << odo->wheelTurnBias() * 180 / M_PI << " deg/m (std "
             << odo->wheelTurnBiasStd() * 180 / M_PI << ")\n";
        f << line.str();
    }
}

}  // namespace hymm::app
