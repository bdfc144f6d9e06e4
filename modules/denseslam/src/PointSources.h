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

/** laser_reflectors: retro-reflective beacons from a scan's intensities (car park). */
class ReflectorSource : public PointLandmarkSource
{
public:
    ReflectorSource(const extract::ReflectorExtractor::Options& o, const PointSourceSettings& s)
        : extractor_(o), settings_(s)
    {
    }
    std::string name() const override { return "laser_reflectors"; }
    PointSourceInput input() const override { return PointSourceInput::Scan; }
    PointObservations observe(const mrpt::obs::CObservation& obs) const override;

private:
    extract::ReflectorExtractor extractor_;
    PointSourceSettings settings_;
};

/** laser_trees: trunks extracted from a scan (e.g. Victoria Park). */
class TreeSource : public PointLandmarkSource
{
public:
    TreeSource(const extract::TreeExtractor::Options& o, const PointSourceSettings& s)
        : extractor_(o), settings_(s)
    {
    }
    std::string name() const override { return "laser_trees"; }
    PointSourceInput input() const override { return PointSourceInput::Scan; }
    PointObservations observe(const mrpt::obs::CObservation& obs) const override;

private:
    extract::TreeExtractor extractor_;
    PointSourceSettings settings_;
};

}  // namespace hymm::denseslam
