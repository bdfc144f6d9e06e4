/**
 * @file text_io.h
 * @brief Private helpers of the layers' text serialisation: numbers are written as hex
 *        floats (exact round trip) and read back with std::stod, which, unlike
 *        operator>> in libstdc++, parses hex floats.
 */
#pragma once

#include <istream>
#include <stdexcept>
#include <string>

namespace hymm::dense::text_io
{
/** Next whitespace-separated token as a double; throws std::runtime_error naming `who`. */
inline double readNumber(std::istream& in, const char* who)
{
    std::string tok;
    if (!(in >> tok)) throw std::runtime_error(std::string(who) + ": unexpected end of stream");
    try
    {
        size_t used = 0;
        const double v = std::stod(tok, &used);
        if (used != tok.size()) throw std::invalid_argument(tok);
        return v;
    }
    catch (const std::exception&)
    {
        throw std::runtime_error(std::string(who) + ": bad number '" + tok + "'");
    }
}

/** Reads "<tag> <count>"; throws std::runtime_error unless the tag matches. */
inline size_t readHeader(std::istream& in, const std::string& tag, const char* who)
{
    std::string t;
    size_t n = 0;
    if (!(in >> t >> n) || t != tag)
        throw std::runtime_error(std::string(who) + ": expected '" + tag + " <count>', got '" + t + "'");
    return n;
}

}  // namespace hymm::dense::text_io
