#pragma once
// Sample generation, SPEC §1 and §6.1: power-law radii by inverse CDF from a seeded generator, placed at
// random without overlap in a cube. Bitwise reproducible across compilers: the generator and the
// uniform transform are our own (std:: distributions are implementation-defined).
#include <cstdint>
#include <vector>

#include "engine.hpp"

namespace grainlab {

// A grading curve as a sieve analysis gives it (beyond SPEC §1, which draws p(r) ~ r^-D): the percent of the
// solids' mass finer than each diameter. Between two sieves the percent passing is linear in ln d, as the curve
// is drawn on its semi-log axes and D10, D50 are read off it (ASTM D6913's interpolation): the mass per ln d is
// uniform there, so the number density is p(d) ~ d^-4 within a sieve interval (mass ~ d^3 p(d) d(d) / d(ln d)).
struct Grading {
  std::vector<Real> diameter;  // sieve sizes [m], strictly increasing
  std::vector<Real> passing;   // percent by mass finer, non-decreasing from 0 (the first) to 100 (the last)
  bool empty() const { return diameter.empty(); }
};
// The diameter at which `g` passes `percent` (0-100), interpolated in ln d (D10: grading_diameter(g, 10)).
Real grading_diameter(const Grading& g, Real percent);
// The grading (by mass) of a set of radii: at each of `diameters`, the percent of their volume in spheres of
// diameter <= it.
std::vector<Real> passing_at(std::vector<Real> r, const std::vector<Real>& diameters);
// Where to compare a drawn sample with its grading: each sieve and each interval's geometric middle, with the percent
// the curve passes there (at a middle the mean of its ends, the curve being linear in ln d); flat steps have no middle.
struct GradingPoints {
  std::vector<Real> at, want;
  std::vector<char> sieve;  // 1: at[k] is a sieve, 0: a middle
};
GradingPoints grading_check_points(const Grading& g);
// D10, D30, D50, D60 and the coefficients of uniformity Cu = D60/D10 and curvature Cc = D30^2/(D10 D60) of a
// grading curve or of a sample's radii (by mass; between two spheres' diameters interpolated in ln d).
struct GradingIndices {
  Real d10 = 0, d30 = 0, d50 = 0, d60 = 0, cu = 0, cc = 0;
};
GradingIndices grading_indices(const Grading& g);
GradingIndices grading_indices(std::vector<Real> r);

struct PackingSpec {
  int count = 3000;
  Real D = 3.63;                 // p(r) ~ r^-D                       [-]
  Real r_min = 0.2e-3;           // [m] (with a grading: half its first diameter)
  Real r_max = 0.6e-3;           // [m] (with a grading: half its last diameter)
  Grading grading;               // when given, the radii follow it instead of D (on [r_min, r_max])
  std::uint64_t seed = 1;
  Real solid_fraction = 0.3;     // loose initial solid fraction       [-]
};

struct Packing {
  std::vector<Vec3d> x;
  std::vector<Real> r;
  Vec3d lo{}, hi{};
  long overflowed = 0;  // spheres placed past their cell's flat slots (generate_packing): the tests see that path taken
};

// xoshiro256** seeded through splitmix64.
class Rng {
 public:
  explicit Rng(std::uint64_t seed);
  std::uint64_t next();
  Real uniform() { return Real(next() >> 11) * 0x1.0p-53; }  // [0, 1)
 private:
  std::uint64_t s_[4];
};

// Inverse CDF of p(r) ~ r^-D on [a, b]: u in [0, 1) -> a radius (D = 1: uniform in ln r).
Real power_law_radius(Real u, Real D, Real a, Real b);
// Inverse CDF of a grading's radius distribution: u in [0, 1) -> a radius (one draw a sphere, as power_law_radius).
class GradingSampler {
 public:
  explicit GradingSampler(const Grading& g);
  Real radius(Real u) const;
 private:
  std::vector<Real> a_, b_;    // each sieve interval's radii
  std::vector<Real> cum_;      // the cumulative number fraction at each interval's end (the last exactly 1)
};

// Permutation that puts particles in Morton (Z-curve) order of cubic cells of edge `cell`: spatial
// neighbours end up close in memory, which the contact kernel's neighbour reads need (perf/NOTES.md:
// 1.6x on the race scene, whose file order is random). order[k] = old index of new particle k; ties keep
// the old order, so the result is a pure function of the positions.
std::vector<int> spatial_order(const std::vector<Vec3d>& x, Real cell);

// Throws ParameterError when the spec is invalid or the cube cannot hold the spheres at that fraction.
// slots_per_cell: the placement grid's flat slots a cell (0: sized from the mean occupancy); any value gives the
// same packing, bit for bit (the tests force the overflow path with 1).
Packing generate_packing(const PackingSpec& spec, int slots_per_cell = 0);
// The radii generate_packing(spec) gives its spheres (as a multiset: largest first, before the spatial
// order), without placing them: what the stable time step needs, in O(N). The same errors for the same specs
// (but a failed placement, which only placing finds).
std::vector<Real> packing_radii(const PackingSpec& spec);

}  // namespace grainlab
