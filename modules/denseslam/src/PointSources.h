// The registered point sources (LandmarkSources.h; private to the module).
#pragma once

#include "hymm/denseslam/LandmarkSources.h"

#include <hymm/extract/ReflectorExtractor.h>
#include <hymm/extract/TreeExtractor.h>

namespace hymm::denseslam
{
/** bearing_range: the landmarks of a CObservationBearingRange (e.g. MRPT's
 *  simul-landmarks), with their ids when [DenseSlam] use_landmark_ids. */
class BearingRangeSource : public PointLandmarkSource
{
public:
    explicit BearingRangeSource(const PointSourceSettings& s) : settings_(s) {}
    std::string name() const override { return "bearing_range"; }
    PointSourceInput input() const override { return PointSourceInput::BearingRange; }
    PointObservations observe(const mrpt::obs::CObservation& obs) const override;

private:
    PointSourceSettings settings_;
};

/** A scan source on one of hymm::extract's extractors (its section's options and noise). */
template <class Extractor>
class ExtractorSource : public PointLandmarkSource
{
public:
    ExtractorSource(const char* name, const typename Extractor::Options& o, const PointSourceSettings& s)
        : name_(name), extractor_(o), settings_(s)
    {
    }
    std::string name() const override { return name_; }
    PointSourceInput input() const override { return PointSourceInput::Scan; }
    PointObservations observe(const mrpt::obs::CObservation& obs) const override;

private:
    const char* name_;
    Extractor extractor_;
    PointSourceSettings settings_;
};

/** laser_reflectors: retro-reflective beacons from a scan's intensities (car park). */
using ReflectorSource = ExtractorSource<extract::ReflectorExtractor>;
/** laser_trees: trunks extracted from a scan (e.g. Victoria Park). */
using TreeSource = ExtractorSource<extract::TreeExtractor>;

// Each extractor's features and its scans' conditions (PointSources.cpp).
template <>
PointObservations ReflectorSource::observe(const mrpt::obs::CObservation& obs) const;
template <>
PointObservations TreeSource::observe(const mrpt::obs::CObservation& obs) const;

}  // namespace hymm::denseslam
