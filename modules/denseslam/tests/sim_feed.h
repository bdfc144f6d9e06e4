/**
 * @file sim_feed.h
 * @brief Test helpers: feed a simulated run to a DenseSlam in memory, frame by frame,
 *        as a rawlog would deliver it; look up a simulated object by name.
 */
#pragma once

#include <hymm/denseslam/DenseSlam.h>
#include <hymm/sim/Simulator.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPosePDFGaussian.h>

#include <functional>
#include <stdexcept>
#include <string>

namespace hymm::denseslam::testing
{
/** Every simulated frame to `slam` (odometry action, then the sensory frame); calls
 *  `probe(t)` after each frame. */
inline void run(const hymm::sim::Scenario& s, DenseSlam& slam,
                const std::function<void(double)>& probe)
{
    hymm::sim::Simulator sim(s);
    hymm::sim::SimFrame f;
    while (sim.next(f))
    {
        slam.processOdometry(mrpt::poses::CPosePDFGaussian(
            mrpt::poses::CPose2D(f.odometry_mean[0], f.odometry_mean[1], f.odometry_mean[2]),
            mrpt::math::CMatrixDouble33(f.odometry_cov)));
        mrpt::obs::CSensoryFrame sf;
        if (f.scan) sf.insert(f.scan);
        if (f.detections) sf.insert(f.detections);
        slam.processFrame(sf);
        probe(f.t);
    }
}

inline const hymm::sim::WorldObject& object(const hymm::sim::World& w, const std::string& name)
{
    for (const auto& o : w.objects())
        if (o.name == name) return o;
    throw std::invalid_argument("no object " + name);
}

}  // namespace hymm::denseslam::testing
