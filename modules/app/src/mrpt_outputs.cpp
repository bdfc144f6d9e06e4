// hymm-slam's results in MRPT's formats: map.3Dscene, map.simplemap, map.hymm, run.rawlog.
#include <hymm/app/mrpt_outputs.h>

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/opengl/CSetOfLines.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/poses/CPosePDFGaussian.h>

#include <algorithm>
#include <optional>
#include <stdexcept>

namespace hymm::app
{
void KeyframeRecorder::record(const DenseSlam& slam, const io::RawlogEntry& entry)
{
    // The input's odometry as the pipeline used it (DenseSlam::processEntry): an action's
    // increment only when the pipeline made a prediction of it (a NaN or absurd one is
    // skipped there), a reading only when it is finite (the pipeline's reference).
    const size_t predictions = slam.stats().predictions;
    if (entry.actions && predictions > predictions_seen_)
        if (auto mov = entry.actions->getBestMovementEstimation())
        {
            odometry_now_ = odometry_now_ + mov->poseChange->getMeanVal();
            has_odometry_ = true;
        }
    predictions_seen_ = predictions;
    if (const auto* odo = dynamic_cast<const mrpt::obs::CObservationOdometry*>(entry.observation.get()))
        if (std::isfinite(odo->odometry.x()) && std::isfinite(odo->odometry.y()) &&
            std::isfinite(odo->odometry.phi()))
        {
            odometry_now_ = odo->odometry;
            has_odometry_ = true;
        }
    // Odometry first seen after some keyframes: those had none (the origin); one pose per
    // keyframe from here on.
    if (has_odometry_) odometry_.resize(frames_.size());
    const size_t n = slam.path().size();
    if (n == path_size_) return;
    path_size_ = n;
    mrpt::obs::CSensoryFrame::Ptr sf = entry.frame;
    if (!sf && entry.observation)
    {
        sf = mrpt::obs::CSensoryFrame::Create();
        sf->insert(entry.observation);
    }
    if (!sf) return;
    frames_.emplace_back(n - 1, sf);
    if (has_odometry_) odometry_.push_back(odometry_now_);
}

namespace
{
std::vector<dense::CHybridMetricMap::Landmark> landmarksOf(const ekf::EkfSlam& ekf)
{
    std::vector<dense::CHybridMetricMap::Landmark> out;
    for (long id : ekf.landmarkIds())
        if (ekf.landmarkBlock(id).dim == 2) out.push_back({id, ekf.landmarkMean(id), ekf.landmarkCov(id)});
    return out;
}
}  // namespace

dense::CHybridMetricMap hybridMetricMap(const DenseSlam& slam)
{
    if (!slam.partition() || !slam.hybridMap())
        throw std::logic_error("hybridMetricMap: the run has no dense layers");
    dense::CHybridMetricMap m;
    m.assign(*slam.partition(), *slam.hybridMap(), landmarksOf(slam.ekf()));
    return m;
}

mrpt::maps::CSimpleMap makeSimpleMap(const DenseSlam& slam, const KeyframeRecorder& recorder)
{
    mrpt::maps::CSimpleMap sm;
    for (const auto& [i, sf] : recorder.frames())
    {
        const auto& s = slam.path().at(i);
        const Eigen::Matrix3d c = 0.5 * (s.cov + s.cov.transpose());
        auto pdf = mrpt::poses::CPosePDFGaussian::Create(
            mrpt::poses::CPose2D(s.pose.x(), s.pose.y(), s.pose.z()), mrpt::math::CMatrixDouble33(c));
        sm.insert(mrpt::poses::CPosePDF::Ptr(pdf), sf);
    }
    return sm;
}

void writeRunRawlog(const DenseSlam& slam, const KeyframeRecorder& recorder, const std::string& path)
{
    mrpt::io::CFileGZOutputStream f;
    if (!f.open(path, 1)) throw std::runtime_error("cannot write '" + path + "'");
    auto ar = mrpt::serialization::archiveFrom(f);
    for (size_t k = 0; k < recorder.frames().size(); ++k)
    {
        const auto& [i, sf] = recorder.frames()[k];
        const auto& s = slam.path().at(i);
        auto pose = mrpt::obs::CObservationRobotPose::Create();
        pose->sensorLabel = "HYMM_POSE";
        const Eigen::Matrix3d c = 0.5 * (s.cov + s.cov.transpose());
        pose->pose = mrpt::poses::CPose3DPDFGaussian(mrpt::poses::CPosePDFGaussian(
            mrpt::poses::CPose2D(s.pose.x(), s.pose.y(), s.pose.z()), mrpt::math::CMatrixDouble33(c)));
        for (const auto& o : *sf)
            if (o && o->timestamp != INVALID_TIMESTAMP)
            {
                pose->timestamp = o->timestamp;
                break;
            }
        ar << *pose;
        const bool own_odometry = std::any_of(sf->begin(), sf->end(), [](const auto& o) {
            return o && IS_CLASS(*o, mrpt::obs::CObservationOdometry);
        });
        if (k < recorder.odometry().size() && !own_odometry)
        {
            auto odo = mrpt::obs::CObservationOdometry::Create();
            odo->sensorLabel = "ODOMETRY";
            odo->timestamp = pose->timestamp;
            odo->odometry = recorder.odometry()[k];
            ar << *odo;
        }
        for (const auto& o : *sf)
            if (o) ar << *o;
    }
    f.close();
}

namespace
{
mrpt::opengl::COpenGLScene sceneOf(const DenseSlam& slam, const dense::CHybridMetricMap* map)
{
    mrpt::opengl::COpenGLScene scene;
    auto path = mrpt::opengl::CSetOfLines::Create();
    path->setName("path");
    path->setColor(0.0f, 0.5f, 0.0f);
    path->setLineWidth(2.0f);
    const auto& p = slam.path();
    for (size_t i = 1; i < p.size(); ++i)
        path->appendLine(p[i - 1].pose.x(), p[i - 1].pose.y(), 0.03, p[i].pose.x(), p[i].pose.y(), 0.03);
    scene.insert(path);
    if (map)
    {
        // The map draws triangles, landmarks and layers as named top-level objects.
        mrpt::opengl::CSetOfObjects objs;
        map->getVisualizationInto(objs);
        for (const auto& o : objs) scene.insert(o);
    }
    else
    {
        scene.insert(dense::landmarksObject(landmarksOf(slam.ekf())));
    }
    return scene;
}
}  // namespace

mrpt::opengl::COpenGLScene makeScene(const DenseSlam& slam)
{
    if (!slam.partition() || !slam.hybridMap()) return sceneOf(slam, nullptr);
    const auto map = hybridMetricMap(slam);
    return sceneOf(slam, &map);
}

void writeMrptOutputs(const DenseSlam& slam, const KeyframeRecorder& recorder, const std::string& dir)
{
    const std::string d = dir.empty() || dir.back() == '/' ? dir : dir + "/";
    std::optional<dense::CHybridMetricMap> map;
    if (slam.partition() && slam.hybridMap()) map = hybridMetricMap(slam);
    if (!sceneOf(slam, map ? &*map : nullptr).saveToFile(d + "map.3Dscene"))
        throw std::runtime_error("cannot write '" + d + "map.3Dscene'");
    if (!makeSimpleMap(slam, recorder).saveToFile(d + "map.simplemap"))
        throw std::runtime_error("cannot write '" + d + "map.simplemap'");
    if (map) map->saveToFile(d + "map.hymm");
    writeRunRawlog(slam, recorder, d + "run.rawlog");
}

}  // namespace hymm::app
