/**
 * @file ch3_sample.h
 * @brief The bundled chapter-3 sample (rawlog and ground truth) as hymm-slam arguments, shared
 *        by the slam_app tests.
 */
#pragma once

#include <hymm/app/SlamApp.h>

#include <string>

namespace hymm::test
{
inline const std::string kCh3Rawlog = std::string(HYMM_SOURCE_DIR) + "/rawlogs/ch3_objects.rawlog";
inline const std::string kCh3Gt = std::string(HYMM_SOURCE_DIR) + "/rawlogs/ch3_objects_gt_";

/** hymm-slam on the chapter-3 sample with `config`, writing to `out`, scored against its truth. */
inline hymm::app::SlamApp::Args ch3SampleArgs(const std::string& config, const std::string& out)
{
    hymm::app::SlamApp::Args a;
    a.config = config;
    a.rawlog = kCh3Rawlog;
    a.out_dir = out;
    a.gt_path = kCh3Gt + "path.tum";
    a.gt_landmarks = kCh3Gt + "landmarks.csv";
    a.gt_objects = kCh3Gt + "objects.txt";
    a.quiet = true;
    return a;
}
}  // namespace hymm::test
