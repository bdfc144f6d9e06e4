// summary.txt: the run's counters in readable form, one line per enabled dense layer.
#include <hymm/app/slam_outputs.h>

#include <fstream>
#include <iomanip>
#include <stdexcept>

#include "layer_outputs.h"
#include "return_books.h"

namespace hymm::app
{
namespace
{
// One line per enabled layer: what it holds and its memory.
void writeLayerSummary(std::ostream& f, const DenseSlam& slam)
{
    const auto* hybrid = slam.hybridMap();
    const auto items = hybrid->sizeByKind();
    const auto bytes = hybrid->memoryBytesByKind();
    for (const std::string& kind : hybrid->enabledKinds())
    {
        const size_t n = valueOr0(items, kind);
        f << std::setprecision(1) << "layer " << std::left << std::setw(15) << kind << std::right;
        if (const auto* layer = findLayerOutput(kind))
            layer->describe(f, slam, n);
        else
            f << n << " items";
        f << ", " << valueOr0(bytes, kind) / 1024.0 << " KiB\n" << std::setprecision(3);
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
          << ", waiting " << store->numStoredPoints() << "; not stored: outside potential regions "
          << s.delayed_outside_potential << ", over budget " << s.delayed_thinned
          << "; evicted " << s.delayed_evicted << ", lost " << s.delayed_lost << "\n";
    if (slam.hybridMap()) writeLayerSummary(f, slam);
    if (slam.classicGrid()) f << "classic grid         on\n";
}
}  // namespace

void writeSummary(const DenseSlam& slam, double run_seconds, size_t entries, const std::string& file)
{
    std::ofstream f(file);
    if (!f) throw std::runtime_error("cannot write '" + file + "'");
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
    if (s.reflectors_extracted + s.trees_extracted > 0)
        f << "; reflectors " << s.reflectors_extracted << ", trees " << s.trees_extracted
          << ", trees dropped as a reflector's object " << s.trees_duplicate;
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
    writeRegionSummary(f, slam);
    if (!f) throw std::runtime_error("error writing '" + file + "'");
}

}  // namespace hymm::app
