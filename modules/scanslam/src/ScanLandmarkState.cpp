// Scan-SLAM's state for a saved run (hymm-slam --save-state / --resume): every value bit
// for bit (core/state_archive.h), including the acceptance test's random generator, so a
// resumed run creates and observes exactly the landmarks the uninterrupted one would; and
// the scan odometry's reference scan and filters, so it fuses the same steps.
#include <hymm/core/state_archive.h>

#include <cmath>
#include <cstring>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <type_traits>

#include "hymm/scanslam/ScanLandmarkMap.h"
#include "hymm/scanslam/ScanOdometry.h"
#include "hymm/scanslam/ScanTemplate.h"
#include "hymm/scanslam/SegmentAcceptance.h"

namespace hymm::scanslam
{
using namespace hymm::core::state;

namespace
{
template <class V>
void writeVectors(mrpt::serialization::CArchive& out, const std::vector<V>& v)
{
    writeSize(out, v.size());
    for (const auto& x : v) writeMatrix(out, x);
}
template <class V>
void readVectors(mrpt::serialization::CArchive& in, std::vector<V>& v, const char* what)
{
    v.resize(readSize(in, what));
    for (auto& x : v) readMatrix(in, x, what);
}
/** ScanLandmarkMap's apparent-pose blocks (view_corr_model = state): landmark -> block,
 *  viewpoint of its last step, fused viewpoints before it existed. */
template <class Map>
void writeApparent(mrpt::serialization::CArchive& out, const Map& apparent)
{
    writeSize(out, apparent.size());
    for (const auto& [id, a] : apparent)
    {
        writeLong(out, id);
        writeLong(out, a.block);
        writeMatrix(out, a.view);
        out << static_cast<std::uint64_t>(a.first_view);
    }
}
template <class Map>
void readApparent(mrpt::serialization::CArchive& in, Map& apparent)
{
    apparent.clear();
    const size_t n = readSize(in, "apparent pose block");
    for (size_t i = 0; i < n; ++i)
    {
        auto& a = apparent[readLong(in)];
        a.block = readLong(in);
        readMatrix(in, a.view, "apparent pose viewpoint");
        a.first_view = readU64(in);
    }
}
/** Every plain counter of ScanLandmarkMap::Stats, in the state's order (a new counter
 *  goes at the end, with a new state version). */
std::vector<size_t*> counters(ScanLandmarkMap::Stats& s)
{
    return {&s.scans, &s.scans_empty, &s.beams_invalid, &s.predicted, &s.out_of_view, &s.view_changed,
            &s.prediction_uncertain, &s.aligned, &s.updated, &s.gated, &s.update_numeric,
            &s.update_invalid, &s.returns_explained, &s.segments, &s.short_runs, &s.segments_far,
            &s.segments_collinear, &s.creation_failed, &s.created, &s.augmented, &s.augment_points,
            &s.augment_empty, &s.merge_candidates, &s.merge_align_failed, &s.merge_gated, &s.merged};
}

/** A distribution's state through its standard stream form (exact for the real ones:
 *  the library writes max_digits10 digits). */
template <class D>
std::string distributionText(const D& d)
{
    std::ostringstream os;
    os.imbue(std::locale::classic());
    os << d;
    return os.str();
}
template <class D>
void readDistribution(const std::string& text, D& d)
{
    std::istringstream is(text);
    is.imbue(std::locale::classic());
    is >> d;
    if (!is) throw std::runtime_error("corrupt state: random distribution '" + text.substr(0, 40) + "'");
}
}  // namespace

void savePointSet(mrpt::serialization::CArchive& out, const PointSet& p)
{
    writeVectors(out, p.points);
    writeVectors(out, p.covs);
    writeValues(out, p.range);
    writeValues(out, p.bearing);
}

void loadPointSet(mrpt::serialization::CArchive& in, PointSet& p)
{
    readVectors(in, p.points, "template point");
    readVectors(in, p.covs, "template covariance");
    readValues(in, p.range, "template range");
    readValues(in, p.bearing, "template bearing");
    if (p.covs.size() != p.points.size() || (!p.range.empty() && p.range.size() != p.points.size()) ||
        (!p.bearing.empty() && p.bearing.size() != p.points.size()))
        throw std::runtime_error("corrupt state: template point lists of different sizes");
}

void ScanTemplate::saveState(mrpt::serialization::CArchive& out) const
{
    savePointSet(out, sog);
    writeMatrix(out, frame_in_sensor);
}

void ScanTemplate::loadState(mrpt::serialization::CArchive& in)
{
    loadPointSet(in, sog);
    readMatrix(in, frame_in_sensor, "template frame");
}

void SegmentAcceptance::SavableRandom::save(mrpt::serialization::CArchive& out) const
{
    // MRPT keeps the MT19937 words private in a plain class: its bytes are its state.
    static_assert(std::is_trivially_copyable_v<mrpt::random::Generator_MT19937>);
    std::string bytes(sizeof(m_MT19937), '\0');
    std::memcpy(bytes.data(), &m_MT19937, sizeof(m_MT19937));
    out << bytes << distributionText(m_normdistribution) << distributionText(m_uint32)
        << distributionText(m_uint64);
}

void SegmentAcceptance::SavableRandom::load(mrpt::serialization::CArchive& in)
{
    std::string bytes, normal, u32, u64;
    in >> bytes >> normal >> u32 >> u64;
    if (bytes.size() != sizeof(m_MT19937))
        throw std::runtime_error("corrupt state: random generator of " + std::to_string(bytes.size()) + " bytes");
    std::memcpy(&m_MT19937, bytes.data(), sizeof(m_MT19937));
    readDistribution(normal, m_normdistribution);
    readDistribution(u32, m_uint32);
    readDistribution(u64, m_uint64);
}

void SegmentAcceptance::saveState(mrpt::serialization::CArchive& out) const
{
    writeSize(out, stats_.count.size());
    for (size_t c : stats_.count) out << static_cast<std::uint64_t>(c);
    rng_.save(out);
}

void SegmentAcceptance::loadState(mrpt::serialization::CArchive& in)
{
    if (readSize(in, "acceptance outcome") != stats_.count.size())
        throw std::runtime_error("corrupt state: acceptance outcome list");
    for (size_t& c : stats_.count) c = readU64(in);
    rng_.load(in);
}

void ScanLandmarkMap::saveState(mrpt::serialization::CArchive& out) const
{
    writeTag(out, "ScanLandmarkMap");
    writeSize(out, templates_.size());
    for (const auto& [id, tpl] : templates_)
    {
        writeLong(out, id);
        tpl.saveState(out);
    }
    auto s = stats_;
    writeCounters(out, counters(s));
    writeCounts(out, s.align_failed);
    writeSize(out, s.acceptance.size());
    for (size_t n : s.acceptance) out << static_cast<std::uint64_t>(n);
    writeCounts(out, s.wide);
    acceptance_.saveState(out);
    // The wide search's bookkeeping: last search per landmark and the answer waiting for a
    // second template's confirmation (the per-scan budget restarts with every scan).
    writeSize(out, wide_last_.size());
    for (const auto& [id, scan] : wide_last_)
    {
        writeLong(out, id);
        out << static_cast<std::uint64_t>(scan);
    }
    writeSize(out, merge_last_.size());
    for (const auto& [pair, scan] : merge_last_)
    {
        writeLong(out, pair.first);
        writeLong(out, pair.second);
        out << static_cast<std::uint64_t>(scan);
    }
    writeLong(out, wide_pending_.id);
    out << static_cast<std::uint64_t>(wide_pending_.scan);
    writeMatrix(out, wide_pending_.correction);
    writeSize(out, last_aligned_.size());
    for (const AlignedObservation& a : last_aligned_)
    {
        writeLong(out, a.id);
        writeMatrix(out, a.z);
        writeMatrix(out, a.R);
        writeMatrix(out, a.z_hat);
        out << a.updated << a.wide;
    }
    writeSize(out, fused_views_.size());  // the fused viewpoints of view_corr_share (state version 9)
    for (const auto& [id, views] : fused_views_)
    {
        writeLong(out, id);
        writeVectors(out, views);
    }
    writeApparent(out, apparent_);  // state version 10
    // The returns of the templates' first scans (wide_max_free_conflict; version 11).
    writeSize(out, first_scans_.size());
    for (const auto& [id, returns] : first_scans_)
    {
        writeLong(out, id);
        writeVectors(out, returns);
    }
    revisits_.save(out);  // state version 12
    writeTag(out, "ScanLandmarkMap end");
}

void ScanLandmarkMap::loadState(mrpt::serialization::CArchive& in)
{
    expectTag(in, "ScanLandmarkMap");
    templates_.clear();
    const size_t n = readSize(in, "scan template");
    for (size_t i = 0; i < n; ++i)
    {
        const long id = readLong(in);
        templates_[id].loadState(in);
    }
    stats_ = Stats{};
    readCounters(in, counters(stats_), "scan landmark counter");
    readCounts(in, stats_.align_failed, "alignment failure reason");
    if (readSize(in, "acceptance outcome") != stats_.acceptance.size())
        throw std::runtime_error("corrupt state: acceptance outcome list");
    for (size_t& v : stats_.acceptance) v = readU64(in);
    readCounts(in, stats_.wide, "wide search outcome");
    acceptance_.loadState(in);
    wide_last_.clear();
    const size_t nl = readSize(in, "wide search landmark");
    for (size_t i = 0; i < nl; ++i)
    {
        const long id = readLong(in);
        wide_last_[id] = readU64(in);
    }
    merge_last_.clear();
    const size_t nm = readSize(in, "merge attempt");
    for (size_t i = 0; i < nm; ++i)
    {
        const long keep = readLong(in);
        const long drop = readLong(in);
        merge_last_[{keep, drop}] = readU64(in);
    }
    wide_pending_.id = readLong(in);
    wide_pending_.scan = readU64(in);
    readMatrix(in, wide_pending_.correction, "pending wide correction");
    last_aligned_.resize(readSize(in, "aligned observation"));
    for (AlignedObservation& a : last_aligned_)
    {
        a.id = readLong(in);
        readMatrix(in, a.z, "aligned observation");
        readMatrix(in, a.R, "aligned observation covariance");
        readMatrix(in, a.z_hat, "aligned prediction");
        a.updated = readBool(in);
        a.wide = readBool(in);
    }
    fused_views_.clear();
    const size_t nv = readSize(in, "fused viewpoint landmark");
    for (size_t i = 0; i < nv; ++i) readVectors(in, fused_views_[readLong(in)], "fused viewpoint");
    readApparent(in, apparent_);
    first_scans_.clear();
    const size_t nf = readSize(in, "template first scan");
    for (size_t i = 0; i < nf; ++i) readVectors(in, first_scans_[readLong(in)], "template first scan return");
    revisits_.load(in);
    expectTag(in, "ScanLandmarkMap end");
}

namespace
{
/** Every plain counter of ScanOdometry::Stats, in the state's order. */
std::vector<size_t*> counters(ScanOdometry::Stats& s)
{
    return {&s.scans, &s.no_reference, &s.too_few_points, &s.gated, &s.fused,
            &s.keyframes, &s.bias_updates, &s.bias_gated, &s.bias_applied, &s.growth_clamped};
}
}  // namespace

void saveIncrement(mrpt::serialization::CArchive& out, const ScanOdometry::Increment& i)
{
    writeMatrix(out, i.mean);
    writeMatrix(out, i.cov);
}

ScanOdometry::Increment loadIncrement(mrpt::serialization::CArchive& in, const char* what)
{
    ScanOdometry::Increment i;
    readMatrix(in, i.mean, what);
    readMatrix(in, i.cov, what);
    if (!i.mean.allFinite() || !i.cov.allFinite())
        throw std::runtime_error(std::string("corrupt state: ") + what + " is not finite");
    return i;
}

void ScanOdometry::saveState(mrpt::serialization::CArchive& out) const
{
    writeTag(out, "ScanOdometry");
    Stats stats = stats_;
    writeCounters(out, counters(stats));
    writeCounts(out, stats_.align_failed);
    out << has_reference_;
    savePointSet(out, reference_);
    writeMatrix(out, reference_mount_);
    saveIncrement(out, since_reference_);
    out << reference_is_previous_;
    writeMatrix(out, handed_cov_);
    saveIncrement(out, wheel_since_reference_);
    out << wheel_distance_since_reference_;
    out << turn_observation_.has_value();
    if (turn_observation_) out << turn_observation_->e << turn_observation_->ds << turn_observation_->var;
    out << last_relative_.has_value();
    if (last_relative_) saveIncrement(out, *last_relative_);
    out << last_is_reference_ << turn_bias_ << turn_bias_var_;
    writeTag(out, "ScanOdometry end");
}

void ScanOdometry::loadState(mrpt::serialization::CArchive& in)
{
    // Read into a copy first: a corrupt state leaves this one as it was.
    ScanOdometry::Stats stats;
    expectTag(in, "ScanOdometry");
    readCounters(in, counters(stats), "scan odometry counter");
    readCounts(in, stats.align_failed, "scan odometry failure reason");
    const bool has_reference = readBool(in);
    PointSet reference;
    loadPointSet(in, reference);
    Vec3 mount;
    readMatrix(in, mount, "scan odometry mount");
    const Increment since = loadIncrement(in, "scan odometry pose since the reference");
    const bool reference_is_previous = readBool(in);
    Mat3 handed_cov;
    readMatrix(in, handed_cov, "scan odometry steps since the reference");
    const Increment wheel_since = loadIncrement(in, "scan odometry wheels since the reference");
    const double wheel_distance = readDouble(in);
    std::optional<TurnObservation> turn;
    if (readBool(in))
    {
        TurnObservation t;
        in >> t.e >> t.ds >> t.var;
        turn = t;
    }
    std::optional<Increment> last_relative;
    if (readBool(in)) last_relative = loadIncrement(in, "scan odometry last alignment");
    const bool last_is_reference = readBool(in);
    const double bias = readDouble(in), bias_var = readDouble(in);
    expectTag(in, "ScanOdometry end");
    if (!std::isfinite(wheel_distance) || !std::isfinite(bias) || !(bias_var >= 0) || !mount.allFinite() ||
        !handed_cov.allFinite())
        throw std::runtime_error("corrupt state: scan odometry values are not finite");
    stats_ = std::move(stats);
    has_reference_ = has_reference;
    reference_ = std::move(reference);
    reference_mount_ = mount;
    since_reference_ = since;
    reference_is_previous_ = reference_is_previous;
    handed_cov_ = handed_cov;
    wheel_since_reference_ = wheel_since;
    wheel_distance_since_reference_ = wheel_distance;
    turn_observation_ = turn;
    last_relative_ = last_relative;
    last_is_reference_ = last_is_reference;
    turn_bias_ = bias;
    turn_bias_var_ = bias_var;
}

}  // namespace hymm::scanslam
