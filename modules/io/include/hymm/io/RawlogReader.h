/**
 * @file RawlogReader.h
 * @brief Sequential reader of MRPT rawlog files, in either of MRPT's two formats:
 *        action/sensory-frame pairs, or a plain sequence of observations.
 *
 * Unlike CRawlog::getActionObservationPairOrObservation(), which returns `false`
 * both at the end of the file and on a read error, this reader tells the two apart:
 * a clean end returns false, a missing, empty, truncated or corrupt file throws with
 * the path and the entry index, so a bad rawlog never passes for a short one.
 *
 * Hostile sizes: MRPT's deserialiser allocates what a count declares before reading
 * the elements. The reader hands it a stream that knows how many bytes the file holds
 * and refuses, before MRPT reads it, a count of the classes HYMM consumes that cannot
 * fit in them (frames, action collections, 2D scans, bearing-range observations: see
 * src/GuardedRawlogStream.h for the layouts and what is not guarded). Such an entry
 * throws "declares N beams ... but only M bytes follow", and memory stays below about
 * twice the file's uncompressed size (three times for bearing-range measurements).
 * Gzip files are decompressed once when opened to count their bytes; corrupt gzip data
 * is reported as corrupt, at the entry it cuts.
 */
#pragma once

#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservation.h>
#include <mrpt/obs/CSensoryFrame.h>

#include <memory>
#include <string>

namespace hymm::io
{
namespace detail
{
class GuardedRawlogStream;
}

/** One rawlog entry: an action collection, a sensory frame, or a single observation
 *  (exactly one of the three is set). */
struct RawlogEntry
{
    mrpt::obs::CActionCollection::Ptr actions;
    mrpt::obs::CSensoryFrame::Ptr frame;
    mrpt::obs::CObservation::Ptr observation;
};

class RawlogReader
{
public:
    /** Opens `path` (plain or gzip-compressed); throws if it does not exist or cannot be
     *  read. Reads the whole file once to count its uncompressed bytes. */
    explicit RawlogReader(const std::string& path);
    ~RawlogReader();
    RawlogReader(const RawlogReader&) = delete;
    RawlogReader& operator=(const RawlogReader&) = delete;

    /** Reads the next entry. Returns false at a clean end of file; throws
     *  std::runtime_error on a truncated or corrupt entry, or on an object that is
     *  not an action collection, sensory frame or observation. */
    bool next(RawlogEntry& entry);

    /** Entries successfully read so far. */
    size_t entriesRead() const { return entries_; }
    const std::string& path() const { return path_; }

private:
    std::string path_;
    std::unique_ptr<detail::GuardedRawlogStream> stream_;
    size_t entries_ = 0;
};

}  // namespace hymm::io
