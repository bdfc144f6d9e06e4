// Average-NEES consistency of simulator -> rawlog -> DenseSlam on the chapter-2 loop
// (thesis Table 2.2), a short version of benchmarks/consistency.
#include <gtest/gtest.h>
#include <hymm/app/ConsistencyStudy.h>
#include <mrpt/system/filesystem.h>

#include <cmath>
#include <iostream>

namespace
{
TEST(ConsistencyTest, Chapter2LoopIsConsistentOverSeeds)
{
    hymm::app::ConsistencyStudy study;
    study.scenario_ini = std::string(HYMM_SOURCE_DIR) + "/configs/sim/ch2_landmarks.ini";
    study.slam_ini = std::string(HYMM_SOURCE_DIR) + "/configs/ch2_slam.ini";
    study.seeds = {101, 102, 103, 104, 105, 106, 107, 108};
    study.laps = 1;  // one loop, closed once, as in thesis Fig. 2.8
    study.work_dir = mrpt::system::getTempFileName() + "_consistency";
    const auto r = study.run();

    ASSERT_EQ(r.runs, 8u);
    ASSERT_GT(r.steps, 400u);
    // Consistency: the run-averaged NEES inside its 95% chi-square band.
    std::cout << "vehicle steps inside " << r.vehicle_fraction_inside << ", landmarks inside "
              << r.landmark_fraction_inside << ", mean averaged NEES " << r.vehicle_nees_mean << "\n";
    EXPECT_GE(r.vehicle_fraction_inside, 0.85);
    EXPECT_GE(r.landmark_fraction_inside, 0.85);
    // Accuracy: the loop is closed and the map is right to a fraction of a metre.
    for (size_t i = 0; i < r.runs; ++i)
    {
        EXPECT_LT(r.final_position_error[i], 1.0) << "run " << i;
        EXPECT_LT(r.landmark_mean_error[i], 1.0) << "run " << i;
    }
}

TEST(ConsistencyTest, MissingScenarioIsAClearError)
{
    hymm::app::ConsistencyStudy study;
    study.scenario_ini = "/nonexistent/scenario.ini";
    study.slam_ini = std::string(HYMM_SOURCE_DIR) + "/configs/ch2_slam.ini";
    study.seeds = {1};
    study.work_dir = mrpt::system::getTempFileName();
    EXPECT_THROW(study.run(), std::exception);
}

}  // namespace
