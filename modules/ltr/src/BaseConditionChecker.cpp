/**
 * @file BaseConditionChecker.cpp
 * @brief Base-landmark selection conditions (thesis Sec. 3.5).
 */
#include "hymm/ltr/BaseConditionChecker.h"

#include <hymm/core/config_utils.h>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace hymm::ltr
{
namespace
{
constexpr double kDeg = 3.14159265358979323846 / 180.0;
// Eigen-directions of a covariance block with variance below this fraction of the
// largest are treated as exactly known when whitening (they carry no error to
// correlate).
constexpr double kRelativeRankTol = 1e-12;
// Absolute variance [m^2 or rad^2] below which a whole block counts as exactly known.
constexpr double kNegligibleVariance = 1e-18;
// Separating-axis tolerance, relative to the size of the two triangles: projections
// that overlap by less than this are touching (shared edge/vertex), not overlapping.
constexpr double kOverlapRelTol = 1e-9;

std::string fmt(const char* what, double value, const char* cmp, double limit)
{
    std::ostringstream os;
    os << what << " " << value << " " << cmp << " " << limit;
    return os.str();
}

CheckResult fail(BaseCondition r, double value, double limit, std::string detail)
{
    return CheckResult{r, value, limit, std::move(detail)};
}

/** Whitening matrix W (n x r) with W^T P W = I on the non-negligible subspace. */
Eigen::MatrixXd whitening(const Eigen::MatrixXd& p)
{
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (p + p.transpose()));
    const Eigen::VectorXd& ev = es.eigenvalues();
    const double emax = ev.maxCoeff();
    if (!(emax > kNegligibleVariance)) return Eigen::MatrixXd(p.rows(), 0);
    std::vector<int> keep;
    for (int i = 0; i < ev.size(); ++i)
        if (ev(i) > kRelativeRankTol * emax) keep.push_back(i);
    Eigen::MatrixXd w(p.rows(), static_cast<long>(keep.size()));
    for (size_t k = 0; k < keep.size(); ++k)
        w.col(static_cast<long>(k)) = es.eigenvectors().col(keep[k]) / std::sqrt(ev(keep[k]));
    return w;
}

double perAxis(const Eigen::MatrixXd& p_aa, const Eigen::MatrixXd& p_ab, const Eigen::MatrixXd& p_bb)
{
    double rho = 1.0;
    for (int k = 0; k < 2; ++k)
    {
        const double den = p_aa(k, k) * p_bb(k, k);
        // A coordinate without variance is exactly known: it cannot deform the region.
        if (!(den > kNegligibleVariance * kNegligibleVariance)) continue;
        rho = std::min(rho, std::abs(p_ab(k, k)) / std::sqrt(den));
    }
    return std::min(rho, 1.0);
}

/** Thesis Fig. 3.10a: the n-sigma ellipse of each vertex (vertices taken as independent,
 *  the conservative case) must not touch the line through the other two vertices, or an
 *  update could flip the triangle over. */
CheckResult checkEllipses(const TriangleFrame::Vertices& v, const std::array<Eigen::Matrix2d, 3>& cov,
                          double ellipse_sigma)
{
    // The half-extent of the ellipse along the unit normal n of that line is
    // n_sigma * sqrt(n^T P n).
    for (int k = 0; k < 3; ++k)
    {
        const Eigen::Vector2d& p = v[static_cast<size_t>(k)];
        const Eigen::Vector2d& q1 = v[static_cast<size_t>((k + 1) % 3)];
        const Eigen::Vector2d& q2 = v[static_cast<size_t>((k + 2) % 3)];
        const Eigen::Vector2d edge = q2 - q1;
        const Eigen::Vector2d n = Eigen::Vector2d(-edge.y(), edge.x()).normalized();
        const double height = std::abs(n.dot(p - q1));
        const Eigen::Matrix2d& c = cov[static_cast<size_t>(k)];
        const double extent = ellipse_sigma * std::sqrt(std::max(0.0, n.dot(c * n)));
        if (!(extent < height))
            return fail(
                BaseCondition::IllConditioned, extent, height,
                "vertex " + std::to_string(k) + ": " +
                    fmt("ellipse half-extent [m]", extent, ">= distance to opposite edge", height));
    }
    return {};
}
}  // namespace

const char* toString(BaseCondition c)
{
    switch (c)
    {
        case BaseCondition::Accepted: return "Accepted";
        case BaseCondition::UnknownLandmark: return "UnknownLandmark";
        case BaseCondition::RepeatedLandmark: return "RepeatedLandmark";
        case BaseCondition::SmallArea: return "SmallArea";
        case BaseCondition::SmallAngle: return "SmallAngle";
        case BaseCondition::DegenerateTriangle: return "DegenerateTriangle";
        case BaseCondition::LongEdge: return "LongEdge";
        case BaseCondition::IllConditioned: return "IllConditioned";
        case BaseCondition::LowVertexCorrelation: return "LowVertexCorrelation";
        case BaseCondition::LowVehicleCorrelation: return "LowVehicleCorrelation";
        case BaseCondition::Overlap: return "Overlap";
        case BaseCondition::TwoVirtualVertices: return "TwoVirtualVertices";
    }
    return "Unknown";
}

// ---------------------------------------------------------------------------------
// Options
// ---------------------------------------------------------------------------------
hymm::core::OptionTable BaseConditionChecker::Options::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.real("min_vertex_correlation", min_vertex_correlation, "", between(0, 1),
           "every vertex pair at least this correlated (condition 1)");
    t.real("min_vehicle_correlation", min_vehicle_correlation, "", between(0, 1),
           "every vertex with the vehicle at least this correlated (0: off)");
    t.choice("correlation_measure", correlation_measure,
             {{"min_canonical", CorrelationMeasure::MinCanonical}, {"per_axis", CorrelationMeasure::PerAxis}},
             "how two 2-D positions' correlation is measured");
    t.real("ellipse_sigma", ellipse_sigma, "sigmas", atLeast(0, 100), "uncertainty ellipse of condition 2 (Fig. 3.10)");
    t.real("min_area_m2", min_area_m2, "m^2", above(0, 1e6), "smallest triangle area");
    t.real("min_angle_deg", min_angle, "deg", halfOpen(0, 60), "smallest triangle angle", kDeg);
    t.real("max_edge_length_m", max_edge_length_m, "m", above(0, 1e4), "longest triangle edge");
    t.real("max_condition_number", max_condition_number, "", atLeast(1, 1e12),
           "of the axes matrix D = [L2-L1, L3-L1]");
    return t;
}

void BaseConditionChecker::Options::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& cfg, const std::string& s)
{
    table().load(cfg, s);
    validate(s);
}

void BaseConditionChecker::Options::saveToConfigFile(
    mrpt::config::CConfigFileBase& cfg, const std::string& s) const
{
    auto copy = *this;
    copy.table().save(cfg, s);
}

void BaseConditionChecker::Options::validate(const std::string& s) const
{
    using hymm::core::throwConfigError;
    auto num = [](double v) { return std::to_string(v); };
    if (!(min_vertex_correlation >= 0 && min_vertex_correlation <= 1))
        throwConfigError(
            s, "min_vertex_correlation", num(min_vertex_correlation), "must be in [0, 1]");
    if (!(min_vehicle_correlation >= 0 && min_vehicle_correlation <= 1))
        throwConfigError(
            s, "min_vehicle_correlation", num(min_vehicle_correlation), "must be in [0, 1]");
    if (!(ellipse_sigma >= 0)) throwConfigError(s, "ellipse_sigma", num(ellipse_sigma), "must be >= 0");
    if (!(min_area_m2 > 0)) throwConfigError(s, "min_area_m2", num(min_area_m2), "must be > 0");
    if (!(min_angle >= 0 && min_angle < 60 * kDeg))
        throwConfigError(s, "min_angle_deg", num(min_angle / kDeg), "must be in [0, 60)");
    if (!(max_edge_length_m > 0))
        throwConfigError(s, "max_edge_length_m", num(max_edge_length_m), "must be > 0");
    if (!(max_condition_number >= 1))
        throwConfigError(s, "max_condition_number", num(max_condition_number), "must be >= 1");
}

// ---------------------------------------------------------------------------------
// Checker
// ---------------------------------------------------------------------------------
BaseConditionChecker::BaseConditionChecker(const Options& options) : options_(options)
{
    options_.validate();
}

double BaseConditionChecker::correlationCoefficient(
    const Eigen::MatrixXd& p_aa, const Eigen::MatrixXd& p_ab, const Eigen::MatrixXd& p_bb,
    CorrelationMeasure measure)
{
    if (p_ab.rows() != p_aa.rows() || p_ab.cols() != p_bb.rows())
        throw std::invalid_argument("correlationCoefficient: block sizes do not match");
    if (measure == CorrelationMeasure::PerAxis) return perAxis(p_aa, p_ab, p_bb);
    const Eigen::MatrixXd wa = whitening(p_aa);
    const Eigen::MatrixXd wb = whitening(p_bb);
    if (wa.cols() == 0 || wb.cols() == 0) return 1.0;
    const Eigen::MatrixXd m = wa.transpose() * p_ab * wb;
    const Eigen::VectorXd s = Eigen::JacobiSVD<Eigen::MatrixXd>(m).singularValues();
    // Only min(ra, rb) canonical correlations exist; JacobiSVD returns exactly those.
    return std::clamp(s(s.size() - 1), 0.0, 1.0);
}

double BaseConditionChecker::vehicleCorrelation(long id, const LandmarkCovarianceView& view) const
{
    const Eigen::MatrixXd p_vv = view.vehicleCov();
    const Eigen::MatrixXd p_lv = view.crossVehicle(id);
    return correlationCoefficient(view.cov(id), p_lv, p_vv, options_.correlation_measure);
}

double BaseConditionChecker::landmarkCorrelation(
    long a, long b, const LandmarkCovarianceView& view) const
{
    return correlationCoefficient(
        view.cov(a), view.crossCov(a, b), view.cov(b), options_.correlation_measure);
}

CheckResult BaseConditionChecker::checkCorrelation(
    const std::array<long, 3>& ids, const LandmarkCovarianceView& view) const
{
    for (int i = 0; i < 3; ++i)
        for (int j = i + 1; j < 3; ++j)
        {
            const long a = ids[static_cast<size_t>(i)], b = ids[static_cast<size_t>(j)];
            const double rho = landmarkCorrelation(a, b, view);
            if (rho < options_.min_vertex_correlation)
                return fail(
                    BaseCondition::LowVertexCorrelation, rho, options_.min_vertex_correlation,
                    "landmarks " + std::to_string(a) + "-" + std::to_string(b) + ": " +
                        fmt("correlation", rho, "<", options_.min_vertex_correlation));
        }
    if (options_.min_vehicle_correlation > 0)
        for (const long id : ids)
        {
            const double rho = vehicleCorrelation(id, view);
            if (rho < options_.min_vehicle_correlation)
                return fail(
                    BaseCondition::LowVehicleCorrelation, rho, options_.min_vehicle_correlation,
                    "landmark " + std::to_string(id) + " with vehicle: " +
                        fmt("correlation", rho, "<", options_.min_vehicle_correlation));
        }
    return {};
}

CheckResult BaseConditionChecker::checkGeometry(
    const std::array<long, 3>& ids, const LandmarkCovarianceView& view) const
{
    return checkGeometry(
        {view.mean(ids[0]), view.mean(ids[1]), view.mean(ids[2])},
        {view.cov(ids[0]), view.cov(ids[1]), view.cov(ids[2])});
}

CheckResult BaseConditionChecker::checkGeometry(
    const TriangleFrame::Vertices& v, const std::array<Eigen::Matrix2d, 3>& cov) const
{
    for (const auto& p : v)
        if (!p.allFinite())
            return fail(BaseCondition::DegenerateTriangle, 0, 0, "a vertex is not finite");
    const double area = 0.5 * std::abs((v[1] - v[0]).x() * (v[2] - v[0]).y() -
                                       (v[1] - v[0]).y() * (v[2] - v[0]).x());
    if (!(area >= options_.min_area_m2))
        return fail(
            BaseCondition::SmallArea, area, options_.min_area_m2,
            fmt("area [m^2]", area, "<", options_.min_area_m2));

    for (int k = 0; k < 3; ++k)
    {
        const Eigen::Vector2d& p = v[static_cast<size_t>(k)];
        const Eigen::Vector2d e1 = v[static_cast<size_t>((k + 1) % 3)] - p;
        const Eigen::Vector2d e2 = v[static_cast<size_t>((k + 2) % 3)] - p;
        const double angle =
            std::atan2(std::abs(e1.x() * e2.y() - e1.y() * e2.x()), e1.dot(e2));
        if (angle < options_.min_angle)
            return fail(
                BaseCondition::SmallAngle, angle, options_.min_angle,
                "vertex " + std::to_string(k) + ": " +
                    fmt("angle [deg]", angle / kDeg, "<", options_.min_angle / kDeg));
    }

    const std::string why = TriangleFrame::degeneracyReason(v, options_.frameLimits());
    if (!why.empty()) return fail(BaseCondition::DegenerateTriangle, 0, 0, why);

    for (int k = 0; k < 3; ++k)
    {
        const double len =
            (v[static_cast<size_t>((k + 1) % 3)] - v[static_cast<size_t>(k)]).norm();
        if (len > options_.max_edge_length_m)
            return fail(
                BaseCondition::LongEdge, len, options_.max_edge_length_m,
                fmt("edge length [m]", len, ">", options_.max_edge_length_m));
    }

    return checkEllipses(v, cov, options_.ellipse_sigma);
}

bool BaseConditionChecker::interiorsOverlap(
    const TriangleFrame::Vertices& a, const TriangleFrame::Vertices& b)
{
    double scale = 0;
    for (int k = 0; k < 3; ++k)
    {
        const size_t i = static_cast<size_t>(k), j = static_cast<size_t>((k + 1) % 3);
        scale = std::max({scale, (a[j] - a[i]).norm(), (b[j] - b[i]).norm()});
    }
    const double tol = kOverlapRelTol * std::max(scale, 1.0);
    // Two convex polygons have disjoint interiors iff some edge normal separates them
    // (touching allowed).
    for (const auto* tri : {&a, &b})
        for (int k = 0; k < 3; ++k)
        {
            const Eigen::Vector2d e =
                (*tri)[static_cast<size_t>((k + 1) % 3)] - (*tri)[static_cast<size_t>(k)];
            const double len = e.norm();
            if (!(len > 0)) continue;
            const Eigen::Vector2d n(-e.y() / len, e.x() / len);
            double amin = INFINITY, amax = -INFINITY, bmin = INFINITY, bmax = -INFINITY;
            for (int m = 0; m < 3; ++m)
            {
                const double pa = n.dot(a[static_cast<size_t>(m)]);
                const double pb = n.dot(b[static_cast<size_t>(m)]);
                amin = std::min(amin, pa);
                amax = std::max(amax, pa);
                bmin = std::min(bmin, pb);
                bmax = std::max(bmax, pb);
            }
            if (std::min(amax, bmax) - std::max(amin, bmin) <= tol) return false;
        }
    return true;
}

CheckResult BaseConditionChecker::checkOverlap(
    const TriangleFrame::Vertices& candidate,
    const std::vector<TriangleFrame::Vertices>& existing) const
{
    for (size_t i = 0; i < existing.size(); ++i)
        if (interiorsOverlap(candidate, existing[i]))
            return fail(
                BaseCondition::Overlap, static_cast<double>(i), 0,
                "interior intersects existing region #" + std::to_string(i) + " of the list");
    return {};
}

CheckResult BaseConditionChecker::check(
    const std::array<long, 3>& ids, const LandmarkCovarianceView& view,
    const std::vector<TriangleFrame::Vertices>& existing) const
{
    for (const long id : ids)
        if (!view.has(id))
            return fail(
                BaseCondition::UnknownLandmark, static_cast<double>(id), 0,
                "landmark " + std::to_string(id) + " is not in the map");
    if (ids[0] == ids[1] || ids[0] == ids[2] || ids[1] == ids[2])
        return fail(BaseCondition::RepeatedLandmark, 0, 0, "a landmark is used twice");
    if (CheckResult r = checkGeometry(ids, view); !r.accepted()) return r;
    if (CheckResult r = checkCorrelation(ids, view); !r.accepted()) return r;
    return checkOverlap({view.mean(ids[0]), view.mean(ids[1]), view.mean(ids[2])}, existing);
}

}  // namespace hymm::ltr
