#include "hymm/denseslam/DenseSlamStats.h"

namespace hymm::denseslam
{
void DenseSlamStats::add(const ekf::UpdateReport& r)
{
    associated += r.associated;
    created += r.created;
    rejected_gate += r.rejected_gate;
    ambiguous += r.ambiguous;
    rejected_numeric += r.rejected_numeric;
}

void DenseSlamStats::add(const dense::HybridMetricMap::InsertStats& st, size_t failed)
{
    returns_stored += st.returns_stored;
    returns_outside += st.returns_outside;
    returns_withheld += st.returns_withheld;
    no_return_beams += st.no_return;
    failed_readings += failed;
    ++dense_scans;
    returns_fallback += st.returns_fallback;
    returns_withheld_fallback += st.withheld_fallback;
}

void DenseSlamStats::add(const uif::DelayedDenseStore::AddReport& r)
{
    delayed_stored += r.stored;
    returns_dropped += r.offered - r.stored;
    delayed_outside_potential += r.outside_potential;
    delayed_thinned += r.thinned;
    delayed_evicted += r.evicted_points;
    delayed_lost += r.lost_points;
}

void DenseSlamStats::add(const uif::DelayedDenseStore::FuseReport& r)
{
    delayed_fused += r.fused;
    delayed_fused_fallback += r.fused_outside;
    delayed_lost += r.lost_points;
}

}  // namespace hymm::denseslam
