/**
 * @file SegmentAcceptance.h
 * @brief Whether a segment can be registered well enough to become a landmark
 *        (thesis 5.2.2, 5.7): copies of it get fresh sensor noise and a random
 *        translation and rotation and are registered back onto the template; the
 *        segment is accepted when the alignment error is below a fraction (thesis: 10 %)
 *        of the displacement and, optionally, the alignment covariance's trace is small
 *        (the inverse of the "object saliency score").
 *
 * The error and the displacement are measured on the segment's own points (the RMS of
 * the point displacements, the "typical boundary error" of 5.2.2), so that translation
 * and rotation weigh in metres on the segment's scale.
 */
#pragma once

#include <hymm/core/OptionTable.h>
#include <mrpt/random/RandomGenerators.h>
#include <mrpt/serialization/CArchive.h>

#include <array>
#include <string>

#include "hymm/scanslam/ScanMatcher.h"

namespace hymm::scanslam
{
class SegmentAcceptance
{
public:
    struct Options
    {
        int trials = 3;                    //!< perturbed copies registered per segment
        double displacement_xy_m = 0.3;    //!< length of the random translation [m]
        double displacement_phi = 3 * M_PI / 180;  //!< size of the random rotation (either sign) [rad]
        double max_error_fraction = 0.1;   //!< thesis 5.7: 10 % of the displacement
        double max_cov_trace = 0;          //!< also require trace(R_xy) below this [m^2] (0: off)
        double min_extent_m = 0.5;         //!< segments shorter end to end are rejected [m]

        /** Every key, declared once (loader, unknown-key check, saver, README table). */
        core::OptionTable table();
        /** Reads [section]; unknown keys, bad values and no displacement at all throw
         *  naming the key. */
        void load(const mrpt::config::CConfigFileBase& cfg, const std::string& section);
        void save(mrpt::config::CConfigFileBase& cfg, const std::string& section) const;
    };

    enum class Outcome
    {
        accepted = 0,
        too_small,           //!< fewer than 3 points or extent below min_extent_m
        registration_failed, //!< the matcher returned no result
        error_too_large,     //!< error above the fraction of the displacement
        covariance_too_large //!< trace above max_cov_trace
    };
    static constexpr size_t kOutcomes = 5;
    static const char* outcomeName(Outcome o);

    struct Stats
    {
        std::array<size_t, kOutcomes> count{};
        size_t total() const;
    };

    SegmentAcceptance(const Options& options, const ScanMatcher& matcher, uint32_t seed);

    /** Tests `segment` (points in the sensor frame with their covariances); counts
     *  the outcome. `worst_ratio` (optional): the largest error/displacement ratio. */
    Outcome test(const PointSet& segment, double* worst_ratio = nullptr);

    const Stats& stats() const { return stats_; }

    /** The outcome counts and the generator's state bit for bit, for a saved run. */
    void saveState(mrpt::serialization::CArchive& out) const;
    void loadState(mrpt::serialization::CArchive& in);

private:
    /** MRPT's generator with its (protected) state made savable: the MT19937 words and
     *  the normal and integer distributions, so a resumed run draws what the
     *  uninterrupted one would have. */
    class SavableRandom : public mrpt::random::CRandomGenerator
    {
    public:
        void save(mrpt::serialization::CArchive& out) const;
        void load(mrpt::serialization::CArchive& in);
    };

    Options options_;
    const ScanMatcher& matcher_;
    SavableRandom rng_;
    Stats stats_;
};

}  // namespace hymm::scanslam
