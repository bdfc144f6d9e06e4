// One occupancy cell updated with the inverse sensor model of the occupancy layer
// (prob_hit 0.7, prob_miss 0.4, prior 0.5: OccupancyLayer::Options defaults): HYMM's
// LogOddsGrid (float log-odds, corrected Eq. 4.7, clamped to [0.03, 0.97]) against MRPT's
// COccupancyGridMap2D::updateCell (MRPT 2.5's default build: 8-bit quantised log-odds).
// Counters: the largest |P(occupied) - exact Bayes| over 1..20 identical hits
// (`hit_err`) and over 1..20 misses (`miss_err`), the exact value being
// logistic(n logit(p)) clamped to the layer's limits; `p_max` / `p_min` = P(occupied)
// after 200 hits / misses. The timed loop is one hit and one miss on the cell.
//
// Run: build/benchmarks/grid_cell_vs_mrpt_bench
#include <benchmark/benchmark.h>
#include <hymm/dense/LogOddsGrid.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <algorithm>
#include <cmath>
#include <functional>

namespace
{
constexpr double kHit = 0.7, kMiss = 0.4, kClampMin = 0.03, kClampMax = 0.97;

double exact(double p, int n)
{
    const double l = n * hymm::dense::logit(p);
    return std::clamp(hymm::dense::logistic(l), kClampMin, kClampMax);
}

/** Largest error over 1..20 updates, and P after 200; `update(p)` applies one reading,
 *  `read()` returns P(occupied), `reset()` restores the prior. */
void score(benchmark::State& st, const std::function<void(double)>& update, const std::function<double()>& read,
           const std::function<void()>& reset)
{
    for (const auto& [name, p] : {std::pair{"hit", kHit}, std::pair{"miss", kMiss}})
    {
        reset();
        double err = 0;
        for (int n = 1; n <= 20; ++n)
        {
            update(p);
            err = std::max(err, std::abs(read() - exact(p, n)));
        }
        for (int n = 21; n <= 200; ++n) update(p);
        st.counters[std::string(name) + "_err"] = err;
        st.counters[p > 0.5 ? "p_max" : "p_min"] = read();
    }
}

void BM_HymmLogOddsCell(benchmark::State& st)
{
    hymm::dense::LogOddsGrid g(Eigen::Vector2d(0, 0), 1, 1, 1.0, 0.0f);
    const Eigen::Vector2d c(0.5, 0.5);
    const auto lmin = static_cast<float>(hymm::dense::logit(kClampMin));
    const auto lmax = static_cast<float>(hymm::dense::logit(kClampMax));
    const auto lhit = static_cast<float>(hymm::dense::logit(kHit));
    const auto lmiss = static_cast<float>(hymm::dense::logit(kMiss));
    auto update = [&](double p) {
        if (p > 0.5)
            g.markOccupied(c);
        else
            g.markFree(c - Eigen::Vector2d(0.2, 0), c, false);
        g.applyMarks(lmiss, lhit, lmin, lmax);
    };
    score(st, update, [&] { return hymm::dense::logistic(g.logOdds(0, 0)); }, [&] { g.setLogOdds(0, 0, 0.0f); });
    for (auto _ : st)
    {
        update(kHit);
        update(kMiss);
        benchmark::DoNotOptimize(g.logOdds(0, 0));
    }
}

void BM_MrptGridCell(benchmark::State& st)
{
    mrpt::maps::COccupancyGridMap2D g(0, 1, 0, 1, 1.0f);
    // MRPT's cells hold P(free): an occupied reading p is the value 1 - p.
    auto update = [&](double p) { g.updateCell(0, 0, static_cast<float>(1 - p)); };
    score(st, update, [&] { return 1.0 - g.getCell(0, 0); }, [&] { g.setCell(0, 0, 0.5f); });
    for (auto _ : st)
    {
        update(kHit);
        update(kMiss);
        benchmark::DoNotOptimize(g.getCell(0, 0));
    }
}
}  // namespace

BENCHMARK(BM_HymmLogOddsCell);
BENCHMARK(BM_MrptGridCell);
BENCHMARK_MAIN();
