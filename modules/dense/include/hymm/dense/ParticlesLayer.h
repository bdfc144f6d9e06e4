/**
 * @file ParticlesLayer.h
 * @brief Sample-based occupancy of one region (thesis Sec. 4.2, particle-DenseSLAM).
 *
 * Each particle is a position in the region's reference frame with a weight
 * w = P(occupied) (Eq. 4.9). Per scan (insert()):
 *  1. Observation model (Eq. 4.8-4.9): `samples_per_return` samples are drawn from the
 *     range-bearing sensor model (Gaussian in range and bearing, in the current metric
 *     frame, then mapped to the reference frame) around each return, and weighted by
 *     the occupancy model of that return (sensor_models.h, Eq. 4.4).
 *  2. Association (Eq. 4.10): every prior particle j takes the nearest new sample i
 *     closer than d_min; one new sample may update several prior ones (Fig. 4.9).
 *  3. Update (Eq. 4.11): w_j <- Bayes(w_j, w_i); with `position_averaging` the prior
 *     particle also moves to the mean of the two positions (Sec. 4.2.3). Samples that
 *     updated a prior particle are consumed; the others join the map with w = w_i
 *     (Eq. 4.12: a new sample on a 0.5 prior keeps its own weight).
 *  4. Free space (end of Sec. 4.2.2): prior particles not updated in step 3 that lie in
 *     the free part of a beam of this scan are re-weighted with the occupancy model of
 *     that beam through Eq. 4.11, so an area vacated by a moving object loses its
 *     occupancy. A particle inside the peak of any beam's model is left alone
 *     (occupied evidence wins, as in the grid layers), and several beams over one
 *     particle give one update with the most "free" value. Beams with no return
 *     (RegionScan rays with beam_hit = false) take part like the others.
 *     Protection (`free_space_protection`): a beam's free part is a cone (bearing
 *     noise), so it also sweeps particles its neighbours explain; the thesis' step
 *     lowers every particle "under the free space region". A particle is therefore
 *     NOT lowered by any beam of the scan when
 *      (a) a return of the same scan (this region's, those of beams crossing it, and
 *          RegionScan::shadow_returns) lies closer than d_min to it: the surface it
 *          describes was seen now (a wall at grazing incidence, an object's edge), or
 *      (b) it lies beyond the return of one of its own beams, the beams of the scan
 *          nearest its bearing on either side (within the cone): it is hidden behind
 *          a nearer surface (an object partly occluding another). Both neighbours are
 *          used, not only the nearest: at grazing incidence consecutive returns on a
 *          wall lie farther apart than 2 d_min, and a particle between two of them
 *          lies beyond the nearer return and in front of the farther one.
 *     A vacated area seen through beams that return nothing, or from a surface
 *     behind it, has no return within d_min and lies in front of its beams' returns:
 *     it is still lowered.
 *  5. Particles below `min_weight` are removed; with `max_per_cell` > 0 at most that
 *     many are kept per square cell of side d_min (reference frame), the heaviest; with
 *     `max_particles` > 0 only the heaviest `max_particles` of the region are kept.
 *     Why the cell cap (revisits): a prior particle absorbs at most one sample per scan
 *     (step 3), so every scan adds the samples no particle took, and the weights of
 *     samples drawn from the sensor model are >= p_min > min_weight: a surface seen
 *     again and again gathers particles without end (the chapter-3 world: +100k per
 *     lap, linearly, docs/benchmarks.md "Soak"), and steps 2-4 walk them all. d_min is
 *     the layer's resolution (two particles closer than it take the same samples), so
 *     a cap per d_min cell bounds memory and cost by the area mapped, and keeping the
 *     heaviest keeps the ones the returns confirmed most (the layer describes occupied
 *     structure, Sec. 4.2.1).
 * Distances (d_min) are measured in the reference frame; the affine reference ->
 * current map of a region is close to a rigid motion, so this equals the metric
 * distance up to the (small) deformation of the triangle.
 *
 * Printed Eq. 4.11 writes the prior of the denominator as P(s(x_i)|r^k); the Bayes rule
 * for the state of x_j needs P(s(x_j)|r^k) in both places (the new sample x_i has no
 * prior). bayesOccupancyUpdate() implements the corrected form; a test checks it.
 */
#pragma once

#include <hymm/core/OptionTable.h>
#include "hymm/dense/DenseLayer.h"
#include "hymm/dense/sensor_models.h"

#include <mrpt/config/CLoadableOptions.h>

#include <cstdint>
#include <random>
#include <vector>

namespace hymm::dense
{
class ParticlesLayer : public DenseLayer
{
public:
    /** Ini section [ParticlesLayer]; unknown keys are errors. */
    struct Options : public mrpt::config::CLoadableOptions
    {
        int samples_per_return = 20;  //!< samples drawn from the sensor model per return
        double range_std_m = 0.1;     //!< [m] sensor noise when the scan carries none (Table 4.1)
        double bearing_std_deg = 1.0; //!< [deg] idem
        double prob_min = 0.3;        //!< p_min of Eq. 4.4: occupancy deep in free space
        double prob_max = 0.9;        //!< p_max of Eq. 4.4: occupancy at the return
        double d_min_m = 0.2;         //!< [m] association distance, Eq. 4.10 (Sec. 4.2.3)
        bool position_averaging = true;  //!< move associated particles to the mean (Sec. 4.2.3)
        bool free_space_update = true;   //!< step 4 (vacated areas lose weight)
        /** step 4 protection: particles explained by a return of the scan (d_min) or
         *  hidden behind one of their own beams' returns are not lowered */
        bool free_space_protection = true;
        double min_weight = 0.1;      //!< particles below are removed
        double max_weight = 0.99;     //!< upper clamp so particles stay revisable
        int max_particles = 0;        //!< per region; 0 = unbounded (thesis: no subsampling)
        /** per square cell of side d_min, the heaviest kept; 0 = unbounded (thesis) */
        int max_per_cell = 8;
        int random_seed = 1;          //!< mixed with the region's vertices: reproducible maps
        double render_min_weight = 0.0;  //!< renderInto draws particles with w >= this

        /** Every ini key, declared once: loader, saver and README table come from it. */
        hymm::core::OptionTable table();
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
        void validate(const std::string& section = "ParticlesLayer") const;

        RangeBearingNoise noise() const;
        OccupancyProfile profile() const { return {prob_min, prob_max}; }
    };

    struct Particle
    {
        Eigen::Vector2d position;  //!< reference-frame coordinates [m]
        double weight;             //!< P(occupied), Eq. 4.9
    };

    /** Per-insert counts (diagnostics and tests). */
    struct UpdateStats
    {
        size_t drawn = 0;         //!< samples drawn from the sensor model
        size_t associated = 0;    //!< prior particles updated by a new sample (Eq. 4.11)
        size_t added = 0;         //!< new samples kept as particles (Eq. 4.12)
        size_t free_updated = 0;  //!< prior particles re-weighted as free space
        size_t free_protected = 0;  //!< in a beam's free part, kept by the protection of step 4
        size_t removed = 0;       //!< below min_weight or subsampled away
    };

    static constexpr const char* kKind = "particles";

    /** `reference` seeds the random stream (different regions draw differently). */
    ParticlesLayer(const Options& options, const hymm::ltr::TriangleFrame::Vertices& reference);

    std::string kind() const override { return kKind; }
    void insert(const RegionScan& scan) override;
    size_t size() const override { return particles_.size(); }
    size_t memoryBytes() const override;
    /** Into a mrpt::maps::CPointsMap: particle positions (w >= render_min_weight) at the
     *  current region position; into a CPointsMapXYZI the weight is the intensity. */
    void renderInto(
        const hymm::ltr::AffineRegionMap& reference_to_current,
        mrpt::maps::CMetricMap& out) const override;
    void save(std::ostream& out) const override;
    void load(std::istream& in) override;
    void saveState(mrpt::serialization::CArchive& out) const override;  //!< DenseLayerState.cpp
    void loadState(mrpt::serialization::CArchive& in) override;

    const std::vector<Particle>& particles() const { return particles_; }
    const UpdateStats& lastUpdate() const { return last_; }

private:
    struct Beam
    {
        double bearing;  // current frame [rad]
        double range;    // to the return / max-range end [m]
        bool hit;
    };
    std::vector<Particle> drawSamples(const RegionScan& scan, const Eigen::Matrix2d& to_current_linear);
    /** Steps 2-3; flags the prior particles it updated, returns the unused samples. */
    std::vector<Particle> associate(const std::vector<Particle>& samples, std::vector<char>& updated);
    void freeSpaceUpdate(
        const RegionScan& scan, const Eigen::Matrix2d& to_current_linear,
        const std::vector<char>& updated);
    /** Beams of the scan in the current frame sorted by bearing (rays, then the shadow
     *  returns), and the scan's returns in the reference frame. */
    void scanBeams(
        const RegionScan& scan, const Eigen::Matrix2d& to_current_linear, std::vector<Beam>& beams,
        std::vector<Eigen::Vector2d>& returns) const;
    /** Rule (b) of step 4: a particle at (rho, phi) [m, rad] lies beyond the return of
     *  the beam nearest its bearing on either side, within `half` [rad]. `beams` sorted
     *  by bearing. */
    static bool hiddenBehindOwnBeams(const std::vector<Beam>& beams, double rho, double phi, double half);
    void prune();

    const Options options_;
    std::vector<Particle> particles_;
    std::mt19937_64 rng_;
    RangeBearingNoise noise_;  // of the scan being inserted
    UpdateStats last_;
};

}  // namespace hymm::dense
