#pragma once
// Minimal HDF5 (C API) reading and writing for grainlab's files. Every failure throws one line naming
// the file and the object; HDF5's own error-stack printing is switched off.
#include <cstdint>
#include <string>
#include <vector>

#include "engine.hpp"

namespace grainlab {

struct H5Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class H5Writer {
 public:
  explicit H5Writer(const std::string& path);  // creates/truncates `path`
  ~H5Writer();
  H5Writer(const H5Writer&) = delete;
  H5Writer& operator=(const H5Writer&) = delete;
  void group(const std::string& name);
  void write(const std::string& name, const std::vector<double>& v);
  void write(const std::string& name, const std::vector<int>& v);
  void write(const std::string& name, const std::vector<std::int64_t>& v);
  void write(const std::string& name, const std::vector<std::uint8_t>& v);
  void write(const std::string& name, const std::vector<Vec3d>& v);  // N x 3
  void write_string(const std::string& name, const std::string& s);  // 1-D char dataset
  void attr(const std::string& name, double v);
  void attr(const std::string& name, const std::string& v);
  void close();  // flushes; the destructor closes too, silently

 private:
  std::string path_;
  long long file_ = -1;
};

class H5Reader {
 public:
  explicit H5Reader(const std::string& path);
  ~H5Reader();
  H5Reader(const H5Reader&) = delete;
  H5Reader& operator=(const H5Reader&) = delete;
  bool has(const std::string& name) const;
  std::vector<double> doubles(const std::string& name) const;
  std::vector<int> ints(const std::string& name) const;
  std::vector<std::int64_t> int64s(const std::string& name) const;
  std::vector<std::uint8_t> bytes(const std::string& name) const;
  std::vector<Vec3d> vec3(const std::string& name) const;
  std::string string(const std::string& name) const;
  double attr_double(const std::string& name) const;
  std::string attr_string(const std::string& name) const;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  long long file_ = -1;
};

// Writes through `path`.tmp.PID, fsyncs, renames: a crash leaves the old file or the new one, never a
// half-written file under the final name. `fill` writes the content.
template <class F>
void write_h5_atomic(const std::string& path, F&& fill);
void commit_atomic(const std::string& tmp, const std::string& path);  // fsync + rename (+ cleanup on error)
std::string temp_name(const std::string& path);

template <class F>
void write_h5_atomic(const std::string& path, F&& fill) {
  const std::string tmp = temp_name(path);
  try {
    H5Writer w(tmp);
    fill(w);
    w.close();
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
  commit_atomic(tmp, path);
}

// Engine state <-> HDF5 group `/state` (checkpoints and reusable samples).
void write_state(H5Writer& w, const EngineState& s);
EngineState read_state(const H5Reader& r);
// 16 hex digits that tell one saved state from another (its particles, contact history and walls; not its clock):
// a run records its sample.file's, so that a resume or a study rerun notices a sample file replaced under it.
std::string state_digest(const EngineState& s);

}  // namespace grainlab
