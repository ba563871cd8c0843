// `grainlab import`: a text packing as a sample file (import.hpp).
#include "import.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "h5io.hpp"
#include "packing.hpp"
#include "simulation.hpp"

namespace grainlab {
namespace fs = std::filesystem;

namespace {
std::string num(Real v, int digits = 4) {
  std::ostringstream os;
  os.precision(digits);
  os << v;
  return os.str();
}
std::string mm(Real v) { return num(v * 1e3) + " mm"; }
// A line as an error quotes it: its first 80 characters, without the line end.
std::string quoted(std::string s) {
  while (!s.empty() && (s.back() == '\r' || s.back() == '\n')) s.pop_back();
  return "'" + (s.size() > 80 ? s.substr(0, 77) + "..." : s) + "'";
}

struct Read {
  std::vector<Vec3d> x;
  std::vector<Real> r;
  std::vector<long> line;  // each sphere's line in the file (1-based), for messages
};

// One sphere a line: four numbers (blanks or commas between them); blank lines and lines starting with # skipped.
Read read_packing(const std::string& path, Real scale) {
  std::ifstream f(path);
  if (!f) throw std::runtime_error(path + ": cannot read it (" + std::strerror(errno) + ")");
  Read in;
  std::string text;
  long ln = 0;
  const char* names[4] = {"x", "y", "z", "r"};
  while (std::getline(f, text)) {
    ++ln;
    const size_t b = text.find_first_not_of(" \t\r");
    if (b == std::string::npos || text[b] == '#') continue;
    std::string s = text;
    std::replace(s.begin(), s.end(), ',', ' ');
    Real v[4];
    int k = 0;
    const char* p = s.c_str();
    for (;;) {
      while (*p == ' ' || *p == '\t' || *p == '\r') ++p;
      if (!*p) break;
      char* end = nullptr;
      const double d = std::strtod(p, &end);
      if (end == p || (*end && *end != ' ' && *end != '\t' && *end != '\r'))
        throw std::runtime_error(path + ":" + std::to_string(ln) + ": " + quoted(text) + " is not four numbers x y z r "
                                 "(metres, blanks or commas between; a header line starts with #)");
      if (k < 4) v[k] = d;
      ++k;
      p = end;
    }
    if (k != 4)
      throw std::runtime_error(path + ":" + std::to_string(ln) + ": " + std::to_string(k) + " numbers in " + quoted(text) +
                               ", four expected: x y z r (one sphere a line; cut other columns, or start the line with #)");
    for (int c = 0; c < 4; ++c)
      if (!std::isfinite(v[c]))
        throw std::runtime_error(path + ":" + std::to_string(ln) + ": " + names[c] + " = " + num(v[c]) +
                                 " is not a finite number");
    if (!(v[3] > 0))
      throw std::runtime_error(path + ":" + std::to_string(ln) + ": r = " + num(v[3]) + " must be > 0");
    if (in.r.size() >= 100000000)
      throw std::runtime_error(path + ": more than 100000000 spheres (sample.count's range is [1, 1e8])");
    in.x.push_back({v[0] * scale, v[1] * scale, v[2] * scale});
    in.r.push_back(v[3] * scale);
    in.line.push_back(ln);
    // sample.r_max's range: a radius past 1 m is a file in other units far more often than a sample of boulders
    if (in.r.back() > 1)
      throw std::runtime_error(path + ":" + std::to_string(ln) + ": r = " + num(in.r.back()) + " m" +
                               (scale != 1 ? " (after --scale " + num(scale) + ")" : std::string()) +
                               " is above 1 m (sample.r_max's range is (0, 1]): a file in mm takes --scale 1e-3");
  }
  if (f.bad()) throw std::runtime_error(path + ": read error");
  if (in.r.empty()) throw std::runtime_error(path + ": no spheres in it (one a line: x y z r, in metres)");
  return in;
}
}  // namespace

PackingContacts packing_contacts(const std::vector<Vec3d>& x, const std::vector<Real>& r, const Vec3d& lo,
                                 const Vec3d& hi) {
  PackingContacts pc;
  const size_t n = r.size();
  if (n == 0) return pc;
  const Real rmax = *std::max_element(r.begin(), r.end());
  // Two spheres overlap only where their centres are closer than r_i + r_j <= 2 r_max: cells at least that wide, so a
  // sphere's partners lie in its own cell and the 26 around it; at most ~8 N cells (a few spheres in a large box).
  const Real cap = std::cbrt(8.0 * double(n)) + 1;
  int nc[3];
  Real edge[3];
  for (int a = 0; a < 3; ++a) {
    const Real L = hi[a] - lo[a];
    nc[a] = int(std::max<Real>(1, std::min<Real>(cap, std::floor(L / (2 * rmax)))));
    edge[a] = L / nc[a];
  }
  auto cell_of = [&](const Vec3d& p, int a) { return std::min(nc[a] - 1, std::max(0, int((p[a] - lo[a]) / edge[a]))); };
  const size_t ncell = size_t(nc[0]) * nc[1] * nc[2];
  std::vector<size_t> start(ncell + 1, 0), cell(n);
  for (size_t i = 0; i < n; ++i) {
    cell[i] = (size_t(cell_of(x[i], 2)) * nc[1] + cell_of(x[i], 1)) * nc[0] + cell_of(x[i], 0);
    ++start[cell[i] + 1];
  }
  for (size_t c = 0; c < ncell; ++c) start[c + 1] += start[c];
  std::vector<size_t> fill(start.begin(), start.end() - 1), in_cell(n);
  for (size_t i = 0; i < n; ++i) in_cell[fill[cell[i]]++] = i;
  for (size_t i = 0; i < n; ++i) {
    const int cx = cell_of(x[i], 0), cy = cell_of(x[i], 1), cz = cell_of(x[i], 2);
    for (int Z = std::max(0, cz - 1); Z <= std::min(nc[2] - 1, cz + 1); ++Z)
      for (int Y = std::max(0, cy - 1); Y <= std::min(nc[1] - 1, cy + 1); ++Y)
        for (int X = std::max(0, cx - 1); X <= std::min(nc[0] - 1, cx + 1); ++X) {
          const size_t c = (size_t(Z) * nc[1] + Y) * nc[0] + X;
          for (size_t k = start[c]; k < start[c + 1]; ++k) {
            const size_t j = in_cell[k];
            if (j <= i) continue;  // each pair once
            Real d2 = 0;
            for (int a = 0; a < 3; ++a) d2 += (x[j][a] - x[i][a]) * (x[j][a] - x[i][a]);
            const Real s = r[i] + r[j];
            if (d2 >= s * s) continue;
            ++pc.touching;
            const Real ov = (s - std::sqrt(d2)) / std::min(r[i], r[j]);
            if (ov > pc.max_overlap) {
              pc.max_overlap = ov;
              pc.max_i = int(i);
              pc.max_j = int(j);
            }
          }
        }
    // below 1e-12 of a radius: the round-off of a bounding box's own x - r, not a sphere pressing the wall
    for (int a = 0; a < 3; ++a)
      for (const Real gap : {x[i][a] - lo[a], hi[a] - x[i][a]})
        if (const Real ov = (r[i] - gap) / r[i]; ov > 1e-12) {
          ++pc.wall_touching;
          pc.max_wall_overlap = std::max(pc.max_wall_overlap, ov);
        }
  }
  return pc;
}

std::vector<std::string> import_packing(const ImportOptions& opt) {
  if (!(opt.scale > 0) || !std::isfinite(opt.scale))
    throw std::runtime_error("--scale = " + num(opt.scale) + " must be a number > 0 (1e-3 for a file in mm)");
  if (!(opt.density > 0 && opt.density <= 1e6))
    throw std::runtime_error("--density = " + num(opt.density) + " kg/m^3 is outside sample.density's range (0, 1e6]");
  if (!(opt.density_scaling >= 1 && opt.density_scaling <= 1e12))
    throw std::runtime_error("--density-scaling = " + num(opt.density_scaling) +
                             " is outside sample.density_scaling's range [1, 1e12]");
  const char* axis = "xyz";
  if (opt.box_given)
    for (int a = 0; a < 3; ++a)
      if (!(opt.lo[a] < opt.hi[a]) || !std::isfinite(opt.lo[a]) || !std::isfinite(opt.hi[a]))
        throw std::runtime_error(std::string("--box: ") + axis[a] + "lo = " + num(opt.lo[a]) + " must be below " +
                                 axis[a] + "hi = " + num(opt.hi[a]) + " (six numbers: xlo xhi ylo yhi zlo zhi, m)");
  std::error_code ec;
  if (fs::exists(opt.out, ec))
    throw std::runtime_error(opt.out + ": exists; import never replaces a file: remove it or name another --out");
  Read in = read_packing(opt.packing, opt.scale);
  const size_t n = in.r.size();

  Vec3d lo = opt.lo, hi = opt.hi;
  if (!opt.box_given) {  // each wall touches the outermost sphere on its side: no sphere presses a wall yet
    lo = {in.x[0][0] - in.r[0], in.x[0][1] - in.r[0], in.x[0][2] - in.r[0]};
    hi = {in.x[0][0] + in.r[0], in.x[0][1] + in.r[0], in.x[0][2] + in.r[0]};
    for (size_t i = 0; i < n; ++i)
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], in.x[i][a] - in.r[i]);
        hi[a] = std::max(hi[a], in.x[i][a] + in.r[i]);
      }
  }
  for (size_t i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a)
      if (!(in.x[i][a] > lo[a] && in.x[i][a] < hi[a]))
        throw std::runtime_error(opt.packing + ":" + std::to_string(in.line[i]) + ": the centre's " + axis[a] + " = " +
                                 num(in.x[i][a], 6) + " m is outside the box's [" + num(lo[a], 6) + ", " + num(hi[a], 6) +
                                 "] m (--box): every centre must lie between the walls");

  // Spatial (Morton) order: a file's order is often random in space, and the contact kernel's neighbour reads need
  // neighbours close in memory (perf/NOTES.md attempt 3a: 1.7x on the race scene, whose file order is random).
  Real rmean = 0;
  for (Real ri : in.r) rmean += ri;
  rmean /= Real(n);
  const std::vector<int> order = spatial_order(in.x, 2 * rmean);
  EngineState s;
  s.x.resize(n);
  s.r.resize(n);
  s.v.assign(n, Vec3d{0, 0, 0});
  s.w = s.f = s.t = s.v;
  std::vector<int> index(n);
  for (size_t k = 0; k < n; ++k) {
    s.x[k] = in.x[size_t(order[k])];
    s.r[k] = in.r[size_t(order[k])];
    index[k] = order[k];
  }
  s.walls = make_box_walls(lo, hi);
  s.walls_are_box = true;

  Real Vs = 0;
  for (Real ri : s.r) Vs += 4.0 / 3.0 * M_PI * ri * ri * ri;
  const Real V = (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
  const PackingContacts pc = packing_contacts(s.x, s.r, lo, hi);
  const GradingIndices gi = grading_indices(s.r);
  const std::string from = fs::absolute(opt.packing, ec).lexically_normal().string();
  write_h5_atomic(opt.out, [&](H5Writer& w) {
    write_state(w, s);
    w.attr("density", opt.density);
    w.attr("density_scaling", opt.density_scaling);
    w.attr("stage", std::string("import"));
    w.attr("imported_from", from);
    w.attr("import_scale", opt.scale);
    w.attr("e", (V - Vs) / Vs);
    w.attr("build", version_line());
    // sphere k of the sample is sphere index[k] of the file (0-based, counting sphere lines only: numpy.loadtxt's
    // row), so that results can be laid beside the file's own columns
    w.group("/import");
    w.write("/import/index", index);
  });

  const auto [rmin, rmax] = std::minmax_element(s.r.begin(), s.r.end());
  std::vector<std::string> lines;
  lines.push_back("imported " + std::to_string(n) + " spheres from " + opt.packing + ": diameters " + mm(2 * *rmin) +
                  " to " + mm(2 * *rmax) + "; by mass d50 " + mm(gi.d50) + ", Cu " + num(gi.cu, 3));
  lines.push_back("box " + mm(hi[0] - lo[0]) + " x " + mm(hi[1] - lo[1]) + " x " + mm(hi[2] - lo[2]) +
                  (opt.box_given ? " (--box)" : " (the spheres' bounding box)") + ": solid fraction " +
                  num(Vs / V, 4) + ", void ratio e " + num((V - Vs) / Vs, 4));
  std::string c = "contacts: " + std::to_string(pc.touching) + " overlapping pairs (Z " +
                  num(2.0 * double(pc.touching) / double(n), 3) + ")";
  const long line_i = pc.touching > 0 ? in.line[size_t(index[size_t(pc.max_i)])] : 0;
  const long line_j = pc.touching > 0 ? in.line[size_t(index[size_t(pc.max_j)])] : 0;
  if (pc.touching > 0)
    c += ", the largest overlap " + num(pc.max_overlap, 3) + " of the smaller radius (lines " +
         std::to_string(std::min(line_i, line_j)) + " and " + std::to_string(std::max(line_i, line_j)) + ")";
  c += pc.wall_touching > 0 ? "; " + std::to_string(pc.wall_touching) + " sphere-wall overlaps, the largest " +
                                   num(pc.max_wall_overlap, 3) + " of the sphere's radius"
                             : "; no sphere presses a wall";
  lines.push_back(c);
  // numerics.max_overlap's default: a run stops with a diagnosis where an overlap passes it
  if (std::max(pc.max_overlap, pc.max_wall_overlap) > 0.2)
    lines.push_back("warning: an overlap of " + num(std::max(pc.max_overlap, pc.max_wall_overlap), 3) +
                    " is past numerics.max_overlap's default 0.2: a run from this sample stops at its first step "
                    "unless its config raises numerics.max_overlap (or the file is in other units: --scale)");
  lines.push_back("sample: " + opt.out + " (start a run from it with sample: {file: " + opt.out + "})");
  return lines;
}

}  // namespace grainlab
