#pragma once
// `grainlab import`: a packing made elsewhere (YADE's export.text, a CT scan's spheres, the shared race scene: x y z r
// a line; or a LAMMPS / LIGGGHTS text dump, its last snapshot) as a grainlab sample file, which `sample: {file: ...}`
// then starts runs and studies from like any sample_<stage>.h5: the same plan, resume and digest checks, no code path
// of its own.
#include <string>
#include <vector>

#include "engine.hpp"

namespace grainlab {

struct ImportOptions {
  std::string packing;         // text: one sphere a line, `x y z r` (blanks or commas between), `#` comments; or a dump
  std::string out;             // the sample file to write; never replaces a file
  bool box_given = false;      // else the box is the spheres' bounding box (each wall touching the outermost sphere)
  Vec3d lo{}, hi{};            // the walls' box [m] (after scale)
  // --crop: a box [m] (after scale) cut out of the packing: the spheres wholly inside it, and it as the walls (a
  // sample of a larger packing: a CT scan's, a big LIGGGHTS run's, the race scene's octant)
  bool crop = false;
  Vec3d crop_lo{}, crop_hi{};
  Real scale = 1;              // multiplies x, y, z and r: 1e-3 for a file in mm
  // --columns X,Y,Z,R: the four fields of a text packing's lines that are x y z r (1-based numbers, or names of its
  // header line), other fields ignored; empty: four fields a line, x y z r
  std::vector<std::string> columns;
  bool diameter = false;  // --size diameter: a text packing's fourth value (R of --columns) is a diameter
  Real density = 2650;         // [kg/m^3], as sample.density
  bool density_given = false;  // --density: else a data file's atoms' density, where they have one
  Real density_scaling = 1;    // as sample.density_scaling
};

// What a packing's spheres do to each other and to the walls: pairs that overlap (touch), the largest overlap over
// the smaller radius (SPEC §2's delta; what numerics.max_overlap bounds) and that over a sphere's radius against a
// wall. O(N): spheres binned in cells of the largest diameter.
struct PackingContacts {
  long touching = 0;
  Real max_overlap = 0;  // delta / min(r_i, r_j), 0 without a touching pair
  int max_i = -1, max_j = -1;
  Real max_wall_overlap = 0;  // (r - distance to the wall) / r
  long wall_touching = 0;     // sphere-wall pairs that overlap
};
PackingContacts packing_contacts(const std::vector<Vec3d>& x, const std::vector<Real>& r, const Vec3d& lo,
                                 const Vec3d& hi);

// Reads, checks and writes the packing (atomically; the spheres in spatial order, their file rows kept in the sample
// as /import/index, a dump's atom ids as /import/id). Returns the lines to print: what came in and what a run will
// meet. Throws std::runtime_error with a message naming the file, the line and the allowed range.
std::vector<std::string> import_packing(const ImportOptions& opt);

// `grainlab export`: the other way, a sample file or checkpoint (its spheres and box walls) or a snapshot (its spheres)
// as text for another code: `xyzr`, one sphere a line at 17 significant digits (so that `grainlab import` of it gives
// the same doubles) beside OUT_box.txt (xlo xhi ylo yhi zlo zhi, the shared race scene's form); or `lammps`, a data
// file for atom_style sphere / granular (id type diameter density x y z), its box the walls'. Written atomically, never
// over a file. Returns the lines to print.
struct ExportOptions {
  std::string in, out;
  std::string format = "xyzr";  // xyzr, lammps or dump (a LAMMPS text dump; `in` may then be a run directory)
};
std::vector<std::string> export_sample(const ExportOptions& opt);

}  // namespace grainlab
