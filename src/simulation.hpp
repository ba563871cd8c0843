#pragma once
// The laboratory driver (SPEC §6): generate a sample, run its stages, write the series.
#include <functional>
#include <string>

#include "config.hpp"

namespace grainlab {

struct RunOptions {
  std::string out_dir;  // overrides the config's output.dir when not empty
  bool quiet = false;
};

struct StageResult {
  std::string name;
  bool converged = false;  // isotropic: equilibrium reached; triaxial: max strain reached
  long steps = 0;
  Real p = 0, q = 0, e = 0;
};

// Writes `content` to `path` through a temporary file and a rename: a crash never leaves a
// half-written file under the final name.
void write_file_atomic(const std::string& path, const std::string& content);

std::vector<StageResult> run_simulation(const RunConfig& cfg, const RunOptions& opt);

}  // namespace grainlab
