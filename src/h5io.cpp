#include "h5io.hpp"

#include <fcntl.h>
#include <hdf5.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

namespace grainlab {
namespace {

struct Silence {
  Silence() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }
};
void silence() { static Silence s; }

[[noreturn]] void fail(const std::string& path, const std::string& what) { throw H5Error(path + ": " + what); }

template <class T>
hid_t native();
template <>
hid_t native<double>() { return H5T_NATIVE_DOUBLE; }
template <>
hid_t native<int>() { return H5T_NATIVE_INT; }
template <>
hid_t native<std::int64_t>() { return H5T_NATIVE_INT64; }
template <>
hid_t native<std::uint8_t>() { return H5T_NATIVE_UINT8; }
template <>
hid_t native<char>() { return H5T_NATIVE_CHAR; }

template <class T>
void write_raw(const std::string& path, hid_t file, const std::string& name, const T* data, hsize_t n, hsize_t cols) {
  hsize_t dims[2] = {n, cols};
  const hid_t space = H5Screate_simple(cols > 1 ? 2 : 1, dims, nullptr);
  const hid_t set = H5Dcreate2(file, name.c_str(), native<T>(), space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  herr_t st = set >= 0 && (n * cols == 0 || H5Dwrite(set, native<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, data) >= 0) ? 0 : -1;
  if (set >= 0) H5Dclose(set);
  H5Sclose(space);
  if (st < 0) fail(path, "cannot write dataset " + name + " (disk full or read-only?)");
}

template <class T>
std::vector<T> read_raw(const std::string& path, hid_t file, const std::string& name, hsize_t cols) {
  const hid_t set = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  if (set < 0) fail(path, "missing dataset " + name + " (not a grainlab file, or truncated)");
  const hid_t space = H5Dget_space(set);
  hsize_t dims[2] = {0, 1};
  const int rank = H5Sget_simple_extent_ndims(space);
  if (rank < 1 || rank > 2) {
    H5Sclose(space);
    H5Dclose(set);
    fail(path, "dataset " + name + " has an unexpected shape");
  }
  H5Sget_simple_extent_dims(space, dims, nullptr);
  if (rank == 1) dims[1] = 1;
  H5Sclose(space);
  if (dims[1] != cols) {
    H5Dclose(set);
    fail(path, "dataset " + name + " has " + std::to_string(dims[1]) + " columns, expected " + std::to_string(cols));
  }
  std::vector<T> out(dims[0] * cols);
  const herr_t st = out.empty() ? 0 : H5Dread(set, native<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data());
  H5Dclose(set);
  if (st < 0) fail(path, "cannot read dataset " + name + " (corrupt or truncated file)");
  return out;
}

}  // namespace

// The file is built in memory (core driver, no backing store) and written out by close() with our own
// checked I/O. HDF5 never touches the disk: when a write fails (disk full, read-only, quota) HDF5 has
// nothing half-closed to trip over at exit, and the error is one clear line of ours.
H5Writer::H5Writer(const std::string& path) : path_(path) {
  silence();
  const hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  H5Pset_fapl_core(fapl, 1 << 20, 0);
  file_ = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
  H5Pclose(fapl);
  if (file_ < 0) fail(path, "cannot create the HDF5 file in memory");
}
H5Writer::~H5Writer() {
  if (file_ >= 0) H5Fclose(hid_t(file_));
}
void H5Writer::close() {
  if (file_ < 0) return;
  std::vector<char> image;
  bool ok = H5Fflush(hid_t(file_), H5F_SCOPE_GLOBAL) >= 0;
  const ssize_t size = ok ? H5Fget_file_image(hid_t(file_), nullptr, 0) : -1;
  if (size > 0) {
    image.resize(size_t(size));
    ok = H5Fget_file_image(hid_t(file_), image.data(), image.size()) == size;
  } else {
    ok = false;
  }
  H5Fclose(hid_t(file_));
  file_ = -1;
  if (!ok) fail(path_, "cannot assemble the HDF5 image (out of memory?)");
  const int fd = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0) fail(path_, std::string("cannot create the file (") + std::strerror(errno) + ")");
  size_t done = 0;
  while (done < image.size()) {
    const ssize_t w = ::write(fd, image.data() + done, image.size() - done);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) {
      const int e = errno;
      ::close(fd);
      std::remove(path_.c_str());
      fail(path_, std::string("cannot write the file (") + std::strerror(e) + "; disk full?)");
    }
    done += size_t(w);
  }
  if (::close(fd) != 0) {
    std::remove(path_.c_str());
    fail(path_, std::string("cannot close the file (") + std::strerror(errno) + "; disk full?)");
  }
}
void H5Writer::group(const std::string& name) {
  const hid_t g = H5Gcreate2(hid_t(file_), name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  if (g < 0) fail(path_, "cannot create group " + name);
  H5Gclose(g);
}
void H5Writer::write(const std::string& n, const std::vector<double>& v) { write_raw(path_, file_, n, v.data(), v.size(), 1); }
void H5Writer::write(const std::string& n, const std::vector<int>& v) { write_raw(path_, file_, n, v.data(), v.size(), 1); }
void H5Writer::write(const std::string& n, const std::vector<std::int64_t>& v) {
  write_raw(path_, file_, n, v.data(), v.size(), 1);
}
void H5Writer::write(const std::string& n, const std::vector<std::uint8_t>& v) {
  write_raw(path_, file_, n, v.data(), v.size(), 1);
}
void H5Writer::write(const std::string& n, const std::vector<Vec3d>& v) {
  write_raw(path_, file_, n, v.empty() ? nullptr : v[0].data(), v.size(), 3);
}
void H5Writer::write_string(const std::string& n, const std::string& s) {
  write_raw(path_, file_, n, s.data(), s.size(), 1);
}
void H5Writer::attr(const std::string& name, double v) {
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t a = H5Acreate2(hid_t(file_), name.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT);
  const bool ok = a >= 0 && H5Awrite(a, H5T_NATIVE_DOUBLE, &v) >= 0;
  if (a >= 0) H5Aclose(a);
  H5Sclose(space);
  if (!ok) fail(path_, "cannot write attribute " + name);
}
void H5Writer::attr(const std::string& name, const std::string& v) {
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, std::max<size_t>(v.size(), 1));
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t a = H5Acreate2(hid_t(file_), name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT);
  std::string buf = v.empty() ? std::string(1, '\0') : v;
  const bool ok = a >= 0 && H5Awrite(a, type, buf.data()) >= 0;
  if (a >= 0) H5Aclose(a);
  H5Sclose(space);
  H5Tclose(type);
  if (!ok) fail(path_, "cannot write attribute " + name);
}

H5Reader::H5Reader(const std::string& path) : path_(path) {
  silence();
  if (!std::filesystem::exists(path)) fail(path, "no such file");
  if (H5Fis_hdf5(path.c_str()) <= 0) fail(path, "not an HDF5 file (corrupt or truncated)");
  file_ = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file_ < 0) fail(path, "cannot open the HDF5 file (corrupt or truncated)");
}
H5Reader::~H5Reader() {
  if (file_ >= 0) H5Fclose(hid_t(file_));
}
bool H5Reader::has(const std::string& name) const {
  return H5Lexists(hid_t(file_), name.c_str(), H5P_DEFAULT) > 0 || H5Aexists(hid_t(file_), name.c_str()) > 0;
}
std::vector<double> H5Reader::doubles(const std::string& n) const { return read_raw<double>(path_, file_, n, 1); }
std::vector<int> H5Reader::ints(const std::string& n) const { return read_raw<int>(path_, file_, n, 1); }
std::vector<std::int64_t> H5Reader::int64s(const std::string& n) const { return read_raw<std::int64_t>(path_, file_, n, 1); }
std::vector<std::uint8_t> H5Reader::bytes(const std::string& n) const { return read_raw<std::uint8_t>(path_, file_, n, 1); }
std::vector<Vec3d> H5Reader::vec3(const std::string& n) const {
  const auto flat = read_raw<double>(path_, file_, n, 3);
  std::vector<Vec3d> out(flat.size() / 3);
  if (!out.empty()) std::memcpy(out.data(), flat.data(), flat.size() * sizeof(double));
  return out;
}
std::string H5Reader::string(const std::string& n) const {
  const auto c = read_raw<char>(path_, file_, n, 1);
  return std::string(c.begin(), c.end());
}
double H5Reader::attr_double(const std::string& name) const {
  const hid_t a = H5Aopen(hid_t(file_), name.c_str(), H5P_DEFAULT);
  if (a < 0) fail(path_, "missing attribute " + name);
  double v = 0;
  const herr_t st = H5Aread(a, H5T_NATIVE_DOUBLE, &v);
  H5Aclose(a);
  if (st < 0) fail(path_, "cannot read attribute " + name);
  return v;
}
std::string H5Reader::attr_string(const std::string& name) const {
  const hid_t a = H5Aopen(hid_t(file_), name.c_str(), H5P_DEFAULT);
  if (a < 0) fail(path_, "missing attribute " + name);
  const hid_t type = H5Aget_type(a);
  const size_t size = H5Tget_size(type);
  std::string buf(size, '\0');
  const herr_t st = H5Aread(a, type, buf.data());
  H5Tclose(type);
  H5Aclose(a);
  if (st < 0) fail(path_, "cannot read attribute " + name);
  return std::string(buf.c_str());
}

std::string temp_name(const std::string& path) { return path + ".tmp." + std::to_string(::getpid()); }

void commit_atomic(const std::string& tmp, const std::string& path) {
  const int fd = ::open(tmp.c_str(), O_RDONLY);
  const bool synced = fd >= 0 && ::fsync(fd) == 0;
  if (fd >= 0) ::close(fd);
  std::error_code ec;
  if (synced) std::filesystem::rename(tmp, path, ec);
  if (!synced || ec) {
    std::remove(tmp.c_str());
    throw H5Error(path + ": cannot commit the file (" + (synced ? ec.message() : std::string(std::strerror(errno))) +
                  "); the previous version is untouched");
  }
}

namespace {
// The walls of a state as /state/walls stores them: 14 values a wall.
std::vector<double> walls_record(const EngineState& s) {
  std::vector<double> walls;
  for (int k = 0; k < kMaxWalls; ++k) {
    const Wall& wl = s.walls.w[k];
    const WallControl& c = s.control[k];
    walls.insert(walls.end(), {wl.n.x, wl.n.y, wl.n.z, wl.offset, double(int(c.mode)), c.velocity, c.target_stress,
                               c.gain, c.area, s.loads.force[k], s.loads.stiffness[k], double(s.loads.touching[k]),
                               c.integral, c.drift});
  }
  return walls;
}
}  // namespace

void write_state(H5Writer& w, const EngineState& s) {
  w.group("/state");
  w.write("/state/scalars", std::vector<double>{double(s.step), s.time, s.dt, s.mu, s.mu_r, s.damping,
                                                 double(s.walls_are_box), double(s.walls.count)});
  w.write("/state/x", s.x);
  w.write("/state/v", s.v);
  w.write("/state/w", s.w);
  w.write("/state/f", s.f);
  w.write("/state/t", s.t);
  w.write("/state/r", s.r);
  w.write("/state/pair_i", s.pair_i);
  w.write("/state/pair_j", s.pair_j);
  w.write("/state/ft", s.ft);
  w.write("/state/mr", s.mr);
  w.write("/state/flags", s.flags);
  w.write("/state/walls", walls_record(s));
}

std::string state_digest(const EngineState& s) {
  // FNV-1a, 64 bits (Fowler, Noll, Vo), over every value write_state stores but the clock (step, time, dt: a
  // sample's are reset when a run starts from it): enough to tell two samples apart, which is all it is for.
  std::uint64_t h = 14695981039346656037ull;
  auto value = [&](auto v) {  // its bytes, least significant first
    std::uint64_t bits = 0;
    static_assert(sizeof v <= sizeof bits);
    std::memcpy(&bits, &v, sizeof v);
    for (size_t b = 0; b < sizeof v; ++b) h = (h ^ ((bits >> (8 * b)) & 0xffu)) * 1099511628211ull;
  };
  auto all = [&](const auto& v) {
    value(std::uint64_t(v.size()));  // the lengths too: [a][bc] and [ab][c] differ
    for (const auto& e : v) value(e);
  };
  for (const double d : {s.mu, s.mu_r, s.damping, double(s.walls_are_box), double(s.walls.count)}) value(d);
  for (const auto* v : {&s.x, &s.v, &s.w, &s.f, &s.t, &s.ft, &s.mr}) {
    value(std::uint64_t(v->size()));
    for (const Vec3d& e : *v)
      for (const Real c : e) value(c);
  }
  all(s.r);
  all(s.pair_i);
  all(s.pair_j);
  all(s.flags);
  all(walls_record(s));
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
  return hex;
}

EngineState read_state(const H5Reader& r) {
  EngineState s;
  // A run's other HDF5 files hold results, not a state to go on from: said by name, since a user pointing
  // sample.file at the last snapshot would otherwise read "not a grainlab file".
  if (!r.has("/state") && (r.has("/particles") || r.has("/series")))
    fail(r.path(), std::string(r.has("/particles") ? "a snapshot of a run (positions and contact forces, no wall state or "
                                                     "contact history)"
                                                   : "a run's series (run.h5)") +
                       ", not a sample or checkpoint: a run starts from a sample_<stage>.h5 of the run that prepared it");
  const auto sc = r.doubles("/state/scalars");
  if (sc.size() != 8) fail(r.path(), "state scalars have the wrong length (corrupt file?)");
  s.step = long(sc[0]);
  s.time = sc[1];
  s.dt = sc[2];
  s.mu = sc[3];
  s.mu_r = sc[4];
  s.damping = sc[5];
  s.walls_are_box = sc[6] != 0;
  s.walls.count = int(sc[7]);
  s.x = r.vec3("/state/x");
  s.v = r.vec3("/state/v");
  s.w = r.vec3("/state/w");
  s.f = r.vec3("/state/f");
  s.t = r.vec3("/state/t");
  s.r = r.doubles("/state/r");
  s.pair_i = r.ints("/state/pair_i");
  s.pair_j = r.ints("/state/pair_j");
  s.ft = r.vec3("/state/ft");
  s.mr = r.vec3("/state/mr");
  s.flags = r.bytes("/state/flags");
  const auto walls = r.doubles("/state/walls");
  // 14 values a wall; 12 in a checkpoint from before the servo's integral action (off there: integral = drift = 0).
  const size_t nw = walls.size() / kMaxWalls;
  if ((nw != 12 && nw != 14) || walls.size() != nw * kMaxWalls || s.walls.count < 0 || s.walls.count > kMaxWalls)
    fail(r.path(), "state walls have the wrong length (corrupt file?)");
  for (int k = 0; k < kMaxWalls; ++k) {
    const double* q = &walls[nw * k];
    s.walls.w[k].n = Vec3(q[0], q[1], q[2]);
    s.walls.w[k].offset = q[3];
    s.control[k].mode = WallMode(int(q[4]));
    s.control[k].velocity = q[5];
    s.control[k].target_stress = q[6];
    s.control[k].gain = q[7];
    s.control[k].area = q[8];
    s.loads.force[k] = q[9];
    s.loads.stiffness[k] = q[10];
    s.loads.touching[k] = int(q[11]);
    if (nw == 14) {
      s.control[k].integral = q[12];
      s.control[k].drift = q[13];
    }
  }
  const size_t n = s.x.size();
  if (s.v.size() != n || s.w.size() != n || s.f.size() != n || s.t.size() != n || s.r.size() != n)
    fail(r.path(), "state particle arrays differ in length (corrupt file?)");
  return s;
}

}  // namespace grainlab
