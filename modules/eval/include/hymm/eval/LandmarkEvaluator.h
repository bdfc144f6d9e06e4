/**
 * @file LandmarkEvaluator.h
 * @brief Landmark map error against ground truth: association, position errors, NEES.
 *
 * Association of estimated landmarks with true ones:
 *  - `id`: by identifier (the simulator's IDs, carried through by a filter that was told
 *    them); one-to-one, an estimate whose ID is unknown or already taken is unmatched;
 *  - `nearest`: greedy one-to-one nearest neighbour by distance, within `gate`;
 *  - `auto`: `id` when every estimated ID is a known true ID and no ID repeats, else
 *    `nearest`. A filter's own internal landmark indices must not be passed as IDs, or
 *    they may be taken for true IDs.
 * For each match: the position error, and the NEES e' P^-1 e when the estimate carries a
 * 2x2 covariance. A single landmark's NEES is chi-square with 2 dof if the map is
 * consistent (see nees.h for bounds).
 */
#pragma once

#include <hymm/core/OptionTable.h>

#include <hymm/io/trajectory_io.h>
#include <hymm/eval/nees.h>
#include <hymm/eval/se2_alignment.h>
#include <mrpt/config/CLoadableOptions.h>

#include <Eigen/Core>

#include <string>
#include <vector>

namespace hymm::eval
{
/** An estimated landmark, optionally with its marginal covariance. */
struct LandmarkEstimate
{
    long id = -1;
    Eigen::Vector2d position = Eigen::Vector2d::Zero();
    bool has_cov = false;
    Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();  //!< [m^2]
};

/**
 * Converts "id,x,y,extra..." records into estimates. With `cov_column` >= 0, extra
 * columns cov_column, +1, +2 hold (sxx, sxy, syy); throws if a record is too short.
 */
std::vector<LandmarkEstimate> landmarkEstimatesFromRecords(
    const std::vector<io::LandmarkRecord>& records, int cov_column = -1);

class LandmarkEvaluator
{
public:
    enum class Association
    {
        Auto,
        Id,
        Nearest
    };

    /** Ini section [LandmarkEvaluator]; unknown keys are errors. */
    struct Options : public mrpt::config::CLoadableOptions
    {
        Association association = Association::Auto;  //!< ini: auto|id|nearest
        double gate = 2.0;  //!< [m] largest distance of a nearest-neighbour match (> 0)

        /** Every ini key, declared once: loader, saver and README table come from it. */
        hymm::core::OptionTable table();
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
        void validate(const std::string& section = "LandmarkEvaluator") const;
    };

    struct Match
    {
        size_t estimate = 0;  //!< index into the estimates
        size_t truth = 0;     //!< index into the true landmarks
        double error = 0;     //!< [m] position error
        NeesValue nees;       //!< status NotFinite with NaN value when no covariance was given
        bool has_nees = false;
    };

    struct Result
    {
        Association used = Association::Nearest;  //!< Id or Nearest (what Auto resolved to)
        std::vector<Match> matches;
        size_t unmatched_estimates = 0;
        size_t unmatched_truth = 0;
        double mean_error = 0;  //!< [m] NaN when nothing matched
        double rmse = 0;        //!< [m]
        double max_error = 0;   //!< [m]
        size_t nees_count = 0;      //!< matches with a valid NEES
        size_t nees_singular = 0;   //!< matches whose covariance was singular or not finite
        double mean_nees = 0;       //!< over nees_count matches, NaN if none
    };

    /** Throws std::invalid_argument on invalid options. */
    explicit LandmarkEvaluator(const Options& options);

    const Options& options() const { return options_; }

    /** `alignment`, if given, is applied to the estimates (and rotates their covariances)
     *  first, e.g. the transform found by TrajectoryEvaluator. */
    Result evaluate(
        const std::vector<LandmarkEstimate>& estimates,
        const std::vector<io::LandmarkRecord>& truth,
        const Se2Transform* alignment = nullptr) const;

    static std::string associationName(Association a);
    static Association parseAssociation(const std::string& name);

private:
    const Options options_;
};

}  // namespace hymm::eval
