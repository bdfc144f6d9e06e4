// Thesis Example 3.2 over a real loop closure (the bundled chapter-3 run, 2 laps): at
// the update that closes the loop, landmarks far from the vehicle (out of sensor range,
// so moved only through their correlations, like fused dense content) move in global
// coordinates, while their coordinates in the LTR that contains them -- barycentric
// coordinates w.r.t. the current vertex estimates, expressed in metres in the region's
// reference frame -- move at most a third as much. That is why the dense layers store
// local coordinates and never update them (Sec. 3.6).
#include <gtest/gtest.h>
#include <hymm/denseslam/DenseSlam.h>
#include <hymm/io/RawlogReader.h>
#include <hymm/ltr/TriangleFrame.h>
#include <mrpt/config/CConfigFile.h>

#include <algorithm>
#include <map>
#include <iostream>
#include <string>

namespace
{
using hymm::denseslam::DenseSlam;

struct Snapshot
{
    Eigen::Vector2d vehicle;
    std::map<long, Eigen::Vector2d> landmarks;
};

Snapshot snapshot(const DenseSlam& slam)
{
    Snapshot s;
    s.vehicle = slam.ekf().vehiclePose().head<2>();
    for (long id : slam.ekf().landmarkIds()) s.landmarks[id] = slam.ekf().landmarkMean(id);
    return s;
}

// Local position of `p` in region `r`: barycentric w.r.t. the vertices in `snap`,
// mapped to metres through the reference triangle.
Eigen::Vector2d localPosition(const hymm::ltr::Region& r, const Snapshot& snap, const Eigen::Vector2d& p)
{
    const hymm::ltr::TriangleFrame cur(hymm::ltr::TriangleFrame::Vertices{
        snap.landmarks.at(r.vertex_ids[0]), snap.landmarks.at(r.vertex_ids[1]),
        snap.landmarks.at(r.vertex_ids[2])});
    return hymm::ltr::TriangleFrame(r.reference).toGlobal(cur.toLocal(p));
}

TEST(Example32, LocalCoordinatesMoveAtMostAThirdOfGlobalOnesAtTheLoopClosure)
{
    mrpt::config::CConfigFile cfg(std::string(HYMM_SOURCE_DIR) + "/configs/ch3_slam.ini");
    DenseSlam slam = DenseSlam::fromConfig(cfg);
    hymm::io::RawlogReader reader(std::string(HYMM_SOURCE_DIR) + "/rawlogs/ch3_objects.rawlog");
    hymm::io::RawlogEntry entry;

    // The frame whose update moves the out-of-range landmarks most is the closure.
    constexpr double kOutOfRange = 30.0;  // [m] > the 25 m sensor range
    Snapshot prev = snapshot(slam), before, after;
    double best = 0;
    size_t frames = 0;
    while (reader.next(entry))
    {
        slam.processEntry(entry);
        if (slam.path().size() == frames) continue;
        frames = slam.path().size();
        const Snapshot cur = snapshot(slam);
        double moved = 0;
        for (const auto& [id, p] : cur.landmarks)
        {
            const auto it = prev.landmarks.find(id);
            if (it != prev.landmarks.end() && (p - cur.vehicle).norm() > kOutOfRange)
                moved += (p - it->second).norm();
        }
        if (moved > best)
        {
            best = moved;
            before = prev;
            after = cur;
        }
        prev = cur;
    }
    ASSERT_NE(slam.partition(), nullptr);

    double sum_global = 0, sum_local = 0;
    size_t n = 0;
    for (const auto& [id, p1] : after.landmarks)
    {
        if (!before.landmarks.count(id) || (p1 - after.vehicle).norm() <= kOutOfRange) continue;
        const Eigen::Vector2d p0 = before.landmarks.at(id);
        // A region (of real landmarks) containing the landmark, not having it as a vertex.
        for (long rid : slam.partition()->regionIds())
        {
            const auto& r = slam.partition()->region(rid);
            bool usable = true;
            for (long v : r.vertex_ids)
                usable = usable && v != id && before.landmarks.count(v) && after.landmarks.count(v);
            if (!usable) continue;
            const hymm::ltr::TriangleFrame f0(hymm::ltr::TriangleFrame::Vertices{
                before.landmarks.at(r.vertex_ids[0]), before.landmarks.at(r.vertex_ids[1]),
                before.landmarks.at(r.vertex_ids[2])});
            // Within the region or near it (landmarks are vertices of most regions).
            const Eigen::Vector2d l = f0.toLocal(p0);
            if (l.x() < -0.5 || l.y() < -0.5 || l.x() + l.y() > 1.5) continue;
            const double dg = (p1 - p0).norm();
            const double dl = (localPosition(r, after, p1) - localPosition(r, before, p0)).norm();
            sum_global += dg;
            sum_local += dl;
            ++n;
            break;
        }
    }
    ASSERT_GE(n, 5u) << "too few landmarks far from the vehicle at the closure";
    const double mean_global = sum_global / n, mean_local = sum_local / n;
    // A real closure: the far landmarks moved by centimetres to decimetres.
    EXPECT_GT(mean_global, 0.02);
    EXPECT_LE(mean_local, mean_global / 3.0)
        << "global " << mean_global << " m, local " << mean_local << " m over " << n << " landmarks";
    RecordProperty("mean_global_move_m", std::to_string(mean_global));
    RecordProperty("mean_local_move_m", std::to_string(mean_local));
    std::cout << "Example 3.2 at the closure: " << n << " landmarks, mean global move "
              << mean_global << " m, mean local move " << mean_local << " m\n";
}

}  // namespace
