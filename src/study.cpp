#include "study.hpp"

#include <fcntl.h>
#include <glob.h>
#include <sched.h>
#include <sys/file.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "config.hpp"
#include "h5io.hpp"
#include "simulation.hpp"

namespace grainlab {
namespace fs = std::filesystem;
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& key, const std::string& msg) {
  throw ConfigError(path + ": " + key + ": " + msg);
}

std::vector<double> numbers(const YAML::Node& n, const std::string& path, const std::string& key, bool signed_ok = false) {
  std::vector<double> out;
  // An absent axis (a study without `axes:` passes a null node for each) or one left blank has no values.
  if (!n || n.IsNull()) return out;
  const YAML::Node seq = n.IsSequence() ? n : YAML::Node(std::vector<YAML::Node>{n});
  for (auto v : seq) {
    double x = 0;
    try {
      x = v.as<double>();
    } catch (const YAML::Exception&) {
      fail(path, key, "must be a number or a list of numbers");
    }
    if (!std::isfinite(x) || (x < 0 && !signed_ok)) fail(path, key, signed_ok ? "values must be finite" : "values must be finite and >= 0");
    out.push_back(x);
  }
  return out;
}

std::string fmt(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

// A number in a job's name: fmt's, without a '+' ("1e9" for 1e+09, "2.5e8")
std::string name_number(double v) {
  std::string s = fmt(v);
  for (const char* from : {"e+0", "e+"})
    if (const size_t at = s.find(from); at != std::string::npos) s.replace(at, std::strlen(from), "e");
  return s;
}

// A base's K0 consolidations: its oedometric stages, and its K paths (drained, k_ratio: a CAU or CAD test's
// anisotropic consolidation), before a shear stage of another kind (a CK0U or CK0D test: isotropic, oedometric, then
// the shear). They prepare the anisotropic stress the shear starts from (Laboratory::
// start_stage), so the study's shear values (drainage, direction, b, stress_path, rate, end strain) leave them as the
// base gives them; they set the shear's. (They set every stage of an oedometer base, whose stages are all oedometric.)
std::vector<bool> k0_consolidations(const YAML::Node& stages) {
  std::vector<bool> k0(stages.size(), false);
  bool shear_after = false;  // a later shear stage that is not such a consolidation
  for (size_t k = stages.size(); k-- > 0;) {
    const YAML::Node st = stages[k];
    if ((st["type"] ? st["type"].as<std::string>() : "isotropic") == "isotropic") continue;
    const std::string drainage = st["drainage"] ? st["drainage"].as<std::string>() : "undrained";
    if (drainage == "oedometric" || (drainage == "drained" && st["k_ratio"])) k0[k] = shear_after;
    else shear_after = true;
  }
  return k0;
}

// The base config with the study's values applied (YAML node surgery, then validated by the loader). base_sample: the
// base's own sample.file, absolute (a base that starts from a saved sample: its sample jobs consolidate that sample
// again at their p0 and mu_r; it has no seed or count to set). A job's own file (the sample_file axis's) replaces the
// base's sample, drawn or saved, as a saved one.
// Sets a triaxial stage's axial_strain_rate (or max_axial_strain) to v and scales its step cap up with the duration (the
// old rate over v; v over the old end), never down: the cap the base gave its rate or end covers the same strain at a
// slower rate or a longer end, so the slow tests of a rate series are not cut short by a cap meant for the fast one.
// own_cap: the job sets the stage's max_steps itself (left alone).
void set_with_cap(YAML::Node& s, const char* key, double v, bool own_cap = false) {
  const StageConfig def;
  const bool rate = std::string(key) == "axial_strain_rate";
  const double old = s[key] ? s[key].as<double>() : rate ? def.axial_strain_rate : def.max_axial_strain;
  const double old_cap = s["max_steps"] ? s["max_steps"].as<double>() : double(def.max_steps);
  const double longer = rate ? (v > 0 ? old / v : 0) : v / old;  // the duration's factor (a rest's 0 rate: none)
  if (!own_cap && longer > 1) s["max_steps"] = long(std::min(1e12, std::ceil(old_cap * longer)));
  s[key] = yaml_number(v);
}

YAML::Node job_config(const YAML::Node& base, const StudyJob& j, bool shear_only, const std::string& sample_file,
                      const std::string& base_sample = "") {
  YAML::Node c = YAML::Clone(base);
  if (shear_only) {
    c["sample"] = YAML::Node(YAML::NodeType::Map);
    c["sample"]["file"] = sample_file;
  } else if (!j.specimen_file.empty() || !base_sample.empty()) {
    c["sample"] = YAML::Node(YAML::NodeType::Map);
    // absolute: the job's config lives in jobs/NAME/
    c["sample"]["file"] = j.specimen_file.empty() ? base_sample : j.specimen_file;
  } else {
    // Always written: the study's value, or the base's where the axis is not swept (a seed of 0 is a seed).
    c["sample"]["seed"] = j.seed;
    c["sample"]["count"] = j.count;
    if (!j.grading_yaml.empty()) {
      // The curve gives the sizes: the power law's keys would be refused beside it (config.cpp).
      for (const char* k : {"D", "r_min", "r_max", "grading"}) c["sample"].remove(k);
      c["sample"]["grading"] = YAML::Load(j.grading_yaml);
    }
  }
  c["material"]["mu_r"] = yaml_number(j.mu_r);
  if (j.E > 0) c["material"]["E"] = yaml_number(j.E);
  YAML::Node stages(YAML::NodeType::Sequence);
  bool first_iso = true;
  // The sample job runs the base's isotropic stages before its first shear stage (the preparation), the shear job
  // every stage from there, an isotropic stage between shear stages included: a reconsolidation after cycles (a
  // re-liquefaction test: cycles, reconsolidation, cycles), which the sample job used to run before any shear.
  bool sheared = false;
  const std::vector<bool> k0 = k0_consolidations(base["stages"]);
  for (size_t k = 0; k < base["stages"].size(); ++k) {
    YAML::Node s = YAML::Clone(base["stages"][k]);
    const std::string type = s["type"] ? s["type"].as<std::string>() : "isotropic";
    if (j.set_mu_r) s["mu_r"] = yaml_number(j.mu_r);
    sheared = sheared || type != "isotropic";
    if (type == "isotropic" && sheared) {
      if (!shear_only) continue;
      if (j.p0 > 0) s["pressure"] = yaml_number(j.p0);  // every isotropic stage's (the base's share one: iso_pressures)
    } else if (type == "isotropic") {
      if (shear_only) continue;
      if (j.p0 > 0) s["pressure"] = yaml_number(j.p0);
      if (first_iso && j.e0 > 0) s["target_e0"] = yaml_number(j.e0);
      first_iso = false;
      s["save_sample"] = true;
    } else if (!shear_only) {
      continue;
    } else if (k0[k]) {
      // a K0 consolidation: as the base has it (but a swept mu_r, above)
    } else {
      if (j.set_drainage) s["drainage"] = j.drainage;
      if (type == "triaxial" && j.set_direction) s["direction"] = j.direction;
      if (type == "triaxial" && j.set_b) s["b"] = yaml_number(j.b);
      if (type == "triaxial" && j.set_stress_path) s["stress_path"] = j.stress_path;
      if (type == "triaxial" && j.rate > 0) set_with_cap(s, "axial_strain_rate", j.rate);
      if (type == "triaxial" && j.strain > 0) set_with_cap(s, "max_axial_strain", j.strain);
      if (type == "cyclic" && j.q_amplitude > 0 && s["q_amplitude"]) s["q_amplitude"] = yaml_number(j.q_amplitude);
      // a stage that gives its amplitude as csr takes the axis's csr as it is (the run applies it at the stage's p'_c)
      if (type == "cyclic" && j.csr > 0 && s["csr"]) s["csr"] = yaml_number(j.csr);
      if (type == "cyclic" && j.strain_amplitude > 0 && s["strain_amplitude"]) {
        s["strain_amplitude"] = yaml_number(j.strain_amplitude);
        s["axial_strain_rate"] = yaml_number(j.strain_rate);
      }
    }
    for (const StudyJob::StageKey& sk : j.stage_keys) {  // a stage axis's value (a sample job's: its preparation's)
      if (sk.stage != k) continue;
      // a slower rate or a longer end scales the stage's step cap up as the axes do, unless the job sets that cap
      if (sk.key == "axial_strain_rate" || sk.key == "max_axial_strain") {
        const bool own_cap = std::any_of(j.stage_keys.begin(), j.stage_keys.end(), [&](const StudyJob::StageKey& o) {
          return o.stage == k && o.key == "max_steps";
        });
        set_with_cap(s, sk.key.c_str(), sk.value, own_cap);
      } else {
        s[sk.key] = yaml_number(sk.value);
      }
    }
    stages.push_back(s);
  }
  c["stages"] = stages;
  if (c["output"]) c["output"].remove("dir");
  return c;
}

}  // namespace

Study load_study_unchecked(const std::string& path);

Study load_study(const std::string& path) {
  try {
    return load_study_unchecked(path);
  } catch (const YAML::Exception& e) {  // a wrong type somewhere: still one line naming the file
    std::string what = e.what();
    for (char& ch : what)
      if (ch == '\n') ch = ' ';
    throw ConfigError(path + ": " + what);
  }
}

// Values of an axis or an extra job beyond "finite and >= 0" (numbers()): seed and count are whole numbers (a
// count of 2.5 spheres would be cut to 2 without a word), count >= 1; a pressure is > 0 (0 would silently mean
// the base's pressure).
void check_axis_values(const std::vector<double>& v, const std::string& path, const std::string& key) {
  const auto ends_with = [&](const char* tail) {
    const size_t n = std::strlen(tail);
    return key.size() >= n && key.compare(key.size() - n, n, tail) == 0;
  };
  if (ends_with("p0"))
    for (double x : v)
      if (!(x > 0)) fail(path, key, "values must be > 0 (Pa); leave p0 out for the base's pressure");
  if (ends_with("E"))
    for (double x : v)
      if (!(x > 0 && x <= 1e13)) fail(path, key, "values must be in (0, 1e13] (Pa, material.E); leave E out for the base's");
  if (ends_with("csr"))
    for (double x : v)
      if (!(x > 0)) fail(path, key, "values must be > 0 (q_amplitude / (2 p'_0)); leave csr out for the base's q_amplitude");
  if (ends_with("strain_amplitude"))
    for (double x : v)
      if (!(x > 0 && x < 0.9))
        fail(path, key, "values must be in (0, 0.9) (axial strain); leave strain_amplitude out for the base's");
  if (ends_with("axial_strain_rate"))
    for (double x : v)
      if (!(x > 0 && x <= 1e6))
        fail(path, key, "values must be in (0, 1e6] (1/s); leave axial_strain_rate out for the base's");
  if (ends_with(".b"))
    for (double x : v)
      if (!(x <= 1)) fail(path, key, "values must be in [0, 1] ((sigma_2 - sigma_3) / (sigma_1 - sigma_3)); leave b out for the base's");
  const bool is_seed = ends_with("seed"), is_count = ends_with("count");
  if (!is_seed && !is_count) return;
  for (double x : v) {
    if (x != std::floor(x) || x > 9007199254740992.0) fail(path, key, "values must be whole numbers in [0, 2^53]");
    if (is_count && (x < 1 || x > 1e8)) fail(path, key, "values must be in [1, 1e8] (spheres)");
  }
}

Study load_study_unchecked(const std::string& path) {
  Study s;
  s.path = path;
  const YAML::Node root = load_yaml_screened(path);
  if (!root.IsMap()) throw ConfigError(path + ": (top level): must be a mapping");
  const std::set<std::string> known = {"base", "axes", "extra", "critical_state", "peak"};
  for (auto it : root)
    if (!known.count(it.first.as<std::string>()))
      fail(path, it.first.as<std::string>(), "unknown key (known: base, axes, extra, critical_state, peak)");
  if (!root["base"]) fail(path, "base", "is required (a run config whose stages prepare and shear a sample)");
  if (!root["base"].IsScalar() || root["base"].Scalar().empty())
    fail(path, "base", "must be the path of a run config (relative to this file), whose stages prepare and shear a sample");
  s.base = expand_path(root["base"].Scalar(), path + ": base");
  if (s.base[0] != '/') s.base = (fs::path(path).parent_path() / s.base).string();
  RunConfig base_cfg;
  YAML::Node base;
  try {
    base_cfg = load_run_config(s.base);  // the base must be a valid config on its own
    base = load_yaml_screened(s.base);
  } catch (const std::exception& e) {
    fail(path, "base", e.what());
  }
  // A base that starts from a saved sample (sample.file): its spheres are the file's, so the count that names the jobs
  // is the file's, and there is no seed or count to sweep.
  s.base_sample = base_cfg.sample_file;
  const std::string& base_sample = s.base_sample;
  if (!base_sample.empty()) {
    try {
      base_cfg.packing.count = int(plan_run(base_cfg).particles);
    } catch (const std::exception& e) {
      fail(path, "base", e.what());
    }
  }
  // The sample_file axis gives every sample its spheres as the base's sample.file does (below).
  const bool file_axis = root["axes"] && root["axes"].IsMap() && root["axes"]["sample_file"];
  const auto need_generated = [&](const std::string& key) {
    if (file_axis)
      fail(path, key, "axes.sample_file gives each sample the spheres of its file: no seed, count or grading to set");
    if (!base_sample.empty())
      fail(path, key, "the base starts from sample.file (" + base_sample + "), whose spheres are the file's: no seed or "
                      "count to set");
  };
  bool has_iso = false, has_tri = false;
  std::string base_drainage;  // the base's first shear's, the default of the drainage axis and of extra jobs
  std::string base_direction;  // the base's first triaxial stage's (none: a cyclic base), likewise for direction
  Real base_b = 0;              // and for b
  std::string base_path;        // and for stress_path
  // A cyclic stage's stress amplitude is what the csr axis sets, from the p'_0 of each job (the pressure of the
  // base's last isotropic stage, or the p0 axis): CSR = q_amplitude / (2 p'_0), the cyclic liquefaction test's measure.
  // A stage that gives csr instead takes the axis's csr, which the run applies at the stage's own p'_c
  // (StageConfig::csr): the stress it has, after a K0 stage or a reconsolidation too.
  bool has_q_cyclic = false;
  // Their amplitudes, by stage ("20 kPa", or "csr 0.1" where the stage gives csr): a staged test loads at rising
  // amplitudes in turn, which one csr would flatten
  std::vector<std::pair<std::string, std::string>> q_stages;
  long base_cycles = 0;
  Real base_p0 = 0;
  std::set<Real> iso_pressures;  // of the base's isotropic stages: several make a loading path, which p0 would flatten
  // The strain_amplitude axis sets the amplitude of the base's strain-controlled cyclic stage and scales its rate
  // with it: the modulus-reduction and damping curves (one test per amplitude, each on a fresh specimen of the
  // sample, as ASTM D3999 tests are run) at one loading frequency. Only one such stage: with several (a staged
  // test, configs/modulus_damping.yaml) the axis would not say which it sets.
  std::vector<std::string> strain_stages;
  Real base_strain_amp = 0, base_strain_rate = 0;
  // What the study's keys set, per stage of the base they set (job_config): mu_r on every stage (and the material);
  // drainage on every shear stage, direction, b, stress_path, axial_strain_rate and max_axial_strain on every
  // triaxial one, but for the K0 consolidations
  std::map<std::string, std::vector<std::pair<std::string, std::string>>> stage_values;
  const std::vector<bool> k0 = k0_consolidations(base["stages"]);  // not the shear the axes' defaults are taken from
  // The csr axis's q_amplitude = 2 csr p'_0 is of the preparation's pressure. A stage that leaves another p' for the
  // next stage's cycles to start from (a drained or K0 shear; a reconsolidation to another pressure; not an undrained
  // stage, after which an undrained one keeps its p'_c) and the first q_amplitude stage after it: a warning, as the
  // CSR is not the one of the stress the cycles start from (a stage's csr is: StageConfig::csr).
  std::string moved_by, csr_moved;
  for (size_t k = 0; k < base_cfg.stages.size(); ++k) {
    const StageConfig& st = base_cfg.stages[k];
    if (st.type == StageType::Cyclic && st.q_amplitude > 0 && !moved_by.empty() && csr_moved.empty())
      csr_moved = "stage " + st.name + " starts where stage " + moved_by + " left the sample";
    if (st.type == StageType::Isotropic)
      moved_by = has_tri && st.pressure != base_p0 ? st.name + " (isotropic, " + fmt(st.pressure / 1e3) + " kPa)" : "";
    else if (st.drainage != Drainage::Undrained)
      moved_by = st.name + " (" + drainage_name(st.drainage) + ")";
    (st.type == StageType::Isotropic ? has_iso : has_tri) = true;
    if (st.type == StageType::Isotropic) {
      if (!has_tri) base_p0 = st.pressure;  // the preparation's: a reconsolidation after a shear is no p'_0
      iso_pressures.insert(st.pressure);
    }
    if (st.type == StageType::Cyclic) {
      has_q_cyclic = has_q_cyclic || st.stress_reversal();
      if (st.stress_reversal()) {
        std::ostringstream amp;
        if (st.csr > 0) amp << "csr " << st.csr;
        else amp << st.q_amplitude / 1e3 << " kPa";
        q_stages.emplace_back(st.name, amp.str());
      }
      base_cycles = st.cycles;
      if (st.strain_amplitude > 0) {
        strain_stages.push_back(st.name);
        base_strain_amp = st.strain_amplitude;
        base_strain_rate = st.axial_strain_rate;
      }
    }
    // every stage's, its own or the material's (with the material's first: a stage of its own that differs from it
    // is one a mu_r axis would flatten, and the job's name gives the material's)
    if (k == 0) stage_values["mu_r"].emplace_back("material", fmt(base_cfg.engine.contact.mu_r));
    stage_values["mu_r"].emplace_back(st.name, fmt(st.mu_r));
    if (k0[k]) continue;
    if (st.type != StageType::Isotropic) stage_values["drainage"].emplace_back(st.name, drainage_name(st.drainage));
    if (st.type == StageType::Triaxial) {
      stage_values["direction"].emplace_back(st.name, st.extension ? "extension" : "compression");
      stage_values["b"].emplace_back(st.name, fmt(st.b));
      stage_values["stress_path"].emplace_back(st.name, st.constant_p     ? "constant_p"
                                                        : st.plane_strain ? "plane_strain"
                                                                          : "constant_sigma3");
      stage_values["axial_strain_rate"].emplace_back(st.name, fmt(st.axial_strain_rate) + "/s");
      stage_values["max_axial_strain"].emplace_back(st.name, fmt(st.max_axial_strain));
    }
    if (st.type != StageType::Isotropic && base_drainage.empty())
      base_drainage = drainage_name(st.drainage);
    if (st.type == StageType::Triaxial && base_direction.empty()) {
      base_direction = st.extension ? "extension" : "compression";
      base_b = st.b;
      base_path = st.constant_p ? "constant_p" : st.plane_strain ? "plane_strain" : "constant_sigma3";
    }
  }
  // A base without a shear stage is a preparation study: its jobs are the samples alone (how e_0 and the grading of a
  // consolidated sample depend on its size, seed, p'_0, mu_r or target e_0), and its report their Samples and
  // Preparation sections.
  if (!has_iso)
    fail(path, "base", "its stages must include an isotropic stage (and a triaxial or cyclic one to shear the sample; "
                       "without one the study prepares samples only)" +
                           std::string(base_sample.empty() ? "" : "; a base from sample.file too: its isotropic stage "
                                                                  "consolidates the saved sample again (quickly where "
                                                                  "it is at that pressure already)"));
  if (const YAML::Node cs = root["critical_state"]) {
    for (auto it : cs) {
      const std::string k = it.first.as<std::string>();
      const double v = it.second.as<double>();
      if (!(v > 0 && v < 1)) fail(path, "critical_state." + k, "must be in (0, 1)");
      if (k == "window") s.window = v;
      else if (k == "qp_tol") s.qp_tol = v;
      else if (k == "p_tol") s.p_tol = v;
      else if (k == "e_tol") s.e_tol = v;
      else fail(path, "critical_state." + k, "unknown key (known: window, qp_tol, p_tol, e_tol)");
    }
  }
  if (const YAML::Node pk = root["peak"]) {
    if (!pk.IsMap()) fail(path, "peak", "must be a mapping ({window: W, max_ke_ratio: X})");
    for (auto it : pk) {
      const std::string k = it.first.as<std::string>(), key = "peak." + k;
      if (k != "window" && k != "max_ke_ratio") fail(path, key, "unknown key (known: window, max_ke_ratio)");
      // window in [0, 0.2] of axial strain (0: single rows; a fifth of a 40 % test at most, or no peak is left);
      // max_ke_ratio in (0, 10] (above 10 kinetic energy dwarfs the elastic and no row is left out).
      const bool win = k == "window";
      const std::string range = win ? "[0, 0.2] (axial strain)" : "(0, 10] (kinetic / elastic energy)";
      double v = 0;
      try {
        v = it.second.as<double>();
      } catch (const YAML::Exception&) {
        fail(path, key, "must be a number in " + range);
      }
      if (win ? !(v >= 0 && v <= 0.2) : !(v > 0 && v <= 10)) fail(path, key, "must be in " + range);
      (win ? s.peak_window : s.peak_max_ke) = v;
    }
  }
  // Axes: the full grid; each axis defaults to the base config's value (drainage: its first shear's).
  const YAML::Node ax = root["axes"];
  // An axis's values: given, at least one; a value listed twice made one job, the grid smaller than it reads (likely
  // a typo for another value).
  const auto listed_once = [&](const std::vector<double>& v, const std::string& key, bool given) {
    if (given && v.empty()) fail(path, key, "an empty list: give at least one value, or leave the axis out");
    for (size_t i = 0; i < v.size(); ++i)
      for (size_t j = 0; j < i; ++j)
        if (v[i] == v[j])
          fail(path, key, fmt(v[i]) + " is listed twice (values " + std::to_string(j + 1) + " and " +
                              std::to_string(i + 1) + "): an axis lists each value once");
  };
  auto axis = [&](const char* k, const std::vector<double>& def) {
    const std::string key = std::string("axes.") + k;
    auto v = numbers(ax ? ax[k] : YAML::Node(), path, key);
    listed_once(v, key, ax && ax[k]);
    check_axis_values(v, path, key);
    return v.empty() ? def : v;
  };
  if (ax)
    for (auto it : ax) {
      const std::string k = it.first.as<std::string>();
      if (k.rfind("stages.", 0) == 0) continue;  // a stage axis (below)
      if (!std::set<std::string>{"mu_r", "e0", "p0", "E", "drainage", "direction", "b", "stress_path",
                                 "axial_strain_rate", "seed", "count", "grading", "sample_file", "csr",
                                 "strain_amplitude"}
               .count(k))
        fail(path, "axes." + k,
             "unknown axis (known: mu_r, e0, p0, E, drainage, direction, b, stress_path, axial_strain_rate, seed, count, "
             "grading, sample_file, csr, strain_amplitude, and stages.<stage name>.<key>)");
    }
  // The grading axis: named sieve curves (sample.grading's form), one sample each, in place of the base's sizes: how a
  // sample's e_0 depends on its grading (e_max and e_min fall as Cu rises, Youd 1973: the preparation report's figure
  // against each curve's Cu), and its shear tests' (critical-state line, friction, liquefaction resistance: the report
  // gives each curve a section of its own, as its fits group tests by mu_r and the loading and would pool the curves).
  // A name that ends a sample job's directory name (the grading axis's _g<name>, the sample_file axis's _f<name>)
  const auto job_suffix_name = [&](const std::string& name, const std::string& k, const char* whose) {
    if (name.empty() || name.size() > 40 ||
        name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-_.") != std::string::npos)
      fail(path, k, std::string(whose) + " name ends its sample job's directory name: 1-40 letters, digits, '-', '_' "
                    "or '.'");
  };
  struct NamedGrading {
    std::string name, yaml;
    double cu;
  };
  std::vector<NamedGrading> gradings;
  if (ax && ax["grading"]) {
    const std::string key = "axes.grading";
    need_generated(key);
    const YAML::Node g = ax["grading"];
    if (!g.IsMap() || g.size() == 0)
      fail(path, key, "must name each sieve curve: {fine: {diameter: [...], passing: [...]}, coarse: {...}}, at least one");
    for (auto it : g) {
      const std::string name = it.first.as<std::string>();
      std::string k = key;
      k.append(".").append(name);
      job_suffix_name(name, k, "a grading's");  // _g<name>
      StudyJob probe;
      probe.seed = base_cfg.packing.seed;
      probe.count = base_cfg.packing.count;
      probe.grading_yaml = YAML::Dump(it.second);
      // The curve checked as the job's config will check it, its errors named by this key: "sample.grading.passing[0]"
      // of the job is "axes.grading.NAME.passing[0]" here.
      const std::string tag = "\x01";
      RunConfig rc;
      try {
        rc = parse_run_config(job_config(base, probe, false, ""), tag);
      } catch (const ConfigError& e) {
        std::string m = e.what();
        const std::string job_key = tag + ": sample.grading";
        if (m.rfind(job_key, 0) == 0) {
          std::string msg = path;
          msg.append(": ").append(k).append(m, job_key.size());
          throw ConfigError(msg);
        }
        if (m.rfind(tag + ": ", 0) == 0) m = m.substr(tag.size() + 2);
        fail(path, k, m);
      }
      if (rc.packing.grading.empty())  // (the loader refuses a curve it cannot read; grading_indices needs one)
        fail(path, k, "must be a sieve curve: {diameter: [...], passing: [...]}");
      gradings.push_back({name, probe.grading_yaml, grading_indices(rc.packing.grading).cu});
    }
  }
  // The sample_file axis: named sample files (sample.file's form: a sample a run saved, or `grainlab import` made of a
  // packing from elsewhere; relative to this file), each consolidated by a sample job of its own at the job's p0 and
  // mu_r, in place of the base's sample: one study over specimens prepared apart (a dense and a loose one of one
  // material sheared at the same pressures; packings from YADE, LIGGGHTS or a CT scan). The report gives each file a
  // section of its own, as it gives each grading (a file's spheres may be another material's, and its fits would pool
  // them), and draws their tests' end states together.
  struct NamedFile {
    std::string name, file;
    long count;
    double e;  // in its walls, as the file holds it (0: unknown)
  };
  std::vector<NamedFile> specimens;
  if (file_axis) {
    const std::string key = "axes.sample_file";
    const YAML::Node g = ax["sample_file"];
    // A path relative to this file, absolute
    const auto absolute = [&](const std::string& p, const std::string& k) {
      std::string file = expand_path(p, path + ": " + k);
      if (file[0] != '/') file = (fs::path(path).parent_path() / file).string();
      std::error_code ec;
      if (const fs::path abs = fs::absolute(file, ec); !ec) file = abs.lexically_normal().string();
      return file;
    };
    // The files: named in a mapping, or a pattern's matches named by their stems ("packings/*.h5": one job per file,
    // packings/dense.h5 named dense), in order of name
    std::vector<std::pair<std::string, std::string>> named;  // (name, absolute path), the key's suffix per name
    if (g.IsScalar() && g.Scalar().find_first_of("*?[") != std::string::npos) {
      const std::string pattern = absolute(g.Scalar(), key);
      glob_t gl{};
      if (::glob(pattern.c_str(), 0, nullptr, &gl) == 0)
        for (size_t i = 0; i < gl.gl_pathc; ++i)
          named.emplace_back(fs::path(gl.gl_pathv[i]).stem().string(), gl.gl_pathv[i]);
      globfree(&gl);
      if (named.empty()) fail(path, key, "'" + g.Scalar() + "' matches no file (" + pattern + ")");
      std::sort(named.begin(), named.end());
    } else if (g.IsMap() && g.size() > 0) {
      for (auto it : g) {
        const std::string name = it.first.as<std::string>();
        std::string field = key;
        field.append(".").append(name);
        if (!it.second.IsScalar() || it.second.Scalar().empty())
          fail(path, field, "must be the path of a sample file (one a run saved with save_sample, or "
                            "`grainlab import` made), relative to this file");
        named.emplace_back(name, absolute(it.second.Scalar(), field));
      }
    } else {
      fail(path, key, "must name each sample file: {dense: dense.h5, loose: loose.h5} (paths relative to this file), at "
                      "least one; or be a pattern, \"packings/*.h5\", whose files are named by their stems");
    }
    for (const auto& [name, file] : named) {
      std::string k = key;
      k.append(".").append(name);
      job_suffix_name(name, k, "a sample file's");  // _f<name>
      std::error_code ec;
      for (const NamedFile& o : specimens) {
        if (o.name == name)  // (a pattern's two files of one stem, a.h5 and a.hdf5)
          fail(path, k, "names two files, " + o.file + " and " + file + ": a sample file's name is its job's");
        if (fs::equivalent(o.file, file, ec))  // (two names of one file: one sample twice, the grid doubled)
          fail(path, k, "is " + o.name + "'s file (" + o.file + ") again: each sample file once");
      }
      StudyJob probe;
      probe.specimen_file = file;
      RunPlan plan;
      try {  // the file read as the job will read it (a missing file, a text packing, one of another kind: said here)
        std::string where = path;
        where.append(" (").append(k).append(")");
        plan = plan_run(parse_run_config(job_config(base, probe, false, ""), where));
      } catch (const std::exception& e) {
        fail(path, k, e.what());
      }
      specimens.push_back({name, file, plan.particles, plan.sample_e});
    }
  }
  const auto need_q_cyclic = [&](const std::string& key) {
    if (!has_q_cyclic)
      fail(path, key, "sets the stress amplitude of a cyclic stage (q_amplitude = 2 csr p'_0, or the stage's csr), and "
                      "the base (" + s.base + ") has no cyclic stage with q_amplitude or csr");
    // It sets every stress-controlled cyclic stage (job_config): of a staged test, whose stages load at amplitudes of
    // their own in turn, it would make one test of one amplitude, silently (as p0 would flatten a loading path).
    for (const auto& [name, amp] : q_stages)
      if (amp != q_stages.front().second) {
        std::ostringstream os;
        os << "sets the stress amplitude of every cyclic stage with q_amplitude or csr, and the base's (" << s.base
           << ") load at amplitudes of their own (" << q_stages.front().first << " " << q_stages.front().second
           << ", " << name << " " << amp << ") that it would make one: give the base one amplitude, or "
           << "leave csr out and set each stage's q_amplitude in a base of its own";
        fail(path, key, os.str());
      }
  };
  if (ax && ax["csr"]) need_q_cyclic("axes.csr");
  if (ax && ax["seed"]) need_generated("axes.seed");
  if (ax && ax["count"]) need_generated("axes.count");
  // p0 sets the pressure of every isotropic stage (job_config): of a base that consolidates in stages to one pressure
  // (configs/paper/study-base.yaml), as meant; of one whose stages follow a loading path (configs/compression-base.yaml)
  // it would silently flatten the path.
  const auto need_one_pressure = [&](const std::string& key) {
    if (iso_pressures.size() > 1) {
      std::ostringstream os;
      os << "sets the pressure of every isotropic stage, and the base's (" << s.base << ") follow a path of "
         << iso_pressures.size() << " pressures (" << *iso_pressures.begin() / 1e3 << " to " << *iso_pressures.rbegin() / 1e3
         << " kPa) that it would flatten: give each path its own base";
      fail(path, key, os.str());
    }
  };
  if (ax && ax["p0"]) need_one_pressure("axes.p0");
  const auto need_strain_cyclic = [&](const std::string& key) {
    if (strain_stages.size() != 1)
      fail(path, key, "sets the strain amplitude of the base's strain-controlled cyclic stage (one with strain_amplitude), "
                      "and the base (" + s.base + ") has " +
                          (strain_stages.empty() ? std::string("none")
                                                 : std::to_string(strain_stages.size()) + " (" + strain_stages[0] + ", " +
                                                       strain_stages[1] + (strain_stages.size() > 2 ? ", ..." : "") +
                                                       "): the axis would not say which"));
    s.strain_stage = strain_stages[0];
  };
  if (ax && ax["strain_amplitude"]) need_strain_cyclic("axes.strain_amplitude");
  // The word axes (drainage, direction): a list or one word, each value checked by `check`; an empty list is an
  // error, as for the number axes (it would silently mean the base's value).
  const auto words = [&](const char* k, const auto& check) {
    std::vector<std::string> v;
    if (!ax || !ax[k]) return v;
    const std::string key = std::string("axes.") + k;
    for (auto w : (ax[k].IsSequence() ? ax[k] : YAML::Node(std::vector<YAML::Node>{ax[k]}))) {
      v.push_back(w.as<std::string>());
      check(key, v.back());
    }
    if (v.empty()) fail(path, key, "an empty list: give at least one value, or leave the axis out");
    for (size_t i = 0; i < v.size(); ++i)
      for (size_t j = 0; j < i; ++j)
        if (v[i] == v[j])
          fail(path, key, "'" + v[i] + "' is listed twice (values " + std::to_string(j + 1) + " and " +
                              std::to_string(i + 1) + "): an axis lists each value once");
    return v;
  };
  const auto check_drainage = [&](const std::string& key, const std::string& d) {
    if (!has_tri)
      fail(path, key, "sets the drainage of the base's shear stages, and the base (" + s.base + ") has none (a "
                      "preparation study sweeps mu_r, e0, p0, seed and count)");
    if (d != "drained" && d != "undrained" && d != "oedometric")
      fail(path, key, "'" + d + "' is not drained, undrained or oedometric");
  };
  std::vector<std::string> drain = words("drainage", check_drainage);
  const bool drainage_axis = !drain.empty();
  if (drain.empty()) drain = {base_drainage};
  // The direction axis sets every triaxial stage of the base (a cyclic stage reverses by itself): triaxial
  // compression and extension of the same sample, the pair that shows whether the friction angle depends on the
  // intermediate principal stress (Mohr-Coulomb says not: one phi, M = 6 sin phi / (3 -+ sin phi)). Left out, the
  // base's stages keep their own.
  const auto check_direction = [&](const std::string& key, const std::string& d) {
    if (base_direction.empty())
      fail(path, key, "sets the loading direction of the base's triaxial stages, and the base (" + s.base +
                          ") has none (a cyclic stage reverses by itself)");
    if (d != "compression" && d != "extension") fail(path, key, "'" + d + "' is not compression or extension");
  };
  std::vector<std::string> directions = words("direction", check_direction);
  const bool direction_axis = !directions.empty();
  if (directions.empty()) directions = {base_direction};
  // The b axis sets every triaxial stage of the base too: the true-triaxial series at one p'_0 and sigma_3, from which
  // the report tells which failure criterion the packing follows (Mohr-Coulomb: phi independent of b; Matsuoka-Nakai,
  // Lade-Duncan: phi rising from b = 0). b > 0 needs a drained compression shear (the stage's own check, config.cpp):
  // a job of the grid that crosses it with undrained or extension is an error naming the axis, not skipped.
  const auto need_triaxial = [&](const std::string& key) {
    if (base_direction.empty())
      fail(path, key, "sets b of the base's triaxial stages, and the base (" + s.base + ") has none");
  };
  if (ax && ax["b"]) need_triaxial("axes.b");
  const bool b_axis = ax && ax["b"];
  // The axial_strain_rate axis sets every triaxial stage's rate as well (a cyclic stage's rate is its loading
  // frequency, which the strain_amplitude axis scales): the same test at several inertial numbers, from which the
  // report tells how far its peak and critical state still depend on the rate (the mu(I) rheology) and extrapolates
  // them to I -> 0.
  const auto need_rate_triaxial = [&](const std::string& key) {
    if (base_direction.empty())
      fail(path, key, "sets axial_strain_rate of the base's triaxial stages, and the base (" + s.base + ") has none");
  };
  if (ax && ax["axial_strain_rate"]) need_rate_triaxial("axes.axial_strain_rate");
  // The stress_path axis sets every triaxial stage of the base as well: the same b series at constant sigma_3 and at
  // constant p' (Thornton 2000's path) in one study; the report calibrates the failure criteria per path. constant_p
  // needs a drained shear, plane_strain a drained or undrained shear at b = 0 (the stage's own rules, named at the
  // study's key below): a plane-strain test beside the b series, as an extra job, falls on the series' failure
  // criteria at its b.
  const auto check_path = [&](const std::string& key, const std::string& v) {
    if (base_direction.empty())
      fail(path, key, "sets the stress path of the base's triaxial stages, and the base (" + s.base + ") has none");
    if (v != "constant_sigma3" && v != "constant_p" && v != "plane_strain")
      fail(path, key, "'" + v + "' is not constant_sigma3, constant_p or plane_strain");
  };
  std::vector<std::string> paths = words("stress_path", check_path);
  const bool path_axis = !paths.empty();
  if (paths.empty()) paths = {base_path};
  // A shear key sets its value on every stage it applies to (job_config): of a base whose stages differ in it (a
  // drained loading, then an undrained shear; a loading, then an unloading), it would make them one, silently, as csr
  // would a staged cyclic test's amplitudes. The drainage, left out, leaves each stage its own (it was the first
  // shear's on every stage: the drained loading's drainage on the undrained shear too).
  const auto need_one = [&](const std::string& field, const std::string& k) {
    const auto& v = stage_values[k];
    for (const auto& [name, value] : v)
      if (value != v.front().second) {
        std::ostringstream os;
        os << "sets the " << k << " of every " << (k == "mu_r" ? "" : k == "drainage" ? "shear " : "triaxial ")
           << "stage of the base, and the base's (" << s.base << ") have their own (" << v.front().first << " "
           << v.front().second << ", " << name << " " << value << ") that it would make one: give the base one " << k
           << ", or leave " << k << " out of the study";
        fail(path, field, os.str());
      }
  };
  const bool mu_r_axis = ax && ax["mu_r"];
  if (mu_r_axis) need_one("axes.mu_r", "mu_r");
  if (drainage_axis) need_one("axes.drainage", "drainage");
  if (direction_axis) need_one("axes.direction", "direction");
  if (b_axis) need_one("axes.b", "b");
  if (path_axis) need_one("axes.stress_path", "stress_path");
  if (ax && ax["axial_strain_rate"]) need_one("axes.axial_strain_rate", "axial_strain_rate");
  // Stage axes, `stages.<name>.<key>: [values]` (and an extra job's `stages.<name>.<key>: value`): a key of one stage
  // of the base that no other axis sets. From the first shear stage on (a K path's k_ratio: CAU at several K; an
  // unloading's stress_ratio or ocr; a loading's sigma_v) each value is a shear of the same sample; on a preparation
  // stage (an isotropic stage before the first shear: a preloading's pressure, which makes isotropically
  // overconsolidated samples; a compaction's mu, the preparation friction set directly where e0 would search for
  // it) each value is a sample of its own, named by it ("_<stage>-<key><value>"), and its shears take it. The job's
  // config checks the values (their ranges are the stage's).
  size_t first_shear = base_cfg.stages.size();
  for (size_t k = 0; k < base_cfg.stages.size() && first_shear == base_cfg.stages.size(); ++k)
    if (base_cfg.stages[k].type != StageType::Isotropic) first_shear = k;
  const size_t first_iso = first_shear > 0 ? 0 : base_cfg.stages.size();  // the stage e0 sets target_e0 on
  // "stages.<name>.<key>" as a StageKey (value 0), checked; field names it in errors
  const auto stage_key = [&](const std::string& k, const std::string& field) {
    const size_t dot = k.rfind('.');
    const std::string stage_name = dot > 7 ? k.substr(7, dot - 7) : "", key = k.substr(dot + 1);
    if (stage_name.empty() || key.empty())
      fail(path, field, "a stage axis is stages.<stage name>.<key> (stages.kc.k_ratio: [0.5, 0.7])");
    size_t st = base_cfg.stages.size();
    std::string names;
    for (size_t j = 0; j < base_cfg.stages.size(); ++j) {
      if (base_cfg.stages[j].name == stage_name) st = j;
      names += (j ? ", " : "") + base_cfg.stages[j].name;
    }
    if (st == base_cfg.stages.size()) {
      std::string msg = "the base (" + s.base;
      msg.append(") has no stage named '").append(stage_name).append("' (its stages: ").append(names).append(")");
      fail(path, field, msg);
    }
    // what other axes (or an extra job's keys) set, and what makes the stage another kind of stage. A stage's rate
    // and end strain are its own where neither the study's axes nor an extra job set every triaxial stage's (a probe's
    // rate after a rest, whose rate is 0: the axial_strain_rate axis refuses that base)
    const auto study_sets = [&](const char* shear_key) {
      if (ax && ax[shear_key]) return true;
      if (const YAML::Node ex = root["extra"]; ex && ex.IsSequence())
        for (const auto& e : ex)
          if (e.IsMap() && e[shear_key]) return true;
      return false;
    };
    // p0 sets every isotropic stage's pressure and e0 the first one's target_e0 (job_config); a sample job saves its
    // preparation (save_sample, a switch, not a number)
    if (std::set<std::string>{"name", "type", "mu_r", "drainage", "direction", "b", "stress_path", "q_amplitude", "csr",
                              "strain_amplitude", "cycles", "save_sample"}.count(key) ||
        (key == "pressure" && study_sets("p0")) || (key == "target_e0" && study_sets("e0")) ||
        (key == "axial_strain_rate" && study_sets("axial_strain_rate")) ||
        (key == "max_axial_strain" && study_sets("max_axial_strain")))
      fail(path, field, "'" + key + "' is " + (key == "name" || key == "type" ? "what the stage is"
                                               : key == "save_sample"        ? "how a study keeps its samples"
                                                                             : "set by axes." +
                        (key == "pressure" ? std::string("p0") : key == "q_amplitude" ? std::string("csr")
                         : key == "target_e0" ? std::string("e0") : key) +
                        " or an extra job's key") + ": a stage axis sets another of the stage's keys");
    // A target_e0 search tries frictions of its own (Laboratory::search_e0: 0, mu_max, then between), so the mu of
    // the stage it runs on would change nothing: the base's own target_e0, or e0's on the first isotropic stage.
    if (key == "mu" && base_cfg.stages[st].type == StageType::Isotropic &&
        (base_cfg.stages[st].target_e0 > 0 || (study_sets("e0") && st == first_iso)))
      fail(path, field, "'mu' of '" + stage_name + "' is what its target_e0 search sets (" +
                        (base_cfg.stages[st].target_e0 > 0 ? std::string("the base's target_e0") : "axes.e0 or an "
                        "extra job's e0") + "), so the axis would change nothing: sweep e0, or set mu without a target");
    return StudyJob::StageKey{st, stage_name, key, 0};
  };
  struct StageAxis {
    StudyJob::StageKey at;
    std::vector<double> values;
  };
  std::vector<StageAxis> stage_axes;
  if (ax)
    for (auto it : ax) {
      const std::string k = it.first.as<std::string>(), field = "axes." + k;
      if (k.rfind("stages.", 0) != 0) continue;
      const StudyJob::StageKey at = stage_key(k, field);
      const std::vector<double> v = numbers(it.second, path, field, true);
      listed_once(v, field, true);
      stage_axes.push_back({at, v});
    }
  // the stage axes' grid: every combination of their values (one empty combination without them)
  std::vector<std::vector<StudyJob::StageKey>> stage_grid{{}};
  for (const StageAxis& a : stage_axes) {
    std::vector<std::vector<StudyJob::StageKey>> next;
    for (const auto& g : stage_grid)
      for (double x : a.values) {
        next.push_back(g);
        next.back().push_back(a.at);
        next.back().back().value = x;
      }
    stage_grid = std::move(next);
  }
  struct Point {
    double mu_r, e0, p0;
    long seed, count;
    std::string drainage;
    bool set_drainage;
    double csr, ea;
    std::string direction;
    bool set_direction;
    double b;
    bool set_b;
    std::string b_key;  // where b was set, for the error below
    std::string stress_path;
    bool set_stress_path;
    std::string path_key;  // where stress_path was set, likewise
    double rate;           // the triaxial stages' axial_strain_rate (0: the base's)
    double strain;         // the triaxial stages' max_axial_strain (0: the base's; extra jobs only)
    bool set_mu_r;         // mu_r from the axis or an extra job (every stage's), not the base's
    int grading;           // index in gradings (-1: the base's sizes)
    double E = 0;          // material.E (0: the base's)
    std::vector<StudyJob::StageKey> stage_keys = {};  // the stage axes' values, or an extra job's stage keys
    int specimen = -1;     // index in specimens (-1: the base's sample)
  };
  std::vector<Point> points;
  if (ax || !root["extra"]) {
    for (double mur : axis("mu_r", {base_cfg.engine.contact.mu_r}))
      for (double e0 : axis("e0", {0}))
        for (double p0 : axis("p0", {0}))
          for (double seed : axis("seed", {double(base_cfg.packing.seed)}))
            for (double count : axis("count", {double(base_cfg.packing.count)}))
             for (double E : axis("E", {0}))
              for (int gi = gradings.empty() ? -1 : 0; gi < int(gradings.size()); ++gi)
              for (int fi = specimens.empty() ? -1 : 0; fi < int(specimens.size()); ++fi)
              for (auto& d : drain)
                for (auto& dir : directions)
                  for (double b : axis("b", {base_b}))
                    for (auto& sp : paths)
                      for (double rate : axis("axial_strain_rate", {0}))
                        for (double csr : axis("csr", {0}))
                          for (double ea : axis("strain_amplitude", {0}))
                            for (const std::vector<StudyJob::StageKey>& sv : stage_grid)
                              points.push_back({mur, e0, p0, long(seed), long(count), d, drainage_axis, csr, ea, dir,
                                                direction_axis, b, b_axis, "axes.b", sp, path_axis, "axes.stress_path",
                                                rate, 0, mu_r_axis, gi, E, sv, fi});
  }
  if (const YAML::Node ex = root["extra"]) {
    if (!ex.IsSequence()) fail(path, "extra", "must be a list of jobs");
    for (size_t k = 0; k < ex.size(); ++k) {
      const std::string key = "extra[" + std::to_string(k) + "]";
      Point pt{base_cfg.engine.contact.mu_r, 0, 0, long(base_cfg.packing.seed), long(base_cfg.packing.count),
               base_drainage, false, 0, 0, base_direction, false, base_b, false, "", base_path, false, "", 0, 0, false, -1};
      for (auto it : ex[k]) {
        const std::string f = it.first.as<std::string>();
        if (f == "drainage") {
          pt.drainage = it.second.as<std::string>();
          pt.set_drainage = true;
          check_drainage(key + ".drainage", pt.drainage);
          need_one(key + ".drainage", "drainage");
          continue;
        }
        if (f == "direction") {
          pt.direction = it.second.as<std::string>();
          pt.set_direction = true;
          check_direction(key + ".direction", pt.direction);
          need_one(key + ".direction", "direction");
          continue;
        }
        if (f == "sample_file") {  // one of the axis's files, by its name
          const std::string name = it.second.IsScalar() ? it.second.Scalar() : "";
          std::string names;
          for (size_t i = 0; i < specimens.size(); ++i) {
            if (specimens[i].name == name) pt.specimen = int(i);
            names += (i ? ", " : "") + specimens[i].name;
          }
          if (pt.specimen < 0) {
            std::string why = "names a file of axes.sample_file, and the study has no such axis";
            if (!specimens.empty()) {
              why = "'";
              why.append(name).append("' is not a name of axes.sample_file (").append(names).append(")");
            }
            fail(path, key + ".sample_file", why);
          }
          continue;
        }
        if (f == "stress_path") {
          pt.stress_path = it.second.as<std::string>();
          pt.set_stress_path = true;
          pt.path_key = key + ".stress_path";
          check_path(pt.path_key, pt.stress_path);
          need_one(pt.path_key, "stress_path");
          continue;
        }
        std::string field = key;
        field.append(".").append(f);
        if (f.rfind("stages.", 0) == 0) {  // a stage's key, as a stage axis sets it
          StudyJob::StageKey sk = stage_key(f, field);
          const std::vector<double> v = numbers(it.second, path, field, true);
          if (v.size() != 1) fail(path, field, "must be one number");
          sk.value = v[0];
          pt.stage_keys.push_back(sk);
          continue;
        }
        const std::vector<double> vs = numbers(it.second, path, field);
        if (vs.size() != 1) fail(path, field, "must be one number");
        check_axis_values(vs, path, field);
        const double v = vs[0];
        if (f == "mu_r") {
          need_one(field, "mu_r");
          pt.mu_r = v;
          pt.set_mu_r = true;
        }
        else if (f == "e0") pt.e0 = v;
        else if (f == "E") pt.E = v;
        else if (f == "p0") {
          need_one_pressure(field);
          pt.p0 = v;
        }
        else if (f == "seed") {
          need_generated(field);
          pt.seed = long(v);
        } else if (f == "count") {
          need_generated(field);
          pt.count = long(v);
        }
        else if (f == "csr") {
          need_q_cyclic(field);
          pt.csr = v;
        } else if (f == "strain_amplitude") {
          need_strain_cyclic(field);
          pt.ea = v;
        } else if (f == "axial_strain_rate") {
          need_rate_triaxial(field);
          need_one(field, "axial_strain_rate");
          pt.rate = v;
        } else if (f == "max_axial_strain") {
          if (base_direction.empty())
            fail(path, field, "sets max_axial_strain of the base's triaxial stages, and the base (" + s.base + ") has none");
          if (!(v > 0 && v <= 0.9)) fail(path, field, "= " + fmt(v) + " must be in (0, 0.9], as a stage's");
          need_one(field, "max_axial_strain");
          pt.strain = v;
        } else if (f == "b") {
          need_triaxial(field);
          need_one(field, "b");
          pt.b = v;
          pt.set_b = true;
          pt.b_key = field;
        } else
          fail(path, field,
               "unknown key (known: mu_r, e0, p0, E, drainage, direction, b, stress_path, axial_strain_rate, "
               "max_axial_strain, seed, count, csr, strain_amplitude, sample_file, and stages.<stage name>.<key>)");
      }
      points.push_back(pt);
    }
  }
  // Stage keys as comparable values (two jobs of one name must agree in them: the name has them to 6 digits only)
  const auto key_values = [](const std::vector<StudyJob::StageKey>& keys) {
    std::vector<std::tuple<size_t, std::string, double>> v;
    v.reserve(keys.size());
    for (const auto& sk : keys) v.emplace_back(sk.stage, sk.key, sk.value);
    return v;
  };
  // Distinct samples, each prepared once.
  std::map<std::string, size_t> sample_index;
  for (const Point& pt : points) {
    if (pt.set_b && pt.b > 0 && (pt.drainage != "drained" || pt.direction != "compression"))
      fail(path, pt.b_key, "b = " + fmt(pt.b) + " needs a drained compression shear, and this job's is " + pt.drainage + " " +
                               pt.direction + " (true triaxial holds sigma_2 by the lateral walls' servo; list the pairs "
                               "as extra jobs to cross b with other drainages or directions)");
    if (pt.set_stress_path && pt.stress_path == "constant_p" && pt.drainage != "drained")
      fail(path, pt.path_key, "constant_p needs a drained shear, and this job's is " + pt.drainage + " (undrained, the "
                              "walls keep the volume and p' is the test's result; list the pairs as extra jobs to cross "
                              "stress_path with drainage)");
    if (pt.set_stress_path && pt.stress_path == "plane_strain" && (pt.drainage == "oedometric" || pt.b > 0))
      fail(path, pt.path_key, "plane_strain needs a drained or undrained shear at b = 0, and this job's is " +
                              pt.drainage + " " + pt.direction + (pt.b > 0 ? ", b = " + fmt(pt.b) : "") +
                              " (the x walls held, the y walls at their start's stress or at constant volume: b is the "
                              "test's result; list it as an extra job beside a b series)");
    std::ostringstream sn;
    sn << "sample_mur" << fmt(pt.mu_r) << "_e" << (pt.e0 > 0 ? fmt(pt.e0) : "base") << "_p"
       << (pt.p0 > 0 ? fmt(pt.p0 / 1e3) + "k" : "base");
    // A base's saved sample has no seed of its own here (the file's spheres were drawn by the run that made it):
    // "_file", where "_s1" named the config's default seed as if the sample were drawn with it.
    // A file of the sample_file axis: its name ("_f<name>"), and its spheres' count.
    const NamedFile* file = pt.specimen >= 0 ? &specimens[pt.specimen] : nullptr;
    if (file) sn << "_f" << file->name;
    else if (base_sample.empty()) sn << "_s" << pt.seed;
    else sn << "_file";
    sn << "_n" << (file ? file->count : pt.count);
    if (pt.grading >= 0) sn << "_g" << gradings[pt.grading].name;
    if (pt.E > 0) sn << "_E" << name_number(pt.E);
    // a stage axis's value on a preparation stage makes a sample of its own (named by it); the shear stages' go to
    // the shear below
    std::vector<StudyJob::StageKey> prep_keys;
    for (const StudyJob::StageKey& sk : pt.stage_keys)
      if (sk.stage < first_shear) {
        prep_keys.push_back(sk);
        sn << "_" << sk.stage_name << "-" << sk.key << name_number(sk.value);
      }
    if (!sample_index.count(sn.str())) {
      StudyJob j;
      j.name = sn.str();
      j.is_sample = true;
      j.mu_r = pt.mu_r;
      j.set_mu_r = pt.set_mu_r;
      j.e0 = pt.e0;
      j.p0 = pt.p0;
      j.E = pt.E;
      j.seed = pt.seed;
      j.count = file ? file->count : pt.count;
      j.stage_keys = prep_keys;
      if (file) {
        j.specimen_name = file->name;
        j.specimen_file = file->file;
        j.specimen_e = file->e;
      }
      if (pt.grading >= 0) {
        j.grading_name = gradings[pt.grading].name;
        j.grading_yaml = gradings[pt.grading].yaml;
        j.grading_cu = gradings[pt.grading].cu;
      }
      j.config_yaml = YAML::Dump(job_config(base, j, false, "", base_sample));
      sample_index[j.name] = s.samples.size();
      s.samples.push_back(j);
    } else {
      // The same name is the same sample (a point listed twice), unless the values differ below the name's six
      // significant digits: then two samples would silently become one.
      const StudyJob& o = s.samples[sample_index[sn.str()]];
      if (o.mu_r != pt.mu_r || o.e0 != pt.e0 || o.p0 != pt.p0 || o.E != pt.E ||
          key_values(o.stage_keys) != key_values(prep_keys))
        fail(path, "axes", "two values of mu_r, e0, p0, E or a preparation stage's axis agree to 6 significant digits "
                           "(job " + sn.str() + "); make them differ sooner or list one of them");
    }
    if (!has_tri) continue;  // a preparation study: the sample is the job
    StudyJob sh = s.samples[sample_index[sn.str()]];
    sh.is_sample = false;
    sh.sample_name = sn.str();
    sh.drainage = pt.drainage;
    sh.set_drainage = pt.set_drainage;
    sh.name = "shear_" + pt.drainage + "_" + sn.str().substr(7);
    sh.direction = pt.direction;
    sh.set_direction = pt.set_direction;
    if (pt.direction == "extension") sh.name += "_ext";  // compression keeps the names studies had before the axis
    sh.b = pt.b;
    sh.set_b = pt.set_b;
    if (pt.set_b && pt.b > 0) sh.name += "_b" + fmt(pt.b);  // b = 0 likewise
    sh.stress_path = pt.stress_path;
    sh.set_stress_path = pt.set_stress_path;
    if (pt.set_stress_path && pt.stress_path == "constant_p") sh.name += "_cp";  // constant sigma_3 likewise
    if (pt.set_stress_path && pt.stress_path == "plane_strain") sh.name += "_ps";
    sh.cycles = base_cycles;
    if (pt.csr > 0) {
      sh.csr = pt.csr;
      sh.q_amplitude = 2 * pt.csr * (pt.p0 > 0 ? pt.p0 : base_p0);
      sh.name += "_csr" + fmt(pt.csr);
    }
    if (pt.ea > 0) {
      sh.strain_amplitude = pt.ea;
      // to 12 significant digits: 0.2 x (1e-4 / 1e-3) is 0.020000000000000004 in binary, and job.yaml shows it
      char buf[32];
      std::snprintf(buf, sizeof buf, "%.12g", base_strain_rate * (pt.ea / base_strain_amp));
      sh.strain_rate = std::strtod(buf, nullptr);
      sh.name += "_ea" + fmt(pt.ea);
    }
    if (pt.rate > 0) {
      sh.rate = pt.rate;
      sh.rate_group = sh.name;  // the same test at other rates: the report's rate series
      sh.name += "_rate" + fmt(pt.rate);  // without the axis, the names studies had before it
    }
    // every stage key (the report's sections split by them); the name has the preparation's from the sample's
    sh.stage_keys = pt.stage_keys;
    for (const StudyJob::StageKey& sk : pt.stage_keys)
      if (sk.stage >= first_shear) sh.name += "_" + sk.stage_name + "-" + sk.key + name_number(sk.value);
    // The end strain is not in the name: a shear to 30 % is the start of the same shear to 40 %, so raising an extra
    // job's max_axial_strain extends the job that ran (resumed from its checkpoint) instead of starting another.
    sh.strain = pt.strain;
    bool dup = false;
    for (auto& o : s.shears) {
      if (o.name != sh.name) continue;
      dup = true;
      if (o.csr != sh.csr || o.strain_amplitude != sh.strain_amplitude || o.b != sh.b || o.rate != sh.rate ||
          key_values(o.stage_keys) != key_values(sh.stage_keys))  // as above
        fail(path, "axes",
             "two values of csr, strain_amplitude, b, axial_strain_rate or a stage axis agree to 6 significant digits "
             "(job " + sh.name + "); make them differ sooner or list one of them");
      if (o.strain != sh.strain)
        fail(path, "extra",
             "two jobs differ only in max_axial_strain (job " + sh.name + "): the shorter is the start of the longer; "
             "list the longer alone");
    }
    if (!dup) s.shears.push_back(sh);
  }
  // Every job's config is checked now, as the run would check it, so that `grainlab validate` of a study
  // catches what its jobs would stop on (a value valid on an axis but not in the config it lands in).
  for (const StudyJob& j : s.samples) parse_run_config(YAML::Load(j.config_yaml), path + " (job " + j.name + ")");
  for (const StudyJob& j : s.shears)
    parse_run_config(job_config(base, j, true, "sample.h5"), path + " (job " + j.name + ")");
  if (!csr_moved.empty() &&
      std::any_of(s.shears.begin(), s.shears.end(), [](const StudyJob& j) { return j.csr > 0; }))
    s.warnings.push_back(path + ": csr sets q_amplitude = 2 csr p'_0 at the preparation's pressure, and " + csr_moved +
                         ", so the cycles start from another p' (summary.json p_0) and their CSR is not csr: give "
                         "that stage csr instead of q_amplitude (A = 2 csr p'_c at the stress it starts from, "
                         "configs/README.md)");
  return s;
}

std::string duration_text(double seconds) {
  char b[48];
  const long whole = std::lround(seconds);
  if (seconds < 59.95)
    std::snprintf(b, sizeof b, "%.1f s", seconds);
  else if (whole < 3600)
    std::snprintf(b, sizeof b, "%ld min %02ld s", whole / 60, whole % 60);
  else
    std::snprintf(b, sizeof b, "%ld h %02ld min", whole / 3600, (whole / 60) % 60);
  return b;
}

double shears_left_seconds(const std::vector<double>& left, double rate, int slots) {
  if (left.empty() || !(rate > 0) || slots < 1) return 0;
  double sum = 0, longest = 0;
  for (double w : left) {
    sum += w;
    longest = std::max(longest, w);
  }
  return std::max(longest, sum / double(std::min<size_t>(size_t(slots), left.size()))) / rate;
}

std::string shear_config(const Study& s, const StudyJob& j, const std::string& sample_file) {
  return YAML::Dump(job_config(load_yaml_screened(s.base), j, true, sample_file));
}

StudyPlan plan_study(const Study& s) {
  StudyPlan sp;
  const YAML::Node base = load_yaml_screened(s.base);
  std::map<std::string, RunConfig> sample_cfg;
  std::map<std::string, Real> sample_p;  // the pressure a sample's last isotropic stage leaves
  const auto where = [&](const StudyJob& j) { return s.path + " (job " + j.name + ")"; };
  const auto plan = [&](const StudyJob& j, const RunConfig& c, Real p_start) {
    try {
      return plan_run(c, p_start, j.is_sample);  // a sample job places its spheres as it will
    } catch (const std::exception& e) {
      throw std::runtime_error(where(j) + ": " + e.what());
    }
  };
  const auto keep = [&](const StudyJob& j, const RunPlan& p) {
    // a shear job's spheres are its sample job's (planned on the radii that job draws): said once, of the sample
    if (j.is_sample)
      for (const std::string& w : p.sample_warnings) sp.warnings.push_back("job " + j.name + ": " + w);
    for (const std::string& w : p.warnings) sp.warnings.push_back("job " + j.name + ": " + w);
    sp.memory_need_max = std::max(sp.memory_need_max, p.memory_need);
  };
  for (const StudyJob& j : s.samples) {
    const RunConfig c = parse_run_config(YAML::Load(j.config_yaml), where(j));
    const RunPlan p = plan(j, c, 0);
    keep(j, p);
    for (double n : p.steps) sp.sample_steps_max = std::max(sp.sample_steps_max, long(n));
    if (!j.grading_name.empty()) {
      auto [it, fresh] = sp.grading_dt.emplace(j.grading_name, p.dt);
      if (!fresh) it->second = std::min(it->second, double(p.dt));
    }
    for (const StageConfig& st : c.stages)
      if (st.type == StageType::Isotropic) sample_p[j.name] = st.pressure;
    sample_cfg[j.name] = c;
  }
  for (const StudyJob& j : s.shears) {
    // The sample file does not exist before the study prepares it: its radii are the ones its job draws (a
    // consolidation moves spheres, it does not resize them), with that job's density and scaling.
    RunConfig c = parse_run_config(job_config(base, j, true, "sample.h5"), where(j));
    const RunConfig& sc = sample_cfg.at(j.sample_name);
    c.sample_file = sc.sample_file;  // a sample job that starts from a saved sample: its spheres (else none: drawn)
    c.packing = sc.packing;
    c.density = sc.density;
    c.density_scaling = sc.density_scaling;
    const RunPlan p = plan(j, c, sample_p[j.sample_name]);
    keep(j, p);
    double n = 0;
    for (double k : p.steps) n += k;
    sp.shear_work[j.name] = n * double(j.count);
    // a stress-reversal cyclic stage's length depends on the sample: its plan steps are only its max_steps
    const bool capped = std::any_of(c.stages.begin(), c.stages.end(), [](const StageConfig& st) {
      return st.type == StageType::Cyclic && st.stress_reversal();
    });
    if (capped) {
      ++sp.capped_shears;
      sp.capped_steps_max = std::max(sp.capped_steps_max, long(n));
    } else {
      if (std::any_of(c.stages.begin(), c.stages.end(), [](const StageConfig& st) {
            return st.type == StageType::Triaxial && st.stress_ended();
          }))
        ++sp.stress_ended_shears;
      const bool first = sp.shear_steps_total == 0;
      sp.shear_steps_min = first ? long(n) : std::min(sp.shear_steps_min, long(n));
      sp.shear_steps_max = std::max(sp.shear_steps_max, long(n));
      sp.shear_steps_total += n;
    }
    if (p.inertial_test > 0) {
      sp.inertial_min = sp.inertial_min > 0 ? std::min(sp.inertial_min, p.inertial_test) : p.inertial_test;
      sp.inertial_max = std::max(sp.inertial_max, p.inertial_test);
    }
    sp.inertial_all_max = std::max(sp.inertial_all_max, p.inertial_max);
  }
  return sp;
}

namespace {
struct Running {
  pid_t pid;
  const StudyJob* job;
  std::chrono::steady_clock::time_point start;
  bool resumed;  // from a checkpoint an earlier call left: its wall time is not its planned work's
  int slot;      // which of the --jobs slots it runs in (its places, where OpenMP binds: JobPlaces)
};

// Where OpenMP binds its threads (OMP_PROC_BIND, OMP_PLACES; the binding Kokkos advises), a process's threads bind
// to the places it starts with, and libgomp pins the study's own initial thread to its first place as it loads: every
// job inherited that one place, and `--jobs 2` ran both jobs on one core (measured: the tiny study's two 1-thread jobs
// on CPU 0 at 50 % each). So the study's places are divided among the --jobs slots, consecutive ones to each (a place
// each, in turn, where the slots outnumber them; divided rather than counted by a job's threads, which count CPUs: with
// OMP_PLACES=cores on a 2-way SMT machine a core is one place of two CPUs): the job's affinity is its slot's CPUs and
// its OMP_PLACES names its places, so its OpenMP binds within them with the user's policy. Where OpenMP does not bind,
// nothing is set: the kernel's scheduler spreads the jobs.
class JobPlaces {
 public:
  explicit JobPlaces(int jobs) {
    const auto places = compat::openmp_places();
    if (places.empty()) return;
    const size_t np = places.size(), nj = size_t(std::max(1, jobs));
    shared_ = np < nj;
    for (size_t s = 0; s < nj; ++s) {
      Slot slot;
      CPU_ZERO(&slot.cpus);
      const size_t begin = np >= nj ? s * np / nj : s % np, end = np >= nj ? (s + 1) * np / nj : begin + 1;
      const std::vector<std::vector<int>> mine(places.begin() + long(begin), places.begin() + long(end));
      for (const auto& place : mine)
        for (const int c : place)
          if (c >= 0 && c < CPU_SETSIZE) CPU_SET(c, &slot.cpus);
      slot.text = compat::places_text(mine);
      for (char** e = environ; *e != nullptr; ++e)
        if (std::strncmp(*e, "OMP_PLACES=", 11) != 0) slot.env.emplace_back(*e);
      slot.env.push_back("OMP_PLACES=" + slot.text);
      slots_.push_back(std::move(slot));
    }
    for (Slot& slot : slots_) {  // pointers into the strings once no string moves again
      for (std::string& e : slot.env) slot.envp.push_back(e.data());
      slot.envp.push_back(nullptr);
    }
  }
  bool binds() const { return !slots_.empty(); }
  bool shared() const { return shared_; }
  // "{0} | {1}": each slot's places
  std::string text() const {
    std::string t;
    for (const Slot& slot : slots_) t += (t.empty() ? "" : " | ") + slot.text;
    return t;
  }
  // In the forked child, before exec: only a system call and a pointer store (the study may hold other threads' locks).
  void apply_in_child(int slot) {
    if (!binds()) return;
    Slot& s = slots_[size_t(slot) % slots_.size()];
    if (sched_setaffinity(0, sizeof(cpu_set_t), &s.cpus) != 0) _exit(4);
    environ = s.envp.data();
  }

 private:
  struct Slot {
    cpu_set_t cpus;
    std::string text;
    std::vector<std::string> env;  // the study's environment with OMP_PLACES set to the slot's places
    std::vector<char*> envp;
  };
  std::vector<Slot> slots_;
  bool shared_ = false;
};

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// The isotropic stages of a finished run that ran out of steps (summary.json's done: false): the stage reached its
// max_steps before its pressure, unbalanced-force and kinetic-energy criteria held, so the sample is not in equilibrium
// at its pressure (the run says so on its stdout, which a study's job keeps quiet; the report marks it too). A later
// isotropic stage that converged puts the sample in equilibrium after all (a seat that ran out of steps, then a
// preloading and an unloading that converged): only the path's point at that stage's end was not one.
struct Unconverged {
  std::vector<std::string> stages;  // those that ran out of steps, in order
  bool last_converged = true;       // the last isotropic stage converged: the sample ends in equilibrium
  // a target_e0 search that missed its target (summary.json's target_e0 and tolerance against e): "stage: e 0.767
  // against target_e0 0.8 (tolerance 0.003)"; empty where none missed
  std::string e0_missed;
  // the e its trials reached, from its stage's sample file (/search/trial_e): " (its 2 trials reached e 0.6863 to
  // 0.7672)"; empty where the file has none
  std::string e0_trials;
};
Unconverged unconverged_stages(const fs::path& summary) {
  Unconverged u;
  try {
    for (const YAML::Node& st : YAML::LoadFile(summary.string())["stages"]) {
      if (!st["type"] || st["type"].as<std::string>() != "isotropic" || !st["done"]) continue;
      u.last_converged = st["done"].as<bool>();
      if (!u.last_converged) u.stages.push_back(st["name"] ? st["name"].as<std::string>() : "?");
      if (st["target_e0"] && st["e"] && st["target_e0_tolerance"]) {
        const double e = st["e"].as<double>(), t = st["target_e0"].as<double>();
        if (std::abs(e - t) > st["target_e0_tolerance"].as<double>()) {
          std::ostringstream os;
          const std::string stage = st["name"] ? st["name"].as<std::string>() : "?";
          os << std::setprecision(4) << stage << ": e " << e << " against target_e0 " << t << " (tolerance "
             << st["target_e0_tolerance"].as<double>() << ")";
          u.e0_missed = os.str();
          try {  // where a target could lie: the void ratios the trials' frictions, 0 to mu_max, did make
            const std::vector<double> te = H5Reader((summary.parent_path() / ("sample_" + stage + ".h5")).string())
                                               .doubles("/search/trial_e");
            if (!te.empty()) {
              std::ostringstream ts;
              ts << std::fixed << std::setprecision(4) << " (its " << te.size() << " trials reached e "
                 << *std::min_element(te.begin(), te.end()) << " to " << *std::max_element(te.begin(), te.end()) << ")";
              u.e0_trials = ts.str();
            }
          } catch (const std::exception&) {  // no sample file, or one from a build before the trials: say less
          }
        }
      }
    }
  } catch (const std::exception&) {  // unreadable: nothing to say (the report reads it again)
  }
  return u;
}

volatile std::sig_atomic_t g_study_stop = 0, g_study_pipe_closed = 0, g_study_checkpoint = 0;
extern "C" void on_study_checkpoint(int) { g_study_checkpoint = 1; }
extern "C" void on_study_stop(int sig) {
  g_study_stop = 1;
  if (sig == SIGPIPE) g_study_pipe_closed = 1;
}
extern "C" void on_child(int) {}  // only to end sigsuspend

// Signal set-up of the study's job loop. Ctrl-C, SIGTERM, SIGHUP or SIGPIPE (the reader of the study's lines gone,
// as for a run: simulation.cpp): no new job starts, the running ones get SIGTERM and stop at a checkpoint like an
// interrupted run, and the study exits 130 once they have; a rerun resumes them. (SIGKILL of the study:
// PR_SET_PDEATHSIG in each job.) SIGINT, SIGHUP or SIGPIPE ignored by the caller (`&` in a script, nohup) stays
// ignored; after a SIGPIPE it stays ignored, so the lines still buffered cannot kill the study before its exit code.
// SIGCHLD and the stop signals are blocked in the loop and taken only in sigsuspend, so a signal cannot fall between a
// check of the flag and the wait. SIGUSR1 (a batch system's warning before its time limit) is passed on to the running
// jobs, each of which writes a checkpoint and goes on (simulation.cpp, SignalGuard); a job starts with it blocked and
// unblocks it once its handler is in, so one sent as a job starts waits for the handler instead of ending the job.
class StudySignals {
 public:
  StudySignals() {
    g_study_stop = 0;
    struct sigaction sa {};
    sa.sa_handler = on_study_stop;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, nullptr, &old_int_);
    int_ignored_ = old_int_.sa_handler == SIG_IGN;
    if (!int_ignored_) sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGHUP, nullptr, &old_hup_);
    hup_ignored_ = old_hup_.sa_handler == SIG_IGN;
    if (!hup_ignored_) sigaction(SIGHUP, &sa, nullptr);
    g_study_pipe_closed = 0;
    sigaction(SIGPIPE, nullptr, &old_pipe_);
    pipe_ignored_ = old_pipe_.sa_handler == SIG_IGN;
    if (!pipe_ignored_) sigaction(SIGPIPE, &sa, nullptr);
    sigaction(SIGTERM, &sa, &old_term_);
    sa.sa_handler = on_study_checkpoint;
    g_study_checkpoint = 0;
    sigaction(SIGUSR1, &sa, &old_usr1_);
    sa.sa_handler = on_child;
    sigaction(SIGCHLD, &sa, &old_chld_);
    sigset_t block;
    sigemptyset(&block);
    for (int sig : {SIGCHLD, SIGINT, SIGTERM, SIGHUP, SIGPIPE, SIGUSR1}) sigaddset(&block, sig);
    sigprocmask(SIG_BLOCK, &block, &prev_);
  }
  ~StudySignals() {
    sigprocmask(SIG_SETMASK, &prev_, nullptr);
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGHUP, &old_hup_, nullptr);
    if (g_study_pipe_closed) signal(SIGPIPE, SIG_IGN);
    else sigaction(SIGPIPE, &old_pipe_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
    sigaction(SIGUSR1, &old_usr1_, nullptr);
    sigaction(SIGCHLD, &old_chld_, nullptr);
  }
  StudySignals(const StudySignals&) = delete;
  StudySignals& operator=(const StudySignals&) = delete;
  // In a forked job, before exec: default actions and the caller's mask, so that a SIGTERM sent to the job
  // before grainlab run installs its own handler ends it (it has written nothing yet).
  void reset_in_child() const {
    signal(SIGINT, int_ignored_ ? SIG_IGN : SIG_DFL);
    signal(SIGHUP, hup_ignored_ ? SIG_IGN : SIG_DFL);
    signal(SIGPIPE, pipe_ignored_ ? SIG_IGN : SIG_DFL);
    signal(SIGTERM, SIG_DFL);
    signal(SIGUSR1, SIG_DFL);
    signal(SIGCHLD, SIG_DFL);
    sigset_t mask = prev_;
    sigaddset(&mask, SIGUSR1);  // kept blocked through exec until the run's handler is in
    sigprocmask(SIG_SETMASK, &mask, nullptr);
  }
  void wait_for_signal() const { sigsuspend(&prev_); }

 private:
  struct sigaction old_int_ {}, old_hup_ {}, old_term_ {}, old_chld_ {}, old_pipe_ {}, old_usr1_ {};
  sigset_t prev_{};
  bool int_ignored_ = false, hup_ignored_ = false, pipe_ignored_ = false;
};

// Runs args[0] with args (found on the PATH; no shell, so any character in a path is taken as it is) and waits for it:
// its exit code, 128 + the signal that ended it, or -1 where it could not start. With `err`, its standard error is
// collected there and its standard output discarded; else both are the study's.
int run_and_wait(const std::vector<std::string>& args, std::string* err) {
  int fd[2] = {-1, -1};
  if (err && pipe(fd) != 0) return -1;
  std::fflush(nullptr);  // the child would flush the study's pending lines a second time
  const pid_t pid = fork();
  if (pid == 0) {
    if (err) {
      const int null = ::open("/dev/null", O_WRONLY);
      if (null < 0 || dup2(null, 1) < 0 || dup2(fd[1], 2) < 0) _exit(127);
      ::close(fd[0]);
    }
    std::vector<char*> argv;
    argv.reserve(args.size() + 1);
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execvp(argv[0], argv.data());
    std::fprintf(stderr, "grainlab study: cannot run %s (%s)\n", argv[0], std::strerror(errno));
    _exit(127);
  }
  if (err) {
    ::close(fd[1]);
    char buf[4096];
    for (ssize_t n; pid > 0 && ((n = ::read(fd[0], buf, sizeof(buf))) > 0 || (n < 0 && errno == EINTR));)
      if (n > 0) err->append(buf, size_t(n));
    ::close(fd[0]);
  }
  if (pid < 0) return -1;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// Whether `grainlab run CFG --out DIR --resume` would refuse: the run's own check (`run --check-resume`, in a child
// process like every job: the study does not start Kokkos), its error line where it would ("" where it would go on).
// An edit that moves a job's end before where its run is (a max_axial_strain lowered below the strain a finished
// shear reached) passes the study's comparison of configs, which cannot see where the run went.
std::string resume_refusal(const std::string& self, const std::string& cfg, const std::string& dir) {
  std::string err;
  const int rc = run_and_wait({self, "run", cfg, "--out", dir, "--check-resume", "--threads", "1"}, &err);
  if (rc == 0) return "";
  // Its last line, less "grainlab: error: CFG: " (the study names the job itself).
  while (!err.empty() && (err.back() == '\n' || err.back() == '\r')) err.pop_back();
  std::string line = err.substr(err.rfind('\n') == std::string::npos ? 0 : err.rfind('\n') + 1);
  for (const std::string& prefix : {std::string("grainlab: error: "), cfg + ": "})
    if (line.compare(0, prefix.size(), prefix) == 0) line.erase(0, prefix.size());
  return line.empty() ? "its check ended with " + (rc < 0 ? std::string("no process") : "exit " + std::to_string(rc))
                      : line;
}

// One study process per output directory: a second one would launch the same jobs, which their run locks
// would then fail one by one. The lock is not inherited by the jobs (O_CLOEXEC), so it ends with the study.
class StudyLock {
 public:
  explicit StudyLock(const fs::path& out) {
    const std::string path = (out / ".lock").string();
    fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) throw std::runtime_error(path + ": cannot create the lock file (" + std::strerror(errno) + ")");
    if (!lock_or_warn(fd_, path)) {
      ::close(fd_);
      throw std::runtime_error(out.string() + ": in use by another grainlab study (lock held on " + path + ")");
    }
  }
  ~StudyLock() { ::close(fd_); }
  StudyLock(const StudyLock&) = delete;
  StudyLock& operator=(const StudyLock&) = delete;

 private:
  int fd_ = -1;
};
}  // namespace

int run_study(const Study& s, const StudyOptions& o) {
  const fs::path out = o.out_dir.empty() ? fs::path("runs") / fs::path(s.path).stem() : fs::path(o.out_dir);
  // A run's directory: the study's jobs/, figures/ and report would sit among the run's files
  if (holds_run(out.string()))
    throw std::runtime_error(out.string() + ": holds a run (grainlab run --out); a study's --out is a directory of its "
                                            "own (nothing was changed)");
  if (std::error_code ec; !fs::create_directories(out / "jobs", ec) && ec)
    throw std::runtime_error(out.string() + ": cannot create the study's directory (" + ec.message() + ")");
  const StudyLock lock(out);
  // The cores of this process's affinity, not the machine's: a container's cpuset of 2 on a 64-core host must not
  // start 32 threads a job (OpenMP threads beyond the cores wait on each other at every barrier, main.cpp).
  // Without --threads, at most what OMP_THREAD_LIMIT or OMP_MAX_ACTIVE_LEVELS allow a job (compat::openmp_thread_cap;
  // given more by --threads, main refuses the study).
  const int per_job_threads = o.threads > 0
                                  ? threads_per_job(o.threads, o.jobs)
                                  : std::min(threads_per_job(usable_cores(), o.jobs), compat::openmp_thread_cap());
  // Where --threads did not set them, a job of few spheres gets fewer: a thread a kSpheresPerThread spheres, as a
  // run's default (default_threads: a small sample spread over many threads waits on their barriers).
  const auto job_threads = [&](const StudyJob& j) {
    return o.threads > 0 || j.count <= 0 ? per_job_threads : default_threads(j.count, per_job_threads);
  };
  // Write every job's config first: a bad one fails now, not hours in.
  auto cfg_path = [&](const StudyJob& j) { return out / "jobs" / j.name / "job.yaml"; };
  auto sample_file = [&](const StudyJob& sample) {
    std::string last_iso;
    for (auto st : YAML::Load(sample.config_yaml)["stages"]) last_iso = st["name"] ? st["name"].as<std::string>() : "";
    // Relative to the shear's job.yaml (load_run_config resolves it from there): the README's relative --out
    // works from any working directory, and a moved study directory still finds its samples.
    return (fs::path("..") / sample.name / "run" / ("sample_" + last_iso + ".h5")).string();
  };
  std::map<std::string, const StudyJob*> by_name;
  for (const StudyJob& j : s.samples) by_name[j.name] = &j;
  const YAML::Node base = YAML::LoadFile(s.base);
  std::vector<std::pair<const StudyJob*, std::string>> texts;
  for (auto* list : {&s.samples, &s.shears})
    for (const StudyJob& j : *list)
      texts.emplace_back(&j, (j.is_sample ? j.config_yaml
                                          : YAML::Dump(job_config(base, j, true, sample_file(*by_name.at(j.sample_name))))) +
                                 "\n");
  // A rerun skips finished jobs and resumes started ones, so a job that ran with another config than the study
  // now gives it (an edited base or study file, the same --out) would put stale results in the report without a
  // word. Such jobs stop the study before anything is written. The configs are compared as the run resolves
  // them (every default filled in, the sample path made absolute), so a job.yaml that says the same in other
  // words (an older grainlab's absolute sample path) is the same job.
  const auto resolved = [&](const std::string& yaml, const fs::path& where) {
    try {
      return resolved_config_yaml(parse_run_config(YAML::Load(yaml), where.string()));
    } catch (const std::exception&) {
      return std::string("unreadable");  // a job.yaml that no longer parses counts as changed
    }
  };
  // A shear whose new config only extends what it ran (the shear taken further, a stage appended) is no stale
  // result: it goes on from its checkpoint like `grainlab run --resume` of an extended config. Compared as if
  // the job had finished every stage it had (the strictest case: what passes here passes the job's own check).
  // A sample must be unchanged, since the shears already run used it, unless no shear does: a preparation study's
  // samples extend alike (a loading path taken further).
  std::vector<std::string> changed;
  std::vector<const StudyJob*> extended;
  for (const auto& [j, text] : texts) {
    std::ifstream in(cfg_path(*j), std::ios::binary);
    if (!in) continue;
    const std::string old((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const fs::path run = out / "jobs" / j->name / "run";
    std::error_code ec;
    if (!fs::is_directory(run, ec) || fs::is_empty(run, ec)) continue;  // never started: nothing to go stale
    const std::string then_text = resolved(old, cfg_path(*j)), now_text = resolved(text, cfg_path(*j));
    if (then_text == now_text) continue;
    // Compared with the new checkpoint cadence on both sides: a cadence changes nothing a run computes, and its run
    // takes the new one itself where it resumes (with_checkpoint_cadence).
    const std::string then = with_checkpoint_cadence_of(then_text, now_text),
                      now = with_checkpoint_cadence_of(now_text, now_text);
    if (then == now) continue;
    if ((!j->is_sample || s.shears.empty()) && then_text != "unreadable" &&
        extension_mismatch(then, now, int(YAML::Load(then)["stages"].size())).empty())
      extended.push_back(j);
    else
      changed.push_back(j->name);
  }
  if (!changed.empty())
    throw std::runtime_error((out / "jobs" / changed[0] / "job.yaml").string() + ": this job ran with another config than " +
                             s.path + " gives it now (" + std::to_string(changed.size()) +
                             " job(s) so); use another --out, or delete those jobs/ directories to run them again "
                             "(nothing was changed)");
  // The same config on another sample is another job too: a base's sample.file prepared again, or a sample job
  // deleted and run again (on another thread count: other bits), under jobs that already ran on the former one.
  // Each started job's checkpoints record the sample it started from (run_sample_digest); the file its config
  // names now is compared with it where the file is there (a sample job yet to run is checked after it has).
  struct Resampled {
    std::string job, file, then, now;
  };
  const auto resampled = [&]() {
    std::vector<Resampled> found;
    std::map<std::string, std::string> digest_now;  // sample file -> its digest (each file read once)
    for (const auto& [j, text] : texts) {
      const std::string then = run_sample_digest((out / "jobs" / j->name / "run").string());
      if (then.empty()) continue;  // not started, or a build before the digest
      std::string file;
      try {
        file = parse_run_config(YAML::Load(text), cfg_path(*j).string()).sample_file;
      } catch (const std::exception&) {
        continue;  // validated, and named, where the job configs are written
      }
      if (std::error_code ec; file.empty() || !fs::exists(file, ec)) continue;
      auto it = digest_now.find(file);
      if (it == digest_now.end()) it = digest_now.emplace(file, sample_file_digest(file)).first;
      if (it->second != then) found.push_back({j->name, file, then, it->second});
    }
    return found;
  };
  const auto on_another_sample = [&](const std::vector<Resampled>& r) {
    return "this job ran on another sample than " + r[0].file + " holds now (sample " + r[0].then + " then, " +
           r[0].now + " now; " + std::to_string(r.size()) + " job(s) so)";
  };
  if (const auto r = resampled(); !r.empty())
    throw std::runtime_error((out / "jobs" / r[0].job / "job.yaml").string() + ": " + on_another_sample(r) +
                             ": put that sample back, use another --out, or delete those jobs/ directories to run them "
                             "on this one (nothing was changed)");
  // Each extended job as its run will see it: a refusal now, with nothing changed, rather than a failed job whose
  // `done` is gone (the report would drop it) until the study is edited back. The new config goes to a temporary
  // file beside job.yaml (its relative sample path resolves from there), removed after.
  for (const StudyJob* j : extended) {
    const fs::path dir = out / "jobs" / j->name, tmp = dir / ("job.yaml.check." + std::to_string(getpid()));
    std::string why;
    try {
      write_file_atomic(tmp.string(), std::find_if(texts.begin(), texts.end(), [&](const auto& t) {
                                         return t.first == j;
                                       })->second);
      why = resume_refusal(o.self_exe, tmp.string(), (dir / "run").string());
    } catch (...) {
      std::error_code ec;
      fs::remove(tmp, ec);
      throw;
    }
    std::error_code ec;
    fs::remove(tmp, ec);
    if (!why.empty())
      throw std::runtime_error((dir / "job.yaml").string() + ": the edited " + s.path + " extends this job, but its run " +
                               "refuses: " + why + " (nothing was changed; give the former end back, use another " +
                               "--out, or delete that jobs/ directory to run the job again)");
  }
  for (const StudyJob* j : extended) fs::remove(out / "jobs" / j->name / "done");  // to be resumed, further
  if (!extended.empty() && !o.quiet)
    std::printf("study %s: %zu %s extended by the edited study, resumed from their checkpoints\n", s.path.c_str(),
                extended.size(), s.shears.empty() ? "sample(s)" : "shear(s)");
  for (const auto& [j, text] : texts) {
    fs::create_directories(out / "jobs" / j->name);
    write_file_atomic(cfg_path(*j).string(), "# generated by grainlab study from " + s.path + "\n" + text);
    load_run_config(cfg_path(*j).string());  // every job validates now (a sample file is opened only at run)
  }
  for (const StudyJob& j : s.shears) by_name[j.name] = &j;
  // Study index for the report.
  {
    // a job's stage axes' values, `"stage_keys": {"<stage>.<key>": value, ...}`: a shear's every one, a sample's its
    // preparation's; only with a stage axis (study.json as it was without)
    const auto stage_keys_json = [](std::ostringstream& os, const StudyJob& j) {
      if (j.stage_keys.empty()) return;
      os << ", \"stage_keys\": {";
      for (size_t a = 0; a < j.stage_keys.size(); ++a)
        os << (a ? ", " : "") << json_string(j.stage_keys[a].stage_name + "." + j.stage_keys[a].key) << ": "
           << j.stage_keys[a].value;
      os << "}";
    };
    std::ostringstream js;
    js << "{\n  \"study\": " << json_string(s.path) << ",\n  \"strain_stage\": " << json_string(s.strain_stage)
       << ",\n  \"critical_state\": {\"window\": " << s.window
       << ", \"qp_tol\": " << s.qp_tol << ", \"p_tol\": " << s.p_tol << ", \"e_tol\": " << s.e_tol
       << "},\n  \"peak\": {\"window\": " << s.peak_window << ", \"max_ke_ratio\": " << s.peak_max_ke
       << "},\n  \"jobs\": [\n";
    for (size_t k = 0; k < s.shears.size(); ++k) {
      const StudyJob& j = s.shears[k];
      js << "    {\"name\": \"" << j.name << "\", \"dir\": \"jobs/" << j.name << "/run\", \"sample\": \"" << j.sample_name
         << "\", \"mu_r\": " << j.mu_r << ", \"e0\": " << j.e0 << ", \"p0\": " << j.p0 << ", \"drainage\": \""
         << j.drainage << "\", \"direction\": " << json_string(j.direction) << ", \"b\": " << j.b << ", \"stress_path\": " << json_string(j.stress_path) << ", \"seed\": " << j.seed
         << ", \"count\": " << j.count << ", \"csr\": " << j.csr
         << ", \"cycles\": " << j.cycles << ", \"strain_amplitude\": " << j.strain_amplitude
         << ", \"axial_strain_rate\": " << j.rate << ", \"rate_group\": " << json_string(j.rate_group)
         << ", \"max_axial_strain\": " << j.strain;
      stage_keys_json(js, j);
      js << ", \"grading\": " << json_string(j.grading_name) << ", \"cu\": " << j.grading_cu
         << ", \"specimen\": " << json_string(j.specimen_name) << ", \"specimen_file\": " << json_string(j.specimen_file)
         << ", \"E\": " << j.E << "}"
         << (k + 1 < s.shears.size() ? "," : "") << "\n";
    }
    // Every sample job (a preparation study's only jobs): the report's Samples and Preparation sections. p0 and e0
    // of 0 are the base's.
    js << "  ],\n  \"samples\": [\n";
    for (size_t k = 0; k < s.samples.size(); ++k) {
      const StudyJob& j = s.samples[k];
      js << "    {\"name\": \"" << j.name << "\", \"dir\": \"jobs/" << j.name << "/run\", \"mu_r\": " << j.mu_r
         << ", \"e0\": " << j.e0 << ", \"p0\": " << j.p0 << ", \"seed\": " << j.seed << ", \"count\": " << j.count;
      stage_keys_json(js, j);
      js << ", \"grading\": " << json_string(j.grading_name) << ", \"cu\": " << j.grading_cu
         << ", \"specimen\": " << json_string(j.specimen_name) << ", \"specimen_file\": " << json_string(j.specimen_file)
         << ", \"E\": " << j.E << "}"
         << (k + 1 < s.samples.size() ? "," : "") << "\n";
    }
    js << "  ]\n}\n";
    write_file_atomic((out / "study.json").string(), js.str());
  }
  auto done = [&](const StudyJob& j) { return fs::exists(out / "jobs" / j.name / "done"); };
  std::optional<StudySignals> signals;  // for the job loop only: the report's python runs with the usual signals
  signals.emplace();
  JobPlaces job_places(o.jobs);
  auto launch = [&](const StudyJob& j, int slot) -> pid_t {
    const std::string log = (out / "jobs" / j.name / "log.txt").string();
    const pid_t parent = getpid();
    // The child's freopen flushes the stdio buffers it inherited: flush them here, or every job would print
    // the study's pending lines a second time (stdout is block-buffered when it is a file or a pipe).
    std::fflush(nullptr);
    const pid_t pid = fork();
    if (pid == 0) {
      signals->reset_in_child();
      // A study stopped by SIGTERM or SIGKILL must not leave its jobs running unattended (a rerun would
      // start a second writer on the same run directory): the job gets SIGTERM when the study dies and
      // stops at a checkpoint like a Ctrl-C'd run, which the rerun resumes.
      prctl(PR_SET_PDEATHSIG, SIGTERM);
      if (getppid() != parent) _exit(3);  // the study died before prctl took effect
      if (!freopen(log.c_str(), "a", stdout) || !freopen(log.c_str(), "a", stderr)) _exit(2);
      job_places.apply_in_child(slot);
      const std::string cfg = cfg_path(j).string(), dir = (out / "jobs" / j.name / "run").string(),
                        th = std::to_string(job_threads(j));
      execl(o.self_exe.c_str(), o.self_exe.c_str(), "run", cfg.c_str(), "--out", dir.c_str(), "--resume", "--threads",
            th.c_str(), "--quiet", (char*)nullptr);
      _exit(127);
    }
    return pid;
  };
  // Longest first (Graham's LPT rule): --jobs slots that took the shears in the study's order could end on one long
  // shear alone (the quick study's mu_r 0.3 shears plan 2.6x the steps of its mu_r 0 ones, the rolling time-step
  // limit: in its order the six end at 6.2 mu_r-0 shear lengths on 2 slots, longest first at 5.6, the bound 5.4).
  // Each sample before its shears, the samples in the order of their longest shear. The plan is validate's
  // (plan_study, ~0.3 s for the quick study, 2 s for the paper's); where it fails, the study's own order. The order
  // changes no result: each job runs alone on its own files.
  std::map<std::string, double> work;
  if (std::any_of(s.shears.begin(), s.shears.end(), [&](const StudyJob& j) { return !done(j); })) {
    try {
      work = plan_study(s).shear_work;
    } catch (const std::exception&) {
      // each job still runs and reports its own error
    }
  }
  const auto work_of = [&](const StudyJob& j) {
    const auto it = work.find(j.name);
    return it == work.end() ? 0.0 : it->second;
  };
  std::map<std::string, double> sample_work;  // its longest shear's
  for (const StudyJob& j : s.shears) sample_work[j.sample_name] = std::max(sample_work[j.sample_name], work_of(j));
  std::vector<const StudyJob*> samples_first, shears_first;
  for (auto& j : s.samples)
    if (!done(j)) samples_first.push_back(&j);
  for (auto& j : s.shears)
    if (!done(j)) shears_first.push_back(&j);
  std::stable_sort(samples_first.begin(), samples_first.end(), [&](const StudyJob* a, const StudyJob* b) {
    return sample_work[a->name] > sample_work[b->name];
  });
  std::stable_sort(shears_first.begin(), shears_first.end(),
                   [&](const StudyJob* a, const StudyJob* b) { return work_of(*a) > work_of(*b); });
  std::vector<const StudyJob*> queue = samples_first;
  queue.insert(queue.end(), shears_first.begin(), shears_first.end());
  const size_t total = s.samples.size() + s.shears.size();
  for (const std::string& w : s.warnings) std::fprintf(stderr, "grainlab: warning: %s\n", w.c_str());
  if (!o.quiet) {
    bool fewer = false;  // a job below per_job_threads x kSpheresPerThread spheres, which starts fewer threads
    for (const auto* js : {&s.samples, &s.shears})
      for (const StudyJob& j : *js) fewer = fewer || job_threads(j) < per_job_threads;
    const std::string few = " (fewer for a job of fewer than " + std::to_string(per_job_threads * kSpheresPerThread) +
                            " spheres: a thread a " + std::to_string(kSpheresPerThread) + ")";
    std::printf("study %s: %zu sample%s, %zu shear%s; %zu to run, %d at a time x %d thread%s%s; output %s\n",
                s.path.c_str(), s.samples.size(), plural(long(s.samples.size())), s.shears.size(),
                plural(long(s.shears.size())), queue.size(), o.jobs, per_job_threads, plural(long(per_job_threads)),
                fewer ? few.c_str() : "", out.c_str());
    if (job_places.binds())
      std::printf("OpenMP binds threads (OMP_PROC_BIND, OMP_PLACES): its places divided among the running jobs, %s%s\n",
                  job_places.text().c_str(),
                  job_places.shared() ? " (fewer places than --jobs: some jobs share one)" : "");
  }
  std::vector<Running> running;
  int failures = 0, interrupted = 0;
  bool stopping = false, forwarded = false;
  size_t finished = total - queue.size();
  // The progress lines' estimate of the shears left: the planned work (shear_work) the shears started and finished in
  // this call did in their wall seconds (a resumed one did part of its work before). Only the shears': a preparation
  // ends at equilibrium, which no plan foretells.
  double shear_work_done = 0, shear_seconds = 0;
  while (!queue.empty() || !running.empty()) {
    if (g_study_stop) stopping = true;
    if (stopping && !forwarded) {
      for (const Running& r : running) kill(r.pid, SIGTERM);
      forwarded = true;
    }
    if (stopping) queue.clear();  // left for the rerun
    if (g_study_checkpoint) {
      g_study_checkpoint = 0;
      for (const Running& r : running) kill(r.pid, SIGUSR1);
      std::fprintf(stderr, "grainlab study: SIGUSR1: %zu running job(s) asked for a checkpoint; the study goes on\n",
                   running.size());
    }
    // Start what can start: samples any time, shears once their sample is done.
    for (auto it = queue.begin(); it != queue.end() && int(running.size()) < o.jobs;) {
      const StudyJob* j = *it;
      if (!j->is_sample && !done(*by_name[j->sample_name])) {
        bool sample_failed = true;
        for (auto& r : running) sample_failed = sample_failed && r.job->name != j->sample_name;
        for (auto* q : queue) sample_failed = sample_failed && q->name != j->sample_name;
        if (!sample_failed) {
          ++it;
          continue;
        }
        std::fprintf(stderr, "grainlab study: %s skipped: its sample %s failed\n", j->name.c_str(), j->sample_name.c_str());
        ++failures;
        it = queue.erase(it);
        continue;
      }
      const bool resumed = fs::exists(out / "jobs" / j->name / "run" / "series.csv");
      int slot = 0;  // the lowest free one
      while (std::any_of(running.begin(), running.end(), [&](const Running& r) { return r.slot == slot; })) ++slot;
      running.push_back({launch(*j, slot), j, std::chrono::steady_clock::now(), resumed, slot});
      it = queue.erase(it);
    }
    if (running.empty()) continue;
    int status = 0;
    const pid_t pid = waitpid(-1, &status, WNOHANG);
    if (pid == 0) {
      signals->wait_for_signal();  // a job ended, or Ctrl-C / SIGTERM
      continue;
    }
    if (pid < 0) {
      if (errno == EINTR) continue;
      std::fprintf(stderr, "grainlab study: lost track of %zu running job(s) (%s)\n", running.size(), std::strerror(errno));
      failures += int(running.size());
      break;
    }
    for (auto it = running.begin(); it != running.end(); ++it) {
      if (it->pid != pid) continue;
      const StudyJob& j = *it->job;
      const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      if (code == 0) {
        ++finished;
        write_file_atomic((out / "jobs" / j.name / "done").string(), "ok\n");
        const double took = seconds_since(it->start);
        if (!j.is_sample && !it->resumed && work_of(j) > 0) {
          shear_work_done += work_of(j);
          shear_seconds += took;
        }
        std::string left_text;
        if (shear_work_done > 0 && shear_seconds > 0) {
          const double rate = shear_work_done / shear_seconds;
          std::vector<double> left;  // the shears queued, and those running less what they have done by this rate
          for (const StudyJob* q : queue)
            if (!q->is_sample) left.push_back(work_of(*q));
          for (const Running& r : running)
            if (r.pid != pid && !r.job->is_sample)
              left.push_back(std::max(0.0, work_of(*r.job) - rate * seconds_since(r.start)));
          if (!left.empty())
            left_text = "; the shears left: about " + duration_text(shears_left_seconds(left, rate, o.jobs));
        }
        if (!o.quiet)
          std::printf("[%zu/%zu] %s done in %s%s\n", finished, total, j.name.c_str(), duration_text(took).c_str(),
                      left_text.c_str());
        // a sample's preparation, or a shear job's isotropic stage between its shears (a reconsolidation)
        const Unconverged u = unconverged_stages(out / "jobs" / j.name / "run" / "summary.json");
        for (size_t k = 0; k < u.stages.size(); ++k)
          std::fprintf(stderr, "grainlab study: warning: %s: stage %s ran out of steps (its max_steps) before equilibrium: %s; "
                       "raise the stage's max_steps\n", j.name.c_str(), u.stages[k].c_str(),
                       k + 1 == u.stages.size() && !u.last_converged
                           ? "the sample is not in equilibrium at its pressure and its e is not an equilibrium's"
                           : "a later isotropic stage converged, so the sample ends in equilibrium, but its path passed "
                             "that stage's pressure out of equilibrium");
        // a target_e0 the search's frictions could not reach: the job's name says the target, its sample has another e
        if (!u.e0_missed.empty())
          std::fprintf(stderr, "grainlab study: warning: %s: target_e0 NOT reached (%s): its frictions, 0 to the "
                       "stage's mu_max, do not make that void ratio of this sample here%s; the report gives the e it "
                       "has\n", j.name.c_str(), u.e0_missed.c_str(), u.e0_trials.c_str());
      } else if (code == 130 || code == 128 + SIGINT || code == 128 + SIGTERM || code == 128 + SIGHUP) {
        // Stopped at a checkpoint (130), or by the signal before it had started: the rerun resumes it. A job
        // stopped so means the user (or the system) is stopping the study: start nothing new.
        ++interrupted;
        stopping = true;
        std::fprintf(stderr, "grainlab study: %s interrupted (exit %d); rerun the study to resume it\n", j.name.c_str(),
                     code);
      } else {
        ++failures;
        // A shear of a sample that ran out of steps starts out of equilibrium, the likeliest cause of its failure (a
        // servo that loses its target at step 0): the study warned of the sample as it ended, and says so again here.
        // A rerun would resume the shear on the same sample and fail again: the remedy is a new sample (the sample
        // job's config changes, which a rerun into the same --out refuses while shears have run on the old one).
        std::string cause;
        if (const Unconverged u = unconverged_stages(out / "jobs" / j.sample_name / "run" / "summary.json");
            !j.is_sample && !u.last_converged)
          cause = "; its sample " + j.sample_name + " is not in equilibrium (stage " + u.stages.back() +
                  " ran out of steps): raise its max_steps and run the study into another --out (or delete the jobs/ "
                  "directories of that sample and of its shears)";
        std::fprintf(stderr, "grainlab study: %s failed (exit %d); see %s%s\n", j.name.c_str(), code,
                     (out / "jobs" / j.name / "log.txt").c_str(),
                     cause.empty() ? "; rerun the study to resume it" : cause.c_str());
      }
      running.erase(it);
      break;
    }
  }
  signals.reset();
  if (stopping) {
    std::fprintf(stderr, "grainlab study: interrupted%s (%d job(s) stopped at a checkpoint, %zu of %zu done); rerun the "
                         "same command to resume\n", g_study_pipe_closed ? " by the reader of its output closing the pipe" : "",
                 interrupted, finished, total);
    return 130;
  }
  if (failures) {
    std::fprintf(stderr, "grainlab study: %d job(s) failed or were skipped; the report covers the finished ones\n", failures);
  }
  // Every sample is there now: a job that ran on a former one (its sample job run again since) must not sit in the
  // report beside the jobs of the new one.
  if (const auto r = resampled(); !r.empty()) {
    std::fprintf(stderr,
                 "grainlab study: %s: %s: delete those jobs/ directories and rerun the study to run them on it; the "
                 "report was not rewritten\n",
                 (out / "jobs" / r[0].job).c_str(), on_another_sample(r).c_str());
    return 1;
  }
  // Report: figures, tables and critical-state lines (scripts/grainlab_plot.py study).
  const char* env = std::getenv("GRAINLAB_PYTHON");
  const std::string py = env && *env ? env : (access("/usr/bin/python3", X_OK) == 0 ? "/usr/bin/python3" : "python3");
  const std::string script = GRAINLAB_SOURCE_DIR "/scripts/grainlab_plot.py", dir = out.string();
  const std::string cmd = py + " " + script + " study " + dir;  // for the message
  // Started directly, not through a shell (std::system): a quote in the --out ("Bob's runs") broke the command.
  const int rc = run_and_wait({py, script, "study", dir}, nullptr);
  if (rc != 0) {
    std::fprintf(stderr, "grainlab study: the report could not be written (%s)\n", cmd.c_str());
    return 1;
  }
  return failures ? 1 : 0;
}

}  // namespace grainlab
