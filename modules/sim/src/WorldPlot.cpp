#include "hymm/sim/WorldPlot.h"
#include <hymm/core/output_files.h>

#include <hymm/core/config_utils.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>

#include <algorithm>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "config_text.h"

namespace hymm::sim
{
namespace
{
constexpr int kMaxSidePx = 6000;   // the resolution is coarsened beyond this
constexpr int kHeaderPx = 150;     // band above the map for the title and legend
constexpr int kMinWidthPx = 560;   // wide enough for the title and legend
constexpr double kScaleBarM = 10;  // length of the scale bar [m]
const cv::Scalar kObjectFill(215, 215, 215), kObjectEdge(70, 70, 70);
const cv::Scalar kChangingEdge(0, 140, 255);  // orange: moving, added or removed objects
const cv::Scalar kLandmark(0, 130, 0), kPath(200, 60, 0), kReturn(0, 0, 230);

/** World-to-pixel mapping over a bounding box. */
struct Canvas
{
    double xmin, ymax, res;
    cv::Point px(const Vec2& p) const
    {
        return {static_cast<int>(std::lround((p.x() - xmin) / res)),
                kHeaderPx + static_cast<int>(std::lround((ymax - p.y()) / res))};
    }
    std::vector<cv::Point> px(const Polygon& poly) const
    {
        std::vector<cv::Point> out;
        for (const auto& p : poly) out.push_back(px(p));
        return out;
    }
};
}  // namespace

hymm::core::OptionTable WorldPlot::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.real("resolution_m", resolution_m, "m", above(0, 100), "metres per pixel (coarsened for huge worlds)");
    t.integer("scan_stride", scan_stride, "", 1, 1000000, "plot the returns of every n-th scan");
    t.real("margin_m", margin_m, "m", between(0, 1e4), "white border around everything drawn");
    return t;
}

void WorldPlot::Options::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                            const std::string& s)
{
    table().load(cfg, s);
}

void WorldPlot::Options::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                          const std::string& s) const
{
    auto copy = *this;
    copy.table().save(cfg, s);
}

WorldPlot::WorldPlot(const Options& options) : options_(options) {}

void WorldPlot::add(const Eigen::Vector3d& pose, const mrpt::obs::CObservation2DRangeScan* scan)
{
    path_.emplace_back(pose[0], pose[1]);
    if (!scan || scans_++ % static_cast<size_t>(options_.scan_stride) != 0) return;
    const mrpt::poses::CPose2D sensor =
        mrpt::poses::CPose2D(pose[0], pose[1], pose[2]) + mrpt::poses::CPose2D(scan->sensorPose);
    for (size_t i = 0; i < scan->getScanSize(); ++i)
    {
        if (!scan->getScanRangeValidity(i)) continue;
        const double r = scan->getScanRange(i), a = scan->getScanAngle(i);
        const auto g = sensor + mrpt::poses::CPose2D(r * std::cos(a), r * std::sin(a), 0);
        returns_.emplace_back(g.x(), g.y());
    }
}

namespace
{
// Title, legend and scale bar in the header band of `img` (map at `res` m/pixel).
void drawHeader(cv::Mat& img, const std::string& title, double res)
{
    cv::line(img, {0, kHeaderPx - 1}, {img.cols, kHeaderPx - 1}, {180, 180, 180}, 1);
    const double font = 0.6;
    cv::putText(img, title, {10, 25}, cv::FONT_HERSHEY_SIMPLEX, font, {0, 0, 0}, 1, cv::LINE_AA);
    int y = 50;
    for (const auto& [text, color] :
         std::vector<std::pair<std::string, cv::Scalar>>{{"true path", kPath},
                                                         {"landmarks", kLandmark},
                                                         {"objects", kObjectEdge},
                                                         {"moving/changing objects", kChangingEdge},
                                                         {"laser returns (true pose)", kReturn}})
    {
        cv::rectangle(img, {10, y - 10}, {22, y + 2}, color, cv::FILLED);
        cv::putText(img, text, {30, y}, cv::FONT_HERSHEY_SIMPLEX, font * 0.8, {0, 0, 0}, 1,
                    cv::LINE_AA);
        y += 20;
    }
    const int bar = static_cast<int>(kScaleBarM / res), y0 = kHeaderPx - 12;
    const int x0 = img.cols - 10 - bar;
    cv::line(img, {x0, y0}, {x0 + bar, y0}, {0, 0, 0}, 2);
    cv::putText(img, "10 m", {x0, y0 - 6}, cv::FONT_HERSHEY_SIMPLEX, font * 0.8, {0, 0, 0}, 1,
                cv::LINE_AA);
}
}  // namespace

void WorldPlot::save(const std::string& png_path, const World& world,
                     const std::string& title) const
{
    // Bounding box of everything drawn.
    double xmin = std::numeric_limits<double>::infinity(), ymin = xmin, xmax = -xmin, ymax = -xmin;
    const auto grow = [&](const Vec2& p, double r)
    {
        xmin = std::min(xmin, p.x() - r), xmax = std::max(xmax, p.x() + r);
        ymin = std::min(ymin, p.y() - r), ymax = std::max(ymax, p.y() + r);
    };
    for (const auto& p : path_) grow(p, 0);
    for (const auto& lm : world.landmarks()) grow(lm.position, lm.radius);
    for (const auto& obj : world.objects())
        for (const auto& k : obj.trajectory)
            for (const auto& p : obj.outlineAt(k.t)) grow(p, 0);
    if (!(xmax >= xmin)) grow(Vec2::Zero(), 1);
    const double m = options_.margin_m;
    const double res = std::max(options_.resolution_m,
                                std::max(xmax - xmin + 2 * m, ymax - ymin + 2 * m) / kMaxSidePx);
    const Canvas cv_map{xmin - m, ymax + m, res};
    cv::Mat img(kHeaderPx + static_cast<int>(std::ceil((ymax - ymin + 2 * m) / res)) + 1,
                std::max(kMinWidthPx, static_cast<int>(std::ceil((xmax - xmin + 2 * m) / res)) + 1),
                CV_8UC3, cv::Scalar(255, 255, 255));

    for (const auto& obj : world.objects())
    {
        if (obj.isStatic())
        {
            const auto pts = cv_map.px(obj.outlineAt(0));
            cv::fillPoly(img, std::vector<std::vector<cv::Point>>{pts}, kObjectFill);
            cv::polylines(img, pts, true, kObjectEdge, 2, cv::LINE_AA);
        }
        else  // every key pose of a moving object, or the one pose of an added/removed one
            for (const auto& k : obj.trajectory)
                cv::polylines(img, cv_map.px(obj.outlineAt(k.t)), true, kChangingEdge, 2,
                              cv::LINE_AA);
    }
    for (const auto& p : returns_) cv::circle(img, cv_map.px(p), 1, kReturn, cv::FILLED);
    if (path_.size() > 1) cv::polylines(img, cv_map.px(path_), false, kPath, 2, cv::LINE_AA);
    for (const auto& lm : world.landmarks())
        cv::circle(img, cv_map.px(lm.position), std::max(3, static_cast<int>(lm.radius / res)),
                   kLandmark, cv::FILLED, cv::LINE_AA);

    drawHeader(img, title, res);

    std::vector<uchar> png;
    if (!cv::imencode(".png", img, png))
        throw std::runtime_error("cannot encode image '" + png_path + "'");
    core::writeFileAtomically(png_path,
                              std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
}

}  // namespace hymm::sim
