/**
 * @file RevisitLog.h
 * @brief Where a run comes back to a landmark it left: an update of a landmark that had
 *        none (nor its creation) for a gap of time is a revisit, the way a loop closes
 *        (by the local alignment when the drift is small, by a wide answer when not).
 */
#pragma once

#include <mrpt/core/Clock.h>
#include <mrpt/serialization/CArchive.h>

#include <map>
#include <utility>
#include <vector>

namespace hymm::scanslam
{
class RevisitLog
{
public:
    struct Revisit
    {
        double t = 0;         //!< [s] scan time, from the run's first scan
        long id = 0;
        double unseen_s = 0;  //!< [s] since its last update (or creation)
        double age_s = 0;     //!< [s] since its creation
        bool wide = false;    //!< by a wide answer (else a local alignment)
    };

    /** The time of the scan being processed (the rawlog's clock); an invalid time keeps
     *  the last one. */
    void setScanTime(mrpt::Clock::time_point t);
    /** Landmark `id` was made now. */
    void created(long id);
    /** Landmark `id` was updated now: listed as a revisit when its last update or
     *  creation is `gap_s` or more ago and earlier than now. */
    void updated(long id, bool wide, double gap_s);
    /** Forgets the landmarks `keep` says no to (removed from the map). */
    template <class Keep>
    void prune(Keep keep)
    {
        for (auto it = seen_.begin(); it != seen_.end();) it = keep(it->first) ? std::next(it) : seen_.erase(it);
    }
    const std::vector<Revisit>& list() const { return revisits_; }

    /** Bit for bit, for a saved run. */
    void save(mrpt::serialization::CArchive& out) const;
    void load(mrpt::serialization::CArchive& in);

private:
    double now_ = 0, first_ = 0;  //!< [s] the current and the first scan's time
    bool has_time_ = false;
    std::map<long, std::pair<double, double>> seen_;  //!< id -> (created, last updated) [s]
    std::vector<Revisit> revisits_;
};

}  // namespace hymm::scanslam
