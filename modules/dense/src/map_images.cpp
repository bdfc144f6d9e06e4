#include "hymm/dense/map_images.h"
#include <hymm/core/output_files.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

namespace hymm::dense
{
namespace
{
// Guard against a wrong resolution producing a multi-gigabyte image.
constexpr long kMaxPixels = 100'000'000;

/** Metric -> pixel transform of an image whose row 0 holds y = y_max. */
struct PixelFrame
{
    double x_min, y_max, res;
    cv::Point px(const Eigen::Vector2d& p) const
    {
        return {static_cast<int>(std::floor((p.x() - x_min) / res)),
                static_cast<int>(std::floor((y_max - p.y()) / res))};
    }
};

void drawTriangles(cv::Mat& img, const PixelFrame& f, const hymm::ltr::RegionPartition& part)
{
    const cv::Scalar red(0, 0, 255);
    for (const long id : part.regionIds())
    {
        const auto& v = part.region(id).current;
        for (size_t k = 0; k < 3; ++k) cv::line(img, f.px(v[k]), f.px(v[(k + 1) % 3]), red, 1, cv::LINE_AA);
    }
}

void write(const std::string& path, const cv::Mat& img)
{
    // Encoded in memory (the bytes cv::imwrite would write) so that the file write is
    // checked: imwrite does not report a full disk.
    std::vector<uchar> png;
    bool ok = false;
    try
    {
        ok = cv::imencode(".png", img, png);
    }
    catch (const cv::Exception& e)
    {
        throw std::runtime_error("cannot encode PNG '" + path + "': " + e.what());
    }
    if (!ok) throw std::runtime_error("cannot encode PNG '" + path + "'");
    hymm::core::writeFileAtomically(
        path, std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
}

void checkSize(long w, long h, const std::string& path)
{
    if (w <= 0 || h <= 0 || w * h > kMaxPixels)
        throw std::invalid_argument(
            "PNG '" + path + "' would be " + std::to_string(w) + "x" + std::to_string(h) + " pixels");
}

/** Bounding box of metric content, growing over the given points. */
struct Box
{
    Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector2d hi = -lo;
    void add(const Eigen::Vector2d& p)
    {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    void add(const hymm::ltr::RegionPartition& part)
    {
        for (const long id : part.regionIds())
            for (const auto& v : part.region(id).current) add(v);
    }
};

/** White image covering `box` (origin if empty) plus `margin_m`, and its pixel frame. */
cv::Mat whiteCanvas(Box box, double resolution_m, double margin_m, const std::string& path,
                    PixelFrame& f)
{
    if (!(resolution_m > 0))
        throw std::invalid_argument("PNG '" + path + "': resolution must be > 0");
    if (!(box.lo.x() <= box.hi.x())) box.lo = box.hi = Eigen::Vector2d::Zero();
    box.lo -= Eigen::Vector2d::Constant(margin_m);
    box.hi += Eigen::Vector2d::Constant(margin_m);
    const long w = static_cast<long>(std::ceil((box.hi.x() - box.lo.x()) / resolution_m));
    const long h = static_cast<long>(std::ceil((box.hi.y() - box.lo.y()) / resolution_m));
    checkSize(w, h, path);
    f = PixelFrame{box.lo.x(), box.hi.y(), resolution_m};
    return cv::Mat(static_cast<int>(h), static_cast<int>(w), CV_8UC3, cv::Scalar(255, 255, 255));
}
}  // namespace

void saveOccupancyPng(
    const mrpt::maps::COccupancyGridMap2D& grid, const std::string& path,
    const hymm::ltr::RegionPartition* triangles)
{
    const int w = static_cast<int>(grid.getSizeX()), h = static_cast<int>(grid.getSizeY());
    checkSize(w, h, path);
    cv::Mat img(h, w, CV_8UC3);
    for (int cy = 0; cy < h; ++cy)
        for (int cx = 0; cx < w; ++cx)
        {
            const auto g = static_cast<unsigned char>(std::lround(255.0 * (1.0 - grid.getCell(cx, cy))));
            img.at<cv::Vec3b>(h - 1 - cy, cx) = cv::Vec3b(g, g, g);
        }
    if (triangles)
    {
        const PixelFrame f{grid.getXMin(), grid.getYMax(), grid.getResolution()};
        drawTriangles(img, f, *triangles);
    }
    write(path, img);
}

void savePointsPng(
    const mrpt::maps::CPointsMap& points, const std::string& path, double resolution_m,
    const hymm::ltr::RegionPartition* triangles, double margin_m)
{
    if (!(resolution_m > 0)) throw std::invalid_argument("savePointsPng: resolution must be > 0");
    Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    const auto& xs = points.getPointsBufferRef_x();
    const auto& ys = points.getPointsBufferRef_y();
    for (size_t i = 0; i < xs.size(); ++i)
    {
        lo = lo.cwiseMin(Eigen::Vector2d(xs[i], ys[i]));
        hi = hi.cwiseMax(Eigen::Vector2d(xs[i], ys[i]));
    }
    if (triangles)
        for (const long id : triangles->regionIds())
            for (const auto& v : triangles->region(id).current)
            {
                lo = lo.cwiseMin(v);
                hi = hi.cwiseMax(v);
            }
    if (!(lo.x() <= hi.x())) lo = hi = Eigen::Vector2d::Zero();
    lo -= Eigen::Vector2d::Constant(margin_m);
    hi += Eigen::Vector2d::Constant(margin_m);
    const long w = static_cast<long>(std::ceil((hi.x() - lo.x()) / resolution_m));
    const long h = static_cast<long>(std::ceil((hi.y() - lo.y()) / resolution_m));
    checkSize(w, h, path);
    cv::Mat img(static_cast<int>(h), static_cast<int>(w), CV_8UC3, cv::Scalar(255, 255, 255));
    const PixelFrame f{lo.x(), hi.y(), resolution_m};
    if (triangles) drawTriangles(img, f, *triangles);
    for (size_t i = 0; i < xs.size(); ++i)
        cv::circle(img, f.px(Eigen::Vector2d(xs[i], ys[i])), 1, cv::Scalar(0, 0, 0), cv::FILLED);
    write(path, img);
}

void savePointsByValuePng(const mrpt::maps::CPointsMapXYZI& points, const std::string& path,
                          double resolution_m, double v_min, double v_max,
                          const hymm::ltr::RegionPartition* triangles, double margin_m)
{
    if (!(v_max > v_min)) throw std::invalid_argument("savePointsByValuePng: need v_max > v_min");
    const auto& xs = points.getPointsBufferRef_x();
    const auto& ys = points.getPointsBufferRef_y();
    Box box;
    for (size_t i = 0; i < xs.size(); ++i) box.add(Eigen::Vector2d(xs[i], ys[i]));
    if (triangles) box.add(*triangles);
    PixelFrame f{};
    cv::Mat img = whiteCanvas(box, resolution_m, margin_m, path, f);
    if (triangles) drawTriangles(img, f, *triangles);
    // One JET colour per 8-bit level; draw low values first so high ones stay on top.
    cv::Mat levels(1, 256, CV_8UC1), colours;
    for (int k = 0; k < 256; ++k) levels.at<unsigned char>(0, k) = static_cast<unsigned char>(k);
    cv::applyColorMap(levels, colours, cv::COLORMAP_JET);
    std::vector<std::pair<int, size_t>> order;
    order.reserve(xs.size());
    for (size_t i = 0; i < xs.size(); ++i)
    {
        const double t =
            std::clamp((points.getPointIntensity(i) - v_min) / (v_max - v_min), 0.0, 1.0);
        order.emplace_back(static_cast<int>(std::lround(255.0 * t)), i);
    }
    std::stable_sort(order.begin(), order.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& [level, i] : order)
    {
        const cv::Vec3b c = colours.at<cv::Vec3b>(0, level);
        cv::circle(img, f.px(Eigen::Vector2d(xs[i], ys[i])), 1, cv::Scalar(c[0], c[1], c[2]),
                   cv::FILLED);
    }
    write(path, img);
}

void savePolylinesPng(const std::vector<std::vector<Eigen::Vector2d>>& polylines,
                      const std::string& path, double resolution_m,
                      const hymm::ltr::RegionPartition* triangles, double margin_m)
{
    Box box;
    for (const auto& poly : polylines)
        for (const auto& p : poly) box.add(p);
    if (triangles) box.add(*triangles);
    PixelFrame f{};
    cv::Mat img = whiteCanvas(box, resolution_m, margin_m, path, f);
    if (triangles) drawTriangles(img, f, *triangles);
    for (const auto& poly : polylines)
    {
        std::vector<cv::Point> pts;
        pts.reserve(poly.size());
        for (const auto& p : poly) pts.push_back(f.px(p));
        cv::polylines(img, pts, true, cv::Scalar(200, 0, 0), 1, cv::LINE_AA);
    }
    write(path, img);
}

void saveScalarFieldPng(
    const ScalarField& field, const std::string& path, double v_min, double v_max,
    const hymm::ltr::RegionPartition* triangles, const std::vector<std::vector<Eigen::Vector2d>>* polylines)
{
    if (!(v_max > v_min)) throw std::invalid_argument("saveScalarFieldPng: need v_max > v_min");
    const int w = field.sizeX(), h = field.sizeY();
    checkSize(w, h, path);
    cv::Mat grey(h, w, CV_8UC1), nodata(h, w, CV_8UC1, cv::Scalar(0));
    for (int iy = 0; iy < h; ++iy)
        for (int ix = 0; ix < w; ++ix)
        {
            const double v = field.values(iy, ix);
            if (std::isnan(v)) nodata.at<unsigned char>(h - 1 - iy, ix) = 255;
            const double t = std::isnan(v) ? 0.0 : std::clamp((v - v_min) / (v_max - v_min), 0.0, 1.0);
            grey.at<unsigned char>(h - 1 - iy, ix) = static_cast<unsigned char>(std::lround(255.0 * t));
        }
    cv::Mat img;
    cv::applyColorMap(grey, img, cv::COLORMAP_JET);
    img.setTo(cv::Scalar(255, 255, 255), nodata);
    const PixelFrame f{field.origin.x(), field.origin.y() + h * field.resolution, field.resolution};
    if (triangles) drawTriangles(img, f, *triangles);
    if (polylines)
        for (const auto& poly : *polylines)
        {
            std::vector<cv::Point> pts;
            for (const auto& p : poly) pts.push_back(f.px(p));
            cv::polylines(img, pts, true, cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
        }
    write(path, img);
}

}  // namespace hymm::dense
