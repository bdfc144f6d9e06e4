/**
 * @file TrajectoryEvaluator.h
 * @brief Vehicle trajectory error against ground truth: position RMSE / mean / max and
 *        heading RMSE (absolute trajectory error), with optional SE(2) alignment.
 *
 * Association of each estimated pose with a ground-truth pose:
 *  - `nearest`: the ground-truth pose closest in time, if within `time_tolerance`;
 *  - `interpolate`: ground truth linearly interpolated at the estimate's time (heading
 *    along the shortest arc) between the two samples that bracket it, if they are at most
 *    `time_tolerance` apart (so a gap in the ground truth is not bridged);
 *  - `index`: the i-th estimate with the i-th ground-truth pose (for ground truth without
 *    timestamps, e.g. MRPT simul-landmarks' robot path; see ground_truth_io.h).
 * Estimates without a partner are counted as unmatched and left out of the errors.
 *
 * With `align` on, the estimate is first moved by the rigid transform that best fits its
 * matched positions onto the ground truth (se2_alignment.h), over the whole run or only
 * over its first `align_fit_distance` metres. The whole-run fit is the usual ATE for an
 * estimator whose frame is arbitrary; for SLAM started at the true initial pose (the
 * thesis' simulations) leave it off, so a global drift is not hidden.
 */
#pragma once

#include <hymm/core/OptionTable.h>

#include <hymm/io/trajectory_io.h>
#include <hymm/eval/se2_alignment.h>
#include <mrpt/config/CLoadableOptions.h>

#include <string>
#include <vector>

namespace hymm::eval
{
class TrajectoryEvaluator
{
public:
    enum class Association
    {
        Nearest,
        Interpolate,
        Index
    };

    /** Ini section [TrajectoryEvaluator]; unknown keys are errors. */
    struct Options : public mrpt::config::CLoadableOptions
    {
        Association association = Association::Interpolate;  //!< ini: nearest|interpolate|index
        double time_tolerance = 0.05;  //!< [s] see the file comment (> 0)
        bool align = false;            //!< fit an SE(2) transform before computing errors
        /** [m] with `align`: 0 fits the transform on every matched pose (least squares
         *  over the whole run, which also absorbs drift); > 0 fits it only on the matched
         *  poses whose ground truth lies within the first `align_fit_distance` metres
         *  travelled, so the start frame is tied to the truth and later drift shows. */
        double align_fit_distance = 0.0;

        /** Every ini key, declared once: loader, saver and README table come from it. */
        hymm::core::OptionTable table();
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
        void validate(const std::string& section = "TrajectoryEvaluator") const;
    };

    /** Error of one matched pose (estimate minus truth, after alignment if any). */
    struct PoseError
    {
        double t = 0;      //!< [s] estimate's timestamp
        double dx = 0;     //!< [m]
        double dy = 0;     //!< [m]
        double dphi = 0;   //!< [rad] wrapped to (-pi, pi]
        double position() const;
    };

    struct Result
    {
        size_t matched = 0;
        size_t unmatched = 0;      //!< estimates with no ground-truth partner
        double position_rmse = 0;  //!< [m] NaN when nothing matched
        double position_mean = 0;  //!< [m]
        double position_max = 0;   //!< [m]
        double heading_rmse = 0;   //!< [rad]
        double heading_max = 0;    //!< [rad] largest |dphi|
        bool aligned = false;      //!< an alignment was requested and succeeded
        Se2Transform alignment;    //!< applied to the estimate (identity if not aligned)
        std::vector<PoseError> errors;
    };

    /** Throws std::invalid_argument on invalid options. */
    explicit TrajectoryEvaluator(const Options& options);

    const Options& options() const { return options_; }

    /** Ground truth need not be sorted; timestamps of `truth` are ignored for `index`. */
    Result evaluate(
        const std::vector<io::StampedPose2D>& estimate,
        const std::vector<io::StampedPose2D>& truth) const;

    static std::string associationName(Association a);
    /** Throws std::invalid_argument naming the valid choices. */
    static Association parseAssociation(const std::string& name);

private:
    const Options options_;
};

}  // namespace hymm::eval
