// grainlab command line: run and validate configs.
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "import.hpp"
#include "simulation.hpp"
#include "study.hpp"

namespace {
// Error lines are one line whatever a message contains (a YAML value may hold newlines).
std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  return s;
}
// The run directory a config is the own config.yaml of (RUN/config.yaml, RUN holding a run), else "".
std::string own_run_dir(const std::string& config) {
  const std::filesystem::path p(config);
  if (p.filename() != "config.yaml") return "";
  const std::string dir = p.parent_path().empty() ? "." : p.parent_path().string();
  return grainlab::holds_run(dir) ? dir : "";
}
int usage(FILE* f) {
  std::fprintf(f,
               "usage: grainlab run CONFIG.yaml [--out DIR] [--threads N] [--resume] [--quiet]\n"
               "       grainlab validate CONFIG.yaml\n"
               "       grainlab plot RUN_DIR [RUN_DIR...] [--out DIR]     figures (PNG + PDF)\n"
               "       grainlab csl RUN_DIR [RUN_DIR...] [--out DIR] [--window W]\n"
               "                                                          critical-state lines per mu_r (W: the axial-strain\n"
               "                                                          span a critical state holds steady, 0.05)\n"
               "       grainlab study STUDY.yaml [--out DIR] [--jobs N] [--threads N] [--quiet]\n"
               "       grainlab import PACKING.txt [--out SAMPLE.h5] [--box XLO XHI YLO YHI ZLO ZHI | --box FILE]\n"
               "                       [--crop XLO XHI YLO YHI ZLO ZHI | --crop FILE] [--columns X,Y,Z,R]\n"
               "                       [--size radius|diameter]\n"
               "                       [--scale S] [--density RHO] [--density-scaling S]\n"
               "                                                          a packing made elsewhere (x y z r a line, m; or a\n"
               "                                                          LAMMPS/LIGGGHTS dump or data file) as a sample\n"
               "                                                          file for sample: {file: SAMPLE.h5}\n"
               "       grainlab export SAMPLE.h5|RUN_DIR [--out FILE] [--format xyzr|lammps|dump]\n"
               "                                                          a sample, checkpoint or snapshot as text for\n"
               "                                                          another code (x y z r and its box; a LAMMPS data\n"
               "                                                          file; a LAMMPS dump of a run's snapshots: OVITO)\n"
               "       grainlab version                                   build: version, source commit, Kokkos, backend\n");
  if (f != stdout) return 2;  // after a bad command line, the usage alone
  std::fprintf(f,
               "exit codes: 0 done, 1 error (config, I/O, memory), 2 bad command line, 3 numerical blow-up,\n"
               "            130 interrupted (Ctrl-C, SIGTERM, SIGHUP, a closed output pipe: checkpoint written; continue with\n"
               "                --resume); SIGUSR1 writes a checkpoint and the run goes on (a study passes it to its jobs)\n"
               "threads: --threads N, else OMP_NUM_THREADS, else a thread a 1000 spheres up to the cores (a study\n"
               "         divides them among its --jobs)\n"
               "environment: OMP_NUM_THREADS (threads, unless --threads), GRAINLAB_MEMORY_LIMIT (bytes a run may\n"
               "             plan for; 16G, 512M), GRAINLAB_PYTHON (interpreter of plot, csl and the study report),\n"
               "             GRAINLAB_FIGURE_FORMATS (the figures' files: a list of png, pdf, svg; png,pdf)\n");
  return 0;
}
// A whole-number option in [lo, hi]. Anything else (empty, "abc", "2.5", out of range) gets one line naming the
// option and its range, and the caller exits 2, as for an unknown option: a typo never runs with a guess.
bool whole_number(const char* option, const char* text, long lo, long hi, long& value) {
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(text, &end, 10);
  if (end == text || *end || errno == ERANGE || v < lo || v > hi) {
    std::fprintf(stderr, "grainlab: %s must be an integer in [%ld, %ld], got '%s'\n", option, lo, hi, text);
    return false;
  }
  value = v;
  return true;
}
// OMP_NUM_THREADS sets the threads where --threads does not. A value libgomp cannot read (0, "abc", "1.5", "-2",
// empty) it reports with a line of its own and then starts one thread a core: a run would go on with a thread count
// nobody asked for (on a shared node, every core). Refused instead, like a bad --threads: one line naming the
// variable, what it holds and what it may hold, exit 2. libgomp's syntax: a whole number, blanks around it allowed,
// optionally the first of a comma list (nested levels); the count is that first number.
bool omp_threads_env_ok(int threads) {
#if defined(KOKKOS_ENABLE_OPENMP)
  const char* env = std::getenv("OMP_NUM_THREADS");
  if (threads > 0 || !env) return true;  // --threads given, or the variable unset: OpenMP's default
  std::string first(env);
  first = first.substr(0, first.find(','));
  const size_t b = first.find_first_not_of(" \t\n"), e = first.find_last_not_of(" \t\n");
  first = b == std::string::npos ? std::string() : first.substr(b, e - b + 1);
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(first.c_str(), &end, 10);
  if (first.empty() || !end || *end || errno == ERANGE || v < 1) {
    std::fprintf(stderr, "grainlab: OMP_NUM_THREADS must be a whole number in [1, %d] (or unset), got '%s' (OpenMP "
                 "would ignore it and start one thread a core): set it, unset it or give --threads N\n",
                 grainlab::compat::kMaxHostThreads, one_line(env).c_str());
    return false;
  }
#else
  (void)threads;  // no OpenMP threads: the variable means nothing to this build
#endif
  return true;
}
// OpenMP settings under which Kokkos's OpenMP backend cannot start `threads` (compat::host_threads): more than
// OMP_THREAD_LIMIT or OMP_MAX_ACTIVE_LEVELS=0 allow is refused (one line, exit 2; Kokkos 3.4 aborted in its
// initialisation, which grainlab passed on as "set fewer with --threads N"). OMP_DYNAMIC=true lets OpenMP give a
// region fewer threads than it asked for, as the load average suggests (libgomp: the same abort on this 2-core VM):
// turned off, as a run's thread count is the one its build line names, and its dynamics are the same bits at any
// count anyway.
bool omp_env_allows(int threads) {
#if defined(KOKKOS_ENABLE_OPENMP)
  omp_set_dynamic(0);
  std::string why;
  if (const int t = grainlab::compat::host_threads(threads), cap = grainlab::compat::openmp_thread_cap(&why); t > cap) {
    std::fprintf(stderr, "grainlab: %d threads, but %s allows %d: give --threads %d, or unset the variable\n", t,
                 why.c_str(), cap, cap);
    return false;
  }
#else
  (void)threads;
#endif
  return true;
}
// The command's one file argument, wherever it stands among the options (`grainlab run --threads 2 cfg.yaml`; before,
// "--threads" was read as the config): 1 where `arg` is it, 0 where `arg` is an option, -1 for a second file (said
// here; the caller exits 2).
int take_file(const std::string& arg, std::string& file) {
  if (!arg.empty() && arg[0] == '-') return 0;
  if (!file.empty()) {
    std::fprintf(stderr, "grainlab: unexpected argument '%s' (the file is '%s'; one a command)\n", arg.c_str(),
                 file.c_str());
    return -1;
  }
  file = arg;
  return 1;
}
// A number option (a finite double; the range is the command's to check, naming its key): anything else gets one
// line and exit 2, as whole_number.
bool real_number(const char* option, const char* text, double& value) {
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text, &end);
  if (end == text || *end || errno == ERANGE || !std::isfinite(v)) {
    std::fprintf(stderr, "grainlab: %s must be a number, got '%s'\n", option, text);
    return false;
  }
  value = v;
  return true;
}
// The command line of a command that takes one file and options with values (import, export): take(option, a) reads
// the option's value(s) from argv, moving a past them, and returns 0, or 2 after one line saying why, or -1 for an
// option it does not know. Returns -1 when the line is read, else the exit code (help: 0; a bad line: 2).
template <class Take>
int file_and_options(int argc, char** argv, std::string& file, const Take& take) {
  for (int a = 2; a < argc; ++a) {
    const std::string s = argv[a];
    if (s == "-h" || s == "--help") return usage(stdout);
    if (const int f = take_file(s, file); f != 0) {
      if (f < 0) return 2;
      continue;
    }
    if (a + 1 >= argc) {
      std::fprintf(stderr, "grainlab: %s needs a value\n", s.c_str());
      return 2;
    }
    const int rc = take(s, a);
    if (rc == -1) {
      std::fprintf(stderr, "grainlab: unknown option '%s'\n", s.c_str());
      return usage(stderr);
    }
    if (rc != 0) return rc;
  }
  return -1;
}
// A command's lines printed, or its error as one line (exit 1).
template <class F>
int print_lines(const F& lines) {
  try {
    for (const std::string& line : lines()) std::printf("%s\n", line.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "grainlab: error: %s\n", one_line(e.what()).c_str());
    return 1;
  }
  return 0;
}
// `grainlab import`: its options, then import_packing (import.hpp).
int import_command(int argc, char** argv) {
  grainlab::ImportOptions io;
  std::string packing;
  const int rc = file_and_options(argc, argv, packing, [&](const std::string& s, int& a) {
    if (s == "--out") {
      io.out = argv[++a];
    } else if (s == "--box" || s == "--crop") {
      // six numbers, or a file holding them (the shared race's scene_32k_box.txt)
      double b[6];
      char* end = nullptr;
      std::strtod(argv[a + 1], &end);
      if (end != argv[a + 1] && !*end) {
        if (a + 6 >= argc) {
          std::fprintf(stderr, "grainlab: %s needs six numbers: xlo xhi ylo yhi zlo zhi (m)\n", s.c_str());
          return 2;
        }
        for (double& v : b)
          if (!real_number(s.c_str(), argv[++a], v)) return 2;
      } else {
        const std::string f = argv[++a];
        std::ifstream in(f);
        std::string extra;
        bool ok = bool(in);
        for (double& v : b) ok = ok && bool(in >> v);
        if (!ok || (in >> extra)) {
          std::fprintf(stderr, "grainlab: %s %s: %s\n", s.c_str(), f.c_str(),
                       ok       ? "holds more than six numbers (xlo xhi ylo yhi zlo zhi, m)"
                       : !std::filesystem::is_regular_file(f) ? "cannot read it (six numbers, or a file of them)"
                                : "not six numbers xlo xhi ylo yhi zlo zhi (m)");
          return 2;
        }
      }
      const bool crop = s == "--crop";
      (crop ? io.crop : io.box_given) = true;
      (crop ? io.crop_lo : io.lo) = {b[0], b[2], b[4]};
      (crop ? io.crop_hi : io.hi) = {b[1], b[3], b[5]};
    } else if (s == "--columns") {
      // X,Y,Z,R: four fields, numbers from 1 or the header's names
      io.columns.clear();
      std::string item;
      for (std::istringstream in(argv[++a]); std::getline(in, item, ',');) io.columns.push_back(item);
      if (io.columns.size() != 4 ||
          std::any_of(io.columns.begin(), io.columns.end(), [](const std::string& c) { return c.empty(); })) {
        std::fprintf(stderr, "grainlab: --columns needs four columns X,Y,Z,R: numbers from 1, or the header's names "
                             "(--columns 2,3,4,5)\n");
        return 2;
      }
    } else if (s == "--size") {  // what a text packing's fourth value is
      const std::string v = argv[++a];
      if (v != "radius" && v != "diameter") {
        std::fprintf(stderr, "grainlab: --size must be radius or diameter, got '%s'\n", v.c_str());
        return 2;
      }
      io.diameter = v == "diameter";
    } else if (s == "--scale" || s == "--density" || s == "--density-scaling") {
      double v = 0;
      if (!real_number(s.c_str(), argv[++a], v)) return 2;
      (s == "--scale" ? io.scale : s == "--density" ? io.density : io.density_scaling) = v;
      io.density_given |= s == "--density";
    } else {
      return -1;
    }
    return 0;
  });
  if (rc >= 0) return rc;
  if (packing.empty()) {
    std::fprintf(stderr, "grainlab import: which packing? (a text file of x y z r lines is missing)\n");
    return usage(stderr);
  }
  io.packing = packing;
  if (io.out.empty())  // beside the packing, its name with .h5
    io.out = std::filesystem::path(packing).replace_extension(".h5").string();
  for (int k = 0; k < 3; ++k) {  // --scale applies to the box and the crop as to the spheres: one unit for all
    io.lo[k] *= io.scale;
    io.hi[k] *= io.scale;
    io.crop_lo[k] *= io.scale;
    io.crop_hi[k] *= io.scale;
  }
  return print_lines([&] { return grainlab::import_packing(io); });
}
// `grainlab export`: its options, then export_sample (import.hpp).
int export_command(int argc, char** argv) {
  grainlab::ExportOptions eo;
  std::string in;
  const int rc = file_and_options(argc, argv, in, [&](const std::string& s, int& a) {
    if (s == "--out") {
      eo.out = argv[++a];
    } else if (s == "--format") {
      eo.format = argv[++a];
      if (eo.format != "xyzr" && eo.format != "lammps" && eo.format != "dump") {
        std::fprintf(stderr, "grainlab: --format must be xyzr, lammps or dump, got '%s'\n", eo.format.c_str());
        return 2;
      }
    } else {
      return -1;
    }
    return 0;
  });
  if (rc >= 0) return rc;
  if (in.empty()) {
    std::fprintf(stderr, "grainlab export: which file? (a sample, checkpoint or snapshot .h5 is missing)\n");
    return usage(stderr);
  }
  eo.in = in;
  if (eo.out.empty()) {  // beside the input (a run directory: beside it), its name with .txt, .data or .dump
    std::filesystem::path p = std::filesystem::path(in).lexically_normal();
    if (!p.has_filename()) p = p.parent_path();  // "runs/q/" -> "runs/q"
    const char* ext = eo.format == "xyzr" ? ".txt" : eo.format == "lammps" ? ".data" : ".dump";
    eo.out = std::filesystem::is_directory(p) ? p.string() + ext : p.replace_extension(ext).string();
  }
  return print_lines([&] { return grainlab::export_sample(eo); });
}
// An option that takes a value, given last without one ("--out" at the end of the line).
bool missing_value(const std::string& option, int a, int argc) {
  for (const char* o : {"--out", "--threads", "--jobs", "--stop-after-steps"})
    if (option == o && a + 1 >= argc) {
      std::fprintf(stderr, "grainlab: %s needs a value\n", o);
      return true;
    }
  return false;
}
}  // namespace

int main(int argc, char** argv) {
  // HDF5 (1.10 on) locks a file it opens, and on a filesystem without locks (NFS without its lock daemon: ENOLCK) the
  // open fails: every resume there found "no readable checkpoint", each called corrupt (test cli_no_file_locks).
  // grainlab's HDF5 files are written whole to a temporary name and renamed, so a reader never meets one half-written
  // and the locks protect nothing: off, unless the user's environment says otherwise; the report's Python (h5py)
  // inherits it.
  setenv("HDF5_USE_FILE_LOCKING", "FALSE", 0);
  if (argc < 2) return usage(stderr);
  const std::string cmd = argv[1];
  if (cmd == "-h" || cmd == "--help" || cmd == "help") return usage(stdout);
  if (cmd == "version" || cmd == "--version") {
    std::printf("%s\n", grainlab::version_line().c_str());
    return 0;
  }
  if (cmd == "import") return import_command(argc, argv);
  if (cmd == "export") return export_command(argc, argv);
  if (cmd == "plot" || cmd == "csl") {
    // The figures are matplotlib's: hand over to the script shipped with the sources. The interpreter is
    // $GRAINLAB_PYTHON, else Debian's /usr/bin/python3 (where scripts/setup-deps.sh installs matplotlib),
    // else python3 from PATH.
    const char* env = std::getenv("GRAINLAB_PYTHON");
    std::string py = env && *env ? env : (access("/usr/bin/python3", X_OK) == 0 ? "/usr/bin/python3" : "python3");
    std::string script = GRAINLAB_SOURCE_DIR "/scripts/grainlab_plot.py";
    std::vector<char*> args{const_cast<char*>(py.c_str()), const_cast<char*>(script.c_str())};
    for (int a = 1; a < argc; ++a) args.push_back(argv[a]);
    args.push_back(nullptr);
    execvp(py.c_str(), args.data());
    const int err = errno;
    std::fprintf(stderr, "grainlab: cannot run %s%s: %s (the figures need a Python 3 with numpy, matplotlib, h5py, "
                 "scipy, pyyaml: scripts/setup-deps.sh installs them)\n",
                 py.c_str(), env && *env ? " (GRAINLAB_PYTHON)" : "", std::strerror(err));
    return 1;
  }
  if (cmd == "study") {
    grainlab::StudyOptions so;
    char self[4096];
    const ssize_t len = readlink("/proc/self/exe", self, sizeof(self) - 1);
    so.self_exe = len > 0 ? std::string(self, size_t(len)) : std::string(argv[0]);
    std::string study;
    for (int a = 2; a < argc; ++a) {
      const std::string s = argv[a];
      if (s == "-h" || s == "--help") return usage(stdout);
      if (missing_value(s, a, argc)) return 2;
      if (const int f = take_file(s, study); f != 0) {
        if (f < 0) return 2;
      } else if (s == "--out" && a + 1 < argc) so.out_dir = argv[++a];
      else if ((s == "--jobs" || s == "--threads") && a + 1 < argc) {
        long v = 0;
        if (!whole_number(s.c_str(), argv[++a], 1, s == "--jobs" ? 4096 : grainlab::compat::kMaxHostThreads, v)) return 2;
        (s == "--jobs" ? so.jobs : so.threads) = int(v);
      } else if (s == "--quiet") so.quiet = true;
      else {
        std::fprintf(stderr, "grainlab: unknown option '%s'\n", s.c_str());
        return usage(stderr);
      }
    }
    if (study.empty()) {
      std::fprintf(stderr, "grainlab study: which study? (a STUDY.yaml is missing)\n");
      return usage(stderr);
    }
    // Its threads are --threads, else OMP_NUM_THREADS, else the usable cores, divided among the jobs: refused here,
    // before any job starts, where unreadable or too many.
    if (!omp_threads_env_ok(so.threads)) return 2;
    if (const int t = grainlab::compat::host_threads(so.threads); t > grainlab::compat::kMaxHostThreads) {
      std::fprintf(stderr, "grainlab: %d threads (OMP_NUM_THREADS): Kokkos's OpenMP backend runs at most %d: set fewer "
                   "with --threads N\n", t, grainlab::compat::kMaxHostThreads);
      return 2;
    }
#if defined(KOKKOS_ENABLE_OPENMP) && !defined(KOKKOS_ENABLE_CUDA)
    // The jobs are child processes started with --threads (their share), which overrides the variable in each: so
    // the study reads it here, as a run does, and treats it as --threads (a user's choice: no fewer for small jobs).
    // Before, a study ignored it and took every core (on a shared node, OMP_NUM_THREADS=4 started cores/jobs a job).
    if (so.threads == 0 && std::getenv("OMP_NUM_THREADS")) so.threads = grainlab::compat::host_threads(0);
#endif
    // a job's share (run_study's per_job_threads) within OMP_THREAD_LIMIT and OMP_MAX_ACTIVE_LEVELS, or every job fails
    if (so.threads > 0 && !omp_env_allows(grainlab::threads_per_job(so.threads, so.jobs))) return 2;
    if (!grainlab::is_study_file(study) && grainlab::is_run_config_file(study)) {
      std::fprintf(stderr, "grainlab: error: %s: a run config, not a study (a study names its `base`): run it with "
                   "`grainlab run %s`\n", study.c_str(), study.c_str());
      return 1;
    }
    try {
      return grainlab::run_study(grainlab::load_study(study), so);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "grainlab: error: %s\n", one_line(e.what()).c_str());
      return 1;
    }
  }
  if (cmd != "run" && cmd != "validate") {
    std::fprintf(stderr, "grainlab: unknown command '%s'\n", cmd.c_str());
    return usage(stderr);
  }
  std::string config;
  grainlab::RunOptions opt;
  int threads = 0;
  for (int a = 2; a < argc; ++a) {
    const std::string s = argv[a];
    if (s == "-h" || s == "--help") return usage(stdout);
    if (missing_value(s, a, argc)) return 2;
    if (const int f = take_file(s, config); f != 0) {
      if (f < 0) return 2;
    } else if (s == "--quiet") {
      opt.quiet = true;
    } else if (s == "--resume") {
      opt.resume = true;
    } else if (s == "--check-resume") {  // internal: grainlab study's check of a job its edit extends (RunOptions)
      opt.resume = opt.check_resume = opt.quiet = true;
    } else if (s == "--stop-after-steps" && a + 1 < argc) {  // testing aid: acts like Ctrl-C after N steps
      if (!whole_number("--stop-after-steps", argv[++a], 0, 1000000000000L, opt.stop_after_steps)) return 2;
    } else if (s == "--out" && a + 1 < argc) {
      opt.out_dir = argv[++a];
    } else if (s == "--threads" && a + 1 < argc) {
      long t = 0;
      if (!whole_number("--threads", argv[++a], 1, grainlab::compat::kMaxHostThreads, t)) return 2;
      threads = int(t);
    } else {
      std::fprintf(stderr, "grainlab: unknown option '%s'\n", s.c_str());
      return usage(stderr);
    }
  }
  if (config.empty()) {
    std::fprintf(stderr, "grainlab %s: which config? (a CONFIG.yaml is missing)\n", cmd.c_str());
    return usage(stderr);
  }
  if (cmd == "validate" && grainlab::is_study_file(config)) {
    try {
      const grainlab::Study st = grainlab::load_study(config);
      const grainlab::StudyPlan sp = grainlab::plan_study(st);
      std::printf("%s: ok (study: %zu sample%s, %zu shear test%s%s)\n", config.c_str(), st.samples.size(),
                  grainlab::plural(long(st.samples.size())), st.shears.size(), grainlab::plural(long(st.shears.size())),
                  st.shears.empty() ? "; a preparation study: its base has no shear stage" : "");
      std::printf("  preparation: at most %ld steps a stage (a target_e0 search: all its trials; a stage ends at "
                  "equilibrium, usually far sooner)\n",
                  sp.sample_steps_max);
      if (sp.shear_steps_total > 0)
        std::printf("  shear tests: %ld to %ld steps each, %.4g in all%s\n", sp.shear_steps_min, sp.shear_steps_max,
                    sp.shear_steps_total,
                    sp.stress_ended_shears > 0 ? " (at most: a stage that ends at a stress is counted to its strain cap)"
                                               : "");
      if (sp.capped_shears > 0)
        std::printf("  cyclic tests reversing at q: %ld, at most %ld steps each (max_steps; each ends at its cycles or "
                    "max_axial_strain, how soon depends on the sample)\n",
                    sp.capped_shears, sp.capped_steps_max);
      if (sp.inertial_max > 0)
        std::printf("  inertial number of the shears at their p'_0: ~%.2g to %.2g%s\n", sp.inertial_min, sp.inertial_max,
                    sp.inertial_max > grainlab::kQuasiStaticInertial
                        ? " (some above the quasi-static 0.001: lower axial_strain_rate or density_scaling)"
                        : "");
      // a stage before the shear that strains faster (a K0 loading at the base's rate, which an axial_strain_rate
      // axis leaves as it is): said apart, since the line above is the tests' own
      if (sp.inertial_all_max > sp.inertial_max * (1 + 1e-9))
        std::printf("  inertial number of the straining stages before the shears (a K0 loading at the base's rate): up to "
                    "~%.2g%s\n", sp.inertial_all_max,
                    sp.inertial_all_max > grainlab::kQuasiStaticInertial ? " (above the quasi-static 0.001)" : "");
      // Replicates: a 5 000-sphere sample's peak q/p' scatters by 0.010 from seed to seed (configs/seed-study.yaml),
      // so a study with one seed gives one draw per test; the report measures the spread where there are several.
      std::set<long> seeds;
      for (const grainlab::StudyJob& j : st.shears.empty() ? st.samples : st.shears) seeds.insert(j.seed);
      // The sample_file axis's files, each with its spheres, in the study's order.
      std::vector<std::string> files;
      for (const grainlab::StudyJob& j : st.samples) {
        std::ostringstream e;
        if (j.specimen_e > 0) e << ", e " << std::setprecision(4) << j.specimen_e;
        const std::string f = j.specimen_name + ": " + std::to_string(j.count) + " spheres" + e.str() + ", " +
                              j.specimen_file;
        if (!j.specimen_name.empty() && std::find(files.begin(), files.end(), f) == files.end()) files.push_back(f);
      }
      if (!files.empty()) {
        std::string list;
        for (const std::string& f : files) list += (list.empty() ? "" : "; ") + f;
        std::printf("  sample files: %zu, each consolidated again by its sample jobs in place of the base's sample "
                    "(%s)\n", files.size(), list.c_str());
      } else if (!st.base_sample.empty())
        std::printf("  sample: the base's sample.file %s, consolidated again by each sample job (one sample: no seed "
                    "to sweep)\n", st.base_sample.c_str());
      else if (seeds.size() == 1)
        std::printf("  seeds: 1 (each result is one sample's draw: a seed axis gives the report's sample-to-sample "
                    "scatter, configs/seed-study.yaml)\n");
      else if (seeds.size() > 1)
        std::printf("  seeds: %zu (%s that differ only in their seed get the report's sample-to-sample scatter)\n",
                    seeds.size(), st.shears.empty() ? "samples" : "tests");
      // The grading axis's curves, each with its Cu (the report's preparation figure's x), in the study's order.
      std::vector<std::string> curves;
      for (const grainlab::StudyJob& j : st.samples) {
        std::ostringstream c;
        c << j.grading_name << ": Cu " << std::setprecision(3) << j.grading_cu;
        if (const auto dt = sp.grading_dt.find(j.grading_name); dt != sp.grading_dt.end()) c << ", dt " << dt->second << " s";
        if (!j.grading_name.empty() && std::find(curves.begin(), curves.end(), c.str()) == curves.end())
          curves.push_back(c.str());
      }
      if (!curves.empty()) {
        std::string list;
        for (const std::string& c : curves) list += (list.empty() ? "" : "; ") + c;
        // dt: the finest spheres' (SPEC §4), so a wider curve takes more steps to the same end
        std::printf("  gradings: %zu curves in place of the base's sizes (%s)\n", curves.size(), list.c_str());
      }
      std::printf("  memory: about %s for the largest job (1.5 kB a sphere), times --jobs\n",
                  grainlab::memory_amount(sp.memory_need_max).c_str());
      std::fflush(stdout);  // the plan, then its warnings, also when both go to one file
      for (const std::string& w : st.warnings) std::fprintf(stderr, "grainlab: warning: %s\n", w.c_str());
      for (const std::string& w : sp.warnings) std::fprintf(stderr, "grainlab: warning: %s\n", w.c_str());
      return 0;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "grainlab: error: %s\n", one_line(e.what()).c_str());
      return 1;
    }
  }
  if (cmd == "run" && grainlab::is_study_file(config)) {
    std::fprintf(stderr, "grainlab: error: %s: a study (it names a `base`), not a run config: run it with "
                 "`grainlab study %s`\n", config.c_str(), config.c_str());
    return 1;
  }
  grainlab::RunConfig cfg;
  try {
    cfg = grainlab::load_run_config(config);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "grainlab: error: %s\n", one_line(e.what()).c_str());
    return 1;
  }
  // A run's own config.yaml (RUN/config.yaml, RUN holding the run) runs in RUN unless --out says otherwise: what
  // `grainlab run RUN/config.yaml --resume` means from any working directory, wherever RUN has been moved.
  if (cmd == "run" && opt.out_dir.empty()) opt.out_dir = own_run_dir(config);
  if (cmd == "validate") {
    // The same checks a run makes before it writes anything (the sample's stable time step against the
    // config's dt, memory, the spheres' placement), and what the run will do: a config that validates does not stop
    // at its start.
    grainlab::RunPlan plan;
    try {
      plan = grainlab::plan_run(cfg, 0, true);
    } catch (const std::exception& e) {
      // A run's own config whose sample file has gone (its preparation run cleaned up or moved): a fresh run needs
      // it, but the run itself resumes without it (its checkpoints record the sample), which "no such file" alone
      // did not say.
      std::string hint;
      const std::string d = own_run_dir(config);
      std::error_code ec;
      if (!d.empty() && !cfg.sample_file.empty() && !std::filesystem::exists(cfg.sample_file, ec) &&
          !grainlab::run_sample_digest(d).empty())
        hint = "; the run in " + d + " recorded that sample in its checkpoints, so `grainlab run " + config +
               " --resume` goes on without it (a fresh run needs the file)";
      std::fprintf(stderr, "grainlab: error: %s: %s%s\n", config.c_str(), one_line(e.what()).c_str(), hint.c_str());
      return 1;
    }
    std::printf("%s: ok (%zu stage%s, %ld particle%s%s)\n", config.c_str(), cfg.stages.size(),
                grainlab::plural(long(cfg.stages.size())), plan.particles, grainlab::plural(long(plan.particles)),
                !cfg.sample_file.empty() ? ", read from sample.file"
                : plan.placed           ? ", placed as the run places them"
                                        : "; their placement is checked at the run's start");
    std::printf("  dt = %.4g s: %.3g of the stable limit %.4g s (%s)\n", double(plan.dt), double(plan.dt / plan.dt_limit),
                double(plan.dt_limit), plan.rolling ? "rolling on in some stage" : "no rolling resistance");
    std::printf("  memory: about %s (1.5 kB a sphere)", grainlab::memory_amount(plan.memory_need).c_str());
    if (plan.memory_available > 0)
      std::printf("; %s available (%s)", grainlab::memory_amount(plan.memory_available).c_str(), plan.memory_source.c_str());
    std::printf("\n  %s\n", plan.sample.c_str());
    if (!plan.fines.empty()) std::printf("  %s\n", plan.fines.c_str());
    for (const std::string& l : plan.stages) std::printf("  %s\n", l.c_str());
    std::fflush(stdout);
    for (const auto* ws : {&plan.sample_warnings, &plan.warnings})
      for (const std::string& w : *ws) std::fprintf(stderr, "grainlab: warning: %s: %s\n", config.c_str(), w.c_str());
    return 0;
  }
  if (!omp_threads_env_ok(threads)) return 2;
#if defined(KOKKOS_ENABLE_OPENMP) && !defined(KOKKOS_ENABLE_CUDA)
  // Neither --threads nor OMP_NUM_THREADS: a thread for each kSpheresPerThread spheres, up to the cores (OpenMP would
  // start one a core, and on a 300-sphere run two threads took 1.5x one's time on the project's VM), and up to what
  // OMP_THREAD_LIMIT or OMP_MAX_ACTIVE_LEVELS allow.
  if (threads == 0 && !std::getenv("OMP_NUM_THREADS")) {
    std::string why;
    const int cores = grainlab::usable_cores(), cap = grainlab::compat::openmp_thread_cap(&why);
    const long spheres = grainlab::config_spheres(cfg);
    const int wanted = spheres > 0 ? grainlab::default_threads(spheres, cores) : cores;
    threads = std::min(wanted, cap);
    if (threads < wanted)
      opt.threads_note = "threads: " + std::to_string(threads) + " of " + std::to_string(cores) + " cores (" + why +
                         "); --threads N or OMP_NUM_THREADS to choose";
    else if (threads < cores)
      opt.threads_note = "threads: " + std::to_string(threads) + " of " + std::to_string(cores) + " cores (" +
                         std::to_string(spheres) + " spheres: a thread a " + std::to_string(grainlab::kSpheresPerThread) +
                         "; more threads would wait on each other at every step's barriers); --threads N or "
                         "OMP_NUM_THREADS to choose";
  }
#endif
  if (!omp_env_allows(threads)) return 2;
  try {
    grainlab::compat::initialize(threads);
  } catch (const std::exception& e) {  // more threads than Kokkos's OpenMP pool (compat::kMaxHostThreads)
    std::fprintf(stderr, "grainlab: %s: set fewer with --threads N\n", e.what());
    return 2;
  }
  // OpenMP threads beyond the cores wait on each other at every barrier (several a step): measured on the 2-core VM,
  // the tests' smoke run takes 0.47 s at 2 threads, 5.6 s at 3, 6.0 s at 4 (perf/startup.sh threads 4, medians of 3).
  // Allowed (a user may know better), said.
  if (const int t = grainlab::compat::host_threads(threads), cores = grainlab::usable_cores(); t > cores)
    std::fprintf(stderr,
                 "grainlab: warning: %d threads on %d core%s (this process's CPU affinity and quota): OpenMP threads beyond the "
                 "cores wait on each other at every step's barriers (a 300-sphere run: 12x slower at 3 threads on 2 "
                 "cores than at 2); --threads %d\n",
                 t, cores, grainlab::plural(long(cores)), cores);
  int rc = 0;
  try {
    const grainlab::RunResult r = grainlab::run_simulation(cfg, opt);
    if (r.interrupted) rc = 130;  // like a shell's Ctrl-C, but with a checkpoint written
  } catch (const grainlab::BlowUpError& e) {
    std::fprintf(stderr, "grainlab: error: %s: %s\n", config.c_str(), one_line(e.what()).c_str());
    rc = 3;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "grainlab: error: %s: %s\n", config.c_str(), one_line(e.what()).c_str());
    rc = 1;
  }
  Kokkos::finalize();
  return rc;
}
