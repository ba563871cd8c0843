// Config loading: shipped configs validate, and bad input gets one clear error naming file, key, range.
#include <gtest/gtest.h>

#include <yaml-cpp/yaml.h>

#include <pwd.h>
#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdlib>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>

#include "src/config.hpp"
#include "src/simulation.hpp"
#include "src/study.hpp"
#include "scratch.hpp"

using namespace grainlab;
namespace fs = std::filesystem;

namespace {
std::string write_tmp(const std::string& name, const std::string& text) {
  const fs::path p = test::scratch(name + ".yaml");
  std::ofstream(p) << text;
  return p.string();
}
// A shear job's run config as the study writes it (its sample file named sample.h5), parsed as the run parses it
RunConfig job_run_config(const Study& s, const StudyJob& j) {
  return parse_run_config(YAML::Load(shear_config(s, j, "sample.h5")), j.name);
}
std::string error_of(const std::string& path) {
  try {
    load_run_config(path);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}
const char* kMinimal = "stages:\n  - {type: isotropic}\n";
}  // namespace

TEST(Config, ShippedConfigsValidate) {
  int n = 0;
  for (auto& e : fs::recursive_directory_iterator(GRAINLAB_SOURCE_DIR "/configs")) {
    if (e.path().extension() != ".yaml") continue;
    SCOPED_TRACE(e.path().string());
    if (is_study_file(e.path().string())) EXPECT_NO_THROW(load_study(e.path().string()));
    else EXPECT_NO_THROW(load_run_config(e.path().string()));
    ++n;
  }
  EXPECT_GE(n, 1);
}

// A run's config.yaml (and checkpoint fingerprint) writes each number as the shortest text that reads back to the
// same double: 0.3, not 0.29999999999999999. Read back bitwise over random doubles of every magnitude; a '.'
// before every exponent, so that YAML 1.1 readers (PyYAML: a float needs the dot) read floats. Every shipped run
// config then resolves to a text that parses to the same resolved text (a resumed run compares exactly that).
TEST(Config, NumbersAreWrittenShortAndReadBackBitwise) {
  EXPECT_EQ(yaml_number(0.3), "0.3");
  EXPECT_EQ(yaml_number(190e3), "190000");
  EXPECT_EQ(yaml_number(100e6), "1.0e+08");
  EXPECT_EQ(yaml_number(2.5e-5), "2.5e-05");
  EXPECT_EQ(yaml_number(0), "0");
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> mant(1.0, 10.0);
  std::uniform_int_distribution<int> ex(-30, 30);
  for (int k = 0; k < 20000; ++k) {
    const double v = (k % 2 ? -1 : 1) * mant(rng) * std::pow(10.0, ex(rng));
    const std::string t = yaml_number(v);
    const double back = YAML::Load(t).as<double>();
    ASSERT_EQ(0, std::memcmp(&back, &v, sizeof v)) << t;
    if (t.find('e') != std::string::npos) {
      ASSERT_NE(t.find('.'), std::string::npos) << t;
    }
  }
  int n = 0;
  for (auto& e : fs::recursive_directory_iterator(GRAINLAB_SOURCE_DIR "/configs")) {
    if (e.path().extension() != ".yaml" || is_study_file(e.path().string())) continue;
    SCOPED_TRACE(e.path().string());
    const std::string text = resolved_config_yaml(load_run_config(e.path().string()));
    EXPECT_EQ(resolved_config_yaml(parse_run_config(YAML::Load(text), e.path().string())), text);
    EXPECT_EQ(text.find("999999"), std::string::npos) << text;
    ++n;
  }
  EXPECT_GE(n, 3);
}

// sample.D = 1 (p(r) ~ 1/r, uniform in ln r: Packing.PowerLawRadiiFollowTheirDistribution) is a law like any other
// (it was refused: the inverse CDF's general form divides by 1 - D); it reads back from the resolved config.
TEST(Config, DOfOneIsTheLogUniformLaw) {
  const RunConfig c =
      parse_run_config(YAML::Load("sample: {count: 50, D: 1}\nstages: [{type: isotropic}]\n"), "d1.yaml");
  EXPECT_EQ(c.packing.D, 1.0);
  const std::string text = resolved_config_yaml(c);
  EXPECT_EQ(resolved_config_yaml(parse_run_config(YAML::Load(text), "d1.yaml")), text);
  EXPECT_EQ(parse_run_config(YAML::Load(text), "d1.yaml").packing.D, 1.0);
}

// A grading's config reads back from the run's resolved config.yaml to the same curve and the same radii (a resumed
// run compares the resolved text; the radii are the sample), with r_min and r_max its end sieves' halves.
TEST(Config, AGradingReadsBackFromTheResolvedConfig) {
  const RunConfig c = load_run_config(write_tmp(
      "grading", std::string("sample: {count: 500, seed: 3, grading: {diameter: [0.425e-3, 0.6e-3, 1.18e-3], "
                             "passing: [0, 35, 100]}}\n") + kMinimal));
  EXPECT_EQ(c.packing.grading.diameter, (std::vector<Real>{0.425e-3, 0.6e-3, 1.18e-3}));
  EXPECT_EQ(c.packing.grading.passing, (std::vector<Real>{0, 35, 100}));
  EXPECT_EQ(c.packing.r_min, 0.425e-3 / 2);
  EXPECT_EQ(c.packing.r_max, 1.18e-3 / 2);
  const std::string text = resolved_config_yaml(c);
  EXPECT_NE(text.find("grading:\n    diameter: [0.000425, 6.0e-04, 0.00118]\n    passing: [0, 35, 100]"), std::string::npos)
      << text;
  EXPECT_EQ(text.find("r_min"), std::string::npos) << text;
  const RunConfig back = parse_run_config(YAML::Load(text), "config.yaml");
  EXPECT_EQ(resolved_config_yaml(back), text);
  EXPECT_EQ(packing_radii(back.packing), packing_radii(c.packing));
  // the plan names the curve's indices and the drawn sample's percent passing at each sieve
  const RunPlan plan = plan_run(c);
  EXPECT_NE(plan.sample.find("500 spheres drawn from sample.grading (3 sieves, 0.425 mm to 1.18 mm: D50 = "),
            std::string::npos) << plan.sample;
  EXPECT_NE(plan.sample.find("(asked 0 / 35 / 100)"), std::string::npos) << plan.sample;
  EXPECT_TRUE(plan.sample_warnings.empty() && plan.warnings.empty());
  // a draw that misses the curve is a warning of the sample's (cli_grading_plan's 300 spheres: 6.1 points at 0.8 mm)
  const RunPlan few = plan_run(load_run_config(write_tmp(
      "grading_few", std::string("sample: {count: 300, seed: 42, grading: {diameter: [0.4e-3, 0.6e-3, 0.8e-3, 1.0e-3, "
                                 "1.2e-3], passing: [0, 20, 55, 90, 100]}}\n") + kMinimal)));
  ASSERT_EQ(few.sample_warnings.size(), 1u);
  EXPECT_NE(few.sample_warnings[0].find("pass 61.1 % at 0.8 mm against the 55 % asked"), std::string::npos);
  EXPECT_TRUE(few.warnings.empty());
}

// A stress probe's direction (StageConfig::stress_direction) sets the linear path and the direction: cot(theta) / sqrt2,
// extension where sin(theta) < 0; 90 and 270 exactly the standard path (slope 0); 125.26 deg constant p' (slope -1/2
// to 1e-5, the angle's 5 digits). The resolved config gives the angle (not the slope) and its direction, and reads back
// to the same text.
TEST(Config, AStressDirectionSetsTheLinearPath) {
  const auto stage = [](const std::string& th) {
    const RunConfig c = load_run_config(write_tmp("sdir", "stages:\n  - {name: probe, type: triaxial, drainage: drained, "
                                                          "stress_direction: " + th + ", stress_increment: 1.0e4}\n"));
    return c;
  };
  for (const char* th : {"90", "270"}) {
    const RunConfig c = stage(th);
    EXPECT_EQ(*c.stages[0].lateral_slope, 0) << th;
    EXPECT_EQ(c.stages[0].extension, std::string(th) == "270");
  }
  EXPECT_NEAR(*stage("125.26439").stages[0].lateral_slope, -0.5, 1e-5);
  const RunConfig c = stage("300");
  EXPECT_NEAR(*c.stages[0].lateral_slope, std::cos(300 * M_PI / 180) / (std::sqrt(2.0) * std::sin(300 * M_PI / 180)), 1e-15);
  EXPECT_TRUE(c.stages[0].extension);
  const std::string text = resolved_config_yaml(c);
  EXPECT_NE(text.find("direction: extension"), std::string::npos) << text;
  EXPECT_NE(text.find("stress_direction: 300"), std::string::npos) << text;
  EXPECT_EQ(text.find("lateral_slope"), std::string::npos) << text;
  EXPECT_EQ(resolved_config_yaml(parse_run_config(YAML::Load(text), "config.yaml")), text);
}

// numerics.fines_mass_radius: read, written back only where set (a run without it resolves as every earlier build's),
// and the plan's account of it checked against the radii: the spheres under the radius, their share of the solid mass,
// the sample's mass factor, and the stable limit against SPEC §1's masses, (r_f / r_min)^1.5 without rolling (the
// lightest sphere against the same stiffest spring). A radius under every sphere is a warning: it scales nothing.
TEST(Config, TheFinesMassRadiusIsPlannedAndResolved) {
  const std::string sample = "sample: {count: 800, seed: 5, grading: {diameter: [0.2e-3, 1.8e-3], passing: [0, 100]}}\n";
  const RunConfig c = load_run_config(write_tmp("fines", sample + "numerics: {fines_mass_radius: 0.2e-3}\n" + kMinimal));
  EXPECT_EQ(c.engine.fines_mass_radius, 0.2e-3);
  const std::string text = resolved_config_yaml(c);
  EXPECT_NE(text.find("fines_mass_radius: 2.0e-04"), std::string::npos) << text;
  EXPECT_EQ(resolved_config_yaml(parse_run_config(YAML::Load(text), "config.yaml")), text);
  const RunConfig off = load_run_config(write_tmp("fines_off", sample + kMinimal));
  EXPECT_EQ(resolved_config_yaml(off).find("fines_mass_radius"), std::string::npos);
  const std::vector<Real> r = packing_radii(c.packing);
  long below = 0;
  double m_all = 0, m_below = 0, m_run = 0;
  for (Real ri : r) {
    const double m = double(ri) * ri * ri;
    m_all += m;
    m_run += std::max(0.2e-3, double(ri)) * std::max(0.2e-3, double(ri)) * std::max(0.2e-3, double(ri));
    if (ri < 0.2e-3) ++below, m_below += m;
  }
  const RunPlan plan = plan_run(c), spec = plan_run(off);
  EXPECT_TRUE(spec.fines.empty());
  ASSERT_GT(below, 0);
  char want[256];
  std::snprintf(want, sizeof(want), "%ld of %zu spheres (%.3g %% of the solid mass) weigh as a sphere of that radius, "
                "the sample's mass x %.3g", below, r.size(), 100 * m_below / m_all, m_run / m_all);
  EXPECT_NE(plan.fines.find(want), std::string::npos) << plan.fines << "\n" << want;
  const Real r_min = *std::min_element(r.begin(), r.end());
  EXPECT_NEAR(plan.dt_limit / spec.dt_limit, std::pow(0.2e-3 / r_min, 1.5), 1e-12);
  // (the 800 spheres miss the wide curve at its middle, a warning of their own: not counted here)
  const auto fines_warnings = [](const RunPlan& pl) {
    std::vector<std::string> w;
    for (const std::string& s : pl.sample_warnings)
      if (s.find("fines_mass_radius") != std::string::npos) w.push_back(s);
    return w;
  };
  EXPECT_TRUE(fines_warnings(plan).empty());
  const RunPlan none = plan_run(load_run_config(
      write_tmp("fines_none", sample + "numerics: {fines_mass_radius: 0.05e-3}\n" + kMinimal)));
  ASSERT_EQ(fines_warnings(none).size(), 1u);
  EXPECT_NE(fines_warnings(none)[0].find("numerics.fines_mass_radius = 5e-05 m is not above the smallest radius"),
            std::string::npos) << fines_warnings(none)[0];
  EXPECT_EQ(none.dt_limit, spec.dt_limit);
  // A shear's inertial number for the scaled fines: the smallest sphere at its scaled density rho s (r_f / r)^3,
  // I = rate 2 r sqrt(rho_eff / p'), against the quasi-static 1e-3 (perf/FINES_SCALING.md: biased above it).
  const std::string shear = "stages:\n  - {type: isotropic, pressure: 100e3}\n"
                            "  - {type: triaxial, drainage: drained, axial_strain_rate: 0.25}\n";
  const RunPlan sh = plan_run(load_run_config(
      write_tmp("fines_shear", "sample: {count: 800, seed: 5, density_scaling: 1000, grading: {diameter: [0.2e-3, "
                               "1.8e-3], passing: [0, 100]}}\nnumerics: {fines_mass_radius: 0.2e-3}\n" + shear)));
  ASSERT_EQ(sh.stages.size(), 2u);
  const double I_f = 0.25 * 2 * r_min * std::sqrt(2650 * 1000 * std::pow(0.2e-3 / r_min, 3) / 100e3);
  std::snprintf(want, sizeof(want), "the scaled fines' ~%.2g (the smallest sphere at its scaled mass)", I_f);
  EXPECT_NE(sh.stages[1].find(want), std::string::npos) << sh.stages[1] << "\n" << want;
  EXPECT_EQ(sh.stages[1].find("lower axial_strain_rate or numerics.fines_mass_radius"), std::string::npos);
  EXPECT_NEAR(sh.inertial_max, I_f, 1e-12 * I_f);  // (another order of the same products)
}

TEST(Config, DefaultsAreSpecReferenceValues) {
  const RunConfig c = load_run_config(write_tmp("min", kMinimal));
  EXPECT_EQ(c.engine.contact.E, 100e6);
  EXPECT_EQ(c.engine.contact.mu, 0.5);
  EXPECT_EQ(c.engine.contact.roll_arm, 0.05);
  EXPECT_EQ(c.packing.D, 3.63);
  EXPECT_EQ(c.density, 2650);
  EXPECT_EQ(c.engine.dt_factor, 0.2);
  EXPECT_EQ(c.engine.inner_skin, EngineParams{}.inner_skin);
  EXPECT_EQ(c.stages.at(0).pressure, 190e3);
}

// A path of a config (output.dir, sample.file) or study (base) is expanded as a shell would: a leading ~ is the home
// directory, $NAME and ${NAME} environment variables. `dir: ~/runs/a` made a directory named "~" in the working
// directory, `dir: $SCRATCH/a` one named "$SCRATCH".
TEST(Config, APathExpandsHomeAndVariablesLikeAShell) {
  const char* was = std::getenv("HOME");
  const std::string saved = was ? was : "";
  const std::string home = test::scratch("tilde_home").string();
  ::setenv("HOME", home.c_str(), 1);
  const RunConfig c = load_run_config(write_tmp("tilde", std::string("output: {dir: ~/runs/a}\n") + kMinimal));
  EXPECT_EQ(c.out_dir, home + "/runs/a");
  const RunConfig s = load_run_config(write_tmp("tilde_sample", "sample: {file: ~/s.h5}\n" + std::string(kMinimal)));
  EXPECT_EQ(s.sample_file, home + "/s.h5");
  EXPECT_EQ(expand_path("~", "f: k"), home);
  EXPECT_EQ(expand_path("a/~/b", "f: k"), "a/~/b") << "only a leading ~";
  EXPECT_EQ(expand_path("~root/x", "f: k"), std::string(::getpwnam("root")->pw_dir) + "/x");
  std::string e;
  try {
    expand_path("~no_such_user_x1/runs", "f.yaml: output.dir");
  } catch (const ConfigError& x) {
    e = x.what();
  }
  EXPECT_EQ(e, "f.yaml: output.dir = '~no_such_user_x1/runs': no user 'no_such_user_x1' whose home ~no_such_user_x1 is");
  ::setenv("GRAINLAB_TEST_SCRATCH", "/scratch/u", 1);
  EXPECT_EQ(expand_path("$GRAINLAB_TEST_SCRATCH/runs/${GRAINLAB_TEST_SCRATCH}x", "f: k"), "/scratch/u/runs//scratch/ux");
  EXPECT_EQ(load_run_config(write_tmp("dollar", std::string("output: {dir: $HOME/r}\n") + kMinimal)).out_dir,
            home + "/r");
  ::unsetenv("GRAINLAB_TEST_SCRATCH");
  for (const auto& [path, says] : std::vector<std::pair<std::string, std::string>>{
           {"$GRAINLAB_TEST_SCRATCH/a", "the environment variable GRAINLAB_TEST_SCRATCH is not set"},
           {"${GRAINLAB_TEST_SCRATCH", "a $ must start an environment variable, $NAME or ${NAME}"},
           {"a/$/b", "a $ must start an environment variable, $NAME or ${NAME}"},
           {"a/$1", "a $ must start an environment variable, $NAME or ${NAME}"}}) {
    std::string got;
    try {
      expand_path(path, "f.yaml: output.dir");
    } catch (const ConfigError& x) {
      got = x.what();
    }
    EXPECT_EQ(got, "f.yaml: output.dir = '" + path + "': " + says);
  }
  // the study's base: a home-relative path is not read beside the study file
  fs::create_directories(home);
  fs::copy_file(GRAINLAB_SOURCE_DIR "/configs/quick-study-base.yaml", home + "/base.yaml",
                fs::copy_options::overwrite_existing);
  EXPECT_EQ(load_study(write_tmp("tilde_study", "base: ~/base.yaml\naxes: {mu_r: [0]}\n")).base, home + "/base.yaml");
  if (was) ::setenv("HOME", saved.c_str(), 1);
  else ::unsetenv("HOME");
}

TEST(Config, OutOfRangeNamesFileKeyAndRange) {
  const std::string p = write_tmp("range", std::string("material: {E: -5}\n") + kMinimal);
  const std::string e = error_of(p);
  EXPECT_NE(e.find(p), std::string::npos) << e;
  EXPECT_NE(e.find("material.E"), std::string::npos) << e;
  EXPECT_NE(e.find("allowed range (0,"), std::string::npos) << e;
}

TEST(Config, RejectsBadInputClearly) {
  struct Case {
    const char* name;
    std::string text;
    const char* expect;
  };
  const std::vector<Case> cases = {
      {"typo", std::string("material: {mu_roll: 0.1}\n") + kMinimal, "material.mu_roll: unknown key"},
      {"type", std::string("sample: {count: many}\n") + kMinimal, "sample.count: must be a number"},
      {"nan", std::string("material: {mu: .nan}\n") + kMinimal, "material.mu"},
      {"int", std::string("sample: {count: 10.5}\n") + kMinimal, "must be an integer"},
      {"rmax", std::string("sample: {r_min: 1e-3, r_max: 1e-4}\n") + kMinimal, "sample.r_max"},
      {"stage", "stages:\n  - {type: shake}\n", "stages[0].type = 'shake' is not one of"},
      // a stage's name names its sample file and is a CSV field: a path, a comma, one name twice
      {"stage_path", "stages:\n  - {name: ../x, type: isotropic}\n",
       "stages[0].name = '../x': a stage name is 1 to 64 letters, digits"},
      {"stage_comma", "stages:\n  - {name: \"a,b\", type: isotropic}\n", "stages[0].name = 'a,b': a stage name"},
      {"stage_twice", "stages:\n  - {name: c, type: isotropic}\n  - {name: d}\n  - {name: c, type: isotropic}\n",
       "stages[2].name = 'c' is stages[0]'s name too"},
      {"stage_default_twice", "stages:\n  - {type: isotropic}\n  - {name: stage0, type: isotropic}\n",
       "stages[1].name = 'stage0' is stages[0]'s name too"},
      {"nostages", "material: {E: 1e8}\n", "stages: must be a non-empty list"},
      // a value left out is not the default (a blank section is: `material:` alone)
      {"no_value", "material:\nsample:\n  count:\n  seed: 3\nstages: [{type: isotropic}]\n",
       "sample.count: has no value: give one, or leave the key out for its default"},
      {"no_value_stage", "stages:\n  - {type: isotropic, pressure: ~}\n",
       "stages[0].pressure: has no value: give one, or leave the key out for its default"},
      {"empty", "", "the file is empty"},
      {"yaml", "stages: [\n", "not valid YAML"},
      // yaml-cpp's own words for a tab in the indentation do not name it
      {"tab_indent", "sample:\n\tcount: 300\nstages: [{type: isotropic}]\n",
       "(a tab in the indentation of line 2: YAML indents with spaces only)"},
      {"notmap", "- 1\n- 2\n", "must be a mapping"},
      // a key twice in one mapping: yaml-cpp would take the first silently; the lines say where (one flow line, or two)
      {"dup_flow", std::string("sample: {count: 100, seed: 3, count: 200}\n") + kMinimal,
       "sample.count: given twice (on line 1); a key may appear once in its mapping"},
      {"dup_block", "sample:\n  count: 100\n  count: 200\nstages:\n  - {type: isotropic}\n",
       "sample.count: given twice (lines 2 and 3)"},
      {"dup_stage", "stages:\n  - {type: isotropic}\n  - {type: triaxial, mu: 0.3, mu: 0.4}\n",
       "stages[1].mu: given twice (on line 3)"},
      {"dup_top", std::string("material: {mu: 0.3}\nmaterial: {mu: 0.4}\n") + kMinimal,
       "material: given twice (lines 1 and 2)"},
      {"dtfactor", std::string("numerics: {dt_factor: 1.5}\n") + kMinimal, "numerics.dt_factor"},
      {"inner1", std::string("numerics: {inner_skin: 1}\n") + kMinimal, "numerics.inner_skin = 1 is outside the allowed range [0, 1)"},
      {"inner-", std::string("numerics: {inner_skin: -0.1}\n") + kMinimal, "numerics.inner_skin"},
      // cyclic stages: exactly one amplitude, a strain amplitude below the end strain, whole cycles; their keys
      // mean nothing to a monotonic stage
      {"cyc_none", "stages:\n  - {type: cyclic, cycles: 3}\n",
       "stages[0].q_amplitude: a cyclic stage reverses at exactly one of q_amplitude (Pa, > 0: stress reversal), csr (> "
       "0: stress reversal at q_0 +- 2 csr p'_c) or strain_amplitude (> 0: strain reversal); this one gives neither"},
      {"cyc_both", "stages:\n  - {type: cyclic, q_amplitude: 3e4, strain_amplitude: 0.01}\n",
       "this one gives q_amplitude and strain_amplitude"},
      {"cyc_csr_q", "stages:\n  - {type: cyclic, q_amplitude: 3e4, csr: 0.1}\n", "this one gives q_amplitude and csr"},
      {"cyc_csr_range", "stages:\n  - {type: cyclic, csr: 11}\n", "stages[0].csr = 11 is outside the allowed range [0, 10]"},
      {"csr_tri", "stages:\n  - {type: triaxial, csr: 0.1}\n", "stages[0].csr: unknown key"},
      {"cyc_amp", "stages:\n  - {type: cyclic, strain_amplitude: 0.05, max_axial_strain: 0.05}\n",
       "stages[0].strain_amplitude = 0.05 must be below max_axial_strain = 0.05"},
      {"cyc_n", "stages:\n  - {type: cyclic, q_amplitude: 3e4, cycles: 0}\n",
       "stages[0].cycles = 0 is outside the allowed range [1, 1e+06]"},
      {"cyc_frac", "stages:\n  - {type: cyclic, q_amplitude: 3e4, cycles: 1.5}\n", "stages[0].cycles = 1.5 must be an integer"},
      {"cyc_tri", "stages:\n  - {type: triaxial, cycles: 2}\n", "stages[0].cycles: unknown key"},
      // triaxial extension: a direction of a triaxial stage only (a cyclic stage goes both ways already)
      {"dir_bad", "stages:\n  - {type: triaxial, direction: sideways}\n", "stages[0].direction"},
      {"dir_cyc", "stages:\n  - {type: cyclic, q_amplitude: 3e4, direction: extension}\n", "stages[0].direction: unknown key"},
      {"dir_iso", "stages:\n  - {type: isotropic, direction: extension}\n", "stages[0].direction: unknown key"},
      // true triaxial: b in [0, 1], on a drained compression stage (it sets the x walls' servo target)
      {"b_big", "stages:\n  - {type: triaxial, drainage: drained, b: 1.5}\n",
       "stages[0].b = 1.5 is outside the allowed range [0, 1]"},
      {"b_und", "stages:\n  - {type: triaxial, b: 0.5}\n",
       "stages[0].b = 0.5 needs a drained compression stage (here undrained)"},
      {"b_ext", "stages:\n  - {type: triaxial, drainage: drained, direction: extension, b: 0.5}\n",
       "stages[0].b = 0.5 needs a drained compression stage (here direction: extension)"},
      {"b_cyc", "stages:\n  - {type: cyclic, q_amplitude: 3e4, b: 0.5}\n", "stages[0].b: unknown key"},
      // the constant-p' path: a drained triaxial stage's (undrained, the walls keep the volume)
      {"path_und", "stages:\n  - {type: triaxial, stress_path: constant_p}\n",
       "stages[0].stress_path = constant_p needs a drained stage"},
      {"path_bad", "stages:\n  - {type: triaxial, drainage: drained, stress_path: constant_q}\n", "stages[0].stress_path"},
      {"path_cyc", "stages:\n  - {type: cyclic, q_amplitude: 3e4, stress_path: constant_p}\n",
       "stages[0].stress_path: unknown key"},
      // plane strain: a drained or undrained stage, its x walls held (b and a K path would set them)
      {"ps_oed", "stages:\n  - {type: triaxial, drainage: oedometric, stress_path: plane_strain}\n",
       "stages[0].stress_path = plane_strain needs a drained or undrained stage (here oedometric, which holds both "
       "lateral axes): the x walls held, the y walls at their start's stress (drained) or at constant volume "
       "(undrained)"},
      {"ps_b", "stages:\n  - {type: triaxial, drainage: drained, b: 0.5, stress_path: plane_strain}\n",
       "stages[0].stress_path = plane_strain holds the x walls, and b = 0.5 would servo them to sigma_3 + b (sigma_z - "
       "sigma_3): give one of them (plane strain's b is the test's result)"},
      {"ps_k", "stages:\n  - {type: triaxial, drainage: drained, stress_path: plane_strain, k_ratio: 0.5}\n",
       "stages[0].k_ratio = 0.5 and stress_path: plane_strain both set the lateral stresses: give one of them"},
      {"ps_slope", "stages:\n  - {type: triaxial, drainage: drained, stress_path: plane_strain, lateral_slope: 1}\n",
       "stages[0].lateral_slope = 1 and stress_path: plane_strain both set the lateral stresses"},
      // the oedometric (K0) test: lateral walls held; b and constant_p set lateral stresses. The cyclic oedometer
      // reverses at sigma_v,0 +- sigma_v_amplitude (or a strain), a triaxial cycle at q: each refuses the other's
      {"oed_cyc", "stages:\n  - {type: cyclic, q_amplitude: 3e4, drainage: oedometric}\n",
       "stages[0].q_amplitude: reverses a triaxial cycle at a deviator stress, and this stage is oedometric (its lateral "
       "walls held): an oedometric cycle reverses at sigma_v_amplitude (Pa, > 0: sigma_v,0 +- A) or strain_amplitude"},
      {"oed_cyc_csr", "stages:\n  - {type: cyclic, csr: 0.1, drainage: oedometric}\n",
       "stages[0].csr: reverses a triaxial cycle at a deviator stress"},
      {"oed_cyc_sv_tri", "stages:\n  - {type: cyclic, sigma_v_amplitude: 3e4, drainage: drained}\n",
       "stages[0].sigma_v_amplitude = 30000 reverses an oedometric cycle, and this stage is drained: give drainage: "
       "oedometric, or q_amplitude / csr for a triaxial cycle"},
      {"oed_cyc_none", "stages:\n  - {type: cyclic, drainage: oedometric}\n",
       "stages[0].sigma_v_amplitude: an oedometric cyclic stage reverses at exactly one of sigma_v_amplitude (Pa, > 0: "
       "sigma_v,0 +- A) or strain_amplitude (> 0: strain reversal); this one gives neither"},
      {"oed_cyc_both", "stages:\n  - {type: cyclic, drainage: oedometric, sigma_v_amplitude: 3e4, strain_amplitude: "
       "0.001}\n", "this one gives strain_amplitude and sigma_v_amplitude"},
      {"oed_cyc_sv_tri_key", "stages:\n  - {type: triaxial, drainage: oedometric, sigma_v_amplitude: 3e4}\n",
       "stages[0].sigma_v_amplitude: unknown key"},
      // sigma_v,0 - A must stay a compression where the stage before gives sigma_v,0
      {"oed_cyc_deep", "stages:\n  - {type: isotropic, pressure: 1e5}\n  - {type: triaxial, drainage: oedometric, "
       "sigma_v: 2e5}\n  - {type: cyclic, drainage: oedometric, sigma_v_amplitude: 2e5}\n",
       "stages[2].sigma_v_amplitude = 200000 must be below the vertical stress the cycles start from, 200000 Pa "
       "(stages[1]'s sigma_v): sigma_v,0 - A would be no compression"},
      {"oed_cyc_deep_iso", "stages:\n  - {type: isotropic, pressure: 1e5}\n  - {type: cyclic, drainage: oedometric, "
       "sigma_v_amplitude: 1.5e5}\n", "(stages[0]'s pressure)"},
      {"oed_b", "stages:\n  - {type: triaxial, drainage: oedometric, b: 0.5}\n",
       "stages[0].b = 0.5 needs a drained compression stage (here oedometric)"},
      {"oed_path", "stages:\n  - {type: triaxial, drainage: oedometric, stress_path: constant_p}\n",
       "stages[0].stress_path = constant_p needs a drained stage (here oedometric"},
      {"drain_bad", "stages:\n  - {type: triaxial, drainage: wet}\n", "stages[0].drainage"},
      // an oedometer's stress ends: an oedometric stage's or a K path's; ocr unloads from an earlier stage's sigma_v,max
      {"sv_drained", "stages:\n  - {type: triaxial, drainage: drained, sigma_v: 3e5}\n",
       "stages[0].sigma_v: ends an oedometric stage, a K path (k_ratio) or a linear path (lateral_slope) at a vertical "
       "stress, and this stage is drained (give drainage: oedometric, or k_ratio, or lateral_slope, or leave sigma_v out "
       "and end the stage at max_axial_strain)"},
      // a K path: drained, (0, 1], the lateral stresses its own
      {"k_undrained", "stages:\n  - {type: triaxial, k_ratio: 0.7}\n",
       "stages[0].k_ratio = 0.7 needs a drained stage (here undrained: the walls keep the volume or their place)"},
      {"k_b", "stages:\n  - {type: triaxial, drainage: drained, b: 0.5, k_ratio: 0.7}\n",
       "stages[0].k_ratio = 0.7 and b = 0.5 both set the lateral stresses: give one of them"},
      {"k_cp", "stages:\n  - {type: triaxial, drainage: drained, stress_path: constant_p, k_ratio: 0.7}\n",
       "stages[0].k_ratio = 0.7 and stress_path: constant_p both set the lateral stresses: give one of them"},
      {"k_big", "stages:\n  - {type: triaxial, drainage: drained, k_ratio: 1.5}\n",
       "stages[0].k_ratio = 1.5 is outside the allowed range (0, 1]"},
      {"k_cyc", "stages:\n  - {type: cyclic, drainage: drained, q_amplitude: 3e4, k_ratio: 0.7}\n",
       "stages[0].k_ratio: unknown key"},
      // a linear path: drained, [-5, 5], the lateral stresses its own (b sets sigma_2 on it)
      {"ls_undrained", "stages:\n  - {type: triaxial, lateral_slope: 0.5}\n",
       "stages[0].lateral_slope = 0.5 needs a drained stage (here undrained: the walls keep the volume or their place)"},
      {"ls_oed", "stages:\n  - {type: triaxial, drainage: oedometric, lateral_slope: 0.5}\n",
       "stages[0].lateral_slope = 0.5 needs a drained stage (here oedometric"},
      {"ls_k", "stages:\n  - {type: triaxial, drainage: drained, k_ratio: 0.7, lateral_slope: 0.5}\n",
       "stages[0].lateral_slope = 0.5 and k_ratio = 0.7 both set the lateral stresses: give one of them"},
      {"ls_cp", "stages:\n  - {type: triaxial, drainage: drained, stress_path: constant_p, lateral_slope: 0.5}\n",
       "stages[0].lateral_slope = 0.5 and stress_path: constant_p both set the lateral stresses: give one of them "
       "(constant p' is lateral_slope: -0.5)"},
      {"ls_big", "stages:\n  - {type: triaxial, drainage: drained, lateral_slope: -6}\n",
       "stages[0].lateral_slope = -6 is outside the allowed range [-5, 5]"},
      {"ls_cyc", "stages:\n  - {type: cyclic, drainage: drained, q_amplitude: 3e4, lateral_slope: 0.5}\n",
       "stages[0].lateral_slope: unknown key"},
      // a rest (axial_strain_rate 0): a triaxial stage's, without a path or a stress end
      {"rest_len", "stages:\n  - {type: triaxial, drainage: drained, axial_strain_rate: 0}\n",
       "stages[0].axial_strain_rate = 0 is a rest (the axial walls held, the lateral ones as the drainage holds them, "
       "for max_steps steps): give max_steps, its length"},
      {"rest_q", "stages:\n  - {type: triaxial, drainage: drained, axial_strain_rate: 0, max_steps: 10, q: 1e4}\n",
       "stages[0].axial_strain_rate = 0 is a rest (the axial walls held, the lateral ones as the drainage holds them, for "
       "max_steps steps), and q moves the stress or ends the stage at one: leave q out, or give the stage a rate"},
      {"rest_k", "stages:\n  - {type: triaxial, drainage: drained, axial_strain_rate: 0, max_steps: 10, k_ratio: 0.5}\n",
       "stages[0].axial_strain_rate = 0 is a rest"},
      {"rest_cyc", "stages:\n  - {type: cyclic, q_amplitude: 1e4, axial_strain_rate: 0}\n",
       "stages[0].axial_strain_rate = 0 is outside the allowed range (0, 1e+06]"},
      // a probe's direction: reachable by the axial walls, one path, its direction its own, axisymmetric, drained
      {"sd_lateral", "stages:\n  - {type: triaxial, drainage: drained, stress_direction: 175}\n",
       "stages[0].stress_direction = 175 is within 8.05 degrees of pure lateral loading or unloading (0, 180), which the "
       "strain-controlled axial walls cannot follow (dsigma_a = 0 there): give a direction in [8.05, 171.95] or "
       "[188.05, 351.95]"},
      {"sd_range", "stages:\n  - {type: triaxial, drainage: drained, stress_direction: 400}\n",
       "stages[0].stress_direction = 400 is outside the allowed range [0, 360]"},
      {"sd_ls", "stages:\n  - {type: triaxial, drainage: drained, stress_direction: 90, lateral_slope: 0.5}\n",
       "stages[0].stress_direction = 90 and lateral_slope = 0.5 both set the path: give one of them"},
      {"sd_dir", "stages:\n  - {type: triaxial, drainage: drained, stress_direction: 270, direction: compression}\n",
       "stages[0].stress_direction = 270 unloads the axial walls where sin(theta) < 0 and loads them elsewhere, and "
       "direction = compression says otherwise: leave direction out"},
      {"sd_b", "stages:\n  - {type: triaxial, drainage: drained, stress_direction: 90, b: 0.5}\n",
       "stages[0].stress_direction = 90 is a direction of the Rendulic plane (sigma_x = sigma_y), and b = 0.5 parts "
       "sigma_x from sigma_y: give one of them"},
      {"sd_undrained", "stages:\n  - {type: triaxial, stress_direction: 90}\n",
       "stages[0].stress_direction = 90 needs a drained stage (here undrained"},
      {"sv_zero", "stages:\n  - {type: triaxial, drainage: oedometric, sigma_v: 0}\n",
       "stages[0].sigma_v = 0 is outside the allowed range (0, 1e+10]"},
      {"sv_cyc", "stages:\n  - {type: cyclic, q_amplitude: 3e4, sigma_v: 3e5}\n", "stages[0].sigma_v: unknown key"},
      {"ocr_one", "stages:\n  - {type: isotropic}\n  - {type: triaxial, drainage: oedometric, direction: extension, ocr: 1}\n",
       "stages[1].ocr = 1 is outside the allowed range (1, 1e+06]"},
      {"ocr_load", "stages:\n  - {type: isotropic}\n  - {type: triaxial, drainage: oedometric, ocr: 2}\n",
       "stages[1].ocr = 2 ends an unloading at sigma_v,max / ocr, and this stage loads (direction: compression)"},
      {"ocr_first", "stages:\n  - {type: triaxial, drainage: oedometric, direction: extension, ocr: 2}\n",
       "stages[0].ocr = 2 unloads to sigma_v,max / ocr, sigma_v,max the largest of the stages before, and this is the "
       "first stage: give sigma_v"},
      {"ocr_sv", "stages:\n  - {type: isotropic}\n  - {type: triaxial, drainage: oedometric, direction: extension, "
       "ocr: 2, sigma_v: 1e5}\n", "stages[1].sigma_v = 100000 and ocr = 2 both end the stage at a stress: give one of them"},
      // a deviator end: triaxial stages of any drainage, one stress end at most, |q| <= 1e10
      {"q_cyc", "stages:\n  - {type: cyclic, q_amplitude: 3e4, q: 1e5}\n", "stages[0].q: unknown key"},
      {"q_iso", "stages:\n  - {type: isotropic, q: 1e5}\n", "stages[0].q: unknown key"},
      {"q_big", "stages:\n  - {type: triaxial, drainage: drained, q: -2e10}\n",
       "stages[0].q = -2e10 is outside the allowed range [-1e+10, 1e+10]"},
      {"q_sv", "stages:\n  - {type: triaxial, drainage: oedometric, sigma_v: 3e5, q: 1e5}\n",
       "stages[0].sigma_v = 300000 and q = 100000 both end the stage at a stress: give one of them"},
      {"eta_q", "stages:\n  - {type: triaxial, drainage: undrained, q: 1e5, stress_ratio: 0.5}\n",
       "stages[0].q = 100000 and stress_ratio = 0.5 both end the stage at a stress: give one of them"},
      {"eta_big", "stages:\n  - {type: triaxial, drainage: drained, stress_ratio: 3.5}\n",
       "stages[0].stress_ratio = 3.5 is outside the allowed range [-1.5, 3]"},
      // a stress probe's end: > 0, one stress end
      {"ds_zero", "stages:\n  - {type: triaxial, drainage: drained, stress_increment: 0}\n",
       "stages[0].stress_increment = 0 is outside the allowed range (0, 1e+10]"},
      {"ds_q", "stages:\n  - {type: triaxial, drainage: drained, q: 1e5, stress_increment: 1e4}\n",
       "stages[0].q = 100000 and stress_increment = 10000 both end the stage at a stress: give one of them"},
      {"q_null", "stages:\n  - {type: triaxial, drainage: drained, q: }\n",
       "stages[0].q: has no value: give one, or leave the key out for its default"},
      // the servo's integral action: [0, 0.5] (WallControl::integral: stable below 1 on an ideal wall)
      {"ki_big", "stages:\n  - {type: triaxial, drainage: drained, servo_integral: 0.8}\n",
       "stages[0].servo_integral = 0.8 is outside the allowed range [0, 0.5]"},
      {"ki_neg", "stages:\n  - {type: isotropic, servo_integral: -0.1}\n", "stages[0].servo_integral"},
      // liquefaction criteria: r_u in (0, 1]; a given double amplitude must be reachable below 2 max_axial_strain
      {"liq_ru0", "stages:\n  - {type: cyclic, q_amplitude: 3e4, liquefaction_ru: 0}\n",
       "stages[0].liquefaction_ru = 0 is outside the allowed range (0, 1]"},
      {"liq_ru", "stages:\n  - {type: cyclic, q_amplitude: 3e4, liquefaction_ru: 1.2}\n",
       "stages[0].liquefaction_ru = 1.2 is outside the allowed range (0, 1]"},
      {"liq_da", "stages:\n  - {type: cyclic, q_amplitude: 3e4, max_axial_strain: 0.02, liquefaction_da_strain: 0.04}\n",
       "stages[0].liquefaction_da_strain = 0.04 must be below 2 max_axial_strain = 0.04"},
      {"liq_tri", "stages:\n  - {type: triaxial, liquefaction_ru: 0.9}\n", "stages[0].liquefaction_ru: unknown key"},
      // a grading curve: sieves from the finest up, percent passing from 0 to 100, one value a sieve; it gives the
      // sizes, so D, r_min and r_max are refused beside it (and it beside sample.file)
      {"grad_D", std::string("sample: {D: 3, grading: {diameter: [1e-3, 2e-3], passing: [0, 100]}}\n") + kMinimal,
       "sample.D: cannot be combined with sample.grading (the curve gives the sizes)"},
      {"grad_rmax", std::string("sample: {r_max: 1e-3, grading: {diameter: [1e-3, 2e-3], passing: [0, 100]}}\n") + kMinimal,
       "sample.r_max: cannot be combined with sample.grading"},
      {"grad_order", std::string("sample: {grading: {diameter: [1e-3, 3e-3, 2e-3], passing: [0, 50, 100]}}\n") + kMinimal,
       "sample.grading.diameter[2] = 0.002 m must be larger than the diameter before it, 0.003 m"},
      {"grad_down", std::string("sample: {grading: {diameter: [1e-3, 2e-3, 3e-3], passing: [0, 60, 50]}}\n") + kMinimal,
       "sample.grading.passing[2] = 50 % is below the 60 % before it"},
      {"grad_start", std::string("sample: {grading: {diameter: [1e-3, 2e-3], passing: [10, 100]}}\n") + kMinimal,
       "sample.grading.passing[0] = 10 % must be 0: the curve starts at the smallest sphere"},
      {"grad_end", std::string("sample: {grading: {diameter: [1e-3, 2e-3], passing: [0, 95]}}\n") + kMinimal,
       "sample.grading.passing[1] = 95 % must be 100: the curve ends at the largest sphere (add a sieve above it where "
       "the passing is 100)"},
      {"grad_fraction", std::string("sample: {grading: {diameter: [1e-3, 2e-3], passing: [0, 1]}}\n") + kMinimal,
       "sample.grading.passing[1] = 1 % must be 100: the curve ends at the largest sphere (percent, not a fraction"},
      {"grad_count", std::string("sample: {grading: {diameter: [1e-3, 2e-3, 3e-3], passing: [0, 100]}}\n") + kMinimal,
       "sample.grading.passing: has 2 values for the 3 of sample.grading.diameter: one a sieve"},
      {"grad_one", std::string("sample: {grading: {diameter: [1e-3], passing: [100]}}\n") + kMinimal,
       "sample.grading.diameter: must be a list of 2 to 1000 numbers (allowed range (0, 2]); it has 1"},
      {"grad_scalar", std::string("sample: {grading: {diameter: 1e-3, passing: [0, 100]}}\n") + kMinimal,
       "sample.grading.diameter: must be a list of 2 to 1000 numbers"},
      {"grad_elem", std::string("sample: {grading: {diameter: [1e-3, big], passing: [0, 100]}}\n") + kMinimal,
       "sample.grading.diameter[1]: must be a number (allowed range (0, 2])"},
      {"grad_pct", std::string("sample: {grading: {diameter: [1e-3, 2e-3], passing: [0, 101]}}\n") + kMinimal,
       "sample.grading.passing[1] = 101 is outside the allowed range [0, 100]"},
      {"grad_missing", std::string("sample: {grading: {diameter: [1e-3, 2e-3]}}\n") + kMinimal,
       "sample.grading.passing: is required here"},
      {"grad_key", std::string("sample: {grading: {diameter: [1e-3, 2e-3], passing: [0, 100], by: mass}}\n") + kMinimal,
       "sample.grading.by: unknown key"},
      {"grad_file", std::string("sample: {file: x.h5, grading: {diameter: [1e-3, 2e-3], passing: [0, 100]}}\n") + kMinimal,
       "sample.grading: cannot be combined with sample.file"},
  };
  for (const Case& c : cases) {
    const std::string e = error_of(write_tmp(c.name, c.text));
    EXPECT_NE(e.find(c.expect), std::string::npos) << c.name << ": got '" << e << "'";
    EXPECT_EQ(e.find('\n'), std::string::npos) << c.name << ": error must be one line";
  }
  EXPECT_NE(error_of("/nonexistent/grainlab.yaml").find("cannot open the file for reading (No such file or directory)"),
            std::string::npos);
  // A directory, a pipe and a device, each named: the directory failed at its first read in the C++ library's words
  // with no file name, a pipe's second read (the command's, after the check of which command the file is for) found
  // it empty, and /dev/zero was read until memory ran out.
  const fs::path dir = test::scratch("a_dir.yaml"), fifo = test::scratch("a_fifo.yaml");
  fs::create_directories(dir);
  fs::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0) << std::strerror(errno);
  EXPECT_EQ(error_of(dir.string()), dir.string() + ": is a directory, not a config file");
  for (const std::string& p : {fifo.string(), std::string("/dev/zero")}) {
    const std::string e = error_of(p);  // refused before the open: a FIFO's open would wait for a writer
    EXPECT_EQ(e.rfind(p + ": not a regular file (a pipe or a device?)", 0), 0u) << e;
    EXPECT_FALSE(is_run_config_file(p)) << p;
  }
}

// The 4 MiB limit on a config file is exact, whatever the read's block size (the text is read in 64 KiB blocks, at
// most one byte past the limit): a config of 4 MiB loads, one byte more is refused by name; a size between blocks
// reads whole.
TEST(Config, AConfigOfTheSizeLimitLoadsAndOneByteMoreIsRefused) {
  constexpr size_t kLimit = size_t(4) << 20;  // load_yaml_screened's kMaxBytes
  const auto padded = [](size_t bytes) {      // kMinimal, then a comment line that brings the file to `bytes`
    std::string t = std::string(kMinimal) + "# ";
    t += std::string(bytes - t.size() - 1, 'x') + "\n";
    return t;
  };
  for (const size_t n : {kLimit, kLimit - 1, kLimit - (size_t(1) << 16), size_t(3 << 20) + 12345}) {
    const std::string p = write_tmp("limit_" + std::to_string(n), padded(n));
    ASSERT_EQ(fs::file_size(p), n);
    EXPECT_EQ(error_of(p), "") << n << " bytes";
  }
  const std::string over = write_tmp("limit_over", padded(kLimit + 1));
  EXPECT_EQ(error_of(over), over + ": larger than 4 MiB: not a grainlab config");
  // the byte past the limit is a newline after the comment: a read that stopped at the limit would load it
  const std::string just_over = write_tmp("limit_newline", padded(kLimit) + "\n");
  EXPECT_EQ(error_of(just_over), just_over + ": larger than 4 MiB: not a grainlab config");
}

// Studies: the axes are checked as values, and every job's config is checked as its run would check it, at load
// (so `grainlab validate` catches it); a seed of 0 on an axis is the seed 0, not "the base's seed".
namespace {
// The error of loading a study file of this text ("" where it loads).
std::string error(const std::string& name, const std::string& text) {
  try {
    load_study(write_tmp(name, text));
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}
// Each study text must fail to load with a one-line error that contains `expect`.
struct StudyErrorCase {
  const char* name;
  std::string text, expect;
};
void expect_study_errors(const std::vector<StudyErrorCase>& cases) {
  for (const StudyErrorCase& c : cases) {
    const std::string e = error(c.name, c.text);
    EXPECT_NE(e.find(c.expect), std::string::npos) << c.name << ": got '" << e << "'";
    EXPECT_EQ(e.find('\n'), std::string::npos) << c.name << ": error must be one line";
  }
}
std::string study_error(const std::string& name, const std::string& axes) {
  return error(name, "base: " GRAINLAB_SOURCE_DIR "/configs/quick-study-base.yaml\n" + axes);
}
}  // namespace

TEST(Config, StudyAxesAndJobsAreChecked) {
  struct Case {
    const char* name;
    const char* axes;
    const char* expect;
  };
  const Case cases[] = {
      {"study_empty", "axes: {mu_r: []}\n", "axes.mu_r: an empty list"},
      {"study_drain_empty", "axes: {drainage: []}\n", "axes.drainage: an empty list"},
      {"study_drain_bad", "axes: {drainage: [drainded]}\n", "axes.drainage: 'drainded' is not drained, undrained or oedometric"},
      {"study_extra_drain", "extra: [{drainage: wet}]\n", "extra[0].drainage: 'wet' is not drained, undrained or oedometric"},
      {"study_frac", "axes: {count: [2.5]}\n", "axes.count: values must be whole numbers"},
      {"study_zero", "axes: {count: [0]}\n", "axes.count: values must be in [1, 1e8]"},
      {"study_extra", "extra: [{seed: 1.5}]\n", "extra[0].seed: values must be whole numbers"},
      {"study_p0", "axes: {p0: [0, 100e3]}\n", "axes.p0: values must be > 0 (Pa)"},
      {"study_close", "axes: {mu_r: [0.1, 0.10000001]}\n",
       "axes: two values of mu_r, e0, p0, E or a preparation stage's axis agree to 6 significant"},
      // a value listed twice made one job, silently (the grid smaller than it reads)
      {"study_twice", "axes: {mu_r: [0.3, 0.1, 0.30]}\n", "axes.mu_r: 0.3 is listed twice (values 1 and 3): an axis lists "
                                                          "each value once"},
      {"study_twice_word", "axes: {drainage: [drained, drained]}\n", "axes.drainage: 'drained' is listed twice (values 1 "
                                                                     "and 2)"},
      // Valid on the axis (>= 0), outside the run config's [0, 10]: found in the job's config.
      {"study_job", "axes: {mu_r: [50]}\n", "(job sample_mur50_ebase_pbase_s11_n5000): material.mu_r = 50 is outside"},
      // How the report takes its peaks (Study::peak_window, peak_max_ke).
      {"study_pk_win", "peak: {window: 0.3}\n", "peak.window: must be in [0, 0.2] (axial strain)"},
      {"study_pk_win_neg", "peak: {window: -0.01}\n", "peak.window: must be in [0, 0.2] (axial strain)"},
      {"study_pk_zero", "peak: {max_ke_ratio: 0}\n", "peak.max_ke_ratio: must be in (0, 10] (kinetic / elastic"},
      {"study_pk_big", "peak: {max_ke_ratio: 11}\n", "peak.max_ke_ratio: must be in (0, 10]"},
      {"study_pk_word", "peak: {max_ke_ratio: high}\n", "peak.max_ke_ratio: must be a number in (0, 10]"},
      {"study_pk_key", "peak: {width: 0.1}\n", "peak.width: unknown key (known: window, max_ke_ratio)"},
      {"study_pk_map", "peak: 0.1\n", "peak: must be a mapping"},
      {"study_dup", "axes: {mu_r: [0.1], mu_r: [0.3]}\n", "axes.mu_r: given twice (on line 2)"},
      {"study_top", "peaks: {window: 0.01}\n", "peaks: unknown key (known: base, axes, extra, critical_state, peak)"},
  };
  for (const Case& c : cases) {
    const std::string e = study_error(c.name, c.axes);
    EXPECT_NE(e.find(c.expect), std::string::npos) << c.name << ": got '" << e << "'";
    EXPECT_EQ(e.find('\n'), std::string::npos) << c.name << ": error must be one line";
  }
  // a base with no value read as the file "null"; a list, as a conversion error
  for (const char* base : {"", "~", "[a, b]"}) {
    const std::string e = error("study_base", std::string("base: ") + base + "\naxes: {mu_r: [0]}\n");
    EXPECT_NE(e.find("base: must be the path of a run config"), std::string::npos) << base << ": got '" << e << "'";
  }
}

// How the report takes its peaks: single rows and every row unless the study's `peak` block says otherwise. A study
// of a base alone (no axes: the base's own test, once) loads: it used to fail with "axes.mu_r: must be a number", an
// absent axes block reading as a null value on every axis.
TEST(Config, StudyOfAPipeOrWithAPipeAsBaseIsNamed) {
  const fs::path fifo = test::scratch("study_fifo.yaml");
  fs::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0) << std::strerror(errno);
  const std::string e = error("study_pipe_base", "base: " + fifo.string() + "\n");
  EXPECT_NE(e.find(fifo.string() + ": not a regular file"), std::string::npos) << e;
  EXPECT_FALSE(is_study_file(fifo.string()));
}

TEST(Config, StudyPeakSettingsDefaultAndAreRead) {
  const std::string base = "base: " GRAINLAB_SOURCE_DIR "/configs/quick-study-base.yaml\n";
  const Study alone = load_study(write_tmp("study_pk_default", base));
  EXPECT_EQ(alone.peak_window, 0.0);
  EXPECT_EQ(alone.peak_max_ke, 0.0);
  EXPECT_EQ(alone.samples.size(), 1u);
  EXPECT_EQ(alone.shears.size(), 1u);
  const Study set = load_study(write_tmp("study_pk_set", base + "peak: {window: 0.02, max_ke_ratio: 0.05}\n"));
  EXPECT_EQ(set.peak_window, 0.02);
  EXPECT_EQ(set.peak_max_ke, 0.05);
}

// Cyclic studies: the csr axis sets each cyclic job's q_amplitude to 2 csr p'_0 (the p0 axis, else the base's
// consolidation pressure), names the job by it, and shares the sample between amplitudes; csr needs a base with a
// stress-reversal cyclic stage, and values > 0.
TEST(Config, StudyCsrAxisSetsTheCyclicAmplitude) {
  const std::string base = write_tmp("study_cyclic_base",
                                     "sample: {count: 300}\nstages:\n  - {name: consolidate, type: isotropic, pressure: 2.0e5}\n"
                                     "  - {name: shake, type: cyclic, q_amplitude: 3e4, cycles: 5}\n");
  const Study s = load_study(write_tmp("study_cyclic", "base: " + base + "\naxes: {csr: [0.1, 0.25], p0: [1.0e5, 2.0e5]}\n"));
  ASSERT_EQ(s.samples.size(), 2u);
  ASSERT_EQ(s.shears.size(), 4u);
  for (const StudyJob& j : s.shears) {
    SCOPED_TRACE(j.name);
    EXPECT_NE(j.name.find("_csr" + std::string(j.csr == 0.1 ? "0.1" : "0.25")), std::string::npos);
    EXPECT_EQ(j.q_amplitude, 2 * j.csr * j.p0);
    EXPECT_EQ(j.cycles, 5);
  }
  EXPECT_NE(error("study_csr0", "base: " + base + "\naxes: {csr: [0]}\n").find("axes.csr: values must be > 0"),
            std::string::npos);
  const std::string e = error("study_csr_mono", "base: " GRAINLAB_SOURCE_DIR "/configs/quick-study-base.yaml\n"
                                                "axes: {csr: [0.2]}\n");
  EXPECT_NE(e.find("axes.csr: sets the stress amplitude of a cyclic stage (q_amplitude = 2 csr p'_0, or the stage's "
                   "csr), and the base ("),
            std::string::npos)
      << e;
  // A staged test (amplitudes in turn) is refused, in the axes and in an extra job; two stages of one amplitude (a
  // test that goes on in a second stage) take the csr both.
  const std::string staged = write_tmp("study_staged_base", "sample: {count: 300}\nstages:\n"
                                       "  - {name: consolidate, type: isotropic, pressure: 2.0e5}\n"
                                       "  - {name: low, type: cyclic, q_amplitude: 2e4, cycles: 5}\n"
                                       "  - {name: high, type: cyclic, q_amplitude: 4e4, cycles: 5}\n");
  const std::string flattened = "sets the stress amplitude of every cyclic stage with q_amplitude or csr, and the base's (" +
                                staged + ") load at amplitudes of their own (low 20 kPa, high 40 kPa) that it would make one";
  for (const auto& [tag, study, key] : std::vector<std::array<std::string, 3>>{
           {"study_csr_staged", "base: " + staged + "\naxes: {csr: [0.1]}\n", "axes.csr"},
           {"study_csr_staged_extra", "base: " + staged + "\nextra: [{csr: 0.1}]\n", "extra[0].csr"}}) {
    const std::string got = error(tag, study);
    EXPECT_NE(got.find(key + ": " + flattened), std::string::npos) << got;
  }
  const std::string twice = write_tmp("study_twice_base", "sample: {count: 300}\nstages:\n"
                                      "  - {name: consolidate, type: isotropic, pressure: 2.0e5}\n"
                                      "  - {name: first, type: cyclic, q_amplitude: 2e4, cycles: 5}\n"
                                      "  - {name: more, type: cyclic, q_amplitude: 2e4, cycles: 5}\n");
  const Study t = load_study(write_tmp("study_twice", "base: " + twice + "\naxes: {csr: [0.2]}\n"));
  ASSERT_EQ(t.shears.size(), 1u);
  const RunConfig c = job_run_config(t, t.shears[0]);
  ASSERT_EQ(c.stages.size(), 2u);
  EXPECT_EQ(c.stages[0].q_amplitude, 8e4);
  EXPECT_EQ(c.stages[1].q_amplitude, 8e4);
  // A stage that gives csr takes the axis's csr itself (the run applies it at the stage's p'_c), no q_amplitude; a
  // base mixing the two in a staged test is refused as amplitudes of their own.
  const std::string by_csr = write_tmp("study_csr_stage_base", "sample: {count: 300}\nstages:\n"
                                       "  - {name: consolidate, type: isotropic, pressure: 2.0e5}\n"
                                       "  - {name: shake, type: cyclic, csr: 0.1, cycles: 5}\n");
  const Study u = load_study(write_tmp("study_csr_stage", "base: " + by_csr + "\naxes: {csr: [0.2, 0.3]}\n"));
  ASSERT_EQ(u.shears.size(), 2u);
  for (const StudyJob& j : u.shears) {
    const RunConfig cj = job_run_config(u, j);
    ASSERT_EQ(cj.stages.size(), 1u);
    EXPECT_EQ(cj.stages[0].csr, j.csr) << j.name;
    EXPECT_EQ(cj.stages[0].q_amplitude, 0.0) << j.name;
  }
  const std::string mixed = write_tmp("study_mixed_base", "sample: {count: 300}\nstages:\n"
                                      "  - {name: consolidate, type: isotropic, pressure: 2.0e5}\n"
                                      "  - {name: low, type: cyclic, q_amplitude: 2e4, cycles: 5}\n"
                                      "  - {name: high, type: cyclic, csr: 0.1, cycles: 5}\n");
  const std::string got = error("study_csr_mixed", "base: " + mixed + "\naxes: {csr: [0.1]}\n");
  EXPECT_NE(got.find("load at amplitudes of their own (low 20 kPa, high csr 0.1)"), std::string::npos) << got;
  // The csr axis on a q_amplitude stage whose cycles start from another p' than the preparation's (after a K0 stage, a
  // drained loading, a reconsolidation to another pressure) is a warning naming both stages and the remedy; not
  // after an undrained stage (an undrained one goes on with its p'_c), nor for a stage that gives csr, nor without
  // a csr axis.
  const std::string iso = "sample: {count: 300}\nstages:\n  - {name: consolidate, type: isotropic, pressure: 2.0e5}\n";
  const std::string k0 = "  - {name: k0, type: triaxial, drainage: oedometric, max_axial_strain: 0.01}\n";
  const auto warnings = [&](const std::string& tag, const std::string& stages, const std::string& axes) {
    const std::string b = write_tmp(tag + "_base", iso + stages);
    return load_study(write_tmp(tag, "base: " + b + "\naxes: " + axes + "\n")).warnings;
  };
  const std::vector<std::string> w = warnings("study_csr_k0", k0 + "  - {name: shake, type: cyclic, q_amplitude: 2e4}\n",
                                              "{csr: [0.1]}");
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find(": csr sets q_amplitude = 2 csr p'_0 at the preparation's pressure, and stage shake starts where "
                      "stage k0 (oedometric) left the sample, so the cycles start from another p' (summary.json p_0) "
                      "and their CSR is not csr: give that stage csr instead of q_amplitude"),
            std::string::npos)
      << w[0];
  const std::vector<std::string> r = warnings("study_csr_recon",
                                              "  - {name: cyc, type: cyclic, q_amplitude: 2e4}\n"
                                              "  - {name: recon, type: isotropic, pressure: 1.0e5}\n"
                                              "  - {name: cyc2, type: cyclic, q_amplitude: 2e4}\n", "{csr: [0.1]}");
  ASSERT_EQ(r.size(), 1u);
  EXPECT_NE(r[0].find("stage cyc2 starts where stage recon (isotropic, 100 kPa) left the sample"), std::string::npos) << r[0];
  EXPECT_TRUE(warnings("study_csr_k0_csr", k0 + "  - {name: shake, type: cyclic, csr: 0.1}\n", "{csr: [0.1]}").empty());
  EXPECT_TRUE(warnings("study_csr_k0_mu", k0 + "  - {name: shake, type: cyclic, q_amplitude: 2e4}\n", "{mu_r: [0.1]}")
                  .empty());
  EXPECT_TRUE(warnings("study_csr_undrained",
                       "  - {name: mono, type: triaxial, drainage: undrained, max_axial_strain: 0.01}\n"
                       "  - {name: shake, type: cyclic, q_amplitude: 2e4}\n", "{csr: [0.1]}")
                  .empty());
}

// A base that reconsolidates between shear stages (cycles, an isotropic reconsolidation, cycles again: a
// re-liquefaction test): its sample jobs run the isotropic stages before the first shear (the preparation), its shear
// jobs every stage from there, the reconsolidation in its place (it was run by the sample job, before any shear: a
// test the base did not ask for, silently), with the p0 axis's pressure. The csr axis's p'_0 is the
// preparation's, not a later isotropic stage's (which gave half the amplitude where the reconsolidation went to half
// the pressure).
TEST(Config, StudyKeepsAReconsolidationBetweenShears) {
  const auto base = [](const std::string& tag, const std::string& recon_p) {
    return write_tmp(tag, "sample: {count: 300}\nstages:\n  - {name: consolidate, type: isotropic, pressure: 2.0e5}\n"
                          "  - {name: shake, type: cyclic, q_amplitude: 2e4, cycles: 5}\n"
                          "  - {name: recon, type: isotropic, pressure: " + recon_p + "}\n"
                          "  - {name: reshake, type: cyclic, q_amplitude: 2e4, cycles: 5}\n");
  };
  const Study s = load_study(write_tmp("study_recon", "base: " + base("study_recon_base", "2.0e5") +
                                                          "\naxes: {csr: [0.1], p0: [1.0e5]}\n"));
  ASSERT_EQ(s.samples.size(), 1u);
  ASSERT_EQ(s.shears.size(), 1u);
  const RunConfig prep = parse_run_config(YAML::Load(s.samples[0].config_yaml), s.samples[0].name);
  ASSERT_EQ(prep.stages.size(), 1u);
  EXPECT_EQ(prep.stages[0].name, "consolidate");
  EXPECT_EQ(prep.stages[0].pressure, 1e5);
  EXPECT_TRUE(prep.stages[0].save_sample);
  const RunConfig c = job_run_config(s, s.shears[0]);
  ASSERT_EQ(c.stages.size(), 3u);
  EXPECT_EQ(c.stages[0].name, "shake");
  EXPECT_EQ(c.stages[1].name, "recon");
  EXPECT_EQ(c.stages[1].type, StageType::Isotropic);
  EXPECT_EQ(c.stages[1].pressure, 1e5) << "the p0 axis sets every isotropic stage";
  EXPECT_EQ(c.stages[2].name, "reshake");
  EXPECT_EQ(c.stages[0].q_amplitude, 2e4);  // 2 csr p'_0
  EXPECT_EQ(c.stages[2].q_amplitude, 2e4);
  const Study half = load_study(write_tmp("study_recon_half", "base: " + base("study_recon_half_base", "1.0e5") +
                                                                  "\naxes: {csr: [0.1]}\n"));
  ASSERT_EQ(half.shears.size(), 1u);
  EXPECT_EQ(half.shears[0].q_amplitude, 4e4) << "2 csr p'_0 of the preparation's 200 kPa";
}

// A base whose shear stages differ in a key the study sets on every one (job_config): a drained loading then an
// undrained shear keep their drainages where the study does not sweep it (the first shear's drainage was written on
// every stage: the undrained shear ran drained, silently); a drainage axis or an extra job's drainage, a direction
// axis on a loading then an unloading, and an extra job's max_axial_strain on stages that end at their own strains
// are refused, naming both stages (they would make them one). So do a preparation's own mu_r and a mu_r axis.
TEST(Config, StudyLeavesEachShearStageItsOwnValues) {
  const std::string head = "sample: {count: 300}\nstages:\n  - {name: consolidate, type: isotropic, pressure: 2.0e5}\n";
  const std::string base = write_tmp("study_two_base", head +
                                     "  - {name: pre, type: triaxial, drainage: drained, max_axial_strain: 0.01}\n"
                                     "  - {name: shear, type: triaxial, drainage: undrained, max_axial_strain: 0.05}\n");
  const Study s = load_study(write_tmp("study_two", "base: " + base + "\naxes: {mu_r: [0, 0.1]}\n"));
  ASSERT_EQ(s.shears.size(), 2u);
  for (const StudyJob& j : s.shears) {
    const RunConfig c = job_run_config(s, j);
    ASSERT_EQ(c.stages.size(), 2u);
    EXPECT_EQ(c.stages[0].drainage, Drainage::Drained) << j.name;
    EXPECT_EQ(c.stages[1].drainage, Drainage::Undrained) << j.name;
    EXPECT_EQ(j.drainage, "drained") << "named after the first shear stage's";
  }
  const std::string both = "sets the drainage of every shear stage of the base, and the base's (" + base +
                           ") have their own (pre drained, shear undrained) that it would make one";
  for (const auto& [tag, study, key] : std::vector<std::array<std::string, 3>>{
           {"study_two_axis", "base: " + base + "\naxes: {drainage: [drained, undrained]}\n", "axes.drainage"},
           {"study_two_extra", "base: " + base + "\nextra: [{drainage: undrained}]\n", "extra[0].drainage"}}) {
    const std::string got = error(tag, study);
    EXPECT_NE(got.find(key + ": " + both), std::string::npos) << got;
  }
  const std::string strain = error("study_two_strain", "base: " + base + "\nextra: [{max_axial_strain: 0.2}]\n");
  EXPECT_NE(strain.find("extra[0].max_axial_strain: sets the max_axial_strain of every triaxial stage of the base, and "
                        "the base's (" + base + ") have their own (pre 0.01, shear 0.05)"),
            std::string::npos)
      << strain;
  const std::string unload = write_tmp("study_unload_base", head +
                                       "  - {name: load, type: triaxial, drainage: drained, max_axial_strain: 0.01}\n"
                                       "  - {name: unload, type: triaxial, drainage: drained, direction: extension, "
                                       "max_axial_strain: 0.01}\n");
  const std::string dir = error("study_unload", "base: " + unload + "\naxes: {direction: [compression, extension]}\n");
  EXPECT_NE(dir.find("axes.direction: sets the direction of every triaxial stage of the base, and the base's (" + unload +
                     ") have their own (load compression, unload extension)"),
            std::string::npos)
      << dir;
  // A preparation without rolling resistance (SPEC §6.2: each stage its own mu_r) keeps it where the study does not
  // sweep mu_r (the material's was written on every stage); a mu_r axis or extra job's mu_r is refused.
  const std::string prep0 = write_tmp("study_prep0_base", "sample: {count: 300}\nmaterial: {mu_r: 0.1}\nstages:\n"
                                      "  - {name: consolidate, type: isotropic, pressure: 2.0e5, mu_r: 0}\n"
                                      "  - {name: shear, type: triaxial}\n");
  const Study p = load_study(write_tmp("study_prep0", "base: " + prep0 + "\naxes: {seed: [3, 4]}\n"));
  ASSERT_EQ(p.samples.size(), 2u);
  for (const StudyJob& j : p.samples) {
    const RunConfig c = parse_run_config(YAML::Load(j.config_yaml), j.name);
    EXPECT_EQ(c.stages.at(0).mu_r, 0.0) << j.name;
    EXPECT_EQ(c.engine.contact.mu_r, 0.1) << j.name;
  }
  for (const auto& [tag, study, key] : std::vector<std::array<std::string, 3>>{
           {"study_prep0_axis", "base: " + prep0 + "\naxes: {mu_r: [0.1, 0.3]}\n", "axes.mu_r"},
           {"study_prep0_extra", "base: " + prep0 + "\nextra: [{mu_r: 0.3}]\n", "extra[0].mu_r"}}) {
    const std::string got = error(tag, study);
    EXPECT_NE(got.find(key + ": sets the mu_r of every stage of the base, and the base's (" + prep0 +
                       ") have their own (material 0.1, consolidate 0)"),
              std::string::npos)
        << got;
  }
}

// Modulus-reduction studies: the strain_amplitude axis sets the amplitude of the base's one strain-controlled cyclic
// stage and scales its rate with it, so every job's quarter cycle A/rate lasts as long as the base's (one loading
// frequency); the stress-reversal stage of the same base keeps its q_amplitude; the samples are shared between
// amplitudes. Errors: no such stage, two of them (which would it set?), values outside (0, 0.9), a value the job's
// own config refuses (at or above its max_axial_strain), and two values that name one job.
TEST(Config, StudyStrainAmplitudeAxisSetsAmplitudeAndRate) {
  const std::string head = "sample: {count: 300}\nstages:\n  - {name: consolidate, type: isotropic, pressure: 2.0e5}\n";
  const std::string loops = "  - {name: loops, type: cyclic, strain_amplitude: 1.0e-3, axial_strain_rate: 0.3, cycles: 3}\n";
  const std::string base = write_tmp("study_strain_base", head + loops +
                                     "  - {name: shake, type: cyclic, q_amplitude: 3e4, cycles: 5}\n");
  const Study s = load_study(write_tmp("study_strain", "base: " + base +
                                       "\naxes: {strain_amplitude: [1.0e-5, 1.0e-3, 0.02], mu_r: [0, 0.2]}\n"));
  ASSERT_EQ(s.samples.size(), 2u);
  ASSERT_EQ(s.shears.size(), 6u);
  EXPECT_EQ(s.strain_stage, "loops");
  for (const StudyJob& j : s.shears) {
    SCOPED_TRACE(j.name);
    const RunConfig c = job_run_config(s, j);
    ASSERT_EQ(c.stages.size(), 2u);
    EXPECT_EQ(c.stages[0].strain_amplitude, j.strain_amplitude);
    // the quarter cycle A / rate of the base's, 1e-3 / 0.3 s, to the 12 digits the rate is written with
    EXPECT_NEAR(c.stages[0].strain_amplitude / c.stages[0].axial_strain_rate, 1.0e-3 / 0.3, 1e-12 * 1.0e-3 / 0.3);
    EXPECT_EQ(c.stages[1].q_amplitude, 3e4);  // the stress-reversal stage is not the axis's
    EXPECT_EQ(c.stages[1].axial_strain_rate, 1.0);
    EXPECT_NE(j.name.find("_ea" + std::string(j.strain_amplitude == 1e-5 ? "1e-05" : j.strain_amplitude == 1e-3 ? "0.001"
                                                                                                               : "0.02")),
              std::string::npos);
  }
  EXPECT_EQ(s.shears[0].strain_rate, 0.003) << "0.3 x 1e-5 / 1e-3, written without binary noise";
  std::string loops2 = loops;  // a second such stage, under its own name (each stage has its own)
  loops2.replace(loops2.find("name: loops"), 11, "name: loops2");
  const std::string two = write_tmp("study_strain_two", head + loops + loops2);
  expect_study_errors({
      {"study_ea_none", "base: " GRAINLAB_SOURCE_DIR "/configs/quick-study-base.yaml\naxes: {strain_amplitude: [1e-4]}\n",
       "axes.strain_amplitude: sets the strain amplitude of the base's strain-controlled cyclic stage (one with "
       "strain_amplitude), and the base (" GRAINLAB_SOURCE_DIR "/configs/quick-study-base.yaml) has none"},
      {"study_ea_two", "base: " + two + "\nextra: [{strain_amplitude: 1e-4}]\n",
       "extra[0].strain_amplitude: sets the strain amplitude of the base's strain-controlled cyclic stage (one with "
       "strain_amplitude), and the base (" + two + ") has 2 (loops, loops2): the axis would not say which"},
      {"study_ea_zero", "base: " + base + "\naxes: {strain_amplitude: [0]}\n",
       "axes.strain_amplitude: values must be in (0, 0.9)"},
      {"study_ea_big", "base: " + base + "\naxes: {strain_amplitude: [0.06]}\n",
       "(job shear_undrained_mur0_ebase_pbase_s1_n300_ea0.06): stages[0].strain_amplitude = 0.06 must be below "
       "max_axial_strain = 0.05"},
      {"study_ea_close", "base: " + base + "\naxes: {strain_amplitude: [1e-4, 1.0000001e-4]}\n",
       "axes: two values of csr, strain_amplitude, b, axial_strain_rate or a stage axis agree to 6 significant digits"},
  });
}

// Triaxial compression against extension: the direction axis sets every triaxial stage of the base (its cyclic stage
// is left alone), shares the sample between directions, and names extension shears "_ext" (compression keeps the
// names of studies from before the axis); an extra job may set it; left out, the base's direction is the job's and
// nothing is written. Errors: a value other than compression/extension, an empty list, a base without a triaxial
// stage.
TEST(Config, StudyDirectionAxisSetsTheTriaxialStages) {
  const std::string head = "sample: {count: 300}\nstages:\n  - {name: consolidate, type: isotropic, pressure: 2.0e5}\n";
  const std::string base = write_tmp("study_dir_base", head +
                                     "  - {name: shear, type: triaxial, max_axial_strain: 0.05}\n"
                                     "  - {name: shake, type: cyclic, q_amplitude: 3e4, cycles: 2}\n");
  const Study s = load_study(write_tmp("study_dir", "base: " + base +
                                       "\naxes: {direction: [compression, extension], mu_r: [0, 0.2]}\n"
                                       "extra: [{mu_r: 0.4, direction: extension}, {mu_r: 0.4}]\n"));
  ASSERT_EQ(s.samples.size(), 3u);
  ASSERT_EQ(s.shears.size(), 6u);
  int ext = 0;
  for (const StudyJob& j : s.shears) {
    SCOPED_TRACE(j.name);
    const RunConfig c = job_run_config(s, j);
    ASSERT_EQ(c.stages.size(), 2u);
    EXPECT_EQ(c.stages[0].extension, j.direction == "extension");
    EXPECT_EQ(j.name.size() > 4 && j.name.compare(j.name.size() - 4, 4, "_ext") == 0, j.direction == "extension");
    EXPECT_EQ(c.stages[1].type, StageType::Cyclic);
    ext += j.direction == "extension";
  }
  EXPECT_EQ(ext, 3);
  EXPECT_EQ(s.shears[0].name, "shear_undrained_mur0_ebase_pbase_s1_n300");
  EXPECT_EQ(s.shears[1].name, "shear_undrained_mur0_ebase_pbase_s1_n300_ext");
  EXPECT_FALSE(s.shears[5].set_direction);  // the extra job without the key: the base's, not written
  EXPECT_EQ(shear_config(s, s.shears[5], "sample.h5").find("direction"), std::string::npos);
  EXPECT_EQ(s.shears[5].direction, "compression");
  // An extension base without the axis: its jobs are extension shears, named so.
  const std::string ext_base = write_tmp("study_dir_ext_base", head +
                                         "  - {name: shear, type: triaxial, max_axial_strain: 0.05, direction: extension}\n");
  const Study se = load_study(write_tmp("study_dir_ext", "base: " + ext_base + "\naxes: {mu_r: [0.1]}\n"));
  ASSERT_EQ(se.shears.size(), 1u);
  EXPECT_EQ(se.shears[0].direction, "extension");
  EXPECT_EQ(se.shears[0].name, "shear_undrained_mur0.1_ebase_pbase_s1_n300_ext");
  const std::string cyc = write_tmp("study_dir_cyc", head + "  - {name: shake, type: cyclic, q_amplitude: 3e4, cycles: 2}\n");
  expect_study_errors({
      {"study_dir_bad", "base: " + base + "\naxes: {direction: [compresion]}\n",
       "axes.direction: 'compresion' is not compression or extension"},
      {"study_dir_empty", "base: " + base + "\naxes: {direction: []}\n", "axes.direction: an empty list"},
      {"study_dir_extra", "base: " + base + "\nextra: [{direction: shear}]\n",
       "extra[0].direction: 'shear' is not compression or extension"},
      {"study_dir_cyclic", "base: " + cyc + "\naxes: {direction: [extension]}\n",
       "axes.direction: sets the loading direction of the base's triaxial stages, and the base (" + cyc + ") has none"},
  });
}

// Both stress paths in one study: the stress_path axis sets every triaxial stage of the base, crossed with b (the
// true-triaxial series at constant sigma_3 and at constant p'), shares the sample between paths, and names
// constant-p' shears "_cp" (constant sigma_3 keeps the names of before); an extra job may set it; left out, the base's
// path is the job's and nothing is written. Errors: a word other than the two, an empty list, a base without a
// triaxial stage, and constant_p crossed with an undrained shear (named at the study's key).
TEST(Config, StudyStressPathAxisSetsTheTriaxialStages) {
  const std::string head = "sample: {count: 300}\nstages:\n  - {name: consolidate, type: isotropic, pressure: 2.0e5}\n";
  const std::string base = write_tmp("study_sp_base", head +
                                     "  - {name: shear, type: triaxial, drainage: drained, max_axial_strain: 0.05}\n");
  const Study s = load_study(write_tmp("study_sp", "base: " + base +
                                       "\naxes: {stress_path: [constant_sigma3, constant_p], b: [0, 0.5]}\n"
                                       "extra: [{mu_r: 0.4, stress_path: constant_p}, {mu_r: 0.4}]\n"));
  ASSERT_EQ(s.samples.size(), 2u);
  ASSERT_EQ(s.shears.size(), 6u);
  const char* names[] = {"shear_drained_mur0_ebase_pbase_s1_n300", "shear_drained_mur0_ebase_pbase_s1_n300_cp",
                         "shear_drained_mur0_ebase_pbase_s1_n300_b0.5", "shear_drained_mur0_ebase_pbase_s1_n300_b0.5_cp",
                         "shear_drained_mur0.4_ebase_pbase_s1_n300_cp", "shear_drained_mur0.4_ebase_pbase_s1_n300"};
  const bool cp[] = {false, true, false, true, true, false};
  for (size_t k = 0; k < s.shears.size(); ++k) {
    const StudyJob& j = s.shears[k];
    SCOPED_TRACE(j.name);
    EXPECT_EQ(j.name, names[k]);
    EXPECT_EQ(j.stress_path, cp[k] ? "constant_p" : "constant_sigma3");
    const RunConfig c = job_run_config(s, j);
    ASSERT_EQ(c.stages.size(), 1u);
    EXPECT_EQ(c.stages[0].constant_p, cp[k]);
    EXPECT_EQ(c.stages[0].b, k == 2 || k == 3 ? 0.5 : 0.0);
  }
  EXPECT_EQ(s.shears[1].sample_name, s.shears[0].sample_name);  // one sample for both paths
  EXPECT_FALSE(s.shears[5].set_stress_path);  // the extra job without the key: the base's, not written
  EXPECT_EQ(shear_config(s, s.shears[5], "sample.h5").find("stress_path"), std::string::npos);
  // A constant-p' base without the axis: its jobs carry its path, under the names of before.
  const std::string cp_base = write_tmp("study_sp_cp_base", head + "  - {name: shear, type: triaxial, drainage: "
                                                                   "drained, max_axial_strain: 0.05, stress_path: constant_p}\n");
  const Study sc = load_study(write_tmp("study_sp_cp", "base: " + cp_base + "\naxes: {mu_r: [0.1]}\n"));
  ASSERT_EQ(sc.shears.size(), 1u);
  EXPECT_EQ(sc.shears[0].stress_path, "constant_p");
  EXPECT_EQ(sc.shears[0].name, "shear_drained_mur0.1_ebase_pbase_s1_n300");
  const std::string cyc = write_tmp("study_sp_cyc", head + "  - {name: shake, type: cyclic, q_amplitude: 3e4, cycles: 2}\n");
  expect_study_errors({
      {"study_sp_bad", "base: " + base + "\naxes: {stress_path: [constant_q]}\n",
       "axes.stress_path: 'constant_q' is not constant_sigma3, constant_p or plane_strain"},
      {"study_sp_empty", "base: " + base + "\naxes: {stress_path: []}\n", "axes.stress_path: an empty list"},
      {"study_sp_extra", "base: " + base + "\nextra: [{stress_path: p}]\n",
       "extra[0].stress_path: 'p' is not constant_sigma3, constant_p or plane_strain"},
      {"study_sp_cyclic", "base: " + cyc + "\naxes: {stress_path: [constant_p]}\n",
       "axes.stress_path: sets the stress path of the base's triaxial stages, and the base (" + cyc + ") has none"},
      {"study_sp_undrained", "base: " + base + "\naxes: {stress_path: [constant_p], drainage: [drained, undrained]}\n",
       "axes.stress_path: constant_p needs a drained shear, and this job's is undrained"},
      {"study_sp_extra_undrained", "base: " + base + "\nextra: [{stress_path: constant_p, drainage: undrained}]\n",
       "extra[0].stress_path: constant_p needs a drained shear, and this job's is undrained"},
      // plane strain: a drained or undrained shear at b = 0 (its b is the test's result), as an extra job beside a b
      // series; extension as compression
      {"study_ps_b", "base: " + base + "\naxes: {stress_path: [plane_strain], b: [0, 0.5]}\n",
       "axes.stress_path: plane_strain needs a drained or undrained shear at b = 0, and this job's is drained "
       "compression, b = 0.5"},
      {"study_ps_oed", "base: " + base + "\nextra: [{stress_path: plane_strain, drainage: oedometric}]\n",
       "extra[0].stress_path: plane_strain needs a drained or undrained shear at b = 0, and this job's is oedometric"},
  });
  // A plane-strain extra job beside a b series: one sample, named _ps, the stage's plane_strain set and b = 0.
  const Study ps = load_study(write_tmp("study_ps", "base: " + base + "\naxes: {b: [0, 0.5]}\n"
                                                     "extra: [{stress_path: plane_strain}]\n"));
  ASSERT_EQ(ps.samples.size(), 1u);
  ASSERT_EQ(ps.shears.size(), 3u);
  EXPECT_EQ(ps.shears[2].name, "shear_drained_mur0_ebase_pbase_s1_n300_ps");
  EXPECT_EQ(ps.shears[2].stress_path, "plane_strain");
  const RunConfig pc = job_run_config(ps, ps.shears[2]);
  EXPECT_TRUE(pc.stages.at(0).plane_strain);
  EXPECT_FALSE(pc.stages.at(0).constant_p);
  EXPECT_EQ(pc.stages.at(0).b, 0.0);
  EXPECT_FALSE(job_run_config(ps, ps.shears[1]).stages.at(0).plane_strain);
  // undrained too: the y walls at constant volume
  const Study psu = load_study(write_tmp("study_psu", "base: " + base + "\n"
                                                       "extra: [{stress_path: plane_strain, drainage: undrained}]\n"));
  ASSERT_EQ(psu.shears.size(), 1u);  // extra jobs alone, without axes
  EXPECT_EQ(psu.shears[0].name, "shear_undrained_mur0_ebase_pbase_s1_n300_ps");
  EXPECT_TRUE(job_run_config(psu, psu.shears[0]).stages.at(0).plane_strain);
  EXPECT_EQ(job_run_config(psu, psu.shears[0]).stages.at(0).drainage, Drainage::Undrained);
  // and in extension: the axial walls apart, the y walls at their start's stress (then the major one)
  const Study pse = load_study(write_tmp("study_pse", "base: " + base + "\n"
                                                       "extra: [{stress_path: plane_strain, direction: extension}]\n"));
  ASSERT_EQ(pse.shears.size(), 1u);
  const RunConfig pec = job_run_config(pse, pse.shears[0]);
  EXPECT_TRUE(pec.stages.at(0).plane_strain);
  EXPECT_TRUE(pec.stages.at(0).extension);
}

// The true-triaxial series: the b axis sets b on every triaxial stage of the base, shares the sample between its
// values, and names b > 0 shears "_b<value>" (b = 0 keeps the names of studies from before the axis); an extra job
// may set it; left out, the base's b is the job's (study.json, the report) and nothing is written. Errors: a value
// outside [0, 1], an empty list, a base without a triaxial stage, and b > 0 crossed with an undrained or extension
// shear (the stage's own rule, named at the study's key rather than as a job's config error).
TEST(Config, StudyBAxisSetsTheTriaxialStages) {
  const std::string head = "sample: {count: 300}\nstages:\n  - {name: consolidate, type: isotropic, pressure: 2.0e5}\n";
  const std::string base = write_tmp("study_b_base", head +
                                     "  - {name: shear, type: triaxial, drainage: drained, max_axial_strain: 0.05}\n");
  const Study s = load_study(write_tmp("study_b", "base: " + base + "\naxes: {b: [0, 0.5, 1], mu_r: [0, 0.2]}\n"
                                                  "extra: [{mu_r: 0.4, b: 0.25}, {mu_r: 0.4}]\n"));
  ASSERT_EQ(s.samples.size(), 3u);
  ASSERT_EQ(s.shears.size(), 8u);
  const double expect_b[] = {0, 0.5, 1, 0, 0.5, 1, 0.25, 0};
  for (size_t k = 0; k < s.shears.size(); ++k) {
    const StudyJob& j = s.shears[k];
    SCOPED_TRACE(j.name);
    EXPECT_EQ(j.b, expect_b[k]);
    const RunConfig c = job_run_config(s, j);
    ASSERT_EQ(c.stages.size(), 1u);
    EXPECT_EQ(c.stages[0].b, expect_b[k]);
    EXPECT_EQ(j.name.find("_b") != std::string::npos, expect_b[k] > 0);
  }
  EXPECT_EQ(s.shears[0].name, "shear_drained_mur0_ebase_pbase_s1_n300");
  EXPECT_EQ(s.shears[1].name, "shear_drained_mur0_ebase_pbase_s1_n300_b0.5");
  EXPECT_EQ(s.shears[6].name, "shear_drained_mur0.4_ebase_pbase_s1_n300_b0.25");
  EXPECT_EQ(s.shears[1].sample_name, s.shears[0].sample_name);  // one sample for every b
  EXPECT_FALSE(s.shears[7].set_b);  // the extra job without the key: the base's, not written
  EXPECT_EQ(shear_config(s, s.shears[7], "sample.h5").find("b:"), std::string::npos);
  // A true-triaxial base without the axis: its jobs carry its b (for the report), under the names of before.
  const std::string tt_base = write_tmp("study_b_tt_base", head +
                                        "  - {name: shear, type: triaxial, drainage: drained, max_axial_strain: 0.05, b: 0.3}\n");
  const Study st = load_study(write_tmp("study_b_tt", "base: " + tt_base + "\naxes: {mu_r: [0.1]}\n"));
  ASSERT_EQ(st.shears.size(), 1u);
  EXPECT_EQ(st.shears[0].b, 0.3);
  EXPECT_EQ(st.shears[0].name, "shear_drained_mur0.1_ebase_pbase_s1_n300");
  const std::string cyc = write_tmp("study_b_cyc", head + "  - {name: shake, type: cyclic, q_amplitude: 3e4, cycles: 2}\n");
  expect_study_errors({
      {"study_b_big", "base: " + base + "\naxes: {b: [0.5, 1.5]}\n", "axes.b: values must be in [0, 1]"},
      {"study_b_neg", "base: " + base + "\naxes: {b: [-0.5]}\n", "axes.b"},
      {"study_b_empty", "base: " + base + "\naxes: {b: []}\n", "axes.b: an empty list"},
      {"study_b_extra_big", "base: " + base + "\nextra: [{b: 2}]\n", "extra[0].b: values must be in [0, 1]"},
      {"study_b_cyclic", "base: " + cyc + "\naxes: {b: [0.5]}\n",
       "axes.b: sets b of the base's triaxial stages, and the base (" + cyc + ") has none"},
      {"study_b_undrained", "base: " + base + "\naxes: {b: [0, 0.5], drainage: [drained, undrained]}\n",
       "axes.b: b = 0.5 needs a drained compression shear, and this job's is undrained compression"},
      {"study_b_ext", "base: " + base + "\nextra: [{b: 0.5, direction: extension}]\n",
       "extra[0].b: b = 0.5 needs a drained compression shear, and this job's is drained extension"},
      {"study_b_close", "base: " + base + "\naxes: {b: [0.5, 0.50000001]}\n",
       "axes: two values of csr, strain_amplitude, b, axial_strain_rate or a stage axis agree to 6 significant digits"},
  });
}

// The step cap of the one shear of a study (study_keys) over a base whose triaxial stage leaves max_steps at its
// default (1e6) and ends at 0.05; -1 unless the study has exactly one shear.
long default_base_cap(const std::string& tag, const std::string& head, const std::string& study_keys) {
  const std::string plain = write_tmp(tag + "_plain", head + "  - {name: shear, type: triaxial, max_axial_strain: 0.05}\n");
  const Study s = load_study(write_tmp(tag + "_default", "base: " + plain + "\n" + study_keys));
  if (s.shears.size() != 1) return -1;
  return job_run_config(s, s.shears[0]).stages[0].max_steps;
}

// A rate series: the axial_strain_rate axis sets every triaxial stage's rate (a cyclic stage's, its loading frequency,
// is left alone), shares the sample between rates, names each shear "_rate<value>" and gives it the rate group the
// report's rate section gathers (its name without the suffix). A slower rate scales the stage's step cap up with the
// duration (2 /s and max_steps 1000 -> 0.5 /s and 4000; the default 1e6 at 1 /s -> 4e6 at 0.25 /s), a faster one
// keeps it. An extra job may set it; left out, the base's rate, the names of before and no group. Errors: a value
// outside (0, 1e6], a base without a triaxial stage (axis and extra key), two values equal to 6 digits.
TEST(Config, StudyRateAxisSetsTheTriaxialStages) {
  const std::string head = "sample: {count: 300}\nstages:\n  - {name: consolidate, type: isotropic, pressure: 2.0e5}\n";
  const std::string base = write_tmp("study_rate_base", head +
                                     "  - {name: shear, type: triaxial, drainage: drained, max_axial_strain: 0.05, "
                                     "axial_strain_rate: 2, max_steps: 1000}\n"
                                     "  - {name: shake, type: cyclic, q_amplitude: 3e4, cycles: 2, axial_strain_rate: 3}\n");
  const Study s = load_study(write_tmp("study_rate", "base: " + base + "\naxes: {axial_strain_rate: [0.5, 2, 4]}\n"
                                                     "extra: [{mu_r: 0.4, axial_strain_rate: 1}, {mu_r: 0.4}]\n"));
  ASSERT_EQ(s.samples.size(), 2u);
  ASSERT_EQ(s.shears.size(), 5u);
  const double rate[] = {0.5, 2, 4, 1, 2};
  const long cap[] = {4000, 1000, 1000, 2000, 1000};
  const char* names[] = {"shear_drained_mur0_ebase_pbase_s1_n300_rate0.5", "shear_drained_mur0_ebase_pbase_s1_n300_rate2",
                         "shear_drained_mur0_ebase_pbase_s1_n300_rate4", "shear_drained_mur0.4_ebase_pbase_s1_n300_rate1",
                         "shear_drained_mur0.4_ebase_pbase_s1_n300"};
  for (size_t k = 0; k < s.shears.size(); ++k) {
    const StudyJob& j = s.shears[k];
    SCOPED_TRACE(j.name);
    EXPECT_EQ(j.name, names[k]);
    EXPECT_EQ(j.rate_group, k < 4 ? j.name.substr(0, j.name.rfind("_rate")) : "");
    const RunConfig c = job_run_config(s, j);
    ASSERT_EQ(c.stages.size(), 2u);
    EXPECT_EQ(c.stages[0].axial_strain_rate, rate[k]);
    EXPECT_EQ(c.stages[0].max_steps, cap[k]);
    EXPECT_EQ(c.stages[1].axial_strain_rate, 3.0);  // the cyclic stage's own
  }
  EXPECT_EQ(s.shears[1].sample_name, s.shears[0].sample_name);  // one sample for every rate
  EXPECT_EQ(s.shears[4].rate, 0.0);  // the extra job without the key: the base's
  EXPECT_EQ(default_base_cap("study_rate", head, "axes: {axial_strain_rate: [0.25]}\n"), 4000000);
  const std::string cyc = write_tmp("study_rate_cyc", head + "  - {name: shake, type: cyclic, q_amplitude: 3e4, cycles: 2}\n");
  expect_study_errors({
      {"study_rate_zero", "base: " + base + "\naxes: {axial_strain_rate: [0]}\n",
       "axes.axial_strain_rate: values must be in (0, 1e6] (1/s)"},
      {"study_rate_big", "base: " + base + "\nextra: [{axial_strain_rate: 2e6}]\n",
       "extra[0].axial_strain_rate: values must be in (0, 1e6] (1/s)"},
      {"study_rate_empty", "base: " + base + "\naxes: {axial_strain_rate: []}\n", "axes.axial_strain_rate: an empty list"},
      {"study_rate_cyclic", "base: " + cyc + "\naxes: {axial_strain_rate: [1]}\n",
       "axes.axial_strain_rate: sets axial_strain_rate of the base's triaxial stages, and the base (" + cyc + ") has none"},
      {"study_rate_extra_cyclic", "base: " + cyc + "\nextra: [{axial_strain_rate: 1}]\n",
       "extra[0].axial_strain_rate: sets axial_strain_rate of the base's triaxial stages, and the base (" + cyc +
           ") has none"},
      {"study_rate_close", "base: " + base + "\naxes: {axial_strain_rate: [1, 1.0000001]}\n",
       "axes: two values of csr, strain_amplitude, b, axial_strain_rate or a stage axis agree to 6 significant digits"},
  });
}

// The contact stiffness as an axis (E: material.E, k_n = E rbar): each E its own sample (a packing consolidates to
// another overlap at another stiffness), named "_E1e9" (no '+'), its shears at the same E; an extra job's E likewise;
// the base's without the axis (no suffix: the names studies had before it). study.json gives each job's E (the report's
// sections). Errors: a value outside (0, 1e13], two values within 6 digits.
TEST(Config, StudyStiffnessAxisSetsTheMaterial) {
  const std::string base = write_tmp("study_E_base", "sample: {count: 300}\nmaterial: {E: 5.0e7}\nstages:\n"
                                     "  - {name: consolidate, type: isotropic, pressure: 2.0e5}\n"
                                     "  - {name: shear, type: triaxial, drainage: drained, max_axial_strain: 0.05}\n");
  const Study s = load_study(write_tmp("study_E", "base: " + base + "\naxes: {E: [1.0e8, 2.5e9]}\nextra: [{E: 3.0e8}, {mu_r: 0.1}]\n"));
  ASSERT_EQ(s.samples.size(), 4u);
  ASSERT_EQ(s.shears.size(), 4u);
  const char* names[] = {"shear_drained_mur0_ebase_pbase_s1_n300_E1e8", "shear_drained_mur0_ebase_pbase_s1_n300_E2.5e9",
                         "shear_drained_mur0_ebase_pbase_s1_n300_E3e8", "shear_drained_mur0.1_ebase_pbase_s1_n300"};
  const double E[] = {1e8, 2.5e9, 3e8, 5e7};
  for (size_t k = 0; k < s.shears.size(); ++k) {
    const StudyJob& j = s.shears[k];
    SCOPED_TRACE(j.name);
    EXPECT_EQ(j.name, names[k]);
    EXPECT_EQ(j.sample_name, "sample_" + j.name.substr(std::string("shear_drained_").size()));
    EXPECT_EQ(job_run_config(s, j).engine.contact.E, E[k]);
    EXPECT_EQ(parse_run_config(YAML::Load(s.samples[k].config_yaml), "sample").engine.contact.E, E[k]);
  }
  expect_study_errors({
      {"study_E_zero", "base: " + base + "\naxes: {E: [0]}\n", "axes.E: values must be in (0, 1e13] (Pa, material.E)"},
      {"study_E_big", "base: " + base + "\nextra: [{E: 2e13}]\n", "extra[0].E: values must be in (0, 1e13] (Pa, material.E)"},
      {"study_E_close", "base: " + base + "\naxes: {E: [1.0e8, 1.0000001e8]}\n",
       "axes: two values of mu_r, e0, p0, E or a preparation stage's axis agree to 6 significant digits"},
  });
}

// Tests of one sample that end at other strains: an extra job's max_axial_strain sets every triaxial stage's end
// (configs/oedometer-jaky-study.yaml: a K0 test at 3 % and a drained shear of the same sample to 30 %), scales the
// step cap up with the strain (never down: 0.05 and 1000 -> 0.2 and 4000; the default 1e6 at 0.05 -> 2e6 at 0.1), and
// shares the grid's sample. The end is not in the name (a raised end extends the job that ran: study_tiny). Errors:
// a value outside (0, 0.9], a base without a triaxial stage, two jobs that differ only in their end.
TEST(Config, StudyExtraJobEndsAtItsOwnStrain) {
  const std::string head = "sample: {count: 300}\nstages:\n  - {name: consolidate, type: isotropic, pressure: 2.0e5}\n";
  const std::string base = write_tmp("study_end_base", head +
                                     "  - {name: load, type: triaxial, drainage: oedometric, max_axial_strain: 0.05, "
                                     "max_steps: 1000}\n");
  const Study s = load_study(write_tmp("study_end", "base: " + base + "\naxes: {drainage: [oedometric]}\n"
                                                    "extra: [{drainage: drained, max_axial_strain: 0.2}, "
                                                    "{drainage: undrained, max_axial_strain: 0.01}]\n"));
  ASSERT_EQ(s.samples.size(), 1u);
  ASSERT_EQ(s.shears.size(), 3u);
  const char* names[] = {"shear_oedometric_mur0_ebase_pbase_s1_n300", "shear_drained_mur0_ebase_pbase_s1_n300",
                         "shear_undrained_mur0_ebase_pbase_s1_n300"};
  const double end[] = {0.05, 0.2, 0.01};
  const long cap[] = {1000, 4000, 1000};
  for (size_t k = 0; k < s.shears.size(); ++k) {
    const StudyJob& j = s.shears[k];
    SCOPED_TRACE(j.name);
    EXPECT_EQ(j.name, names[k]);
    EXPECT_EQ(j.sample_name, s.samples[0].name);
    const RunConfig c = job_run_config(s, j);
    ASSERT_EQ(c.stages.size(), 1u);
    EXPECT_EQ(c.stages[0].max_axial_strain, end[k]);
    EXPECT_EQ(c.stages[0].max_steps, cap[k]);
    EXPECT_EQ(c.stages[0].drainage, k == 0 ? Drainage::Oedometric : k == 1 ? Drainage::Drained : Drainage::Undrained);
  }
  EXPECT_EQ(s.shears[0].strain, 0.0);  // the grid's job: the base's end
  EXPECT_EQ(default_base_cap("study_end", head, "extra: [{max_axial_strain: 0.1}]\n"), 2000000);
  const std::string cyc = write_tmp("study_end_cyc", head + "  - {name: shake, type: cyclic, q_amplitude: 3e4, cycles: 2}\n");
  expect_study_errors({
      {"study_end_big", "base: " + base + "\nextra: [{max_axial_strain: 0.95}]\n",
       "extra[0].max_axial_strain: = 0.95 must be in (0, 0.9], as a stage's"},
      {"study_end_zero", "base: " + base + "\nextra: [{max_axial_strain: 0}]\n",
       "extra[0].max_axial_strain: = 0 must be in (0, 0.9], as a stage's"},
      {"study_end_cyclic", "base: " + cyc + "\nextra: [{max_axial_strain: 0.1}]\n",
       "extra[0].max_axial_strain: sets max_axial_strain of the base's triaxial stages, and the base (" + cyc +
           ") has none"},
      {"study_end_twice", "base: " + base + "\nextra: [{max_axial_strain: 0.1}, {max_axial_strain: 0.2}]\n",
       "extra: two jobs differ only in max_axial_strain (job shear_oedometric_mur0_ebase_pbase_s1_n300): the shorter is "
       "the start of the longer; list the longer alone"},
      {"study_end_axis", "base: " + base + "\naxes: {max_axial_strain: [0.1]}\n", "axes.max_axial_strain: unknown axis"},
  });
}

// Stage axes, stages.<name>.<key>: each value sets that key of that stage in a shear job of the shared sample (a
// K path's k_ratio, the shear's max_steps), the grid crossed with the other axes, the job named by it; the rest of the
// stage and the other stages as the base gives them. An extra job sets a stage's key the same way. Errors: a stage the
// base lacks, a key another axis sets (p0 a preparation stage's pressure, e0 its target_e0) or the study (save_sample),
// the stage's own range (named by the job: a sample's too), a value twice, values one name cannot tell apart, an empty
// list, no key.
TEST(Config, StudyStageAxisSetsOneStagesKey) {
  const std::string base = write_tmp("study_stage_base",
                                     "sample: {count: 300}\nstages:\n"
                                     "  - {name: seat, type: isotropic, pressure: 2.0e4}\n"
                                     "  - {name: kc, type: triaxial, drainage: drained, k_ratio: 0.6, sigma_v: 1.0e5}\n"
                                     "  - {name: cau, type: triaxial, drainage: undrained, max_axial_strain: 0.02}\n");
  const Study s = load_study(write_tmp("study_stage", "base: " + base + "\naxes: {stages.kc.k_ratio: [0.5, 0.8], "
                                                      "stages.cau.max_steps: [5000, 9000]}\n"
                                                      "extra: [{stages.kc.k_ratio: 0.65}]\n"));
  ASSERT_EQ(s.samples.size(), 1u);
  ASSERT_EQ(s.shears.size(), 5u);
  std::set<std::string> names;
  for (const StudyJob& j : s.shears) {
    SCOPED_TRACE(j.name);
    names.insert(j.name);
    const bool extra = j.stage_keys.size() == 1;  // the extra job sets k_ratio alone: max_steps is the base's
    ASSERT_EQ(j.stage_keys.size(), extra ? 1u : 2u);
    const RunConfig c = job_run_config(s, j);
    ASSERT_EQ(c.stages.size(), 2u);
    EXPECT_EQ(c.stages[0].k_ratio, j.stage_keys[0].value);
    EXPECT_EQ(c.stages[0].sigma_v, 1e5);
    EXPECT_EQ(c.stages[0].max_steps, 1000000);
    EXPECT_EQ(c.stages[1].max_steps, extra ? 1000000 : long(j.stage_keys[1].value));
    EXPECT_EQ(c.stages[1].max_axial_strain, 0.02);
  }
  // A stage's own rate and end strain, where no axis or extra job sets every triaxial stage's: the step cap scaled up as
  // the axes scale it (0.5/s: twice the default 1e6; an end of 0.04 against 0.02: twice), unless the job sets it too.
  const Study r = load_study(write_tmp("study_stage_rate", "base: " + base + "\naxes: {stages.cau.axial_strain_rate: [0.5, 2], "
                                                           "stages.cau.max_axial_strain: [0.04]}\n"
                                                           "extra: [{stages.cau.axial_strain_rate: 0.25, stages.cau.max_steps: 7000}]\n"));
  ASSERT_EQ(r.shears.size(), 3u);
  for (const StudyJob& j : r.shears) {
    SCOPED_TRACE(j.name);
    const RunConfig c = job_run_config(r, j);
    EXPECT_EQ(c.stages[0].axial_strain_rate, 1.0);  // the K path keeps the base's
    EXPECT_EQ(c.stages[1].axial_strain_rate, j.stage_keys[0].value);
    if (j.stage_keys[1].key == "max_steps") {
      EXPECT_EQ(c.stages[1].max_steps, 7000);
      EXPECT_EQ(c.stages[1].max_axial_strain, 0.02);
    } else {
      EXPECT_EQ(c.stages[1].max_axial_strain, 0.04);
      EXPECT_EQ(c.stages[1].max_steps, j.stage_keys[0].value == 0.5 ? 4000000 : 2000000);
    }
  }
  EXPECT_EQ(names, (std::set<std::string>{"shear_undrained_mur0_ebase_pbase_s1_n300_kc-k_ratio0.5_cau-max_steps5000",
                                          "shear_undrained_mur0_ebase_pbase_s1_n300_kc-k_ratio0.5_cau-max_steps9000",
                                          "shear_undrained_mur0_ebase_pbase_s1_n300_kc-k_ratio0.8_cau-max_steps5000",
                                          "shear_undrained_mur0_ebase_pbase_s1_n300_kc-k_ratio0.8_cau-max_steps9000",
                                          "shear_undrained_mur0_ebase_pbase_s1_n300_kc-k_ratio0.65"}));
  expect_study_errors({
      {"stage_ax_none", "base: " + base + "\naxes: {stages.kx.k_ratio: [0.5]}\n",
       "axes.stages.kx.k_ratio: the base (" + base + ") has no stage named 'kx' (its stages: seat, kc, cau)"},
      {"stage_ax_prep_p0", "base: " + base + "\naxes: {p0: [3.0e4], stages.seat.pressure: [1.0e5]}\n",
       "axes.stages.seat.pressure: 'pressure' is set by axes.p0 or an extra job's key: a stage axis sets another of the "
       "stage's keys"},
      {"stage_ex_prep_p0", "base: " + base + "\naxes: {stages.seat.pressure: [1.0e5]}\nextra: [{p0: 3.0e4}]\n",
       "axes.stages.seat.pressure: 'pressure' is set by axes.p0 or an extra job's key"},
      {"stage_ax_prep_e0", "base: " + base + "\naxes: {e0: [0.6], stages.seat.target_e0: [0.65]}\n",
       "axes.stages.seat.target_e0: 'target_e0' is set by axes.e0 or an extra job's key"},
      {"stage_ax_prep_mu_e0", "base: " + base + "\naxes: {e0: [0.6], stages.seat.mu: [0.1, 0.3]}\n",
       "axes.stages.seat.mu: 'mu' of 'seat' is what its target_e0 search sets (axes.e0 or an extra job's e0), so the "
       "axis would change nothing: sweep e0, or set mu without a target"},
      {"stage_ax_prep_save", "base: " + base + "\naxes: {stages.seat.save_sample: [0]}\n",
       "axes.stages.seat.save_sample: 'save_sample' is how a study keeps its samples: a stage axis sets another of the "
       "stage's keys"},
      {"stage_ax_prep_range", "base: " + base + "\naxes: {stages.seat.pressure_tolerance: [2]}\n",
       "(job sample_mur0_ebase_pbase_s1_n300_seat-pressure_tolerance2): stages[0].pressure_tolerance = 2 is outside "
       "the allowed range"},
      {"stage_ax_prep_close", "base: " + base + "\naxes: {stages.seat.pressure: [1.0e5, 1.00000001e5]}\n",
       "axes: two values of mu_r, e0, p0, E or a preparation stage's axis agree to 6 significant digits (job "
       "sample_mur0_ebase_pbase_s1_n300_seat-pressure100000)"},
      {"stage_ax_taken", "base: " + base + "\naxes: {axial_strain_rate: [1], stages.cau.axial_strain_rate: [2]}\n",
       "axes.stages.cau.axial_strain_rate: 'axial_strain_rate' is set by axes.axial_strain_rate or an extra job's key: a "
       "stage axis sets another of the stage's keys"},
      {"stage_ex_taken", "base: " + base + "\naxes: {stages.cau.max_axial_strain: [0.1]}\nextra: [{max_axial_strain: 0.2}]\n",
       "axes.stages.cau.max_axial_strain: 'max_axial_strain' is set by axes.max_axial_strain or an extra job's key"},
      {"stage_ax_direction", "base: " + base + "\naxes: {stages.cau.direction: [1]}\n",
       "axes.stages.cau.direction: 'direction' is set by axes.direction or an extra job's key"},
      {"stage_ax_range", "base: " + base + "\naxes: {stages.kc.k_ratio: [1.5]}\n",
       "(job shear_undrained_mur0_ebase_pbase_s1_n300_kc-k_ratio1.5): stages[0].k_ratio = 1.5 is outside the allowed "
       "range (0, 1]"},
      {"stage_ax_twice", "base: " + base + "\naxes: {stages.kc.k_ratio: [0.5, 0.5]}\n",
       "axes.stages.kc.k_ratio: 0.5 is listed twice"},
      {"stage_ax_empty", "base: " + base + "\naxes: {stages.kc.k_ratio: []}\n",
       "axes.stages.kc.k_ratio: an empty list: give at least one value, or leave the axis out"},
      {"stage_ax_nokey", "base: " + base + "\naxes: {stages.kc: [0.5]}\n",
       "axes.stages.kc: a stage axis is stages.<stage name>.<key>"},
      {"stage_ex_none", "base: " + base + "\nextra: [{stages.kx.k_ratio: 0.5}]\n",
       "extra[0].stages.kx.k_ratio: the base (" + base + ") has no stage named 'kx'"},
      {"stage_ex_list", "base: " + base + "\nextra: [{stages.kc.k_ratio: [0.5, 0.6]}]\n",
       "extra[0].stages.kc.k_ratio: must be one number"},
      {"stage_ax_close", "base: " + base + "\naxes: {stages.kc.k_ratio: [0.5, 0.50000001]}\n",
       "axes: two values of csr, strain_amplitude, b, axial_strain_rate or a stage axis agree to 6 significant digits (job "
       "shear_undrained_mur0_ebase_pbase_s1_n300_kc-k_ratio0.5)"},
  });
}

// A stage axis on a preparation stage (an isotropic stage before the first shear): each value a sample of its own,
// named by it, whose config sets that stage's key (and only the sample's: the shears start from its file), crossed
// with the other axes and the shear stages' axes; its shears take the sample's name and list every stage key (the
// report's sections split by them); an extra job sets a preparation stage's key the same way. Here a preloading's
// pressure: isotropically overconsolidated samples (OCR 1, 2 and 4 of the 20 kPa consolidation).
TEST(Config, StudyStageAxisOnAPreparationStageMakesSamples) {
  const std::string base = write_tmp("study_prep_axis_base",
                                     "sample: {count: 300}\nstages:\n"
                                     "  - {name: pre, type: isotropic, pressure: 2.0e4}\n"
                                     "  - {name: iso, type: isotropic, pressure: 2.0e4}\n"
                                     "  - {name: cu, type: triaxial, drainage: undrained, max_axial_strain: 0.02}\n");
  const Study s = load_study(write_tmp("study_prep_axis", "base: " + base + "\naxes: {stages.pre.pressure: [2.0e4, 4.0e4], "
                                                          "stages.cu.max_steps: [5000, 9000], seed: [1, 2]}\n"
                                                          "extra: [{stages.pre.pressure: 8.0e4, seed: 3}]\n"));
  ASSERT_EQ(s.samples.size(), 5u);
  ASSERT_EQ(s.shears.size(), 9u);
  std::set<std::string> samples;
  for (const StudyJob& j : s.samples) {
    SCOPED_TRACE(j.name);
    samples.insert(j.name);
    ASSERT_EQ(j.stage_keys.size(), 1u);
    EXPECT_EQ(j.stage_keys[0].stage_name + "." + j.stage_keys[0].key, "pre.pressure");
    const RunConfig c = parse_run_config(YAML::Load(j.config_yaml), j.name);
    ASSERT_EQ(c.stages.size(), 2u);
    EXPECT_EQ(c.stages[0].pressure, j.stage_keys[0].value);
    EXPECT_EQ(c.stages[1].pressure, 2e4);  // the stage the axis does not name: as the base gives it
    EXPECT_EQ(long(c.packing.seed), j.seed);
  }
  EXPECT_EQ(samples, (std::set<std::string>{"sample_mur0_ebase_pbase_s1_n300_pre-pressure20000",
                                            "sample_mur0_ebase_pbase_s1_n300_pre-pressure40000",
                                            "sample_mur0_ebase_pbase_s2_n300_pre-pressure20000",
                                            "sample_mur0_ebase_pbase_s2_n300_pre-pressure40000",
                                            "sample_mur0_ebase_pbase_s3_n300_pre-pressure80000"}));
  for (const StudyJob& j : s.shears) {
    SCOPED_TRACE(j.name);
    ASSERT_TRUE(samples.count(j.sample_name));
    const StudyJob& sample = *std::find_if(s.samples.begin(), s.samples.end(),
                                           [&](const StudyJob& x) { return x.name == j.sample_name; });
    // the sample's name once, then the shear stage's value
    const bool extra = j.stage_keys.size() == 1;
    std::string want = "shear_undrained_" + j.sample_name.substr(7);
    if (!extra) want += "_cu-max_steps" + std::to_string(long(j.stage_keys[1].value));
    EXPECT_EQ(j.name, want);
    ASSERT_EQ(j.stage_keys.size(), extra ? 1u : 2u);
    EXPECT_EQ(j.stage_keys[0].key, "pressure");
    EXPECT_EQ(j.stage_keys[0].value, sample.stage_keys[0].value);
    const RunConfig c = job_run_config(s, j);
    ASSERT_EQ(c.stages.size(), 1u);  // the shear alone: the preparation is the sample's
    EXPECT_EQ(c.stages[0].max_steps, extra ? 1000000 : long(j.stage_keys[1].value));
  }
  // a preparation study (no shear stage) sweeps its stages' keys as well: here the compaction's friction
  const std::string prep = write_tmp("study_prep_axis_prep_base",
                                     "sample: {count: 300}\nstages:\n  - {name: iso, type: isotropic, pressure: 2.0e4}\n");
  const Study p = load_study(write_tmp("study_prep_axis_prep", "base: " + prep + "\naxes: {stages.iso.mu: [0, 0.25]}\n"));
  EXPECT_TRUE(p.shears.empty());
  ASSERT_EQ(p.samples.size(), 2u);
  for (const StudyJob& j : p.samples)
    EXPECT_EQ(parse_run_config(YAML::Load(j.config_yaml), j.name).stages[0].mu, j.stage_keys.at(0).value) << j.name;
  EXPECT_EQ(p.samples[1].name, "sample_mur0_ebase_pbase_s1_n300_iso-mu0.25");
  // ... but not the friction of a stage whose target_e0 search sets it (the base's target here; the e0 axis's:
  // Config.StudyStageAxisSetsOneStagesKey); that stage's other keys, and the next stage's mu, are the axis's
  const std::string target = write_tmp("study_prep_axis_target_base",
                                       "sample: {count: 300}\nstages:\n"
                                       "  - {name: iso, type: isotropic, pressure: 2.0e4, target_e0: 0.7}\n"
                                       "  - {name: more, type: isotropic, pressure: 4.0e4}\n");
  expect_study_errors({{"study_prep_axis_target", "base: " + target + "\naxes: {stages.iso.mu: [0, 0.25]}\n",
                        "axes.stages.iso.mu: 'mu' of 'iso' is what its target_e0 search sets (the base's target_e0)"}});
  EXPECT_EQ(load_study(write_tmp("study_prep_axis_target_ok", "base: " + target + "\naxes: {stages.more.mu: [0, 0.25], "
                                                              "stages.iso.pressure_tolerance: [0.005]}\n"))
                .samples.size(),
            2u);
}

// The study's progress lines: wall times as read (rounding at each unit's edge: 59.96 s is "1 min 00 s", 3599.6 s
// "1 h 00 min"), and the estimate of the shears left by hand: three shears of planned work 6, 3, 3 (spheres x steps)
// at 2 a second on 2 slots take 3 s (the 12 shared by the two, and the longest alone, both 6); 10, 1, 1 take 5 s (the
// longest bounds it: the 12 shared would say 3); on one slot all 12 in turn, 6 s; on 4 slots (3 shears) the longest
// alone; nothing left, 0.
TEST(Config, StudyProgressGivesDurationsAndTheShearsLeft) {
  EXPECT_EQ(duration_text(0.04), "0.0 s");
  EXPECT_EQ(duration_text(12.34), "12.3 s");
  EXPECT_EQ(duration_text(59.96), "1 min 00 s");
  EXPECT_EQ(duration_text(185), "3 min 05 s");
  EXPECT_EQ(duration_text(3599.6), "1 h 00 min");
  EXPECT_EQ(duration_text(7500), "2 h 05 min");
  EXPECT_DOUBLE_EQ(shears_left_seconds({6, 3, 3}, 2, 2), 3.0);
  EXPECT_DOUBLE_EQ(shears_left_seconds({10, 1, 1}, 2, 2), 5.0);
  EXPECT_DOUBLE_EQ(shears_left_seconds({6, 3, 3}, 2, 1), 6.0);
  EXPECT_DOUBLE_EQ(shears_left_seconds({6, 3, 3}, 2, 4), 3.0);
  EXPECT_DOUBLE_EQ(shears_left_seconds({}, 2, 2), 0.0);
  EXPECT_DOUBLE_EQ(shears_left_seconds({6}, 0, 2), 0.0);  // no rate measured yet
}

TEST(Config, StudySeedZeroIsASeed) {
  const Study s = load_study(write_tmp("study_seed0", "base: " GRAINLAB_SOURCE_DIR
                                                      "/configs/quick-study-base.yaml\naxes: {seed: [0, 1]}\n"));
  ASSERT_EQ(s.samples.size(), 2u);
  for (const StudyJob& j : s.samples) {
    const RunConfig c = parse_run_config(YAML::Load(j.config_yaml), j.name);
    EXPECT_EQ(long(c.packing.seed), j.seed) << j.name;
  }
  EXPECT_NE(s.samples[0].seed, s.samples[1].seed);
}

// A base without a shear stage makes a preparation study: its jobs are the samples of the grid (count x seed here),
// each with its axis values in its config, and no shear; the axes and extra jobs that set a shear are errors naming
// the key, and a base needs an isotropic stage still. A p0 axis on a base whose isotropic stages follow a loading path
// is an error too.
TEST(Config, StudyOfABaseWithoutAShearPreparesSamplesOnly) {
  const std::string prep = "base: " GRAINLAB_SOURCE_DIR "/configs/preparation-base.yaml\n";
  const Study s = load_study(write_tmp("study_prep", prep + "axes: {count: [2000, 5000], seed: [1, 2]}\n"));
  EXPECT_TRUE(s.shears.empty());
  ASSERT_EQ(s.samples.size(), 4u);
  std::set<std::pair<long, long>> seen;
  for (const StudyJob& j : s.samples) {
    const RunConfig c = parse_run_config(YAML::Load(j.config_yaml), j.name);
    EXPECT_EQ(long(c.packing.count), j.count) << j.name;
    EXPECT_EQ(long(c.packing.seed), j.seed) << j.name;
    ASSERT_EQ(c.stages.size(), 1u) << j.name;
    EXPECT_TRUE(c.stages[0].affine) << j.name;
    seen.insert({j.count, j.seed});
  }
  EXPECT_EQ(seen.size(), 4u);
  const std::string path = "base: " GRAINLAB_SOURCE_DIR "/configs/compression-base.yaml\n";
  const std::string shear_less = write_tmp("study_no_iso_base", "sample: {count: 500, seed: 3}\n"
                                                                "stages: [{name: shear, type: triaxial}]\n");
  expect_study_errors({
      {"study_prep_drain", prep + "axes: {drainage: [drained]}\n",
       "axes.drainage: sets the drainage of the base's shear stages, and the base"},
      {"study_prep_extra_drain", prep + "extra: [{drainage: undrained}]\n",
       "extra[0].drainage: sets the drainage of the base's shear stages"},
      {"study_prep_dir", prep + "axes: {direction: [extension]}\n", "axes.direction: sets the loading direction"},
      {"study_prep_rate", prep + "axes: {axial_strain_rate: [0.5]}\n", "axes.axial_strain_rate: sets axial_strain_rate"},
      {"study_prep_b", prep + "axes: {b: [0.5]}\n", "axes.b: sets b of the base's triaxial stages"},
      {"study_prep_csr", prep + "axes: {csr: [0.1]}\n", "axes.csr: sets the stress amplitude of a cyclic stage"},
      {"study_no_iso", "base: " + shear_less + "\n", "base: its stages must include an isotropic stage"},
      // p0 sets every isotropic stage: a loading path (50 ... 800 kPa and back) would be flattened
      {"study_path_p0", path + "axes: {p0: [100e3]}\n",
       "axes.p0: sets the pressure of every isotropic stage, and the base's"},
      {"study_path_extra_p0", path + "extra: [{p0: 100e3}]\n", "extra[0].p0: sets the pressure of every isotropic stage"},
  });
  // the seeds of a path are fine, and a base consolidating in stages to one pressure takes a p0 axis
  EXPECT_EQ(error("study_path_seeds", path + "axes: {seed: [1, 2]}\n"), "");
  EXPECT_EQ(error("study_paper_p0", "base: " GRAINLAB_SOURCE_DIR "/configs/paper/study-base.yaml\naxes: {p0: [100e3]}\n"),
            "");
}

// An axis left out takes the base's value: drainage too (quick-study-base.yaml shears drained), for the grid
// and for extra jobs.
TEST(Config, StudyDrainageDefaultsToTheBase) {
  const Study s = load_study(write_tmp("study_drain", "base: " GRAINLAB_SOURCE_DIR
                                                      "/configs/quick-study-base.yaml\naxes: {mu_r: [0.1]}\n"
                                                      "extra: [{mu_r: 0.2}]\n"));
  ASSERT_EQ(s.shears.size(), 2u);
  for (const StudyJob& j : s.shears) EXPECT_EQ(j.drainage, "drained") << j.name;
}

// `grainlab validate` of a study plans every job as it will run (plan_study): a shear on the radii its sample job
// draws (the sample file does not exist yet) from the p' its preparation leaves. The miniature's shears are the
// 0.002-0.004 in inertial number that configs/quick-study-base.yaml states, its six shears' steps add up, and a
// job that would stop at its start (a dt above the stable limit) is an error naming the job.
// The plan's inertial number of a study's tests is each test's own stage's: configs/shansep-rate-study.yaml shears at
// 0.5, 0.25 and 0.125/s after a K0 loading at 0.5/s (an axial_strain_rate axis keeps a K0 consolidation's rate), so
// its tests span a factor of 4 in I (the same p'_0 estimate, the seat's), and the loading's own I, the largest, is
// given apart (it was taken for every test's: 0.0021 for all three rates).
TEST(Config, StudyPlanGivesEachTestsOwnInertialNumber) {
  const StudyPlan sp = plan_study(load_study(GRAINLAB_SOURCE_DIR "/configs/shansep-rate-study.yaml"));
  ASSERT_GT(sp.inertial_min, 0);
  EXPECT_NEAR(sp.inertial_max / sp.inertial_min, 4.0, 1e-9);
  EXPECT_NEAR(sp.inertial_all_max, sp.inertial_max, 1e-9 * sp.inertial_max);  // the 0.5/s shear's, the loading's rate
  const StudyPlan iso = plan_study(load_study(GRAINLAB_SOURCE_DIR "/configs/iso-ocr-rate-study.yaml"));
  // (0.5/s against 0.0625/s: 8x; three seeds, whose samples' mean diameters differ by ~0.2 %: measured 8.015)
  EXPECT_NEAR(iso.inertial_max / iso.inertial_min, 8.0, 0.04);
}

TEST(Config, StudyPlanCoversEveryJob) {
  const StudyPlan sp = plan_study(load_study(GRAINLAB_SOURCE_DIR "/configs/quick-study.yaml"));
  EXPECT_GT(sp.inertial_min, 0.002);
  EXPECT_LT(sp.inertial_max, 0.0045);
  EXPECT_GT(sp.shear_steps_min, 0);
  EXPECT_LE(sp.shear_steps_min, sp.shear_steps_max);
  EXPECT_GE(sp.shear_steps_total, 6.0 * sp.shear_steps_min);
  EXPECT_LE(sp.shear_steps_total, 6.0 * sp.shear_steps_max);
  EXPECT_TRUE(sp.warnings.empty());
  const std::string base = write_tmp("study_plan_base", "sample: {count: 500, seed: 3}\nnumerics: {dt: 1.0e-3}\n"
                                                        "stages: [{type: isotropic}, {name: shear, type: triaxial}]\n");
  std::string e;
  try {
    plan_study(load_study(write_tmp("study_plan", "base: " + base + "\naxes: {mu_r: [0.1]}\n")));
  } catch (const std::exception& x) {
    e = x.what();
  }
  EXPECT_NE(e.find("(job sample_mur0.1_ebase_pbase_s3_n500): numerics.dt = 0.001 s is above the stable limit"),
            std::string::npos)
      << e;
  // A grading the sample job's 300 spheres miss (6.1 points at 0.8 mm: cli_grading_plan) is said once, of the sample
  // job: its shear jobs are planned on the same spheres.
  const std::string graded = write_tmp(
      "study_plan_graded", "sample: {count: 300, seed: 42, grading: {diameter: [0.4e-3, 0.6e-3, 0.8e-3, 1.0e-3, 1.2e-3], "
                           "passing: [0, 20, 55, 90, 100]}}\nstages: [{type: isotropic}, {name: shear, type: triaxial}]\n");
  const StudyPlan gp = plan_study(load_study(write_tmp("study_plan_g", "base: " + graded + "\naxes: {drainage: [drained, "
                                                                      "undrained]}\n")));
  ASSERT_EQ(gp.warnings.size(), 1u);
  EXPECT_EQ(gp.warnings[0].rfind("job sample_mur0_ebase_pbase_s42_n300: sample.grading: the 300 spheres drawn pass 61.1 %", 0),
            0u) << gp.warnings[0];
}

// A container's CPU quota (cgroup v2 cpu.max) as cores: usable_cores() takes the smaller of it and the affinity.
TEST(Config, CpuQuotaCountsCores) {
  EXPECT_EQ(cores_of_cpu_max("200000 100000\n"), 2);
  EXPECT_EQ(cores_of_cpu_max("150000 100000"), 2);  // 1.5 cores: rounded up (a warning at 2 threads would be noise)
  EXPECT_EQ(cores_of_cpu_max("50000 100000"), 1);
  EXPECT_EQ(cores_of_cpu_max("max 100000\n"), 0);  // no limit
  EXPECT_EQ(cores_of_cpu_max(""), 0);
  EXPECT_EQ(cores_of_cpu_max("100000 0"), 0);
  EXPECT_GE(usable_cores(), 1);
}

// The limits of cgroup v1 (RHEL 7 and 8, Ubuntu 20.04, a container on such a host) and v2, in the process's cgroup and
// its parents, on a mock of /sys/fs/cgroup: only v2's root cpu.max and memory.max were read, so `docker --cpus 2` on a
// v1 host of 64 cores started 64 threads.
TEST(Config, CgroupLimitsV1AndV2) {
  const fs::path root = test::scratch("cgroup");
  const auto put = [&](const std::string& rel, const std::string& text) {
    fs::create_directories((root / rel).parent_path());
    std::ofstream(root / rel) << text;
  };
  // v1, cpu and cpuacct mounted together: the job's quota 2.5 cores (rounded up), its parent unlimited
  put("cpu,cpuacct/cpu.cfs_quota_us", "-1\n");
  put("cpu,cpuacct/cpu.cfs_period_us", "100000\n");
  put("cpu,cpuacct/slurm/job7/cpu.cfs_quota_us", "250000\n");
  put("cpu,cpuacct/slurm/job7/cpu.cfs_period_us", "100000\n");
  put("memory/memory.limit_in_bytes", "9223372036854771712\n");  // v1's "no limit"
  put("memory/slurm/memory.limit_in_bytes", "8589934592\n");
  put("memory/slurm/job7/memory.limit_in_bytes", "17179869184\n");  // above its parent's: the parent's binds
  const std::string v1 = "12:memory:/slurm/job7\n4:cpu,cpuacct:/slurm/job7\n1:name=systemd:/x\n0::/\n";
  EXPECT_EQ(cgroup_cores(v1, root.string()), 3);
  EXPECT_EQ(cgroup_memory_limit(v1, root.string()), 8589934592.0);
  // a container's namespaced view: its path names a cgroup the mount does not show, its limit at the mount's root
  put("cpu,cpuacct/cpu.cfs_quota_us", "100000\n");
  EXPECT_EQ(cgroup_cores("4:cpu,cpuacct:/docker/abc\n", root.string()), 1);
  // v2: a parent's cpu.max binds where the cgroup's own says max
  put("a/cpu.max", "200000 100000\n");
  put("a/b/cpu.max", "max 100000\n");
  put("a/b/memory.max", "1073741824\n");
  EXPECT_EQ(cgroup_cores("0::/a/b\n", root.string()), 2);
  EXPECT_EQ(cgroup_memory_limit("0::/a/b\n", root.string()), 1073741824.0);
  // nothing there, or an unreadable text: no limit
  EXPECT_EQ(cgroup_cores("0::/none\n", (root / "missing").string()), 0);
  EXPECT_EQ(cgroup_memory_limit("garbage", root.string()), 0.0);
  // a path without its leading '/': read as it stands, and the walk ends (it looped forever, growing its list)
  EXPECT_EQ(cgroup_cores("0::a/b\n", root.string()), 0);
}

// The pace of a stage's output writes (series.csv, cycles.csv, run.h5 rewritten whole): every 20 rows, a minute for a
// slow run, never sooner than ten times the last write took.
TEST(Config, OutputWritesArePaced) {
  EXPECT_FALSE(output_flush_due(19, 1, 0.001));
  EXPECT_TRUE(output_flush_due(20, 1, 0.001));
  EXPECT_FALSE(output_flush_due(20, 0.05, 0.01)) << "a write of 10 ms waits 100 ms";
  EXPECT_TRUE(output_flush_due(40, 0.1, 0.01));
  EXPECT_FALSE(output_flush_due(1, 59, 0.001));
  EXPECT_TRUE(output_flush_due(1, 60, 0.001)) << "a slow run's row is written within a minute";
  EXPECT_FALSE(output_flush_due(0, 1e4, 0.001)) << "nothing new: nothing to write";
  EXPECT_FALSE(output_flush_due(1, 61, 10)) << "a write of 10 s waits 100 s";
  EXPECT_TRUE(output_flush_due(1, 100, 10));
}

// Every run's build string names the source commit it was built from (scripts/source_commit.cmake, at every build):
// git's own describe of the source tree, less a -dirty mark that an edit since the build may have changed.
TEST(Build, NamesItsSourceCommit) {
  const std::string commit = source_commit(), line = version_line();
  EXPECT_NE(line.find("(source " + commit + "); Kokkos "), std::string::npos) << line;
  std::string git;
  if (FILE* p = ::popen("git -C '" GRAINLAB_SOURCE_DIR "' describe --always --abbrev=12 2>/dev/null", "r")) {
    char buf[256];
    while (std::fgets(buf, sizeof buf, p)) git += buf;
    if (::pclose(p) != 0) git.clear();
  }
  while (!git.empty() && git.back() == '\n') git.pop_back();
  if (git.empty()) {
    EXPECT_EQ(commit, "unknown") << "no git, or not a checkout";
  } else {
    EXPECT_EQ(commit.substr(0, commit.find("-dirty")), git);
  }
}
