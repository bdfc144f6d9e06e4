/**
 * @file region_seed.h
 * @brief The random seed words of a region's layer: the option's seed and the bit
 *        patterns of the region's reference vertices, so regions draw independent
 *        streams and the same map is rebuilt on the same data.
 */
#pragma once

#include <hymm/ltr/TriangleFrame.h>

#include <cstdint>
#include <cstring>
#include <vector>

namespace hymm::dense::detail
{
inline std::vector<std::uint32_t> regionSeedWords(std::uint32_t seed,
                                                  const hymm::ltr::TriangleFrame::Vertices& reference)
{
    std::vector<std::uint32_t> words{seed};
    for (const auto& v : reference)
        for (int k = 0; k < 2; ++k)
        {
            std::uint64_t bits = 0;
            const double x = v[k];
            std::memcpy(&bits, &x, sizeof(bits));
            words.push_back(static_cast<std::uint32_t>(bits));
            words.push_back(static_cast<std::uint32_t>(bits >> 32));
        }
    return words;
}
}  // namespace hymm::dense::detail
