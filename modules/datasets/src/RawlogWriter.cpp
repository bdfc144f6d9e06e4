#include "hymm/datasets/RawlogWriter.h"

#include <hymm/io/OdometryRawlogWriter.h>

#include <algorithm>
#include <stdexcept>

#include "hymm/datasets/ImportSummary.h"

namespace hymm::datasets
{
void writeOdometryRawlog(const std::string& path, const OdometryIntegrator& odometry,
                         const std::vector<mrpt::obs::CObservation::Ptr>& observations,
                         ImportSummary& summary)
{
    const auto earlier = [](const auto& a, const auto& b) { return a->timestamp < b->timestamp; };
    if (!std::is_sorted(observations.begin(), observations.end(), earlier))
        throw std::invalid_argument("writeOdometryRawlog: observations not sorted by time");

    io::OdometryRawlogWriter writer(path);
    double t_prev = 0;
    for (size_t k = 0; k < observations.size(); ++k)
    {
        const double t = mrpt::Clock::toDouble(observations[k]->timestamp);
        if (k == 0)
        {
            t_prev = odometry.samples().empty() ? t : std::min(t, odometry.samples().front().t);
            summary.first_time_s = t;
        }
        const auto inc = odometry.integrate(t_prev, t);
        summary.odometry_gap_s += inc.uncovered_s;
        writer.writeFrame(observations[k]->timestamp, inc.mean, inc.cov, {observations[k]});
        summary.last_time_s = t;
        t_prev = t;
    }
    writer.close();
    summary.frames += writer.frames();
    summary.observations += writer.frames();
    summary.outputs.push_back(path);
}

}  // namespace hymm::datasets
