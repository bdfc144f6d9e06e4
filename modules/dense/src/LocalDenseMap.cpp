#include "hymm/dense/LocalDenseMap.h"

#include <istream>
#include <ostream>
#include <stdexcept>

namespace hymm::dense
{
LocalDenseMap::LocalDenseMap(long region_id, const hymm::ltr::TriangleFrame::Vertices& reference)
    : region_id_(region_id), reference_(reference)
{
}

void LocalDenseMap::addLayer(std::unique_ptr<DenseLayer> layer)
{
    if (!layer) throw std::invalid_argument("LocalDenseMap::addLayer: null layer");
    if (this->layer(layer->kind()))
        throw std::invalid_argument(
            "LocalDenseMap::addLayer: region " + std::to_string(region_id_) +
            " already has a layer of kind '" + layer->kind() + "'");
    layers_.push_back(std::move(layer));
}

const DenseLayer* LocalDenseMap::layer(const std::string& kind) const
{
    for (const auto& l : layers_)
        if (l->kind() == kind) return l.get();
    return nullptr;
}

DenseLayer* LocalDenseMap::layer(const std::string& kind)
{
    for (auto& l : layers_)
        if (l->kind() == kind) return l.get();
    return nullptr;
}

std::vector<std::string> LocalDenseMap::layerKinds() const
{
    std::vector<std::string> out;
    for (const auto& l : layers_) out.push_back(l->kind());
    return out;
}

void LocalDenseMap::insert(const RegionScan& scan)
{
    for (auto& l : layers_) l->insert(scan);
}

size_t LocalDenseMap::memoryBytes() const
{
    size_t n = sizeof(*this) + layers_.capacity() * sizeof(void*);
    for (const auto& l : layers_) n += l->memoryBytes();
    return n;
}

void LocalDenseMap::save(std::ostream& out) const
{
    out << std::hexfloat << "region " << region_id_;
    for (const auto& v : reference_) out << ' ' << v.x() << ' ' << v.y();
    out << std::defaultfloat << ' ' << layers_.size() << '\n';
    for (const auto& l : layers_)
    {
        out << "layer " << l->kind() << '\n';
        l->save(out);
    }
}

std::unique_ptr<LocalDenseMap> LocalDenseMap::load(std::istream& in, const LayerFactory& factory)
{
    std::string tag;
    long id = -1;
    if (!(in >> tag >> id) || tag != "region")
        throw std::runtime_error("LocalDenseMap::load: expected 'region <id>'");
    hymm::ltr::TriangleFrame::Vertices ref;
    for (auto& v : ref)
        for (int k = 0; k < 2; ++k)
        {
            std::string tok;
            in >> tok;
            try
            {
                v[k] = std::stod(tok);
            }
            catch (const std::exception&)
            {
                throw std::runtime_error(
                    "LocalDenseMap::load: region " + std::to_string(id) + ": bad vertex '" + tok + "'");
            }
        }
    size_t n = 0;
    if (!(in >> n)) throw std::runtime_error("LocalDenseMap::load: region " + std::to_string(id) + ": bad layer count");
    auto map = std::make_unique<LocalDenseMap>(id, ref);
    for (size_t i = 0; i < n; ++i)
    {
        std::string kind;
        if (!(in >> tag >> kind) || tag != "layer")
            throw std::runtime_error("LocalDenseMap::load: region " + std::to_string(id) + ": expected 'layer <kind>'");
        auto layer = factory(kind, ref);
        if (!layer)
            throw std::runtime_error("LocalDenseMap::load: unknown or disabled layer kind '" + kind + "'");
        layer->load(in);
        map->addLayer(std::move(layer));
    }
    return map;
}

}  // namespace hymm::dense
