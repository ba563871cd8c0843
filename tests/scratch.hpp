#pragma once
// Scratch files of one test process, all under <tmp>/grainlab_tests_<pid>/: test_main.cpp removes the folder when
// every test passed and keeps it (and says where) when one failed, so a green `make test` leaves nothing behind in the
// temp directory and a red one leaves what to inspect (GRAINLAB_KEEP_SCRATCH=1 keeps it always). The pid keeps
// apart two runs of one binary at the same time (a PHYSICS test's 1- and 2-thread runs under `ctest --parallel`).
#include <unistd.h>

#include <filesystem>
#include <string>

namespace grainlab::test {

inline std::filesystem::path scratch_root() {
  static const std::filesystem::path root =
      std::filesystem::temp_directory_path() / ("grainlab_tests_" + std::to_string(::getpid()));
  return root;
}

// A path for `name` inside the scratch root (which it creates); the path itself is not created.
inline std::filesystem::path scratch(const std::string& name) {
  std::filesystem::create_directories(scratch_root());
  return scratch_root() / name;
}

}  // namespace grainlab::test
