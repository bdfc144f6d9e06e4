// hymm-slam's outputs of the high-level landmarks ([HighLevelLandmarks] enabled, thesis
// 6.1): metrics, summary line, hll.csv and the figure of Fig. 6.5 (hll.png).
#include <hymm/app/slam_outputs.h>
#include <hymm/core/output_files.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <iomanip>
#include <stdexcept>

namespace hymm::app
{
namespace
{
/** Pose of HLL `h` now: its landmark's estimate once initialised, else the detection. */
Eigen::Vector3d hllPose(const DenseSlam& slam, const hll::HighLevelLandmarks::Hll& h, bool* in_filter = nullptr)
{
    const bool in = h.landmark_id >= 0 && slam.ekf().hasLandmark(h.landmark_id);
    if (in_filter) *in_filter = in;
    return in ? Eigen::Vector3d(slam.ekf().landmarkBlockMean(h.landmark_id).head<3>()) : h.rect.pose();
}
}  // namespace

void writeHllMetrics(eval::MetricsJson& j, const DenseSlam& slam)
{
    const auto* h = slam.highLevelLandmarks();
    if (!h) return;
    auto& o = j.object("hll");
    for (const auto& [k, n] : h->stats().list()) o.set(k, static_cast<unsigned long>(n));
    // The observation step of the HLLs in the filter (alignments, updates, gate).
    for (const auto& [k, n] : h->tracker().stats().list())
        if (k == "predicted" || k == "out_of_view" || k == "aligned" || k == "updated" || k == "gated" ||
            k.rfind("align_failed.", 0) == 0 || k == "update_numeric" || k == "update_invalid")
            o.set(k, static_cast<unsigned long>(n));
    size_t in_filter = 0;
    for (const auto& x : h->hlls()) in_filter += x.landmark_id >= 0 && slam.ekf().hasLandmark(x.landmark_id);
    o.set("in_filter", static_cast<unsigned long>(in_filter));
}

void writeHllSummary(std::ostream& f, const DenseSlam& slam)
{
    const auto* h = slam.highLevelLandmarks();
    if (!h) return;
    f << "high-level landmarks";
    for (const auto& [k, n] : h->stats().list()) f << ' ' << k << '=' << n;
    f << " updated=" << h->tracker().stats().updated << "\n";
}

namespace
{
void writeHllCsv(const DenseSlam& slam, const hll::HighLevelLandmarks& h, const std::string& file)
{
    core::AtomicTextFile f(file);
    f << "index,t_accepted,gaussians,outline_m,template_points,landmark_id,t_initialised,x,y,phi,half_x,half_y\n"
      << std::setprecision(10);
    for (const auto& x : h.hlls())
    {
        const Eigen::Vector3d p = hllPose(slam, x);
        f << x.index << ',' << x.t_accepted << ',' << x.gaussians << ',' << x.outline_m << ','
          << x.tpl.sog.size() << ','
          << x.landmark_id << ',' << x.t_initialised << ',' << p.x() << ',' << p.y() << ',' << p.z()
          << ',' << x.rect.half.x() << ',' << x.rect.half.y() << '\n';
    }
    f.commit();
}

/** The canvas of Fig. 6.5: an occupancy grid drawn at `scale` pixels per cell (white
 *  free, black occupied), world points mapped to its pixels. */
struct HllCanvas
{
    static constexpr int kScale = 2;
    const mrpt::maps::COccupancyGridMap2D& grid;
    cv::Mat img;
    double res;  //!< [m/pixel]

    explicit HllCanvas(const mrpt::maps::COccupancyGridMap2D& g) : grid(g), res(g.getResolution() / kScale)
    {
        const int w = static_cast<int>(grid.getSizeX()), hgt = static_cast<int>(grid.getSizeY());
        img = cv::Mat(hgt, w, CV_8UC3);
        for (int cy = 0; cy < hgt; ++cy)
            for (int cx = 0; cx < w; ++cx)
            {
                const auto v = static_cast<unsigned char>(std::lround(255.0 * (1.0 - grid.getCell(cx, cy))));
                img.at<cv::Vec3b>(hgt - 1 - cy, cx) = cv::Vec3b(v, v, v);
            }
        cv::resize(img, img, cv::Size(), kScale, kScale, cv::INTER_NEAREST);
    }
    cv::Point px(const Eigen::Vector2d& p) const
    {
        return cv::Point(static_cast<int>(std::lround((p.x() - grid.getXMin()) / res)),
                         static_cast<int>(std::lround((grid.getYMax() - p.y()) / res)));
    }
    void rect(const hll::OrientedRect& r, const cv::Scalar& c, int thick)
    {
        const auto k = r.corners();
        for (int e = 0; e < 4; ++e) cv::line(img, px(k[e]), px(k[(e + 1) % 4]), c, thick, cv::LINE_AA);
    }
};

// The corners found (circles) and the candidate rectangles at detection: rejected thin
// orange, accepted thick blue (drawn last, on top).
void drawSearches(HllCanvas& canvas, const hll::HighLevelLandmarks& h)
{
    for (const auto& s : h.searches())
    {
        for (const auto& c : s.candidates)
            if (c.outcome != hll::HllDetector::Outcome::accepted) canvas.rect(c.rect, cv::Scalar(0, 140, 255), 1);
        for (const auto& c : s.corners) cv::circle(canvas.img, canvas.px(c), 5, cv::Scalar(200, 0, 200), 1, cv::LINE_AA);
    }
    for (const auto& s : h.searches())
        for (const auto& c : s.candidates)
            if (c.outcome == hll::HllDetector::Outcome::accepted) canvas.rect(c.rect, cv::Scalar(255, 60, 0), 3);
}

// An HLL's axes (red x, green y) at its current estimate and, once in the filter, the
// 3-sigma ellipse of its frame's position.
void drawHll(HllCanvas& canvas, const DenseSlam& slam, const hll::HighLevelLandmarks::Hll& x)
{
    bool in = false;
    const Eigen::Vector3d p = hllPose(slam, x, &in);
    const Eigen::Vector2d o = p.head<2>();
    const Eigen::Vector2d ux(std::cos(p.z()), std::sin(p.z())), uy(-ux.y(), ux.x());
    cv::arrowedLine(canvas.img, canvas.px(o), canvas.px(o + 4 * ux), cv::Scalar(0, 0, 230), 2, cv::LINE_AA, 0, 0.2);
    cv::arrowedLine(canvas.img, canvas.px(o), canvas.px(o + 4 * uy), cv::Scalar(0, 170, 0), 2, cv::LINE_AA, 0, 0.2);
    if (!in) return;
    const Eigen::Matrix2d P = slam.ekf().landmarkBlockCov(x.landmark_id).topLeftCorner<2, 2>();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(P);
    std::vector<cv::Point> poly;
    for (int k = 0; k < 36; ++k)
    {
        const double a = 2 * M_PI * k / 36;
        const Eigen::Vector2d d = es.eigenvectors() *
                                  Eigen::Vector2d(3 * std::sqrt(std::max(es.eigenvalues()[0], 0.0)) * std::cos(a),
                                                  3 * std::sqrt(std::max(es.eigenvalues()[1], 0.0)) * std::sin(a));
        poly.push_back(canvas.px(o + d));
    }
    cv::polylines(canvas.img, poly, true, cv::Scalar(0, 0, 255), 1, cv::LINE_AA);
}
}  // namespace

void writeHllOutputs(const DenseSlam& slam, const std::string& dir, bool png)
{
    const auto* h = slam.highLevelLandmarks();
    if (!h) return;
    writeHllCsv(slam, *h, dir + "hll.csv");
    if (!png || !slam.partition() || !slam.hybridMap() || slam.hybridMap()->size() == 0) return;
    // Fig. 6.5: the occupancy layer with the searches and the HLLs.
    mrpt::maps::COccupancyGridMap2D grid;
    slam.hybridMap()->renderOccupancy(*slam.partition(), 0.2, grid);
    if (grid.getSizeX() == 0 || grid.getSizeY() == 0) return;
    HllCanvas canvas(grid);
    drawSearches(canvas, *h);
    for (const auto& x : h->hlls()) drawHll(canvas, slam, x);
    const std::string path = dir + "hll.png";
    if (!cv::imwrite(path, canvas.img)) throw std::runtime_error("cannot write '" + path + "'");
}

}  // namespace hymm::app
