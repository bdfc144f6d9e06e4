#include "hymm/io/trajectory_io.h"
#include <hymm/core/output_files.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace hymm::io
{
std::string tableLocation(const std::string& path, size_t line)
{
    return path + ":" + std::to_string(line) + ": ";
}

void readNumberTable(const std::string& path, const std::string& what,
                     const std::function<void(const std::vector<double>&, size_t)>& row)
{
    std::ifstream f(path);
    if (!f) throw std::runtime_error("cannot open " + what + " '" + path + "'");
    std::string line, tok;
    std::vector<double> v;
    size_t lineno = 0;
    while (std::getline(f, line))
    {
        ++lineno;
        const auto first = line.find_first_not_of(" \t\r");
        if (first == std::string::npos || line[first] == '#' || line[first] == '%') continue;
        std::replace(line.begin(), line.end(), ',', ' ');
        std::istringstream is(line);
        v.clear();
        while (is >> tok)
        {
            char* end = nullptr;
            const double d = std::strtod(tok.c_str(), &end);
            if (end == tok.c_str() || *end != '\0' || !std::isfinite(d))
                throw std::runtime_error(tableLocation(path, lineno) + "'" + tok +
                                         "' is not a finite number");
            v.push_back(d);
        }
        row(v, lineno);
    }
}

void writeTum(const std::string& path, const std::vector<StampedPose2D>& poses)
{
    core::AtomicTextFile f(path);
    f << "# timestamp x y z qx qy qz qw\n";
    for (const auto& p : poses)
    {
        // Fixed microsecond time stamps: epoch times need 16 digits, which the
        // significant-digit format would round to 0.01 s.
        f << std::fixed << std::setprecision(6) << p.t << ' ' << std::defaultfloat
          << std::setprecision(12) << p.x << ' ' << p.y << " 0 0 0 " << std::sin(p.phi / 2)
          << ' ' << std::cos(p.phi / 2) << '\n';
    }
    f.commit();
}

std::vector<StampedPose2D> readTum(const std::string& path)
{
    std::vector<StampedPose2D> out;
    readNumberTable(path, "trajectory file", [&](const std::vector<double>& v, size_t line) {
        if (v.size() != 8)
            throw std::runtime_error(tableLocation(path, line) + "expected 8 TUM columns, got " +
                                     std::to_string(v.size()));
        // Heading about z from the quaternion (planar poses).
        const double phi = 2.0 * std::atan2(v[6], v[7]);
        out.push_back(StampedPose2D{v[0], v[1], v[2], std::atan2(std::sin(phi), std::cos(phi))});
    });
    return out;
}

void writeLandmarksCsv(
    const std::string& path, const std::vector<LandmarkRecord>& lms, const std::string& header)
{
    core::AtomicTextFile f(path);
    f << "# " << header << '\n' << std::setprecision(12);
    for (const auto& l : lms)
    {
        f << l.id << ',' << l.x << ',' << l.y;
        for (double e : l.extra) f << ',' << e;
        f << '\n';
    }
    f.commit();
}

std::vector<LandmarkRecord> readLandmarksCsv(const std::string& path)
{
    std::vector<LandmarkRecord> out;
    readNumberTable(path, "landmark file", [&](const std::vector<double>& v, size_t line) {
        if (v.size() < 3)
            throw std::runtime_error(tableLocation(path, line) +
                                     "expected at least 3 columns (id,x,y)");
        LandmarkRecord r;
        r.id = static_cast<long>(v[0]);
        r.x = v[1];
        r.y = v[2];
        r.extra.assign(v.begin() + 3, v.end());
        out.push_back(std::move(r));
    });
    return out;
}

}  // namespace hymm::io
