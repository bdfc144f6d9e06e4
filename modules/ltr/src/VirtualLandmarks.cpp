#include "hymm/ltr/VirtualLandmarks.h"

#include <hymm/core/config_utils.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <string>

namespace hymm::ltr
{
hymm::core::OptionTable VirtualLandmarkOptions::table()
{
    using namespace hymm::core;
    OptionTable t;
    t.flag("enabled", enabled, "create virtual landmarks (Sec. 3.5.1)");
    t.real("min_vehicle_correlation", min_vehicle_correlation, "", between(0, 1),
           "of each real edge vertex with the vehicle");
    t.integer("min_points", min_points, "returns", 1, 100000, "returns beyond an edge needed to propose a virtual vertex");
    t.real("min_depth_m", min_depth_m, "m", above(0, 1000), "smallest apex distance from the edge");
    t.real("max_depth_m", max_depth_m, "m", above(0, 1000), "returns deeper than this are not considered (> min_depth_m)");
    t.real("margin_m", margin_m, "m", atLeast(0, 1000), "added to the depth that holds the returns");
    t.real("search_radius_m", search_radius_m, "m", above(0, 1e4), "edges with both ends this close to the vehicle");
    t.integer("max_per_frame", max_per_frame, "", 0, 1000, "virtual landmarks created per frame at most");
    t.real("position_std_m", position_std_m, "m", above(0, 100),
           "definitional noise added to the propagated covariance");
    return t;
}

void VirtualLandmarkOptions::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& cfg, const std::string& s)
{
    table().load(cfg, s);
    validate(s);
}

void VirtualLandmarkOptions::saveToConfigFile(
    mrpt::config::CConfigFileBase& cfg, const std::string& s) const
{
    auto copy = *this;
    copy.table().save(cfg, s);
}

void VirtualLandmarkOptions::validate(const std::string& s) const
{
    using hymm::core::throwConfigError;
    if (!(min_vehicle_correlation >= 0 && min_vehicle_correlation <= 1))
        throwConfigError(s, "min_vehicle_correlation", std::to_string(min_vehicle_correlation),
                         "must be in [0, 1]");
    if (min_points < 1) throwConfigError(s, "min_points", std::to_string(min_points), "must be >= 1");
    if (!(min_depth_m > 0))
        throwConfigError(s, "min_depth_m", std::to_string(min_depth_m), "must be > 0");
    if (!(max_depth_m > min_depth_m))
        throwConfigError(s, "max_depth_m", std::to_string(max_depth_m), "must be > min_depth_m");
    if (!(margin_m >= 0)) throwConfigError(s, "margin_m", std::to_string(margin_m), "must be >= 0");
    if (!(search_radius_m > 0))
        throwConfigError(s, "search_radius_m", std::to_string(search_radius_m), "must be > 0");
    if (max_per_frame < 0)
        throwConfigError(s, "max_per_frame", std::to_string(max_per_frame), "must be >= 0");
    if (!(position_std_m > 0))
        throwConfigError(s, "position_std_m", std::to_string(position_std_m), "must be > 0");
}

namespace
{
double cross(const Eigen::Vector2d& u, const Eigen::Vector2d& v)
{
    return u.x() * v.y() - u.y() * v.x();
}

bool strictlyInside(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                    const Eigen::Vector2d& c)
{
    const double d1 = cross(b - a, p - a), d2 = cross(c - b, p - b), d3 = cross(a - c, p - c);
    return (d1 > 0 && d2 > 0 && d3 > 0) || (d1 < 0 && d2 < 0 && d3 < 0);
}

/** A free edge: no other region uses both ends. */
bool freeEdge(const RegionPartition& partition, long a, long b)
{
    const auto ra = partition.regionsUsingLandmark(a), rb = partition.regionsUsingLandmark(b);
    size_t shared = 0;
    for (const long x : ra) shared += std::count(rb.begin(), rb.end(), x);
    return shared == 1;
}

/** "Created at a moment where the vehicle is highly correlated with the other two
 *  landmarks" (Sec. 3.5.1). */
bool correlated(const RegionPartition& partition, const LandmarkCovarianceView& view, long a, long b,
                const VirtualLandmarkOptions& options)
{
    const auto& chk = partition.checker();
    return !(chk.vehicleCorrelation(a, view) < options.min_vehicle_correlation ||
             chk.vehicleCorrelation(b, view) < options.min_vehicle_correlation);
}

/** Whether edge (a, b) may carry a virtual landmark: two real landmarks of the filter,
 *  a free edge, both ends `near` the vehicle and correlated with it. */
template <class Near>
bool usableEdge(const RegionPartition& partition, const LandmarkCovarianceView& view, long a, long b,
                const VirtualLandmarkOptions& options, const Near& near)
{
    if (view.isVirtual(a) || view.isVirtual(b) || !view.has(a) || !view.has(b)) return false;
    return freeEdge(partition, a, b) && near(a) && near(b) && correlated(partition, view, a, b, options);
}

/** Unit normal of edge e = pb - pa pointing away from the region's third vertex pc;
 *  `side` (-1 or 1) is the sign that turned it so. */
Eigen::Vector2d outwardNormal(const Eigen::Vector2d& e, const Eigen::Vector2d& pa, const Eigen::Vector2d& pc,
                              double& side)
{
    Eigen::Vector2d n(-e.y(), e.x());
    n.normalize();
    side = n.dot(pc - pa) > 0 ? -1.0 : 1.0;  // away from the owning region
    n *= side;
    return n;
}

/** Depth of the apex on the bisector of edge (pa, pa + e) (unit outward normal n) that puts
 *  each return inside the triangle: at edge parameter t and height h the triangle is
 *  2 D min(t, 1-t) tall. One depth per return that fits within max_depth_m. */
std::vector<double> apexDepths(const std::vector<Eigen::Vector2d>& unassigned, const Eigen::Vector2d& pa,
                               const Eigen::Vector2d& e, const Eigen::Vector2d& n,
                               const VirtualLandmarkOptions& options)
{
    const double len2 = e.squaredNorm();
    std::vector<double> need;
    for (const auto& p : unassigned)
    {
        const double t = (p - pa).dot(e) / len2;
        const double h = (p - pa).dot(n);
        if (!(t > 0 && t < 1 && h > 0 && h <= options.max_depth_m)) continue;
        const double d = h / (1.0 - std::abs(2.0 * t - 1.0));
        if (d + options.margin_m <= options.max_depth_m) need.push_back(d);
    }
    return need;
}

/** Whether a landmark lies inside the proposed triangle; only landmarks within reach of
 *  it are tested (idsNear: no scan of the map). */
bool holdsLandmark(const LandmarkCovarianceView& view, const VirtualLandmarkProposal& p)
{
    const Eigen::Vector2d pa = view.mean(p.a), pb = view.mean(p.b);
    const double reach = p.depth + (pb - pa).norm();
    for (const long id : view.idsNear(p.edge_midpoint, reach))
        if (id != p.a && id != p.b && strictlyInside(view.mean(id), pa, pb, p.position)) return true;
    return false;
}
}  // namespace

Eigen::Vector2d virtualApex(
    const Eigen::Vector2d& a, const Eigen::Vector2d& b, double side, double depth,
    Eigen::Matrix2d* J_a, Eigen::Matrix2d* J_b)
{
    const Eigen::Vector2d e = b - a;
    const double len = e.norm();
    if (!(len > 0)) throw std::invalid_argument("virtualApex: the edge vertices coincide");
    Eigen::Matrix2d rot90;
    rot90 << 0, -1, 1, 0;
    const Eigen::Vector2d u = e / len;
    if (J_a || J_b)
    {
        // d(Rot90 e / |e|)/de = Rot90 (I - u u^T) / |e|.
        const Eigen::Matrix2d dn =
            side * depth * rot90 * (Eigen::Matrix2d::Identity() - u * u.transpose()) / len;
        if (J_a) *J_a = 0.5 * Eigen::Matrix2d::Identity() - dn;
        if (J_b) *J_b = 0.5 * Eigen::Matrix2d::Identity() + dn;
    }
    return 0.5 * (a + b) + side * depth * (rot90 * u);
}

std::vector<VirtualLandmarkProposal> proposeVirtualLandmarks(
    const RegionPartition& partition, const LandmarkCovarianceView& view,
    const std::vector<Eigen::Vector2d>& unassigned, const VirtualLandmarkOptions& options)
{
    std::vector<VirtualLandmarkProposal> out;
    if (!options.enabled || options.max_per_frame == 0 ||
        unassigned.size() < static_cast<size_t>(options.min_points))
        return out;
    const Eigen::Vector2d vehicle = view.vehiclePose().head<2>();
    const double r = options.search_radius_m;
    const auto near = [&](long id) { return (view.mean(id) - vehicle).norm() <= r; };

    std::set<std::pair<long, long>> seen;
    for (const long rid : partition.regionsInBox(vehicle - Eigen::Vector2d::Constant(r),
                                                 vehicle + Eigen::Vector2d::Constant(r)))
    {
        const Region& reg = partition.region(rid);
        for (int k = 0; k < 3; ++k)
        {
            const long a = reg.vertex_ids[k], b = reg.vertex_ids[(k + 1) % 3];
            const long c = reg.vertex_ids[(k + 2) % 3];
            if (!seen.insert({std::min(a, b), std::max(a, b)}).second) continue;
            if (!usableEdge(partition, view, a, b, options, near)) continue;

            const Eigen::Vector2d pa = view.mean(a), pb = view.mean(b), pc = view.mean(c);
            const Eigen::Vector2d e = pb - pa;
            const double len2 = e.squaredNorm();
            if (!(len2 > 0)) continue;
            double side = 0;
            const Eigen::Vector2d n = outwardNormal(e, pa, pc, side);
            const std::vector<double> need = apexDepths(unassigned, pa, e, n, options);
            if (need.size() < static_cast<size_t>(options.min_points)) continue;
            const double depth = std::max(
                options.min_depth_m, *std::max_element(need.begin(), need.end()) + options.margin_m);

            VirtualLandmarkProposal prop;
            prop.a = a;
            prop.b = b;
            prop.region = rid;
            prop.edge_midpoint = 0.5 * (pa + pb);
            prop.outward = n;
            prop.side = side;
            prop.depth = depth;
            prop.position = prop.edge_midpoint + depth * n;
            prop.points = need.size();
            out.push_back(prop);
        }
    }
    // A triangle holding a landmark would block the real regions around it.
    out.erase(std::remove_if(out.begin(), out.end(),
                             [&](const VirtualLandmarkProposal& p) { return holdsLandmark(view, p); }),
              out.end());
    std::sort(out.begin(), out.end(), [](const auto& x, const auto& y) {
        return x.points > y.points || (x.points == y.points && std::make_pair(x.a, x.b) < std::make_pair(y.a, y.b));
    });
    if (out.size() > static_cast<size_t>(options.max_per_frame))
        out.resize(static_cast<size_t>(options.max_per_frame));
    return out;
}

}  // namespace hymm::ltr
