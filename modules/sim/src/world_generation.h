/**
 * @file world_generation.h
 * @brief Private: landmarks and objects scattered along both sides of the path.
 *
 * Candidates are proposed every `spacing` metres of path on each side, at a random
 * lateral offset and along-path jitter; a candidate too close to the path, to an object
 * or to another landmark is dropped (not retried), so the result depends only on the
 * options and the generation seed.
 */
#pragma once

#include <mrpt/random/RandomGenerators.h>

#include "hymm/sim/ClosedPath.h"
#include "hymm/sim/World.h"

namespace hymm::sim::detail
{
class WorldGenerator
{
public:
    WorldGenerator(const World::Options& options, const ClosedPath& path);

    /** Appends generated objects (named gen_<n>, kind "generated"). */
    void addObjects(std::vector<WorldObject>& objects);

    /** Appends generated landmarks that keep clear of `objects`. */
    void addLandmarks(std::vector<Landmark>& landmarks, const std::vector<WorldObject>& objects);

private:
    /** A point `offset` metres left (side = +1) or right (-1) of the path near `s`. */
    Vec2 besidePath(double s, double spacing, int side, double off_min, double off_max);
    Polygon randomShape();

    const World::Options& o_;
    const ClosedPath& path_;
    mrpt::random::CRandomGenerator rng_;
};

}  // namespace hymm::sim::detail
