/**
 * @file geometry.h
 * @brief Exact 2D geometry of the simulated world: rays against circles, segments and
 *        polygons, and the distances used to place generated landmarks and objects.
 *
 * Rays are o + t d with |d| = 1 and t >= 0; a hit is the smallest such t on the
 * boundary. A ray that starts inside a circle or polygon hits its boundary on the way
 * out (the first boundary crossing), so a sensor placed inside an object sees that
 * object's wall at the exit distance. A ray running exactly along a segment (parallel
 * and collinear) does not hit it: a laser beam grazing a wall returns from whatever
 * lies behind it.
 */
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

namespace hymm::sim
{
using Vec2 = Eigen::Vector2d;

/** Closed polygon: the last vertex joins the first. Either orientation. */
using Polygon = std::vector<Vec2>;

/** Distance t >= 0 from `o` along unit `d` to the circle (c, r), or nullopt. */
std::optional<double> rayCircle(const Vec2& o, const Vec2& d, const Vec2& c, double r);

/** Distance t >= 0 from `o` along unit `d` to segment [a, b], or nullopt (parallel
 *  rays included). */
std::optional<double> raySegment(const Vec2& o, const Vec2& d, const Vec2& a, const Vec2& b);

/** Nearest boundary hit of the ray with any edge of `poly`, or nullopt. */
std::optional<double> rayPolygon(const Vec2& o, const Vec2& d, const Polygon& poly);

/** Even-odd test; points exactly on the boundary may go either way. */
bool pointInPolygon(const Vec2& p, const Polygon& poly);

double pointSegmentDistance(const Vec2& p, const Vec2& a, const Vec2& b);

/** Distance from `p` to the polygon as a solid: 0 inside, else to the nearest edge. */
double pointPolygonDistance(const Vec2& p, const Polygon& poly);

/** Distance between two segments (0 if they cross). */
double segmentSegmentDistance(const Vec2& a0, const Vec2& a1, const Vec2& b0, const Vec2& b1);

/** Distance between the boundaries of two closed polylines (0 if they cross). */
double boundaryDistance(const Polygon& a, const Polygon& b);

/** Distance between two polygons as solids: 0 if they overlap or one holds the other. */
double polygonDistance(const Polygon& a, const Polygon& b);

/** Signed area (> 0 counter-clockwise). */
double signedArea(const Polygon& poly);

/** `local` rotated by `phi` then translated by (x, y). */
Polygon transformPolygon(const Polygon& local, double x, double y, double phi);

/** Centre and radius of a circle holding every vertex (centroid of the vertices and
 *  the largest distance to it; not the minimal one). */
void boundingCircle(const Polygon& poly, Vec2& centre, double& radius);

}  // namespace hymm::sim
