/**
 * @file matcher_choice.h
 * @brief The `matcher` key every user of the scan matchers declares: one of
 *        makeMatcher()'s kinds (sog, icp, correlative).
 */
#pragma once

#include <hymm/core/OptionTable.h>

#include <string>

namespace hymm::scanslam
{
/** Declares `matcher` in `t`: "sog", "icp" or "correlative", documented by `doc`. */
inline void declareMatcherChoice(core::OptionTable& t, std::string& matcher, const std::string& doc)
{
    t.choice("matcher", matcher,
             {{"sog", std::string("sog")}, {"icp", std::string("icp")}, {"correlative", std::string("correlative")}},
             doc);
}

}  // namespace hymm::scanslam
