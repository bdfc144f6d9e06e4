#include "hymm/io/RawlogReader.h"

#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/filesystem.h>

#include <stdexcept>

#include "GuardedRawlogStream.h"

namespace hymm::io
{
RawlogReader::RawlogReader(const std::string& path) : path_(path)
{
    if (!mrpt::system::fileExists(path))
        throw std::runtime_error("rawlog not found: '" + path + "'");
    stream_ = std::make_unique<detail::GuardedRawlogStream>(path);
}

RawlogReader::~RawlogReader() = default;

bool RawlogReader::next(RawlogEntry& entry)
{
    entry = RawlogEntry{};
    auto arch = mrpt::serialization::archiveFrom(*stream_);
    const uint64_t pos_before = stream_->getPosition();
    const std::string where = "rawlog '" + path_ + "' ";
    const std::string at_entry = " entry " + std::to_string(entries_);
    // Corrupt gzip data ends what can be read early: an entry it cuts (or the "end" it
    // makes) is reported as corruption, not as a truncated entry or a clean end.
    const auto gzipCorrupt = [&]()
    {
        if (stream_->dataError().find("unexpected end of file") != std::string::npos)
            return std::runtime_error(where + "is truncated in" + at_entry +
                                      " (the gzip data ends early)");
        return std::runtime_error(where + "is corrupt: gzip data error (" + stream_->dataError() +
                                  ") after " + std::to_string(stream_->readableBytes()) +
                                  " uncompressed bytes, in" + at_entry);
    };
    mrpt::serialization::CSerializable::Ptr obj;
    try
    {
        stream_->beginEntry();
        obj = arch.ReadObject();
    }
    catch (const mrpt::serialization::CExceptionEOF&)
    {
        if (!stream_->dataError().empty()) throw gzipCorrupt();
        // EOF before the first byte of an object is the normal end; EOF after some
        // bytes of it means the file was cut short.
        if (stream_->getPosition() == pos_before) return false;
        throw std::runtime_error(where + "is truncated in" + at_entry);
    }
    catch (const std::exception& e)
    {
        // A file whose gzip data is corrupt or cut is reported as such: what the entry
        // then declares or holds is garbage decompressed before zlib noticed.
        if (!stream_->dataError().empty()) throw gzipCorrupt();
        if (stream_->cutRead()) throw std::runtime_error(where + "is truncated in" + at_entry);
        if (!stream_->sizeError().empty())
            throw std::runtime_error(where + "is corrupt at" + at_entry + ": it " +
                                     stream_->sizeError());
        throw std::runtime_error(where + "is corrupt at" + at_entry + ": " + e.what());
    }
    if (!obj)
        throw std::runtime_error(where + "has a null object at" + at_entry);

    if (auto a = std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(obj))
        entry.actions = a;
    else if (auto f = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(obj))
        entry.frame = f;
    else if (auto o = std::dynamic_pointer_cast<mrpt::obs::CObservation>(obj))
        entry.observation = o;
    else
        throw std::runtime_error(where + "entry " + std::to_string(entries_) + " is a " +
                                 obj->GetRuntimeClass()->className +
                                 ", not an action, sensory frame or observation");
    ++entries_;
    return true;
}

}  // namespace hymm::io
