#pragma once
// The virtual laboratory (SPEC §6): generate or load a sample, run its stages (isotropic consolidation
// with an optional void-ratio target, triaxial undrained/drained shear), write the series, snapshots,
// samples and checkpoints of one run directory, and resume it exactly.
#include <string>
#include <vector>

#include "config.hpp"

namespace grainlab {

struct RunOptions {
  std::string out_dir;  // overrides the config's output.dir when not empty
  bool quiet = false;
  bool resume = false;
  long stop_after_steps = -1;  // testing aid: behave as if interrupted after this many steps (-1: never)
};

struct StageResult {
  std::string name;
  bool converged = false;  // isotropic: equilibrium reached; triaxial: max strain reached
  long steps = 0;
  Real p = 0, q = 0, e = 0;
  Real mu = 0;             // friction used (the search result when target_e0 is set)
};

// A numerical blow-up stopped the run: the message names step, particles, quantity and a suggested dt;
// the newest checkpoint (written before the event) is kept.
struct BlowUpError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct RunResult {
  bool interrupted = false;  // stopped by a signal (or stop_after_steps): a checkpoint was written
  std::string checkpoint;    // the checkpoint written at the interruption
  std::vector<StageResult> stages;
};

// Writes `content` to `path` through a temporary file and a rename: a crash never leaves a
// half-written file under the final name.
void write_file_atomic(const std::string& path, const std::string& content);

RunResult run_simulation(const RunConfig& cfg, const RunOptions& opt);

// Series columns (name, unit), in order; documented in configs/README.md.
const std::vector<std::pair<std::string, std::string>>& series_columns();

}  // namespace grainlab
