/**
 * @file HllDetector.h
 * @brief The search for high-level landmarks in the dense maps (thesis 6.1.3): Harris
 *        corners on the occupancy layer, each corner paired with its nearest neighbour
 *        within `pair_max_distance_m` (thesis: 12 m), a rectangle `margin_m` (thesis:
 *        5 m) around each pair, accepted when the SOG layer holds at least
 *        `min_gaussians` (thesis: 200) Gaussians inside it and it overlaps neither an
 *        existing landmark's area nor a rectangle accepted before it.
 *
 * Only the regions near the vehicle are read: the partition's box lookup
 * (RegionPartition::regionsInBox) gives the regions meeting a square of half-side
 * `search_half_size_m` around the vehicle, whose occupancy layers are rendered into a
 * local grid of that square and whose SOG layers give the Gaussians. The cost of one
 * search depends on that area, not on the size of the map.
 *
 * The rectangle of a pair (a, b) is oriented along b - a: its frame has its origin at
 * the midpoint and its x axis from a to b; it reaches `margin_m` beyond each corner
 * along that axis and `margin_m` to either side. That frame is the HLL's local frame
 * (thesis 6.1.2, Fig. 6.2), the pose that enters the state vector (Eq. 6.4).
 *
 * The pieces (corner detection on any grid, pairing, rectangles, acceptance) are free
 * functions so that they can be tested on a synthetic grid with known corners.
 */
#pragma once

#include <hymm/core/OptionTable.h>
#include <hymm/dense/HybridMetricMap.h>
#include <hymm/ltr/RegionPartition.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <utility>
#include <vector>

namespace hymm::hll
{
using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat2 = Eigen::Matrix2d;

/** A rectangle with its own frame: centre, orientation of its x axis, half extents. */
struct OrientedRect
{
    Vec2 centre = Vec2::Zero();
    double phi = 0;            //!< [rad] orientation of the local x axis
    Vec2 half = Vec2::Zero();  //!< [m] half extents along local x and y

    Vec3 pose() const { return {centre.x(), centre.y(), phi}; }
    /** Global point in the rectangle's frame. */
    Vec2 toLocal(const Vec2& p) const;
    bool contains(const Vec2& p) const;
    /** Corners, counter-clockwise from (-hx, -hy). */
    std::array<Vec2, 4> corners() const;
    /** This rectangle (given in a frame) placed by the pose `z` of that frame. */
    OrientedRect placed(const Vec3& z) const;
};

/** Whether two rectangles share area (separating-axis test; touching counts). */
bool overlaps(const OrientedRect& a, const OrientedRect& b);

/** Smallest rectangle, aligned with the frame, around `points` (frame coordinates),
 *  grown by `grow_m` on every side; placed in that frame (centre, phi = 0). */
OrientedRect boundingRect(const std::vector<Vec2>& points, double grow_m = 0);

class HllDetector
{
public:
    /** Ini section [HighLevelLandmarks] (detector keys; HighLevelLandmarks adds its own). */
    struct Options
    {
        double period_s = 60;            //!< log time between two searches (thesis: 1 min)
        double search_half_size_m = 30;  //!< half-side of the square searched around the vehicle
        double cell_size_m = 0.2;        //!< cell of the rendered occupancy patch
        double occupied_prob = 0.65;     //!< a cell above this is occupied in the corner image
        double blur_sigma_cells = 1.0;   //!< smoothing of the corner image (staircase walls)
        int harris_block_size = 5;       //!< [cells] neighbourhood of the Harris matrix
        double harris_k = 0.04;          //!< Harris' free parameter
        double quality_level = 0.05;     //!< corners weaker than this times the best are dropped
        double min_corner_distance_m = 1.0;  //!< non-maximum suppression radius
        int max_corners = 200;           //!< strongest corners kept per search
        double min_object_extent_m = 2.0;  //!< smaller occupied components (poles) make no corners
        double landmark_clearance_m = 1.5; //!< corners this close to a point landmark are dropped
        double pair_max_distance_m = 12; //!< nearest neighbour this close pairs (thesis: 12 m)
        double min_pair_distance_m = 1.0;  //!< closer corners are one corner (no pair)
        double margin_m = 5;             //!< rectangle beyond the corners (thesis: 5 m)
        size_t min_gaussians = 200;      //!< SOG Gaussians needed inside (thesis: 200)
        double min_outline_m = 0;        //!< outline length needed inside (0: not tested)
        double outline_cell_m = 0.2;     //!< cell that measures the outline length

        /** The keys above, declared once. */
        core::OptionTable table();
    };

    /** Why a candidate was or was not accepted. */
    enum class Outcome
    {
        accepted,
        too_few_gaussians,   //!< fewer than min_gaussians inside
        outline_too_short,   //!< less than min_outline_m of outline inside
        overlaps_landmark,   //!< meets an existing landmark's area (an exclusion)
        overlaps_candidate,  //!< meets a rectangle accepted earlier in the same search
    };
    static const char* outcomeName(Outcome o);

    struct Candidate
    {
        Vec2 a = Vec2::Zero(), b = Vec2::Zero();  //!< the pair of corners
        OrientedRect rect;
        size_t gaussians = 0;  //!< SOG means inside rect
        double outline_m = 0;  //!< [m] outline length inside rect (outlineInside)
        Outcome outcome = Outcome::too_few_gaussians;
    };

    /** A SOG Gaussian at its current global position. */
    struct Gaussian
    {
        Vec2 mean = Vec2::Zero();
        Mat2 cov = Mat2::Identity();
    };

    struct Search
    {
        double t = 0;                   //!< [s] log time of the search
        Vec2 lo = Vec2::Zero(), hi = Vec2::Zero();  //!< the square searched
        size_t regions = 0;             //!< regions the box lookup returned
        size_t regions_degenerate = 0;  //!< of those, skipped: current triangle degenerate
        std::vector<Vec2> corners;
        size_t components_dropped = 0;     //!< occupied components below min_object_extent_m
        size_t corners_near_landmark = 0;  //!< corners dropped within landmark_clearance_m
        std::vector<Candidate> candidates;
        std::vector<Gaussian> gaussians;  //!< SOG of the regions searched (templates come from it)
        size_t accepted() const;
    };

    /** What the corner step left out. */
    struct CornerStats
    {
        size_t components_dropped = 0;  //!< occupied components too small to be an object
        size_t near_landmark = 0;       //!< corners on a point landmark
    };

    explicit HllDetector(const Options& options);
    const Options& options() const { return options_; }

    /** One search around `vehicle`: renders the occupancy layers of the regions near it,
     *  finds corners, pairs, rectangles and accepts against the SOG layers and
     *  `exclusions` (areas of landmarks that exist, global frame); no corner within
     *  landmark_clearance_m of one of `point_landmarks` (global). */
    Search search(const Vec2& vehicle, const ltr::RegionPartition& partition,
                  const dense::HybridMetricMap& map, const std::vector<OrientedRect>& exclusions,
                  double t, const std::vector<Vec2>& point_landmarks = {}) const;

    // --- the steps, on any grid ------------------------------------------------------
    /** Harris corners (cv::goodFeaturesToTrack with the Harris measure) of the occupied
     *  cells of `grid`, in the grid's metric coordinates; occupied components smaller
     *  than min_object_extent_m are left out of the image, corners within
     *  landmark_clearance_m of one of `point_landmarks` are dropped (counted in `stats`). */
    std::vector<Vec2> detectCorners(const mrpt::maps::COccupancyGridMap2D& grid,
                                    const std::vector<Vec2>& point_landmarks = {},
                                    CornerStats* stats = nullptr) const;
    /** Each corner with its nearest neighbour when that is within [min_pair_distance_m,
     *  pair_max_distance_m]; unordered pairs (i < j), each once. */
    std::vector<std::pair<size_t, size_t>> pairCorners(const std::vector<Vec2>& corners) const;
    /** The rectangle of a pair (see the file comment). */
    OrientedRect pairRectangle(const Vec2& a, const Vec2& b) const;
    /** Candidates of `corners` with their Gaussian counts and outcomes: sorted by count
     *  (most first), each accepted when it has min_gaussians and meets neither an
     *  exclusion nor an accepted candidate. */
    std::vector<Candidate> evaluate(const std::vector<Vec2>& corners,
                                    const std::vector<Gaussian>& gaussians,
                                    const std::vector<OrientedRect>& exclusions) const;

private:
    Options options_;
};

/** Number of `gaussians` whose mean lies in `rect`. */
size_t countInside(const OrientedRect& rect, const std::vector<HllDetector::Gaussian>& gaussians);
/** [m] Length of outline in `rect`, independent of how many Gaussians a metre holds: the
 *  number of distinct cells of side `cell_m` (in the rectangle's frame) holding a mean,
 *  times `cell_m`. */
double outlineInside(const OrientedRect& rect, const std::vector<HllDetector::Gaussian>& gaussians, double cell_m);

}  // namespace hymm::hll
