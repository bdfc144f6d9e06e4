#include "hymm/eval/relative_pose_error.h"

#include <mrpt/math/wrap2pi.h>
#include <mrpt/poses/CPose2D.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace hymm::eval
{
namespace
{
/** a^-1 (+) b. */
mrpt::poses::CPose2D relative(const io::StampedPose2D& a, const io::StampedPose2D& b)
{
    return mrpt::poses::CPose2D(b.x, b.y, b.phi) - mrpt::poses::CPose2D(a.x, a.y, a.phi);
}

bool finite(const io::StampedPose2D& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.phi); }

void summarise(std::vector<double> v, double& mean, double& median, double& max)
{
    std::sort(v.begin(), v.end());
    double sum = 0;
    for (double e : v) sum += e;
    mean = sum / static_cast<double>(v.size());
    const size_t n = v.size();
    median = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
    max = v.back();
}
}  // namespace

RelativePoseError relativePoseError(const std::vector<io::StampedPose2D>& estimate,
                                    const std::vector<io::StampedPose2D>& truth)
{
    if (estimate.size() != truth.size())
        throw std::invalid_argument("relativePoseError: " + std::to_string(estimate.size()) + " estimates for " +
                                    std::to_string(truth.size()) + " true poses");
    for (size_t i = 0; i < estimate.size(); ++i)
        if (!finite(estimate[i]) || !finite(truth[i]))
            throw std::invalid_argument("relativePoseError: pose " + std::to_string(i) + " is not finite");
    RelativePoseError r;
    if (estimate.size() < 2)
    {
        const double nan = std::numeric_limits<double>::quiet_NaN();
        r.translation_mean = r.translation_median = r.translation_max = nan;
        r.rotation_mean = r.rotation_median = r.rotation_max = nan;
        return r;
    }
    std::vector<double> et, er;
    for (size_t i = 0; i + 1 < estimate.size(); ++i)
    {
        const auto e = relative(estimate[i], estimate[i + 1]);
        const auto g = relative(truth[i], truth[i + 1]);
        et.push_back(std::hypot(e.x() - g.x(), e.y() - g.y()));
        er.push_back(std::abs(mrpt::math::wrapToPi(e.phi() - g.phi())));
    }
    r.pairs = et.size();
    summarise(et, r.translation_mean, r.translation_median, r.translation_max);
    summarise(er, r.rotation_mean, r.rotation_median, r.rotation_max);
    return r;
}

}  // namespace hymm::eval
