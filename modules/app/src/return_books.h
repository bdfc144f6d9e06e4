/**
 * @file return_books.h
 * @brief Where every laser return within the dense range went (stored in a region, kept
 *        by the fallback, in the delayed store, fused later, dropped) and why the ones in
 *        no region fell there (ltr/outside_causes.h, on the final map).
 */
#pragma once

#include <hymm/app/slam_outputs.h>
#include <hymm/eval/MetricsJson.h>

#include <string>

namespace hymm::app
{
/** metrics.json "dense": returns_fallback, returns_dropped and the "returns" object whose
 *  books balance (outside = fallback + delayed store + dropped). */
void writeReturnBooks(eval::MetricsJson& dj, const DenseSlam& slam);

/** summary.txt: "cause n [of them dropped]" for every cause of a return in no region. */
std::string describeOutsideCauses(const DenseSlam& slam);
}  // namespace hymm::app
