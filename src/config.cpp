#include "config.hpp"

#include <yaml-cpp/yaml.h>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <algorithm>
#include <cstdlib>
#include <pwd.h>
#include <unistd.h>
#include <charconv>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <type_traits>

namespace grainlab {
namespace {

constexpr Real kInf = std::numeric_limits<Real>::infinity();

std::string fmt(Real v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

// A YAML mapping with its dotted path, the keys read so far, and range-checked getters.
class Section {
 public:
  Section(const YAML::Node& n, std::string path, const std::string* file) : n_(n), path_(std::move(path)), file_(file) {
    if (!n_.IsMap()) fail(path_.empty() ? "(top level)" : path_, "must be a mapping of keys to values");
  }
  [[noreturn]] void fail(const std::string& key, const std::string& msg) const {
    // "key = value is outside ..." reads as one statement; other messages follow "key: ".
    const bool states_value = msg.rfind("= ", 0) == 0;
    throw ConfigError(*file_ + ": " + key + (states_value ? " " : ": ") + msg);
  }
  std::string key_path(const std::string& k) const { return path_.empty() ? k : path_ + "." + k; }
  // A key written with no value (`count:` or `count: ~`) is an error, not its default: a value left out by mistake
  // would otherwise silently mean the default, as a misspelt key would (finish). A section may be blank (sub).
  bool has(const std::string& k) {
    seen_.insert(k);
    if (n_[k] && n_[k].IsNull())
      fail(key_path(k), "has no value: give one, or leave the key out for its default");
    return bool(n_[k]);
  }

  // Real in [lo, hi] (lower bound open when lo_open), finite.
  Real real(const std::string& k, Real def, Real lo, Real hi, bool lo_open = false) {
    if (!has(k)) return def;
    return real_node(k, lo, hi, lo_open);
  }
  long integer(const std::string& k, long def, long lo, long hi) {
    if (!has(k)) return def;
    const Real v = real_node(k, Real(lo), Real(hi), false);
    if (v != std::floor(v)) fail(key_path(k), "= " + fmt(v) + " must be an integer");
    return long(v);
  }
  std::string choice(const std::string& k, const std::string& def, const std::vector<std::string>& allowed) {
    std::string v = def;
    if (has(k)) {
      if (!n_[k].IsScalar()) fail(key_path(k), "must be a string");
      v = n_[k].Scalar();
    }
    std::string list;
    for (auto& a : allowed) {
      if (a == v) return v;
      list += (list.empty() ? "" : ", ") + a;
    }
    fail(key_path(k), "= '" + v + "' is not one of: " + list);
  }
  std::string string(const std::string& k, const std::string& def) {
    if (!has(k)) return def;
    if (!n_[k].IsScalar() || n_[k].Scalar().empty()) fail(key_path(k), "must be a non-empty string");
    return n_[k].Scalar();
  }
  bool boolean(const std::string& k, bool def) {
    if (!has(k)) return def;
    const YAML::Node v = n_[k];
    bool b = def;
    try {
      if (!v.IsScalar()) throw YAML::Exception(YAML::Mark(), "");
      b = v.as<bool>();
    } catch (const YAML::Exception&) {
      fail(key_path(k), "must be true or false");
    }
    return b;
  }
  // A required list of [min_size, max_size] numbers, each in [lo, hi] (lower bound open when lo_open), finite.
  std::vector<Real> real_list(const std::string& k, size_t min_size, size_t max_size, Real lo, Real hi, bool lo_open) {
    if (!has(k)) fail(key_path(k), "is required here");
    const YAML::Node v = n_[k];
    if (!v.IsSequence() || v.size() < min_size || v.size() > max_size)
      fail(key_path(k), "must be a list of " + std::to_string(min_size) + " to " + std::to_string(max_size) +
                            " numbers (" + range(lo, hi, lo_open) + ")" +
                            (v.IsSequence() ? "; it has " + std::to_string(v.size()) : ""));
    std::vector<Real> out;
    for (size_t i = 0; i < v.size(); ++i) out.push_back(real_value(v[i], key_path(k) + "[" + std::to_string(i) + "]", lo, hi, lo_open));
    return out;
  }
  Section sub(const std::string& k) {
    seen_.insert(k);
    YAML::Node c = n_[k];
    if (!c || c.IsNull()) c = YAML::Node(YAML::NodeType::Map);
    return Section(c, key_path(k), file_);
  }
  YAML::Node raw(const std::string& k) {
    seen_.insert(k);
    return n_[k];
  }
  // Unknown keys are errors: a misspelt key would otherwise silently mean its default.
  void finish() const {
    for (auto it = n_.begin(); it != n_.end(); ++it) {
      const std::string k = it->first.IsScalar() ? it->first.Scalar() : "?";
      if (!seen_.count(k)) {
        std::string known;
        for (auto& s : seen_) known += (known.empty() ? "" : ", ") + s;
        fail(key_path(k), "unknown key (known here: " + known + ")");
      }
    }
  }

 private:
  static std::string range(Real lo, Real hi, bool lo_open) {
    return std::string("allowed range ") + (lo_open ? "(" : "[") + fmt(lo) + ", " + fmt(hi) + (hi == kInf ? ")" : "]");
  }
  Real real_node(const std::string& k, Real lo, Real hi, bool lo_open) { return real_value(n_[k], key_path(k), lo, hi, lo_open); }
  Real real_value(const YAML::Node& v, const std::string& where, Real lo, Real hi, bool lo_open) const {
    Real x = 0;
    bool ok = v.IsScalar();
    if (ok) {
      try {
        x = v.as<Real>();
      } catch (const YAML::Exception&) {
        ok = false;
      }
    }
    if (!ok) fail(where, "must be a number (" + range(lo, hi, lo_open) + ")");
    if (!std::isfinite(x) || x < lo || x > hi || (lo_open && x == lo))
      fail(where, "= " + (v.IsScalar() ? v.Scalar() : fmt(x)) + " is outside the " + range(lo, hi, lo_open));
    return x;
  }

  YAML::Node n_;
  std::string path_;
  const std::string* file_;
  std::set<std::string> seen_;
};

// A key given twice in one mapping is an error: YAML wants keys unique, and yaml-cpp keeps both and looks up the
// first, so `{count: 100, count: 200}` would run 100 spheres without a word. The screen of load_yaml_screened bounds
// the nesting, and with it this recursion.
void reject_duplicate_keys(const YAML::Node& n, const std::string& where, const std::string& path) {
  if (n.IsSequence()) {
    for (size_t i = 0; i < n.size(); ++i) reject_duplicate_keys(n[i], where + "[" + std::to_string(i) + "]", path);
  } else if (n.IsMap()) {
    std::map<std::string, int> line;  // key -> its first line (1-based)
    for (auto it = n.begin(); it != n.end(); ++it) {
      const std::string k = it->first.IsScalar() ? it->first.Scalar() : "?";
      std::string at = where;
      if (!at.empty()) at += '.';
      at += k;
      const int l = it->first.Mark().line + 1;
      const auto [first, fresh] = line.emplace(k, l);
      if (!fresh) {
        std::ostringstream os;
        os << path << ": " << at << ": given twice (";
        if (first->second == l)
          os << "on line " << l;
        else
          os << "lines " << first->second << " and " << l;
        os << "); a key may appear once in its mapping";
        throw ConfigError(os.str());
      }
      reject_duplicate_keys(it->second, at, path);
    }
  }
}

}  // namespace

YAML::Node load_yaml_screened(const std::string& path) {
  YAML::Node root;
  {
    // A directory opens as a stream and fails at the first read with the C++ library's words, naming no file. A pipe
    // (`grainlab run <(sed ... base.yaml)`) or a device is read through once, but a config is read more than once
    // (which command it is for, then the config; a run copies it into its output) and its relative paths resolve
    // from its directory: the second read of a pipe found it empty. Both are refused by name.
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (fs::is_directory(st)) throw ConfigError(path + ": is a directory, not a config file");
    if (fs::exists(st) && !fs::is_regular_file(st))
      throw ConfigError(path + ": not a regular file (a pipe or a device?): a config is read more than once and its "
                        "relative paths resolve from its directory; write it to a file first");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw ConfigError(path + ": cannot open the file for reading (" + std::strerror(errno) + ")");
    // Screen the raw text before the parser sees it: yaml-cpp recurses once per nesting level without
    // a limit, so a hostile file could overflow the stack (issue 7: fuzzed configs must never crash).
    constexpr size_t kMaxBytes = 4 << 20;
    constexpr int kMaxDepth = 64;
    // At most one byte past the limit is read: /dev/zero or an endless pipe is refused, not read until memory ends.
    // Read in blocks, not into a zeroed string of the limit's size: zeroing 4 MiB touched ~1 000 fresh pages at
    // each of a command's two reads, 57 against 34 ms for a `grainlab validate` on the 2-core VM (perf/startup.sh
    // validate; a page fault costs 14-16 us there, perf/fault_cost.sh).
    std::string text;
    char block[1 << 16];
    while (text.size() <= kMaxBytes) {
      in.read(block, std::streamsize(std::min(sizeof block, kMaxBytes + 1 - text.size())));
      text.append(block, size_t(in.gcount()));
      if (!in) break;
    }
    if (in.bad()) throw ConfigError(path + ": cannot read the file (" + std::strerror(errno) + ")");
    if (text.size() > kMaxBytes) throw ConfigError(path + ": larger than 4 MiB: not a grainlab config");
    if (text.find('\0') != std::string::npos) throw ConfigError(path + ": contains NUL bytes: not a text file");
    int depth = 0, max_depth = 0;
    size_t indent = 0, max_indent = 0;
    bool line_start = true;
    char quote = 0;
    for (char ch : text) {
      if (ch == '\n') {
        line_start = true;
        indent = 0;
        quote = 0;
        continue;
      }
      if (line_start && ch == ' ') {
        max_indent = std::max(max_indent, ++indent);
        continue;
      }
      line_start = false;
      if (quote) {
        if (ch == quote) quote = 0;
      } else if (ch == '"' || ch == '\'') {
        quote = ch;
      } else if (ch == '#') {
        quote = '\n';  // comment: ignore to the end of the line
      } else if (ch == '[' || ch == '{') {
        max_depth = std::max(max_depth, ++depth);
      } else if (ch == ']' || ch == '}') {
        --depth;
      }
    }
    if (max_depth > kMaxDepth || max_indent > size_t(2) * kMaxDepth)
      throw ConfigError(path + ": nested deeper than " + std::to_string(kMaxDepth) + " levels: not a grainlab config");
    try {
      root = YAML::Load(text);
    } catch (const YAML::Exception& e) {
      std::string what = e.what();
      for (char& ch : what)
        if (ch == '\n') ch = ' ';
      // yaml-cpp's words for a tab in the indentation ("illegal map value", "end of map not found") do not name it
      if (e.mark.line >= 0) {
        std::istringstream lines(text);
        std::string line;
        for (int k = 0; k <= e.mark.line && std::getline(lines, line); ++k) {
        }
        const size_t lead = line.find_first_not_of(" \t");
        if (line.substr(0, lead).find('\t') != std::string::npos)
          what += " (a tab in the indentation of line " + std::to_string(e.mark.line + 1) +
                  ": YAML indents with spaces only)";
      }
      throw ConfigError(path + ": not valid YAML: " + what);
    } catch (const std::exception& e) {
      throw ConfigError(path + ": cannot parse: " + e.what());
    }
  }
  reject_duplicate_keys(root, "", path);
  return root;
}

namespace {
// A readable YAML mapping with this top-level key (false for anything that does not load).
bool has_top_key(const std::string& path, const char* key) {
  try {
    const YAML::Node n = load_yaml_screened(path);
    return n.IsMap() && n[key];
  } catch (const std::exception&) {
    return false;
  }
}
}  // namespace

bool is_study_file(const std::string& path) { return has_top_key(path, "base"); }

bool is_run_config_file(const std::string& path) { return has_top_key(path, "stages"); }

RunConfig load_run_config(const std::string& path) { return parse_run_config(load_yaml_screened(path), path); }

namespace {
[[noreturn]] void path_error(const std::string& where, const std::string& path, const std::string& why) {
  throw ConfigError(where + " = '" + path + "': " + why);
}
// $NAME and ${NAME} in a path replaced by the environment's values; an unset (or empty) variable is an error.
std::string expand_variables(const std::string& path, const std::string& where) {
  std::string out;
  for (size_t i = 0; i < path.size();) {
    if (path[i] != '$') {
      out += path[i++];
      continue;
    }
    const bool braced = i + 1 < path.size() && path[i + 1] == '{';
    size_t j = i + (braced ? 2 : 1), end = j;
    while (end < path.size() && (std::isalnum(static_cast<unsigned char>(path[end])) || path[end] == '_')) ++end;
    const std::string name = path.substr(j, end - j);
    const bool unclosed = braced && (end >= path.size() || path[end] != '}');
    if (name.empty() || std::isdigit(static_cast<unsigned char>(name[0])) || unclosed)
      path_error(where, path, "a $ must start an environment variable, $NAME or ${NAME}");
    const char* v = std::getenv(name.c_str());
    if (!v || !*v) path_error(where, path, "the environment variable " + name + " is not set");
    out += v;
    i = end + (braced ? 1 : 0);
  }
  return out;
}
}  // namespace

std::string expand_path(const std::string& raw, const std::string& where) {
  std::string path = expand_variables(raw, where);
  if (path.empty() || path[0] != '~') return path;
  const size_t slash = path.find('/');
  const std::string user = path.substr(1, slash == std::string::npos ? std::string::npos : slash - 1);
  const std::string rest = slash == std::string::npos ? "" : path.substr(slash);
  std::string home;
  if (user.empty()) {
    const char* h = std::getenv("HOME");
    if (h && *h) home = h;
    else if (const passwd* pw = ::getpwuid(::getuid())) home = pw->pw_dir ? pw->pw_dir : "";
    if (home.empty()) path_error(where, raw, "~ is the home directory, and HOME is not set");
  } else {
    const passwd* pw = ::getpwnam(user.c_str());
    if (!pw || !pw->pw_dir) path_error(where, raw, "no user '" + user + "' whose home ~" + user + " is");
    home = pw->pw_dir;
  }
  return home + rest;
}

RunConfig parse_run_config(const YAML::Node& root, const std::string& path) {
  RunConfig c;
  c.path = path;
  if (!root || root.IsNull()) throw ConfigError(path + ": the file is empty");
  Section top(root, "", &path);

  Section s = top.sub("sample");
  c.sample_file = expand_path(s.string("file", ""), path + ": sample.file");
  if (!c.sample_file.empty()) {
    // A saved sample brings its particles, box and densities: generation keys would be ignored, so
    // they are refused rather than silently dropped.
    for (const char* k : {"count", "D", "r_min", "r_max", "grading", "seed", "initial_solid_fraction", "density",
                          "density_scaling"})
      if (s.has(k)) s.fail(std::string("sample.") + k, "cannot be combined with sample.file (the file defines it)");
    // A relative path is relative to this config's directory. It is then made absolute, so that the resolved
    // config a run writes (its config.yaml, run.h5 attribute and checkpoint fingerprint) names the same file from
    // any working directory.
    if (c.sample_file[0] != '/') {
      const size_t slash = path.find_last_of('/');
      if (slash != std::string::npos) c.sample_file = path.substr(0, slash + 1) + c.sample_file;
    }
    std::error_code ec;
    const std::filesystem::path abs = std::filesystem::absolute(c.sample_file, ec);
    if (!ec) c.sample_file = abs.lexically_normal().string();
  }
  c.packing.count = int(s.integer("count", 3000, 1, 100000000));
  if (s.has("grading")) {
    // A sieve curve (percent passing by mass at each diameter) in place of SPEC §1's power law: it gives the sizes.
    for (const char* k : {"D", "r_min", "r_max"})
      if (s.has(k))
        s.fail(std::string("sample.") + k, "cannot be combined with sample.grading (the curve gives the sizes)");
    Section g = s.sub("grading");
    Grading& gr = c.packing.grading;
    gr.diameter = g.real_list("diameter", 2, 1000, 0, 2, true);
    gr.passing = g.real_list("passing", 2, 1000, 0, 100, false);
    g.finish();
    if (gr.passing.size() != gr.diameter.size())
      g.fail("sample.grading.passing", "has " + std::to_string(gr.passing.size()) + " values for the " +
                                           std::to_string(gr.diameter.size()) + " of sample.grading.diameter: one a sieve");
    for (size_t k = 1; k < gr.diameter.size(); ++k) {
      const std::string at = "[" + std::to_string(k) + "]";
      if (!(gr.diameter[k] > gr.diameter[k - 1]))
        g.fail("sample.grading.diameter" + at, "= " + fmt(gr.diameter[k]) + " m must be larger than the diameter "
                                                   "before it, " + fmt(gr.diameter[k - 1]) + " m (sieves from the finest up)");
      if (gr.passing[k] < gr.passing[k - 1])
        g.fail("sample.grading.passing" + at, "= " + fmt(gr.passing[k]) + " % is below the " + fmt(gr.passing[k - 1]) +
                                                  " % before it: the percent passing grows with the diameter");
    }
    if (gr.passing.front() != 0)
      g.fail("sample.grading.passing[0]", "= " + fmt(gr.passing.front()) + " % must be 0: the curve starts at the "
                                          "smallest sphere (add a sieve below it where the passing is 0)");
    if (gr.passing.back() != 100)
      g.fail("sample.grading.passing[" + std::to_string(gr.passing.size() - 1) + "]",
             "= " + fmt(gr.passing.back()) + " % must be 100: the curve ends at the largest sphere (" +
                 (gr.passing.back() == 1 ? "percent, not a fraction: 100 where the curve says 1)"
                                         : "add a sieve above it where the passing is 100)"));
    c.packing.r_min = gr.diameter.front() / 2;
    c.packing.r_max = gr.diameter.back() / 2;
  } else {
    c.packing.D = s.real("D", 3.63, 0, 10);
    c.packing.r_min = s.real("r_min", 0.2e-3, 0, 1, true);
    c.packing.r_max = s.real("r_max", 0.6e-3, 0, 1, true);
    if (c.packing.r_max < c.packing.r_min)
      s.fail("sample.r_max", "= " + fmt(c.packing.r_max) + " must be >= sample.r_min = " + fmt(c.packing.r_min));
  }
  // Seeds up to 2^53: every such integer is exact in the double the YAML number is read as.
  c.packing.seed = std::uint64_t(s.integer("seed", 1, 0, 1L << 53));
  c.packing.solid_fraction = s.real("initial_solid_fraction", 0.3, 0, 0.45, true);
  c.density = s.real("density", 2650, 0, 1e6, true);
  c.density_scaling = s.real("density_scaling", 1, 1, 1e12);
  s.finish();

  Section m = top.sub("material");
  ContactParams& cp = c.engine.contact;
  cp.E = m.real("E", 100e6, 0, 1e13, true);
  cp.kappa = m.real("kappa", 1, 0, 10);
  cp.mu = m.real("mu", 0.5, 0, 10);
  cp.mu_r = m.real("mu_r", 0, 0, 10);
  cp.roll_arm = m.real("roll_arm", 0.05, 0, 1);
  cp.normal_damping = m.real("normal_damping", 0, 0, 1, false);
  if (cp.normal_damping >= 1) m.fail("material.normal_damping", "must be < 1 (under-damped contact)");
  c.engine.E_wall = m.real("E_wall", cp.E, 0, 1e13, true);
  m.finish();

  Section n = top.sub("numerics");
  c.engine.dt_factor = n.real("dt_factor", 0.2, 0, 1, true);
  cp.dt = n.real("dt", 0, 0, 1, true);  // 0 = automatic; a value above the stable limit is refused later
  c.engine.skin = n.real("skin", 0.1e-3, 0, 1, true);
  c.engine.inner_skin = n.real("inner_skin", c.engine.inner_skin, 0, 1);
  if (c.engine.inner_skin >= 1) n.fail("numerics.inner_skin", "= " + fmt(c.engine.inner_skin) + " is outside the allowed range [0, 1) (a fraction of skin; 0 = off)");
  c.engine.damping = n.real("damping", 0.7, 0, 1);
  c.engine.servo_max_step = n.real("servo_max_step", 1e-3, 0, 1, true);
  c.health.max_overlap = n.real("max_overlap", 0.2, 0, 10, true);
  c.health.max_step_move = n.real("max_step_move", 0.5, 0, 100, true);
  c.engine.fines_mass_radius = n.real("fines_mass_radius", 0, 0, 1, false);
  n.finish();

  YAML::Node st = top.raw("stages");
  if (!st || !st.IsSequence() || st.size() == 0) top.fail("stages", "must be a non-empty list of stages");
  std::map<std::string, size_t> stage_names;
  for (size_t k = 0; k < st.size(); ++k) {
    Section g(st[k], "stages[" + std::to_string(k) + "]", &path);
    StageConfig sc;
    sc.name = g.string("name", "stage" + std::to_string(k));
    // A stage's name names its sample file (sample_<name>.h5 in the run directory) and is a field of series.csv:
    // a '/' made a path the run could not write at the stage's end (after its work), a ',' or a newline broke the
    // CSV's columns, and two stages of one name wrote one sample file over the other.
    if (sc.name.size() > 64 ||
        sc.name.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_.-") != std::string::npos)
      g.fail(g.key_path("name"), "= '" + sc.name + "': a stage name is 1 to 64 letters, digits, '_', '-' or '.' (it "
                                 "names the file sample_<name>.h5 and a column of series.csv)");
    if (const auto [it, fresh] = stage_names.emplace(sc.name, k); !fresh)
      g.fail(g.key_path("name"), "= '" + sc.name + "' is stages[" + std::to_string(it->second) +
                                     "]'s name too: each stage needs its own (it names sample_<name>.h5)");
    const std::string type = g.choice("type", "isotropic", {"isotropic", "triaxial", "cyclic"});
    sc.type = type == "isotropic" ? StageType::Isotropic : type == "triaxial" ? StageType::Triaxial : StageType::Cyclic;
    sc.mu = g.real("mu", cp.mu, 0, 10);
    sc.mu_r = g.real("mu_r", cp.mu_r, 0, 10);
    sc.damping = g.real("damping", c.engine.damping, 0, 1);
    sc.pressure = g.real("pressure", 190e3, 0, 1e10, true);
    sc.max_steps = g.integer("max_steps", 1000000, 1, 1000000000000L);
    sc.check_every = g.integer("check_every", 200, 1, 1000000000L);
    sc.servo_gain = g.real("servo_gain", 0.5, 0, 1, true);
    // The loop on an ideal wall is stable below 1 (WallControl::integral); a packing answers slower than its
    // wall contacts, so the range stops well short of it.
    sc.servo_integral = g.real("servo_integral", 0, 0, 0.5);
    if (sc.type == StageType::Isotropic) {
      sc.pressure_tolerance = g.real("pressure_tolerance", 0.01, 0, 1, true);
      sc.pressure_ramp_steps = g.integer("pressure_ramp_steps", 0, 0, 1000000000000L);
      sc.ufr_tolerance = g.real("ufr_tolerance", 0.01, 0, 1, true);
      sc.ke_tolerance = g.real("ke_tolerance", 1e-4, 0, 1, true);
      sc.target_e0 = g.real("target_e0", 0, 0, 10);
      sc.target_e0_tolerance = g.real("target_e0_tolerance", 0.003, 0, 1, true);
      sc.mu_max = g.real("mu_max", 1.0, 0, 10, true);
      sc.max_trials = int(g.integer("max_trials", 10, 2, 100));
      sc.save_sample = g.boolean("save_sample", true);
      sc.affine = g.boolean("affine", false);
    } else {
      const std::string drainage = g.choice("drainage", "undrained", {"undrained", "drained", "oedometric"});
      sc.drainage = drainage == "undrained" ? Drainage::Undrained
                    : drainage == "drained" ? Drainage::Drained
                                            : Drainage::Oedometric;
      // 0 on a triaxial stage: a rest (StageConfig::axial_strain_rate)
      sc.axial_strain_rate = g.real("axial_strain_rate", 1.0, 0, 1e6, sc.type == StageType::Cyclic);
      sc.max_axial_strain = g.real("max_axial_strain", 0.05, 0, 0.9, true);
      sc.max_servo_error = g.real("max_servo_error", 0.25, 0, 1, true);
      if (sc.type == StageType::Triaxial) {
        sc.extension = g.choice("direction", "compression", {"compression", "extension"}) == "extension";
        sc.b = g.real("b", 0, 0, 1);
        // b sets a stress: a drained compression stage's lateral servo (undrained, the walls keep the volume; in
        // extension the axial stress is the minor one, sigma_3 = sigma_z, which the axial walls' velocity sets)
        if (sc.b > 0 && (sc.drainage != Drainage::Drained || sc.extension))
          g.fail(g.key_path("b"), "= " + fmt(sc.b) + " needs a drained compression stage (here " +
                                      (sc.drainage != Drainage::Drained ? drainage_name(sc.drainage) : "direction: extension") +
                                      "); leave b out or give 0");
        const std::string stress_path =
            g.choice("stress_path", "constant_sigma3", {"constant_sigma3", "constant_p", "plane_strain"});
        sc.constant_p = stress_path == "constant_p";
        sc.plane_strain = stress_path == "plane_strain";
        // plane strain holds the x walls and servos the y walls at their start's stress (undrained: places them at
        // constant volume): a drained or undrained compression or extension (an oedometer holds both lateral axes), and
        // sigma_x is its result, which b would set
        if (sc.plane_strain && sc.drainage == Drainage::Oedometric)
          g.fail(g.key_path("stress_path"), "= plane_strain needs a drained or undrained stage (here oedometric, which "
                                            "holds both lateral axes): the x walls held, the y walls at their start's "
                                            "stress (drained) or at constant volume (undrained)");
        if (sc.plane_strain && sc.b > 0)
          g.fail(g.key_path("stress_path"), "= plane_strain holds the x walls, and b = " + fmt(sc.b) +
                                            " would servo them to sigma_3 + b (sigma_z - sigma_3): give one of them "
                                            "(plane strain's b is the test's result)");
        if (sc.constant_p && sc.drainage != Drainage::Drained)
          g.fail(g.key_path("stress_path"), "= constant_p needs a drained stage (here " + std::string(drainage_name(sc.drainage)) +
                                            ": the walls keep the volume or their place, and p' is the test's result); "
                                            "leave stress_path out or give constant_sigma3");
        // A K path (StageConfig::k_ratio): drained, and the lateral stress is its own (not b's or constant p's)
        sc.k_ratio = g.real("k_ratio", 0, 0, 1, true);
        if (g.has("k_ratio") && sc.drainage != Drainage::Drained)
          g.fail(g.key_path("k_ratio"), "= " + fmt(sc.k_ratio) + " needs a drained stage (here " +
                                            drainage_name(sc.drainage) + ": the walls keep the volume or their place); "
                                            "leave k_ratio out or give drainage: drained");
        if (g.has("k_ratio") && (sc.b > 0 || sc.constant_p || sc.plane_strain))
          g.fail(g.key_path("k_ratio"), "= " + fmt(sc.k_ratio) + " and " +
                                            (sc.b > 0 ? "b = " + fmt(sc.b) : "stress_path: " + stress_path) +
                                            " both set the lateral stresses: give one of them");
        // A linear stress path (StageConfig::lateral_slope): drained; b sets sigma_2 on it, as on the standard path.
        // [-5, 5]: every direction but those within 11 degrees of pure lateral loading or unloading in the (sigma_a,
        // sigma_r) plane (8.05 in the Rendulic plane), which the strain-controlled axial walls cannot follow (dsigma_a = 0
        // there). Or as a probe's direction in the Rendulic plane (StageConfig::stress_direction), which sets the
        // slope and the direction both.
        const bool by_angle = g.has("stress_direction");
        const std::string path_key = by_angle ? "stress_direction" : "lateral_slope";
        if (by_angle) {
          const Real th = g.real("stress_direction", 0, 0, 360), rad = th * Real(M_PI / 180);
          // 90 and 270 the standard path to the bit (cos(pi/2) is 6e-17 in double)
          const Real slope = th == 90 || th == 270 ? Real(0) : std::cos(rad) / (std::sqrt(Real(2)) * std::sin(rad));
          const bool unloading = std::sin(rad) < 0;
          if (!(std::abs(slope) <= 5))
            g.fail(g.key_path(path_key), "= " + fmt(th) + " is within 8.05 degrees of pure lateral loading or unloading (0, "
                                         "180), which the strain-controlled axial walls cannot follow (dsigma_a = 0 "
                                         "there): give a direction in [8.05, 171.95] or [188.05, 351.95]");
          if (g.has("lateral_slope"))
            g.fail(g.key_path(path_key), "= " + fmt(th) + " and lateral_slope = " + fmt(g.real("lateral_slope", 0, -5, 5)) +
                                             " both set the path: give one of them");
          if (g.has("direction") && sc.extension != unloading)
            g.fail(g.key_path(path_key), "= " + fmt(th) + " unloads the axial walls where sin(theta) < 0 and loads them "
                                         "elsewhere, and direction = " + (sc.extension ? "extension" : "compression") +
                                         " says otherwise: leave direction out");
          if (sc.b > 0)
            g.fail(g.key_path(path_key), "= " + fmt(th) + " is a direction of the Rendulic plane (sigma_x = sigma_y), and "
                                         "b = " + fmt(sc.b) + " parts sigma_x from sigma_y: give one of them");
          sc.stress_direction = th;
          sc.lateral_slope = slope;
          sc.extension = unloading;
        } else if (g.has("lateral_slope")) {
          sc.lateral_slope = g.real("lateral_slope", 0, -5, 5);
        }
        if (sc.lateral_slope) {
          const std::string v = fmt(by_angle ? *sc.stress_direction : *sc.lateral_slope);
          if (sc.drainage != Drainage::Drained) {
            std::string msg = "= " + v + " needs a drained stage (here ";
            msg.append(drainage_name(sc.drainage)).append(": the walls keep the volume or their place); leave ");
            msg.append(path_key).append(" out or give drainage: drained");
            g.fail(g.key_path(path_key), msg);
          }
          if (sc.constant_p || sc.plane_strain || sc.k_ratio > 0)
            g.fail(g.key_path(path_key), "= " + v + " and " +
                                             (sc.k_ratio > 0 ? "k_ratio = " + fmt(sc.k_ratio)
                                                             : "stress_path: " + stress_path) +
                                             " both set the lateral stresses: give one of them (constant p' is "
                                             "lateral_slope: -0.5)");
        }
        // An oedometer's stress ends: sigma_v loading or unloading to a stress, ocr unloading to sigma_v,max / ocr;
        // a K path's and a linear path's too (its sigma_v is what it is loaded to, as an oedometer's)
        sc.sigma_v = g.real("sigma_v", 0, 0, 1e10, true);
        sc.ocr = g.real("ocr", 0, 1, 1e6, true);
        for (const char* key : {"sigma_v", "ocr"})
          if (g.has(key) && sc.drainage != Drainage::Oedometric && !(sc.k_ratio > 0) && !sc.lateral_slope)
            g.fail(g.key_path(key), std::string("ends an oedometric stage, a K path (k_ratio) or a linear path "
                                                "(lateral_slope) at a vertical stress, and this stage is ") +
                                        drainage_name(sc.drainage) + " (give drainage: oedometric, or k_ratio, or "
                                        "lateral_slope, or leave " + key + " out and end the stage at max_axial_strain)");
        if (g.has("ocr") && k == 0)
          g.fail(g.key_path("ocr"), "= " + fmt(sc.ocr) + " unloads to sigma_v,max / ocr, sigma_v,max the largest of the "
                                    "stages before, and this is the first stage: give sigma_v");
        // A deviator end, any drainage (a drained loading's unload-reload loop, an undrained shear to a q)
        // or at a stress ratio q/p': in [-1.5, 3], the range of triaxial stress states with sigma_3 >= 0 (q/p' = 3 at
        // sigma_x = sigma_y = 0, -1.5 at sigma_z = 0)
        if (g.has("q")) sc.q_end = g.real("q", 0, -1e10, 1e10);
        if (g.has("stress_ratio")) sc.eta_end = g.real("stress_ratio", 0, -1.5, 3);
        // a stress probe's end: the size of the stress increment from the start (StageConfig::dsigma_end)
        if (g.has("stress_increment")) sc.dsigma_end = g.real("stress_increment", 0, 0, 1e10, true);
        std::vector<std::string> ends;  // the stress ends given, "key = value"
        for (const auto& [key, v] : {std::pair<const char*, Real>{"sigma_v", sc.sigma_v}, {"ocr", sc.ocr},
                                     {"q", sc.q_end.value_or(0)}, {"stress_ratio", sc.eta_end.value_or(0)},
                                     {"stress_increment", sc.dsigma_end.value_or(0)}})
          if (g.has(key)) ends.push_back(std::string(key) + " = " + fmt(v));
        if (ends.size() > 1)
          g.fail(g.key_path(ends[0].substr(0, ends[0].find(' '))), ends[0].substr(ends[0].find(' ') + 1) + " and " + ends[1] +
                                                                      " both end the stage at a stress: give one of them");
        // A rest holds the axial walls and ends at max_steps: nothing moves the stress along a path to an end
        if (sc.axial_strain_rate == 0) {
          std::string moving;
          for (const char* key : {"sigma_v", "ocr", "q", "stress_ratio", "stress_increment", "lateral_slope",
                                  "stress_direction", "k_ratio", "stress_path"})
            if (g.has(key) && moving.empty()) moving = key;
          if (sc.b > 0) moving = "b";
          // its length is max_steps: not left to the 1e6 default meant as a cap
          if (!g.has("max_steps"))
            g.fail(g.key_path("axial_strain_rate"), "= 0 is a rest (the axial walls held, the lateral ones as the "
                                                     "drainage holds them, for max_steps steps): give max_steps, its length");
          if (!moving.empty()) {
            std::string msg = "= 0 is a rest (the axial walls held, the lateral ones as the drainage holds them, for "
                              "max_steps steps), and ";
            msg.append(moving).append(" moves the stress or ends the stage at one: leave ").append(moving);
            msg.append(" out, or give the stage a rate");
            g.fail(g.key_path("axial_strain_rate"), msg);
          }
        }
        if (g.has("ocr") && !sc.extension)
          g.fail(g.key_path("ocr"), "= " + fmt(sc.ocr) + " ends an unloading at sigma_v,max / ocr, and this stage loads "
                                    "(direction: compression): give direction: extension, or sigma_v to load to a stress");
      }
      if (sc.type == StageType::Cyclic) {
        sc.cycles = g.integer("cycles", 1, 1, 1000000);
        sc.q_amplitude = g.real("q_amplitude", 0, 0, 1e10);
        sc.csr = g.real("csr", 0, 0, 10);
        sc.strain_amplitude = g.real("strain_amplitude", 0, 0, 0.9);
        sc.sigma_v_amplitude = g.real("sigma_v_amplitude", 0, 0, 1e10);
        sc.liquefaction_ru = g.real("liquefaction_ru", 0.95, 0, 1, true);
        sc.liquefaction_da_strain = g.real("liquefaction_da_strain", 0.05, 0, 1.8, true);
        std::string amps;  // the amplitudes given
        for (const auto& [key, v] : {std::pair<const char*, Real>{"q_amplitude", sc.q_amplitude}, {"csr", sc.csr},
                                     {"strain_amplitude", sc.strain_amplitude}, {"sigma_v_amplitude", sc.sigma_v_amplitude}})
          if (v > 0) amps += (amps.empty() ? "" : " and ") + std::string(key);
        // The cyclic oedometer's controlled stress is the vertical one (q follows from the lateral stress the held
        // walls take), and a triaxial cycle's is q (sigma_v_amplitude would be q_amplitude under a constant sigma_3)
        const bool oedometric = sc.drainage == Drainage::Oedometric;
        if (oedometric && (sc.q_amplitude > 0 || sc.csr > 0))
          g.fail(g.key_path(sc.q_amplitude > 0 ? "q_amplitude" : "csr"),
                 "reverses a triaxial cycle at a deviator stress, and this stage is oedometric (its lateral walls held): "
                 "an oedometric cycle reverses at sigma_v_amplitude (Pa, > 0: sigma_v,0 +- A) or strain_amplitude");
        if (!oedometric && sc.sigma_v_amplitude > 0)
          g.fail(g.key_path("sigma_v_amplitude"), "= " + fmt(sc.sigma_v_amplitude) + " reverses an oedometric cycle, and "
                 "this stage is " + drainage_name(sc.drainage) + ": give drainage: oedometric, or q_amplitude / csr for "
                 "a triaxial cycle");
        if (oedometric && (amps.empty() || amps.find(" and ") != std::string::npos))
          g.fail(g.key_path("sigma_v_amplitude"), "an oedometric cyclic stage reverses at exactly one of sigma_v_amplitude "
                 "(Pa, > 0: sigma_v,0 +- A) or strain_amplitude (> 0: strain reversal); this one gives " +
                 (amps.empty() ? std::string("neither") : amps));
        // sigma_v,0 - A must stay a compression: where the stage before says what sigma_v,0 is (an oedometric loading
        // to a sigma_v, an isotropic stage's pressure); the run checks it at the stage's start otherwise
        if (sc.sigma_v_amplitude > 0 && !c.stages.empty()) {
          const StageConfig& prev = c.stages.back();
          const bool known = prev.type == StageType::Isotropic ||
                             (prev.type == StageType::Triaxial && prev.drainage == Drainage::Oedometric && prev.sigma_v > 0);
          const Real sv0 = prev.type == StageType::Isotropic ? prev.pressure : prev.sigma_v;
          if (known && sc.sigma_v_amplitude >= sv0)
            g.fail(g.key_path("sigma_v_amplitude"), "= " + fmt(sc.sigma_v_amplitude) + " must be below the vertical stress the "
                   "cycles start from, " + fmt(sv0) + " Pa (stages[" + std::to_string(k - 1) + "]'s " +
                   (prev.type == StageType::Isotropic ? "pressure" : "sigma_v") + "): sigma_v,0 - A would be no compression");
        }
        if (amps.empty() || amps.find(" and ") != std::string::npos)
          g.fail(g.key_path("q_amplitude"), "a cyclic stage reverses at exactly one of q_amplitude (Pa, > 0: stress reversal), "
                                     "csr (> 0: stress reversal at q_0 +- 2 csr p'_c) or strain_amplitude (> 0: strain "
                                     "reversal); this one gives " + (amps.empty() ? std::string("neither") : amps));
        if (sc.strain_amplitude >= sc.max_axial_strain)
          g.fail(g.key_path("strain_amplitude"), "= " + fmt(sc.strain_amplitude) + " must be below max_axial_strain = " +
                                              fmt(sc.max_axial_strain) + " (the stage would end at the first peak)");
        // given, it must be reachable; the default that is not is a warning of the plan (plan_run)
        if (g.has("liquefaction_da_strain") && sc.liquefaction_da_strain >= 2 * sc.max_axial_strain)
          g.fail(g.key_path("liquefaction_da_strain"),
                 "= " + fmt(sc.liquefaction_da_strain) + " must be below 2 max_axial_strain = " +
                     fmt(2 * sc.max_axial_strain) + " (|eps_a| stays below max_axial_strain, so no half cycle spans more)");
      }
    }
    g.finish();
    c.stages.push_back(sc);
  }

  Section o = top.sub("output");
  c.out_dir = expand_path(o.string("dir", "runs/" + [&] {
    std::string b = path.substr(path.find_last_of('/') + 1);
    return b.substr(0, b.find_last_of('.'));
  }()), path + ": output.dir");
  c.output_every = o.integer("every", 1000, 1, 1000000000000L);
  c.snapshot_strain = o.real("snapshot_strain", 0.01, 0, 1);
  c.checkpoint_every = o.integer("checkpoint_every", 100000, 0, 1000000000000L);
  c.checkpoint_minutes = o.real("checkpoint_minutes", 10, 0, 1e6);
  c.keep_checkpoints = int(o.integer("keep_checkpoints", 2, 1, 1000));
  o.finish();
  top.finish();
  return c;
}

std::string yaml_number(double v) {
  char buf[40];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);  // shortest that reads back bitwise (C++17)
  std::string t(buf, res.ptr);
  const size_t exp = t.find('e');
  if (exp != std::string::npos && t.find('.') == std::string::npos) t.insert(exp, ".0");
  return t;
}

namespace {
// yaml-cpp's emitter writes every double at one fixed precision (17 digits: "0.29999999999999999" for 0.3);
// this one writes them as yaml_number and passes everything else on.
class NumberEmitter {
 public:
  template <class T>
  NumberEmitter& operator<<(const T& v) {
    if constexpr (std::is_floating_point_v<T>)
      e_ << yaml_number(v);
    else
      e_ << v;
    return *this;
  }
  const char* c_str() const { return e_.c_str(); }

 private:
  YAML::Emitter e_;
};
}  // namespace

std::string resolved_config_yaml(const RunConfig& c) {
  NumberEmitter e;
  e << YAML::BeginMap;
  e << YAML::Key << "sample" << YAML::Value << YAML::BeginMap;
  if (!c.sample_file.empty()) {
    e << YAML::Key << "file" << YAML::Value << c.sample_file;
  } else {
    e << YAML::Key << "count" << YAML::Value << c.packing.count;
    if (c.packing.grading.empty()) {
      e << YAML::Key << "D" << YAML::Value << c.packing.D << YAML::Key << "r_min" << YAML::Value << c.packing.r_min
        << YAML::Key << "r_max" << YAML::Value << c.packing.r_max;
    } else {
      e << YAML::Key << "grading" << YAML::Value << YAML::BeginMap;
      e << YAML::Key << "diameter" << YAML::Value << YAML::Flow << YAML::BeginSeq;
      for (Real d : c.packing.grading.diameter) e << d;
      e << YAML::EndSeq << YAML::Key << "passing" << YAML::Value << YAML::Flow << YAML::BeginSeq;
      for (Real p : c.packing.grading.passing) e << p;
      e << YAML::EndSeq << YAML::EndMap;
    }
    e << YAML::Key << "seed" << YAML::Value << c.packing.seed << YAML::Key
      << "initial_solid_fraction" << YAML::Value << c.packing.solid_fraction << YAML::Key << "density"
      << YAML::Value << c.density << YAML::Key << "density_scaling" << YAML::Value << c.density_scaling;
  }
  e << YAML::EndMap;
  const ContactParams& cp = c.engine.contact;
  e << YAML::Key << "material" << YAML::Value << YAML::BeginMap << YAML::Key << "E" << YAML::Value << cp.E
    << YAML::Key << "kappa" << YAML::Value << cp.kappa << YAML::Key << "mu" << YAML::Value << cp.mu << YAML::Key
    << "mu_r" << YAML::Value << cp.mu_r << YAML::Key << "roll_arm" << YAML::Value << cp.roll_arm << YAML::Key
    << "normal_damping" << YAML::Value << cp.normal_damping << YAML::Key << "E_wall" << YAML::Value
    << c.engine.E_wall << YAML::EndMap;
  e << YAML::Key << "numerics" << YAML::Value << YAML::BeginMap << YAML::Key << "dt_factor" << YAML::Value
    << c.engine.dt_factor;
  if (cp.dt > 0) e << YAML::Key << "dt" << YAML::Value << cp.dt;
  e << YAML::Key << "skin" << YAML::Value << c.engine.skin << YAML::Key << "inner_skin" << YAML::Value
    << c.engine.inner_skin << YAML::Key << "damping" << YAML::Value
    << c.engine.damping << YAML::Key << "servo_max_step" << YAML::Value << c.engine.servo_max_step << YAML::Key << "max_overlap"
    << YAML::Value << c.health.max_overlap << YAML::Key << "max_step_move" << YAML::Value << c.health.max_step_move;
  // written only where set, as dt: the resolved config of a run without it reads as every earlier build's
  if (c.engine.fines_mass_radius > 0) e << YAML::Key << "fines_mass_radius" << YAML::Value << c.engine.fines_mass_radius;
  e << YAML::EndMap;
  e << YAML::Key << "stages" << YAML::Value << YAML::BeginSeq;
  for (const StageConfig& sc : c.stages) {
    e << YAML::BeginMap << YAML::Key << "name" << YAML::Value << sc.name << YAML::Key << "type" << YAML::Value
      << (sc.type == StageType::Isotropic ? "isotropic" : sc.type == StageType::Triaxial ? "triaxial" : "cyclic")
      << YAML::Key << "mu" << YAML::Value << sc.mu << YAML::Key << "mu_r" << YAML::Value << sc.mu_r << YAML::Key << "damping" << YAML::Value << sc.damping
      << YAML::Key << "max_steps" << YAML::Value << sc.max_steps << YAML::Key << "check_every" << YAML::Value
      << sc.check_every << YAML::Key << "servo_gain" << YAML::Value << sc.servo_gain;
    if (sc.servo_integral > 0) e << YAML::Key << "servo_integral" << YAML::Value << sc.servo_integral;
    if (sc.type == StageType::Isotropic) {
      e << YAML::Key << "pressure" << YAML::Value << sc.pressure << YAML::Key << "pressure_ramp_steps" << YAML::Value
        << sc.pressure_ramp_steps << YAML::Key << "pressure_tolerance" << YAML::Value << sc.pressure_tolerance
        << YAML::Key << "ufr_tolerance" << YAML::Value << sc.ufr_tolerance << YAML::Key
        << "ke_tolerance" << YAML::Value << sc.ke_tolerance << YAML::Key << "save_sample" << YAML::Value
        << sc.save_sample;
      if (sc.affine) e << YAML::Key << "affine" << YAML::Value << true;  // written only when on: older runs' configs stay as they were
      if (sc.target_e0 > 0)
        e << YAML::Key << "target_e0" << YAML::Value << sc.target_e0 << YAML::Key << "target_e0_tolerance"
          << YAML::Value << sc.target_e0_tolerance << YAML::Key << "mu_max" << YAML::Value << sc.mu_max << YAML::Key
          << "max_trials" << YAML::Value << sc.max_trials;
    } else {
      e << YAML::Key << "drainage" << YAML::Value << drainage_name(sc.drainage)
        << YAML::Key << "axial_strain_rate" << YAML::Value << sc.axial_strain_rate << YAML::Key
        << "max_axial_strain" << YAML::Value << sc.max_axial_strain << YAML::Key << "max_servo_error" << YAML::Value
        << sc.max_servo_error;
      if (sc.type == StageType::Triaxial)
        e << YAML::Key << "direction" << YAML::Value << (sc.extension ? "extension" : "compression") << YAML::Key << "b"
          << YAML::Value << sc.b;
      if (sc.constant_p) e << YAML::Key << "stress_path" << YAML::Value << "constant_p";
      if (sc.plane_strain) e << YAML::Key << "stress_path" << YAML::Value << "plane_strain";
      if (sc.k_ratio > 0) e << YAML::Key << "k_ratio" << YAML::Value << sc.k_ratio;
      if (sc.stress_direction) e << YAML::Key << "stress_direction" << YAML::Value << *sc.stress_direction;
      else if (sc.lateral_slope) e << YAML::Key << "lateral_slope" << YAML::Value << *sc.lateral_slope;
      // only where set, as affine: the configs of runs without them stay as they were (resume compares them)
      if (sc.sigma_v > 0) e << YAML::Key << "sigma_v" << YAML::Value << sc.sigma_v;
      if (sc.ocr > 0) e << YAML::Key << "ocr" << YAML::Value << sc.ocr;
      if (sc.q_end) e << YAML::Key << "q" << YAML::Value << *sc.q_end;
      if (sc.eta_end) e << YAML::Key << "stress_ratio" << YAML::Value << *sc.eta_end;
      if (sc.dsigma_end) e << YAML::Key << "stress_increment" << YAML::Value << *sc.dsigma_end;
      if (sc.type == StageType::Cyclic) {
        e << YAML::Key << "cycles" << YAML::Value << sc.cycles;
        if (sc.q_amplitude > 0) e << YAML::Key << "q_amplitude" << YAML::Value << sc.q_amplitude;
        else if (sc.csr > 0) e << YAML::Key << "csr" << YAML::Value << sc.csr;
        else if (sc.sigma_v_amplitude > 0) e << YAML::Key << "sigma_v_amplitude" << YAML::Value << sc.sigma_v_amplitude;
        else e << YAML::Key << "strain_amplitude" << YAML::Value << sc.strain_amplitude;
        e << YAML::Key << "liquefaction_ru" << YAML::Value << sc.liquefaction_ru << YAML::Key << "liquefaction_da_strain"
          << YAML::Value << sc.liquefaction_da_strain;
      }
    }
    e << YAML::EndMap;
  }
  e << YAML::EndSeq;
  e << YAML::Key << "output" << YAML::Value << YAML::BeginMap << YAML::Key << "dir" << YAML::Value << c.out_dir
    << YAML::Key << "every" << YAML::Value << c.output_every << YAML::Key << "snapshot_strain" << YAML::Value
    << c.snapshot_strain << YAML::Key << "checkpoint_every" << YAML::Value << c.checkpoint_every << YAML::Key
    << "checkpoint_minutes" << YAML::Value << c.checkpoint_minutes << YAML::Key << "keep_checkpoints" << YAML::Value
    << c.keep_checkpoints << YAML::EndMap;
  e << YAML::EndMap;
  return std::string(e.c_str()) + "\n";
}

}  // namespace grainlab
