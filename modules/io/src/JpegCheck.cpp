// Decodes a JPEG held in memory with libjpeg, as MRPT's CImage::loadFromStreamAsJPEG does,
// but with an error handler that returns instead of ending the process: MRPT installs
// libjpeg's standard handler, whose error_exit calls exit(), so a corrupt JPEG in a rawlog
// ended any program reading it (found by rawlog_fuzz).
#include <cstddef>
#include <csetjmp>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

// jpeglib.h needs FILE and size_t declared first.
#include <jpeglib.h>

#include "GuardedRawlogStream.h"

namespace hymm::io::detail
{
namespace
{
struct ErrorManager
{
    jpeg_error_mgr base;  // first: libjpeg sees a jpeg_error_mgr*
    std::jmp_buf jump;
    char message[JMSG_LENGTH_MAX];
};

[[noreturn]] void onError(j_common_ptr cinfo)
{
    auto* err = reinterpret_cast<ErrorManager*>(cinfo->err);
    (*cinfo->err->format_message)(cinfo, err->message);
    std::longjmp(err->jump, 1);
}

void onMessage(j_common_ptr, int) {}  // warnings (corrupt entropy data) are not errors

// No C++ object with a destructor lives across the setjmp: a longjmp skips destructors.
bool decode(jpeg_decompress_struct& cinfo, ErrorManager& err, const uint8_t* data, size_t n, uint64_t max_bytes)
{
    if (setjmp(err.jump)) return false;
    jpeg_create_decompress(&cinfo);
    jpeg_mem_src(&cinfo, data, static_cast<unsigned long>(n));
    jpeg_read_header(&cinfo, TRUE);
    // MRPT sizes the image from the header, and a progressive JPEG makes libjpeg hold
    // the whole image's coefficients (2 bytes a sample): refused before either, so this
    // decode holds at most about twice the cap, as MRPT's own does.
    const uint64_t bytes = uint64_t{cinfo.image_width} * cinfo.image_height * static_cast<uint64_t>(cinfo.num_components);
    if (bytes > max_bytes)
    {
        std::snprintf(err.message, sizeof(err.message), "it decodes to %llu bytes, more than %llu",
                      static_cast<unsigned long long>(bytes), static_cast<unsigned long long>(max_bytes));
        return false;
    }
    jpeg_start_decompress(&cinfo);
    // MRPT copies 3 bytes a pixel out of libjpeg's row whenever it is not grey: a
    // 2-component JPEG (which libjpeg decodes) would be read past its row buffer.
    if (cinfo.output_components == 2)
    {
        std::snprintf(err.message, sizeof(err.message), "2 colour components, which MRPT reads as 3");
        return false;
    }
    const auto stride = static_cast<JDIMENSION>(cinfo.output_width * cinfo.output_components);
    JSAMPARRAY row = (*cinfo.mem->alloc_sarray)(reinterpret_cast<j_common_ptr>(&cinfo), JPOOL_IMAGE, stride, 1);
    while (cinfo.output_scanline < cinfo.output_height) jpeg_read_scanlines(&cinfo, row, 1);
    jpeg_finish_decompress(&cinfo);
    return true;
}
}  // namespace

std::string jpegDecodeError(const uint8_t* data, size_t n, uint64_t max_bytes)
{
    jpeg_decompress_struct cinfo{};
    ErrorManager err{};
    cinfo.err = jpeg_std_error(&err.base);
    err.base.error_exit = onError;
    err.base.emit_message = onMessage;
    const bool ok = decode(cinfo, err, data, n, max_bytes);
    jpeg_destroy_decompress(&cinfo);
    return ok ? std::string() : std::string(err.message);
}

void GuardedRawlogStream::checkJpegDecodes(uint64_t at, uint32_t n)
{
    // MRPT decodes the JPEG with libjpeg's standard error handler, which ends the process
    // on a corrupt one (exit(1), no exception): decoded here first with one that returns.
    // The frame-header cap (armJpeg) comes first, so that this decode stays bounded; a
    // JPEG beyond kMaxJpegBytes is refused; the decode also refuses a frame header the
    // walk did not reach that declares more than kMaxDecodedImageBytes.
    if (n == 0 || at + 4 + uint64_t{n} > total_) return;  // the count check refuses the latter
    if (n > kMaxJpegBytes)
    {
        size_error_ = "holds a JPEG image of " + std::to_string(n) + " bytes at byte " + std::to_string(at) +
                      ", more than the " + std::to_string(kMaxJpegBytes) + " a rawlog image may hold";
        throw RawlogSizeError(size_error_);
    }
    // Decoded in place in the look-ahead buffer, which MRPT's read then consumes.
    const uint8_t* jpeg = lookAhead(at + 4, n, kJpegWindow);
    if (!jpeg) return;
    const std::string why = jpegDecodeError(jpeg, n, kMaxDecodedImageBytes);
    if (why.empty()) return;
    size_error_ = "holds a JPEG image at byte " + std::to_string(at) + " that libjpeg cannot decode (" + why +
                  "; MRPT's decoder would end the program)";
    throw RawlogSizeError(size_error_);
}

}  // namespace hymm::io::detail
