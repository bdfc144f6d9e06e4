#include "hymm/sim/ground_truth_io.h"
#include <hymm/core/output_files.h>

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "config_text.h"

namespace hymm::sim
{
namespace
{
void writeRecord(std::ostream& f, const ObjectOutlineRecord& r)
{
    f << r.id << ' ' << detail::formatNumber(r.t_from) << ' ' << detail::formatNumber(r.t_to);
    for (const auto& p : r.outline)
        f << ' ' << detail::formatNumber(p.x()) << ' ' << detail::formatNumber(p.y());
    f << '\n';
}
}  // namespace

void writeObjectOutlines(const std::string& path, const World& world,
                         const std::vector<double>& frame_t,
                         const std::vector<double>& frame_stamps)
{
    if (frame_t.size() != frame_stamps.size())
        throw std::invalid_argument("writeObjectOutlines: frame times and stamps differ in size");
    core::AtomicTextFile f(path);
    f << "# HYMM simulator: true object outlines\n"
         "# id t_from t_to x1 y1 ... xn yn  (closed polygon, global frame [m], counter-clockwise;\n"
         "# the outline holds for the frames stamped t_from..t_to [s], inclusive)\n";
    for (const auto& obj : world.objects())
        f << "# object " << obj.id << ' ' << obj.name << ' ' << obj.kind << '\n';
    for (const auto& obj : world.objects())
    {
        // Runs of consecutive frames with the object present and unchanged.
        bool open = false;
        ObjectOutlineRecord rec;
        for (size_t i = 0; i < frame_t.size(); ++i)
        {
            if (!obj.presentAt(frame_t[i]))
            {
                if (open) writeRecord(f, rec);
                open = false;
                continue;
            }
            Polygon outline = obj.outlineAt(frame_t[i]);
            if (open && outline == rec.outline)
            {
                rec.t_to = frame_stamps[i];
                continue;
            }
            if (open) writeRecord(f, rec);
            rec = ObjectOutlineRecord{obj.id, frame_stamps[i], frame_stamps[i], std::move(outline)};
            open = true;
        }
        if (open) writeRecord(f, rec);
    }
    f.commit();
}

std::vector<ObjectOutlineRecord> readObjectOutlines(const std::string& path)
{
    std::ifstream f(path);
    if (!f) throw std::runtime_error("cannot open object file '" + path + "'");
    std::vector<ObjectOutlineRecord> out;
    std::string line;
    for (size_t lineno = 1; std::getline(f, line); ++lineno)
    {
        const auto first = line.find_first_not_of(" \t\r");
        if (first == std::string::npos || line[first] == '#') continue;
        std::istringstream is(line);
        ObjectOutlineRecord r;
        std::vector<double> xy;
        double v = 0;
        if (!(is >> r.id >> r.t_from >> r.t_to))
            throw std::runtime_error(path + ":" + std::to_string(lineno) +
                                     ": expected 'id t_from t_to x1 y1 ...'");
        while (is >> v) xy.push_back(v);
        if (!is.eof() || xy.size() < 6 || xy.size() % 2 != 0)
            throw std::runtime_error(path + ":" + std::to_string(lineno) +
                                     ": expected at least 3 vertices as x y pairs of numbers");
        for (size_t i = 0; i < xy.size(); i += 2) r.outline.emplace_back(xy[i], xy[i + 1]);
        out.push_back(std::move(r));
    }
    return out;
}

void writeSurfaceProperties(const std::string& path, const World& world)
{
    core::AtomicTextFile f(path);
    const SurfaceProperties& p = world.properties();
    f << "# HYMM simulator: true surface properties (laser intensity before noise and rounding)\n"
         "# field v0 gx gy: value(x, y) = v0 + gx x + gy y on every surface without its own\n"
         "# landmarks v: every landmark trunk;  object id v: an object with its own value\n";
    f << "field " << detail::formatNumber(p.field.v0) << ' ' << detail::formatNumber(p.field.gx)
      << ' ' << detail::formatNumber(p.field.gy) << '\n';
    if (p.landmarks) f << "landmarks " << detail::formatNumber(*p.landmarks) << '\n';
    for (const auto& [id, v] : p.objects)
        f << "object " << id << ' ' << detail::formatNumber(v) << '\n';
    f.commit();
}

SurfaceProperties readSurfaceProperties(const std::string& path)
{
    std::ifstream f(path);
    if (!f) throw std::runtime_error("cannot open surface property file '" + path + "'");
    SurfaceProperties p;
    std::string line;
    for (size_t lineno = 1; std::getline(f, line); ++lineno)
    {
        const auto first = line.find_first_not_of(" \t\r");
        if (first == std::string::npos || line[first] == '#') continue;
        const auto fail = [&](const std::string& what)
        { throw std::runtime_error(path + ":" + std::to_string(lineno) + ": " + what); };
        std::istringstream is(line);
        std::string what;
        is >> what;
        std::vector<double> v;
        long id = 0;
        if (what == "object" && !(is >> id)) fail("expected 'object id value'");
        double x = 0;
        while (is >> x) v.push_back(x);
        if (!is.eof()) fail("not a number in '" + line + "'");
        if (what == "field" && v.size() == 3)
            p.field = PropertyField{v[0], v[1], v[2]};
        else if (what == "landmarks" && v.size() == 1)
            p.landmarks = v[0];
        else if (what == "object" && v.size() == 1)
        {
            if (!p.objects.emplace(id, v[0]).second)
                fail("object " + std::to_string(id) + " listed twice");
        }
        else
            fail("expected 'field v0 gx gy', 'landmarks v' or 'object id v'");
    }
    return p;
}

}  // namespace hymm::sim
