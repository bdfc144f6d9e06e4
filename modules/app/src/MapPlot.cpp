#include "hymm/app/MapPlot.h"
#include <hymm/core/output_files.h>

#include <Eigen/Eigenvalues>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace hymm::app
{
namespace
{
struct Frame
{
    double x0, y1, scale;
    int w, h;
    cv::Point px(const Eigen::Vector2d& p) const
    {
        return {static_cast<int>(std::lround((p.x() - x0) * scale)),
                static_cast<int>(std::lround((y1 - p.y()) * scale))};  // y up
    }
};

Frame makeFrame(const MapPlot& plot)
{
    double xmin = std::numeric_limits<double>::max(), ymin = xmin;
    double xmax = std::numeric_limits<double>::lowest(), ymax = xmax;
    auto grow = [&](const Eigen::Vector2d& p) {
        if (!p.allFinite()) return;
        xmin = std::min(xmin, p.x());
        xmax = std::max(xmax, p.x());
        ymin = std::min(ymin, p.y());
        ymax = std::max(ymax, p.y());
    };
    for (const auto& p : plot.estimated_path) grow(p);
    for (const auto& p : plot.true_path) grow(p);
    for (const auto& l : plot.estimated_landmarks) grow(l.mean);
    for (const auto& p : plot.true_landmarks) grow(p);
    for (const auto& p : plot.dense_points)
        if (p.allFinite()) grow(p);
    for (const auto& l : plot.pose_landmarks)
        for (const auto& p : l.points) grow(p);
    if (xmin > xmax) throw std::invalid_argument("map plot: nothing to draw");
    const double margin = 5.0;  // [m]
    xmin -= margin, ymin -= margin, xmax += margin, ymax += margin;
    double scale = plot.pixels_per_metre;
    const double side = std::max(xmax - xmin, ymax - ymin);
    if (side * scale > plot.max_side) scale = plot.max_side / side;
    Frame f{xmin, ymax, scale, static_cast<int>(std::ceil((xmax - xmin) * scale)),
            static_cast<int>(std::ceil((ymax - ymin) * scale))};
    return f;
}

void drawPolyline(cv::Mat& img, const Frame& f, const std::vector<Eigen::Vector2d>& pts,
                  const cv::Scalar& colour, int thickness)
{
    std::vector<cv::Point> px;
    px.reserve(pts.size());
    for (const auto& p : pts)
        if (p.allFinite()) px.push_back(f.px(p));
    if (px.size() >= 2)
        cv::polylines(img, std::vector<std::vector<cv::Point>>{px}, false, colour, thickness,
                      cv::LINE_AA);
}
void drawEllipse(cv::Mat& img, const Frame& f, const Eigen::Vector2d& mean,
                 const Eigen::Matrix2d& cov, double sigma_scale, const cv::Scalar& colour)
{
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(0.5 * (cov + cov.transpose()));
    if (es.info() != Eigen::Success) return;
    const Eigen::Vector2d ev = es.eigenvalues().cwiseMax(0.0);
    const Eigen::Vector2d major = es.eigenvectors().col(1);
    const double ang = -std::atan2(major.y(), major.x()) * 180.0 / M_PI;  // image y down
    const cv::Size axes(
        std::max(1, static_cast<int>(std::lround(sigma_scale * std::sqrt(ev[1]) * f.scale))),
        std::max(1, static_cast<int>(std::lround(sigma_scale * std::sqrt(ev[0]) * f.scale))));
    cv::ellipse(img, f.px(mean), axes, ang, 0, 360, colour, 1, cv::LINE_AA);
}

// Template points (green), the frame's x (red) and y (green) axes, its xy ellipse.
void drawPoseLandmarks(cv::Mat& img, const Frame& f, const MapPlot& plot)
{
    const cv::Scalar green(0, 150, 0), red(0, 0, 220);
    for (const auto& l : plot.pose_landmarks)
    {
        if (!l.pose.allFinite()) continue;
        for (const auto& p : l.points)
            if (p.allFinite()) cv::circle(img, f.px(p), 1, green, cv::FILLED);
        const Eigen::Vector2d o = l.pose.head<2>();
        const Eigen::Vector2d ex(std::cos(l.pose.z()), std::sin(l.pose.z()));
        const Eigen::Vector2d ey(-ex.y(), ex.x());
        cv::line(img, f.px(o), f.px(o + plot.axis_length * ex), red, 1, cv::LINE_AA);
        cv::line(img, f.px(o), f.px(o + plot.axis_length * ey), green, 1, cv::LINE_AA);
        drawEllipse(img, f, o, l.cov.topLeftCorner<2, 2>(), plot.sigma_scale, red);
    }
}
}  // namespace

void writeMapPng(const MapPlot& plot, const std::string& path)
{
    const Frame f = makeFrame(plot);
    cv::Mat img(f.h, f.w, CV_8UC3, cv::Scalar(255, 255, 255));
    const cv::Scalar grey(150, 150, 150), blue(200, 60, 0), red(0, 0, 220);

    for (const auto& p : plot.dense_points)
        if (p.allFinite()) cv::circle(img, f.px(p), 0, cv::Scalar(0, 0, 0), cv::FILLED);
    drawPolyline(img, f, plot.true_path, grey, 2);
    for (const auto& p : plot.true_landmarks)
        cv::drawMarker(img, f.px(p), grey, cv::MARKER_STAR, 9, 1, cv::LINE_AA);
    drawPolyline(img, f, plot.estimated_path, blue, 1);
    for (const auto& l : plot.estimated_landmarks)
    {
        if (!l.mean.allFinite()) continue;
        cv::circle(img, f.px(l.mean), 2, blue, cv::FILLED, cv::LINE_AA);
        drawEllipse(img, f, l.mean, l.cov, plot.sigma_scale, red);
    }
    drawPoseLandmarks(img, f, plot);
    // Scale bar: 10 m.
    const int bar = static_cast<int>(std::lround(10.0 * f.scale));
    cv::line(img, {10, f.h - 10}, {10 + bar, f.h - 10}, cv::Scalar(0, 0, 0), 2);
    cv::putText(img, "10 m", {10, f.h - 16}, cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(0, 0, 0), 1);
    std::vector<uchar> png;
    if (!cv::imencode(".png", img, png)) throw std::runtime_error("cannot encode PNG '" + path + "'");
    core::writeFileAtomically(path, std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
}

}  // namespace hymm::app
