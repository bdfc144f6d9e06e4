/**
 * @file single_pass_figure.cpp
 * @brief Drawing of SinglePassFigure with OpenCV (x right, y up).
 */
#include "single_pass_figure.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace hymm::bench
{
namespace
{
constexpr int kLegendHeight = 70;   //!< [px] band above the map for the title and legend
constexpr int kPngCompression = 9;  //!< smallest file (the figures go into the docs)

const cv::Scalar kWhite(255, 255, 255), kBlack(0, 0, 0), kGrey(150, 150, 150);
const cv::Scalar kTriangle(200, 200, 255), kPath(230, 200, 150), kFused(220, 90, 0),
    kHole(0, 140, 255);

struct Frame
{
    Eigen::Vector2d lo, hi;
    double res;
    int width, height;
    cv::Point px(const Eigen::Vector2d& p) const
    {
        return {static_cast<int>(std::lround((p.x() - lo.x()) / res)),
                kLegendHeight + static_cast<int>(std::lround((hi.y() - p.y()) / res))};
    }
};

Frame frameFor(const SinglePassFigure& f)
{
    Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e300), hi = -lo;
    const auto add = [&](const Eigen::Vector2d& p)
    {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    };
    for (const auto& poly : f.outlines)
        for (const auto& p : poly) add(p);
    for (const auto* set : {&f.true_path, &f.direct_points, &f.fused_points, &f.holes})
        for (const auto& p : *set) add(p);
    if (!(lo.x() <= hi.x())) throw std::runtime_error("SinglePassFigure: nothing to draw");
    lo.array() -= f.margin_m;
    hi.array() += f.margin_m;
    Frame fr{lo, hi, f.resolution_m, 0, 0};
    fr.width = static_cast<int>(std::ceil((hi.x() - lo.x()) / f.resolution_m)) + 1;
    fr.height = static_cast<int>(std::ceil((hi.y() - lo.y()) / f.resolution_m)) + 1 + kLegendHeight;
    return fr;
}

void legend(cv::Mat& img, const std::string& title)
{
    cv::putText(img, title, {10, 22}, cv::FONT_HERSHEY_SIMPLEX, 0.6, kBlack, 1, cv::LINE_AA);
    int x = 10;
    const auto item = [&](const cv::Scalar& c, const std::string& text)
    {
        cv::rectangle(img, {x, 40}, {x + 12, 52}, c, cv::FILLED);
        cv::putText(img, text, {x + 18, 51}, cv::FONT_HERSHEY_SIMPLEX, 0.45, kBlack, 1,
                    cv::LINE_AA);
        x += 30 + 8 * static_cast<int>(text.size());
    };
    item(kGrey, "true outlines");
    item(kBlack, "points inserted directly");
    item(kFused, "points fused from the delayed store");
    item(kHole, "seen but not mapped");
    item(kTriangle, "LTRs");
}
}  // namespace

void SinglePassFigure::save(const std::string& path) const
{
    if (!(resolution_m > 0)) throw std::runtime_error("SinglePassFigure: resolution must be > 0");
    const Frame fr = frameFor(*this);
    cv::Mat img(fr.height, fr.width, CV_8UC3, kWhite);
    for (const auto& v : triangles)
        for (size_t k = 0; k < 3; ++k)
            cv::line(img, fr.px(v[k]), fr.px(v[(k + 1) % 3]), kTriangle, 1, cv::LINE_AA);
    for (size_t i = 1; i < true_path.size(); ++i)
        cv::line(img, fr.px(true_path[i - 1]), fr.px(true_path[i]), kPath, 2, cv::LINE_AA);
    for (const auto& poly : outlines)
        for (size_t k = 0; k < poly.size(); ++k)
            cv::line(img, fr.px(poly[k]), fr.px(poly[(k + 1) % poly.size()]), kGrey, 1,
                     cv::LINE_AA);
    for (const auto& p : holes) cv::circle(img, fr.px(p), 3, kHole, cv::FILLED);
    for (const auto& p : direct_points) cv::circle(img, fr.px(p), 1, kBlack, cv::FILLED);
    for (const auto& p : fused_points) cv::circle(img, fr.px(p), 1, kFused, cv::FILLED);
    legend(img, title);
    bool ok = false;
    try
    {
        ok = cv::imwrite(path, img, {cv::IMWRITE_PNG_COMPRESSION, kPngCompression});
    }
    catch (const cv::Exception& e)
    {
        throw std::runtime_error("cannot write '" + path + "': " + e.what());
    }
    if (!ok) throw std::runtime_error("cannot write '" + path + "'");
}

}  // namespace hymm::bench
