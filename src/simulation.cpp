#include "simulation.hpp"

#include <fcntl.h>
#include <sched.h>
#include <sys/file.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <algorithm>
#include <chrono>
#include <cctype>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <limits>
#include <optional>
#include <set>
#include <sstream>
#include <utility>

#include <yaml-cpp/yaml.h>

#include "cycle_loop.hpp"
#include "h5io.hpp"
#include "rate_decay.hpp"

#if defined(KOKKOS_ENABLE_CUDA)
#include <cuda_runtime_api.h>  // cudaMemGetInfo: the memory check of a run on the GPU (require_memory)
#endif

namespace grainlab {
namespace fs = std::filesystem;

namespace {
volatile std::sig_atomic_t g_stop = 0, g_pipe_closed = 0, g_checkpoint = 0;
extern "C" void on_stop_signal(int sig) {
  g_stop = 1;
  if (sig == SIGPIPE) g_pipe_closed = 1;
}
extern "C" void on_checkpoint_signal(int) { g_checkpoint = 1; }

// Handlers for the life of a run, the previous ones restored after: Ctrl-C, SIGTERM (a batch system's stop, a
// study's), SIGHUP (the terminal or SSH session closed) and SIGPIPE (the reader of the console lines gone: `| tee`
// killed, `| head`) stop the run at the next step boundary with a checkpoint; by default SIGPIPE killed the run at
// its next progress line with nothing saved since the last checkpoint. A SIGHUP or SIGPIPE the caller ignores
// (nohup) stays ignored. Once the pipe has closed, SIGPIPE stays ignored: any line still written after the run
// (its buffered output, at exit) must not kill the process between the checkpoint and the exit code.
// SIGUSR1 asks for a checkpoint at the next step boundary, and the run goes on: a batch system's warning before its
// time limit (SLURM `--signal=B:USR1@300`, which a study passes to its jobs), where SIGUSR1's default action ended the
// run with nothing saved since its last checkpoint. The limit's SIGTERM then stops the run with a checkpoint as ever.
struct SignalGuard {
  using Handler = void (*)(int);
  Handler old_int, old_term, old_hup, old_pipe, old_usr1;
  SignalGuard() {
    g_stop = 0;
    g_pipe_closed = 0;
    g_checkpoint = 0;
    old_usr1 = std::signal(SIGUSR1, on_checkpoint_signal);
    if (old_usr1 == SIG_IGN) std::signal(SIGUSR1, SIG_IGN);
    sigset_t usr1;  // a study's job starts with it blocked (study.cpp, StudySignals::reset_in_child): one sent meanwhile
    sigemptyset(&usr1);  // arrives now
    sigaddset(&usr1, SIGUSR1);
    sigprocmask(SIG_UNBLOCK, &usr1, nullptr);
    old_int = std::signal(SIGINT, on_stop_signal);
    old_term = std::signal(SIGTERM, on_stop_signal);
    old_hup = std::signal(SIGHUP, on_stop_signal);
    if (old_hup == SIG_IGN) std::signal(SIGHUP, SIG_IGN);
    old_pipe = std::signal(SIGPIPE, on_stop_signal);
    if (old_pipe == SIG_IGN) std::signal(SIGPIPE, SIG_IGN);
  }
  ~SignalGuard() {
    std::signal(SIGINT, old_int);
    std::signal(SIGTERM, old_term);
    std::signal(SIGHUP, old_hup);
    std::signal(SIGPIPE, g_pipe_closed ? SIG_IGN : old_pipe);
    std::signal(SIGUSR1, old_usr1);
  }
  SignalGuard(const SignalGuard&) = delete;
  SignalGuard& operator=(const SignalGuard&) = delete;
};
}  // namespace

void write_file_atomic(const std::string& path, const std::string& content) {
  const std::string tmp = temp_name(path);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(path + ": cannot write (directory missing or not writable)");
    out << content;
    out.flush();
    if (!out) {
      out.close();
      std::remove(tmp.c_str());
      throw std::runtime_error(path + ": write failed (disk full?); the previous file is untouched");
    }
  }
  commit_atomic(tmp, path);
}

std::string json_string(const std::string& s) {
  std::string o = "\"";
  for (const char ch : s) {
    if (ch == '"' || ch == '\\') {
      o += '\\';
      o += ch;
    } else if (static_cast<unsigned char>(ch) < 0x20) {
      char u[8];
      std::snprintf(u, sizeof(u), "\\u%04x", unsigned(static_cast<unsigned char>(ch)));
      o += u;
    } else {
      o += ch;
    }
  }
  return o + "\"";
}

const std::vector<std::pair<std::string, std::string>>& series_columns() {
  static const std::vector<std::pair<std::string, std::string>> cols = {
      {"time", "s"},           {"step", "-"},           {"eps_a", "-"},          {"eps_v", "-"},
      {"e", "-"},              {"p", "Pa"},             {"q", "Pa"},             {"u", "Pa"},
      {"sigma_x", "Pa"},       {"sigma_y", "Pa"},       {"sigma_z", "Pa"},       {"z", "-"},
      {"kinetic_energy", "J"}, {"ke_ratio", "-"},       {"ufr", "-"},            {"inertial_number", "-"},
      {"sliding_frac", "-"},   {"rolling_sliding_frac", "-"}, {"dt", "s"},       {"density_scaling", "-"},
      // SPEC §7 descriptors (kernels/analysis.hpp)
      {"p_contacts", "Pa"},    {"q_contacts", "Pa"},    {"p_contacts_walls", "Pa"}, {"q_p", "-"},
      {"a_c", "-"},            {"a_d", "-"},            {"a_n", "-"},            {"a_t", "-"},
      {"a_c_strong", "-"},     {"a_d_strong", "-"},     {"a_n_strong", "-"},     {"a_t_strong", "-"},
      {"a_c_weak", "-"},       {"a_d_weak", "-"},       {"a_n_weak", "-"},       {"a_t_weak", "-"},
      {"sff", "-"},            {"sff_share_c", "-"},    {"sff_share_d", "-"},    {"sff_share_n", "-"},
      {"sff_share_t", "-"},    {"z_mech", "-"},         {"f_mean", "N"},         {"weak_frac", "-"},
      {"sliding_weak_frac", "-"}, {"mu", "-"},          {"mu_r", "-"},          {"stage_type", "-"},
      // model quality: the deepest sphere-sphere overlap, delta / min(r_i, r_j), the quantity that
      // numerics.max_overlap bounds (a rising trend warns before the health check stops a run)
      {"overlap_max", "-"},
      // cyclic stages: the cycle number N, continuous (Laboratory::cycle_number); 0 in other stages
      {"cycle", "-"},
      // ke_ratio about the skeleton's best-fit affine motion (Diagnostics::kinetic_fluct): the quasi-static measure
      // of a shear, whose walls deform the specimen as a whole (ke_ratio counts that motion too)
      {"ke_fluct_ratio", "-"},
      // the void ratio of the interior (Laboratory::inner_void_ratio): e of the whole box counts the looser layer
      // along the flat walls, whose share falls as count^(-1/3) (configs/size-study.yaml)
      {"e_inner", "-"},
      // q of the contact stress with the sphere-wall contacts (p_contacts_walls' q), and the interior's stress
      // (Laboratory::inner_stress, the box of e_inner): the boundary layer's share of the measured stress
      {"q_contacts_walls", "Pa"},
      {"p_inner", "Pa"},
      {"q_inner", "Pa"},
      // the local damping's drag on the walls' stress (Laboratory::drag_stress): p and q of the walls (series p, q)
      // less these are what the contacts and the spheres' inertia carry; 0 without damping
      {"p_drag", "Pa"},
      {"q_drag", "Pa"},
      // each lateral axis's strain (Laboratory::measure; eps_r is their mean as a cell measures it): a true-triaxial
      // shear's intermediate strain, for its flow direction in the deviatoric plane
      {"eps_x", "-"},
      {"eps_y", "-"},
  };
  return cols;
}

namespace {
// The position of a column by its name: in the series (series_columns()), in cycles.csv (cycle_columns()).
size_t column_of(const std::vector<std::pair<std::string, std::string>>& cols, const char* name) {
  return size_t(std::find_if(cols.begin(), cols.end(), [&](const auto& c) { return c.first == name; }) - cols.begin());
}
size_t series_column(const char* name) { return column_of(series_columns(), name); }
}  // namespace

// cycles.csv: one row per completed cycle of a cyclic stage (CycleLoop): the loop's extremes, its equivalent
// modulus and damping ratio, p' and eps_v at its end, its largest r_u; then the extremes of the shear strain
// gamma = eps_a - eps_r and the equivalent shear modulus G_eq; then `complete`: 1 for a whole cycle, 0 for the part of
// one that a stage ended in (it reached max_axial_strain, as a liquefying sample does, or max_steps): that last
// loop's extremes, moduli, p', eps_v and r_u as far as it went, its damping NaN (an open path has no loop area);
// then E_eq and D of the walls' q less the local damping's drag (CycleLoop; equal to E_eq and D without damping);
// then the walls' vertical stress sigma_v = sigma_z: its extremes, the constrained modulus M_eq and the damping ratio
// D_v of its loop (CycleLoop: the cyclic oedometer's, its area about the cycle's first sigma_v), both less the drag
// (the drag's sigma_z share, as q's), and K =
// sigma_h / sigma_v at the row's instant, sigma_h = (sigma_x + sigma_y) / 2 (at the end of an oedometric cycle, sigma_v
// back at sigma_v,0: the coefficient of earth pressure the cycles leave). Each group after the columns of older builds, so that a script that reads them by position still does.
const std::vector<std::pair<std::string, std::string>>& cycle_columns() {
  static const std::vector<std::pair<std::string, std::string>> cols = {
      {"cycle", "-"},   {"step", "-"},     {"q_max", "Pa"}, {"q_min", "Pa"},   {"eps_a_max", "-"}, {"eps_a_min", "-"},
      {"E_eq", "Pa"},   {"damping", "-"},  {"p", "Pa"},     {"eps_v", "-"},    {"r_u_max", "-"},
      {"gamma_max", "-"}, {"gamma_min", "-"}, {"G_eq", "Pa"}, {"complete", "-"},
      {"E_eq_less_drag", "Pa"}, {"damping_less_drag", "-"},
      {"sigma_v_max", "Pa"}, {"sigma_v_min", "Pa"}, {"M_eq", "Pa"}, {"damping_v", "-"}, {"M_eq_less_drag", "Pa"},
      {"damping_v_less_drag", "-"}, {"K", "-"}};
  return cols;
}
// cycles.csv's columns in builds before gamma_max, before `complete` (their checkpoints hold rows this long; every
// row they hold is a whole cycle: they wrote no other), before the loops less the drag, and before sigma_v's loop
// (those unknown: NaN)
constexpr size_t kCycleColumnsNoShear = 11, kCycleColumnsNoComplete = 14, kCycleColumnsNoDrag = 15,
                 kCycleColumnsNoSigmaV = 17;
constexpr size_t kCycleComplete = kCycleColumnsNoComplete;  // the index of `complete`: the first column after those

namespace {

// The contacts' mean overlap, a fraction of the pair radius, of a packing at pressure p (plan_run, where it is argued):
// 4 pi p / (Z phi E) with Z phi ~ 3.6.
double mean_overlap_estimate(double p, double E) { return 4 * M_PI * p / (3.6 * E); }
// An isotropic stage whose walls measure this share of its pressure has reached it: its walls hold still, and a deep
// overlap then comes from the load, not from how fast it was applied (Laboratory::assert_healthy).
constexpr double kPressureReached = 0.9;

// x rounded up to two significant digits, as an integer (23 995 -> 24 000): a step count advised in a message.
long round_up_2(double x) {
  if (!(x > 0)) return 0;
  const double unit = std::pow(10.0, std::max(0.0, std::floor(std::log10(x)) - 1));
  return long(std::ceil(x / unit - 1e-9) * unit);
}

// ------------------------------------------------------------------------------------------------
// Series: numeric columns plus the stage of each row; the series (series_columns), or a cyclic stage's cycles
// (cycle_columns). Rows are appended (rows, stage); drop_last() is the one way to remove one.
struct Series {
  explicit Series(const std::vector<std::pair<std::string, std::string>>* cols = &series_columns()) : columns(cols) {}
  const std::vector<std::pair<std::string, std::string>>* columns;
  std::vector<std::vector<double>> rows;
  std::vector<int> stage;
  // csv() is written out every flush (Laboratory::flush_outputs), the whole file each time (atomic rewrite): it
  // formats each row once and keeps the text, so a run with N rows formats N rows, not N^2 / 40 of them (configs/quick.yaml
  // at output.every 10, 8 170 rows, took 70 s against 16 s at every 1000, most of it in printf; perf/output_every.sh).
  std::string csv(const std::vector<StageConfig>& stages) const {
    if (text_rows_ > rows.size() || text_.empty()) {
      std::ostringstream os;
      os << "stage";
      for (auto& c : *columns) os << ',' << c.first;
      os << '\n';
      text_ = os.str();
      text_rows_ = 0;
    }
    std::vector<bool> whole;  // integer columns, printed without a decimal point
    for (auto& c : *columns)
      whole.push_back(c.first == "step" ||
                      (columns == &cycle_columns() && (c.first == "cycle" || c.first == "complete")));
    std::ostringstream os;
    os << std::setprecision(12);
    for (size_t r = text_rows_; r < rows.size(); ++r) {
      os << stages[stage[r]].name;
      for (size_t c = 0; c < whole.size(); ++c) {
        os << ',';
        if (whole[c]) os << long(rows[r][c]);
        else os << rows[r][c];
      }
      os << '\n';
    }
    text_ += os.str();
    text_rows_ = rows.size();
    return text_;
  }
  void drop_last() {
    rows.pop_back();
    stage.pop_back();
    text_.clear();  // its text is in the cache: csv() formats the rows afresh
  }
  std::vector<double> column(size_t c) const {
    std::vector<double> v;
    for (auto& r : rows) v.push_back(r[c]);
    return v;
  }
  std::vector<double> flat() const {
    std::vector<double> v;
    for (auto& r : rows) v.insert(v.end(), r.begin(), r.end());
    return v;
  }

 private:
  // the text of the first text_rows_ rows, empty before the first csv() and after drop_last()
  mutable std::string text_;
  mutable size_t text_rows_ = 0;
};

// The driver's own state: everything besides the engine that a resumed run needs.
struct Lab {
  int stage = 0;
  long stage_step = 0;
  bool started = false;
  Real H0 = 0, V0 = 0, p0 = 0, aspect = 1, mu = 0;
  Real last_eps = 0, last_time = 0;  // for the measured strain rate (inertial number)
  int snapshots = 0;
  Real next_snap_eps = 0;
  std::vector<Real> trial_mu, trial_e;  // target_e0 search
  bool searching = false;
  long half_cycles = 0;  // cyclic stage: load reversals so far
  Real cycle = 0;        // cyclic stage: the cycle number of the last series row (it never decreases)
  // cyclic stage, the liquefaction criteria (Laboratory::watch_cycle): eps_a at the last load reversal (the
  // stage's start before the first), and the cycle number N at which each criterion was first met (-1: not yet)
  Real eps_turn = 0, n_ru = -1, n_da = -1;
  // A shear's q at its start where it starts from an anisotropic stress (Laboratory::start_stage), else 0
  Real q0 = 0;
  // The x walls' distance at the stage's start: with H0 and V0 the widths the lateral strains eps_x, eps_y count from
  // (NaN: a stage resumed from a checkpoint of a build before them, whose rows then did not measure them)
  Real Wx0 = 0;
  // sigma'_y at the stage's start: an undrained plane-strain stage's cell pressure acts on the y faces alone, so its u
  // is u_0 + sy0 - sigma'_y (Laboratory::measure; 0 at the start, as SPEC's is)
  Real sy0 = 0;
  // An undrained stage right after an undrained one (a post-cyclic shear, the next amplitude of a staged cyclic
  // test): the excess pore pressure it starts with, that stage's u at its end (no drainage in between; else 0), and
  // the effective mean stress the undrained loading began from, p'_c, r_u's reference (else p'_0)
  Real u0 = 0, pc = 0;
  CycleLoop loop;  // cyclic stage: the cycle under way (Laboratory::watch_cycle)
  Series cycles{&cycle_columns()};
  Series series;
  std::vector<StageResult> results;
  std::vector<std::string> snapshot_files;
  std::vector<double> snapshot_time, snapshot_eps;

  std::vector<double> scalars() const {
    return {double(stage), double(stage_step), double(started), H0, V0, p0, aspect, mu, last_eps, last_time,
            double(snapshots), next_snap_eps, double(searching), double(half_cycles), cycle, eps_turn, n_ru, n_da,
            q0, u0, pc, Wx0, sy0};
  }
  void set_scalars(const std::vector<double>& s) {
    // 13: a checkpoint from before cyclic stages (none of its stages is cyclic); 15: from before the liquefaction
    // criteria (a cyclic stage resumed from one records them from the resumed step on); 18: from before q0 (its
    // stages all started as SPEC §6.3's, from q0 = 0); 19: from before u0 and p'_c (its undrained stages each
    // counted u and r_u from their own start: u0 = 0, p'_c = p'_0); 21: from before eps_x and eps_y (Wx0 unknown: the
    // running stage's rows have NaN for them, the next stage's start measures it; nothing else reads it); 22: from
    // before sy0 (no build before it had undrained plane strain, its only reader: p'_0 - q_0/3, the mean lateral
    // stress)
    if (s.size() != 13 && s.size() != 15 && s.size() != 18 && s.size() != 19 && s.size() != 21 && s.size() != 22 &&
        s.size() != 23)
      throw H5Error("checkpoint lab scalars have the wrong length (corrupt?)");
    stage = int(s[0]);
    stage_step = long(s[1]);
    started = s[2] != 0;
    H0 = s[3];
    V0 = s[4];
    p0 = s[5];
    aspect = s[6];
    mu = s[7];
    last_eps = s[8];
    last_time = s[9];
    snapshots = int(s[10]);
    next_snap_eps = s[11];
    searching = s[12] != 0;
    half_cycles = s.size() > 14 ? long(s[13]) : 0;
    cycle = s.size() > 14 ? s[14] : 0;
    eps_turn = s.size() > 17 ? s[15] : 0;
    n_ru = s.size() > 17 ? s[16] : -1;
    n_da = s.size() > 17 ? s[17] : -1;
    q0 = s.size() > 18 ? s[18] : 0;
    u0 = s.size() > 20 ? s[19] : 0;
    pc = s.size() > 20 ? s[20] : p0;
    Wx0 = s.size() > 21 ? s[21] : std::numeric_limits<Real>::quiet_NaN();
    sy0 = s.size() > 22 ? s[22] : p0 - q0 / 3;
  }
};

std::string join(const std::vector<std::string>& v, char sep) {
  std::string s;
  for (size_t k = 0; k < v.size(); ++k) s += (k ? std::string(1, sep) : "") + v[k];
  return s;
}
std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  if (s.empty()) return out;
  size_t a = 0;
  for (;;) {
    const size_t b = s.find(sep, a);
    out.push_back(s.substr(a, b == std::string::npos ? std::string::npos : b - a));
    if (b == std::string::npos) break;
    a = b + 1;
  }
  return out;
}

// The build string: version and source commit, Kokkos, backend (x its threads, once Kokkos is started), compiler,
// precision.
std::string build_string(bool threads) {
  std::ostringstream os;
  os << "grainlab " << GRAINLAB_VERSION << " (source " << source_commit() << "); Kokkos " << KOKKOS_VERSION / 10000
     << '.' << (KOKKOS_VERSION / 100) % 100 << '.' << KOKKOS_VERSION % 100 << "; backend " << ExecSpace::name();
  if (threads) {
    os << " x " << ExecSpace().concurrency();
    // Where OpenMP binds its threads, to which CPUs (a study's jobs each to their own: study.cpp)
    if (const auto places = compat::openmp_places(); !places.empty())
      os << "; threads bound to places " << compat::places_text(places);
  }
  os << "; compiler " <<
#if defined(__clang__)
      "clang " << __clang_version__
#elif defined(__GNUC__)
      "g++ " << __VERSION__
#else
      "unknown"
#endif
     << "; precision " << (sizeof(Real) == 8 ? "double" : "float");
  return os.str();
}
std::string build_info() { return build_string(true); }

// The resolved config with output.dir blanked: two runs may differ only in where they write.
std::string config_fingerprint(const RunConfig& c) {
  RunConfig d = c;
  d.out_dir = "";
  return resolved_config_yaml(d);
}

// A checkpoint's config fingerprint as this build writes it: an older grainlab wrote the same config in other
// words (numbers at 17 digits; before bae18c0 a relative sample.file, relative to the working directory, which
// the empty anchor path below keeps: a run resumed from where it started finds its sample). Text that no longer
// parses is returned as it is, and so differs.
// A config text read back as a RunConfig (a fingerprint, a resolved config.yaml); throws where it does not parse.
RunConfig parse_config_text(const std::string& text) {
  YAML::Node n = YAML::Load(text);
  n["output"]["dir"] = "-";  // blanked in a fingerprint (config_fingerprint), which the parser refuses
  return parse_run_config(n, "");
}

std::string as_this_build_writes(const std::string& text) {
  try {
    return config_fingerprint(parse_config_text(text));
  } catch (const std::exception&) {
    return text;
  }
}

}  // namespace

// `then` (a config as config_fingerprint writes it) with now's checkpoint cadence (output.checkpoint_every,
// checkpoint_minutes, keep_checkpoints): when and how many checkpoints are written changes nothing a run computes or
// records (a checkpoint's write leaves the state as it was: resumed runs equal uninterrupted ones bitwise), so a run
// resumed with another cadence is the same run (a long run's checkpoints made rarer for a full disk, say). Text that
// does not parse is returned as it is.
std::string with_checkpoint_cadence(const std::string& then, const RunConfig& now) {
  try {
    RunConfig c = parse_config_text(then);
    c.checkpoint_every = now.checkpoint_every;
    c.checkpoint_minutes = now.checkpoint_minutes;
    c.keep_checkpoints = now.keep_checkpoints;
    return config_fingerprint(c);
  } catch (const std::exception&) {
    return then;
  }
}

std::string with_checkpoint_cadence_of(const std::string& config, const std::string& cadence_from) {
  try {
    return with_checkpoint_cadence(config, parse_config_text(cadence_from));
  } catch (const std::exception&) {
    return config;
  }
}

// Empty when the config `now` only extends `then` (both as config_fingerprint writes them) for a run whose newest
// checkpoint lies in stage k (k = the number of stages: finished): every key outside `stages` the same, the
// stages before k the same, stage k the same but for its end (max_axial_strain, max_steps, cycles; the stress ends sigma_v,
// ocr, q, stress_ratio, stress_increment: refuse_passed_end judges whether the run has passed the moved end), the stages after k
// (not started) free, and stages appended. Otherwise the first difference, named as a config key.
std::string extension_mismatch(const std::string& then, const std::string& now, int k) {
  const YAML::Node a = YAML::Load(then), b = YAML::Load(now);
  const auto differs = [](const YAML::Node& x, const YAML::Node& y) { return YAML::Dump(x) != YAML::Dump(y); };
  const auto first_key = [&](const YAML::Node& x, const YAML::Node& y, const std::string& prefix) -> std::string {
    for (const auto& it : x) {
      const std::string key = it.first.as<std::string>();
      if (!y[key] || differs(it.second, y[key])) return prefix + key;
    }
    for (const auto& it : y)
      if (!x[it.first.as<std::string>()]) return prefix + it.first.as<std::string>();
    return "";
  };
  for (const auto& it : a) {
    std::string key = it.first.as<std::string>();
    if (key == "stages") continue;
    if (!b[key]) return key;
    if (differs(it.second, b[key])) {
      const std::string sub = it.second.IsMap() && b[key].IsMap() ? first_key(it.second, b[key], key + ".") : "";
      return sub.empty() ? key : sub;
    }
  }
  for (const auto& it : b)
    if (!a[it.first.as<std::string>()]) return it.first.as<std::string>();
  const YAML::Node sa = a["stages"], sb = b["stages"];
  if (sb.size() < sa.size())
    return "stages: the run has " + std::to_string(sa.size()) + ", this config " + std::to_string(sb.size());
  const int last = std::min<int>(k, int(sa.size()) - 1);
  for (int j = 0; j <= last; ++j) {
    YAML::Node x = YAML::Clone(sa[j]), y = YAML::Clone(sb[j]);
    if (j == last)
      for (const char* key :
           {"max_axial_strain", "max_steps", "cycles", "sigma_v", "ocr", "q", "stress_ratio", "stress_increment"}) {
        x.remove(key);
        y.remove(key);
      }
    std::string key = first_key(x, y, "stages[" + std::to_string(j) + "].");
    if (!key.empty()) return key;
  }
  return "";
}

namespace {

// A number to 4 significant digits, as the run's lines give stresses.
std::string sig4(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.4g", v);
  return b;
}

// A drained shear servos its lateral walls (start_stage) to lateral_targets.
bool lateral_servo(const StageConfig& sc) { return sc.type != StageType::Isotropic && sc.drainage == Drainage::Drained; }
// Whether the lateral targets move with sigma_z (set every step in run_stage); otherwise both are p'_0 throughout.
bool moving_lateral_targets(const StageConfig& sc) {
  return sc.b > 0 || sc.constant_p || sc.k_ratio > 0 || sc.lateral_slope.has_value();
}
// The lateral walls' servo targets of a drained shear, given the step's sigma_z. sigma_y = sigma_3 and sigma_x =
// sigma_3 + b (sigma_z - sigma_3) (true triaxial, StageConfig::b; sigma_x = sigma_y at b = 0), with sigma_3 = p'_0
// (SPEC §6.3; p'_0 - q_0/3, the lateral stress at the start, where a shear starts from an anisotropic stress), or on
// the constant-p' path (StageConfig::constant_p) the sigma_3 that makes (sigma_x + sigma_y + sigma_z) / 3 = p'_0:
// sigma_3 (2 - b) + sigma_z (1 + b) = 3 p'_0. Both hold in extension too (b = 0 there). On a K path
// (StageConfig::k_ratio) sigma_3 = K sigma_z once that passes the start's sigma_3 along the loading; on a linear path
// (StageConfig::lateral_slope) sigma_3 = sigma_3,0 + slope (sigma_z - sigma_z,0), the start's sigma_z,0 = p'_0 + 2 q_0/3
// (at slope -1/2 and b = 0 the constant-p' path's sigma_3, algebraically).
struct LateralTargets {
  Real sx, sy;
};
// A shear's start stresses from its p'_0 and q_0 (SPEC §6.3 with an anisotropic start): sigma_3,0 = p'_0 - q_0/3,
// sigma_z,0 = p'_0 + 2 q_0/3. What the lateral targets, a probe's stress_increment end and its increments count from.
struct StartStress {
  Real s3, sz;
};
StartStress start_stress(Real p0, Real q0) { return {p0 - q0 / 3, p0 + 2 * q0 / 3}; }
LateralTargets lateral_targets(const StageConfig& sc, Real p0, Real q0, Real sz) {
  Real s3 = sc.constant_p ? (3 * p0 - (1 + sc.b) * sz) / (2 - sc.b) : p0 - q0 / 3;
  // a K path (StageConfig::k_ratio): the start's sigma_3 until K sigma_z passes it, K sigma_z from there
  if (sc.k_ratio > 0) s3 = sc.extension ? std::min(s3, sc.k_ratio * sz) : std::max(s3, sc.k_ratio * sz);
  if (sc.lateral_slope) s3 += *sc.lateral_slope * (sz - start_stress(p0, q0).sz);
  return {s3 + sc.b * (sz - s3), s3};
}

// The sample a run starts from (sample.file): its state and the density it was prepared with. A checkpoint has the
// state but not the density (it continues its own run, whose config holds it): named, not "missing attribute density".
struct SampleFile {
  EngineState state;
  Real density, density_scaling;
  std::string digest;  // state_digest of state
};
SampleFile read_sample_file(const std::string& path) {
  if (std::error_code ec; fs::is_directory(path, ec)) {
    // a run's directory, most likely: name the samples it holds
    std::set<std::string> samples;  // sorted
    for (auto& f : fs::directory_iterator(path, ec)) {
      const std::string n = f.path().filename().string();
      if (n.rfind("sample_", 0) == 0 && f.path().extension() == ".h5") samples.insert(n);
    }
    std::string held;
    for (const std::string& n : samples) held += (held.empty() ? "; it holds " : ", ") + n;
    throw H5Error(path + ": a directory, not a sample file" +
                  (held.empty() ? std::string(": a run starts from a sample_<stage>.h5 of the run that prepared it")
                                : held));
  }
  try {
    const H5Reader probe(path);
  } catch (const H5Error&) {
    // A packing made elsewhere, named as the sample itself: a file HDF5 cannot open that is text (no NUL in its first
    // bytes) is said to be one, with the command that makes a sample of it, rather than "not an HDF5 file".
    std::ifstream f(path, std::ios::binary);
    char head[512];
    f.read(head, sizeof head);
    const std::string b(head, size_t(std::max<std::streamsize>(f.gcount(), 0)));
    if (!b.empty() && b.find('\0') == std::string::npos)
      throw H5Error(path + ": text, not an HDF5 file (a sample is one): a packing of x y z r lines or a "
                           "LAMMPS/LIGGGHTS dump becomes a sample with `grainlab import " + path + "`");
    throw;
  }
  const H5Reader r(path);
  EngineState s = read_state(r);
  if (!r.has("density") || !r.has("density_scaling"))
    throw H5Error(path + ": a checkpoint, not a sample: a checkpoint continues its own run (grainlab run CONFIG "
                         "--out <its run directory> --resume); a run starts from a sample_<stage>.h5 of the run that prepared it");
  std::string digest = state_digest(s);
  return {std::move(s), r.attr_double("density"), r.attr_double("density_scaling"), std::move(digest)};
}
// A run directory's checkpoints (checkpoints/ckpt_<12-digit step>.h5: by name is by step), the newest first; none if
// there is no such folder.
std::vector<std::string> checkpoints_newest_first(const std::string& run_dir) {
  std::vector<std::string> all;
  std::error_code ec;
  for (auto& f : fs::directory_iterator(run_dir + "/checkpoints", ec))
    if (f.path().filename().string().rfind("ckpt_", 0) == 0 && f.path().extension() == ".h5") all.push_back(f.path());
  std::sort(all.rbegin(), all.rend());
  return all;
}

// The run's plan (plan_run) for a sample already read (sample: sample.file's, or what stands in for it on a resume).
RunPlan plan_run_with(const RunConfig& cfg, Real p_start, bool place, const SampleFile* sample);

// ------------------------------------------------------------------------------------------------
class Laboratory {
 public:
  Laboratory(const RunConfig& cfg, const RunOptions& opt)
      : cfg_(cfg), opt_(opt), out_(opt.out_dir.empty() ? cfg.out_dir : opt.out_dir), fingerprint_(config_fingerprint(cfg)) {}

  RunResult run();

 private:
  struct Measure {
    Real sx, sy, sz, p, q, V, e, eps_a, eps_v, eps_r, gamma, u, eps_x, eps_y;
  };

  bool holds_run() const;
  void prepare_output_dir();
  void refuse_overwrites() const;
  void load_sample();
  std::optional<SampleFile> sample_from_checkpoints() const;
  void build_engine();
  void start_stage(const StageConfig& sc);
  Measure measure(const StageConfig& sc) const;
  std::vector<double> row(const StageConfig& sc, const Measure& m, const Diagnostics& d);
  // unmet: where given, the criteria missed, with their values and tolerances ("" if none)
  bool isotropic_done(const StageConfig& sc, const Diagnostics& d, std::string* unmet = nullptr) const;
  bool shear_end(const StageConfig& sc, const Measure& m) const;
  // An oedometric stage's stress end (StageConfig::sigma_v, ocr): the sigma_z it ends at, 0 for none; sv_end_ holds
  // the running stage's (run_stage), which shear_end reads.
  Real sigma_v_end(const StageConfig& sc, int k) const;
  Real sigma_v_max(int k) const;
  // A triaxial stage's stress end met: sigma_z at sv_end_, q at StageConfig::q_end, or q/p' at eta_end (q against
  // eta p': no division), each reached along the loading: at or above in compression, at or below in extension.
  // A stress probe's end (StageConfig::dsigma_end): |sigma - sigma_0| reached, whichever the direction.
  bool stress_end(const StageConfig& sc, const Measure& m) const {
    const auto reached = [&](Real x, Real end) { return sc.extension ? x <= end : x >= end; };
    return (sv_end_ > 0 && reached(m.sz, sv_end_)) || (sc.q_end && reached(m.q, *sc.q_end)) ||
           (sc.eta_end && reached(m.q, *sc.eta_end * m.p)) || (sc.dsigma_end && stress_increment(m) >= *sc.dsigma_end);
  }
  // |sigma - sigma_0| of the walls, sigma_0 the shear's start as the lateral targets take it (p'_0 - q_0/3 laterally,
  // p'_0 + 2 q_0/3 axially)
  Real stress_increment(const Measure& m) const {
    const StartStress s0 = start_stress(lab_.p0, lab_.q0);
    return std::sqrt((m.sx - s0.s3) * (m.sx - s0.s3) + (m.sy - s0.s3) * (m.sy - s0.s3) + (m.sz - s0.sz) * (m.sz - s0.sz));
  }
  Real sv_end_ = 0;
  bool cyclic_turn(const StageConfig& sc, const Measure& m);
  // A cyclic stage's controlled level x and its amplitude A: q (stress reversal), sigma_v (an oedometric stage's stress
  // reversal) or eps_a (strain reversal). Stress reversal about the stage's q_0 (0 but after a K0 consolidation or a
  // drained loading: Lab::q0), or about its sigma_z,0 = p'_0 + 2 q_0 / 3 (start_stress: the measured sigma_z after a
  // shear stage, to rounding).
  std::pair<Real, Real> cyclic_level(const StageConfig& sc, const Measure& m) const {
    if (!stress_controlled(sc)) return {m.eps_a, sc.strain_amplitude};
    const ReversalStress r = reversal_stress(sc);
    return {(sc.sigma_v_reversal() ? m.sz : m.q) - r.x0, r.A};
  }
  // sigma_h / sigma_v of the walls, sigma_h = (sigma_x + sigma_y) / 2 (cycles.csv K; NaN without a vertical stress)
  static Real lateral_ratio(const Measure& m) {
    return m.sz > 0 ? Real(0.5) * (m.sx + m.sy) / m.sz : std::numeric_limits<Real>::quiet_NaN();
  }
  // A stress-reversal stage's controlled stress: its name, its level at the start (q_0 or sigma_z,0) and A
  struct ReversalStress {
    const char* name;
    Real x0, A;
  };
  ReversalStress reversal_stress(const StageConfig& sc) const {
    if (sc.sigma_v_reversal()) return {"sigma_v", start_stress(lab_.p0, lab_.q0).sz, sc.sigma_v_amplitude};
    return {"q", lab_.q0, q_amplitude(sc, lab_.pc)};
  }
  // A stress-controlled cyclic stage (q or sigma_v), whose strain per half cycle only the run learns
  static bool stress_controlled(const StageConfig& sc) { return sc.stress_reversal() || sc.sigma_v_reversal(); }
  // A stress-reversal stage's A: its q_amplitude, or 2 csr p'_c (StageConfig::csr) at the p'_c it started with.
  static Real q_amplitude(const StageConfig& sc, Real pc) { return sc.csr > 0 ? 2 * sc.csr * pc : sc.q_amplitude; }
  Real cycle_number(const StageConfig& sc, const Measure& m) const;
  // A triaxial stage's axial strain along its loading: eps_a in compression, -eps_a in extension (what
  // max_axial_strain, snapshot_strain and the plan count).
  static Real strain_along(const StageConfig& sc, Real eps_a) { return sc.extension ? -eps_a : eps_a; }
  Real watch_cycle_number(const StageConfig& sc, const Measure& m) const;
  void watch_cycle(const StageConfig& sc, const Measure& m, bool turn, Real N, const Vec3d& drag);
  // A stress-controlled cyclic stage at its first load reversal, and at the end of its first cycle: a warning if that
  // quarter cycle, or that cycle's mean quarter, was dynamic.
  void warn_dynamic_loops(const StageConfig& sc) const;
  void warn_dynamic_cycle(const StageConfig& sc, double quarter) const;
  // An oedometric cyclic stage's closing line: the strain its cycles accumulated, and M_eq, D_v and K, first and last.
  void print_ratcheting(const StageConfig& sc) const;
  // The stage's first complete cycle, ended at step `row_step` (its cycles.csv row's), over 4: in wave transits
  double quarter_transits(long row_step) const {
    const long start = eng_->step_count() - lab_.stage_step;
    return double(row_step - start) * eng_->dt() / 4 / transit_;
  }
  // deepest: the deepest sphere-sphere overlap now, of the smaller radius; trial: "" or which target_e0 trial
  void watch_overlap(const StageConfig& sc, Real deepest, const std::string& trial = "");
  bool overlap_warned_ = false;  // this stage's watch_overlap warning given
  void write_summary() const;
  // stage_step: the steps the stage (or a target_e0 trial) has run, for a ramp's advice; trial: "" or which trial
  void assert_healthy(long stage_step, const std::string& trial = "");
  [[noreturn]] void stop_run(const std::string& what);
  Real servo_error(const StageConfig& sc, const Measure& m) const;
  Real stage_servo_error(const StageConfig& sc) const;
  Real stage_k0(size_t k) const;
  Real stage_ocr(size_t k) const;
  const std::vector<double>* last_row(size_t k) const;
  Real stage_secant_modulus(size_t k, const StageResult& r) const;
  // A linear path's increments over stage k, in the Rendulic plane: (sqrt2 dsigma_r, dsigma_a) from the start's
  // stresses (p_0, q_0) and (sqrt2 deps_r, deps_a) from its start, at its last series row; NaN without one.
  struct ProbeIncrements {
    Real ds_r, ds_a, de_r, de_a;
  };
  ProbeIncrements probe_increments(size_t k, const StageResult& r) const;
  void check_servo(const StageConfig& sc, const Measure& m);
  Real inner_void_ratio() const;
  Sym inner_stress();
  Vec3d drag_stress();
  Vec3d box_centre() const;
  static Vec3d drag_of(const Vec3d& moment, Real V);
  // The drag's share of q, of its per-axis stresses (as measure()'s q of the walls')
  static Real drag_q(const Vec3d& d) { return d[2] - 0.5 * (d[0] + d[1]); }
  Real core_void_ratio() const;
  Real void_ratio_inset(const Real (&inset)[3]) const;
  Real inset_box(const Real (&inset)[3], Vec3d& lo, Vec3d& hi) const;
  void warn_graded(const StageConfig& sc, const StageResult& r) const;
  void place_lateral_walls(const StageConfig& sc);
  void ramp_pressure(const StageConfig& sc, long stage_step);
  // Runs the stage from lab_.stage_step; returns false when interrupted.
  bool run_stage(const StageConfig& sc);
  bool search_e0(const StageConfig& sc);
  struct TrialEnd {
    Real e = 0;
    bool converged = false;    // ended by isotropic_done, not by max_steps
    bool interrupted = false;  // stopped (a signal; stop_after_steps): e means nothing
    long steps = 0;            // the steps it ran
  };
  TrialEnd trial_consolidation(const StageConfig& sc, const EngineState& s0, Real mu);
  void snapshot(const std::string& tag);
  void write_xdmf();
  void save_sample(const StageConfig& sc);
  // The engine's state, or `state` (a target_e0 search's stage start, written while a trial runs)
  std::string write_checkpoint(const EngineState* state = nullptr);
  bool load_newest_checkpoint();
  void flush_outputs();
  void progress(const std::string& line, bool final = false);
  long trial_steps_ = 0;  // the steps a target_e0 trial had run when the run was interrupted
  bool stop_requested() const {
    return g_stop || (opt_.stop_after_steps >= 0 && total_steps_ >= opt_.stop_after_steps);
  }

  const RunConfig& cfg_;
  RunOptions opt_;
  std::string out_, fingerprint_;
  std::string sample_digest_;  // sample.file's state_digest (else empty): checkpoints and run.h5 record it
  std::optional<SampleFile> sample_;  // sample.file's content (load_sample), until build_engine takes it
  Real planned_dt_ = 0;   // the time step this config gives (plan_run); an extended run must keep its own
  GradingIndices grading_;  // the sample's D10-D60, Cu, Cc by mass (plan_run): summary.json's "sample"
  double transit_ = 0;    // a compression wave's time across the sample (plan_run): cyclic loading against it
  bool extended_ = false; // resumed from a checkpoint of a config that this one extends
  bool recadenced_ = false; // resumed with another checkpoint cadence than the run's (with_checkpoint_cadence)
  void refuse_passed_end(const std::string& path, const YAML::Node& then) const;
  std::unique_ptr<Engine> eng_;
  Real Vs_ = 0, d_mean_ = 0, density_ = 0, scaling_ = 1;
  Lab lab_;
  long total_steps_ = 0;  // steps taken by this process (for stop_after_steps)
  std::chrono::steady_clock::time_point last_ckpt_ = std::chrono::steady_clock::now();
  // flush_outputs' pacing (flush_due): when the files were last written and what that took, in seconds
  std::chrono::steady_clock::time_point last_flush_ = std::chrono::steady_clock::now();
  double flush_cost_ = 0;
  bool flush_due(int rows_since) const;
  std::chrono::steady_clock::time_point stage_t0_ = std::chrono::steady_clock::now();
  // When the last progress line went to a log (not a terminal); none yet in this stage: the epoch.
  std::chrono::steady_clock::time_point last_log_line_{};
  // watch_core_share's window: its start and the process's CPU time there; windows in a row short of the cores
  std::chrono::steady_clock::time_point share_t0_{};
  double share_cpu0_ = 0;
  int share_short_ = 0;
  bool share_warned_ = false;
  void start_core_share();
  void watch_core_share();
  long stage_step0_ = 0;
  bool tty_ = ::isatty(STDOUT_FILENO);
  int lock_fd_ = -1;

 public:
  ~Laboratory() {
    if (lock_fd_ >= 0) ::close(lock_fd_);  // releases the flock
  }
};

namespace {
// Does directory d hold an entry other than the temporary files of interrupted writers (".tmp." in the name)?
bool holds_files(const std::string& d) {
  std::error_code ec;
  if (!fs::is_directory(d, ec)) return false;
  for (auto& f : fs::directory_iterator(d, ec))
    if (f.path().filename().string().find(".tmp.") == std::string::npos) return true;
  return false;
}
// A file's whole text ("" where it cannot be read).
std::string file_text(const std::string& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// Memory a run may plan for, in bytes. On CPU threads: MemAvailable, lowered by a cgroup limit (a container's
// or a batch job's share). On a GPU: the device's free memory, where the particle and contact arrays live (the
// host keeps only output mirrors: 48 B a sphere at 11M, perf/RESULTS.md's GPU section). Either lowered by
// GRAINLAB_MEMORY_LIMIT (bytes, for a shared node or GPU). 0 where none can be read.
double memory_available(std::string& source) {
  double avail = 0;
  const auto lower = [&](double v, const char* what) {
    if (v > 0 && (avail <= 0 || v < avail)) {
      avail = v;
      source = what;
    }
  };
  if constexpr (!kHostBackend) {
#if defined(KOKKOS_ENABLE_CUDA)
    // Device 0, the one Kokkos::initialize takes by default. `validate` calls this without Kokkos: the runtime
    // then opens the context itself. A machine without a usable GPU reads as unknown (the run will say why).
    std::size_t free_bytes = 0, total_bytes = 0;
    if (cudaMemGetInfo(&free_bytes, &total_bytes) == cudaSuccess)
      lower(double(free_bytes), "the GPU's free memory");
    else
      (void)cudaGetLastError();  // clear the error, so that Kokkos's own checks do not report it later
#endif
  } else {
    std::ifstream in("/proc/meminfo");
    std::string key, unit;
    double kb = 0;
    while (in >> key >> kb >> unit)
      if (key == "MemAvailable:") {
        avail = kb * 1024;
        source = "MemAvailable";
      }
    lower(cgroup_memory_limit(file_text("/proc/self/cgroup")), "the cgroup's memory limit");
  }
  if (const char* env = std::getenv("GRAINLAB_MEMORY_LIMIT")) {
    // Bytes, or with a binary unit as a batch system writes it (16G, 512M, 1.5GiB; K M G T, 1024-based).
    char* end = nullptr;
    double v = std::strtod(env, &end);
    if (end != env && *end) {
      const std::string unit(end);
      const std::string units = "KMGT";
      const size_t k = unit.empty() ? std::string::npos : units.find(char(std::toupper(static_cast<unsigned char>(unit[0]))));
      std::string rest = unit.empty() ? "" : unit.substr(1);
      for (char& ch : rest) ch = char(std::tolower(static_cast<unsigned char>(ch)));
      if (k != std::string::npos && (rest.empty() || rest == "b" || rest == "ib")) {
        v *= std::pow(1024.0, double(k + 1));
        end += unit.size();
      }
    }
    if (end == env || *end || !(v > 0) || !std::isfinite(v))
      throw std::runtime_error(std::string("GRAINLAB_MEMORY_LIMIT = '") + env +
                               "': must be a number of bytes > 0, or with a unit K, M, G or T (1024-based: 16G)");
    lower(v, "GRAINLAB_MEMORY_LIMIT");
  }
  return avail;
}

// A run that cannot fit is refused before any work, with the numbers, instead of being killed by the kernel's
// out-of-memory killer hours in, without a word. 1.5 kB a sphere: the peak RSS of a dense lab run, measured
// (configs/quick.yaml at 30 000 spheres, Z = 4: 65-71 MB, of which 19 MB is the program, the peak of a 300-sphere
// run; the race scene holds 1.0-1.1 kB, perf/RESULTS.md; a size ratio of 10, perf/wide_psd.yaml at 20 000 spheres,
// 31 MB, ~0.6 kB above the program). An upper estimate: it refuses only the hopeless cases. On a GPU the same
// arrays are in device memory, so the same figure is checked against the device's free memory; measured there
// (perf/gpu/device.sh memory, an H200): 0.34 kB a sphere for a loose generated sample, 1.08 kB for the dense race
// scene, above ~0.6 GB of CUDA context (perf/RESULTS.md, GPU section, session 37).
constexpr double kBytesPerSphere = 1536;
// Returns the bytes available (0: unknown), naming where the figure comes from.
double require_memory(long n, const std::string& what, std::string& source) {
  if (n <= 0) return 0;
  const double avail = memory_available(source);
  const double need = double(n) * kBytesPerSphere;
  if (avail <= 0 || need <= avail) return avail;
  throw std::runtime_error(what + " = " + std::to_string(n) + " spheres needs about " + memory_amount(need) +
                           " of memory (1.5 kB a sphere), but " + memory_amount(avail) + " is available (" + source +
                           "); use fewer spheres or a machine with more memory");
}
}  // namespace

// A run that starts afresh refuses a directory where it would replace anything: a run (series.csv, run.h5,
// checkpoints), or a file of the same name as one it writes (config.yaml with other content, particles.xdmf,
// sample_<stage>.h5, snapshots/). So `--out .` in a folder that holds the user's own config.yaml stops with one
// line instead of overwriting it. The check only reads, and runs before anything is created.
void Laboratory::refuse_overwrites() const {
  // A study's directory, or its jobs/ folder: the run's files would sit among the study's (a run's own directory
  // inside a study, jobs/NAME/run, is where the study runs its jobs)
  if (holds_study(out_))
    throw std::runtime_error(out_ + ": holds a study (grainlab study --out); a run's --out is a directory of its own "
                                    "(nothing was changed)");
  fs::path dir = fs::path(out_).lexically_normal();
  if (dir.filename().empty()) dir = dir.parent_path();  // "st/jobs/"
  const fs::path up = dir.parent_path().empty() ? fs::path(".") : dir.parent_path();
  if (dir.filename() == "jobs" && holds_study(up.string()))
    throw std::runtime_error(out_ + ": the jobs folder of a study; a run's --out is a directory of its own (nothing "
                                      "was changed)");
  for (const char* f : {"series.csv", "run.h5"})
    if (fs::exists(out_ + "/" + f))
      throw std::runtime_error(out_ + ": already holds a run (" + f +
                               "); continue it with --resume or choose another --out (nothing was changed)");
  if (holds_files(out_ + "/checkpoints"))
    throw std::runtime_error(out_ + "/checkpoints: holds checkpoints of an earlier run; use --resume or another --out");
  const auto refuse = [&](const std::string& name) {
    throw std::runtime_error(out_ + ": already holds " + name +
                             ", which this run would overwrite; choose another --out (nothing was changed)");
  };
  if (fs::exists(out_ + "/config.yaml")) {
    // Our own, from a start killed before its first checkpoint, is the same text: replacing it loses nothing.
    std::ifstream in(out_ + "/config.yaml", std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!in || text != resolved_config_yaml(cfg_)) refuse("config.yaml");
  }
  if (fs::exists(out_ + "/particles.xdmf")) refuse("particles.xdmf");
  if (fs::exists(out_ + "/summary.json")) refuse("summary.json");
  if (fs::exists(out_ + "/cycles.csv")) refuse("cycles.csv");
  if (holds_files(out_ + "/snapshots")) refuse("snapshots/");
  for (const StageConfig& sc : cfg_.stages)
    if (fs::exists(out_ + "/sample_" + sc.name + ".h5")) refuse("sample_" + sc.name + ".h5");
}

bool Laboratory::holds_run() const {
  return grainlab::holds_run(out_);
}

void Laboratory::prepare_output_dir() {
  std::error_code ec;
  fs::create_directories(out_ + "/checkpoints", ec);
  if (ec) throw std::runtime_error(out_ + ": cannot create the output directory (" + ec.message() + ")");
  // One process per run directory: a second one would interleave checkpoints and outputs.
  lock_fd_ = ::open((out_ + "/.lock").c_str(), O_RDWR | O_CREAT, 0644);
  if (lock_fd_ < 0) throw std::runtime_error(out_ + ": cannot create the lock file (" + std::strerror(errno) + ")");
  if (!lock_or_warn(lock_fd_, out_ + "/.lock"))
    throw std::runtime_error(out_ + ": in use by another grainlab process (lock held on " + out_ + "/.lock)");
  // Temporary files of writers that were killed mid-write (the lock says none is running now).
  for (const std::string& d : {out_, out_ + "/checkpoints", out_ + "/snapshots"}) {
    if (!fs::is_directory(d)) continue;
    for (auto& f : fs::directory_iterator(d))
      if (f.path().filename().string().find(".tmp.") != std::string::npos) fs::remove(f.path(), ec);
  }
  if (opt_.resume && !holds_run()) {
    // Killed before its first checkpoint (or never started): nothing of a run to lose, so start afresh (not over
    // files of other origin: refuse_overwrites above).
    if (!opt_.quiet) std::printf("%s: nothing to resume yet; starting the run\n", out_.c_str());
    opt_.resume = false;
  }
  // Probe that the directory is writable now rather than after hours of computing.
  write_file_atomic(out_ + "/.write_probe", "ok\n");
  fs::remove(out_ + "/.write_probe", ec);
}

// sample.file is read once, for the plan and the engine. A run from it holds its whole state in its checkpoints, and
// needs the file only to start: resumed with the file gone (a preparation run cleaned up or moved since), it goes on
// from them. They record the sample's density, density scaling and digest for that, and the radii are the sample's
// (a run never changes them).
void Laboratory::load_sample() {
  if (cfg_.sample_file.empty()) return;
  if (std::error_code ec; opt_.resume && !fs::exists(cfg_.sample_file, ec) && holds_run()) {
    if (std::optional<SampleFile> s = sample_from_checkpoints()) {
      sample_ = std::move(s);
      if (!opt_.quiet)
        std::printf("%s (sample.file) is not there: the run goes on from its checkpoints, which hold its whole state\n",
                    cfg_.sample_file.c_str());
      return;
    }
    throw std::runtime_error(cfg_.sample_file + " (sample.file): no such file, and no readable checkpoint of this run "
                                                "records the sample (a build before they did) to stand in for it: put "
                                                "the file back to resume the run");
  }
  sample_ = read_sample_file(cfg_.sample_file);
}

std::optional<SampleFile> Laboratory::sample_from_checkpoints() const {
  for (const std::string& path : checkpoints_newest_first(out_)) {
    try {
      const H5Reader r(path);
      if (!r.has("sample_digest") || !r.has("sample_density") || !r.has("sample_density_scaling")) continue;
      return SampleFile{read_state(r), r.attr_double("sample_density"), r.attr_double("sample_density_scaling"),
                        r.attr_string("sample_digest")};
    } catch (const H5Error&) {  // load_newest_checkpoint names the unreadable ones
    }
  }
  return std::nullopt;
}

void Laboratory::build_engine() {
  ParticleSetup setup;
  WallSet walls;
  EngineParams ep = cfg_.engine;
  // The time step is chosen once for the whole run, for its stiffest stage (rolling on in any stage).
  for (const StageConfig& sc : cfg_.stages) ep.contact.mu_r = std::max(ep.contact.mu_r, sc.mu_r);
  std::unique_ptr<EngineState> sample;
  if (!cfg_.sample_file.empty()) {
    if (!sample_) load_sample();
    SampleFile f = std::move(*sample_);
    sample_.reset();
    sample_digest_ = f.digest;
    sample = std::make_unique<EngineState>(std::move(f.state));
    setup.x = sample->x;
    setup.r = sample->r;
    setup.density = f.density;
    setup.density_scaling = f.density_scaling;
    walls = sample->walls;
    if (!sample->walls_are_box) throw std::runtime_error(cfg_.sample_file + ": the sample has no box walls");
  } else {
    Packing pk = generate_packing(cfg_.packing);
    setup.x = pk.x;
    setup.r = pk.r;
    setup.density = cfg_.density;
    setup.density_scaling = cfg_.density_scaling;
    walls = make_box_walls(pk.lo, pk.hi);
  }
  density_ = setup.density;
  scaling_ = setup.density_scaling;
  Vs_ = 0;
  d_mean_ = 0;
  for (Real r : setup.r) {
    Vs_ += 4.0 / 3.0 * M_PI * r * r * r;
    d_mean_ += 2 * r;
  }
  d_mean_ /= std::max<size_t>(setup.r.size(), 1);
  eng_ = std::make_unique<Engine>(setup, ep, walls, true);
  if (sample) {
    // A reused sample starts a new run: its own clock and this run's time step.
    sample->step = 0;
    sample->time = 0;
    sample->dt = eng_->dt();
    sample->mu_r = ep.contact.mu_r;
    eng_->restore(*sample);
    // A sample without a record of its wall loads (`grainlab import`'s: no step has pressed its walls yet) gets them
    // from its positions, at this run's wall stiffness: the first stage measures its stress from them, and a shear
    // from zero loads would hold sigma_3 at p'_0 = 0 against walls the overlaps press. Every sample an isotropic stage
    // wrote has them (its walls touch), so its runs keep their bits.
    bool recorded = false;
    for (int k = 0; k < sample->walls.count; ++k)
      recorded |= sample->loads.touching[k] > 0 || sample->loads.force[k] != 0;
    if (!recorded) eng_->load_walls_now();
  }
}

Laboratory::Measure Laboratory::measure(const StageConfig& sc) const {
  const Engine& e = *eng_;
  Measure m;
  m.sx = 0.5 * (e.wall_stress(0) + e.wall_stress(1));
  m.sy = 0.5 * (e.wall_stress(2) + e.wall_stress(3));
  m.sz = 0.5 * (e.wall_stress(4) + e.wall_stress(5));
  m.p = (m.sx + m.sy + m.sz) / 3;
  m.q = m.sz - 0.5 * (m.sx + m.sy);  // triaxial deviator, axial = z
  m.V = e.box_volume();
  m.e = (m.V - Vs_) / Vs_;
  const Real H = e.wall_position(5) - e.wall_position(4);
  m.eps_a = lab_.H0 > 0 ? (lab_.H0 - H) / lab_.H0 : 0;  // SPEC §6.3: strains from wall displacements
  m.eps_v = lab_.V0 > 0 ? (lab_.V0 - m.V) / lab_.V0 : 0;
  // The radial strain from the volume and the height, as a triaxial cell measures it: (1 - eps_v) = (1 - eps_a)
  // (1 - eps_r)^2 for the box H x W_x x W_y (exact at finite strain; the geometric mean of the two lateral strains,
  // which the lateral walls keep near equal). gamma = eps_a - eps_r: 1.5 eps_q, the shear strain on the plane of
  // largest shear (CycleLoop's G_eq). eps_a < max_axial_strain < 0.9 (config), so the root is of a positive number.
  m.eps_r = 1 - std::sqrt((1 - m.eps_v) / (1 - m.eps_a));
  m.gamma = m.eps_a - m.eps_r;
  // Each lateral axis's strain (compression positive, from the stage's start as eps_a): a true-triaxial shear moves
  // the x and y walls apart by different amounts, and its flow direction in the deviatoric plane needs both.
  // Both 0 before the first stage's start (no widths yet), NaN where Lab::Wx0 is (a resumed older checkpoint).
  const Real Wx0 = lab_.Wx0, Wy0 = lab_.H0 > 0 && Wx0 > 0 ? lab_.V0 / (lab_.H0 * Wx0) : 0;
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  m.eps_x = std::isnan(Wx0) ? nan : Wx0 > 0 ? (Wx0 - (e.wall_position(1) - e.wall_position(0))) / Wx0 : 0;
  m.eps_y = std::isnan(Wx0) ? nan : Wy0 > 0 ? (Wy0 - (e.wall_position(3) - e.wall_position(2))) / Wy0 : 0;
  m.u = 0;
  if (sc.type != StageType::Isotropic && sc.drainage == Drainage::Undrained && sc.plane_strain)
    // Plane strain: the cell pressure acts on the y faces alone (the x walls are rigid and held), so their total
    // stress stays the start's, sigma'_y,0 + u_0 (Lab::sy0): u = u_0 + sigma'_y,0 - sigma'_y. The triaxial formula
    // below is the same with sigma'_y the mean lateral stress (p'_0 - q_0/3 its start's, algebraically).
    m.u = lab_.u0 + lab_.sy0 - m.sy;
  else if (sc.type != StageType::Isotropic && sc.drainage == Drainage::Undrained)
    m.u = (lab_.p0 + lab_.u0 + (m.q - lab_.q0) / 3) - m.p;  // SPEC §6.3: u = p_total - p', p_total = p'_0 + u_0 +
                                                            // (q - q_0)/3
  return m;
}

std::vector<double> Laboratory::row(const StageConfig& sc, const Measure& m, const Diagnostics& d) {
  Engine& e = *eng_;
  const Descriptors D = e.analyze();  // between evaluate() and advance(): one instant
  const int np = e.num_particles();
  // Inertial number I = eps_dot d_mean sqrt(rho / p') with the measured axial strain rate and the
  // (scaled) density the dynamics actually uses (SPEC §6.3 quasi-static check).
  const Real dt_rows = e.time() - lab_.last_time;
  // A cyclic stage's axial walls turn between rows, where a difference of eps_a would understate the rate they
  // move at: the prescribed rate is the one.
  const Real rate = sc.type == StageType::Cyclic ? sc.axial_strain_rate
                    : dt_rows > 0                ? std::abs(m.eps_a - lab_.last_eps) / dt_rows
                                                 : 0;
  lab_.last_eps = m.eps_a;
  lab_.last_time = e.time();
  const Real I = m.p > 0 ? rate * d_mean_ * std::sqrt(density_ * scaling_ / m.p) : 0;
  Real p_in = 0, q_in = 0;
  stress_invariants(inner_stress(), p_in, q_in);
  const Vec3d drag = drag_stress();
  return {e.time(),
          double(e.step_count()),
          m.eps_a,
          m.eps_v,
          m.e,
          m.p,
          m.q,
          m.u,
          m.sx,
          m.sy,
          m.sz,
          np ? 2.0 * d.contacts / np : 0,
          d.kinetic,
          d.potential > 0 ? d.kinetic_skeleton / d.potential : 0,
          d.unbalanced_ratio,
          I,
          D.sliding_frac,
          D.rolling_sliding_frac,
          e.dt(),
          scaling_,
          D.p,
          D.q,
          D.p_walls,
          D.p > 0 ? D.q / D.p : 0,
          D.all.a_c,
          D.all.a_d,
          D.all.a_n,
          D.all.a_t,
          D.strong.a_c,
          D.strong.a_d,
          D.strong.a_n,
          D.strong.a_t,
          D.weak.a_c,
          D.weak.a_d,
          D.weak.a_n,
          D.weak.a_t,
          D.sff,
          D.share[0],
          D.share[1],
          D.share[2],
          D.share[3],
          D.z_mech,
          D.f_mean,
          D.weak_frac,
          D.sliding_weak_frac,
          e.params().contact.mu,
          e.params().contact.mu_r,
          // 0 isotropic, 1 triaxial undrained, 2 triaxial drained, 3 cyclic undrained, 4 cyclic drained, 5 triaxial
          // oedometric, 6 cyclic oedometric (after the codes of older builds, so that their meaning stays)
          sc.type == StageType::Isotropic        ? 0.0
          : sc.drainage == Drainage::Oedometric ? (sc.type == StageType::Cyclic ? 6.0 : 5.0)
                                                : (sc.drainage == Drainage::Undrained ? 1.0 : 2.0) +
                                                      (sc.type == StageType::Cyclic ? 2.0 : 0.0),
          std::max(Real(0), e.deepest_overlap().ratio),
          // N never below the steps' before it (watch_cycle_number): a row-only maximum missed a stress peak between
          // rows, so a sample that flowed before its first reversal ended "at N = 0.060" with r_u met at N = 0.078
          sc.type == StageType::Cyclic ? (lab_.cycle = watch_cycle_number(sc, m)) : 0.0,
          d.potential > 0 ? d.kinetic_fluct / d.potential : 0,
          inner_void_ratio(),
          D.q_walls,
          p_in,
          q_in,
          (drag[0] + drag[1] + drag[2]) / 3,
          drag_q(drag),  // as measure()'s p and q of the walls' mean stresses
          m.eps_x,
          m.eps_y};
}

// The local damping's drag as a stress on the walls, per axis: Engine::damping_moment about the box's centre over its
// volume. Why: about the centre, the first-moment balance of the next kick gives each axis's mean wall stress (of
// measure()) as the contact stress with the sphere-wall contacts (analyze()'s sigma_walls) plus this drag, less the
// spheres' inertial term, to O(delta/r) of the wall contacts' share (test Diagnostics.DampingDragClosesTheWallBalance).
// On a flowing sample the drag grows with its length (configs/damping-drag.yaml), so the walls' stress overstates the
// material's by it; walls' stress less drag is the material's as the boundary measures it.
Vec3d Laboratory::drag_stress() {
  Engine& e = *eng_;
  Vec3d m = e.damping_moment(box_centre());
  const Real V = e.box_volume();
  for (Real& v : m) v = V > 0 ? v / V : 0;  // drag_of's arithmetic
  return m;
}

Vec3d Laboratory::box_centre() const {
  Vec3d c{};
  for (int a = 0; a < 3; ++a) c[a] = 0.5 * (eng_->wall_position(2 * a) + eng_->wall_position(2 * a + 1));
  return c;
}

// The drag per axis of a drag moment about the box's centre, V the box's volume at its instant: drag_stress()'s
// arithmetic.
Vec3d Laboratory::drag_of(const Vec3d& moment, Real V) {
  Vec3d d{};
  for (int a = 0; a < 3; ++a) d[a] = V > 0 ? moment[a] / V : 0;
  return d;
}

// The interior: the wall box inset by kInnerMargin mean diameters on every side. (choice) 2 diameters: the wall's
// ordering of the first layers of a packing decays within a few diameters, and the interior must keep a useful share
// of a few thousand spheres (30 % of a 2 000-sphere box, 43 % of a 5 000-sphere one).
constexpr Real kInnerMargin = 2;

// The interior's void ratio, its solids the exact parts of the spheres in it (Engine::solid_volume_in). NaN where no
// interior is left or it holds no centre.
Real Laboratory::inner_void_ratio() const {
  const Real m = kInnerMargin * d_mean_, inset[3] = {m, m, m};
  return void_ratio_inset(inset);
}

// The interior's stress (Engine::stress_in: the spheres whose centres it holds). SPEC §7's contact stress sums every
// sphere-sphere contact over the whole box, so it misses the sphere-wall contacts' share (p_contacts_walls adds it) and
// averages the layers along the walls in; the walls' stress also carries the local damping's drag on a flowing sample.
// Over the last 5 % of strain of configs/size-study.yaml's shears at 2 000 / 10 000 spheres: q/p' of the contacts
// 0.630 / 0.713, of the interior 0.751 / 0.781, of the walls 0.804 / 0.902 (configs/README.md, series p_inner). NaN
// components where no interior is left.
Sym Laboratory::inner_stress() {
  const Real m = kInnerMargin * d_mean_, inset[3] = {m, m, m};
  Vec3d lo{}, hi{};
  if (!(inset_box(inset, lo, hi) > 0)) {
    Sym nan;
    for (Real& v : nan.v) v = std::numeric_limits<Real>::quiet_NaN();
    return nan;
  }
  return eng_->stress_in(lo, hi);
}

// The core's void ratio: the central eighth of the box (a quarter of each side in from each wall), where a sample
// compacted from its walls is loosest (StageResult::e_core).
Real Laboratory::core_void_ratio() const {
  Real inset[3];
  for (int a = 0; a < 3; ++a) inset[a] = 0.25 * (eng_->wall_position(2 * a + 1) - eng_->wall_position(2 * a));
  return void_ratio_inset(inset);
}

// The wall box inset by inset[a] on both sides along axis a: [lo, hi] and its volume (0 where nothing is left).
Real Laboratory::inset_box(const Real (&inset)[3], Vec3d& lo, Vec3d& hi) const {
  Real V = 1;
  for (int a = 0; a < 3; ++a) {
    lo[a] = eng_->wall_position(2 * a) + inset[a];
    hi[a] = eng_->wall_position(2 * a + 1) - inset[a];
    V *= std::max(Real(0), hi[a] - lo[a]);
  }
  return V;
}

// The void ratio of that box (Engine::solid_volume_in: the parts of the spheres inside it); NaN where no box is left or
// it holds no solid.
Real Laboratory::void_ratio_inset(const Real (&inset)[3]) const {
  Vec3d lo{}, hi{};
  const Real V = inset_box(inset, lo, hi);
  const Real Vs = V > 0 ? eng_->solid_volume_in(lo, hi) : 0;
  return Vs > 0 ? (V - Vs) / Vs : std::numeric_limits<Real>::quiet_NaN();
}

// A frictional gas compacted by its walls alone jams first in a crust along them, which then carries the load around
// a looser core: 10 000 spheres at mu = 0.5 end with solid fraction 0.62 one to three diameters from the walls and
// 0.58 at the centre (e_core - e_inner = +0.037). Such a sample is no element test; the stage's `affine` compacts
// homogeneously (-0.003 to +0.012 at 5 000-20 000 spheres; kGradedCore).
void Laboratory::warn_graded(const StageConfig& sc, const StageResult& r) const {
  if (eng_->num_particles() < kGradedMinCount || !(r.e_core - r.e_inner > kGradedCore)) return;
  std::fprintf(stderr,
               "grainlab: warning: stage %s: the sample is graded: its core (the central eighth of the box) has "
               "e = %.4f, its interior (2 mean diameters in from the walls) e = %.4f: looser by %.3f (more than %g)%s\n",
               sc.name.c_str(), r.e_core, r.e_inner, r.e_core - r.e_inner, kGradedCore,
               sc.affine ? "" : "; the walls compacted a crust around a looser core: `affine: true` on the stage "
                                "compacts it homogeneously");
}

bool Laboratory::isotropic_done(const StageConfig& sc, const Diagnostics& d, std::string* unmet) const {
  // SPEC §6.2: every wall within the pressure tolerance, and equilibrium (unbalanced force, kinetic energy).
  bool walls = true;
  int worst = 0;
  for (int k = 0; k < 6; ++k) {
    const Real off = std::abs(eng_->wall_stress(k) - sc.pressure);
    if (off > sc.pressure_tolerance * sc.pressure) walls = false;
    if (off > std::abs(eng_->wall_stress(worst) - sc.pressure)) worst = k;
  }
  const bool contacts = d.contacts > 0, ufr = d.unbalanced_ratio < sc.ufr_tolerance,
             ke = d.kinetic_skeleton < sc.ke_tolerance * d.potential;
  if (unmet) {
    std::ostringstream os;
    os << std::setprecision(3);
    const char* sep = "";
    if (!walls)
      os << std::exchange(sep, "; ") << "wall " << worst << " at " << eng_->wall_stress(worst) / 1e3 << " kPa, "
         << 100 * std::abs(eng_->wall_stress(worst) - sc.pressure) / sc.pressure << " % off " << sc.pressure / 1e3
         << " kPa against pressure_tolerance " << sc.pressure_tolerance;
    if (!contacts) os << std::exchange(sep, "; ") << "no contacts";
    if (!ufr)
      os << std::exchange(sep, "; ") << "unbalanced force ratio " << d.unbalanced_ratio << " against ufr_tolerance "
         << sc.ufr_tolerance;
    if (!ke)
      os << std::exchange(sep, "; ") << "kinetic / elastic energy " << d.kinetic_skeleton / d.potential
         << " against ke_tolerance " << sc.ke_tolerance;
    *unmet = os.str();
  }
  return walls && contacts && ufr && ke;
}

// A shear stage's end, judged at the start of a step (from wall positions and the wall loads the servo used):
// triaxial, eps_a (-eps_a in extension) reached; cyclic, |eps_a| at max_axial_strain (the sample liquefied or failed), or the cycles
// done: after the last extension peak, back at the level the stage started from (q or eps_a = 0).
bool Laboratory::shear_end(const StageConfig& sc, const Measure& m) const {
  // a rest (axial_strain_rate 0) ends on its last step, done
  if (sc.type == StageType::Triaxial && sc.axial_strain_rate == 0) return lab_.stage_step + 1 >= sc.max_steps;
  if (sc.type == StageType::Triaxial) return strain_along(sc, m.eps_a) >= sc.max_axial_strain || stress_end(sc, m);
  if (sc.type != StageType::Cyclic) return false;
  if (std::abs(m.eps_a) >= sc.max_axial_strain) return true;
  return lab_.half_cycles >= 2 * sc.cycles && eng_->wall_control(4).velocity > 0 && cyclic_level(sc, m).first >= 0;
}

// The sigma_z (of the walls, as a step finds it) at which stage k, an oedometric one, ends: its sigma_v, or sigma_v,max /
// ocr with sigma_v,max the largest sigma_z of the series rows of the stages before k (stage_ocr's, so that the
// summary's OCR at the end is the one asked for, within a step's change), which a checkpoint holds: a resumed stage ends
// where the uninterrupted one does. 0: no stress end.
Real Laboratory::sigma_v_end(const StageConfig& sc, int k) const {
  if (sc.type != StageType::Triaxial) return 0;
  if (sc.sigma_v > 0) return sc.sigma_v;
  return sc.ocr > 0 ? sigma_v_max(k) / sc.ocr : 0;
}

// sigma_v,max before stage k: the largest sigma_z of the series rows of stages 0..k-1 (0 without a row).
Real Laboratory::sigma_v_max(int k) const {
  const size_t iz = series_column("sigma_z");
  Real top = 0;
  for (size_t r = 0; r < lab_.series.rows.size() && lab_.series.stage[r] < k; ++r)
    top = std::max(top, Real(lab_.series.rows[r][iz]));
  return top;
}

// Cyclic stages, at the start of a step: at a peak (q or eps_a at +A while compressing, at -A while extending) the
// axial walls reverse. The direction is the axial walls' velocity itself (inward positive: compression), which a
// checkpoint holds, and the decision reads only state a checkpoint restores (wall positions, the wall loads of the
// previous step): a resumed run turns on the same steps. The hysteresis of +-A keeps a noisy q from turning twice.
bool Laboratory::cyclic_turn(const StageConfig& sc, const Measure& m) {
  WallControl& lo = eng_->wall_control(4);
  WallControl& hi = eng_->wall_control(5);
  const auto [level, A] = cyclic_level(sc, m);
  if (lo.velocity > 0 ? level < A : level > -A) return false;
  lo.velocity = -lo.velocity;
  hi.velocity = -hi.velocity;
  ++lab_.half_cycles;
  return true;
}

// The cycle number N of a cyclic stage, continuous: a cycle is 0 -> +A -> -A -> 0 of the controlled level x (q or
// eps_a), so its k-th peak lies at N = (2k - 1) / 4, and between peaks N follows x linearly (clamped to the segment:
// a q that overshoots a peak, or cannot reach the next once the sample has liquefied, does not move N past it). The
// stage ends at N = cycles exactly: after 2 cycles peaks, x back at 0. The series column is the largest N so far
// (Lab::cycle), so that a noisy q, or one that falls back as the sample liquefies, does not count cycles backwards.
Real Laboratory::cycle_number(const StageConfig& sc, const Measure& m) const {
  const auto [x, A] = cyclic_level(sc, m);
  const long k = lab_.half_cycles;
  if (k == 0) return 0.25 * std::clamp<Real>(x / A, 0, 1);
  const Real toward = k % 2 == 1 ? -x : x;  // the distance from the last peak grows with this
  const Real n = 0.25 * Real(2 * k - 1) + 0.5 * std::clamp<Real>((toward + A) / (2 * A), 0, 1);
  return std::min(n, Real(sc.cycles));  // the last quarter ends at x = 0 (the stage's end row may be a bit past)
}

// A cyclic stage, on every step, from the same measure as the turn (so a resumed run sees the same steps), at the
// cycle number N of that measure (never below the series' N, nor the last step's: watch_cycle_number, taken before
// the step, as the series' N may rise in it):
//  - the cycle's loop (CycleLoop): fed every step, with the damping's drag of the step's kick (q_drag: fed after the
//    step, which measures it); when N passes a whole number the cycle is done, its row goes to cycles.csv and the
//    next loop starts at this measure;
//  - the liquefaction criteria:
//    - initial liquefaction: the excess pore pressure ratio r_u = u / p'_0 reaches liquefaction_ru (undrained only;
//      u = p_total - p', SPEC §6.3);
//    - double-amplitude axial strain: |eps_a - eps_a at the last reversal| reaches liquefaction_da_strain. Under
//      stress control eps_a is extreme at the reversals, so at each one this is the peak-to-peak strain of the half
//      cycle just ended (ASTM D5311's double amplitude); between reversals it is the span so far, so a sample that
//      flows past the criterion mid half cycle meets it there. Before the first reversal: |eps_a| from the start.
//    They are first checked, then a turn (decided by this step's cyclic_turn) starts the next half cycle from here.
Real Laboratory::watch_cycle_number(const StageConfig& sc, const Measure& m) const {
  return std::max({lab_.cycle, Real(lab_.loop.n), cycle_number(sc, m)});
}

void Laboratory::watch_cycle(const StageConfig& sc, const Measure& m, bool turn, Real N, const Vec3d& drag) {
  CycleLoop& L = lab_.loop;
  const Real q_drag = drag_q(drag);  // row()'s arithmetic
  L.q_ref = lab_.q0;  // the centre q cycles about (0 after an isotropic stage: the bits of older runs)
  if (!L.open) {
    L.start(m.q, m.eps_a, m.gamma, m.u, q_drag, m.sz, drag[2]);
  } else {
    L.add(m.q, m.eps_a, m.gamma, m.u, q_drag, m.sz, drag[2]);
    if (std::floor(N) > std::floor(L.n)) {
      // the step: the measure's (the loop's last instant), which the step after it has already counted
      lab_.cycles.rows.push_back({std::floor(N), double(eng_->step_count() - 1), L.q_max, L.q_min, L.e_max, L.e_min,
                                  L.modulus(), L.damping(), m.p, m.eps_v, L.u_max / lab_.pc, L.g_max, L.g_min,
                                  L.shear_modulus(), 1.0, L.modulus_less_drag(), L.damping_less_drag(), L.sv_max,
                                  L.sv_min, L.constrained_modulus(), L.damping_v(), L.constrained_modulus_less_drag(),
                                  L.damping_v_less_drag(), lateral_ratio(m)});
      lab_.cycles.stage.push_back(lab_.stage);
      L.start(m.q, m.eps_a, m.gamma, m.u, q_drag, m.sz, drag[2]);
      if (stress_controlled(sc) && std::count(lab_.cycles.stage.begin(), lab_.cycles.stage.end(), lab_.stage) == 1)
        warn_dynamic_cycle(sc, quarter_transits(eng_->step_count() - 1));
    }
  }
  L.n = N;
  if (lab_.n_ru < 0 && sc.drainage == Drainage::Undrained && m.u >= sc.liquefaction_ru * lab_.pc) lab_.n_ru = N;
  if (lab_.n_da < 0 && std::abs(m.eps_a - lab_.eps_turn) >= sc.liquefaction_da_strain) lab_.n_da = N;
  if (turn) lab_.eps_turn = m.eps_a;
}

// How fast a stress-controlled stage loads depends on how far the sample strains to q = A, which only the run learns:
// its first quarter cycle (0 -> +A) against kQuasiStaticTransits wave transits, as plan_run checks a strain-controlled
// stage's. The rate that would give that many if the sample strained as far is not enough: loaded slower it strains
// less (on the tests' reference sample, 0.84/s gave 3.9 transits where 1/s gave 3.4), so the advice says to go below.
void Laboratory::warn_dynamic_loops(const StageConfig& sc) const {
  const double quarter = double(lab_.stage_step) * eng_->dt();
  if (!(quarter < kQuasiStaticTransits * transit_)) return;
  const ReversalStress r = reversal_stress(sc);
  std::fprintf(stderr,
               "grainlab: warning: stage %s: the first quarter cycle (%s = %.4g -> %.4g kPa) took %.3g ms, only %.3g times "
               "the ~%.3g ms a compression wave takes across the sample: the loops (cycles.csv) will measure its "
               "inertia as well as the material, %s and D too high; below axial_strain_rate = %.3g/s (%g transits if "
               "the sample strained as far; loaded slower it strains less)\n",
               sc.name.c_str(), r.name, r.x0 / 1e3, (r.x0 + r.A) / 1e3, quarter * 1e3, quarter / transit_,
               transit_ * 1e3, sc.sigma_v_reversal() ? "M_eq" : "E_eq",
               sc.axial_strain_rate * quarter / (kQuasiStaticTransits * transit_), kQuasiStaticTransits);
}

// The first quarter is the sample's first loading to q_0 + A, the softest: each later one, an unloading or a
// reloading, strains less to its peak and so takes less time at the same rate. On the tests' reference sample at q =
// +-38 kPa the first cycle's mean quarter is 3.5 transits where its first quarter was 3.9, at the rate that warning
// advised: the loops cycles.csv measures are dynamic and the first warning cannot know it. Hence a second look once
// the first cycle is complete, at the quarter summary.json reports (StageResult::quarter_transits).
void Laboratory::warn_dynamic_cycle(const StageConfig& sc, double quarter) const {
  if (!(quarter < kQuasiStaticTransits)) return;
  const ReversalStress r = reversal_stress(sc);
  std::fprintf(stderr,
               "grainlab: warning: stage %s: the first cycle (%s_amplitude %.4g kPa) took %.3g ms, its quarter only %.3g "
               "times the ~%.3g ms a compression wave takes across the sample (summary.json quarter_cycle_transits): "
               "its unloading and reloading are stiffer and quicker than the first quarter; the loops (cycles.csv) "
               "measure the sample's inertia as well as the material, %s and D too high; below axial_strain_rate = "
               "%.3g/s\n",
               sc.name.c_str(), r.name, r.A / 1e3, 4 * quarter * transit_ * 1e3, quarter, transit_ * 1e3,
               sc.sigma_v_reversal() ? "M_eq" : "E_eq", sc.axial_strain_rate * quarter / kQuasiStaticTransits);
}

// The cyclic oedometer's result (cycles.csv, this stage's whole cycles): the permanent axial strain at the end of the
// first and of the last cycle (eps_v there: the held lateral walls make it eps_a), the mean increment per cycle early
// (cycles 2 to 1 + k) and late (the last k), k a quarter of the cycles (at least 1; the first cycle, the virgin
// loading's, apart): ratcheting where the increment holds, shakedown where it falls towards nothing (on 2 000 spheres
// over 20 cycles it fell 2-10x at every amplitude, and single cycles' bursts blur which: configs/cyclic-oedometer-study.yaml),
// the exponent m of the rate's decay, rate ~ N^-m over doubling windows of cycles (src/rate_decay.hpp: 200 cycles of
// configs/cyclic-oedometer-long.yaml tell what 20 do not), and the first and last cycle's M_eq, D_v and K (the lateral
// stress the cycles leave at sigma_v,0).
void Laboratory::print_ratcheting(const StageConfig& sc) const {
  const size_t kE = column_of(cycle_columns(), "eps_v"), kM = column_of(cycle_columns(), "M_eq"),
               kD = column_of(cycle_columns(), "damping_v"), kK = column_of(cycle_columns(), "K"),
               kP = column_of(cycle_columns(), "p");
  std::vector<const std::vector<double>*> rows;
  for (size_t k = 0; k < lab_.cycles.rows.size(); ++k)
    if (lab_.cycles.stage[k] == lab_.stage && lab_.cycles.rows[k][kCycleComplete] == 1.0)
      rows.push_back(&lab_.cycles.rows[k]);
  if (rows.empty()) return;
  const auto& a = *rows.front();
  const auto& b = *rows.back();
  const size_t n = rows.size(), k = std::max<size_t>(1, n / 4);
  if (!sc.sigma_v_reversal()) {
    // Strain reversal brings eps_a back to 0 every cycle: the stress is what moves. sigma_v at a cycle's end from the
    // row's p' and K: p' = sigma_v (1 + 2 K) / 3.
    const auto sv = [&](const std::vector<double>& r) { return 3 * r[kP] / (1 + 2 * r[kK]); };
    std::printf("stage %s: cyclic oedometer (strain reversal): sigma_v at the cycles' ends (eps_a back at 0) %.4g -> "
                "%.4g kPa over %zu cycles; M_eq %.4g -> %.4g MPa, D_v %.4f -> %.4f, K %.4f -> %.4f (cycles.csv)\n",
                sc.name.c_str(), sv(a) / 1e3, sv(b) / 1e3, n, a[kM] / 1e6, b[kM] / 1e6, a[kD], b[kD], a[kK], b[kK]);
    return;
  }
  const auto after = [&](size_t cycle) { return (*rows[cycle - 1])[kE]; };  // the permanent strain after a cycle
  char rate[160];
  if (n >= 3 && k == 1)
    std::snprintf(rate, sizeof(rate), "%.3g %% in cycle 2, %.3g %% in cycle %zu", 100 * (after(2) - after(1)),
                  100 * (after(n) - after(n - 1)), n);
  else if (n >= 3)
    std::snprintf(rate, sizeof(rate), "per cycle %.3g %% over cycles 2-%zu, %.3g %% over %zu-%zu",
                  100 * (after(1 + k) - after(1)) / double(k), 1 + k, 100 * (after(n) - after(n - k)) / double(k),
                  n - k + 1, n);
  else
    std::snprintf(rate, sizeof(rate), "the last cycle's %.3g %%", 100 * (n > 1 ? after(n) - after(n - 1) : after(n)));
  // the rate's decay exponent over doubling windows (src/rate_decay.hpp), of the cycles numbered 1, 2, ... on
  const size_t kN = column_of(cycle_columns(), "cycle");
  std::vector<double> eps;
  for (const auto* r : rows)
    if ((*r)[kN] == double(eps.size() + 1)) eps.push_back((*r)[kE]);
  const RateDecay d = rate_decay(eps);
  char decay[200];
  if (d.ok)
    std::snprintf(decay, sizeof(decay), "rate ~ N^-m, m = %.2f +- %.2f over %zu doubling windows of cycles (m > 1: "
                  "bounded, shakedown; 1: eps_p = a + c ln N; 0: ratcheting)", d.m, d.se, d.windows);
  else
    std::snprintf(decay, sizeof(decay), "no rate exponent m: %s", d.why.c_str());
  std::printf("stage %s: cyclic oedometer: permanent eps_a %.4g %% after cycle 1, %.4g %% after cycle %zu (%s); %s; "
              "M_eq %.4g -> %.4g MPa, D_v %.4f -> %.4f, K = sigma_h/sigma_v at sigma_v,0 %.4f -> %.4f (cycles.csv)\n",
              sc.name.c_str(), 100 * a[kE], 100 * b[kE], n, rate, decay, a[kM] / 1e6, b[kM] / 1e6, a[kD], b[kD], a[kK],
              b[kK]);
}

// The run stops where a sphere-sphere overlap passes numerics.max_overlap (assert_healthy). Past three quarters of it,
// at a series row, it warns once a stage: a slow squeeze of contacts too soft for the load takes thousands of steps from
// there (a 2 000-sphere gas, E = 15 MPa, mu_r 0.3, ramped to 190 kPa over 20 000 steps: overlap_max 0.151 at step 9 000,
// the stop at step 15 799), which plan_run's estimate from the final pressure (0.044 of a radius on average there, under
// its threshold) cannot see: a loose gas carries the load on a few chains first (tests/data/soft_ramp.yaml). Not at
// half: runs that end well pass it for a while as a gas jams (the quick run's consolidation 0.107, the tests' runs
// 0.100-0.105; a shear of test_lab's at 1.7 MPa reaches 0.196 and is warned of).
void Laboratory::watch_overlap(const StageConfig& sc, Real deepest, const std::string& trial) {
  if (overlap_warned_ || !(deepest > 0.75 * cfg_.health.max_overlap)) return;
  overlap_warned_ = true;
  const Measure m = measure(sc);
  // A slower ramp only while an isotropic stage is still on its way to its pressure (assert_healthy argues it)
  const bool ramp = sc.type == StageType::Isotropic && m.p < kPressureReached * sc.pressure;
  std::fprintf(stderr,
               "grainlab: warning: %s: at step %ld (p = %.4g kPa) the deepest sphere-sphere overlap is %.3g of the "
               "smaller radius, past three quarters of numerics.max_overlap = %g, where the run stops: the contacts are soft for "
               "this load (raise material.E, lower the pressure%s, or allow deeper overlaps)\n",
               (trial.empty() ? "stage " + sc.name : trial).c_str(), eng_->step_count(), m.p / 1e3, deepest,
               double(cfg_.health.max_overlap),
               ramp ? " or ramp it in slower" : "");
}

void Laboratory::start_stage(const StageConfig& sc) {
  Engine& e = *eng_;
  lab_.mu = sc.mu;
  e.set_friction(sc.mu, sc.mu_r);
  e.set_damping(sc.damping);
  const Measure m0 = measure(sc);
  lab_.H0 = e.wall_position(5) - e.wall_position(4);
  lab_.V0 = e.box_volume();
  lab_.Wx0 = e.wall_position(1) - e.wall_position(0);
  // An undrained stage after an undrained one goes on with the pore pressure that stage left, as a triaxial cell
  // whose drainage stays closed does: u0 is that stage's u at this instant (measured with its p'_0, u_0, q_0 and
  // sigma'_y,0, which are still the lab's, by its own formula), and r_u stays relative to the p'_c its undrained
  // loading began from. A post-cyclic shear then starts at the r_u the cycles built up, not at 0, and a staged cyclic
  // test's liquefaction criterion counts every stage's cycles towards one r_u. After any other stage (drained,
  // oedometric, isotropic) u starts at 0 from the stress there, SPEC §6.3's.
  const auto undrained = [](const StageConfig& s) {
    return s.type != StageType::Isotropic && s.drainage == Drainage::Undrained;
  };
  const bool closed = undrained(sc) && lab_.stage > 0 && undrained(cfg_.stages[size_t(lab_.stage - 1)]);
  // that stage's u by that stage's own formula (plane strain's or SPEC's: the two differ where sigma_x != sigma_y, as
  // after a plane-strain stage), not this one's
  lab_.u0 = closed ? measure(cfg_.stages[size_t(lab_.stage - 1)]).u : 0;
  lab_.sy0 = m0.sy;
  lab_.p0 = sc.type == StageType::Isotropic ? sc.pressure : std::max<Real>(m0.p, 1e-30);
  if (!closed) lab_.pc = lab_.p0;
  // A shear after a shear stage (a K0 consolidation by an oedometric stage, a drained loading, a cycle) starts from
  // the anisotropic stress that stage left, as a triaxial cell's test of a K0-consolidated sample does: its cell
  // pressure is the lateral stress there, sigma_3 = p'_0 - q_0/3 (drained), the total stress then rises as the
  // axial load does, dp = dq/3, so u = p'_0 + (q - q_0)/3 - p' is 0 at the start (undrained), and a stress reversal
  // cycles about q_0. SPEC §6.3 starts from an isotropic stress, q_0 = 0: there (after an isotropic stage, or from a
  // sample file, which an isotropic stage wrote) exactly SPEC's formulas, and the bits of earlier runs.
  // A linear path (a stress probe) starts from the stress it finds whatever came before: its increments are from there,
  // and a consolidation's q within its tolerance (~1 % of p') is a fifth of a 5 kPa probe at 100 kPa.
  lab_.q0 = (sc.type != StageType::Isotropic && lab_.stage > 0 &&
             cfg_.stages[size_t(lab_.stage - 1)].type != StageType::Isotropic) ||
                    sc.lateral_slope
                ? m0.q
                : 0;
  lab_.aspect = (e.wall_position(1) - e.wall_position(0)) / (e.wall_position(3) - e.wall_position(2));
  lab_.last_eps = 0;
  lab_.last_time = e.time();
  lab_.next_snap_eps = cfg_.snapshot_strain;
  lab_.stage_step = 0;
  lab_.trial_mu.clear();
  lab_.trial_e.clear();
  lab_.searching = sc.type == StageType::Isotropic && sc.target_e0 > 0;
  lab_.half_cycles = 0;
  lab_.cycle = 0;
  lab_.eps_turn = 0;
  lab_.n_ru = lab_.n_da = -1;
  lab_.loop = CycleLoop{};
  for (int k = 0; k < 6; ++k) {
    WallControl& c = e.wall_control(k);
    c = WallControl{};
    c.gain = sc.servo_gain;
    c.integral = sc.servo_integral;
    if (sc.type == StageType::Isotropic) {
      c.mode = WallMode::Servo;
      c.target_stress = sc.pressure;
    } else if (k >= 4) {
      c.mode = WallMode::Velocity;  // axial walls approach each other at the strain rate (recede, in extension)
      c.velocity = (sc.extension ? -0.5 : 0.5) * sc.axial_strain_rate * lab_.H0;
    } else if (sc.drainage == Drainage::Drained && !(sc.plane_strain && k < 2)) {
      c.mode = WallMode::Servo;
      // sigma_3 = p'_0 (SPEC §6.3), or the lateral stress of an anisotropic start
      c.target_stress = lab_.p0 - lab_.q0 / 3;
    } else {
      // plane strain's x walls: held where the stage finds them (StageConfig::plane_strain)
      c.mode = WallMode::Fixed;  // undrained: placed analytically every step; oedometric: held where they are
    }
  }
  lab_.started = true;
  // The cyclic oedometer's unloading half cycle to sigma_v,0 - A (config.cpp refuses an A past a sigma_v,0 it can
  // read from the stage before; here the measured one, after a stage that ends elsewhere)
  const ReversalStress r = reversal_stress(sc);
  if (sc.type == StageType::Cyclic && sc.sigma_v_reversal() && !(r.A < r.x0)) {
    std::ostringstream os;
    os << std::setprecision(4) << "stage '" << sc.name << "': sigma_v_amplitude = " << r.A / 1e3
       << " kPa reaches below zero from the vertical stress the cycles start from, sigma_v,0 = " << r.x0 / 1e3
       << " kPa: give an amplitude below it";
    stop_run(os.str());
  }
}

void Laboratory::place_lateral_walls(const StageConfig& sc) {
  // Exact constant volume (SPEC §6.3 undrained): the lateral walls are placed every step so that
  // Lx Ly H = V0 at the stage's initial aspect ratio, about the current centre.
  Engine& e = *eng_;
  const Real H = e.wall_position(5) - e.wall_position(4);
  const Real cx = 0.5 * (e.wall_position(0) + e.wall_position(1));
  const Real cy = 0.5 * (e.wall_position(2) + e.wall_position(3));
  if (sc.plane_strain) {
    // plane strain: the x walls stay where the stage found them, the y walls alone keep the volume
    const Real Lx = e.wall_position(1) - e.wall_position(0);
    const Real Ly = lab_.V0 / (H * Lx);
    e.set_wall_position(2, cy - 0.5 * Ly);
    e.set_wall_position(3, cy + 0.5 * Ly);
    return;
  }
  const Real Ly = std::sqrt(lab_.V0 / (H * lab_.aspect));
  const Real Lx = lab_.V0 / (H * Ly);
  e.set_wall_position(0, cx - 0.5 * Lx);
  e.set_wall_position(1, cx + 0.5 * Lx);
  e.set_wall_position(2, cy - 0.5 * Ly);
  e.set_wall_position(3, cy + 0.5 * Ly);
}

// Isotropic stages with pressure_ramp_steps > 0: the servo target at the stage's step `stage_step` (a pure
// function of it, so a resumed run sets the same targets). A loose gas compacted straight to the full
// target forms a few sparse force chains that carry all of it before the gas jams: 3 000 spheres from
// solid fraction 0.30 with mu_r = 0.3 "reached" 190 kPa at e = 1.46, Z = 0.8 and squeezed a small sphere
// past the 0.2 r overlap limit at step 2 800. Raising the target gradually lets the network densify at
// low stress first.
void Laboratory::ramp_pressure(const StageConfig& sc, long stage_step) {
  if (sc.type != StageType::Isotropic || sc.pressure_ramp_steps <= 0) return;
  const Real frac = std::min<Real>(1, Real(stage_step) / Real(sc.pressure_ramp_steps));
  for (int k = 0; k < 6; ++k) eng_->wall_control(k).target_stress = frac * sc.pressure;
}

Laboratory::TrialEnd Laboratory::trial_consolidation(const StageConfig& sc, const EngineState& s0, Real mu) {
  Engine& e = *eng_;
  e.restore(s0);
  e.set_friction(mu, sc.mu_r);
  TrialEnd end;
  // A trial is checked as a stage is (run_stage): a trial that blew up (a sphere squeezed past numerics.max_overlap,
  // a NaN) stops the run with the stage's advice, where before its void ratio went on into the search unchecked.
  std::ostringstream trial_os;
  trial_os << std::setprecision(4) << "stage " << sc.name << ", target_e0 trial " << lab_.trial_mu.size() + 1
           << " (mu = " << mu << ")";
  const std::string trial = trial_os.str();
  long s = 0;
  for (; s < sc.max_steps; ++s) {
    const bool check = ((s + 1) % sc.check_every) == 0;
    bool done = false;
    if (check) {
      e.evaluate();
      assert_healthy(s + 1, trial);
      // once a search (search_e0 clears it; run_stage again after the search, for the stage's own run)
      if (!overlap_warned_) watch_overlap(sc, std::max(Real(0), e.deepest_overlap().ratio), trial);
      watch_core_share();  // a search of a large sample is hours of trials: a host shared with others warns here too
      done = isotropic_done(sc, e.diagnostics());
      ramp_pressure(sc, s + 1);
      e.advance();
    } else {
      ramp_pressure(sc, s + 1);
      e.step();  // nothing measured between the halves: the fused step, the same bits (see run_stage)
    }
    ++total_steps_;
    if (done) {
      end.converged = true;
      break;
    }
    if (stop_requested()) {
      end.interrupted = true;
      trial_steps_ = s + 1;
      return end;
    }
    if (g_checkpoint != 0) {
      // SIGUSR1 (SignalGuard): a search's checkpoint is its stage start and the trials finished (what a resume takes
      // up; search_e0), written from s0 and leaving this trial's state alone, so the run goes on to the same bits.
      g_checkpoint = 0;
      const std::string path = write_checkpoint(&s0);
      progress("", true);
      std::fprintf(stderr, "checkpoint at step %ld (SIGUSR1): %s, the start of stage %s and its %zu finished target_e0 "
                   "trial(s): a resume repeats trial %zu (at its step %ld now); the run goes on\n", s0.step, path.c_str(),
                   sc.name.c_str(), lab_.trial_mu.size(), lab_.trial_mu.size() + 1, s + 1);
    }
    if (s % 5000 == 0) {
      std::ostringstream os;
      os << std::setprecision(4) << sc.name << " | target_e0 " << sc.target_e0 << " | trial " << lab_.trial_mu.size() + 1
         << " mu = " << mu << " | step " << s << " | p = " << measure(sc).p / 1e3 << " kPa";
      progress(os.str());
    }
  }
  end.steps = std::min(s + 1, sc.max_steps);
  assert_healthy(end.steps, trial);  // the steps since the last check, before e is taken
  end.e = measure(sc).e;
  return end;
}

bool Laboratory::search_e0(const StageConfig& sc) {
  // e after consolidation grows with the preparation friction (SPEC §6.2): bracket [0, mu_max], then
  // regula falsi (Illinois) on e(mu) - target. Each trial starts from the same stage-start state s0.
  const EngineState s0 = eng_->capture();
  overlap_warned_ = false;  // the search warns once of deep overlaps, its stage's run (run_stage) once more
  auto next_mu = [&]() -> Real {
    const size_t n = lab_.trial_mu.size();
    if (n == 0) return 0;
    if (n == 1) return sc.mu_max;
    // On a small sample e(mu) is monotone only on average (+-0.005 of noise at a few hundred spheres), so
    // the trials are ordered by mu and the narrowest adjacent pair whose void ratios straddle the target
    // is refined, by interpolation kept within 10-90 % of the pair: never a repeated mu, and the
    // interval always shrinks.
    std::vector<std::pair<Real, Real>> t;
    for (size_t k = 0; k < n; ++k) t.emplace_back(lab_.trial_mu[k], lab_.trial_e[k]);
    std::sort(t.begin(), t.end());
    Real best_w = 1e300, mu = -1;
    for (size_t k = 0; k + 1 < t.size(); ++k) {
      const Real a = t[k].second - sc.target_e0, b = t[k + 1].second - sc.target_e0;
      const Real w = t[k + 1].first - t[k].first;
      if (a * b > 0 || w <= 0 || w >= best_w) continue;
      const Real f = std::min<Real>(0.9, std::max<Real>(0.1, a / (a - b)));
      best_w = w;
      mu = t[k].first + f * w;
    }
    return mu;  // -1: the target lies outside [e(0), e(mu_max)]
  };
  if (!opt_.quiet)  // a resumed search: the trials its checkpoint holds, so the log shows the whole search
    for (size_t k = 0; k < lab_.trial_mu.size(); ++k)
      std::printf("%s: target_e0 %.4f: trial %zu mu = %.4f -> e = %.4f (run before the resume)\n", sc.name.c_str(),
                  sc.target_e0, k + 1, lab_.trial_mu[k], lab_.trial_e[k]);
  while (int(lab_.trial_mu.size()) < sc.max_trials) {
    // Converged?
    for (size_t k = 0; k < lab_.trial_mu.size(); ++k)
      if (std::abs(lab_.trial_e[k] - sc.target_e0) <= sc.target_e0_tolerance) goto found;
    {
      const Real mu = next_mu();
      if (mu < 0) break;
      const TrialEnd t = trial_consolidation(sc, s0, mu);
      if (t.interrupted) {
        eng_->restore(s0);
        return false;
      }
      lab_.trial_mu.push_back(mu);
      lab_.trial_e.push_back(t.e);
      if (!opt_.quiet) {
        progress("", true);
        // A trial out of steps is no equilibrium's e (as a stage's "NOT converged" line says of its end)
        std::printf("%s: target_e0 %.4f: trial %zu mu = %.4f -> e = %.4f %s %ld steps%s\n", sc.name.c_str(),
                    sc.target_e0, lab_.trial_mu.size(), mu, t.e, t.converged ? "in" : "(NOT converged in", t.steps,
                    t.converged ? "" : ", its max_steps: e taken there; raise max_steps)");
        std::fflush(stdout);  // a batch job's log shows each trial as it ends (a trial of a large sample takes hours)
      }
      eng_->restore(s0);
      write_checkpoint();  // stage-start state + the trials so far: a resume skips finished trials
    }
  }
found : {
  size_t best = 0;
  for (size_t k = 1; k < lab_.trial_mu.size(); ++k)
    if (std::abs(lab_.trial_e[k] - sc.target_e0) < std::abs(lab_.trial_e[best] - sc.target_e0)) best = k;
  lab_.mu = lab_.trial_mu[best];
  if (std::abs(lab_.trial_e[best] - sc.target_e0) > sc.target_e0_tolerance && !opt_.quiet)
    std::printf("%s: target_e0 %.4f NOT reached within %.4g (reachable here: e in [%.4f, %.4f]); using mu = %.4f "
                "(e = %.4f)\n",
                sc.name.c_str(), sc.target_e0, sc.target_e0_tolerance,
                *std::min_element(lab_.trial_e.begin(), lab_.trial_e.end()),
                *std::max_element(lab_.trial_e.begin(), lab_.trial_e.end()), lab_.mu, lab_.trial_e[best]);
}
  lab_.searching = false;
  eng_->restore(s0);
  eng_->set_friction(lab_.mu, sc.mu_r);
  return true;
}

void Laboratory::progress(const std::string& line, bool final) {
  if (opt_.quiet) return;
  if (tty_) {
    if (final) std::printf("\r%-120s\r", "");
    else std::printf("\r%-120s", line.c_str());
    std::fflush(stdout);
  } else if (!final) {
    // In a log (a file, a pipe: a batch job's output) every line stays: at most one a second (each stage's first
    // at once), or a dense series (output.every 10 on a 1e6-step run: 1e5 rows) fills it with 15 MB of lines the
    // series has. A terminal's line is rewritten in place, so it shows every row.
    const auto now = std::chrono::steady_clock::now();
    if (last_log_line_ != decltype(last_log_line_){} && now - last_log_line_ < std::chrono::seconds(1)) return;
    last_log_line_ = now;
    std::printf("%s\n", line.c_str());
    std::fflush(stdout);
  }
}

// The process's CPU time, user and system, in seconds.
double process_cpu_seconds() {
  rusage u{};
  if (getrusage(RUSAGE_SELF, &u) != 0) return std::nan("");
  return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// Threads that share their cores with other processes: OpenMP threads wait for each other at the end of every kernel
// (several a step), so a thread the scheduler has set aside stalls the rest, each stall up to a time slice. A run of
// several threads then slows far past its share of the cores: on the 2-core VM two 2-thread runs of 400 spheres at
// once took 0.67 to 152 s each against 0.3 s alone (up to 400x; one beside a busy loop: 3-10x), two 10 000-sphere
// benchmarks each ran at 2.2-3.4e6 particle-steps/s against 7-9e6 alone (perf/core_share.sh). `--threads`
// cannot see other processes; the run can: its CPU time over a window of stepping is the cores it got (a spinning
// thread counts too, so this is an upper bound of the useful share). Two windows in a row under kShareWarn of the
// threads say so once a run; the kernels' pool idles only in serial work (I/O, the stage ends: start_core_share
// leaves those out), seconds of it in a window at most.
constexpr double kShareWindow = 5;  // s
constexpr double kShareWarn = 0.75;  // of the threads: a busy loop beside a 2-thread run on 2 cores left it 0.55-0.6
void Laboratory::start_core_share() {
  share_t0_ = std::chrono::steady_clock::now();
  share_cpu0_ = process_cpu_seconds();
  share_short_ = 0;
}

void Laboratory::watch_core_share() {
  const int threads = ExecSpace().concurrency();
  if (share_warned_ || threads < 2 || !Kokkos::SpaceAccessibility<ExecSpace, Kokkos::HostSpace>::accessible) return;
  const auto now = std::chrono::steady_clock::now();
  const double wall = std::chrono::duration<double>(now - share_t0_).count();
  if (wall < kShareWindow) return;
  const double cpu = process_cpu_seconds(), cores = (cpu - share_cpu0_) / wall;
  share_t0_ = now;
  share_cpu0_ = cpu;
  if (!(cores < kShareWarn * threads)) {
    share_short_ = 0;
    return;
  }
  if (++share_short_ < 2) return;
  share_warned_ = true;
  // Bound (OMP_PROC_BIND, OMP_PLACES), every run started alike takes the same first places, whatever its --threads
  const auto places = compat::openmp_places();
  const std::string bound = places.empty() ? ""
                                           : ", and, as OpenMP binds threads here (to places " +
                                                 compat::places_text(places) + "), each its own OMP_PLACES";
  std::fprintf(stderr,
               "grainlab: warning: over the last %.3g s this run's %d threads had %.3g cores' worth of CPU time: other "
               "processes (or, on a virtual machine, other guests) are using its cores, and OpenMP threads wait on each "
               "other at every kernel's end, so it runs far slower than its share (two 2-thread runs of 400 spheres on "
               "2 cores at once: up to 400x each); give each run --threads so that together they fit the cores%s (a "
               "study does so for its jobs), or stop the others\n",
               wall, threads, cores, bound.c_str());
}

bool Laboratory::run_stage(const StageConfig& sc) {
  Engine& e = *eng_;
  e.set_affine_box(sc.type == StageType::Isotropic && sc.affine);  // here, not in start_stage: a resumed stage too
  if (lab_.searching && !search_e0(sc)) return false;
  stage_t0_ = std::chrono::steady_clock::now();
  last_log_line_ = {};  // each stage's first row is logged
  stage_step0_ = lab_.stage_step;
  overlap_warned_ = false;
  sv_end_ = sigma_v_end(sc, lab_.stage);
  bool ended_on_stress = false;  // the stage's end: its stress end met (else its strain, or max_steps)
  Real s_end = 0;                // the ended-on stress (sigma_z, q, q/p', |dsigma|) where it ended, as shear_end found it
  start_core_share();  // not the stage ends' serial writes (samples, snapshots), where the pool's threads sleep
  int rows_since_flush = 0;
  bool done = false;
  Measure final_m{};
  long final_step = 0;  // the step of final_m (the stage's last series row)
  std::string unmet;    // an isotropic stage out of steps: the equilibrium criteria it missed on its last step
  while (lab_.stage_step < sc.max_steps) {
    // What this step does is known before it runs: counters, and the axial strain, which comes from the
    // wall positions that evaluate() leaves alone.
    const bool report = (e.step_count() % cfg_.output_every) == 0;
    const bool last_step = lab_.stage_step + 1 == sc.max_steps;
    const bool check = ((lab_.stage_step + 1) % sc.check_every) == 0 || last_step;
    const bool shear = sc.type != StageType::Isotropic, cyclic = sc.type == StageType::Cyclic;
    const Measure m0 = shear ? measure(sc) : Measure{};
    // The end strain is caught on the first step that reaches it (it used to wait for the next check,
    // report or snapshot step: up to check_every - 1 steps past max_axial_strain).
    const bool strain_end = shear_end(sc, m0);
    if (strain_end) {
      ended_on_stress = stress_end(sc, m0);
      s_end = sc.q_end ? m0.q : sc.eta_end ? m0.q / m0.p : sc.dsigma_end ? stress_increment(m0) : m0.sz;
    }
    const bool turn = cyclic && !strain_end && cyclic_turn(sc, m0);
    if (lateral_servo(sc) && moving_lateral_targets(sc)) {
      // True triaxial (StageConfig::b), the constant-p' path (StageConfig::constant_p): the lateral walls' targets
      // as this step finds sigma_z, from what a checkpoint restores, so a resumed run sets the same targets.
      const LateralTargets t = lateral_targets(sc, lab_.p0, lab_.q0, m0.sz);
      // On the constant-p' path sigma_3 falls as sigma_z rises; at sigma_z = 3 p'_0 / (1 + b) it would reach 0
      // (q/p' = 3 at b = 0: beyond any frictional packing's strength, so a packing there is no longer a soil sample).
      // A linear path of negative slope does the same, and one of slope above 1 in extension.
      if (t.sy < 0.01 * lab_.p0) {
        std::ostringstream os;
        os << std::setprecision(4) << "stage '" << sc.name << "' stopped at step " << e.step_count() << " (eps_a = "
           << m0.eps_a << "): on the " << (sc.lateral_slope ? "linear" : "constant-p'") << " path sigma_3 would be "
           << t.sy / 1e3 << " kPa with sigma_z = " << m0.sz / 1e3 << " kPa (p'_0 = " << lab_.p0 / 1e3 << " kPa";
        if (sc.lateral_slope) os << ", lateral_slope " << *sc.lateral_slope;
        os << "): the lateral walls cannot hold " << (sc.lateral_slope ? "the path" : "p'_0")
           << " with a positive confinement" << (sc.lateral_slope ? ": end the stage before (sigma_v, q)" : "");
        stop_run(os.str());
      }
      for (int k = 0; k < 4; ++k) e.wall_control(k).target_stress = k < 2 ? t.sx : t.sy;
    }
    const Real cycle_n = cyclic ? watch_cycle_number(sc, m0) : 0;  // watch_cycle's N, as the step finds it
    // A damped cyclic stage's loops less the drag want the drag of every step's kick: the step measures it.
    const bool loop_drag = cyclic && sc.damping > 0;
    Vec3d drag{};  // the local damping's drag of this step's kick per axis, a stress (a damped cyclic stage's loops)
    if (turn && lab_.half_cycles == 1 && stress_controlled(sc)) warn_dynamic_loops(sc);
    // Snapshots: every snapshot_strain of eps_a in a triaxial stage, at every load reversal in a cyclic one.
    const bool snap =
        shear && cfg_.snapshot_strain > 0 && (cyclic ? turn : strain_along(sc, m0.eps_a) >= lab_.next_snap_eps);
    if (!(report || check || snap || strain_end)) {
      // An ordinary step measures nothing between its halves, so it takes the fused step(): bitwise
      // evaluate() + advance() (test Determinism.FusedWallLoadsEqualSeparatePass), one pass fewer over
      // the particles on host backends (perf/NOTES.md attempt 21).
      ++lab_.stage_step;
      ramp_pressure(sc, lab_.stage_step);  // servo targets: read when the walls move, at the step's end
      if (loop_drag) {
        const Real V = e.box_volume();  // the walls' at this instant: the step moves them at its end
        drag = drag_of(e.step_measuring_drag(box_centre()), V);
      } else {
        e.step();
      }
    } else {
      e.evaluate();  // x(t), pair forces, history and wall loads now belong to the same instant
      ++lab_.stage_step;
      const Measure m = measure(sc);
      const Diagnostics d = e.diagnostics();
      if (report) {
        lab_.series.rows.push_back(row(sc, m, d));
        lab_.series.stage.push_back(lab_.stage);
        const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - stage_t0_).count();
        const double rate = (lab_.stage_step - stage_step0_) / std::max(el, 1e-9);
        // A rate (and an ETA from it) once there is one to measure: the stage's first step or two timed with the
        // row's own measurement said "2.85e+03 steps/s" where the run went at 5e3.
        const bool timed = lab_.stage_step - stage_step0_ >= 50;
        std::ostringstream line;
        line << std::setprecision(4) << sc.name << " | step " << e.step_count() << " | p = " << m.p / 1e3
             << " kPa | q = " << m.q / 1e3 << " kPa | e = " << m.e;
        if (sc.type == StageType::Triaxial) {
          line << " | eps_a = " << m.eps_a;
          const double steps_left =
              sc.axial_strain_rate == 0
                  ? double(sc.max_steps - lab_.stage_step)  // a rest
                  : (sc.max_axial_strain - strain_along(sc, m.eps_a)) / std::max(1e-30, sc.axial_strain_rate * e.dt());
          // a stress-ended stage's ETA is its strain cap's: an upper bound (the stress may come first)
          if (timed)
            line << " | ETA " << (sc.stress_ended() ? "<= " : "") << std::setprecision(3)
                 << steps_left / std::max(rate, 1e-9) << " s";
        } else if (cyclic) {
          line << " | eps_a = " << m.eps_a << " | cycle " << lab_.cycle << " of " << sc.cycles;
        } else {
          line << " | ufr = " << d.unbalanced_ratio;
        }
        if (timed) line << " | " << std::setprecision(3) << rate << " steps/s";
        progress(line.str());
        watch_core_share();
        if (flush_due(++rows_since_flush)) {
          flush_outputs();
          rows_since_flush = 0;
        }
        check_servo(sc, m);
        watch_overlap(sc, lab_.series.rows.back()[series_column("overlap_max")]);
      }
      if (check) {
        assert_healthy(lab_.stage_step);
        // on its last step an isotropic stage keeps what it missed: its warning if it ends there unconverged
        done = sc.type == StageType::Isotropic ? isotropic_done(sc, d, last_step ? &unmet : nullptr) : strain_end;
      }
      if (snap) {
        snapshot(sc.name + (cyclic ? "_peak" + std::to_string(lab_.half_cycles) : "_eps" + std::to_string(lab_.snapshots)));
        while (!cyclic && lab_.next_snap_eps <= strain_along(sc, m.eps_a)) lab_.next_snap_eps += cfg_.snapshot_strain;
      }
      if (strain_end) done = true;
      if (done || last_step) {
        // The stage's final row and snapshot, at the very instant its end criteria were evaluated.
        if (!report) {
          lab_.series.rows.push_back(row(sc, m, d));
          lab_.series.stage.push_back(lab_.stage);
          check_servo(sc, m);
        }
        final_m = m;
        final_step = e.step_count();
        if (!snap) snapshot(sc.name + "_end");
      }
      ramp_pressure(sc, lab_.stage_step);
      // The drag of this kick (drag_of is drag_stress()'s arithmetic: a row of this instant has the same bits).
      if (loop_drag) drag = drag_of(e.damping_moment(box_centre()), e.box_volume());
      e.advance();  // a step always completes: the history increments of evaluate() are already applied
    }
    if (cyclic) watch_cycle(sc, m0, turn, cycle_n, drag);
    ++total_steps_;
    if (sc.type != StageType::Isotropic && sc.drainage == Drainage::Undrained) place_lateral_walls(sc);
    if (done) break;
    const bool ckpt_steps = cfg_.checkpoint_every > 0 && e.step_count() % cfg_.checkpoint_every == 0;
    const bool ckpt_time =
        cfg_.checkpoint_minutes > 0 &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - last_ckpt_).count() > 60 * cfg_.checkpoint_minutes;
    const bool ckpt_asked = g_checkpoint != 0;  // SIGUSR1 (SignalGuard)
    if (ckpt_steps || ckpt_time || ckpt_asked) {
      g_checkpoint = 0;
      const std::string path = write_checkpoint();
      if (ckpt_asked) {
        progress("", true);
        // Even with --quiet, as an interruption's line: the one who sent the signal learns where the state is
        std::fprintf(stderr, "checkpoint at step %ld (SIGUSR1): %s; the run goes on\n", e.step_count(), path.c_str());
      }
    }
    if (stop_requested()) return false;
  }
  progress("", true);
  StageResult res;
  res.name = sc.name;
  res.converged = done;
  res.steps = lab_.stage_step;
  res.mu = lab_.mu;
  const Measure& m = final_m;
  res.p = m.p;
  res.q = m.q;
  res.e = m.e;
  if (sc.type == StageType::Cyclic) {
    res.cycle = lab_.cycle;
    res.n_ru = lab_.n_ru;
    res.n_da = lab_.n_da;
    // The first complete cycle of this stage: its cycles.csv row's step, from the stage's first step.
    for (size_t k = 0; k < lab_.cycles.rows.size(); ++k)
      if (lab_.cycles.stage[k] == lab_.stage) {
        res.quarter_transits = quarter_transits(long(lab_.cycles.rows[k][1]));
        break;
      }
    // A stage that ended inside a cycle (max_axial_strain: the sample liquefied or failed; or max_steps): that cycle's
    // row as far as it went, complete 0. A stage that did its cycles has just started the next loop at its last
    // measure: nothing in it.
    const CycleLoop& L = lab_.loop;
    if (L.open && (L.e_max > L.e_min || L.q_max > L.q_min)) {
      lab_.cycles.rows.push_back({std::floor(L.n) + 1, double(final_step), L.q_max, L.q_min, L.e_max, L.e_min,
                                  L.modulus(), std::nan(""), m.p, m.eps_v, L.u_max / lab_.pc, L.g_max, L.g_min,
                                  L.shear_modulus(), 0.0, L.modulus_less_drag(), std::nan(""), L.sv_max, L.sv_min,
                                  L.constrained_modulus(), std::nan(""), L.constrained_modulus_less_drag(), std::nan(""),
                                  lateral_ratio(m)});
      lab_.cycles.stage.push_back(lab_.stage);
    }
  }
  res.servo_error = stage_servo_error(sc);
  if (sc.type != StageType::Isotropic) {  // the lab's start values are still this stage's (start_stage)
    res.p0 = lab_.p0;
    res.q0 = lab_.q0;
    res.u0 = lab_.u0;
    res.pc = lab_.pc;
    res.u = m.u;
  }
  if (sc.type == StageType::Isotropic) {
    res.e_inner = inner_void_ratio();
    res.e_core = core_void_ratio();
  }
  lab_.results.push_back(res);
  write_summary();
  if (sc.type == StageType::Isotropic && sc.save_sample) save_sample(sc);
  if (sc.type == StageType::Isotropic) warn_graded(sc, res);
  if (sc.type == StageType::Triaxial && sc.stress_ended() && done) {
    // The stress end asked for, against where the stage ended: at max_axial_strain short of it (a q beyond the
    // sample's peak, a sigma_v beyond the strain), or on its first step (the stress already past it: a loading to less
    // than the sample carries, an unloading to more).
    const bool ratio = sc.eta_end.has_value(), deviator = ratio || sc.q_end;
    // "q/p' = 0.5", "q = 100 kPa": the stress as it ended, and its end
    const auto stress = [&](const char* what, Real v) {
      return std::string(what) + " = " + (ratio ? sig4(v) : sig4(v / 1e3) + " kPa");
    };
    const char* what = ratio ? "q/p'" : sc.q_end ? "q" : sc.dsigma_end ? "|sigma - sigma_0|" : "sigma_v";
    const std::string at = stress(what, s_end);
    const std::string end = ratio      ? stress(what, *sc.eta_end)
                            : sc.q_end ? stress(what, *sc.q_end)
                            : sc.dsigma_end ? stress(what, *sc.dsigma_end)
                            : sc.ocr > 0 ? "sigma_v,max / ocr = " + sig4(sigma_v_max(lab_.stage) / 1e3) + " / " + sig4(sc.ocr) +
                                             " = " + sig4(sv_end_ / 1e3) + " kPa"
                                       : stress(what, sv_end_);
    if (!ended_on_stress)
      std::fprintf(stderr, "grainlab: warning: stage %s ended at max_axial_strain = %g with %s, short of its end %s: %s\n",
                   sc.name.c_str(), sc.max_axial_strain, at.c_str(), end.c_str(),
                   deviator ? "raise max_axial_strain, or end below the sample's peak" : "raise max_axial_strain");
    else if (stage_step0_ == 0 && lab_.stage_step == 1)
      std::fprintf(stderr,
                   "grainlab: warning: stage %s: %s at its start, already past its end %s: it ended on its first step\n",
                   sc.name.c_str(), at.c_str(), end.c_str());
    else if (!opt_.quiet)
      std::printf("stage %s: ended at %s, its end %s\n", sc.name.c_str(), at.c_str(), end.c_str());
  }
  if (sc.type == StageType::Isotropic && !done)  // even with --quiet: what follows starts from a sample not at rest
    std::fprintf(stderr, "grainlab: warning: stage %s: not in equilibrium at its max_steps = %ld%s%s%s: the sample it "
                 "leaves is not at rest (summary.json: done false); raise its max_steps\n", sc.name.c_str(),
                 sc.max_steps, unmet.empty() ? "" : " (", unmet.c_str(), unmet.empty() ? "" : ")");
  if (!opt_.quiet) {
    std::printf("stage %s: %s after %ld steps, mu = %.4g, p = %.4g kPa, q = %.4g kPa, e = %.4f\n", sc.name.c_str(),
                done ? "done" : "NOT converged (max_steps reached)", lab_.stage_step, lab_.mu, m.p / 1e3, m.q / 1e3, m.e);
    // a probe's (a linear path's) increments, directions and stiffness, as the study report gives them
    if (sc.lateral_slope) {
      const ProbeIncrements pi = probe_increments(size_t(lab_.stage), res);
      const auto angle = [](Real x, Real y) { return std::fmod(std::atan2(y, x) * 180 / M_PI + 360, 360.0); };
      std::printf("stage %s: dsigma (sqrt2 r, a) = (%.4g, %.4g) kPa along %.4g deg, deps = (%.4g, %.4g) x 1e-4 along "
                  "%.4g deg: |dsigma|/|deps| = %.4g MPa\n",
                  sc.name.c_str(), pi.ds_r / 1e3, pi.ds_a / 1e3, angle(pi.ds_r, pi.ds_a), pi.de_r * 1e4, pi.de_a * 1e4,
                  angle(pi.de_r, pi.de_a), std::hypot(pi.ds_r, pi.ds_a) / std::hypot(pi.de_r, pi.de_a) / 1e6);
    }
    if (sc.type == StageType::Cyclic)
      std::printf("stage %s: cycle %.4g of %ld%s, eps_a = %.4g, p'/p'_0 = %.4g\n", sc.name.c_str(), lab_.cycle, sc.cycles,
                  std::abs(m.eps_a) >= sc.max_axial_strain ? " (stopped at |eps_a| = max_axial_strain)" : "", m.eps_a,
                  m.p / lab_.pc);
    // the amplitude the cycles reversed at, and the cyclic stress ratio it is of the p' they started from (csr: as
    // given; q_amplitude: after a K0 or drained stage, not the one of the preparation's pressure)
    if (sc.type == StageType::Cyclic && sc.stress_reversal())
      std::printf("stage %s: q = %.4g +- %.4g kPa, CSR = %.4g of p'_c = %.4g kPa\n", sc.name.c_str(), lab_.q0 / 1e3,
                  q_amplitude(sc, lab_.pc) / 1e3, q_amplitude(sc, lab_.pc) / (2 * lab_.pc), lab_.pc / 1e3);
    if (sc.type == StageType::Cyclic && sc.sigma_v_reversal())
      std::printf("stage %s: sigma_v = %.4g +- %.4g kPa\n", sc.name.c_str(), reversal_stress(sc).x0 / 1e3,
                  sc.sigma_v_amplitude / 1e3);
    if (sc.type == StageType::Cyclic && sc.drainage == Drainage::Oedometric) print_ratcheting(sc);
    if (sc.type == StageType::Cyclic && sc.drainage != Drainage::Oedometric) {
      auto at = [](Real n) {
        char b[48];
        std::snprintf(b, sizeof(b), "met at N = %.4g", n);
        return n < 0 ? std::string("not met") : std::string(b);
      };
      std::printf("stage %s: liquefaction: r_u >= %g %s; double-amplitude eps_a >= %g %s\n", sc.name.c_str(),
                  sc.liquefaction_ru, sc.drainage == Drainage::Undrained ? at(lab_.n_ru).c_str() : "(drained: none)",
                  sc.liquefaction_da_strain, at(lab_.n_da).c_str());
    }
    // How much of the walls' q the local damping's drag carries (series q_drag) at the stage's final row: on a flowing
    // sample the walls' stress overstates the material's by it, and it falls with the strain rate and the damping
    // (configs/damping-drag.yaml: 11.9 / 4.4 / 1.3 % of q at 4 / 1 / 0.25 per s, 2 000 spheres, damping 0.2).
    if (sc.type == StageType::Triaxial && sc.damping > 0 && sc.axial_strain_rate > 0 && !lab_.series.rows.empty() &&
        lab_.series.stage.back() == lab_.stage) {  // (a rest ends at rest: no drag to speak of)
      const auto& row = lab_.series.rows.back();
      const double q = row[series_column("q")], p = row[series_column("p")];
      const double qd = row[series_column("q_drag")], pd = row[series_column("p_drag")];
      if (std::abs(q) > 0.01 * p && p > 0 && p - pd > 0)  // not a stage that ended at q ~ 0 (a 1-step stage)
        std::printf("stage %s: the damping's drag is %.1f %% of the walls' q at its end (q/p' %.3f of the walls, %.3f less "
                    "the drag; series q_drag): a slower shear or less damping lowers it\n",
                    sc.name.c_str(), 100 * qd / q, std::fabs(q / p), std::fabs((q - qd) / (p - pd)));
    }
    // A cyclic stage's: the share of its last whole cycle's damping ratio that is the drag's area (cycles.csv). On
    // configs/modulus_damping.yaml (damping 0.1) 30-60 % of D at eps_a = 1e-5, 2-6 % from 1e-4 on.
    if (sc.type == StageType::Cyclic && sc.damping > 0) {
      // (the cyclic oedometer's: its sigma_v loop's D_v)
      const bool oed = sc.drainage == Drainage::Oedometric;
      const size_t kD = column_of(cycle_columns(), oed ? "damping_v" : "damping"),
                   kDn = column_of(cycle_columns(), oed ? "damping_v_less_drag" : "damping_less_drag");
      for (size_t k = lab_.cycles.rows.size(); k-- > 0 && lab_.cycles.stage[k] == lab_.stage;) {
        const auto& row = lab_.cycles.rows[k];
        if (row[kCycleComplete] != 1.0) continue;
        if (row[kD] > 0 && row[kDn] == row[kDn])
          std::printf("stage %s: the damping's drag is %.1f %% of the damping ratio of its last cycle (%s %.4f of the "
                      "walls' loop, %.4f less the drag; cycles.csv %s): a slower cycle or less damping lowers it\n",
                      sc.name.c_str(), 100 * (row[kD] - row[kDn]) / row[kD], oed ? "D_v" : "D", row[kD], row[kDn],
                      oed ? "damping_v_less_drag" : "damping_less_drag");
        break;
      }
    }
  }
  // A rest's end is the state the stage after it starts from: its relaxation, and a warning where the sample is not at
  // rest yet (the skeleton's kinetic over elastic energy, series ke_ratio, above the isotropic stages' default
  // ke_tolerance): a probe after it would start on a moving sample.
  if (sc.type == StageType::Triaxial && sc.axial_strain_rate == 0 && done && !lab_.series.rows.empty() &&
      lab_.series.stage.back() == lab_.stage) {
    size_t first = lab_.series.rows.size() - 1;
    while (first > 0 && lab_.series.stage[first - 1] == lab_.stage) --first;
    const size_t iq = series_column("q");
    const double q0 = lab_.series.rows[first][iq], q1 = lab_.series.rows.back()[iq];
    const double ke = lab_.series.rows.back()[series_column("ke_ratio")], ke_max = StageConfig{}.ke_tolerance;
    if (!opt_.quiet)
      std::printf("stage %s: rested at fixed strain: q %.4g -> %.4g kPa, kinetic / elastic energy %.2g at its end\n",
                  sc.name.c_str(), q0 / 1e3, q1 / 1e3, ke);
    if (ke > ke_max)
      std::fprintf(stderr,
                   "grainlab: warning: stage %s: not at rest at its end (the skeleton's kinetic / elastic energy %.2g, "
                   "above %g, an isotropic stage's default ke_tolerance): the stage after it starts from a moving "
                   "sample; raise its max_steps\n",
                   sc.name.c_str(), ke, ke_max);
  }
  return true;
}

void Laboratory::snapshot(const std::string& tag) {
  const Engine& e = *eng_;
  std::error_code ec;
  fs::create_directories(out_ + "/snapshots", ec);
  char name[64];
  std::snprintf(name, sizeof(name), "snapshots/snap_%05d.h5", lab_.snapshots);
  const EngineState s = e.capture();
  // Contacts: normal from the current positions; f_n and f_t from the pair force of this evaluation.
  const auto fpair = e.contact_forces();
  auto pi = Kokkos::create_mirror_view_and_copy(HostSpace(), e.pairs().pair_i);
  auto pj = Kokkos::create_mirror_view_and_copy(HostSpace(), e.pairs().pair_j);
  auto fl = Kokkos::create_mirror_view_and_copy(HostSpace(), e.history().flags);
  std::vector<int> ci, cj;
  std::vector<Vec3d> cn, cft, cmr;
  std::vector<double> cfn;
  std::vector<std::uint8_t> cfl;
  for (int p = 0; p < e.pairs().npairs; ++p) {
    if (!(fl(p) & kTouching)) continue;
    const int i = pi(p), j = pj(p);
    Vec3d d{s.x[j][0] - s.x[i][0], s.x[j][1] - s.x[i][1], s.x[j][2] - s.x[i][2]};
    const Real len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (auto& c : d) c /= len;
    ci.push_back(i);
    cj.push_back(j);
    cn.push_back(d);
    cfn.push_back(fpair[p][0] * d[0] + fpair[p][1] * d[1] + fpair[p][2] * d[2]);
    cfl.push_back(fl(p));
  }
  // history arrays in capture() are in the same (sorted, touching-only) order as the loop above
  cft = s.ft;
  cmr = s.mr;
  // The particles' ids are their rows here, 0 .. n-1: particles.xdmf's vertex cells use them as their connectivity.
  std::vector<int> ids(s.x.size());
  for (size_t i = 0; i < ids.size(); ++i) ids[i] = int(i);
  write_h5_atomic(out_ + "/" + name, [&](H5Writer& w) {
    w.attr("step", double(e.step_count()));
    w.attr("time", e.time());
    w.attr("tag", tag);
    w.group("/particles");
    w.write("/particles/id", ids);
    w.write("/particles/x", s.x);
    w.write("/particles/v", s.v);
    w.write("/particles/w", s.w);
    w.write("/particles/r", s.r);
    w.group("/contacts");
    w.write("/contacts/i", ci);
    w.write("/contacts/j", cj);
    w.write("/contacts/n", cn);
    w.write("/contacts/f_n", cfn);
    w.write("/contacts/f_t", cft);
    w.write("/contacts/m_r", cmr);
    w.write("/contacts/flags", cfl);
    std::vector<int> conn;
    for (size_t k = 0; k < ci.size(); ++k) conn.insert(conn.end(), {ci[k], cj[k]});
    w.write("/contacts/connectivity", conn);
    // the walls' box at this instant (xlo xhi ylo yhi zlo zhi): `grainlab export --format dump` gives it each frame
    std::vector<double> box(6);
    for (int k = 0; k < 6; ++k) box[size_t(k)] = e.wall_position(k);
    w.group("/walls");
    w.write("/walls/box", box);
  });
  lab_.snapshot_files.push_back(name);
  lab_.snapshot_time.push_back(e.time());
  lab_.snapshot_eps.push_back(measure(cfg_.stages[lab_.stage]).eps_a);
  ++lab_.snapshots;
  write_xdmf();
}

void Laboratory::write_xdmf() {
  // ParaView: particles as points (apply "Point Gaussian" or Glyph by `radius`), contacts as lines
  // coloured by f_n (force chains), one time step per snapshot. Each particle is a vertex cell: a Polyvertex topology
  // needs its connectivity (here the ids, 0 .. n-1), without which VTK's Xdmf3 reader (ParaView 5.11) makes points but
  // no cells, which the default representations do not draw (tests/xdmf_check.py).
  std::ostringstream x;
  x << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n<Domain>\n"
    << "<Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  std::ostringstream c;
  c << "<Grid Name=\"contacts\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (size_t k = 0; k < lab_.snapshot_files.size(); ++k) {
    H5Reader r(out_ + "/" + lab_.snapshot_files[k]);
    const size_t n = r.doubles("/particles/r").size();
    const size_t m = r.ints("/contacts/i").size();
    const std::string f = lab_.snapshot_files[k];
    x << " <Grid Name=\"p" << k << "\"><Time Value=\"" << std::setprecision(12) << lab_.snapshot_time[k] << "\"/>\n"
      << "  <Topology TopologyType=\"Polyvertex\" NodesPerElement=\"1\" NumberOfElements=\"" << n << "\"><DataItem Dimensions=\""
      << n << " 1\" NumberType=\"Int\" Precision=\"4\" Format=\"HDF\">" << f << ":/particles/id</DataItem></Topology>\n"
      << "  <Geometry GeometryType=\"XYZ\"><DataItem Dimensions=\"" << n << " 3\" NumberType=\"Float\" Precision=\"8\" "
         "Format=\"HDF\">" << f << ":/particles/x</DataItem></Geometry>\n";
    for (auto& a : {std::make_pair("radius", "/particles/r"), std::make_pair("id", "/particles/id")})
      x << "  <Attribute Name=\"" << a.first << "\" Center=\"Node\"><DataItem Dimensions=\"" << n << "\" NumberType=\""
        << (std::string(a.first) == "id" ? "Int\" Precision=\"4" : "Float\" Precision=\"8") << "\" Format=\"HDF\">" << f
        << ':' << a.second << "</DataItem></Attribute>\n";
    for (auto& a : {std::make_pair("velocity", "/particles/v"), std::make_pair("spin", "/particles/w")})
      x << "  <Attribute Name=\"" << a.first << "\" AttributeType=\"Vector\" Center=\"Node\"><DataItem Dimensions=\"" << n
        << " 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << f << ':' << a.second
        << "</DataItem></Attribute>\n";
    x << " </Grid>\n";
    c << " <Grid Name=\"c" << k << "\"><Time Value=\"" << std::setprecision(12) << lab_.snapshot_time[k] << "\"/>\n"
      << "  <Topology TopologyType=\"Polyline\" NodesPerElement=\"2\" NumberOfElements=\"" << m << "\">"
      << "<DataItem Dimensions=\"" << m << " 2\" NumberType=\"Int\" Precision=\"4\" Format=\"HDF\">" << f
      << ":/contacts/connectivity</DataItem></Topology>\n"
      << "  <Geometry GeometryType=\"XYZ\"><DataItem Dimensions=\"" << n << " 3\" NumberType=\"Float\" Precision=\"8\" "
         "Format=\"HDF\">" << f << ":/particles/x</DataItem></Geometry>\n"
      << "  <Attribute Name=\"f_n\" Center=\"Cell\"><DataItem Dimensions=\"" << m
      << "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << f << ":/contacts/f_n</DataItem></Attribute>\n"
      << " </Grid>\n";
  }
  x << "</Grid>\n" << c.str() << "</Grid>\n</Domain>\n</Xdmf>\n";
  write_file_atomic(out_ + "/particles.xdmf", x.str());
}

void Laboratory::save_sample(const StageConfig& sc) {
  const std::string path = out_ + "/sample_" + sc.name + ".h5";
  const EngineState s = eng_->capture();
  const StageResult& r = lab_.results.back();
  write_h5_atomic(path, [&](H5Writer& w) {
    write_state(w, s);
    w.attr("density", density_);
    w.attr("density_scaling", scaling_);
    // provenance only: a run that reuses the sample weighs its fines by its own numerics.fines_mass_radius
    if (cfg_.engine.fines_mass_radius > 0) w.attr("fines_mass_radius", cfg_.engine.fines_mass_radius);
    w.attr("p", r.p);
    w.attr("e", r.e);
    w.attr("e_inner", r.e_inner);
    w.attr("e_core", r.e_core);
    w.attr("mu_prep", r.mu);
    if (!lab_.trial_mu.empty()) {  // a target_e0 search's trials, in the order run: e(mu) of this sample, and its scatter
      w.group("/search");
      w.write("/search/trial_mu", lab_.trial_mu);
      w.write("/search/trial_e", lab_.trial_e);
      w.attr("target_e0", sc.target_e0);
    }
    w.attr("stage", sc.name);
    w.attr("config", resolved_config_yaml(cfg_));
    w.attr("build", build_info());
  });
  if (!opt_.quiet) std::printf("sample: %s (reuse it with sample: {file: ...})\n", path.c_str());
}

void Laboratory::assert_healthy(long stage_step, const std::string& trial) {
  const HealthReport h = eng_->check_health(cfg_.health);
  if (h.ok) return;
  std::string what = trial.empty() ? h.what : trial + ": " + h.what;
  // A squeeze in an isotropic stage that loads at once (or on a ramp not much longer than the steps run so far) is
  // most often a loose gas that the servo walls drive at full speed (numerics.servo_max_step) into its jamming: a few
  // chains then take the walls' momentum, before the sample has found contacts enough to share it, and a finer sphere
  // between coarse ones is squeezed past the limit well below the target pressure. A ramp keeps the walls' target,
  // and so their speed, low while the gas jams; raising E or the limit treats the symptom. Measured on a Cu 3 curve
  // (configs/grading-base.yaml with sample.grading 0.2-1.8 mm, one interval: 3 000 spheres, mu 0.5, affine, E = 100 MPa,
  // 100 kPa): no ramp and a 5 000-step ramp both stop at
  // step 4 799 at ~18 kPa (overlap 0.216); 10 000 steps pass at 0.166, 20 000 at 0.127, 50 000 at 0.076: five times
  // the step of the stop (~24 000) is the advice; tests/data/soft_ramp.yaml (E = 15 MPa at 190 kPa, a 20 000-step
  // ramp, stopped at step 15 799) consolidates on a ramp of 80 000. Not where the plan's estimate of the mean overlap
  // at the target already warns (tests/data/soft.yaml, E = 2 MPa: 0.33 of a radius on average): no ramp helps there.
  //
  // Not once the stage has reached its pressure (kPressureReached of it): its walls then hold still, and what squeezes
  // the fine sphere is the load itself, which no ramp lowers. A gas of diameters 0.1-2 mm (p(r) ~ r^-2, 3 000 spheres,
  // E = 100 MPa, 190 kPa; the stopped pair's radii 0.36 and 0.063 mm) stopped so on a 7 000-step ramp at step 12 199
  // with p' at 189.9 kPa, and the ramps advised then (61 000, 220 000 steps) stopped earlier still, at 132 and 81.8 kPa:
  // the advice only sent the user round (tests/data/wide_loaded.yaml). Below it the advice stands: the gas above stops
  // at 18 kPa of 100, tests/data/wide_gas.yaml at 133 kPa of 200, tests/data/soft_ramp.yaml at ~150 kPa of 190 on its
  // 20 000-step ramp, and each consolidates on the ramp advised.
  if (h.squeeze && lab_.stage >= 0 && size_t(lab_.stage) < cfg_.stages.size()) {
    const StageConfig& sc = cfg_.stages[size_t(lab_.stage)];
    const long advice = 5 * std::max(stage_step, 1L);
    const Real p = sc.type == StageType::Isotropic ? measure(sc).p : 0;
    std::ostringstream os;
    os << std::setprecision(4);
    if (sc.type == StageType::Isotropic && p >= kPressureReached * sc.pressure) {
      os << "; stage " << sc.name << " had reached its pressure (p' = " << p / 1e3 << " of " << sc.pressure / 1e3
         << " kPa), so a slower ramp will not help: the load itself is too much for these contacts";
    } else if (sc.type == StageType::Isotropic && sc.pressure_ramp_steps < advice &&
               mean_overlap_estimate(sc.pressure, eng_->params().contact.E) <= cfg_.health.max_overlap / 4) {
      os << "; but first: stage " << sc.name << " loads the gas with "
         << (sc.pressure_ramp_steps > 0 ? "a pressure ramp of only " + std::to_string(sc.pressure_ramp_steps) + " steps"
                                        : "no pressure ramp");
      os << ", so its walls reach the gas's jamming at full speed (p' = " << p / 1e3 << " of " << sc.pressure / 1e3
         << " kPa): ramp the pressure in (stages[" << lab_.stage
         << "].pressure_ramp_steps: " << round_up_2(double(advice)) << ", five times the stage's steps so far)";
    }
    what += os.str();
  }
  stop_run(what);
}

// How far a drained shear's lateral walls are from their servo targets (lateral_targets, here from the same instant's
// sigma_z, where the servo used the step's start), relative, the larger of the two axes. 0 where no wall is servoed
// (undrained: placed).
Real Laboratory::servo_error(const StageConfig& sc, const Measure& m) const {
  if (!lateral_servo(sc)) return 0;
  const LateralTargets t = lateral_targets(sc, lab_.p0, lab_.q0, m.sz);
  const Real tx = std::max<Real>(t.sx, 1e-30), ty = std::max<Real>(t.sy, 1e-30);
  if (sc.plane_strain) return std::abs(m.sy - ty) / ty;  // the x walls are held, not servoed
  return std::max(std::abs(m.sy - ty) / ty, std::abs(m.sx - tx) / tx);
}

// The largest servo_error over the current stage's series rows (what a checkpoint restores, so a resumed run
// reports the same); NaN for a stage without a lateral servo.
Real Laboratory::stage_servo_error(const StageConfig& sc) const {
  if (!lateral_servo(sc)) return std::numeric_limits<Real>::quiet_NaN();
  const size_t ix = series_column("sigma_x"), iy = series_column("sigma_y"), iz = series_column("sigma_z");
  Real worst = 0;
  for (size_t r = 0; r < lab_.series.rows.size(); ++r) {
    if (lab_.series.stage[r] != lab_.stage) continue;
    Measure m{};
    m.sx = lab_.series.rows[r][ix];
    m.sy = lab_.series.rows[r][iy];
    m.sz = lab_.series.rows[r][iz];
    worst = std::max(worst, servo_error(sc, m));
  }
  return worst;
}

// The earth-pressure coefficient of stage k at its end, K0 = sigma_h / sigma_v = (sigma_x + sigma_y) / 2 sigma_z of the
// walls, from its last series row (a stage's end always writes one; the series is checkpointed, so a resumed run gives
// the same); NaN without a row.
Real Laboratory::stage_k0(size_t k) const {
  const std::vector<double>* row = last_row(k);
  if (!row) return std::numeric_limits<Real>::quiet_NaN();
  return 0.5 * ((*row)[series_column("sigma_x")] + (*row)[series_column("sigma_y")]) / (*row)[series_column("sigma_z")];
}

// Stage k's last series row (its end's: a stage's end always writes one), null without one.
const std::vector<double>* Laboratory::last_row(size_t k) const {
  for (size_t r = lab_.series.rows.size(); r-- > 0;)
    if (lab_.series.stage[r] == int(k)) return &lab_.series.rows[r];
  return nullptr;
}

// A triaxial stage's secant modulus E_sec = (q - q_0) / eps_a over the stage (eps_a counted from the stage's start,
// q from the walls, both at its last series row): Young's modulus of a drained stage at constant sigma_3 (the
// unloading stage of an unload-reload loop: E_ur), the undrained E_u of an undrained one. NaN without a row or strain.
Real Laboratory::stage_secant_modulus(size_t k, const StageResult& r) const {
  const std::vector<double>* row = last_row(k);
  const Real eps = row ? (*row)[series_column("eps_a")] : 0;
  return eps != 0 ? (r.q - r.q0) / eps : std::numeric_limits<Real>::quiet_NaN();
}

// A probe's increments (StageConfig::lateral_slope's stage): the stresses from p_0 and q_0 (sigma_a,0 = p_0 + 2 q_0/3,
// sigma_r,0 = p_0 - q_0/3: those the lateral targets and stress_increment take), the strains of the stage's own start,
// eps_r from the box's height and volume, (1 - eps_v) = (1 - eps_a) (1 - eps_r)^2, as the study report takes them.
Laboratory::ProbeIncrements Laboratory::probe_increments(size_t k, const StageResult& r) const {
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  const std::vector<double>* row = last_row(k);
  if (!row) return {nan, nan, nan, nan};
  const auto col = [&](const char* c) { return Real((*row)[series_column(c)]); };
  const Real ea = col("eps_a"), ev = col("eps_v");
  const Real er = 1 - std::sqrt((1 - ev) / (1 - ea));
  const StartStress s0 = start_stress(r.p0, r.q0);
  return {Real(std::sqrt(2.0)) * (0.5 * (col("sigma_x") + col("sigma_y")) - s0.s3), col("sigma_z") - s0.sz,
          Real(std::sqrt(2.0)) * er, ea};
}

// The overconsolidation ratio at the end of stage k, OCR = sigma_v,max / sigma_v: the largest sigma_z of the series rows
// of stages 0..k over that of stage k's last row (1 where the stage ends at the largest vertical stress so far; the
// study report's unloading rows read the same rows); NaN without a row.
Real Laboratory::stage_ocr(size_t k) const {
  const std::vector<double>* row = last_row(k);
  const Real last = row ? (*row)[series_column("sigma_z")] : std::numeric_limits<Real>::quiet_NaN();
  return last > 0 ? sigma_v_max(int(k) + 1) / last : std::numeric_limits<Real>::quiet_NaN();
}

// Every series row of a drained shear: a lateral wall stress further than max_servo_error from its target stops
// the run (StageConfig::max_servo_error), with the row that found it written.
void Laboratory::check_servo(const StageConfig& sc, const Measure& m) {
  const Real se = servo_error(sc, m);
  if (!(se > sc.max_servo_error)) return;
  const LateralTargets t = lateral_targets(sc, lab_.p0, lab_.q0, m.sz);
  // sigma_3's name: SPEC's p'_0, unless a constant-p' path or an anisotropic start (q0) sets it otherwise (sigma_x's
  // target was then still named p'_0, which it was not)
  const bool named_s3 = sc.constant_p || sc.k_ratio > 0 || sc.lateral_slope || lab_.q0 != 0;
  std::ostringstream os;
  os << std::setprecision(4) << "stage '" << sc.name << "' stopped at step " << eng_->step_count()
     << " (eps_a = " << m.eps_a << "): the lateral walls' servo lost its target, sigma_y = " << m.sy / 1e3
     << " kPa against "
     << (sc.constant_p      ? "sigma_3 on the constant-p' path = "
         : sc.k_ratio > 0 ? "sigma_3 on the K path = "
         : sc.lateral_slope ? "sigma_3 on the linear path = "
         : lab_.q0 != 0   ? "sigma_3 at the shear's start = "
                          : "p'_0 = ")
     << t.sy / 1e3 << " kPa";
  if (!sc.plane_strain)  // plane strain's x walls are held: sigma_x has no target
    os << ", sigma_x = " << m.sx / 1e3 << " kPa against "
       << (named_s3 ? (sc.b > 0 ? "sigma_3 + b (sigma_z - sigma_3) = " : "sigma_3 = ")
                    : (sc.b > 0 ? "p'_0 + b (sigma_z - p'_0) = " : "p'_0 = "))
       << t.sx / 1e3 << " kPa";
  os << ": the worst "
     << 100 * se << " % off (max_servo_error " << sc.max_servo_error
     << "). A servo lags its target by a share that grows with the speed its walls must keep (true triaxial at "
        "large b and strain drives the y walls out fastest): "
     << (sc.servo_integral > 0 ? "" : "set the stage's servo_integral (0.1 removes the lag; now 0), ")
     << "lower axial_strain_rate (now " << sc.axial_strain_rate << "), raise the stage's servo_gain (now "
     << sc.servo_gain << ", at most 1) or numerics.servo_max_step (now " << cfg_.engine.servo_max_step
     << " r_min a step)";
  stop_run(os.str());
}

// Stops the run on `what` (a blow-up, a servo that lost its target): the series up to here and blowup.txt are
// written, the newest checkpoint (written before the event: never a broken state) is named, exit 3.
void Laboratory::stop_run(const std::string& what) {
  const std::vector<std::string> ckpts = checkpoints_newest_first(out_);
  const std::string last = ckpts.empty() ? "none" : ckpts.front();
  const std::string msg = what + "; the last good checkpoint is " + last;
  try {
    write_file_atomic(out_ + "/blowup.txt", msg + "\n");
    flush_outputs();  // the series up to the event, for the post-mortem
  } catch (const std::exception&) {
  }
  throw BlowUpError(msg);
}

std::string Laboratory::write_checkpoint(const EngineState* state) {
  EngineState captured;
  if (!state) {
    assert_healthy(lab_.stage_step);  // never replace a good checkpoint by a broken state
    captured = eng_->capture();
    state = &captured;
  }
  const EngineState& s = *state;
  char name[64];
  std::snprintf(name, sizeof(name), "/checkpoints/ckpt_%012ld.h5", s.step);
  std::string path = out_ + name;
  write_h5_atomic(path, [&](H5Writer& w) {
    write_state(w, s);
    w.group("/lab");
    w.write("/lab/scalars", lab_.scalars());
    w.write("/lab/trial_mu", lab_.trial_mu);
    w.write("/lab/trial_e", lab_.trial_e);
    w.write("/lab/series", lab_.series.flat());
    w.write("/lab/series_stage", lab_.series.stage);
    w.write("/lab/loop", lab_.loop.state());
    w.write("/lab/cycles", lab_.cycles.flat());
    w.write("/lab/cycles_stage", lab_.cycles.stage);
    std::vector<double> res;
    std::vector<std::string> names;
    for (auto& r : lab_.results) {
      res.insert(res.end(), {double(r.converged), double(r.steps), r.p, r.q, r.e, r.mu, r.cycle, r.n_ru, r.n_da,
                             r.servo_error, r.quarter_transits, r.e_inner, r.e_core, r.p0, r.q0, r.u0, r.pc, r.u});
      names.push_back(r.name);
    }
    w.write("/lab/results", res);
    w.write_string("/lab/result_names", join(names, '\n'));
    w.write_string("/lab/snapshot_files", join(lab_.snapshot_files, '\n'));
    w.write("/lab/snapshot_time", lab_.snapshot_time);
    w.write("/lab/snapshot_eps", lab_.snapshot_eps);
    w.write_string("/lab/config", fingerprint_);
    w.attr("build", build_info());
    if (!sample_digest_.empty()) {  // what a resume needs of sample.file should the file be gone (load_sample)
      w.attr("sample_digest", sample_digest_);
      w.attr("sample_density", density_);
      w.attr("sample_density_scaling", scaling_);
    }
  });
  last_ckpt_ = std::chrono::steady_clock::now();
  // Keep the newest keep_checkpoints files; older ones go only after the new one is safely in place.
  const std::vector<std::string> all = checkpoints_newest_first(out_);
  for (size_t k = size_t(cfg_.keep_checkpoints); k < all.size(); ++k) fs::remove(all[k]);
  flush_outputs();
  return path;
}

bool Laboratory::load_newest_checkpoint() {
  for (const std::string& path : checkpoints_newest_first(out_)) {
    try {
      H5Reader r(path);
      std::string then = as_this_build_writes(r.string("/lab/config"));
      recadenced_ = false;
      if (then != fingerprint_) {  // another checkpoint cadence alone: the same run (with_checkpoint_cadence)
        const std::string paced = with_checkpoint_cadence(then, cfg_);
        recadenced_ = paced != then;
        then = paced;
      }
      bool extends = false;
      if (then != fingerprint_) {
        // A config that only extends the run (stages appended, the end of the stage it stopped in moved) goes on
        // from here exactly as an uninterrupted run of it would: the stages already run are the same.
        Lab probe;
        probe.set_scalars(r.doubles("/lab/scalars"));
        const std::string why = extension_mismatch(then, fingerprint_, probe.stage);
        if (!why.empty()) {
          std::string m = path;
          m += ": written by a different config (" + why;
          m += " differs); resume with the config that started the run (run.h5 attribute 'config'), or one that only "
               "appends stages or moves the end (max_axial_strain, max_steps, cycles, sigma_v, ocr, q, stress_ratio, "
               "stress_increment) of the stage it stopped in";
          throw std::runtime_error(m);
        }
        extends = true;
      }
      // The checkpoint holds the run's whole state, but the run was built on sample.file (its radii, its record):
      // another sample under that name is another run, said here rather than as radii that differ or, for a
      // sample of the same radii, not at all. (A checkpoint from before the digest has none: not checked.)
      if (!sample_digest_.empty() && r.has("sample_digest") && r.attr_string("sample_digest") != sample_digest_)
        throw std::runtime_error(cfg_.sample_file + " (sample.file): not the sample this run started from (its " +
                                 "checkpoints record sample " + r.attr_string("sample_digest") + ", the file holds " +
                                 sample_digest_ + "): put that sample back to resume the run, or start a new run " +
                                 "from this one with another --out");
      EngineState s = read_state(r);
      Lab lab;
      lab.set_scalars(r.doubles("/lab/scalars"));
      lab.trial_mu = r.doubles("/lab/trial_mu");
      lab.trial_e = r.doubles("/lab/trial_e");
      auto flat = r.doubles("/lab/series");
      lab.series.stage = r.ints("/lab/series_stage");
      const size_t nc = series_columns().size();
      // A checkpoint from before the trailing columns `cycle` ... `eps_y` has one to ten columns fewer: its rows get
      // 0 for `cycle` (no cyclic stage measured it) and NaN for the others (not measured).
      const size_t rows = lab.series.stage.size();
      const double nan = std::numeric_limits<double>::quiet_NaN();
      // cycle, ke_fluct_ratio, e_inner, q_contacts_walls, p_inner, q_inner, p_drag, q_drag, eps_x, eps_y
      const double trailing[] = {0, nan, nan, nan, nan, nan, nan, nan, nan, nan};
      for (size_t missing = 1; missing <= std::size(trailing); ++missing) {
        const size_t nc_old = nc - missing;
        if (flat.size() != rows * nc_old || rows == 0) continue;
        std::vector<double> padded;
        for (size_t k = 0; k < rows; ++k) {
          padded.insert(padded.end(), flat.begin() + long(k * nc_old), flat.begin() + long((k + 1) * nc_old));
          padded.insert(padded.end(), std::end(trailing) - long(missing), std::end(trailing));
        }
        flat = padded;
        break;
      }
      if (flat.size() != lab.series.stage.size() * nc)
        throw H5Error(path + ": series has " + std::to_string(flat.size()) + " values for " +
                      std::to_string(lab.series.stage.size()) + " rows, this build writes " + std::to_string(nc) +
                      " columns per row (a checkpoint of another grainlab version, or corrupt)");
      for (size_t k = 0; k < lab.series.stage.size(); ++k)
        lab.series.rows.emplace_back(flat.begin() + k * nc, flat.begin() + (k + 1) * nc);
      if (r.has("/lab/loop")) {  // a checkpoint from before cycles.csv has none: its cyclic stage's loops start here
        lab.loop.set_state(r.doubles("/lab/loop"));
        const auto cflat = r.doubles("/lab/cycles");
        lab.cycles.stage = r.ints("/lab/cycles_stage");
        const size_t nrows = lab.cycles.stage.size(), cc = cycle_columns().size();
        // 11 columns in a checkpoint from before gamma: its cycles' gamma extremes and G_eq are not known (NaN); 14
        // from before `complete`: every row whole; 15 from before the loops less the drag, 17 from before sigma_v's
        // loop (NaN)
        size_t cc_read = cc;
        for (const size_t older : {kCycleColumnsNoShear, kCycleColumnsNoComplete, kCycleColumnsNoDrag, kCycleColumnsNoSigmaV})
          if (nrows > 0 && cflat.size() == nrows * older) cc_read = older;
        if (cflat.size() != nrows * cc_read) throw H5Error(path + ": cycle rows have the wrong size (corrupt?)");
        for (size_t k = 0; k < nrows; ++k) {
          lab.cycles.rows.emplace_back(cflat.begin() + long(k * cc_read), cflat.begin() + long((k + 1) * cc_read));
          lab.cycles.rows.back().resize(cc, std::nan(""));
          if (cc_read <= kCycleComplete) lab.cycles.rows.back()[kCycleComplete] = 1.0;
        }
      }
      const auto res = r.doubles("/lab/results");
      const auto names = split(r.string("/lab/result_names"), '\n');
      // 18 values a stage; 13 in a checkpoint from before a shear's start stress and end u, 11 from before e_inner
      // and e_core, 10 from before quarter_transits, 9 from before servo_error, 6 from before the liquefaction
      // criteria (it has no N to give)
      size_t nv = 18;
      for (const size_t n : {size_t(18), size_t(13), size_t(11), size_t(10), size_t(9), size_t(6)})
        if (!names.empty() && res.size() == n * names.size()) {
          nv = n;
          break;
        }
      if (res.size() != nv * names.size()) throw H5Error(path + ": stage results have the wrong size (corrupt?)");
      for (size_t k = 0; k < names.size(); ++k) {
        const double* v = res.data() + nv * k;
        StageResult sr;
        sr.name = names[k];
        sr.converged = v[0] != 0;
        sr.steps = long(v[1]);
        sr.p = v[2];
        sr.q = v[3];
        sr.e = v[4];
        sr.mu = v[5];
        if (nv >= 9) {
          sr.cycle = v[6];
          sr.n_ru = v[7];
          sr.n_da = v[8];
        }
        if (nv >= 10) sr.servo_error = v[9];
        if (nv >= 11) sr.quarter_transits = v[10];
        if (nv >= 13) sr.e_inner = v[11], sr.e_core = v[12];
        if (nv >= 18) sr.p0 = v[13], sr.q0 = v[14], sr.u0 = v[15], sr.pc = v[16], sr.u = v[17];
        lab.results.push_back(sr);
      }
      lab.snapshot_files = split(r.string("/lab/snapshot_files"), '\n');
      lab.snapshot_time = r.doubles("/lab/snapshot_time");
      lab.snapshot_eps = r.doubles("/lab/snapshot_eps");
      if (lab.stage < 0 || lab.stage > int(cfg_.stages.size())) throw H5Error(path + ": stage index out of range");
      if (extends && s.dt != planned_dt_) {
        std::ostringstream os;
        os << std::setprecision(6) << path << ": this config extends the run but gives another time step (" << planned_dt_
           << " s, the run's " << s.dt << " s: rolling resistance or stiffness where the run had none); "
           << "start a new run from its sample instead";
        throw std::runtime_error(os.str());
      }
      eng_->restore(s);
      lab_ = lab;
      extended_ = extends;
      const YAML::Node then_config = extends ? YAML::Load(then) : YAML::Node();
      if (extends) refuse_passed_end(path, then_config);
      if (extends && lab_.stage == int(then_config["stages"].size()) && !lab_.results.empty()) {
        // The run had finished: reopen its last stage if the moved end lies beyond where it stopped.
        const StageConfig& sc = cfg_.stages[lab_.stage - 1];
        const Measure m = measure(sc);
        sv_end_ = sigma_v_end(sc, lab_.stage - 1);  // shear_end's stress end, as the stage would run again
        const bool more = lab_.stage_step < sc.max_steps &&
                          (sc.type != StageType::Isotropic ? !shear_end(sc, m) : !lab_.results.back().converged);
        if (more) {
          --lab_.stage;
          lab_.started = true;
          lab_.results.pop_back();
          // the part of a cycle the stage ended in goes on: its row (complete 0) is written again when it ends
          while (!lab_.cycles.rows.empty() && lab_.cycles.stage.back() == lab_.stage &&
                 lab_.cycles.rows.back()[kCycleComplete] == 0) {
            lab_.cycles.drop_last();
          }
        }
      }
      if (!opt_.quiet) std::printf("resuming from %s (step %ld)\n", path.c_str(), s.step);
      return true;
    } catch (const H5Error& e) {
      std::fprintf(stderr, "grainlab: warning: skipping unreadable checkpoint: %s\n", e.what());
    }
  }
  return false;
}

// A config that moves the end of the stage a run stopped in (extension_mismatch) extends the run only if the run
// has not passed the new end: resumed, it must be the run this config starts. A later end always qualifies; an
// earlier one where the run has not gone past it (its strain, step count and reversals in that stage, finished or
// not: a study's step cap scaled down stays far above a shear that ended on its strain). A cyclic stage's
// max_axial_strain may not move earlier (its peaks are not kept).
void Laboratory::refuse_passed_end(const std::string& path, const YAML::Node& then) const {
  const bool finished = lab_.stage >= int(then["stages"].size());
  const int k = finished ? lab_.stage - 1 : lab_.stage;
  if (k < 0 || (!finished && !lab_.started)) return;  // between stages: the next one has not begun
  const StageConfig& sc = cfg_.stages[size_t(k)];
  const YAML::Node old = then["stages"][k];
  const Measure m = measure(sc);
  struct End {
    const char* key;
    double now, reached;  // the new end; where the run is (NaN: not known)
    // the stress ends (StageConfig::sigma_v, ocr, q_end, eta_end): optional, so one the old config lacks is earlier than any
    // (it adds an end) and one the new lacks is later; sign -1 where a larger value ends sooner (in extension)
    bool optional = false;
    double sign = 1;
    const char* unknown = "";  // why `reached` is not known, where it is NaN
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Real sv_top = sigma_v_max(k);  // sigma_v,max before the stage (an ocr end's reference)
  const double along = sc.extension ? -1 : 1;
  const End ends[] = {
      {"max_axial_strain", sc.max_axial_strain, sc.type == StageType::Triaxial ? strain_along(sc, m.eps_a) : nan},
      {"max_steps", double(sc.max_steps), double(lab_.stage_step)},
      {"cycles", double(sc.cycles), sc.type == StageType::Cyclic ? 0.5 * double(lab_.half_cycles) : nan, false, 1,
       "a cyclic stage's peaks are not kept"},
      {"sigma_v", sc.sigma_v > 0 ? along * sc.sigma_v : nan, along * m.sz, true, along},
      {"ocr", sc.ocr > 0 ? sc.ocr : nan, m.sz > 0 ? sv_top / m.sz : nan, true, 1},
      // q rises to a peak and falls (a dense sample's softening) and the steps between series rows are not kept: an
      // earlier or added q end may have been passed wherever q is now
      {"q", sc.q_end ? along * *sc.q_end : nan, nan, true, along,
       "q is not monotonic along a shear, and its steps between series rows are not kept"},
      {"stress_ratio", sc.eta_end ? along * *sc.eta_end : nan, nan, true, along,
       "q/p' is not monotonic along a shear, and its steps between series rows are not kept"},
      {"stress_increment", sc.dsigma_end ? *sc.dsigma_end : nan, nan, true, 1,
       "|sigma - sigma_0| is not monotonic along a shear, and its steps between series rows are not kept"}};
  for (const End& e : ends) {
    if (e.optional && !(e.now == e.now)) continue;  // no such end now: the stage ends later, if at all
    if (!old[e.key] && !e.optional) continue;
    const double before = old[e.key] ? e.sign * old[e.key].as<double>() : std::numeric_limits<double>::infinity();
    if (!(e.now < before) || e.reached <= e.now) continue;  // NaN (not known) refuses
    std::ostringstream os;
    os << std::setprecision(6) << path << ": this config ";
    if (old[e.key]) os << "moves stages[" << k << "]." << e.key << " from " << e.sign * before << " to ";
    else os << "adds stages[" << k << "]." << e.key << " = ";
    os << e.sign * e.now
       << (e.reached == e.reached ? ", which the run has passed" : std::string(", which the run may have passed (") + e.unknown + ")");
    if (e.reached == e.reached)
      os << " (" << e.sign * e.reached << (finished ? " where the stage ended)" : " where it stopped)");
    os << ": resumed, it would not be the run this config starts; give an end beyond it, or start a new run from the "
          "run's sample";
    throw std::runtime_error(os.str());
  }
}

// summary.json: what every finished stage ended at, for scripts (a study's report reads the cyclic ones), rewritten
// whole at every stage end. Numbers read back exactly; null where a criterion was not met.
void Laboratory::write_summary() const {
  auto num = [](double v) {  // the shortest of 15 or 17 digits that reads back as v
    if (!std::isfinite(v)) return std::string("null");
    char b[32];
    std::snprintf(b, sizeof(b), "%.15g", v);
    if (std::strtod(b, nullptr) != v) std::snprintf(b, sizeof(b), "%.17g", v);
    return std::string(b);
  };
  std::ostringstream js;
  js << "{\n  \"config\": " << json_string(cfg_.path) << ",\n  \"build\": " << json_string(build_info())
     << ",\n  \"sample\": {\"spheres\": " << eng_->num_particles() << ", \"d10\": " << num(grading_.d10)
     << ", \"d30\": " << num(grading_.d30) << ", \"d50\": " << num(grading_.d50) << ", \"d60\": " << num(grading_.d60)
     << ", \"cu\": " << num(grading_.cu) << ", \"cc\": " << num(grading_.cc);
  // The fines' mass scaling where it is on (beyond SPEC §1, recorded as its density scaling is): the radius under
  // which the spheres weigh as one of it.
  if (const Real rf = cfg_.engine.fines_mass_radius; rf > 0) js << ", \"fines_mass_radius\": " << num(rf);
  js << "}"
     << ",\n  \"stages\": [";
  for (size_t k = 0; k < lab_.results.size(); ++k) {
    const StageResult& r = lab_.results[k];
    const StageConfig& sc = cfg_.stages.at(k);
    const char* type = sc.type == StageType::Isotropic ? "isotropic" : sc.type == StageType::Triaxial ? "triaxial" : "cyclic";
    js << (k ? "," : "") << "\n    {\"name\": " << json_string(r.name) << ", \"type\": \"" << type << "\"";
    if (sc.type != StageType::Isotropic)
      js << ", \"drainage\": \"" << drainage_name(sc.drainage)
         << "\", \"axial_strain_rate\": " << num(sc.axial_strain_rate);
    if (sc.type == StageType::Triaxial)
      js << ", \"direction\": \"" << (sc.extension ? "extension" : "compression") << "\", \"b\": " << sc.b;
    if ((lateral_servo(sc) || sc.plane_strain) && sc.type == StageType::Triaxial)  // an undrained stage: plane strain's
      js << ", \"stress_path\": \""
         << (sc.constant_p     ? "constant_p"
             : sc.plane_strain ? "plane_strain"
             : sc.k_ratio > 0  ? "constant_k"
             : sc.lateral_slope ? "linear"
                                : "constant_sigma3")
         << "\"";
    if (sc.k_ratio > 0) js << ", \"k_ratio\": " << num(sc.k_ratio);
    // a linear path's slope, and its dq/dp' (null at -1/2: constant p')
    if (sc.lateral_slope)
      js << ", \"lateral_slope\": " << num(*sc.lateral_slope) << ", \"dq_dp\": "
         << num(3 * (1 - *sc.lateral_slope) / (1 + 2 * *sc.lateral_slope));
    if (sc.stress_direction) js << ", \"stress_direction\": " << num(*sc.stress_direction);
    js << ", \"done\": " << (r.converged ? "true" : "false") << ", \"steps\": " << r.steps << ", \"mu\": " << num(r.mu)
       << ", \"p\": " << num(r.p) << ", \"q\": " << num(r.q) << ", \"e\": " << num(r.e);
    // A shear's start (the stress it found: p'_0, q_0) and, undrained, its pore pressures: u_0 it started with, p'_c
    // r_u is relative to, u and r_u at its end (the stage's last series row)
    if (sc.type != StageType::Isotropic) js << ", \"p_0\": " << num(r.p0) << ", \"q_0\": " << num(r.q0);
    if (sc.type != StageType::Isotropic && sc.drainage == Drainage::Undrained)
      js << ", \"u_0\": " << num(r.u0) << ", \"p_c\": " << num(r.pc) << ", \"u\": " << num(r.u)
         << ", \"r_u\": " << num(r.u / r.pc);
    if (sc.type == StageType::Cyclic) {
      auto met = [&](Real n) { return n < 0 ? std::string("null") : num(n); };
      js << ",\n     \"cycles\": " << sc.cycles << ", \"cycle\": " << num(r.cycle) << ", \"liquefaction_ru\": "
         << num(sc.liquefaction_ru) << ", \"n_ru\": " << met(r.n_ru) << ", \"liquefaction_da_strain\": "
         << num(sc.liquefaction_da_strain) << ", \"n_da\": " << met(r.n_da);
    }
    if (lateral_servo(sc)) js << ", \"servo_error\": " << num(r.servo_error);
    if (sc.type != StageType::Isotropic && sc.drainage == Drainage::Oedometric)
      js << ", \"K0\": " << num(stage_k0(k)) << ", \"OCR\": " << num(stage_ocr(k));
    if (sc.type == StageType::Triaxial) js << ", \"E_sec\": " << num(stage_secant_modulus(k, r));
    // a linear path's (a probe's) increments in the Rendulic plane, [Pa] and [-]
    if (sc.lateral_slope) {
      const ProbeIncrements pi = probe_increments(k, r);
      js << ", \"dsigma_rendulic\": [" << num(pi.ds_r) << ", " << num(pi.ds_a) << "], \"deps_rendulic\": ["
         << num(pi.de_r) << ", " << num(pi.de_a) << "]";
    }
    if (sc.type == StageType::Cyclic) js << ", \"quarter_cycle_transits\": " << num(r.quarter_transits);
    // a stress reversal's amplitude and its cyclic stress ratio A / (2 p'_c), whichever of them the config gave
    if (sc.stress_reversal())
      js << ", \"q_amplitude\": " << num(q_amplitude(sc, r.pc)) << ", \"csr\": " << num(q_amplitude(sc, r.pc) / (2 * r.pc));
    // an oedometric stress reversal's: the amplitude and the sigma_v,0 it reversed about
    if (sc.type == StageType::Cyclic && sc.sigma_v_reversal())
      js << ", \"sigma_v_amplitude\": " << num(sc.sigma_v_amplitude) << ", \"sigma_v_0\": " << num(start_stress(r.p0, r.q0).sz);
    if (sc.type == StageType::Isotropic) js << ", \"e_inner\": " << num(r.e_inner) << ", \"e_core\": " << num(r.e_core);
    // a target_e0 search's target and tolerance, which e meets or not (the search's nearest trial; a study's job is
    // quiet, so its study and report read the miss from here)
    if (sc.type == StageType::Isotropic && sc.target_e0 > 0)
      js << ", \"target_e0\": " << num(sc.target_e0) << ", \"target_e0_tolerance\": " << num(sc.target_e0_tolerance);
    js << "}";
  }
  js << "\n  ]\n}\n";
  write_file_atomic(out_ + "/summary.json", js.str());
}

}  // namespace

// The minute is for a slow run: a 1e6-sphere run at 5 steps/s with output.every 1000 has a row every 200 s, and 20
// rows would be an hour with nothing to plot. The floor of ten times the last write is for a long series written
// often: at output.every 10 a 3 000-sphere run writes 6.5 MB of series.csv and 3.8 MB of run.h5 by its end. Outputs
// only: the dynamics, and the files at each stage's end (written there in any case), are the same whatever the pace.
bool output_flush_due(int rows_since, double seconds_since, double last_cost) {
  return rows_since > 0 && (rows_since >= 20 || seconds_since >= 60) && seconds_since >= 10 * last_cost;
}

std::string version_line() { return build_string(false); }

bool holds_study(const std::string& dir) {
  std::error_code ec;
  return fs::exists(dir + "/study.json", ec) || (fs::exists(dir + "/.lock", ec) && fs::is_directory(dir + "/jobs", ec));
}
bool holds_run(const std::string& dir) {
  return fs::exists(dir + "/series.csv") || fs::exists(dir + "/run.h5") || holds_files(dir + "/checkpoints");
}

std::string sample_file_digest(const std::string& path) { return read_sample_file(path).digest; }

std::string run_sample_digest(const std::string& dir) {
  std::vector<std::string> files = checkpoints_newest_first(dir);  // every checkpoint records it, and run.h5 once written
  files.push_back(dir + "/run.h5");
  for (const std::string& path : files) {
    try {
      const H5Reader r(path);
      return r.has("sample_digest") ? r.attr_string("sample_digest") : std::string();
    } catch (const H5Error&) {  // unreadable, or gone (the run pruning it): the next one
    }
  }
  return "";
}

namespace {
bool Laboratory::flush_due(int rows_since) const {
  return output_flush_due(rows_since, std::chrono::duration<double>(std::chrono::steady_clock::now() - last_flush_).count(),
                          flush_cost_);
}

void Laboratory::flush_outputs() {
  const auto t0 = std::chrono::steady_clock::now();
  write_file_atomic(out_ + "/series.csv", lab_.series.csv(cfg_.stages));
  if (!lab_.cycles.rows.empty()) write_file_atomic(out_ + "/cycles.csv", lab_.cycles.csv(cfg_.stages));
  write_h5_atomic(out_ + "/run.h5", [&](H5Writer& w) {
    w.attr("config", resolved_config_yaml(cfg_));
    w.attr("build", build_info());
    w.attr("density_scaling", scaling_);
    if (cfg_.engine.fines_mass_radius > 0) w.attr("fines_mass_radius", cfg_.engine.fines_mass_radius);
    if (!sample_digest_.empty()) w.attr("sample_digest", sample_digest_);
    w.group("/series");
    const auto& cols = series_columns();
    for (size_t c = 0; c < cols.size(); ++c) w.write("/series/" + cols[c].first, lab_.series.column(c));
    w.write("/series/stage", lab_.series.stage);
    std::vector<std::string> units, names;
    for (auto& c : cols) names.push_back(c.first), units.push_back(c.second);
    w.write_string("/series/columns", join(names, ','));
    w.write_string("/series/units", join(units, ','));
    std::vector<std::string> stage_names;
    for (auto& s : cfg_.stages) stage_names.push_back(s.name);
    w.write_string("/series/stage_names", join(stage_names, ','));
    w.group("/snapshots");
    w.write_string("/snapshots/files", join(lab_.snapshot_files, '\n'));
    w.write("/snapshots/time", lab_.snapshot_time);
    w.write("/snapshots/eps_a", lab_.snapshot_eps);
  });
  last_flush_ = std::chrono::steady_clock::now();
  flush_cost_ = std::chrono::duration<double>(last_flush_ - t0).count();
}

RunResult Laboratory::run() {
  SignalGuard guard;
  // Nothing is created before every check that can fail has passed: the plan (memory, the sample's stable time
  // step against the config's dt), the files already in the output directory (a fresh start, and --resume
  // with no run there is one, must not replace any), and the sample itself (a placement that fails).
  load_sample();
  const RunPlan plan = plan_run_with(cfg_, 0, false, sample_ ? &*sample_ : nullptr);
  planned_dt_ = plan.dt;
  transit_ = plan.transit;
  grading_ = plan.grading;
  for (const auto* ws : {&plan.sample_warnings, &plan.warnings})
    for (const std::string& w : *ws) std::fprintf(stderr, "grainlab: warning: %s\n", w.c_str());
  if (opt_.check_resume) {  // nothing to resume is nothing to refuse; else the checkpoint's own refusals
    if (holds_files(out_ + "/checkpoints")) {
      build_engine();
      if (!load_newest_checkpoint())
        throw std::runtime_error(out_ + "/checkpoints: no readable checkpoint to resume from");
    }
    return RunResult{};
  }
  if (!opt_.resume || !holds_run()) refuse_overwrites();
  build_engine();
  prepare_output_dir();
  RunResult result;
  if (opt_.resume) {
    if (!load_newest_checkpoint())
      throw std::runtime_error(out_ + "/checkpoints: no readable checkpoint to resume from");
  }
  if (!opt_.quiet) {
    char fines[64] = "";
    if (cfg_.engine.fines_mass_radius > 0)
      std::snprintf(fines, sizeof(fines), " | fines_mass_radius %.4g mm", 1e3 * cfg_.engine.fines_mass_radius);
    std::printf("%s | %d particles | dt = %.4g s (%.3g of the stable limit) | density scaling %g%s\n",
                build_info().c_str(), eng_->num_particles(), eng_->dt(), eng_->dt() / eng_->critical_dt(), scaling_,
                fines);
    if (!opt_.threads_note.empty()) std::printf("%s\n", opt_.threads_note.c_str());
    // The resolved config (every default filled in) is the run's config.yaml, not the console's: 50 lines before
    // the first progress line buried the plan.
    std::printf("output: %s (config.yaml: the resolved config, every default filled in)\n", out_.c_str());
    if (!opt_.resume) {
      std::printf("plan:\n  %s\n", plan.sample.c_str());
      if (!plan.fines.empty()) std::printf("  %s\n", plan.fines.c_str());
      for (const std::string& l : plan.stages) std::printf("  %s\n", l.c_str());
    }
  }
  if (!opt_.resume) {
    write_file_atomic(out_ + "/config.yaml", resolved_config_yaml(cfg_));
    write_checkpoint();  // step 0: from now on a kill at any moment leaves something to resume
  }
  if (recadenced_ && !extended_) {
    write_file_atomic(out_ + "/config.yaml", resolved_config_yaml(cfg_));  // the run's config is now this one
    if (!opt_.quiet)
      std::printf("%s: checkpoints now every %ld steps and %g minutes (0: off), the newest %d kept; config.yaml records "
                  "it\n", out_.c_str(), cfg_.checkpoint_every, double(cfg_.checkpoint_minutes), cfg_.keep_checkpoints);
  }
  if (extended_) {
    write_file_atomic(out_ + "/config.yaml", resolved_config_yaml(cfg_));  // the run's config is now this one
    if (!opt_.quiet && lab_.stage < int(cfg_.stages.size()))
      std::printf("%s: extended by this config; going on from stage %d\n", out_.c_str(), lab_.stage + 1);
    else if (!opt_.quiet)  // a later end of a stage that ended short of it for another reason: the same run
      std::printf("%s: this config moves an end the run stopped short of; config.yaml now records it\n", out_.c_str());
  }
  if (opt_.resume && lab_.stage >= int(cfg_.stages.size())) {
    // A finished run: its outputs were written with its final checkpoint, so rewriting them would change nothing.
    if (!opt_.quiet) std::printf("%s: the run has finished (step %ld); nothing to resume\n", out_.c_str(), eng_->step_count());
    result.stages = lab_.results;
    return result;
  }
  for (; lab_.stage < int(cfg_.stages.size()); ++lab_.stage) {
    const StageConfig& sc = cfg_.stages[lab_.stage];
    if (!lab_.started) start_stage(sc);
    if (!run_stage(sc)) {
      progress("", true);
      result.interrupted = true;
      // Searching: the checkpoint holds the stage-start state; otherwise the current step boundary.
      result.checkpoint = write_checkpoint();
      // Even with --quiet (which silences progress, not news): a stopped run says where it can resume.
      std::string search;  // a target_e0 search's step is its stage start's: which trial was running, and how far
      if (lab_.searching) {
        std::ostringstream os;
        const size_t k = lab_.trial_mu.size() + 1;
        os << ", in stage " << cfg_.stages[size_t(lab_.stage)].name << "'s target_e0 search at step " << trial_steps_
           << " of trial " << k << " (" << k - 1 << " finished; a resume runs trial " << k << " again)";
        search = os.str();
      }
      std::fprintf(stderr, "interrupted at step %ld%s%s: checkpoint %s; continue with --resume\n", eng_->step_count(),
                   search.c_str(), g_pipe_closed ? " (the reader of its output closed the pipe)" : "",
                   result.checkpoint.c_str());
      result.stages = lab_.results;
      return result;
    }
    lab_.started = false;
  }
  flush_outputs();
  write_checkpoint();  // the final state, so a finished run can be extended or inspected
  if (!opt_.quiet) {
    std::printf("done: %s/series.csv, run.h5, particles.xdmf, summary.json%s\n", out_.c_str(),
                lab_.cycles.rows.empty() ? "" : ", cycles.csv");
  }
  result.stages = lab_.results;
  return result;
}

}  // namespace

int cores_of_cpu_max(const std::string& text) {
  std::istringstream in(text);
  double quota = 0, period = 0;
  if (!(in >> quota >> period) || !(quota > 0) || !(period > 0)) return 0;  // "max" does not parse as a number
  return int(std::min(1e6, std::ceil(quota / period)));
}

bool lock_or_warn(int fd, const std::string& path) {
  if (::flock(fd, LOCK_EX | LOCK_NB) == 0) return true;
  if (errno == EWOULDBLOCK) return false;
  std::fprintf(stderr, "grainlab: warning: %s: this filesystem does not lock files (flock: %s): a second grainlab process "
               "on this directory would not be refused; run one at a time\n", path.c_str(), std::strerror(errno));
  return true;
}

namespace {
// The paths of a cgroup control file for this process: v2's `v2_file` (the "0::PATH" line) and v1's `v1_file` under the
// mount of `controller` (its line "ID:cpu,cpuacct:PATH"; the mount is named by the list, or by the controller), in
// the cgroup and each of its parents up to the mount's root.
std::vector<std::string> cgroup_files(const std::string& proc_self_cgroup, const std::string& root,
                                      const std::string& controller, const std::string& v1_file,
                                      const std::string& v2_file) {
  std::vector<std::string> out;
  std::istringstream in(proc_self_cgroup);
  std::string line;
  while (std::getline(in, line)) {
    const size_t a = line.find(':'), b = a == std::string::npos ? a : line.find(':', a + 1);
    if (b == std::string::npos) continue;
    const std::string list = line.substr(a + 1, b - a - 1);
    std::string path = line.substr(b + 1), dir = root, file = v2_file;
    if (!list.empty()) {
      if (("," + list + ",").find("," + controller + ",") == std::string::npos) continue;
      dir += '/';
      dir += fs::is_directory(fs::path(root) / list) ? list : controller;
      file = v1_file;
    }
    for (;;) {
      std::string f = dir;
      if (path != "/") f += path;
      f += '/';
      f += file;
      out.push_back(std::move(f));
      const size_t cut = path.rfind('/');
      if (path == "/" || cut == std::string::npos) break;  // the root's files read; a path without '/' has no parent
      path.resize(cut);  // "/a/b" -> "/a" -> "" (the root's files, then the end)
    }
  }
  return out;
}
}  // namespace

int cgroup_cores(const std::string& proc_self_cgroup, const std::string& root) {
  int cores = 0;
  for (const std::string& f : cgroup_files(proc_self_cgroup, root, "cpu", "cpu.cfs_quota_us", "cpu.max")) {
    std::string text = file_text(f);  // v2: "QUOTA PERIOD"; v1: the quota (-1: none), its period beside it
    if (f.size() > 16 && f.compare(f.size() - 16, 16, "cpu.cfs_quota_us") == 0)
      text += " " + file_text(f.substr(0, f.size() - 8) + "period_us");
    if (const int q = cores_of_cpu_max(text); q > 0) cores = cores > 0 ? std::min(cores, q) : q;
  }
  return cores;
}

double cgroup_memory_limit(const std::string& proc_self_cgroup, const std::string& root) {
  double limit = 0;
  for (const std::string& f : cgroup_files(proc_self_cgroup, root, "memory", "memory.limit_in_bytes", "memory.max")) {
    std::istringstream in(file_text(f));
    double v = 0;  // v2's "max" (none) does not parse; v1's none is ~9.2e18, above any memory
    if (in >> v && v > 0 && v < 1e18) limit = limit > 0 ? std::min(limit, v) : v;
  }
  return limit;
}

int usable_cores() {
  std::set<int> cpus;
  for (const auto& place : compat::openmp_places()) cpus.insert(place.begin(), place.end());
  cpu_set_t set;
  CPU_ZERO(&set);
  int cores = !cpus.empty() ? int(cpus.size())
              : sched_getaffinity(0, sizeof(set), &set) == 0 && CPU_COUNT(&set) > 0
                  ? CPU_COUNT(&set)
                  : int(std::max(1L, sysconf(_SC_NPROCESSORS_ONLN)));
  if (const int q = cgroup_cores(file_text("/proc/self/cgroup")); q > 0) cores = std::min(cores, q);
  return cores;
}

int default_threads(long spheres, int cores) {
  return int(std::clamp(spheres / kSpheresPerThread, 1L, long(std::max(1, cores))));
}

long config_spheres(const RunConfig& cfg) {
  if (cfg.sample_file.empty()) return cfg.packing.count;
  try {
    return long(H5Reader(cfg.sample_file).doubles("/state/r").size());
  } catch (const std::exception&) {
    return 0;
  }
}

std::string memory_amount(double b) {
  constexpr double kGiB = 1024.0 * 1024 * 1024;
  char t[32];
  if (b >= kGiB) std::snprintf(t, sizeof t, "%.1f GiB", b / kGiB);
  else std::snprintf(t, sizeof t, "%.1f MiB", b / (1024.0 * 1024));
  return t;
}

RunPlan plan_run(const RunConfig& cfg, Real p_start, bool place) { return plan_run_with(cfg, p_start, place, nullptr); }

namespace {
RunPlan plan_run_with(const RunConfig& cfg, Real p_start, bool place, const SampleFile* sample) {
  RunPlan plan;
  EngineParams ep = cfg.engine;
  // The time step is chosen once for the whole run, for its stiffest stage (rolling on in any stage).
  for (const StageConfig& sc : cfg.stages) ep.contact.mu_r = std::max(ep.contact.mu_r, sc.mu_r);
  std::vector<Real> r;
  Real density = cfg.density, scaling = cfg.density_scaling;
  if (!cfg.sample_file.empty()) {
    std::optional<SampleFile> read;  // (a conditional of *sample and a temporary would copy *sample)
    const SampleFile& f = sample ? *sample : read.emplace(read_sample_file(cfg.sample_file));
    r = f.state.r;
    plan.memory_available = require_memory(long(r.size()), "sample.file " + cfg.sample_file, plan.memory_source);
    density = f.density;
    scaling = f.density_scaling;
    if (Vec3d lo, hi; f.state.walls_are_box && box_of_walls(f.state.walls, lo, hi)) {
      Real Vs = 0;
      for (Real ri : r) Vs += 4.0 / 3.0 * M_PI * ri * ri * ri;
      const Real V = (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
      if (V > 0 && Vs > 0) plan.sample_e = V / Vs - 1;
    }
  } else {
    plan.memory_available = require_memory(cfg.packing.count, "sample.count", plan.memory_source);
    r = packing_radii(cfg.packing);
    // The run's own placement, which can fail in a small box (generate_packing says why and what would place it).
    if (place && cfg.packing.count <= kPlaceCheckMax) {
      generate_packing(cfg.packing);
      plan.placed = true;
    }
  }
  plan.particles = long(r.size());
  plan.memory_need = double(plan.particles) * kBytesPerSphere;
  {
    // What a geotechnical user reads off a grading: D50, Cu = D60/D10, Cc = D30^2/(D10 D60), by mass.
    const auto mm = [](double d) {
      std::ostringstream o;
      o << std::setprecision(3) << d * 1e3 << " mm";
      return o.str();
    };
    const auto indices = [&](const GradingIndices& g) {
      std::ostringstream o;
      o << std::setprecision(3) << "D50 = " << mm(g.d50) << ", Cu = " << g.cu << ", Cc = " << g.cc;
      return o.str();
    };
    const auto [lo, hi] = std::minmax_element(r.begin(), r.end());
    plan.grading = grading_indices(r);
    std::ostringstream os;
    os << std::setprecision(4) << "sample: " << r.size() << " sphere" << plural(long(r.size()));
    const Grading& gr = cfg.packing.grading;
    if (!cfg.sample_file.empty()) {
      os << " read from sample.file, diameters " << mm(2 * *lo) << " to " << mm(2 * *hi) << "; by mass "
         << indices(plan.grading);
      if (plan.sample_e > 0) os << "; e " << plan.sample_e << " in its walls";
    } else if (gr.empty()) {
      os << " drawn from p(r) ~ r^-" << cfg.packing.D << " on diameters " << mm(2 * cfg.packing.r_min) << " to "
         << mm(2 * cfg.packing.r_max) << "; by mass " << indices(plan.grading);
    } else {
      os << " drawn from sample.grading (" << gr.diameter.size() << " sieves, " << mm(gr.diameter.front()) << " to "
         << mm(gr.diameter.back()) << ": " << indices(grading_indices(gr)) << "); as drawn "
         << indices(plan.grading);
      // The drawn curve against the asked at every sieve and at each interval's geometric middle, where the asked
      // passes the mean of its ends: a wide interval's coarse end can hold under one sphere (0.02-2 mm, 10^5 spheres:
      // ~1 coarser than 1 mm for the 15 % of the mass there), which its sieves alone, 0 and 100 %, do not show.
      const auto [at, want, sieve] = grading_check_points(gr);
      const std::vector<Real> got = passing_at(r, at);
      size_t worst = 0;
      for (size_t k = 0; k < got.size(); ++k)
        if (std::abs(got[k] - want[k]) > std::abs(got[worst] - want[worst])) worst = k;
      const double miss = got[worst] - want[worst];
      os << std::setprecision(3) << "; percent passing ";
      if (gr.diameter.size() <= 12) {
        std::ostringstream asked;
        for (size_t k = 0, n = 0; k < at.size(); ++k) {
          if (!sieve[k]) continue;
          os << (n ? " / " : "") << got[k];
          asked << (n ? " / " : "") << want[k];
          ++n;
        }
        os << " (asked " << asked.str() << ")";
      } else {
        os << "within " << std::abs(miss) << " points of the asked at every sieve and between";
      }
      if (std::abs(miss) > kGradingMiss) {
        // The coarser side of the worst point: how many spheres carry its mass share.
        long coarser = 0;
        for (Real ri : r) coarser += 2 * ri > at[worst] ? 1 : 0;
        std::ostringstream w;
        w << std::setprecision(3) << "sample.grading: the " << r.size() << " spheres drawn pass " << got[worst]
          << " % at " << mm(at[worst]) << (sieve[worst] ? "" : " (between sieves)") << " against the " << want[worst]
          << " % asked (" << miss << " points; " << coarser << " sphere" << plural(coarser) << " coarser carry the "
          << 100 - want[worst] << " % above it): the mass of a fraction of few spheres scatters from draw to "
          << "draw (sample.seed); raise sample.count, or narrow the curve";
        plan.sample_warnings.push_back(w.str());
      }
    }
    plan.sample = os.str();
  }
  plan.rolling = ep.contact.mu_r > 0;
  const StableStep st = stable_step(r, density, scaling, ep);
  plan.dt_limit = st.limit(plan.rolling);
  // Every key's range admits a sphere too light for the arithmetic (r_min = 1e-300 m: m = 0 in a double), whose
  // stable step is 0 or NaN: the plan would say "dt = nan" and the run divide by zero.
  if (!(std::isfinite(double(plan.dt_limit)) && plan.dt_limit > 0 && st.m_min > 0 && std::isfinite(double(st.k_max)))) {
    std::ostringstream os;
    os << "the stable time step (SPEC §4: sqrt(m_min / k_max)) is " << plan.dt_limit << " s: the lightest sphere's "
       << "mass m_min = " << st.m_min << " kg and the stiffest spring k_max = " << st.k_max << " N/m (smallest radius "
       << *std::min_element(r.begin(), r.end()) << " m, density " << density << " kg/m^3, density_scaling " << scaling
       << ", material.E " << ep.contact.E << " Pa) do not make a positive, finite one";
    throw std::runtime_error(os.str());
  }
  plan.dt = choose_time_step(st, ep);
  const double r_min = *std::min_element(r.begin(), r.end());
  if (const Real rf = ep.fines_mass_radius; rf > 0) {
    // What the fines' mass scaling does to this sample: how many spheres and what share of the solid mass it makes
    // heavier, by how much the sample's mass grows, and the stable step against SPEC §1's masses.
    long scaled = 0;
    double m_spec = 0, m_fines = 0, m_run = 0;
    for (Real ri : r) {
      const double ms = sphere_mass(ri, density, scaling);
      m_spec += ms;
      m_run += particle_mass(ri, density, scaling, rf);
      if (ri < rf) {
        ++scaled;
        m_fines += ms;
      }
    }
    EngineParams spec = ep;
    spec.fines_mass_radius = 0;
    const Real limit_spec = stable_step(r, density, scaling, spec).limit(plan.rolling);
    std::ostringstream os;
    os << std::setprecision(3) << "fines: numerics.fines_mass_radius = " << rf * 1e3 << " mm: " << scaled << " of "
       << r.size() << " spheres (" << 100 * m_fines / m_spec << " % of the solid mass) weigh as a sphere of that "
       << "radius, the sample's mass x " << m_run / m_spec << "; stable limit " << plan.dt_limit << " s against "
       << limit_spec << " s with SPEC §1's masses (x " << plan.dt_limit / limit_spec << ")";
    plan.fines = os.str();
    if (scaled == 0) {
      std::ostringstream w;
      w << std::setprecision(4) << "numerics.fines_mass_radius = " << rf << " m is not above the smallest radius, "
        << *std::min_element(r.begin(), r.end()) << " m: no sphere is made heavier";
      plan.sample_warnings.push_back(w.str());
    }
  }
  double d_mean = 0, v_solid = 0;
  for (Real ri : r) {
    d_mean += 2 * ri;
    v_solid += 4.0 / 3.0 * M_PI * double(ri) * ri * ri;
  }
  d_mean /= std::max<size_t>(r.size(), 1);
  // The time a compression wave takes across the sample, T_w = L / c (choice, beyond SPEC §6.3): c = d sqrt(k_n/m)
  // for a chain of mean spheres (linear contacts: independent of p'), L the side of a cube of the spheres at solid
  // fraction 0.6. A cyclic loop measures the material only when its loading is slow against the sample's response:
  // the loading frequency 1/(4 t_q) (t_q: a quarter cycle) against the sample's fundamental frequency ~ c / (4 L)
  // (a quarter wavelength over its height) is T_w / t_q.
  // (The mean sphere's mass as the engine gives it: with the fines' scaling on, a mean sphere that is a fine is
  // heavier, its waves slower, and the transits longer: the conservative side of the warnings below.)
  const double m_mean = particle_mass(Real(d_mean / 2), density, scaling, ep.fines_mass_radius),
               k_mean = ep.contact.E * d_mean / 2;
  const double transit = std::cbrt(v_solid / 0.6) / (d_mean * std::sqrt(k_mean / m_mean));
  plan.transit = transit;

  double p_prev = p_start;  // the pressure the previous isotropic stage leaves (a shear's p'_0), 0: unknown
  bool p_moved = false;     // a shear stage since it (a K0 loading, cycles): p' is then the run's to find
  for (const StageConfig& sc : cfg.stages) {
    std::ostringstream os;
    os << std::setprecision(4) << "stage " << sc.name << ": ";
    const auto warn = [&](const std::string& w) { plan.warnings.push_back("stage " + sc.name + ": " + w); };
    if (sc.type == StageType::Isotropic) {
      // a search's mu is its own (0, mu_max, then between: Laboratory::search_e0), whatever the stage's mu says
      os << "isotropic to " << sc.pressure / 1e3 << " kPa, ";
      if (sc.target_e0 > 0) os << "mu searched in [0, " << sc.mu_max << "]";
      else os << "mu = " << sc.mu;
      os << ", mu_r = " << sc.mu_r;
      if (sc.target_e0 > 0)
        os << ", for e0 = " << sc.target_e0 << " (up to " << sc.max_trials << " trials of up to "
           << sc.max_steps << " steps)";
      else
        os << ", until equilibrium (at most " << sc.max_steps << " steps)";
      if (sc.pressure_ramp_steps >= sc.max_steps)
        warn("the pressure ramp (pressure_ramp_steps = " + std::to_string(sc.pressure_ramp_steps) +
             ") does not end within max_steps = " + std::to_string(sc.max_steps) +
             ": the stage stops before the full pressure is applied");
      // The contacts' mean overlap at this pressure: with k_n = E r̄ (SPEC §2) and the mean normal force of a
      // packing under p, <f> = 4 pi r̄^2 p / (Z phi) (p = tr of the contact sum (1/V) sum f (x) l, l = 2 r̄), it is
      // <delta> / r̄ = 4 pi p / (Z phi E), ~3.5 p / E at Z phi ~ 3.6 (Z ~ 6, phi ~ 0.6). Measured on the tests' smoke run
      // (300 spheres, 190 kPa, E = 100 MPa; 0.0066 estimated): the mean 0.0083 r̄, the largest 0.051 of the smaller
      // radius, ~8x the estimate (the strong forces' tail, small spheres; tests/contacts_check.py checks both). Past a quarter of max_overlap the largest
      // reach it twice over (the run stops) and the grains are no longer hard; E in MPa written as Pa (E: 100) is such
      // a mistake (the stage then never reaches its pressure). Below, the run's own check decides.
      const double overlap = mean_overlap_estimate(sc.pressure, ep.contact.E);
      if (overlap > cfg.health.max_overlap / 4) {
        std::ostringstream w;
        w << std::setprecision(3) << "at " << sc.pressure / 1e3 << " kPa the contacts would overlap ~" << overlap
          << " of a radius on average (4 pi p / (Z phi E) with material.E = " << ep.contact.E
          << " Pa, Z phi ~ 3.6), the largest ~8x that, against numerics.max_overlap = " << cfg.health.max_overlap
          << ": raise material.E or lower the pressure (hard grains overlap under 0.01)";
        warn(w.str());
      }
      p_prev = sc.pressure;
      p_moved = false;
      plan.steps.push_back(double(sc.max_steps) * (sc.target_e0 > 0 ? sc.max_trials : 1));
    } else {
      const char* drainage = drainage_name(sc.drainage);
      const double strain_step = sc.axial_strain_rate * plan.dt;  // eps_a per step: the axial walls move at 1/2 rate H0
      if (sc.type == StageType::Triaxial && sc.axial_strain_rate == 0) {
        // a rest: max_steps steps, the axial walls held
        os << "triaxial " << drainage << " rest: the axial walls held, " << std::setprecision(6) << sc.max_steps
           << " steps (" << double(sc.max_steps) * plan.dt << " s), mu = " << sc.mu << ", mu_r = " << sc.mu_r;
        plan.steps.push_back(double(sc.max_steps));
      } else if (sc.type == StageType::Triaxial) {
        // The stage ends on the step whose start finds eps_a >= max_axial_strain (-eps_a in extension), one after the
        // strain is reached.
        const double need = std::ceil(sc.max_axial_strain / strain_step) + 1;
        os << "triaxial " << drainage;
        if (sc.b > 0) os << " (true triaxial, b = " << sc.b << ")";
        if (sc.constant_p) os << " at constant p'";
        if (sc.plane_strain) os << " in plane strain (the x walls held)";
        if (sc.k_ratio > 0) os << " on the K path sigma_3 = " << sc.k_ratio << " sigma_z";
        if (const auto ls = sc.lateral_slope) {
          os << " on the linear path dsigma_3/dsigma_z = " << *ls;
          if (*ls == Real(-0.5)) os << " (constant p')";
          else os << " (dq/dp' = " << 3 * (1 - *ls) / (1 + 2 * *ls) << ")";
        }
        const bool stress_ended = sc.stress_ended();  // a stress end, the strain a cap
        if (stress_ended) {
          os << (sc.extension ? " extension" : "") << " to ";
          if (sc.q_end) os << "q = " << *sc.q_end / 1e3 << " kPa";
          else if (sc.eta_end) os << "q/p' = " << *sc.eta_end;
          else if (sc.dsigma_end) os << "|sigma - sigma_0| = " << *sc.dsigma_end / 1e3 << " kPa";
          else if (sc.sigma_v > 0) os << "sigma_v = " << sc.sigma_v / 1e3 << " kPa";
          else os << "sigma_v,max / " << sc.ocr;
          os << " (or eps_a = " << (sc.extension ? "-" : "") << sc.max_axial_strain << ")";
        } else {
          os << (sc.extension ? " extension to eps_a = -" : " to eps_a = ") << sc.max_axial_strain;
        }
        os << " at " << sc.axial_strain_rate << "/s, mu = " << sc.mu << ", mu_r = " << sc.mu_r << ": "
           << (stress_ended ? "at most " : "") << std::setprecision(6) << need << " steps";
        // Right after a consolidation sigma_v is its pressure: a stress end on the wrong side of it is met at once.
        if (sc.sigma_v > 0 && p_prev > 0 && !p_moved && (sc.extension ? sc.sigma_v >= p_prev : sc.sigma_v <= p_prev)) {
          std::ostringstream w;
          w << std::setprecision(4) << "sigma_v = " << sc.sigma_v / 1e3 << " kPa is " << (sc.extension ? "above" : "below")
            << " the " << p_prev / 1e3 << " kPa the stage starts from: it " << (sc.extension ? "unloads" : "loads")
            << " to it at once (ends on its first step)";
          warn(w.str());
        }
        // Before any shear stage q is 0 (a consolidation's, a sample file's, which one wrote, a gas's): a q or q/p' end on
        // the wrong side of it is met at once.
        if (const Real qe = sc.q_end.value_or(sc.eta_end.value_or(0));
            (sc.q_end || sc.eta_end) && !p_moved && (sc.extension ? qe >= 0 : qe <= 0)) {
          std::ostringstream w;
          w << std::setprecision(4) << (sc.q_end ? "q = " : "q/p' = ") << (sc.q_end ? qe / 1e3 : qe)
            << (sc.q_end ? " kPa" : "") << " is " << (sc.extension ? "at or above" : "at or below")
            << " the q = 0 the stage starts from (no shear stage before it): it ends on its first step";
          warn(w.str());
        }
        plan.steps.push_back(std::min(need, double(sc.max_steps)));
        if (need > double(sc.max_steps)) {
          std::ostringstream w;
          const char* sign = sc.extension ? "-" : "";
          w << std::setprecision(4) << "eps_a = " << sign << sc.max_axial_strain << " takes " << need
            << " steps, but max_steps = " << sc.max_steps << ": the stage would stop at eps_a = " << sign
            << double(sc.max_steps) * strain_step << "; raise max_steps (or axial_strain_rate)";
          warn(w.str());
        }
      } else if (sc.stress_reversal() || sc.sigma_v_reversal()) {
        // Stress reversal: how far each half cycle strains depends on the sample (more as p' falls).
        os << "cyclic " << drainage << ", " << sc.cycles << " cycle" << plural(sc.cycles) << " of "
           << (sc.sigma_v_reversal() ? "sigma_v = sigma_v,0 +- " : "q = +-");
        if (sc.sigma_v_reversal()) os << sc.sigma_v_amplitude / 1e3 << " kPa (the lateral walls held)";
        else if (sc.csr > 0) os << "2 x " << sc.csr << " p'_c";
        else os << sc.q_amplitude / 1e3 << " kPa";
        os << " at "
           << sc.axial_strain_rate << "/s, or until |eps_a| = " << sc.max_axial_strain << ", mu = " << sc.mu
           << ", mu_r = " << sc.mu_r << ": at most " << sc.max_steps << " steps";
        plan.steps.push_back(double(sc.max_steps));
      } else {
        // Strain reversal: eps_a reaches A after n = ceil(A / strain step) steps and turns at the start of the next,
        // so each peak lies n steps from 0 (overshooting A by under a step's strain) and a cycle takes 4 n steps; the
        // stage ends on the step that finds eps_a back at 0, one after it.
        const double need = 4 * double(sc.cycles) * std::ceil(sc.strain_amplitude / strain_step) + 1;
        os << "cyclic " << drainage << ", " << sc.cycles << " cycle" << plural(sc.cycles) << " of eps_a = +-"
           << sc.strain_amplitude << " at "
           << sc.axial_strain_rate << "/s, mu = " << sc.mu << ", mu_r = " << sc.mu_r << ": " << std::setprecision(6)
           << need << " steps";
        plan.steps.push_back(std::min(need, double(sc.max_steps)));
        const double quarter = sc.strain_amplitude / sc.axial_strain_rate;
        os << ", each quarter cycle " << std::setprecision(3) << quarter * 1e3 << " ms = " << quarter / transit
           << " wave transits of the sample (~" << transit * 1e3 << " ms)";
        // Measured on the tests' 250-sphere and the quick 3 000-sphere sample (configs/README.md, cycles.csv): E_eq
        // within 2 % of its slow limit from 4 transits a quarter cycle, 40 % and 3x too high at 1 and 0.5.
        if (quarter < kQuasiStaticTransits * transit) {
          std::ostringstream w;
          w << std::setprecision(3) << "each quarter cycle (strain_amplitude / axial_strain_rate = " << quarter * 1e3
            << " ms) lasts only " << quarter / transit << " times the ~" << transit * 1e3
            << " ms a compression wave takes across the sample: the loops (cycles.csv) will measure its inertia as "
               "well as the material, E_eq and D too high; axial_strain_rate <= "
            << sc.strain_amplitude / (kQuasiStaticTransits * transit) << "/s gives " << kQuasiStaticTransits
            << " transits";
          warn(w.str());
        }
        if (need > double(sc.max_steps)) {
          std::ostringstream w;
          w << std::setprecision(4) << sc.cycles << " cycle" << plural(sc.cycles) << " of eps_a = +-"
            << sc.strain_amplitude << (sc.cycles == 1 ? " takes " : " take ") << need
            << " steps, but max_steps = " << sc.max_steps << ": the stage would stop after ~"
            << double(sc.max_steps) * strain_step / (4 * sc.strain_amplitude) << " cycles; raise max_steps";
          warn(w.str());
        }
      }
      if (sc.type == StageType::Cyclic && sc.drainage != Drainage::Oedometric &&
          sc.liquefaction_da_strain >= 2 * sc.max_axial_strain) {
        // (config.cpp refuses such a value given; this is the default, 5 %, against a small max_axial_strain)
        std::ostringstream w;
        w << std::setprecision(4) << "liquefaction_da_strain = " << sc.liquefaction_da_strain
          << " cannot be met: no half cycle spans more than 2 max_axial_strain = " << 2 * sc.max_axial_strain
          << "; set liquefaction_da_strain below it";
        warn(w.str());
      }
      if (p_prev > 0 && sc.axial_strain_rate > 0) {  // (a rest strains nothing)
        // Advice, not a warning: a fast shear is a choice (the tests' miniatures make it); the series
        // reports the measured I of every row.
        const double I = sc.axial_strain_rate * d_mean * std::sqrt(density * scaling / p_prev);
        plan.inertial_max = std::max(plan.inertial_max, I);
        plan.inertial_test = I;  // a later straining stage replaces it
        os << ", inertial number ~" << std::setprecision(2) << I << " at p' = " << std::setprecision(4) << p_prev / 1e3
           << " kPa";
        // After a K0 loading (p' rises: I is lower) or cycles (p' falls: higher) the stage starts where the run finds
        // it; the consolidation's p' is the estimate the plan has.
        if (p_moved) os << " (the last consolidation's; the stages since move p')";
        if (I > kQuasiStaticInertial)
          os << " (above the quasi-static " << kQuasiStaticInertial << ": lower axial_strain_rate or density_scaling)";
        // With the fines' mass scaling, a fine of radius r < r_f has the density rho s (r_f / r)^3, so its inertial
        // number 2 r sqrt(rho_eff / p') grows as r_f^1.5 / sqrt(r): the smallest sphere's is the largest. Measured
        // (perf/FINES_SCALING.md, Cu 3, r_min 0.1 mm, 100 kPa): r_f = 0.2 mm at 1/s, this 2.9e-3, biased the
        // critical q/p' by +0.059 (the seeds' sd 0.017); at 0.25/s, 7.3e-4, within the scatter.
        if (const Real rf = ep.fines_mass_radius; rf > r_min) {
          const double If = sc.axial_strain_rate * 2 * std::sqrt(double(rf) * rf * rf / r_min) *
                            std::sqrt(density * scaling / p_prev);
          plan.inertial_max = std::max(plan.inertial_max, If);
          plan.inertial_test = std::max(I, If);
          os << "; the scaled fines' ~" << std::setprecision(2) << If << " (the smallest sphere at its scaled mass)";
          if (If > kQuasiStaticInertial)
            os << " (above the quasi-static " << kQuasiStaticInertial
               << ": lower axial_strain_rate or numerics.fines_mass_radius)";
        }
      }
    }
    if (sc.type != StageType::Isotropic) p_moved = true;
    plan.stages.push_back(os.str());
  }
  return plan;
}
}  // namespace

RunResult run_simulation(const RunConfig& cfg, const RunOptions& opt) {
  // The run's config.yaml records the directory it runs in: --out's where given (it recorded output.dir, another
  // run's directory or none, which `grainlab run RUN/config.yaml --resume` then went to)
  RunConfig c = cfg;
  if (!opt.out_dir.empty()) c.out_dir = opt.out_dir;
  Laboratory lab(c, opt);
  return lab.run();
}

}  // namespace grainlab
