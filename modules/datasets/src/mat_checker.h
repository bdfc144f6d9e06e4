// Structural check of a MAT file before libmatio reads it (private to hymm::datasets).
#pragma once

#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace hymm::datasets::detail
{
/**
 * Structural check of a MAT file before libmatio sees it. matio sizes its buffers from
 * what the file declares (a dimensions element of 926 million entries, a cell of 2^40
 * elements, a variable name of 4 GB) and allocates them before it notices that the file
 * is far shorter, so a mutated file makes it allocate gigabytes. This walk follows the
 * layout of the MATLAB 5 format (and of v4 files) and refuses any element whose declared
 * size does not fit in the bytes that hold it: what matio then allocates for a variable
 * is at most 8x the bytes of its stored data (a double per stored byte at worst).
 * Compressed (zlib) variables are inflated here, within 16 MiB + 64x the file's size in
 * all, and checked in turn.
 */
class MatChecker
{
   public:
    MatChecker(const std::string& path, uint64_t file_size)
        : path_(path), inflate_budget_(16ull * 1024 * 1024 + 64 * file_size)
    {
    }

    void check(const std::vector<uint8_t>& f)
    {
        if (f.size() >= 128 && (std::memcmp(&f[126], "IM", 2) == 0 || std::memcmp(&f[126], "MI", 2) == 0))
        {
            swap_ = std::memcmp(&f[126], "MI", 2) == 0;
            const uint16_t version = swap_ ? static_cast<uint16_t>(f[124] << 8 | f[125])
                                           : static_cast<uint16_t>(f[125] << 8 | f[124]);
            if (version == 0x0200)
                fail(124, "MAT 7.3 (HDF5) files are not supported; save with -v7 or -v6");
            if (version != 0x0100) fail(124, "unknown MAT 5 version " + std::to_string(version));
            checkElements(f.data() + 128, f.data() + f.size(), 128, 0);
        }
        else
            checkV4(f);
    }

   private:
    struct Tag
    {
        uint32_t type = 0;
        uint64_t nbytes = 0;
        const uint8_t* data = nullptr;
        uint64_t total = 0;  // header, data and padding
    };

    [[noreturn]] void fail(uint64_t at, const std::string& what) const
    {
        throw std::runtime_error("MAT file '" + path_ + "' is corrupt at byte " +
                                 std::to_string(at) + ": " + what);
    }

    uint32_t u32(const uint8_t* p) const
    {
        uint32_t v = 0;
        std::memcpy(&v, p, 4);
        return swap_ ? __builtin_bswap32(v) : v;
    }

    Tag tag(const uint8_t* p, const uint8_t* end, uint64_t at) const
    {
        if (end - p < 8) fail(at, "a data element's header is cut short");
        Tag t;
        const uint32_t w0 = u32(p);
        if (w0 >> 16)
        {  // small data element: type and size in one word, data in the next four bytes
            t.type = w0 & 0xFFFF;
            t.nbytes = w0 >> 16;
            if (t.nbytes > 4) fail(at, "a small data element declares " + std::to_string(t.nbytes) + " bytes");
            t.data = p + 4;
            t.total = 8;
            return t;
        }
        t.type = w0;
        t.nbytes = u32(p + 4);
        t.data = p + 8;
        const auto left = static_cast<uint64_t>(end - t.data);
        if (t.nbytes > left)
            fail(at, "a data element declares " + std::to_string(t.nbytes) + " bytes but only " +
                         std::to_string(left) + " follow");
        // Compressed elements are not padded; others are padded to 8 bytes (the last one
        // of a file may lack its padding).
        const uint64_t padded = t.type == 15 ? t.nbytes : (t.nbytes + 7) / 8 * 8;
        t.total = 8 + std::min(padded, left);
        return t;
    }

    static uint64_t typeBytes(uint32_t type)
    {
        switch (type)
        {
            case 1: case 2: case 16: return 1;      // int8, uint8, utf8
            case 3: case 4: case 17: return 2;      // int16, uint16, utf16
            case 5: case 6: case 7: case 18: return 4;  // int32, uint32, single, utf32
            case 9: case 12: case 13: return 8;     // double, int64, uint64
            default: return 0;
        }
    }

    void checkElements(const uint8_t* p, const uint8_t* end, uint64_t at, int depth)
    {
        while (p < end)
        {
            const Tag t = tag(p, end, at);
            if (t.type == 15)
            {
                if (depth > 0) fail(at, "compressed data inside compressed data");
                const auto inflated = inflate(t, at);
                checkElements(inflated.data(), inflated.data() + inflated.size(), at, depth + 1);
            }
            else if (t.type == 14)
                checkMatrix(t.data, t.data + t.nbytes, at, 0);
            else
                fail(at, "an element of type " + std::to_string(t.type) + " is not a variable");
            p += t.total;
            if (depth == 0) at += t.total;
        }
    }

    std::vector<uint8_t> inflate(const Tag& t, uint64_t at)
    {
        z_stream z{};
        if (inflateInit(&z) != Z_OK) fail(at, "zlib cannot start");
        std::vector<uint8_t> out;
        std::vector<uint8_t> chunk(1 << 16);
        z.next_in = const_cast<Bytef*>(t.data);
        z.avail_in = static_cast<uInt>(t.nbytes);
        int rc = Z_OK;
        while (rc != Z_STREAM_END)
        {
            z.next_out = chunk.data();
            z.avail_out = static_cast<uInt>(chunk.size());
            rc = ::inflate(&z, Z_NO_FLUSH);
            const size_t got = chunk.size() - z.avail_out;
            if (got > inflate_budget_ - std::min<uint64_t>(inflate_budget_, used_))
            {
                inflateEnd(&z);
                fail(at, "compressed data inflates beyond " + std::to_string(inflate_budget_) +
                             " bytes (64x the file)");
            }
            used_ += got;
            out.insert(out.end(), chunk.begin(), chunk.begin() + static_cast<std::ptrdiff_t>(got));
            if (rc == Z_STREAM_END) break;
            if (rc != Z_OK || (got == 0 && z.avail_in == 0))
            {
                inflateEnd(&z);
                fail(at, "corrupt compressed data");
            }
        }
        inflateEnd(&z);
        return out;
    }

    /** What the header of a matrix element declares (array flags, dimensions, name). */
    struct ArrayHeader
    {
        uint32_t cls = 0;  // MATLAB class
        bool complex = false;
        uint32_t nzmax = 0;     // sparse: non-zeros
        uint64_t elements = 0;  // product of the dimensions
    };

    /** Reads the array flags, dimensions and name of the matrix element at p (moved past
     *  them); refuses more than 2^40 elements. */
    ArrayHeader arrayHeader(const uint8_t*& p, const uint8_t* end, uint64_t at) const
    {
        ArrayHeader h;
        const Tag flags = tag(p, end, at);
        if (flags.type != 6 || flags.nbytes != 8) fail(at, "a variable without array flags");
        h.cls = u32(flags.data) & 0xFF;
        h.complex = u32(flags.data) & 0x800;
        h.nzmax = u32(flags.data + 4);
        p += flags.total;
        const Tag dims = tag(p, end, at);
        if (dims.type != 5 || dims.nbytes % 4 != 0 || dims.nbytes < 8)
            fail(at, "a variable without valid dimensions");
        uint64_t elements = 1;
        for (uint64_t i = 0; i < dims.nbytes / 4; ++i)
        {
            const auto d = static_cast<int32_t>(u32(dims.data + 4 * i));
            if (d < 0) fail(at, "a negative dimension");
            elements = d == 0 || elements == 0 ? 0 : elements * static_cast<uint64_t>(d);
            if (elements > (1ull << 40)) fail(at, "a variable declares more than 2^40 elements");
        }
        h.elements = elements;
        p += dims.total;
        if (h.cls == 3)
        {  // object: its class name comes before the fields
            const Tag cname = tag(p, end, at);
            p += cname.total;
        }
        const Tag name = tag(p, end, at);
        if (name.type != 1) fail(at, "a variable without a name element");
        p += name.total;
        return h;
    }

    /** `count` matrix elements from p on (the cells of a cell array, the fields of a
     *  struct), each checked in turn. */
    void checkChildren(const uint8_t*& p, const uint8_t* end, uint64_t at, int depth, uint64_t count,
                       const char* what) const
    {
        for (uint64_t i = 0; i < count; ++i)
        {
            const Tag c = tag(p, end, at);
            if (c.type != 14) fail(at, std::string("a ") + what + " is not a matrix");
            checkMatrix(c.data, c.data + c.nbytes, at, depth + 1);
            p += c.total;
        }
    }

    /** Struct / object: field name length, names, then elements x fields matrices. */
    void checkStruct(const uint8_t* p, const uint8_t* end, uint64_t at, int depth, uint64_t elements) const
    {
        const Tag len = tag(p, end, at);
        if (len.type != 5 || len.nbytes != 4) fail(at, "a struct without field name length");
        const uint32_t l = u32(len.data);
        p += len.total;
        const Tag names = tag(p, end, at);
        if (names.type != 1 || (l == 0 && names.nbytes != 0) || (l != 0 && names.nbytes % l != 0))
            fail(at, "a struct with malformed field names");
        const uint64_t fields = l == 0 ? 0 : names.nbytes / l;
        p += names.total;
        const auto rest = static_cast<uint64_t>(end - p);
        if (elements * fields * 8 > rest) fail(at, "a struct declares " + std::to_string(elements * fields) + " fields but only " + std::to_string(rest) + " bytes follow");
        checkChildren(p, end, at, depth, elements * fields, "struct field");
    }

    void checkMatrix(const uint8_t* p, const uint8_t* end, uint64_t at, int depth) const
    {
        if (depth > 16) fail(at, "cells or structs nested more than 16 deep");
        if (p == end) return;  // an empty element (cells and structs hold them)
        const ArrayHeader h = arrayHeader(p, end, at);
        const uint64_t elements = h.elements;
        const auto left = static_cast<uint64_t>(end - p);
        const auto data = [&](const char* part)
        {
            const Tag d = tag(p, end, at);
            const uint64_t size = typeBytes(d.type);
            if (size == 0) fail(at, std::string("the ") + part + " data have an unknown type");
            if (elements * size > d.nbytes)
                fail(at, "a variable declares " + std::to_string(elements) + " elements but its " +
                             part + " data hold " + std::to_string(d.nbytes) + " bytes");
            p += d.total;
        };
        if ((h.cls >= 6 && h.cls <= 15) || h.cls == 4)
        {  // numeric, logical (uint8 with a flag) and char
            data("real");
            if (h.complex) data("imaginary");
        }
        else if (h.cls == 1)
        {  // cell: one matrix element per cell, at least 8 bytes each
            if (elements * 8 > left) fail(at, "a cell declares " + std::to_string(elements) + " cells but only " + std::to_string(left) + " bytes follow");
            checkChildren(p, end, at, depth, elements, "cell element");
        }
        else if (h.cls == 2 || h.cls == 3)
            checkStruct(p, end, at, depth, elements);
        else if (h.cls == 5)
        {  // sparse: row indices, column starts, values; nzmax must fit the row indices
            const Tag ir = tag(p, end, at);
            if (h.nzmax > left)
                fail(at, "a sparse matrix declares " + std::to_string(h.nzmax) +
                             " non-zeros but only " + std::to_string(left) + " bytes follow");
            p += ir.total;
            const Tag jc = tag(p, end, at);
            p += jc.total;
            if (p < end) p += tag(p, end, at).total;
            if (h.complex && p < end) p += tag(p, end, at).total;
        }
        else
            fail(at, "variables of class " + std::to_string(h.cls) + " are not supported");
    }

    void checkV4(const std::vector<uint8_t>& f)
    {
        // MATLAB 4: per variable five int32 (type, rows, columns, imaginary flag, name
        // length), the name, then the data. Only little-endian full or text matrices.
        uint64_t at = 0;
        if (f.empty()) fail(0, "empty file");
        while (at < f.size())
        {
            if (f.size() - at < 20) fail(at, "not a MAT file (no MAT 5 header, no MAT 4 variable)");
            int32_t h[5];
            std::memcpy(h, &f[at], 20);
            const int32_t type = h[0];
            const int m = type / 1000, o = type / 100 % 10, prec = type / 10 % 10, t = type % 10;
            static const int kSize[] = {8, 4, 4, 2, 2, 1};
            if (type < 0 || m != 0 || o != 0 || prec > 5 || t > 1 || h[1] < 0 || h[2] < 0 ||
                h[3] < 0 || h[3] > 1 || h[4] < 1)
                fail(at, "not a MAT file (no MAT 5 header, no MAT 4 variable)");
            const uint64_t bytes = uint64_t(uint32_t(h[1])) * uint32_t(h[2]) * kSize[prec] * (h[3] ? 2 : 1);
            const uint64_t need = 20 + uint64_t(uint32_t(h[4])) + bytes;
            if (need > f.size() - at)
                fail(at, "a MAT 4 variable declares " + std::to_string(need) + " bytes but only " + std::to_string(f.size() - at) + " follow");
            at += need;
        }
    }

    const std::string& path_;
    bool swap_ = false;
    uint64_t inflate_budget_;
    uint64_t used_ = 0;
};
}  // namespace hymm::datasets::detail
