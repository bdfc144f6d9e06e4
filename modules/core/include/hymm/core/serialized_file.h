/**
 * @file serialized_file.h
 * @brief An MRPT object written as MRPT's map tools read it, with the checks of
 *        output_files.h (temporary name, every write checked, renamed when complete).
 */
#pragma once

#include <string>

namespace mrpt::serialization
{
class CSerializable;
}

namespace hymm::core
{
/** `obj` MRPT-serialised into a gzip file (level 1, as CFileGZOutputStream writes it), as
 *  RawLogViewer, SceneViewer3D and observations2map read it. Serialised in memory first so
 *  that every write is checked; throws std::runtime_error naming `file` on failure. */
void writeSerializedGz(const mrpt::serialization::CSerializable& obj, const std::string& file);

}  // namespace hymm::core
