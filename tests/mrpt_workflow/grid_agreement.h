// A grid MRPT built from hymm-slam's outputs against the occupancy layer of ours, cell by
// cell (mrpt_workflow_test, mrpt_apps_test).
#pragma once

#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <cmath>
#include <cstddef>
#include <iostream>
#include <string>

namespace hymm::testing
{
/** A cell as occupied (1), free (-1) or unknown (0), from its probability of being free. */
inline int cellClass(float p_free)
{
    if (p_free < 0.4f) return 1;
    if (p_free > 0.6f) return -1;
    return 0;
}

struct GridAgreement
{
    size_t both_known = 0;          //!< cells of ours known in both grids
    size_t agree = 0;               //!< of them, the same class
    size_t mrpt_occ = 0;            //!< MRPT-occupied cells known in ours
    size_t mrpt_occ_near_ours = 0;  //!< of them, with an occupied cell of ours within 0.3 m
};

/** Every cell of `ours` against `mrpt` at its centre. */
inline GridAgreement compareGrids(const mrpt::maps::COccupancyGridMap2D& ours,
                                  const mrpt::maps::COccupancyGridMap2D& mrpt)
{
    GridAgreement g;
    const int w = static_cast<int>(std::ceil(0.3 / ours.getResolution()));  // within 0.3 m
    for (unsigned cy = 0; cy < ours.getSizeY(); ++cy)
        for (unsigned cx = 0; cx < ours.getSizeX(); ++cx)
        {
            const int x = static_cast<int>(cx), y = static_cast<int>(cy);
            const int o = cellClass(ours.getCell(x, y));
            const int m = cellClass(mrpt.getPos(static_cast<float>(ours.idx2x(cx)), static_cast<float>(ours.idx2y(cy))));
            if (o != 0 && m != 0)
            {
                ++g.both_known;
                g.agree += o == m;
            }
            if (m != 1 || o == 0) continue;
            ++g.mrpt_occ;
            bool near = false;
            for (int dy = -w; dy <= w && !near; ++dy)
                for (int dx = -w; dx <= w && !near; ++dx) near = cellClass(ours.getCell(x + dx, y + dy)) == 1;
            g.mrpt_occ_near_ours += near;
        }
    return g;
}

/** Prints the agreement under `tag` and checks it: over 10,000 cells known in both, 95 %
 *  of them the same class, 80 % of MRPT's occupied cells within 0.3 m of ours. */
inline void expectGridsAgree(const std::string& tag, const GridAgreement& g)
{
    const double agreement = static_cast<double>(g.agree) / static_cast<double>(g.both_known);
    const double occ_near = static_cast<double>(g.mrpt_occ_near_ours) / static_cast<double>(g.mrpt_occ);
    std::cout << "[" << tag << "] cells known in both " << g.both_known << ", agreement " << agreement
              << "; MRPT occupied cells " << g.mrpt_occ << ", within 0.3 m of an occupied cell of ours " << occ_near
              << "\n";
    ASSERT_GT(g.both_known, 10000u);
    EXPECT_GT(agreement, 0.95);
    EXPECT_GT(occ_near, 0.8);
}

}  // namespace hymm::testing
