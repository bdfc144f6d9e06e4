/**
 * @file mrpt_outputs.h
 * @brief hymm-slam's results in MRPT's own formats, for MRPT's apps and libraries:
 *  - map.3Dscene   mrpt::opengl::COpenGLScene (COpenGLScene::saveToFile) for
 *                  SceneViewer3D: named objects "path" (estimated path),
 *                  "landmarks" (3-sigma ellipses), and with dense layers
 *                  "ltr_triangles" and one object per layer (CHybridMetricMap.h);
 *  - map.simplemap mrpt::maps::CSimpleMap (CSimpleMap::saveToFile): one keyframe per
 *                  path sample, the pose estimate with its covariance (a
 *                  CPose3DPDFGaussian from the 2D pose and 3x3 covariance at that
 *                  step, a filtered estimate: later corrections of the path are not in
 *                  it) and the sensory frame the pipeline processed there; input of
 *                  observations2map and pf-localization (icp-slam reads a rawlog,
 *                  not a simplemap: docs/mrpt-workflows.md);
 *  - map.hymm      with dense layers: the hybrid map (dense::CHybridMetricMap, at the
 *                  final landmark estimates), what CMultiMetricMap .ini sections load
 *                  with `map_file`;
 *  - run.rawlog    the run for RawLogViewer, in MRPT 2's observation format: for each
 *                  keyframe a CObservationRobotPose (label HYMM_POSE, stamped like the
 *                  frame) holding the pose estimate of that step with its covariance
 *                  (the same filtered estimate as map.simplemap), a CObservationOdometry
 *                  (label ODOMETRY) with the input's odometry accumulated up to the frame
 *                  when the input has odometry (actions, or its own CObservationOdometry),
 *                  then the frame's input observations as they were read: a complete
 *                  observation-format copy of the input that MRPT's icp-slam can map.
 * Source: mrpt_outputs.cpp.
 */
#pragma once

#include <hymm/dense/CHybridMetricMap.h>
#include <hymm/denseslam/DenseSlam.h>
#include <hymm/io/RawlogReader.h>

#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/opengl/COpenGLScene.h>

#include <string>
#include <vector>

namespace hymm::app
{
using denseslam::DenseSlam;

/** The sensory frame behind each path sample, collected while a rawlog is processed:
 *  call record() after every DenseSlam::processEntry(). Holds shared pointers to the
 *  observations (no copies). */
class KeyframeRecorder
{
public:
    /** Notes the frame of `entry` (a sensory frame, or a single observation wrapped in
     *  one) if processing it added a path sample. */
    void record(const DenseSlam& slam, const io::RawlogEntry& entry);
    /** Path index and frame of each keyframe, in path order. */
    const std::vector<std::pair<size_t, mrpt::obs::CSensoryFrame::Ptr>>& frames() const { return frames_; }
    /** The input's odometry pose at each keyframe (the actions' increments composed from
     *  the origin, or the latest CObservationOdometry); empty when the input has none. */
    const std::vector<mrpt::poses::CPose2D>& odometry() const { return odometry_; }
    /** Saved run state (slam_state.h): the keyframes so far; loadState() replaces them
     *  (throws std::runtime_error on a corrupt state). Source: slam_state.cpp. */
    void saveState(mrpt::serialization::CArchive& out) const;
    void loadState(mrpt::serialization::CArchive& in);

private:
    size_t path_size_ = 0;
    std::vector<std::pair<size_t, mrpt::obs::CSensoryFrame::Ptr>> frames_;
    bool has_odometry_ = false;
    size_t predictions_seen_ = 0;  //!< the pipeline's predictions at the last record()
    mrpt::poses::CPose2D odometry_now_;
    std::vector<mrpt::poses::CPose2D> odometry_;  //!< at each keyframe, when has_odometry_
};

/** The run's hybrid map as an MRPT map: a copy of the partition (refreshed to the final
 *  landmark estimates first: call DenseSlam::refreshRegions()), the dense layers and
 *  every 2-DOF landmark with its covariance. Throws std::logic_error without dense
 *  layers. */
dense::CHybridMetricMap hybridMetricMap(const DenseSlam& slam);

/** Keyframes of `recorder` at the path estimates (see the file comment). */
mrpt::maps::CSimpleMap makeSimpleMap(const DenseSlam& slam, const KeyframeRecorder& recorder);

/** Writes run.rawlog (see the file comment) to `path`, gzip-compressed; throws
 *  std::runtime_error if it cannot be opened. */
void writeRunRawlog(const DenseSlam& slam, const KeyframeRecorder& recorder, const std::string& path);
/** The scene of map.3Dscene (see the file comment). */
mrpt::opengl::COpenGLScene makeScene(const DenseSlam& slam);

/** Writes map.3Dscene, map.simplemap, run.rawlog and (with dense layers) map.hymm into `dir`.
 *  Throws std::runtime_error if a file cannot be written. */
void writeMrptOutputs(const DenseSlam& slam, const KeyframeRecorder& recorder, const std::string& dir);

}  // namespace hymm::app
