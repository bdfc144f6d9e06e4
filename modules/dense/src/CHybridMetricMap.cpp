// The hybrid metric map as an MRPT CMetricMap: map factory registration, copies,
// serialisation, insertion and the observation likelihood. Drawing: CHybridMetricMapScene.cpp.
#include "hymm/dense/CHybridMetricMap.h"

#include "hybrid_map_text.h"

#include <hymm/core/config_utils.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/rtti/CObject.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/filesystem.h>

#include <fstream>
#include <sstream>
#include <stdexcept>

using hymm::ltr::RegionPartition;

//  Map factory: "[MAP] HybridMetricMap_count = 1" in a CMultiMetricMap .ini; MRPT looks a
//  definition up by its full class name, hence that one too.
MAP_DEFINITION_REGISTER("hymm::dense::CHybridMetricMap,CHybridMetricMap,HybridMetricMap", hymm::dense::CHybridMetricMap)

IMPLEMENTS_SERIALIZABLE(CHybridMetricMap, CMetricMap, hymm::dense)

namespace hymm::dense
{
using namespace hymm::dense::text;  // hybrid_map_text.h

namespace
{
// Formats of serializeTo(): 0 without fallback tiles, 1 with them (their text after the
// likelihood options); readers take both and refuse any other version.
constexpr uint8_t kSerialVersion = 1;

// MRPT 2.5's TLikelihoodOptions can be read from an .ini but not written: field by field.
using LikelihoodOptions = mrpt::maps::COccupancyGridMap2D::TLikelihoodOptions;
void writeLikelihoodOptions(mrpt::serialization::CArchive& out, const LikelihoodOptions& o)
{
    out << static_cast<int32_t>(o.likelihoodMethod) << o.LF_stdHit << o.LF_zHit << o.LF_zRandom
        << o.LF_maxRange << o.LF_decimation << o.LF_maxCorrsDistance << o.LF_useSquareDist
        << o.LF_alternateAverageMethod << o.MI_exponent << o.MI_skip_rays << o.MI_ratio_max_distance
        << o.rayTracing_useDistanceFilter << o.rayTracing_decimation << o.rayTracing_stdHit
        << o.consensus_takeEachRange << o.consensus_pow << o.OWA_weights << o.enableLikelihoodCache;
}

void readLikelihoodOptions(mrpt::serialization::CArchive& in, LikelihoodOptions& o)
{
    int32_t method = 0;
    in >> method >> o.LF_stdHit >> o.LF_zHit >> o.LF_zRandom >> o.LF_maxRange >> o.LF_decimation >>
        o.LF_maxCorrsDistance >> o.LF_useSquareDist >> o.LF_alternateAverageMethod >> o.MI_exponent >>
        o.MI_skip_rays >> o.MI_ratio_max_distance >> o.rayTracing_useDistanceFilter >>
        o.rayTracing_decimation >> o.rayTracing_stdHit >> o.consensus_takeEachRange >> o.consensus_pow >>
        o.OWA_weights >> o.enableLikelihoodCache;
    o.likelihoodMethod = static_cast<mrpt::maps::COccupancyGridMap2D::TLikelihoodMethod>(method);
}
}  // namespace

// --- map definition -------------------------------------------------------------------
constexpr double kMaxLikelihoodResolution = 10.0;  // [m] coarser is no map of a robot's world
CHybridMetricMap::TMapDefinition::TMapDefinition() = default;

void CHybridMetricMap::TMapDefinition::loadFromConfigFile_map_specific(
    const mrpt::config::CConfigFileBase& source, const std::string& prefix)
{
    map_file = source.read_string(prefix, "map_file", map_file);
    // The strict reader, not MRPT's read_double (which takes "0.1m" as 0.1 and "abc" as
    // 0): errors quote the value as written.
    const char* key = "likelihood_resolution_m";
    likelihood_resolution_m = core::readDouble(source, prefix, key, likelihood_resolution_m);
    if (!(likelihood_resolution_m >= 0 && likelihood_resolution_m <= kMaxLikelihoodResolution))
        core::throwConfigError(prefix, key, core::readString(source, prefix, key, ""), "must be in [0, 10] m");
    likelihoodOpts.loadFromConfigFile(source, prefix + "_likelihoodOpts");
    dense_options.loadFromConfigFile(source, prefix + "_HybridMetricMap");
    dense_options.validate(prefix + "_HybridMetricMap");
}

void CHybridMetricMap::TMapDefinition::dumpToTextStream_map_specific(std::ostream& out) const
{
    out << "map_file                = " << (map_file.empty() ? "(none: empty map)" : map_file) << "\n"
        << "likelihood_resolution_m = " << likelihood_resolution_m << "\n";
    likelihoodOpts.dumpToTextStream(out);
}

mrpt::maps::CMetricMap* CHybridMetricMap::internal_CreateFromMapDefinition(
    const mrpt::maps::TMetricMapInitializer& _def)
{
    const auto& def = dynamic_cast<const CHybridMetricMap::TMapDefinition&>(_def);
    CHybridMetricMap* m = nullptr;
    if (def.map_file.empty())
        m = new CHybridMetricMap(def.dense_options);
    else
        m = new CHybridMetricMap(*loadFromFile(def.map_file));
    m->likelihoodOptions = def.likelihoodOpts;
    m->likelihood_resolution_m = def.likelihood_resolution_m;
    m->genericMapParams = def.genericMapParams;
    return m;
}

mrpt::maps::COccupancyGridMap2D freeProbabilityGrid(const mrpt::maps::COccupancyGridMap2D& occupied)
{
    mrpt::maps::COccupancyGridMap2D out(occupied.getXMin(), occupied.getXMax(), occupied.getYMin(),
                                        occupied.getYMax(), occupied.getResolution());
    for (unsigned cy = 0; cy < out.getSizeY(); ++cy)
        for (unsigned cx = 0; cx < out.getSizeX(); ++cx)
        {
            const int x = static_cast<int>(cx), y = static_cast<int>(cy);
            out.setCell(x, y, 1.0f - occupied.getCell(x, y));
        }
    return out;
}

void registerHybridMetricMap()
{
    // Touching the factory id keeps this object file, and so the registration, linked.
    static const bool done = [] {
        mrpt::rtti::registerClass(CLASS_ID(CHybridMetricMap));
        (void)CHybridMetricMap::m_private_map_register_id;
        return true;
    }();
    (void)done;
}

// --- construction and copies -------------------------------------------------------------
CHybridMetricMap::CHybridMetricMap() : CHybridMetricMap(HybridMetricMap::Options{}) {}

CHybridMetricMap::CHybridMetricMap(const HybridMetricMap::Options& options)
    : partition_(std::make_unique<RegionPartition>(RegionPartition::Options{})),
      dense_(std::make_unique<HybridMetricMap>(options))
{
}

CHybridMetricMap::CHybridMetricMap(const CHybridMetricMap& other) : CMetricMap(other)
{
    copyFrom(other);
}

CHybridMetricMap& CHybridMetricMap::operator=(const CHybridMetricMap& other)
{
    if (this != &other)
    {
        CMetricMap::operator=(other);
        copyFrom(other);
    }
    return *this;
}

CHybridMetricMap::~CHybridMetricMap() = default;

void CHybridMetricMap::copyFrom(const CHybridMetricMap& other)
{
    // Partition and layers are not copyable (they own grids and indices); their exact
    // text round trip is the copy.
    partition_ = partitionFrom(
        iniText([&](auto& c) { other.partition_->options().saveToConfigFile(c, "LtrPartition"); }),
        partitionText(*other.partition_));
    dense_ = denseFrom(iniText([&](auto& c) { other.dense_->options().saveAll(c); }),
                       denseText(*other.dense_), fallbackText(*other.dense_));
    landmarks_ = other.landmarks_;
    likelihoodOptions = other.likelihoodOptions;
    likelihood_resolution_m = other.likelihood_resolution_m;
    invalidateCache();
}

void CHybridMetricMap::assign(const RegionPartition& partition, const HybridMetricMap& dense,
                              std::vector<Landmark> landmarks)
{
    partition_ = partitionFrom(
        iniText([&](auto& c) { partition.options().saveToConfigFile(c, "LtrPartition"); }),
        partitionText(partition));
    dense_ = denseFrom(iniText([&](auto& c) { dense.options().saveAll(c); }), denseText(dense),
                       fallbackText(dense));
    landmarks_ = std::move(landmarks);
    invalidateCache();
}

void CHybridMetricMap::invalidateCache()
{
    std::lock_guard<std::mutex> lock(cache_mutex_);
    grid_cache_.reset();
    points_cache_.reset();
}

// --- renderings --------------------------------------------------------------------------
const mrpt::maps::COccupancyGridMap2D& CHybridMetricMap::renderedOccupancy() const
{
    std::lock_guard<std::mutex> lock(cache_mutex_);
    if (!grid_cache_)
    {
        auto g = std::make_unique<mrpt::maps::COccupancyGridMap2D>();
        const double res = likelihood_resolution_m > 0 ? likelihood_resolution_m
                                                       : dense_->options().occupancy.cell_size_m;
        if (dense_->options().enable_occupancy)
        {
            mrpt::maps::COccupancyGridMap2D occupied;
            dense_->renderOccupancy(*partition_, res, occupied);
            *g = freeProbabilityGrid(occupied);
        }
        g->likelihoodOptions = likelihoodOptions;
        grid_cache_ = std::move(g);
    }
    grid_cache_->likelihoodOptions = likelihoodOptions;  // the caller may have changed them
    return *grid_cache_;
}

const mrpt::maps::CSimplePointsMap& CHybridMetricMap::renderedPoints() const
{
    std::lock_guard<std::mutex> lock(cache_mutex_);
    if (!points_cache_)
    {
        auto p = std::make_unique<mrpt::maps::CSimplePointsMap>();
        if (dense_->options().enable_points) dense_->renderPoints(*partition_, *p);
        points_cache_ = std::move(p);
    }
    return *points_cache_;
}

// --- CMetricMap ---------------------------------------------------------------------------
void CHybridMetricMap::internal_clear()
{
    // Keeps the partition and the landmarks (the frame the layers live in); drops content.
    dense_ = std::make_unique<HybridMetricMap>(dense_->options());
    invalidateCache();
}

bool CHybridMetricMap::isEmpty() const { return dense_->size() == 0; }

std::string CHybridMetricMap::asString() const
{
    std::ostringstream s;
    s << "hymm::dense::CHybridMetricMap: " << partition_->size() << " regions, " << landmarks_.size()
      << " landmarks, " << dense_->size() << " regions with dense content (layers:";
    for (const auto& k : dense_->enabledKinds()) s << ' ' << k;
    s << ")";
    return s.str();
}

bool CHybridMetricMap::internal_insertObservation(
    const mrpt::obs::CObservation& obs, const std::optional<const mrpt::poses::CPose3D>& robotPose)
{
    const auto* scan = dynamic_cast<const mrpt::obs::CObservation2DRangeScan*>(&obs);
    if (!scan || partition_->size() == 0) return false;
    const mrpt::math::TPose2D pose =
        robotPose ? mrpt::math::TPose2D(robotPose->x(), robotPose->y(), robotPose->yaw())
                  : mrpt::math::TPose2D(0, 0, 0);
    const auto stats = dense_->insertScan(ScanPoints::fromRangeScan(*scan), pose, *partition_);
    if (stats.regions_updated == 0) return false;
    invalidateCache();
    return true;
}

bool CHybridMetricMap::internal_canComputeObservationLikelihood(const mrpt::obs::CObservation& obs) const
{
    return dynamic_cast<const mrpt::obs::CObservation2DRangeScan*>(&obs) != nullptr &&
           (dense_->options().enable_occupancy || dense_->options().enable_points) && !isEmpty();
}

double CHybridMetricMap::internal_computeObservationLikelihood(
    const mrpt::obs::CObservation& obs, const mrpt::poses::CPose3D& takenFrom) const
{
    if (!internal_canComputeObservationLikelihood(obs)) return 0;  // log-likelihood: no information
    // MRPT's sensor models on the map rendered at the current landmark estimates.
    if (dense_->options().enable_occupancy)
        return renderedOccupancy().computeObservationLikelihood(obs, takenFrom);
    return renderedPoints().computeObservationLikelihood(obs, takenFrom);
}

// --- serialisation ------------------------------------------------------------------------
uint8_t CHybridMetricMap::serializeGetVersion() const
{
    // Version 0 while there is no fallback tile: such maps stay readable by older HYMM.
    return dense_->fallbackTiles() > 0 ? kSerialVersion : 0;
}

void CHybridMetricMap::serializeTo(mrpt::serialization::CArchive& out) const
{
    out << genericMapParams;
    out << iniText([&](auto& c) { partition_->options().saveToConfigFile(c, "LtrPartition"); })
        << partitionText(*partition_);
    out << iniText([&](auto& c) { dense_->options().saveAll(c); }) << denseText(*dense_);
    out << static_cast<uint32_t>(landmarks_.size());
    for (const auto& l : landmarks_)
        out << static_cast<int64_t>(l.id) << l.mean.x() << l.mean.y() << l.cov(0, 0) << l.cov(0, 1)
            << l.cov(1, 1);
    out << likelihood_resolution_m;
    writeLikelihoodOptions(out, likelihoodOptions);
    if (serializeGetVersion() >= 1) out << fallbackText(*dense_);
}

void CHybridMetricMap::serializeFrom(mrpt::serialization::CArchive& in, uint8_t version)
{
    if (version > kSerialVersion)
        throw std::runtime_error("CHybridMetricMap: format version " + std::to_string(version) +
                                 " is not readable by this version (reads 0 to " +
                                 std::to_string(kSerialVersion) + ")");
    in >> genericMapParams;
    std::string p_ini, p_text, d_ini, d_text;
    in >> p_ini >> p_text >> d_ini >> d_text;
    auto partition = partitionFrom(p_ini, p_text);
    auto dense = denseFrom(d_ini, d_text);  // fallback tiles below (version 1)
    uint32_t n = 0;
    in >> n;
    std::vector<Landmark> landmarks(n);
    for (auto& l : landmarks)
    {
        int64_t id = 0;
        double x, y, cxx, cxy, cyy;
        in >> id >> x >> y >> cxx >> cxy >> cyy;
        l.id = static_cast<long>(id);
        l.mean = {x, y};
        l.cov << cxx, cxy, cxy, cyy;
    }
    double res = 0;
    in >> res;
    readLikelihoodOptions(in, likelihoodOptions);
    if (version >= 1)
    {
        std::string tiles;
        in >> tiles;
        std::istringstream t(tiles);
        dense->loadFallbackTiles(t);
    }
    likelihood_resolution_m = res;
    partition_ = std::move(partition);
    dense_ = std::move(dense);
    landmarks_ = std::move(landmarks);
    invalidateCache();
}

void CHybridMetricMap::saveToFile(const std::string& path) const
{
    mrpt::io::CFileGZOutputStream f;
    if (!f.open(path)) throw std::runtime_error("cannot write '" + path + "'");
    auto arch = mrpt::serialization::archiveFrom(f);
    arch << *this;
}

CHybridMetricMap::Ptr CHybridMetricMap::loadFromFile(const std::string& path)
{
    registerHybridMetricMap();
    if (!mrpt::system::fileExists(path)) throw std::runtime_error("HYMM map file not found: '" + path + "'");
    mrpt::io::CFileGZInputStream f;
    if (!f.open(path)) throw std::runtime_error("cannot open HYMM map file '" + path + "'");
    mrpt::serialization::CSerializable::Ptr obj;
    try
    {
        auto arch = mrpt::serialization::archiveFrom(f);
        arch >> obj;
    }
    catch (const std::exception& e)
    {
        throw std::runtime_error("cannot read HYMM map file '" + path + "': " + e.what());
    }
    auto m = std::dynamic_pointer_cast<CHybridMetricMap>(obj);
    if (!m)
        throw std::runtime_error("'" + path + "' holds a " +
                                 std::string(obj ? obj->GetRuntimeClass()->className : "null object") +
                                 ", not a hymm::dense::CHybridMetricMap");
    return m;
}

void CHybridMetricMap::saveMetricMapRepresentationToFile(const std::string& prefix) const
{
    if (dense_->options().enable_occupancy)
        if (!renderedOccupancy().saveAsBitmapFile(prefix + "_occupancy.png"))
            throw std::runtime_error("cannot write '" + prefix + "_occupancy.png'");
    if (dense_->options().enable_points && !renderedPoints().save2D_to_text_file(prefix + "_points.txt"))
        throw std::runtime_error("cannot write '" + prefix + "_points.txt'");
    std::ofstream lm(prefix + "_landmarks.txt");
    lm.precision(17);
    lm << "# id x y cxx cxy cyy\n";
    for (const auto& l : landmarks_)
        lm << l.id << ' ' << l.mean.x() << ' ' << l.mean.y() << ' ' << l.cov(0, 0) << ' ' << l.cov(0, 1)
           << ' ' << l.cov(1, 1) << '\n';
    if (!lm) throw std::runtime_error("cannot write '" + prefix + "_landmarks.txt'");
    partition_->saveToFile(prefix + "_regions.txt");
}

}  // namespace hymm::dense
