/**
 * @file RegionPartitionText.cpp
 * @brief The partition's text format (regions.txt of hymm-slam): a header, the next id,
 *        then one line per region (id, vertex ids, creation time, reference and current
 *        triangles).
 */
#include "hymm/ltr/RegionPartition.h"

#include <hymm/core/output_files.h>

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace hymm::ltr
{
namespace
{
constexpr const char* kFileHeader = "hymm-ltr-partition 1";
}  // namespace

void RegionPartition::save(std::ostream& out) const
{
    out << kFileHeader << "\n" << "next_id " << next_id_ << "\n" << "regions " << regions_.size()
        << "\n";
    out << std::setprecision(17);
    for (const auto& [id, r] : regions_)
    {
        out << id << ' ' << r.vertex_ids[0] << ' ' << r.vertex_ids[1] << ' ' << r.vertex_ids[2]
            << ' ' << r.creation_time;
        for (const auto* tri : {&r.reference, &r.current})
            for (const auto& p : *tri) out << ' ' << p.x() << ' ' << p.y();
        out << "\n";
    }
}

void RegionPartition::load(std::istream& in)
{
    auto bad = [](int line, const std::string& what) {
        throw std::runtime_error(
            "RegionPartition::load: line " + std::to_string(line) + ": " + what);
    };
    std::string line;
    if (!std::getline(in, line) || line != kFileHeader)
        bad(1, std::string("expected header '") + kFileHeader + "'");
    std::string word;
    long next_id = 0;
    size_t n = 0;
    if (!std::getline(in, line) || !(std::istringstream(line) >> word >> next_id) ||
        word != "next_id")
        bad(2, "expected 'next_id <n>'");
    if (!std::getline(in, line) || !(std::istringstream(line) >> word >> n) || word != "regions")
        bad(3, "expected 'regions <n>'");
    std::vector<Region> loaded;
    for (size_t i = 0; i < n; ++i)
    {
        const int ln = static_cast<int>(i) + 4;
        if (!std::getline(in, line)) bad(ln, "missing region line");
        std::istringstream is(line);
        Region r;
        is >> r.id >> r.vertex_ids[0] >> r.vertex_ids[1] >> r.vertex_ids[2] >> r.creation_time;
        for (auto* tri : {&r.reference, &r.current})
            for (auto& p : *tri) is >> p.x() >> p.y();
        if (!is) bad(ln, "expected 'id v1 v2 v3 time' and 12 coordinates");
        const std::string why = TriangleFrame::degeneracyReason(r.reference, FrameLimits());
        if (!why.empty()) bad(ln, "degenerate reference triangle: " + why);
        loaded.push_back(std::move(r));
    }
    clear();
    for (auto& r : loaded)
    {
        if (regions_.count(r.id)) bad(0, "duplicate region id " + std::to_string(r.id));
        insertRegion(std::move(r));
    }
    next_id_ = std::max(next_id_, next_id);
}

void RegionPartition::saveToFile(const std::string& path) const
{
    core::AtomicTextFile f(path);
    save(f);
    f.commit();
}

void RegionPartition::loadFromFile(const std::string& path)
{
    std::ifstream f(path);
    if (!f) throw std::runtime_error("RegionPartition: cannot open '" + path + "'");
    load(f);
}

}  // namespace hymm::ltr
