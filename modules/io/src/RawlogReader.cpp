#include "hymm/io/RawlogReader.h"

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/filesystem.h>

#include <stdexcept>

namespace hymm::io
{
RawlogReader::RawlogReader(const std::string& path) : path_(path)
{
    if (!mrpt::system::fileExists(path))
        throw std::runtime_error("rawlog not found: '" + path + "'");
    stream_ = std::make_unique<mrpt::io::CFileGZInputStream>();
    if (!stream_->open(path)) throw std::runtime_error("cannot open rawlog '" + path + "'");
}

RawlogReader::~RawlogReader() = default;

bool RawlogReader::next(RawlogEntry& entry)
{
    entry = RawlogEntry{};
    auto arch = mrpt::serialization::archiveFrom(*stream_);
    const uint64_t pos_before = stream_->getPosition();
    mrpt::serialization::CSerializable::Ptr obj;
    try
    {
        obj = arch.ReadObject();
    }
    catch (const mrpt::serialization::CExceptionEOF&)
    {
        // EOF before the first byte of an object is the normal end; EOF after some
        // bytes of it means the file was cut short.
        if (stream_->getPosition() == pos_before) return false;
        throw std::runtime_error("rawlog '" + path_ + "' is truncated in entry " +
                                 std::to_string(entries_));
    }
    catch (const std::exception& e)
    {
        throw std::runtime_error("rawlog '" + path_ + "' is corrupt at entry " +
                                 std::to_string(entries_) + ": " + e.what());
    }
    if (!obj)
        throw std::runtime_error("rawlog '" + path_ + "' has a null object at entry " +
                                 std::to_string(entries_));

    if (auto a = std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(obj))
        entry.actions = a;
    else if (auto f = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(obj))
        entry.frame = f;
    else if (auto o = std::dynamic_pointer_cast<mrpt::obs::CObservation>(obj))
        entry.observation = o;
    else
        throw std::runtime_error("rawlog '" + path_ + "': entry " + std::to_string(entries_) +
                                 " is a " + obj->GetRuntimeClass()->className +
                                 ", not an action, sensory frame or observation");
    ++entries_;
    return true;
}

}  // namespace hymm::io
