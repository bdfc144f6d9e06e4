// summary.txt: the run's counters in readable form, one line per enabled dense layer.
#include <hymm/app/slam_outputs.h>
#include <hymm/core/output_files.h>

#include <fstream>
#include <iomanip>
#include <stdexcept>
#include <string>
#include <vector>

#include "output_helpers.h"
#include "return_books.h"

namespace hymm::app
{
namespace
{
// One line per enabled layer: what it holds and its memory.
void writeLayerSummary(std::ostream& f, const DenseSlam& slam)
{
    const auto items = slam.hybridMap()->sizeByKind();
    const auto bytes = slam.hybridMap()->memoryBytesByKind();
    const auto context = layerOutputContext(slam);
    for (const auto* k : enabledLayerKinds(slam))
    {
        f << std::setprecision(1) << "layer " << std::left << std::setw(15) << k->name << std::right;
        k->outputs.describe(f, context, valueOr0(items, k->name));
        f << ", " << valueOr0(bytes, k->name) / 1024.0 << " KiB\n" << std::setprecision(3);
    }
}

void writeRegionSummary(std::ostream& f, const DenseSlam& slam)
{
    const auto& s = slam.stats();
    if (const auto* p = slam.partition())
        f << "regions (LTR)        " << p->size() << " (created " << s.regions_created << ", removed "
          << s.regions_removed << ", partition updates " << s.partition_updates << ")\n"
          << "dense scans          " << s.dense_scans << " (returns stored " << s.returns_stored
          << ", outside regions " << s.returns_outside << " [kept by the fallback "
          << s.returns_fallback << ", in the delayed store " << s.delayed_stored << ", dropped "
          << s.returns_dropped << "], withheld " << s.returns_withheld << " [kept by the fallback "
          << s.returns_withheld_fallback << "]"
          << "; no-return beams as free space " << s.no_return_beams << ", failed readings "
          << s.failed_readings << ")\n"
          // ltr/outside_causes.h, on the final map; in brackets: of the dropped ones.
          << "outside, why (final) " << describeOutsideCauses(slam) << "\n"
          << "virtual landmarks    " << slam.virtualLandmarkIds().size() << " (created "
          << s.virtual_landmarks << ", apexes rejected " << s.virtual_rejected << ")\n";
    if (const auto* store = slam.delayedStore())
        f << "delayed store        stored " << s.delayed_stored << ", fused " << s.delayed_fused
          << ", kept later by the fallback " << s.delayed_fused_fallback << ", waiting " << store->numStoredPoints() << "; not stored: outside potential regions "
          << s.delayed_outside_potential << ", over budget " << s.delayed_thinned
          << "; evicted " << s.delayed_evicted << ", lost " << s.delayed_lost << "\n";
    if (slam.hybridMap()) writeLayerSummary(f, slam);
    if (slam.classicGrid()) f << "classic grid         on\n";
}
}  // namespace

std::vector<std::string> runWarnings(const DenseSlam& slam)
{
    const auto& s = slam.stats();
    std::vector<std::string> w;
    size_t unsupported = 0;
    std::string classes;
    for (const auto& [name, n] : s.unsupported)
    {
        unsupported += n;
        classes += (classes.empty() ? "" : ", ") + name + " " + std::to_string(n);
    }
    const size_t not_used = s.observations_unused + unsupported;
    const std::string why = " (" + std::to_string(s.observations_unused) +
                            " of a kind this config does not use, " + std::to_string(unsupported) +
                            " of unsupported types" + (classes.empty() ? "" : ": " + classes) + ")";
    if (s.rawlog_observations == 0)
        w.push_back("the rawlog held no observations (" + std::to_string(s.entries) + " entries)");
    else if (not_used == s.rawlog_observations)
        w.push_back("none of the rawlog's " + std::to_string(s.rawlog_observations) +
                    " observations was used" + why);
    else if (2 * not_used > s.rawlog_observations)
        w.push_back("most observations were not used: " + std::to_string(not_used) + " of " +
                    std::to_string(s.rawlog_observations) + why);
    // Per-scan sources (scan landmarks) and HLLs update the filter with their own
    // observations.
    size_t source_changes = slam.highLevelLandmarks() ? slam.highLevelLandmarks()->mapChanges() : 0;
    for (const auto& src : slam.scanSources()) source_changes += src->mapChanges();
    if (s.rawlog_observations > 0 && s.observations == 0 && source_changes == 0)
        w.push_back("no landmark observation reached the filter (" + std::to_string(s.frames) +
                    " frames, " + std::to_string(s.scans) + " laser scans, " +
                    std::to_string(s.extracted) + " landmarks extracted)");
    if (s.frames > 1 && s.predictions == 0)
        w.push_back("the rawlog holds no odometry: no motion prediction in " +
                    std::to_string(s.frames) + " frames");
    if (s.time_backwards > 0)
        w.push_back("time went backwards " + std::to_string(s.time_backwards) +
                    " times (frames stamped before the previous one); ground truth matched "
                    "by time will not line up");
    return w;
}

void writeSummary(const DenseSlam& slam, double run_seconds, size_t entries, const std::string& file,
                  const std::vector<std::string>& warnings)
{
    core::AtomicTextFile f(file);
    const auto& s = slam.stats();
    const auto pose = slam.ekf().vehiclePose();
    f << std::fixed << std::setprecision(3) << "rawlog entries       " << entries << "\n"
      << "predictions          " << s.predictions << "\n"
      << "sensory frames       " << s.frames << "\n"
      << "observations         " << s.observations << " (associated " << s.associated
      << ", created " << s.created << ", gate rejects " << s.rejected_gate << ", ambiguous "
      << s.ambiguous << ", numeric rejects " << s.rejected_numeric << ")\n"
      << "skipped readings     " << s.skipped_invalid << "\n"
      << "laser scans          " << s.scans << " (landmarks extracted " << s.extracted;
    const size_t reflectors = valueOr0(s.point_features, "laser_reflectors"),
                 trees = valueOr0(s.point_features, "laser_trees");
    if (reflectors + trees > 0)
        f << "; reflectors " << reflectors << ", trees " << trees << ", trees dropped as a reflector's object "
          << valueOr0(s.point_duplicates, "laser_trees");
    f << ")\n"
      << "landmarks in map     " << slam.ekf().numLandmarks();
    if (!slam.landmarkFeatures().empty())
    {
        const auto by = landmarksByFeature(slam);
        f << " (observed as reflector only " << by.reflector_only << ", as tree only "
          << by.tree_only << ", as both " << by.both << ")";
    }
    f << "\n"
      << "final pose           " << pose[0] << " " << pose[1] << " " << pose[2] << "\n"
      << "run time [s]         " << run_seconds << "\n";
    writeScanSourceSummary(f, slam);
    writeHllSummary(f, slam);
    writeRegionSummary(f, slam);
    if (!s.unsupported.empty())
    {
        f << "unsupported obs.    ";
        for (const auto& [name, n] : s.unsupported) f << " " << name << " " << n;
        f << "\n";
    }
    if (s.time_backwards + s.time_repeated > 0)
        f << "frame time stamps    " << s.time_backwards << " earlier than the previous frame, "
          << s.time_repeated << " equal to it\n";
    if (s.odometry_invalid + s.frames_duplicate + s.frames_without_odometry +
            s.scans_without_valid_beam + s.observations_invalid_geometry > 0)
        f << "faults               non-finite odometry skipped " << s.odometry_invalid
          << ", duplicated frames skipped " << s.frames_duplicate << "; frames without odometry "
          << s.frames_without_odometry << ", scans without a valid beam "
          << s.scans_without_valid_beam << ", observations with an unusable sensor pose or scan geometry skipped "
          << s.observations_invalid_geometry << "\n";
    for (const auto& w : warnings) f << "warning              " << w << "\n";
    f.commit();
}

}  // namespace hymm::app
