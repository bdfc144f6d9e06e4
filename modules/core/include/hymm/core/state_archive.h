/**
 * @file state_archive.h
 * @brief Helpers for the saved run state (hymm-slam --save-state / --resume): fixed-width
 *        integers, doubles, Eigen matrices and standard containers on an MRPT CArchive.
 *
 * Doubles are written as their IEEE bits (CArchive's own operator), so a state read back
 * holds the same values bit for bit: a resumed run computes exactly what the uninterrupted
 * one would have. Sizes are checked on reading (a corrupt size fails here, not in a huge
 * allocation), and every read of a truncated stream throws (CArchive's end-of-file error).
 */
#pragma once

#include <Eigen/Core>
#include <mrpt/serialization/CArchive.h>

#include <array>
#include <cstdint>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace hymm::core::state
{
/** Upper bound on any element count in a state (a corrupt count fails clearly). */
constexpr std::uint64_t kMaxCount = std::uint64_t{1} << 32;

inline void writeSize(mrpt::serialization::CArchive& out, std::uint64_t n) { out << n; }
inline std::uint64_t readSize(mrpt::serialization::CArchive& in, const char* what)
{
    std::uint64_t n = 0;
    in >> n;
    if (n > kMaxCount)
        throw std::runtime_error(std::string("corrupt state: ") + what + " count " + std::to_string(n));
    return n;
}

inline void writeLong(mrpt::serialization::CArchive& out, long v) { out << static_cast<std::int64_t>(v); }
inline long readLong(mrpt::serialization::CArchive& in)
{
    std::int64_t v = 0;
    in >> v;
    return static_cast<long>(v);
}
inline std::uint64_t readU64(mrpt::serialization::CArchive& in)
{
    std::uint64_t v = 0;
    in >> v;
    return v;
}
inline double readDouble(mrpt::serialization::CArchive& in)
{
    double v = 0;
    in >> v;
    return v;
}
inline bool readBool(mrpt::serialization::CArchive& in)
{
    bool v = false;
    in >> v;
    return v;
}

/** Any fixed or dynamic Eigen matrix of doubles: rows, cols, column-major values. */
template <class M>
void writeMatrix(mrpt::serialization::CArchive& out, const Eigen::MatrixBase<M>& m)
{
    writeSize(out, static_cast<std::uint64_t>(m.rows()));
    writeSize(out, static_cast<std::uint64_t>(m.cols()));
    for (Eigen::Index c = 0; c < m.cols(); ++c)
        for (Eigen::Index r = 0; r < m.rows(); ++r) out << static_cast<double>(m(r, c));
}
template <class M>
void readMatrix(mrpt::serialization::CArchive& in, M& m, const char* what)
{
    const auto rows = static_cast<Eigen::Index>(readSize(in, what));
    const auto cols = static_cast<Eigen::Index>(readSize(in, what));
    if (rows * cols > static_cast<Eigen::Index>(kMaxCount))
        throw std::runtime_error(std::string("corrupt state: ") + what + " is too large");
    if constexpr (M::RowsAtCompileTime != Eigen::Dynamic || M::ColsAtCompileTime != Eigen::Dynamic)
    {
        if ((M::RowsAtCompileTime != Eigen::Dynamic && rows != M::RowsAtCompileTime) ||
            (M::ColsAtCompileTime != Eigen::Dynamic && cols != M::ColsAtCompileTime))
            throw std::runtime_error(std::string("corrupt state: ") + what + " has size " +
                                     std::to_string(rows) + "x" + std::to_string(cols));
    }
    m.resize(rows, cols);
    for (Eigen::Index c = 0; c < cols; ++c)
        for (Eigen::Index r = 0; r < rows; ++r) in >> m(r, c);
}

template <class V>
void writeVertices(mrpt::serialization::CArchive& out, const std::array<V, 3>& v)
{
    for (const auto& p : v) out << p.x() << p.y();
}
template <class V>
void readVertices(mrpt::serialization::CArchive& in, std::array<V, 3>& v)
{
    for (auto& p : v) in >> p.x() >> p.y();
}

inline void writeIds(mrpt::serialization::CArchive& out, const std::vector<long>& ids)
{
    writeSize(out, ids.size());
    for (long id : ids) writeLong(out, id);
}
inline std::vector<long> readIds(mrpt::serialization::CArchive& in, const char* what)
{
    std::vector<long> ids(readSize(in, what));
    for (long& id : ids) id = readLong(in);
    return ids;
}

/** A list of numbers (doubles, floats, fixed-width integers) as CArchive writes them. */
template <class T>
void writeValues(mrpt::serialization::CArchive& out, const std::vector<T>& v)
{
    writeSize(out, v.size());
    for (const T& x : v) out << x;
}
template <class T>
void readValues(mrpt::serialization::CArchive& in, std::vector<T>& v, const char* what)
{
    v.resize(readSize(in, what));
    for (T& x : v) in >> x;
}

/** A struct's counters in a fixed order (the state's layout: a new counter goes at the
 *  end, with a new state version); reading checks the count. */
inline void writeCounters(mrpt::serialization::CArchive& out, const std::vector<size_t*>& counters)
{
    writeSize(out, counters.size());
    for (const size_t* v : counters) out << static_cast<std::uint64_t>(*v);
}
inline void readCounters(mrpt::serialization::CArchive& in, const std::vector<size_t*>& counters, const char* what)
{
    if (readSize(in, what) != counters.size())
        throw std::runtime_error(std::string("corrupt state: ") + what + " list");
    for (size_t* v : counters) *v = readU64(in);
}

/** Counts by name (failure reasons, class names). */
inline void writeCounts(mrpt::serialization::CArchive& out, const std::map<std::string, size_t>& counts)
{
    writeSize(out, counts.size());
    for (const auto& [name, n] : counts) out << name << static_cast<std::uint64_t>(n);
}
inline void readCounts(mrpt::serialization::CArchive& in, std::map<std::string, size_t>& counts, const char* what)
{
    counts.clear();
    const size_t n = readSize(in, what);
    for (size_t i = 0; i < n; ++i)
    {
        std::string name;
        in >> name;
        counts[name] = readU64(in);
    }
}

/** A section marker: a misplaced reader (a bug, or a corrupt file) stops at the next one
 *  with the section's name instead of reading garbage onwards. */
inline void writeTag(mrpt::serialization::CArchive& out, const std::string& tag) { out << tag; }
inline void expectTag(mrpt::serialization::CArchive& in, const std::string& tag)
{
    std::string got;
    in >> got;
    if (got != tag)
        throw std::runtime_error("corrupt state: expected section '" + tag + "', found '" +
                                 got.substr(0, 40) + "'");
}

}  // namespace hymm::core::state
