#pragma once
// Parameter studies (issue 8): one YAML names a base run config and the axes to sweep; each distinct
// sample is prepared once and reused by every shear that needs it; jobs are resumable (finished ones
// are skipped, interrupted ones resumed); the report is written by scripts/grainlab_plot.py.
#include <map>
#include <string>
#include <vector>

namespace grainlab {

struct StudyJob {
  std::string name;         // directory name under jobs/
  std::string sample_name;  // preparation job this shear uses
  bool is_sample = false;
  double mu_r = 0, e0 = 0, p0 = 0;  // e0 = 0: the base config's preparation without a target
  // material.E from the E axis or an extra job (0: the base's): the contact stiffness, k_n = E rbar (SPEC §2), a
  // sample's (each E its own preparation: the packing consolidates to another overlap) and its shears'
  double E = 0;
  // mu_r set on every stage (mu_r axis or an extra job's key); else only the material's, which stages without their
  // own take (SPEC §6.2: each stage may set its own mu_r, which the study then leaves as the base gives it)
  bool set_mu_r = false;
  long seed = 0, count = 0;
  // the shear stages' drainage: the study's (drainage axis or an extra job's key; set_drainage) or else the base's
  // first shear stage's, for the name and the report (each stage keeps its own where it is not set)
  std::string drainage;
  bool set_drainage = false;
  // triaxial stages' loading direction, "compression" or "extension": the study's (direction axis or an extra job's
  // key; set_direction) or else the base's first triaxial stage's, for the name and the report
  std::string direction;
  bool set_direction = false;
  // triaxial stages' b = (sigma_2 - sigma_3) / (sigma_1 - sigma_3) (true triaxial, drained compression): the study's
  // (b axis or an extra job's key; set_b) or else the base's first triaxial stage's, for the name and the report
  double b = 0;
  bool set_b = false;
  // triaxial stages' stress path of a drained shear, "constant_sigma3" or "constant_p" (StageConfig::constant_p): the
  // study's (stress_path axis or an extra job's key; set_stress_path) or else the base's first triaxial stage's
  std::string stress_path;
  bool set_stress_path = false;
  double csr = 0;           // cyclic shears: cyclic stress ratio q_amplitude / (2 p'_0) (0: the base's q_amplitude)
  double q_amplitude = 0;   // the amplitude csr gives at the job's p'_0 [Pa] (0: the base's)
  long cycles = 0;          // the base's cyclic stage's cycles (0: a monotonic shear), for the report
  // cyclic shears with a strain_amplitude axis: the strain-controlled stage's amplitude, and its axial_strain_rate
  // scaled from the base's so that every job's quarter cycle lasts as long (a lab test at one loading frequency)
  double strain_amplitude = 0, strain_rate = 0;
  // triaxial stages' axial_strain_rate from the axial_strain_rate axis or an extra job's key (0: the base's), and the
  // job's name without its _rate suffix, which the tests of one rate series share ("" without a rate)
  double rate = 0;
  std::string rate_group;
  // triaxial stages' max_axial_strain from an extra job's key (0: the base's): tests of one sample that end at other
  // strains, e.g. an oedometric test at 3 % beside a drained shear to its critical state (the report's K0 and Jaky);
  // not in the name, so that a larger value extends the job that ran
  double strain = 0;
  // the sample's sieve curve from the grading axis (sample.grading as YAML, in place of the base's sizes; "" for the
  // base's), its name (the job's "_g" suffix) and the curve's Cu = D60/D10 (the report's preparation figure's x)
  std::string grading_yaml, grading_name;
  double grading_cu = 0;
  // the sample file from the sample_file axis (absolute; "" for the base's sample) and its name there (the sample
  // job's "_f" suffix, the report's section): its spheres in place of the base's sample, consolidated by the job's
  // preparation stages at its p0 and mu_r
  std::string specimen_name, specimen_file;
  double specimen_e = 0;  // the file's void ratio in its walls, as it holds it (0: unknown): validate's list
  std::string config_yaml;  // the generated run config
  // A stage axis's values (`axes: {stages.<name>.<key>: [...]}`): the key set on that stage of a shear job (a K path's
  // k_ratio, an unloading's stress_ratio, an oedometer's ocr); a sample job's, the keys of its preparation stages
  // (each value a sample of its own), and a shear's every key (its sample's too); in the job's name
  // ("_<stage>-<key><value>", a shear's from its sample's name) and study.json's "stage_keys"
  struct StageKey {
    size_t stage;  // index in the base's stages
    std::string stage_name, key;
    double value;
  };
  std::vector<StageKey> stage_keys;
};

struct Study {
  std::string path, base;
  std::string base_sample;  // the base's sample.file (absolute) where it starts from a saved sample, else empty
  std::string strain_stage;  // the base's strain-controlled cyclic stage (the strain_amplitude axis sets it), if any
  std::vector<StudyJob> samples, shears;
  double window = 0.05, qp_tol = 0.05, p_tol = 0.05, e_tol = 0.005;  // critical-state detection
  // How the report takes a shear's peaks (largest |q|, q/p', obliquity; `peak: {window: W, max_ke_ratio: X}`): each
  // measure averaged over W of axial strain about each row first (0: single rows), since the stress ratio of a few
  // thousand spheres fluctuates from row to row (0.25 to 1.4 deg) and the largest of single rows is its largest
  // fluctuation; and over the rows whose kinetic / elastic energy (series ke_ratio) is at most max_ke_ratio (0: every
  // row).
  double peak_window = 0, peak_max_ke = 0;
  // What the study may not do as its author meant, said by `grainlab validate` and at the study's start
  std::vector<std::string> warnings;
};

Study load_study(const std::string& path);

// The run config (YAML text) of a shear job of s, its sample read from sample_file: what the study writes to its
// job.yaml, less the header.
std::string shear_config(const Study& s, const StudyJob& j, const std::string& sample_file);

// `grainlab validate` of a study: every job planned as it would run (plan_run; a shear planned on the radii its
// sample job will draw, as the sample file does not exist yet). Throws the first job's error, naming the job.
struct StudyPlan {
  long sample_steps_max = 0;  // the longest preparation stage's step cap
  long shear_steps_min = 0, shear_steps_max = 0;
  double shear_steps_total = 0;
  // shears with a stage of unknown length (a stress-reversal cyclic stage ends at its cycles or max_axial_strain):
  // how many, and the largest step cap among them; the three above count the others only
  long capped_shears = 0, capped_steps_max = 0;
  // of the others, those with a stress-ended triaxial stage (StageConfig::stress_ended): counted to its strain cap, so
  // their steps above are an upper bound
  long stress_ended_shears = 0;
  double memory_need_max = 0;  // bytes, the largest job
  // the tests' estimated inertial numbers at their p'_0 (each job's last straining stage: RunPlan::inertial_test), and
  // the largest of any stage of theirs (a K0 loading before the shear at the base's rate, which a rate axis keeps)
  double inertial_min = 0, inertial_max = 0, inertial_all_max = 0;
  std::vector<std::string> warnings;  // each names its job
  // the grading axis's curves: the shortest time step of each curve's sample jobs [s] (a wider curve's fines step
  // shorter: SPEC §4's m_min against k_max), by curve name
  std::map<std::string, double> grading_dt;
  // each shear's planned work, its spheres times its planned steps (a capped stage's cap), by job name: run_study
  // starts the longest first
  std::map<std::string, double> shear_work;
};
StudyPlan plan_study(const Study& s);

// A wall time as a person reads it: "12.3 s", "3 min 05 s", "2 h 05 min" (the study's progress lines).
std::string duration_text(double seconds);

// The wall time the shears not yet finished will take (run_study's progress lines): `left` the planned work (spheres
// x steps, StudyPlan::shear_work) of each, `rate` the planned work a slot has done a second on the shears finished so
// far, `slots` the jobs run at a time. At least the longest one's time, and at least all of them shared evenly by the
// slots (Graham: longest first ends within 4/3 of the larger bound). 0 where nothing is left.
double shears_left_seconds(const std::vector<double>& left, double rate, int slots);

struct StudyOptions {
  std::string out_dir, self_exe;
  int jobs = 1, threads = 0;
  bool quiet = false;
};
// A job's share of `threads` among `jobs` running at once: at least 1.
inline int threads_per_job(int threads, int jobs) {
  const int share = threads / (jobs > 1 ? jobs : 1);
  return share > 1 ? share : 1;
}

// Runs every job (resumably) and writes the report; returns the process exit code.
int run_study(const Study& s, const StudyOptions& o);

}  // namespace grainlab
