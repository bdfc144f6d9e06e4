/**
 * @file TimeLogger.h
 * @brief A CTimeLogger made only when it is enabled or asked for, and the timed section
 *        that goes with it.
 *
 * MRPT 2.5's CTimeLogger holds a fixed hash table of 2,560 entries: 615 KB per object,
 * written at construction. Held by value, the four profilers of a DenseSlam made it
 * 2.4 MB and cost page faults at every construction, although they are off unless
 * `enable_profiler` is set. LazyTimeLogger makes the logger on first use; TimedSection
 * times a section only when the logger exists and is enabled.
 */
#pragma once

#include <mrpt/system/CTimeLogger.h>

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

namespace hymm::core
{
class LazyTimeLogger
{
public:
    explicit LazyTimeLogger(bool enabled = false, std::string name = {}) : name_(std::move(name))
    {
        if (enabled) get().enable();
    }
    LazyTimeLogger(const LazyTimeLogger& o) : name_(o.name_)
    {
        if (o.logger_) logger_ = std::make_unique<mrpt::system::CTimeLogger>(*o.logger_);
    }
    LazyTimeLogger& operator=(const LazyTimeLogger& o)
    {
        if (this != &o) *this = LazyTimeLogger(o);
        return *this;
    }
    LazyTimeLogger(LazyTimeLogger&&) noexcept = default;
    LazyTimeLogger& operator=(LazyTimeLogger&&) noexcept = default;
    ~LazyTimeLogger() = default;

    /** The logger, made (disabled) on first use: for statistics, clear() or enable(). */
    mrpt::system::CTimeLogger& get() const
    {
        if (!logger_) logger_ = std::make_unique<mrpt::system::CTimeLogger>(false, name_);
        return *logger_;
    }
    /** The logger when it exists and is enabled, nullptr otherwise. */
    mrpt::system::CTimeLogger* active() const { return logger_ && logger_->isEnabled() ? logger_.get() : nullptr; }
    /** Enables or disables it; disabling does not make a logger that does not exist. */
    void enable(bool on)
    {
        if (on || logger_) get().enable(on);
    }

private:
    std::string name_;
    mutable std::unique_ptr<mrpt::system::CTimeLogger> logger_;
};

/** mrpt::system::CTimeLoggerEntry on a LazyTimeLogger: times the scope only when the
 *  logger is active at entry. */
class TimedSection
{
public:
    TimedSection(const LazyTimeLogger& logger, std::string_view name)
    {
        if (auto* l = logger.active()) entry_.emplace(*l, name);
    }
    // A copy would stop (and record) the same section twice.
    TimedSection(const TimedSection&) = delete;
    TimedSection& operator=(const TimedSection&) = delete;
    void stop()
    {
        if (entry_) entry_->stop();
    }

private:
    std::optional<mrpt::system::CTimeLoggerEntry> entry_;
};

}  // namespace hymm::core
