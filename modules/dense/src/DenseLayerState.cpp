// The layers' state for a saved run (hymm-slam --save-state / --resume): each layer's
// content with what its next insert reads (voxel set, counters and random streams), bit
// for bit (core/state_archive.h).
#include "hymm/dense/DenseLayer.h"
#include "hymm/dense/LogOddsGrid.h"
#include "hymm/dense/OccupancyLayer.h"
#include "hymm/dense/ParticlesLayer.h"
#include "hymm/dense/PointsLayer.h"
#include "hymm/dense/PropertyLayer.h"
#include "hymm/dense/SogLayer.h"

#include <hymm/core/state_archive.h>

#include <algorithm>
#include <sstream>

namespace hymm::dense
{
using namespace hymm::core::state;

namespace
{
// Capacities too: memoryBytes() reports them (metrics.json, summary.txt), so a resumed
// run must hold the same allocations as the uninterrupted one.
template <class V>
void writeCapacity(mrpt::serialization::CArchive& out, const V& v)
{
    out << static_cast<std::uint64_t>(v.capacity());
}
template <class V>
void reserveFrom(mrpt::serialization::CArchive& in, V& v)
{
    const auto cap = readSize(in, "capacity");
    V fresh;
    fresh.reserve(cap);
    v.swap(fresh);
}
}  // namespace

void DenseLayer::saveState(mrpt::serialization::CArchive&) const
{
    throw std::logic_error("the dense layer '" + kind() + "' cannot be saved in a run state");
}
void DenseLayer::loadState(mrpt::serialization::CArchive&)
{
    throw std::logic_error("the dense layer '" + kind() + "' cannot be read from a run state");
}

void LogOddsGrid::saveState(mrpt::serialization::CArchive& out) const
{
    writeCapacity(out, l_);
    writeCapacity(out, flags_);
    writeCapacity(out, touched_);
    writeMatrix(out, origin_);
    out << static_cast<std::int32_t>(size_x_) << static_cast<std::int32_t>(size_y_) << cell_size_
        << initial_;
    out.WriteBufferFixEndianness(l_.data(), l_.size());
    out.WriteBuffer(flags_.data(), flags_.size());
    writeSize(out, touched_.size());
    for (size_t t : touched_) out << static_cast<std::uint64_t>(t);
}

void LogOddsGrid::loadState(mrpt::serialization::CArchive& in)
{
    reserveFrom(in, l_);
    reserveFrom(in, flags_);
    reserveFrom(in, touched_);
    readMatrix(in, origin_, "grid origin");
    std::int32_t sx = 0, sy = 0;
    in >> sx >> sy >> cell_size_ >> initial_;
    if (sx < 0 || sy < 0 || static_cast<std::uint64_t>(sx) * static_cast<std::uint64_t>(sy) > kMaxCount)
        throw std::runtime_error("corrupt state: grid of " + std::to_string(sx) + " x " + std::to_string(sy));
    size_x_ = sx;
    size_y_ = sy;
    const size_t n = static_cast<size_t>(sx) * static_cast<size_t>(sy);
    l_.resize(n);
    flags_.resize(n);
    in.ReadBufferFixEndianness(l_.data(), n);
    in.ReadBuffer(flags_.data(), n);
    touched_.resize(readSize(in, "touched cell"));
    for (size_t& t : touched_) t = readU64(in);
}

void OccupancyLayer::saveState(mrpt::serialization::CArchive& out) const
{
    grid_.saveState(out);
    out << static_cast<std::int32_t>(render_mode_);
}
void OccupancyLayer::loadState(mrpt::serialization::CArchive& in)
{
    grid_.loadState(in);
    std::int32_t mode = 0;
    in >> mode;
    render_mode_ = static_cast<RenderMode>(mode);
}

void PointsLayer::saveState(mrpt::serialization::CArchive& out) const
{
    const auto& xs = points_.getPointsBufferRef_x();
    const auto& ys = points_.getPointsBufferRef_y();
    const auto& zs = points_.getPointsBufferRef_z();
    writeSize(out, xs.size());
    for (size_t i = 0; i < xs.size(); ++i) out << xs[i] << ys[i] << zs[i];
    std::vector<std::int64_t> voxels(voxels_.begin(), voxels_.end());
    std::sort(voxels.begin(), voxels.end());  // a set: its hash order is not its content
    writeSize(out, voxels.size());
    for (std::int64_t v : voxels) out << v;
    out << static_cast<std::uint64_t>(offered_) << rng_ << static_cast<std::uint64_t>(area_limit_)
        << static_cast<std::uint64_t>(next_area_check_);
}
void PointsLayer::loadState(mrpt::serialization::CArchive& in)
{
    points_.clear();
    const size_t n = readSize(in, "point");
    for (size_t i = 0; i < n; ++i)
    {
        float x = 0, y = 0, z = 0;
        in >> x >> y >> z;
        points_.insertPoint(x, y, z);
    }
    voxels_.clear();
    const size_t nv = readSize(in, "voxel");
    for (size_t i = 0; i < nv; ++i)
    {
        std::int64_t v = 0;
        in >> v;
        voxels_.insert(v);
    }
    offered_ = readU64(in);
    in >> rng_;
    area_limit_ = readU64(in);
    next_area_check_ = readU64(in);
}

void ParticlesLayer::saveState(mrpt::serialization::CArchive& out) const
{
    writeCapacity(out, particles_);
    writeSize(out, particles_.size());
    for (const Particle& p : particles_) out << p.position.x() << p.position.y() << p.weight;
    // std::mt19937_64 streams its whole state as text (the standard's guarantee).
    std::ostringstream rng;
    rng << rng_;
    out << rng.str() << noise_.range_std_m << noise_.bearing_std_rad;
    for (size_t c : {last_.drawn, last_.associated, last_.added, last_.free_updated, last_.free_protected,
                     last_.removed})
        out << static_cast<std::uint64_t>(c);
}
void ParticlesLayer::loadState(mrpt::serialization::CArchive& in)
{
    reserveFrom(in, particles_);
    particles_.resize(readSize(in, "particle"));
    for (Particle& p : particles_) in >> p.position.x() >> p.position.y() >> p.weight;
    std::string rng;
    in >> rng >> noise_.range_std_m >> noise_.bearing_std_rad;
    std::istringstream s(rng);
    s >> rng_;
    if (!s) throw std::runtime_error("corrupt state: particle layer random generator");
    for (size_t* c : {&last_.drawn, &last_.associated, &last_.added, &last_.free_updated,
                      &last_.free_protected, &last_.removed})
        *c = readU64(in);
}

void SogLayer::saveState(mrpt::serialization::CArchive& out) const
{
    writeCapacity(out, gaussians_);
    writeSize(out, gaussians_.size());
    for (const Gaussian& g : gaussians_)
    {
        writeMatrix(out, g.mean);
        writeMatrix(out, g.cov);
    }
}
void SogLayer::loadState(mrpt::serialization::CArchive& in)
{
    reserveFrom(in, gaussians_);
    gaussians_.resize(readSize(in, "Gaussian"));
    for (Gaussian& g : gaussians_)
    {
        readMatrix(in, g.mean, "Gaussian mean");
        readMatrix(in, g.cov, "Gaussian covariance");
    }
}

void PropertyLayer::saveState(mrpt::serialization::CArchive& out) const
{
    const std::map<std::int64_t, Cell> sorted(cells_.begin(), cells_.end());
    out << static_cast<std::uint64_t>(cells_.bucket_count());  // memoryBytes() counts the buckets
    writeSize(out, sorted.size());
    for (const auto& [key, c] : sorted) out << key << c.info << c.weighted << c.count;
}
void PropertyLayer::loadState(mrpt::serialization::CArchive& in)
{
    cells_.clear();
    // rehash() rounds up to its own bucket counts: only a count the map does not have yet.
    if (const size_t buckets = readSize(in, "bucket"); buckets != cells_.bucket_count()) cells_.rehash(buckets);
    const size_t n = readSize(in, "property cell");
    for (size_t i = 0; i < n; ++i)
    {
        std::int64_t key = 0;
        Cell c;
        in >> key >> c.info >> c.weighted >> c.count;
        cells_[key] = c;
    }
}

}  // namespace hymm::dense
