// The source commit this build was made from (scripts/source_commit.cmake writes the header at every build), alone
// in its file so that a new commit recompiles only this.
#include "src/simulation.hpp"

#include "grainlab_source_commit.hpp"

namespace grainlab {
const char* source_commit() { return GRAINLAB_SOURCE_COMMIT; }
}  // namespace grainlab
