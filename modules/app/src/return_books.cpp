#include "return_books.h"

#include <hymm/denseslam/VirtualLandmarkView.h>
#include <hymm/ltr/outside_causes.h>

#include <sstream>

namespace hymm::app
{
namespace
{
/** Why the returns in no region fell there, on the final map: all of them, and those the
 *  fallback did not keep. */
struct OutsideCauses
{
    ltr::OutsideCauseCounts all, dropped;
};

OutsideCauses outsideCauses(const DenseSlam& slam)
{
    OutsideCauses c;
    const denseslam::VirtualLandmarkView view(slam.ekf(), slam.virtualLandmarkIds(),
                                              slam.options().pose_landmark_vertices);
    // Per cell of the tally, at the mean position of its returns (DenseSlam.h).
    for (const auto& r : slam.outsideReturnCells())
    {
        const auto cause = ltr::classifyOutsideReturn(*slam.partition(), view, r.p);
        c.all[cause] += r.returns;
        c.dropped[cause] += r.returns - r.kept;
    }
    return c;
}

unsigned long ul(size_t n) { return static_cast<unsigned long>(n); }
}  // namespace

void writeReturnBooks(eval::MetricsJson& dj, const DenseSlam& slam)
{
    const auto& st = slam.stats();
    dj.set("returns_fallback", ul(st.returns_fallback));
    dj.set("returns_dropped", ul(st.returns_dropped));
    auto& rj = dj.object("returns");
    const size_t total = st.returns_stored + st.returns_withheld + st.returns_outside;
    rj.set("total", ul(total));
    rj.set("stored_in_region", ul(st.returns_stored));
    rj.set("withheld_local_uncertainty", ul(st.returns_withheld));
    rj.set("withheld_kept_by_fallback", ul(st.returns_withheld_fallback));
    rj.set("withheld_dropped", ul(st.returns_withheld - st.returns_withheld_fallback));
    rj.set("outside_regions", ul(st.returns_outside));
    rj.set("kept_by_fallback", ul(st.returns_fallback));
    rj.set("delayed_stored", ul(st.delayed_stored));
    rj.set("delayed_fused", ul(st.delayed_fused));
    rj.set("delayed_fused_fallback", ul(st.delayed_fused_fallback));
    rj.set("dropped_outside", ul(st.returns_dropped));
    // Returns within the dense range that are in a dense layer: in a region, kept by the
    // fallback, or fused later from the delayed store (into a region or the fallback).
    const size_t reached = st.returns_stored + st.returns_fallback + st.returns_withheld_fallback +
                           st.delayed_fused + st.delayed_fused_fallback;
    rj.set("reached_dense_map", ul(reached));
    rj.set("reached_fraction", total ? static_cast<double>(reached) / static_cast<double>(total) : 0.0);
    const auto causes = outsideCauses(slam);
    rj.set("outside_recorded", ul(causes.all.total()));
    auto& cj = rj.object("outside_causes");
    auto& dcj = rj.object("dropped_causes");
    for (size_t k = 0; k < causes.all.n.size(); ++k)
    {
        const char* name = ltr::toString(static_cast<ltr::OutsideCause>(k));
        cj.set(name, ul(causes.all.n[k]));
        dcj.set(name, ul(causes.dropped.n[k]));
    }
}

std::string describeOutsideCauses(const DenseSlam& slam)
{
    const auto c = outsideCauses(slam);
    std::ostringstream o;
    for (size_t k = 0; k < c.all.n.size(); ++k)
        o << (k ? ", " : "") << ltr::toString(static_cast<ltr::OutsideCause>(k)) << " " << c.all.n[k]
          << " [" << c.dropped.n[k] << "]";
    return o.str();
}
}  // namespace hymm::app
