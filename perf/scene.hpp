#pragma once
// Scenes for the perf executables: the shared race scene (../shared/bench/peers/scene_32k.txt, `x y z r`
// per line, walls from scene_32k_box.txt), optionally cropped to a corner or tiled K^3 times, or a
// generated FCC packing when the shared files are not at hand (CI smoke runs). Particles are put in
// Morton order (the file's order is random; our own packings are generated in cell order).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "src/engine.hpp"
#include "src/packing.hpp"

namespace grainlab::perf {

struct SceneArgs {
  std::string scene, box;
  int tile = 1;        // K^3 copies of the scene side by side (weak scaling)
  double crop = 1;     // keep the spheres inside the lower corner cube of this edge fraction (N ~ crop^3)
  int generate = 0;    // no scene file: a generated dense packing of about this many spheres (CI smoke)
  int sort = 1;        // Morton-order the particles before building the engine
  // Consumes the scene options; false when `key` is not one of them.
  bool parse(const std::string& key, const std::string& v) {
    if (key == "--scene") scene = v;
    else if (key == "--box") box = v;
    else if (key == "--tile") tile = std::stoi(v);
    else if (key == "--crop") crop = std::stod(v);
    else if (key == "--generate") generate = std::stoi(v);
    else if (key == "--sort") sort = std::stoi(v);
    else return false;
    return true;
  }
};

[[noreturn]] inline void scene_error(const std::string& why) {
  std::cerr << "scene: " << why << "\n";
  std::exit(2);
}

struct Scene {
  ParticleSetup s;
  Vec3d lo{}, hi{};
};

inline Scene read_scene(const SceneArgs& a) {
  Scene sc;
  std::ifstream bf(a.box);
  if (!bf) scene_error("cannot read " + a.box);
  Real b[6];
  for (Real& x : b)
    if (!(bf >> x)) scene_error(a.box + ": expected six numbers xlo xhi ylo yhi zlo zhi");
  std::ifstream f(a.scene);
  if (!f) scene_error("cannot read " + a.scene);
  std::vector<std::array<Real, 4>> base;
  std::string line;
  long ln = 0;
  while (std::getline(f, line)) {
    ++ln;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream is(line);
    std::array<Real, 4> p{};
    if (!(is >> p[0] >> p[1] >> p[2] >> p[3]) || !(p[3] > 0))
      scene_error(a.scene + ":" + std::to_string(ln) + ": expected 'x y z r' with r > 0");
    base.push_back(p);
  }
  Real L[3] = {b[1] - b[0], b[3] - b[2], b[5] - b[4]};
  if (a.crop < 1) {  // a smaller scene of the same packing: the spheres wholly inside the corner cube
    std::vector<std::array<Real, 4>> kept;
    for (const auto& p : base)
      if (p[0] + p[3] <= b[0] + a.crop * L[0] && p[1] + p[3] <= b[2] + a.crop * L[1] &&
          p[2] + p[3] <= b[4] + a.crop * L[2])
        kept.push_back(p);
    base = kept;
    for (Real& l : L) l *= a.crop;
  }
  // Tiling: K^3 copies shifted by the box edge. The copies touch across the old faces only where the
  // original spheres touched the walls (those overlaps are the wall overlaps, < 1.3 % of r).
  for (int tz = 0; tz < a.tile; ++tz)
    for (int ty = 0; ty < a.tile; ++ty)
      for (int tx = 0; tx < a.tile; ++tx)
        for (const auto& p : base) {
          sc.s.x.push_back({p[0] + tx * L[0], p[1] + ty * L[1], p[2] + tz * L[2]});
          sc.s.r.push_back(p[3]);
        }
  sc.lo = {b[0], b[2], b[4]};
  sc.hi = {b[0] + a.tile * L[0], b[2] + a.tile * L[1], b[4] + a.tile * L[2]};
  return sc;
}

// An FCC lattice of about n spheres (4 per cubic cell of edge a, c^3 cells), in lattice order, with
// radius() drawn per sphere in that order; returns c (the box is [0, c a]^3).
template <class Radius>
int fcc_lattice(int n, Real a, Radius radius, std::vector<Vec3d>& x, std::vector<Real>& r) {
  const int c = std::max(1, int(std::cbrt(n / 4.0) + 0.5));
  const Real basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  for (int z = 0; z < c; ++z)
    for (int y = 0; y < c; ++y)
      for (int i = 0; i < c; ++i)
        for (auto& bb : basis) {
          x.push_back({(i + bb[0] + 0.25) * a, (y + bb[1] + 0.25) * a, (z + bb[2] + 0.25) * a});
          r.push_back(radius());
        }
  return c;
}

// Morton order of the spheres (perf/NOTES.md attempt 3a), cell edge `cell`; not timed by any benchmark,
// as a reader of a file would do it before building the engine.
inline void morton_sort(std::vector<Vec3d>& x, std::vector<Real>& r, Real cell) {
  const std::vector<int> order = spatial_order(x, cell);
  std::vector<Vec3d> xs(order.size());
  std::vector<Real> rs(order.size());
  for (size_t k = 0; k < order.size(); ++k) {
    xs[k] = x[size_t(order[k])];
    rs[k] = r[size_t(order[k])];
  }
  x.swap(xs);
  r.swap(rs);
}

// Without the shared scene (CI): an FCC lattice with the scene's radius range, slightly overlapping.
inline Scene generated_scene(int n) {
  Scene sc;
  const Real a = 1.0e-3;
  Rng rng(7);
  const int c = fcc_lattice(n, a, [&] { return a / std::sqrt(2.0) / 2 * (0.96 + 0.05 * rng.uniform()); }, sc.s.x, sc.s.r);
  sc.hi = {c * a, c * a, c * a};
  return sc;
}

inline Scene load_scene(const SceneArgs& a) {
  if (a.scene.empty() != a.box.empty()) scene_error("--scene and --box go together");
  if (a.scene.empty() && a.generate <= 0) scene_error("give --scene/--box or --generate N");
  if (a.tile < 1) scene_error("--tile must be >= 1");
  if (!(a.crop > 0.2 && a.crop <= 1)) scene_error("--crop must be in (0.2, 1]");
  Scene sc = a.scene.empty() ? generated_scene(a.generate) : read_scene(a);
  if (a.sort) {
    Real rmean = 0;
    for (Real r : sc.s.r) rmean += r / Real(sc.s.r.size());
    morton_sort(sc.s.x, sc.s.r, 2 * rmean);
  }
  sc.s.density = 2650;
  return sc;
}

}  // namespace grainlab::perf
