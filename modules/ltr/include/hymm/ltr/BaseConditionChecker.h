/**
 * @file BaseConditionChecker.h
 * @brief The base-landmark selection conditions of thesis Sec. 3.5.
 *
 * Before three landmarks become the vertices of a new LTR they must be
 *  1. highly correlated, among themselves and with the vehicle, so that their relative
 *     positions are well known and the region moves almost rigidly after an update
 *     (Sec. 3.3, Fig. 3.9);
 *  2. geometrically well conditioned, so that no update can flip the triangle over:
 *     the thesis' conservative test treats each vertex as independent and requires its
 *     n-sigma uncertainty ellipse not to reach the line through the opposite edge
 *     (Fig. 3.10a); we add minimum area, minimum interior angle, maximum edge length
 *     and a bound on the condition number of the axes matrix;
 *  3. not overlapping existing regions (Fig. 3.10b): interiors must be disjoint;
 *     sharing an edge or a vertex is allowed (that is how the partition covers the
 *     explored area without gaps).
 *
 * Scalar correlation coefficient of two Gaussian blocks (a, b), selectable:
 *  - MinCanonical (default): the smallest canonical correlation, i.e. the smallest
 *    singular value of P_aa^{-1/2} P_ab P_bb^{-1/2}. It is invariant to rotations and
 *    scalings of either block, and is 1 only if every direction of a is fully
 *    explained by b. Directions with negligible variance (relative 1e-12 of the
 *    largest) are left out; a block with no variance at all is treated as perfectly
 *    known and yields 1 (its error cannot deform the region).
 *  - PerAxis: the thesis' per-coordinate coefficient (Eq. 2.62),
 *    rho_k = |P_ab(k,k)| / sqrt(P_aa(k,k) P_bb(k,k)) for k in {x, y}, taking the
 *    smaller of the two (the vehicle block uses its x, y position only).
 * A triple passes if all three vertex pairs reach `min_vertex_correlation` and all
 * three vertices reach `min_vehicle_correlation` with the vehicle pose.
 *
 * Expected outcomes are returned as a CheckResult with a reason enum, never thrown.
 */
#pragma once

#include <hymm/core/OptionTable.h>
#include "hymm/ltr/LandmarkCovarianceView.h"
#include "hymm/ltr/TriangleFrame.h"

#include <mrpt/config/CLoadableOptions.h>

#include <array>
#include <string>
#include <vector>

namespace hymm::ltr
{
enum class BaseCondition
{
    Accepted = 0,
    UnknownLandmark,        //!< a vertex id is not in the landmark map
    RepeatedLandmark,       //!< the same landmark appears twice
    SmallArea,              //!< area below min_area_m2 (includes collinear vertices)
    SmallAngle,             //!< an interior angle below min_angle
    DegenerateTriangle,     //!< axes condition number above max_condition_number
    LongEdge,               //!< an edge longer than max_edge_length_m
    IllConditioned,         //!< a vertex n-sigma ellipse reaches the opposite edge line
    LowVertexCorrelation,   //!< a vertex pair below min_vertex_correlation
    LowVehicleCorrelation,  //!< a vertex below min_vehicle_correlation with the vehicle
    Overlap,                //!< interior intersects an existing region
    TwoVirtualVertices      //!< more than one virtual landmark (Sec. 3.5.1) among the vertices
};

/** Stable name of a condition, e.g. "LowVertexCorrelation". */
const char* toString(BaseCondition c);

enum class CorrelationMeasure
{
    MinCanonical,
    PerAxis
};

struct CheckResult
{
    BaseCondition reason = BaseCondition::Accepted;
    double value = 0;  //!< the offending quantity (coefficient, angle, ratio, ...)
    double limit = 0;  //!< the limit it violated
    std::string detail;  //!< human-readable explanation

    bool accepted() const { return reason == BaseCondition::Accepted; }
};

class BaseConditionChecker
{
public:
    /** Read from the [LtrPartition] section (shared with RegionPartition::Options). */
    struct Options : public mrpt::config::CLoadableOptions
    {
        double min_vertex_correlation = 0.9;   //!< [0..1] every vertex pair (condition 1)
        double min_vehicle_correlation = 0.9;  //!< [0..1] every vertex with the vehicle; 0 = off
        CorrelationMeasure correlation_measure =
            CorrelationMeasure::MinCanonical;  //!< ini: min_canonical | per_axis
        double ellipse_sigma = 3.0;        //!< [sigmas] ellipse of condition 2 (thesis Fig 3.10)
        double min_area_m2 = 1.0;          //!< [m^2]
        double min_angle = 15.0 * 3.14159265358979323846 / 180.0;  //!< [rad] (ini: min_angle_deg)
        double max_edge_length_m = 50.0;   //!< [m]
        double max_condition_number = 1e3;  //!< of the axes matrix D = [L2-L1, L3-L1]

        /** Every ini key, declared once: loader, saver and README table come from it. */
        hymm::core::OptionTable table();
        /** Strict: unknown keys in `section` are errors. */
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
        void validate(const std::string& section = "LtrPartition") const;
        FrameLimits frameLimits() const { return {min_area_m2, max_condition_number}; }
    };

    /** Throws std::invalid_argument on invalid options. */
    explicit BaseConditionChecker(const Options& options);
    const Options& options() const { return options_; }

    /** All conditions; first failure wins, in the order: ids, geometry, correlation,
     *  overlap with `existing` (current vertex positions of nearby regions). */
    CheckResult check(
        const std::array<long, 3>& ids, const LandmarkCovarianceView& view,
        const std::vector<TriangleFrame::Vertices>& existing) const;

    /** Condition 2 on the current means and marginal covariances of `ids`. */
    CheckResult checkGeometry(
        const std::array<long, 3>& ids, const LandmarkCovarianceView& view) const;
    /** Condition 2 on explicit vertices and marginal covariances. */
    CheckResult checkGeometry(
        const TriangleFrame::Vertices& v, const std::array<Eigen::Matrix2d, 3>& cov) const;
    /** Condition 1. */
    CheckResult checkCorrelation(
        const std::array<long, 3>& ids, const LandmarkCovarianceView& view) const;
    /** Condition 3. */
    CheckResult checkOverlap(
        const TriangleFrame::Vertices& candidate,
        const std::vector<TriangleFrame::Vertices>& existing) const;

    /** Landmark-to-vehicle coefficient under the configured measure. */
    double vehicleCorrelation(long id, const LandmarkCovarianceView& view) const;
    /** Landmark-to-landmark coefficient under the configured measure. */
    double landmarkCorrelation(long a, long b, const LandmarkCovarianceView& view) const;

    /** Scalar coefficient of blocks (a, b): see the file comment. */
    static double correlationCoefficient(
        const Eigen::MatrixXd& p_aa, const Eigen::MatrixXd& p_ab, const Eigen::MatrixXd& p_bb,
        CorrelationMeasure measure);

    /** True if the interiors of two triangles intersect (separating-axis test with a
     *  tolerance relative to their size: touching along an edge or at a vertex is
     *  not an overlap). */
    static bool interiorsOverlap(
        const TriangleFrame::Vertices& a, const TriangleFrame::Vertices& b);

private:
    const Options options_;
};

}  // namespace hymm::ltr
