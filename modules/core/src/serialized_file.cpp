#include "hymm/core/serialized_file.h"

#include "hymm/core/output_files.h"

#include <mrpt/io/CMemoryStream.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/serialization/CSerializable.h>

#include <string_view>

namespace hymm::core
{
void writeSerializedGz(const mrpt::serialization::CSerializable& obj, const std::string& file)
{
    mrpt::io::CMemoryStream mem;
    mrpt::serialization::archiveFrom(mem) << obj;
    writeGzFileAtomically(file, std::string_view(static_cast<const char*>(mem.getRawBufferData()),
                                                 static_cast<size_t>(mem.getTotalBytesCount())));
}

}  // namespace hymm::core
