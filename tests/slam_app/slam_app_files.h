/**
 * @file slam_app_files.h
 * @brief What the slam_app tests read back from hymm-slam's output folder and the
 *        chapter-3 sample's truth: a scratch folder, the true surfaces, MRPT objects,
 *        metrics.json numbers, whole files and text lines.
 */
#pragma once

#include "ch3_sample.h"

#include <gtest/gtest.h>
#include <hymm/dense/outline_metrics.h>
#include <hymm/io/trajectory_io.h>
#include <hymm/sim/ground_truth_io.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace hymm::test
{
/** A folder of its own per test process (not created), removed with the object. */
struct TempDir
{
    std::filesystem::path path;
    explicit TempDir(const std::string& prefix)
    {
        path = std::filesystem::temp_directory_path() / (prefix + std::to_string(::getpid()));
        std::filesystem::remove_all(path);
    }
    ~TempDir() { std::filesystem::remove_all(path); }
    std::string operator/(const std::string& name) const { return (path / name).string(); }
};

/** The whole file as bytes (empty if it cannot be read). */
inline std::string readFile(const std::filesystem::path& p)
{
    std::ifstream f(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

/** The sample's true object outlines. */
inline std::vector<hymm::dense::Polygon> trueOutlines()
{
    std::vector<hymm::dense::Polygon> out;
    for (const auto& r : hymm::sim::readObjectOutlines(kCh3Gt + "objects.txt"))
        out.emplace_back(r.outline.begin(), r.outline.end());
    return out;
}

/** Every surface the laser sees: the object outlines and the landmark trunks (radius in
 *  the first extra column of the landmark file), as metrics.json measures against. */
inline std::vector<hymm::dense::Polygon> trueSurfaces()
{
    auto out = trueOutlines();
    for (const auto& l : hymm::io::readLandmarksCsv(kCh3Gt + "landmarks.csv"))
        out.push_back(hymm::dense::circlePolygon(Eigen::Vector2d(l.x, l.y), l.extra.empty() ? 0.0 : l.extra[0]));
    return out;
}

/** An MRPT object from a file the app wrote (gzip or plain). */
template <class T>
void readSerialized(const std::string& file, T& obj)
{
    mrpt::io::CFileGZInputStream f;
    ASSERT_TRUE(f.open(file)) << file;
    mrpt::serialization::archiveFrom(f) >> obj;
}

/** Number under "dense" -> `object` -> `key` in metrics.json text (flat layer objects);
 *  NaN when absent or null. */
inline double denseMetric(const std::string& json, const std::string& object, const std::string& key)
{
    const size_t dense = json.find("\"dense\"");
    const size_t obj = json.find("\"" + object + "\": {", dense);
    const size_t end = json.find('}', obj);
    const size_t k = json.find("\"" + key + "\":", json.find('{', obj));
    if (dense == std::string::npos || obj == std::string::npos || k == std::string::npos || k > end)
        return std::nan("");
    const std::string value = json.substr(json.find(':', k) + 1, 40);
    char* parsed_end = nullptr;
    const double v = std::strtod(value.c_str(), &parsed_end);
    return parsed_end == value.c_str() ? std::nan("") : v;  // null: no value
}

inline std::vector<std::string> readLines(const std::string& file)
{
    std::ifstream f(file);
    std::vector<std::string> lines;
    for (std::string l; std::getline(f, l);) lines.push_back(l);
    return lines;
}
}  // namespace hymm::test
