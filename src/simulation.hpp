#pragma once
// The virtual laboratory (SPEC §6): generate or load a sample, run its stages (isotropic consolidation
// with an optional void-ratio target, triaxial undrained/drained shear), write the series, snapshots,
// samples and checkpoints of one run directory, and resume it exactly.
#include <limits>
#include <string>
#include <vector>

#include "config.hpp"

namespace grainlab {

struct RunOptions {
  std::string out_dir;  // overrides the config's output.dir when not empty
  bool quiet = false;
  bool resume = false;
  long stop_after_steps = -1;  // testing aid: behave as if interrupted after this many steps (-1: never)
  std::string threads_note;    // printed under the run's first line (why it runs at fewer threads than cores)
  // A study's check of a job its edit extends (`run --check-resume`): the refusals --resume of this config would
  // make (a key that differs, another time step, an end moved before where the run is) as its error, nothing written.
  bool check_resume = false;
};

struct StageResult {
  std::string name;
  bool converged = false;  // isotropic: equilibrium reached; triaxial: max strain reached
  long steps = 0;
  Real p = 0, q = 0, e = 0;
  Real mu = 0;             // friction used (the search result when target_e0 is set)
  // cyclic stages: the cycle number N reached, and N at each liquefaction criterion (-1: not met; StageConfig)
  Real cycle = 0, n_ru = -1, n_da = -1;
  // drained shear stages: the largest servo_error over the stage's series rows (NaN: none measured, or a stage
  // finished by a build before it)
  Real servo_error = std::numeric_limits<Real>::quiet_NaN();
  // cyclic stages: the first complete cycle's duration over 4, in wave transits of the sample (RunPlan::transit):
  // how slowly the loops were loaded, measured (a stress-controlled stage's cannot be known before it runs; NaN: no
  // complete cycle, or a stage finished by a build before it)
  Real quarter_transits = std::numeric_limits<Real>::quiet_NaN();
  // isotropic stages: the void ratio of the interior (series e_inner) and of the core, the central eighth of the box
  // (half of each side), at the stage's end: how homogeneous the consolidated sample is (kGradedCore; NaN: a stage
  // finished by a build before them)
  Real e_inner = std::numeric_limits<Real>::quiet_NaN(), e_core = std::numeric_limits<Real>::quiet_NaN();
  // shear stages: the stress it started from, p'_0 and q_0; undrained ones also the pore pressure it started with,
  // u_0, r_u's reference p'_c and u at its end (Laboratory::start_stage; NaN: a stage finished by a build before them)
  Real p0 = std::numeric_limits<Real>::quiet_NaN(), q0 = std::numeric_limits<Real>::quiet_NaN();
  Real u0 = std::numeric_limits<Real>::quiet_NaN(), pc = std::numeric_limits<Real>::quiet_NaN();
  Real u = std::numeric_limits<Real>::quiet_NaN();
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

// `s` as a JSON string literal: quoted, with quotes, backslashes and control characters escaped.
std::string json_string(const std::string& s);

// What a run will do, known before it starts (no Kokkos, nothing placed or written): `grainlab validate` prints
// it, and a run checks it before it creates anything.
struct RunPlan {
  long particles = 0;
  Real dt = 0, dt_limit = 0;      // the step of every stage; the SPEC §4 limit for the run's stiffest stage [s]
  bool rolling = false;           // some stage has mu_r > 0 (the limit includes the rolling period)
  double memory_need = 0, memory_available = 0;  // bytes (available: 0 where unknown)
  std::string memory_source;
  std::vector<std::string> stages;    // one line a stage: what it does, for how many steps
  std::vector<double> steps;          // a stage's steps: triaxial to its end strain (at most max_steps),
                                      // isotropic its max_steps (it ends at equilibrium, usually sooner)
  std::vector<std::string> warnings;  // a stage that max_steps cuts short, a ramp that never ends
  std::vector<std::string> sample_warnings;  // of the spheres themselves (a grading they miss): a study says them once
  double inertial_max = 0;            // the largest estimated inertial number of a shear (0: p' unknown)
  // that of the last stage that strains the sample (the test itself; a K0 loading before it is its consolidation)
  double inertial_test = 0;
  double transit = 0;                 // the time a compression wave takes across the sample [s] (plan_run)
  bool placed = false;                // the sample was placed as the run will place it (plan_run's place)
  std::string sample;                 // the sample's sizes: where from, D50, Cu, Cc by mass (and against its grading)
  std::string fines;                  // numerics.fines_mass_radius's effect (empty: off): spheres, mass, step
  GradingIndices grading;             // the sample's own (its spheres', by mass)
  double sample_e = 0;                // a sample file's void ratio in its box of walls (0: drawn, or no box)
};
// The largest miss, in percentage points passing at a sieve, of a drawn sample against its sample.grading above which
// plan_run warns (choice: the coarse fractions of a small sample are a few spheres each; a sieve analysis repeats to
// about 1-2 points, ASTM D6913's precision statement, so 5 is well past a lab's own scatter).
constexpr double kGradingMiss = 5;
// plan_run's place checks samples of up to this many spheres (choice: 2e5 place in 0.5-0.8 s on one core of the
// 2-core VM, perf/startup.sh placement, 1e6 in ~3.5 s, about half of `perf/startup.sh start`; a study validates
// every sample job so; a larger sample, whose box loses little to its walls, is placed at the run's start, before
// anything is written).
constexpr long kPlaceCheckMax = 200000;
// Throws (with the same messages as the run) when the sample cannot be drawn or read, does not fit in memory,
// or the config's dt is above the stable limit. p_start: the p' a first triaxial stage starts from, where the
// caller knows it (a study's shear of a sample it prepares); 0: unknown. place: also place a generated sample as the
// run will (up to kPlaceCheckMax spheres), which throws the run's error where it cannot be placed (validate).
RunPlan plan_run(const RunConfig& cfg, Real p_start = 0, bool place = false);
// The quasi-static limit of the inertial number (GDR MiDi 2004, Eur. Phys. J. E 14: I < 1e-3).
constexpr double kQuasiStaticInertial = 1e-3;
// A cyclic stage's quarter cycle, in transit times of a compression wave across the sample, below which its loops are
// dynamic (choice, beyond SPEC §6.3; measured, configs/README.md): plan_run warns of a strain-controlled stage, a run
// of a stress-controlled one at its first load reversal.
constexpr double kQuasiStaticTransits = 4;
// A consolidated sample is graded when its core (the central eighth of the box) has a void ratio this much above its
// interior's (the box 2 mean diameters in from the walls): the run warns at the end of an isotropic stage. (choice)
// Measured on 9 samples of 5 000-20 000 spheres each way (mu = 0.5, 100 and 190 kPa, seeds 11-13): compacted
// homogeneously (affine) -0.003 to +0.012, by the walls alone +0.019 to +0.042; 0.015 lies between. Below
// kGradedMinCount spheres the core is too small to tell: at 2 000, affine -0.010 to +0.024 against walls +0.013 to
// +0.030 (250 spheres: +0.028 affine), so the run records the two void ratios but does not warn.
constexpr double kGradedCore = 0.015;
constexpr int kGradedMinCount = 5000;
// Empty when the config `now` only extends `then` (both resolved, as a run's checkpoint records its config) for a
// run whose newest checkpoint lies in stage k (k = the number of stages: finished); otherwise the first differing
// config key. What --resume accepts: stages appended, the end (max_axial_strain, max_steps) of stage k moved, and
// the stages after k (not started) changed.
std::string extension_mismatch(const std::string& then, const std::string& now, int k);
// `then` (a resolved config) with now's checkpoint cadence (output.checkpoint_every, checkpoint_minutes,
// keep_checkpoints), which --resume may change: it changes nothing a run computes or records.
std::string with_checkpoint_cadence(const std::string& then, const RunConfig& now);
// The same for two resolved configs (a study's job.yaml then and now): `config` with the cadence of `cadence_from`, as
// config_fingerprint writes it (output.dir blanked); `config` as it is where either does not parse.
std::string with_checkpoint_cadence_of(const std::string& config, const std::string& cadence_from);
// The plural ending of a count's noun: "1 stage", "2 stages" (printf("%ld stage%s", n, plural(n))).
inline const char* plural(long n) { return n == 1 ? "" : "s"; }
// "4.4 MiB", "1.2 GiB".
std::string memory_amount(double bytes);
// The cores this process may run on: its CPU affinity (taskset, a container's cpuset), as OpenMP counts them for its
// default thread count (the online CPUs where the affinity cannot be read), and at most what a cgroup CPU quota
// (docker --cpus: cgroup_cores) allows, which OpenMP does not see. Where OpenMP binds (OMP_PROC_BIND,
// OMP_PLACES) the CPUs of its places: libgomp has pinned the process to the first place before main, and the affinity
// alone said 1 core (compat::openmp_places).
int usable_cores();
// An exclusive lock on the open file fd (flock, LOCK_NB): true where taken, false where another process holds it. A
// filesystem without locks (Lustre mounted without -o flock: ENOSYS; NFS without its lock daemon: ENOLCK) refused every
// run there as "in use by another grainlab process": there the run goes on unlocked, and says so once on stderr
// (`path`: the lock file).
bool lock_or_warn(int fd, const std::string& path);
// The threads a CPU run starts where neither --threads nor OMP_NUM_THREADS chose them (OpenMP's own default is a thread
// a core): a thread for each kSpheresPerThread spheres, at least 1 and at most `cores`. A step opens ~4 OpenMP
// parallel regions, each a fork, barriers and a join across every thread (~7 us a region at 2 threads on the
// project's VM, more with more threads): a small sample spread over many threads waits on them more than it
// computes (perf/NOTES.md sessions 70 and 71). The dynamics do not depend on the count (fixed-chunk sums: the same bits
// at any), so the choice changes only the time a run takes.
constexpr long kSpheresPerThread = 1000;
int default_threads(long spheres, int cores);
// The spheres a run config starts with: sample.count, or the sample file's (0 where the file cannot be read: the run
// itself says why).
long config_spheres(const RunConfig& cfg);
// The cores of a cgroup v2 cpu.max text, "QUOTA PERIOD" (microseconds each), rounded up; 0 for "max PERIOD" (no
// limit) or an unreadable text.
int cores_of_cpu_max(const std::string& text);
// This process's cgroup limits, from /proc/self/cgroup's text and the cgroup mount `root`: v2 (cpu.max, memory.max)
// or v1 (cpu.cfs_quota_us over cpu.cfs_period_us, memory.limit_in_bytes: RHEL 7 and 8, Ubuntu 20.04 and a container on
// such a host, where only v2 was read and a `docker --cpus 2` container on 64 cores started 64 threads). The
// cgroup's own file and each parent's (a parent's limit binds too; a container's namespaced view is the mount's
// root), the smallest. 0 where none limits.
int cgroup_cores(const std::string& proc_self_cgroup, const std::string& root = "/sys/fs/cgroup");
double cgroup_memory_limit(const std::string& proc_self_cgroup, const std::string& root = "/sys/fs/cgroup");
// Whether a stage writes its outputs again (series.csv, cycles.csv, run.h5: whole-file atomic rewrites that grow with
// the series) at a series row, rows_since rows and seconds_since seconds after the last write, which took last_cost
// seconds: after 20 rows, or a minute for a slow run, never sooner than 10 last_cost (the writes' share of the run
// stays about a tenth or less however long its series grows).
bool output_flush_due(int rows_since, double seconds_since, double last_cost);

RunResult run_simulation(const RunConfig& cfg, const RunOptions& opt);
// The source commit of this build (git describe --always --dirty: "954da91d2c4e", "954da91d2c4e-dirty"; "unknown"
// outside a git checkout), in every run's build string (run.h5, checkpoints, summary.json, its first line).
const char* source_commit();
// `grainlab version`: the build string without the thread count (Kokkos is not started for it).
std::string version_line();
// Whether a directory holds a study (`grainlab study --out`: its study.json, or its lock beside jobs/ before the first
// study.json), or a run (series.csv, run.h5 or checkpoints): neither kind of run goes where the other is.
bool holds_study(const std::string& dir);
bool holds_run(const std::string& dir);
// A sample file's state_digest (h5io.hpp), and the one a run directory's checkpoints record of the sample.file it
// started from ("" if none: not started, no sample.file, or a run of a build before the digest).
std::string sample_file_digest(const std::string& path);
std::string run_sample_digest(const std::string& dir);

// Series columns (name, unit), in order; documented in configs/README.md.
const std::vector<std::pair<std::string, std::string>>& series_columns();
// cycles.csv's columns: one row per completed cycle of a cyclic stage
const std::vector<std::pair<std::string, std::string>>& cycle_columns();

}  // namespace grainlab
