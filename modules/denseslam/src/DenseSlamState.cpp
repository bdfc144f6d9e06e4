// The pipeline's state for a saved run (hymm-slam --save-state / --resume): the filter,
// the dense part (partition, layers, delayed store, classic grid) and the pipeline's own
// counters and bookkeeping, the scan odometry, bit for bit (core/state_archive.h).
#include "hymm/denseslam/DenseSlam.h"

#include <hymm/core/state_archive.h>
#include <mrpt/rtti/CObject.h>

#include <algorithm>

namespace hymm::denseslam
{
using namespace hymm::core::state;

namespace
{
/** Every counter of DenseSlam::Stats but the map of unsupported classes, in a fixed order
 *  (the state's layout: a new counter goes at the end, with a new state version). */
std::vector<size_t*> counters(DenseSlam::Stats& s)
{
    return {&s.entries, &s.predictions, &s.frames, &s.observations, &s.associated, &s.created,
            &s.rejected_gate, &s.ambiguous, &s.rejected_numeric, &s.skipped_invalid, &s.scans,
            &s.extracted, &s.observations_with_id, &s.partition_updates, &s.regions_created, &s.regions_removed,
            &s.dense_scans, &s.returns_stored, &s.returns_outside, &s.returns_fallback,
            &s.returns_dropped, &s.returns_withheld_fallback, &s.returns_withheld, &s.no_return_beams,
            &s.failed_readings, &s.virtual_landmarks, &s.virtual_rejected, &s.delayed_stored,
            &s.delayed_fused, &s.delayed_fused_fallback, &s.delayed_outside_potential,
            &s.delayed_thinned, &s.delayed_evicted, &s.delayed_lost, &s.rawlog_observations,
            &s.observations_unused, &s.time_backwards, &s.time_repeated, &s.odometry_invalid,
            &s.frames_duplicate, &s.frames_without_odometry, &s.scans_without_valid_beam,
            &s.observations_invalid_geometry};
}

/** Counts by point source: every key a registered source (LandmarkSources.h). */
void requirePointSources(const std::map<std::string, size_t>& counts)
{
    for (const auto& [name, n] : counts)
        if (!findPointSourceKind(name))
            throw std::runtime_error("corrupt state: unknown point source '" + name.substr(0, 60) + "'");
}

void writeStats(mrpt::serialization::CArchive& out, const DenseSlam::Stats& stats)
{
    auto s = stats;
    writeCounters(out, counters(s));
    writeCounts(out, s.unsupported);
    writeCounts(out, s.point_features);
    writeCounts(out, s.point_duplicates);
}

DenseSlam::Stats readStats(mrpt::serialization::CArchive& in)
{
    DenseSlam::Stats s;
    readCounters(in, counters(s), "counter");
    readCounts(in, s.unsupported, "unsupported class");
    readCounts(in, s.point_features, "point source");
    readCounts(in, s.point_duplicates, "point source");
    requirePointSources(s.point_features);
    requirePointSources(s.point_duplicates);
    return s;
}

// Class names of the duplicate-frame signature point into MRPT's class registry.
const char* registeredClassName(const std::string& name)
{
    const auto* c = mrpt::rtti::findRegisteredClass(name);
    if (!c) throw std::runtime_error("corrupt state: unknown observation class '" + name.substr(0, 60) + "'");
    return c->className;
}
}  // namespace

void DenseSlam::saveState(mrpt::serialization::CArchive& out) const
{
    writeTag(out, "DenseSlam");
    ekf_.saveState(out);
    writeSize(out, path_.size());
    for (const PathSample& p : path_)
    {
        out << p.t;
        writeMatrix(out, p.pose);
        writeMatrix(out, p.cov);
    }
    std::vector<std::int64_t> cells;
    for (const auto& kv : outside_) cells.push_back(kv.first);
    std::sort(cells.begin(), cells.end());
    writeSize(out, cells.size());
    for (std::int64_t k : cells)
    {
        const OutsideSum& o = outside_.at(k);
        out << k << o.sum.x() << o.sum.y() << static_cast<std::uint64_t>(o.returns)
            << static_cast<std::uint64_t>(o.kept);
    }
    writeStats(out, stats_);
    writeSize(out, features_.size());
    for (const auto& [id, f] : features_)
    {
        writeLong(out, id);
        out << f.created_by;
        writeCounts(out, f.observations);
        out << f.first_t << f.last_t;
    }
    out << last_odometry_.has_value();
    if (last_odometry_) out << last_odometry_->x() << last_odometry_->y() << last_odometry_->phi();
    out << static_cast<std::uint64_t>(updates_) << frame_t_ << last_stamp_.has_value()
        << last_stamp_.value_or(0.0);
    writeSize(out, last_frame_signature_.size());
    for (const auto& [name, stamp] : last_frame_signature_)
        out << std::string(name) << static_cast<std::int64_t>(stamp.time_since_epoch().count());
    out << static_cast<std::uint64_t>(predictions_at_last_frame_);
    writeIds(out, std::vector<long>(virtual_ids_.begin(), virtual_ids_.end()));
    writeLong(out, next_virtual_id_);
    saveOdometryState(out);
    saveDenseState(out);
}

void DenseSlam::saveOdometryState(mrpt::serialization::CArchive& out) const
{
    // The wheels' increment held for the next scan, the scan odometry (reference scan,
    // filters) and the turn bias state's counters; the bias and the vehicle's copy at the
    // reference scan are blocks of the filter, saved with it.
    out << pending_odometry_.has_value();
    if (pending_odometry_) scanslam::saveIncrement(out, *pending_odometry_);
    out << bool(scan_odometry_);
    if (scan_odometry_) scan_odometry_->saveState(out);
    TurnBiasStats t = turn_bias_stats_;
    writeCounters(out, {&t.copies, &t.fused, &t.gated, &t.failed});
}

void DenseSlam::loadOdometryState(mrpt::serialization::CArchive& in)
{
    pending_odometry_.reset();
    if (readBool(in)) pending_odometry_ = scanslam::loadIncrement(in, "pending odometry");
    if (readBool(in) != bool(scan_odometry_))
        throw std::runtime_error("the state's scan odometry differs from the config's ([ScanOdometry] enabled)");
    if (scan_odometry_) scan_odometry_->loadState(in);
    if (pending_odometry_ && !scan_odometry_)
        throw std::runtime_error("corrupt state: pending odometry without scan odometry");
    TurnBiasStats& t = turn_bias_stats_;
    readCounters(in, {&t.copies, &t.fused, &t.gated, &t.failed}, "turn bias counter");
}

void DenseSlam::saveDenseState(mrpt::serialization::CArchive& out) const
{
    out << bool(partition_) << bool(hybrid_) << bool(store_) << bool(classic_);
    if (partition_) partition_->saveState(out);
    if (hybrid_) hybrid_->saveState(out);
    if (store_) store_->saveState(out);
    if (classic_) classic_->saveState(out);
    out << bool(motion_);
    if (motion_) motion_->saveState(out);
    writeSize(out, sources_.size());
    for (const auto& s : sources_)
    {
        out << s->name();
        s->saveState(out);
    }
    out << bool(hll_);
    if (hll_) hll_->saveState(out);
    writeTag(out, "DenseSlam end");
}

void DenseSlam::loadState(mrpt::serialization::CArchive& in)
{
    expectTag(in, "DenseSlam");
    ekf_.loadState(in);
    path_.resize(readSize(in, "path sample"));
    for (PathSample& p : path_)
    {
        in >> p.t;
        readMatrix(in, p.pose, "path pose");
        readMatrix(in, p.cov, "path covariance");
    }
    outside_.clear();
    const size_t nc = readSize(in, "outside cell");
    for (size_t i = 0; i < nc; ++i)
    {
        std::int64_t k = 0;
        OutsideSum o;
        in >> k >> o.sum.x() >> o.sum.y();
        o.returns = readU64(in);
        o.kept = readU64(in);
        outside_[k] = o;
    }
    stats_ = readStats(in);
    features_.clear();
    const size_t nf = readSize(in, "landmark feature record");
    for (size_t i = 0; i < nf; ++i)
    {
        LandmarkFeatures f;
        const long id = readLong(in);
        in >> f.created_by;
        if (!findPointSourceKind(f.created_by))
            throw std::runtime_error("corrupt state: unknown point source '" + f.created_by.substr(0, 60) + "'");
        readCounts(in, f.observations, "point source");
        requirePointSources(f.observations);
        in >> f.first_t >> f.last_t;
        features_[id] = f;
    }
    loadBookkeeping(in);
    loadOdometryState(in);
    loadDenseState(in);
}

void DenseSlam::loadBookkeeping(mrpt::serialization::CArchive& in)
{
    last_odometry_.reset();
    if (readBool(in))
    {
        const double x = readDouble(in), y = readDouble(in), phi = readDouble(in);
        last_odometry_ = mrpt::poses::CPose2D(x, y, phi);
    }
    updates_ = readU64(in);
    in >> frame_t_;
    const bool stamped = readBool(in);
    const double stamp = readDouble(in);
    last_stamp_.reset();
    if (stamped) last_stamp_ = stamp;
    last_frame_signature_.resize(readSize(in, "frame signature"));
    for (auto& [name, stamp_tp] : last_frame_signature_)
    {
        std::string n;
        std::int64_t ticks = 0;
        in >> n >> ticks;
        name = registeredClassName(n);
        stamp_tp = mrpt::Clock::time_point(mrpt::Clock::duration(ticks));
    }
    predictions_at_last_frame_ = readU64(in);
    const std::vector<long> ids = readIds(in, "virtual landmark");
    virtual_ids_ = std::set<long>(ids.begin(), ids.end());
    next_virtual_id_ = readLong(in);
}

void DenseSlam::loadDenseState(mrpt::serialization::CArchive& in)
{
    const bool partition = readBool(in), hybrid = readBool(in), store = readBool(in), classic = readBool(in);
    if (partition != bool(partition_) || hybrid != bool(hybrid_) || store != bool(store_) ||
        classic != bool(classic_))
        throw std::runtime_error("the state's dense layers, delayed store or classic grid differ from the config's");
    if (partition_) partition_->loadState(in);
    if (hybrid_) hybrid_->loadState(in);
    if (store_) store_->loadState(in);
    if (classic_) classic_->loadState(in);
    if (readBool(in) != bool(motion_))
        throw std::runtime_error("the state's motion layers differ from the config's ([DynamicSlam] enabled)");
    if (motion_) motion_->loadState(in);
    if (readSize(in, "landmark source") != sources_.size())
        throw std::runtime_error("the state's landmark sources differ from the config's (landmark_source)");
    for (const auto& s : sources_)
    {
        std::string name;
        in >> name;
        if (name != s->name())
            throw std::runtime_error("the state's landmark source '" + name.substr(0, 40) +
                                     "' differs from the config's '" + s->name() + "'");
        s->loadState(in);
    }
    if (readBool(in) != bool(hll_))
        throw std::runtime_error("the state's high-level landmarks differ from the config's ([HighLevelLandmarks] enabled)");
    if (hll_) hll_->loadState(in);
    expectTag(in, "DenseSlam end");
}

}  // namespace hymm::denseslam
