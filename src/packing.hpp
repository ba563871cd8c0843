#pragma once
// Sample generation, SPEC §1 and §6.1: power-law radii by inverse CDF from a seeded generator, placed at
// random without overlap in a cube. Bitwise reproducible across compilers: the generator and the
// uniform transform are our own (std:: distributions are implementation-defined).
#include <cstdint>

#include "engine.hpp"

namespace grainlab {

struct PackingSpec {
  int count = 3000;
  Real D = 3.63;                 // p(r) ~ r^-D                       [-]
  Real r_min = 0.2e-3;           // [m]
  Real r_max = 0.6e-3;           // [m]
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

// Inverse CDF of p(r) ~ r^-D on [a, b] (D != 1).
Real power_law_radius(Real u, Real D, Real a, Real b);

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
