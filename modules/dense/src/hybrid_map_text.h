// Text round trips of the partition and the dense layers (exact: hex floats or 17
// digits), the copies and the serialisation of CHybridMetricMap are made of.
#pragma once

#include "hymm/dense/HybridMetricMap.h"
#include "hymm/ltr/RegionPartition.h"

#include <mrpt/config/CConfigFileMemory.h>

#include <functional>
#include <memory>
#include <sstream>
#include <string>

namespace hymm::dense::text
{
using hymm::ltr::RegionPartition;

inline std::string iniText(const std::function<void(mrpt::config::CConfigFileMemory&)>& write)
{
    mrpt::config::CConfigFileMemory cfg;
    write(cfg);
    return cfg.getContent();
}

inline std::string partitionText(const RegionPartition& p)
{
    std::ostringstream s;
    s.precision(17);
    p.save(s);
    return s.str();
}

inline std::string denseText(const HybridMetricMap& d)
{
    std::ostringstream s;
    s.precision(17);
    d.save(s);
    return s.str();
}

inline std::string fallbackText(const HybridMetricMap& d)
{
    std::ostringstream s;
    d.saveFallbackTiles(s);
    return s.str();
}

inline std::unique_ptr<RegionPartition> partitionFrom(const std::string& options_ini, const std::string& text)
{
    RegionPartition::Options o;
    mrpt::config::CConfigFileMemory cfg(options_ini);
    o.loadFromConfigFile(cfg, "LtrPartition");
    auto p = std::make_unique<RegionPartition>(o);
    std::istringstream s(text);
    p->load(s);
    return p;
}

inline std::unique_ptr<HybridMetricMap> denseFrom(const std::string& options_ini, const std::string& text,
                                           const std::string& fallback = "fallback_tiles 0")
{
    HybridMetricMap::Options o;
    mrpt::config::CConfigFileMemory cfg(options_ini);
    o.loadAll(cfg);
    auto d = std::make_unique<HybridMetricMap>(o);
    std::istringstream s(text);
    d->load(s);
    std::istringstream f(fallback);
    d->loadFallbackTiles(f);
    return d;
}

}  // namespace hymm::dense::text
