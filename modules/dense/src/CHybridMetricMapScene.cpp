// CHybridMetricMap::getVisualizationInto: one named object per part of the map, so that
// SceneViewer3D lists them and each can be hidden.
#include "hymm/dense/CHybridMetricMap.h"

#include <mrpt/img/color_maps.h>
#include <mrpt/maps/CPointsMapXYZI.h>
#include <mrpt/opengl/CEllipsoid2D.h>
#include <mrpt/opengl/CPointCloud.h>
#include <mrpt/opengl/CPointCloudColoured.h>
#include <mrpt/opengl/CSetOfLines.h>
#include <mrpt/opengl/CSetOfObjects.h>

#include <cmath>

namespace hymm::dense
{
namespace
{
// Drawn a little above the occupancy plane (z = 0) so that lines stay visible on it.
constexpr float kLineZ = 0.02f;
constexpr float kPointZ = 0.01f;

mrpt::opengl::CSetOfLines::Ptr triangles(const hymm::ltr::RegionPartition& partition)
{
    auto lines = mrpt::opengl::CSetOfLines::Create();
    lines->setName("ltr_triangles");
    lines->setColor(0.1f, 0.3f, 0.9f);
    lines->setLineWidth(1.5f);
    for (long id : partition.regionIds())
    {
        const auto& v = partition.region(id).current;
        for (int i = 0; i < 3; ++i)
        {
            const auto& a = v[static_cast<size_t>(i)];
            const auto& b = v[static_cast<size_t>((i + 1) % 3)];
            lines->appendLine(a.x(), a.y(), kLineZ, b.x(), b.y(), kLineZ);
        }
    }
    return lines;
}

}  // namespace

mrpt::opengl::CSetOfObjects::Ptr landmarksObject(const std::vector<CHybridMetricMap::Landmark>& landmarks)
{
    auto group = mrpt::opengl::CSetOfObjects::Create();
    group->setName("landmarks");
    auto means = mrpt::opengl::CPointCloud::Create();
    means->setName("landmark_means");
    means->setColor(0.8f, 0.0f, 0.0f);
    means->setPointSize(5.0f);
    for (const auto& l : landmarks)
    {
        means->insertPoint(static_cast<float>(l.mean.x()), static_cast<float>(l.mean.y()), kLineZ);
        if (!l.cov.allFinite() || l.cov.determinant() <= 0) continue;  // no ellipse to draw
        auto e = mrpt::opengl::CEllipsoid2D::Create();
        mrpt::math::CMatrixDouble22 c;
        c(0, 0) = l.cov(0, 0);
        c(0, 1) = c(1, 0) = 0.5 * (l.cov(0, 1) + l.cov(1, 0));
        c(1, 1) = l.cov(1, 1);
        e->setCovMatrix(c);
        e->setQuantiles(3.0f);  // 3-sigma, as map.png draws them
        e->setLocation(l.mean.x(), l.mean.y(), kLineZ);
        e->setColor(0.8f, 0.0f, 0.0f);
        e->setName("landmark_" + std::to_string(l.id));
        group->insert(e);
    }
    group->insert(means);
    return group;
}

namespace
{
/** The raw returns as a black point cloud. */
mrpt::opengl::CPointCloud::Ptr pointsObject(const mrpt::maps::CSimplePointsMap& m)
{
    auto pts = mrpt::opengl::CPointCloud::Create();
    pts->setName("points");
    pts->setColor(0.0f, 0.0f, 0.0f);
    pts->setPointSize(2.0f);
    for (size_t i = 0; i < m.size(); ++i)
    {
        float x, y;
        m.getPoint(i, x, y);
        pts->insertPoint(x, y, kPointZ);
    }
    return pts;
}

/** The particles coloured by weight P(occupied) (jet colour map). */
mrpt::opengl::CPointCloudColoured::Ptr particlesObject(const mrpt::maps::CPointsMapXYZI& particles)
{
    auto cloud = mrpt::opengl::CPointCloudColoured::Create();
    cloud->setName("particles");
    cloud->setPointSize(2.0f);
    for (size_t i = 0; i < particles.size(); ++i)
    {
        float x, y, z;
        particles.getPoint(i, x, y, z);
        float r, g, b;  // weight P(occupied) in [0, 1]
        mrpt::img::colormap(mrpt::img::cmJET, particles.getPointIntensity(i), r, g, b);
        cloud->push_back(x, y, kPointZ, r, g, b);
    }
    return cloud;
}

/** The SOG layer's ellipses as green polylines. */
mrpt::opengl::CSetOfLines::Ptr sogObject(const std::vector<std::vector<Eigen::Vector2d>>& polys)
{
    auto lines = mrpt::opengl::CSetOfLines::Create();
    lines->setName("sog");
    lines->setColor(0.0f, 0.6f, 0.0f);
    for (const auto& poly : polys)
        for (size_t i = 1; i < poly.size(); ++i)
            lines->appendLine(poly[i - 1].x(), poly[i - 1].y(), kLineZ, poly[i].x(), poly[i].y(), kLineZ);
    return lines;
}

/** The property layer's mean, one point per observed cell coloured over its range. */
mrpt::opengl::CPointCloudColoured::Ptr propertyObject(const ScalarField& mean)
{
    double lo = INFINITY, hi = -INFINITY;
    for (Eigen::Index k = 0; k < mean.values.size(); ++k)
        if (std::isfinite(mean.values(k)))
        {
            lo = std::min(lo, mean.values(k));
            hi = std::max(hi, mean.values(k));
        }
    auto cloud = mrpt::opengl::CPointCloudColoured::Create();
    cloud->setName("property");
    cloud->setPointSize(3.0f);
    const double span = hi > lo ? hi - lo : 1.0;
    for (Eigen::Index iy = 0; iy < mean.values.rows(); ++iy)
        for (Eigen::Index ix = 0; ix < mean.values.cols(); ++ix)
        {
            const double v = mean.values(iy, ix);
            if (!std::isfinite(v)) continue;  // unobserved cell
            float r, g, b;
            mrpt::img::colormap(mrpt::img::cmJET, static_cast<float>((v - lo) / span), r, g, b);
            const double x = mean.origin.x() + (static_cast<double>(ix) + 0.5) * mean.resolution;
            const double y = mean.origin.y() + (static_cast<double>(iy) + 0.5) * mean.resolution;
            cloud->push_back(static_cast<float>(x), static_cast<float>(y), kPointZ, r, g, b);
        }
    return cloud;
}
}  // namespace

void CHybridMetricMap::getVisualizationInto(mrpt::opengl::CSetOfObjects& o) const
{
    if (!genericMapParams.enableSaveAs3DObject) return;
    o.insert(triangles(*partition_));
    o.insert(landmarksObject(landmarks_));
    const auto& opt = dense_->options();
    if (opt.enable_occupancy)
    {
        // MRPT's own drawing of a grid: a textured plane at z = 0.
        auto g = mrpt::opengl::CSetOfObjects::Create();
        g->setName("occupancy");
        renderedOccupancy().getVisualizationInto(*g);
        o.insert(g);
    }
    if (opt.enable_points) o.insert(pointsObject(renderedPoints()));
    if (opt.enable_particles)
    {
        mrpt::maps::CPointsMapXYZI particles;
        dense_->renderLayer(ParticlesLayer::kKind, *partition_, particles);
        o.insert(particlesObject(particles));
    }
    if (opt.enable_sog) o.insert(sogObject(dense_->renderSogEllipses(*partition_)));
    if (opt.enable_property)
    {
        ScalarField mean, stddev;
        dense_->renderProperty(*partition_, opt.property.cell_size_m, mean, stddev);
        o.insert(propertyObject(mean));
    }
}

}  // namespace hymm::dense
