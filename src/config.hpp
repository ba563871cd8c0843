#pragma once
// Run configuration (YAML). Every error names the file, the key and the allowed range; unknown keys
// are errors too (a typo must not silently fall back to a default).
#include <yaml-cpp/yaml.h>

#include <optional>
#include <string>
#include <vector>

#include "engine.hpp"
#include "packing.hpp"

namespace grainlab {

struct ConfigError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Cyclic: triaxial loading whose axial walls reverse at +-q_amplitude (stress reversal, the cyclic liquefaction
// test) or +-strain_amplitude, for `cycles` cycles or until |eps_a| reaches max_axial_strain (choice, beyond SPEC §6.3);
// oedometric (the lateral walls held): the cyclic oedometer, reversing at sigma_v,0 +- sigma_v_amplitude or at
// +-strain_amplitude.
enum class StageType { Isotropic, Triaxial, Cyclic };
// The lateral boundary of a shear stage: drained, the lateral walls servoed to sigma_3 (SPEC §6.3); undrained, placed
// to keep the volume (SPEC §6.3); oedometric (beyond SPEC, triaxial stages), held where the stage found them: zero
// lateral strain, the oedometer / K0 test, whose sigma_h / sigma_v is the earth-pressure coefficient at rest.
enum class Drainage { Undrained, Drained, Oedometric };
inline const char* drainage_name(Drainage d) {
  return d == Drainage::Undrained ? "undrained" : d == Drainage::Drained ? "drained" : "oedometric";
}

struct StageConfig {
  std::string name;
  StageType type = StageType::Isotropic;
  Real mu = 0.5, mu_r = 0.0, damping = 0.7;
  // isotropic consolidation (SPEC §6.2)
  Real pressure = 190e3;           // p'_0 target                                   [Pa]
  Real pressure_tolerance = 0.01;  // |p - p0| / p0                                  [-]
  long pressure_ramp_steps = 0;    // servo target rises linearly from 0 to `pressure` over this many
                                   // steps of the stage (0 = the full target from the first step)
  // The particles follow the servo walls affinely (Engine::set_affine_box; choice, beyond SPEC §6.2, whose walls alone
  // compress the sample): a frictional gas then jams homogeneously instead of in a dense crust along the walls
  // around a looser core. Off by default: SPEC's protocol and the bits of earlier runs.
  bool affine = false;
  Real ufr_tolerance = 0.01;       // unbalanced-force ratio                         [-]
  Real ke_tolerance = 1e-4;        // kinetic / elastic energy                       [-]
  Real servo_gain = 0.5;           // see WallControl::gain                          [-]
  Real servo_integral = 0;         // see WallControl::integral; 0 = off, [0, 0.5]   [-]
  // triaxial shear (SPEC §6.3)
  Drainage drainage = Drainage::Undrained;
  // [1/s]. 0 on a triaxial stage: a rest (choice, beyond SPEC §6.3): the axial walls held where they are, the lateral
  // walls as the drainage holds them (drained: servoed to the start's sigma_3; undrained: the volume; oedometric:
  // held), for max_steps steps, the stage done then. The sample relaxes at fixed strain (the stress relaxation test), and
  // the stage after it starts from the state it rests in: a probe from a sheared state starts at rest, not with the
  // walls' dynamic overstress and the damping's drag of the loading.
  Real axial_strain_rate = 1.0;
  Real max_axial_strain = 0.05;    // [-] cyclic: the stage ends when |eps_a| reaches it (large strain, liquefaction)
  // drained shear: the run stops (exit 3, like a blow-up) when a lateral wall stress on a series row is further than
  // this from its servo target, relative (Laboratory::servo_error): sigma_3 = p'_0 not held is not the test asked for,
  // and a servo that fell this far behind its walls' speed (true triaxial at large b and strain moves the y walls out
  // fastest) squeezed the packing to a blow-up in the one case seen (b = 1, mu_r = 0 at 1/s, configs/true-triaxial-study.yaml). (choice)
  Real max_servo_error = 0.25;     // [-]
  // triaxial: `direction: extension` moves the axial walls apart (eps_a < 0, q < 0: the triaxial extension test at
  // constant sigma_3 drained, constant volume undrained), to eps_a = -max_axial_strain (choice, beyond SPEC §6.3:
  // the critical state in extension, M_e = 6 sin(phi) / (3 + sin(phi)), against compression's 6 sin(phi) / (3 - sin(phi)))
  bool extension = false;
  // triaxial, drained, compression: the intermediate principal stress ratio b = (sigma_2 - sigma_3) / (sigma_1 - sigma_3)
  // held through the stage (choice, beyond SPEC §6.3: the true-triaxial test): the x walls' servo target is
  // sigma_3 + b (sigma_z - sigma_3), sigma_z as the step finds it (the wall loads the servo used), sigma_y = sigma_3 = p'_0.
  // 0: the standard test (sigma_x = sigma_y); 1: sigma_x = sigma_z, the Lode angle of triaxial extension under
  // compression's kinematics.
  Real b = 0;
  // triaxial, drained: the stress path the lateral servo follows (choice, beyond SPEC §6.3's constant sigma_3).
  // constant_p: sigma_3 = (3 p'_0 - (1 + b) sigma_z) / (2 - b) and sigma_2 = sigma_3 + b (sigma_z - sigma_3), so
  // p' = p'_0 through the stage at the stage's b (in extension sigma_x = sigma_y = (3 p'_0 - sigma_z) / 2), sigma_z as
  // the step finds it: the constant-mean-stress tests of the b-effect literature (Thornton 2000, Geotechnique 50(1);
  // Ng 2004, J. Eng. Mech. 130(3)), whose results at several b are then at one p' and one void-ratio state.
  bool constant_p = false;
  // triaxial, drained or undrained: stress_path: plane_strain (choice, beyond SPEC §6.3: the plane-strain or biaxial
  // test). The x walls are held where the stage finds them (zero strain along x, as an oedometer holds both), the y
  // walls servo-held at their start's stress (drained) or placed to keep the volume (undrained), the axial walls as
  // SPEC's: sigma_x is the intermediate stress the sample develops, and b the test's result, not its setting
  // (Cornforth 1964; Bolton 1986 gives plane strain's own phi'_max - phi'_cs = 5 I_R and 0.8 psi_max). In compression
  // the y walls' stress is sigma_3, b = (sigma_x - sigma_y) / (sigma_z - sigma_y); in extension (the passive case) it
  // becomes sigma_1 as sigma_z falls, b = (sigma_x - sigma_z) / (sigma_y - sigma_z). Undrained, the cell pressure
  // acts on the y faces alone: u = u_0 + sigma'_y,0 - sigma'_y (Laboratory::measure), 0 at the start.
  bool plane_strain = false;
  // triaxial, drained: a K path (choice, beyond SPEC §6.3), the anisotropic consolidation of a CAU / CAD test: the
  // lateral servo holds sigma_x = sigma_y = k_ratio sigma_z, sigma_z as the step finds it, once the path meets that
  // line, and sigma_3 of the start (p'_0 - q_0/3) until then: max(sigma_3,0, K sigma_z) loading, min(...) unloading
  // (extension). A target that jumped to K sigma_z at the start would throw the lateral walls off an isotropic sample
  // (190 -> 133 kPa at K = 0.7), so a K-consolidation from a seating pressure first loads at constant sigma_3, as a
  // triaxial cell's does. With sigma_v (or ocr) it ends at a vertical stress. 0: off.
  Real k_ratio = 0;                // [-] (0, 1]
  // triaxial, drained: a linear stress path (choice, beyond SPEC §6.3), the stress-path cell's "dsigma_r / dsigma_a":
  // the lateral servo holds sigma_3 = sigma_3,0 + lateral_slope (sigma_z - sigma_z,0) from the start's stresses
  // (sigma_3,0 = p'_0 - q_0/3, sigma_z,0 = p'_0 + 2 q_0/3), sigma_z as the step finds it; sigma_2 from b as elsewhere.
  // dq/dp' = 3 (1 - slope) / (1 + 2 slope): 0 is the standard drained test (dq/dp' = 3), -1/2 constant p', 1 an
  // isotropic loading driven by the axial walls, beyond 1 or below -1/2 q falls or p' falls as the axial stress rises.
  // The axial walls are strain-controlled, so every direction but pure lateral loading (dsigma_a = 0) is reachable:
  // with direction: extension the path runs the other way. Small stress probes along several slopes from one state
  // are the response envelope of that state (Calvetti et al. 2003, Geotechnique 53(5); Tamagnini et al. 2005).
  // With sigma_v (or ocr, q, stress_ratio) it ends at a stress. Empty: off.
  std::optional<Real> lateral_slope;  // [-] [-5, 5]
  // triaxial, drained: a stress probe's direction (choice, beyond SPEC §6.3), the angle theta of (sqrt2 dsigma_r,
  // dsigma_a) in the Rendulic plane, counterclockwise from the sqrt2 sigma_r axis, in degrees: 90 axial loading at
  // constant sigma_3, 270 axial unloading, 35.26 isotropic loading, 125.26 loading at constant p'. It sets the linear
  // path and the direction, lateral_slope = cot(theta) / sqrt2 and extension where sin(theta) < 0: one number per
  // probe, as a study's stage axis sweeps (Calvetti et al. 2003's response envelopes; Darve's directional analysis).
  // Empty: off.
  std::optional<Real> stress_direction;  // [deg] [0, 360], not within 8.05 of 0, 180, 360
  // triaxial, oedometric: a stress end, as an oedometer loads and unloads (choice, beyond SPEC §6.3): the stage ends on
  // the first step whose sigma_z of the walls reaches sigma_v (at or above it in compression, at or below in extension),
  // or, unloading, falls to sigma_v,max / ocr (sigma_v,max the largest sigma_z of the series rows of the stages before,
  // as summary.json's OCR takes it); max_axial_strain stays the stage's end should the stress not come first. 0: off.
  Real sigma_v = 0;                // [Pa]
  Real ocr = 0;                    // [-] (> 1, extension only)
  // triaxial, any drainage: a deviator-stress end (choice, beyond SPEC §6.3): the stage ends on the first step whose q of
  // the walls (sigma_z - (sigma_x + sigma_y) / 2, the wall loads the servo used) reaches q_end: at or above it in
  // compression, at or below in extension. A drained loading to a q, an extension back to q = 0 and a reloading is the
  // unload-reload loop of a triaxial cell, whose secant is E_ur (summary.json's E_sec of the unloading stage). q is not
  // monotonic along a shear (a dense sample's peak): max_axial_strain stays the end should q not come. Empty: off (0 is
  // an end: an unloading to the isotropic stress).
  std::optional<Real> q_end;       // [Pa]
  // The same end at a stress ratio eta = q/p' of the walls (q >= eta p' in compression, q <= eta p' in extension): the
  // end that scales with the confining pressure, as a study's p0 axis does (an unload-reload loop at the same share of
  // the strength at each p'_0).
  std::optional<Real> eta_end;     // [-]
  // The end of a stress probe (choice, beyond SPEC §6.3): the stage ends on the first step whose stress increment from
  // the start's, |sigma - sigma_0| = sqrt(dsigma_x^2 + dsigma_y^2 + dsigma_z^2) of the walls (sigma_0: sigma_3,0 =
  // p'_0 - q_0/3 laterally, sigma_z,0 = p'_0 + 2 q_0/3 axially, as the lateral targets take it), reaches it: one end
  // for probes of every direction (lateral_slope, direction), loading or unloading, where a sigma_v or a q differs
  // between them (and a q does not change along slope 1). Empty: off.
  std::optional<Real> dsigma_end;  // [Pa] (> 0)
  bool stress_ended() const { return sigma_v > 0 || ocr > 0 || q_end || eta_end || dsigma_end; }
  // cyclic (StageType::Cyclic): compression first; a cycle is 0 -> +A -> -A -> 0 of the controlled quantity
  long cycles = 1;                 // [-]
  Real q_amplitude = 0;            // A in deviator stress q (stress reversal; 0: csr's or strain reversal)   [Pa]
  // A as a cyclic stress ratio, A = 2 csr p'_c, p'_c taken by the run at the stage's start: the p' its undrained
  // loading began from (the stage's own p'_0, or an undrained stage's before it: Laboratory::start_stage), a drained
  // stage's p'_0. The CSR of the cyclic liquefaction test then holds for the stress the sample has, not a pressure the
  // config names: after a K0 consolidation (p'_0 = (1 + 2 K0) sigma'_v / 3), a reconsolidation, or a servo's 1e-4.
  Real csr = 0;                    // [-] (0: q_amplitude's or strain reversal)
  Real strain_amplitude = 0;       // A in axial strain eps_a (strain reversal; 0: stress reversal)  [-]
  bool stress_reversal() const { return q_amplitude > 0 || csr > 0; }
  // A in the walls' vertical stress sigma_z about the stage's sigma_z,0 (an oedometric cyclic stage's stress reversal:
  // the cyclic oedometer, whose controlled stress is the vertical one; 0: strain reversal)   [Pa]
  Real sigma_v_amplitude = 0;
  bool sigma_v_reversal() const { return sigma_v_amplitude > 0; }
  // Liquefaction criteria of a cyclic stage (recorded as the cycle number N at which each is first met; neither ends
  // the stage): initial liquefaction, r_u = u / p'_0 reaching liquefaction_ru (undrained stages), and the
  // double-amplitude axial strain (the peak-to-peak eps_a of a half cycle) reaching liquefaction_da_strain, ASTM
  // D5311's 5 % (choice, beyond SPEC §6.3).
  Real liquefaction_ru = 0.95;         // [-]
  Real liquefaction_da_strain = 0.05;  // [-]
  long max_steps = 1000000;
  long check_every = 200;          // steps between equilibrium checks
  // isotropic: search the stage's mu so the stage ends at this void ratio (0 = off)
  Real target_e0 = 0;
  Real target_e0_tolerance = 0.003;
  Real mu_max = 1.0;               // upper end of the search bracket [0, mu_max]
  int max_trials = 10;
  bool save_sample = true;         // isotropic: write sample_<name>.h5 at the end (reusable)
};

struct RunConfig {
  std::string path;
  PackingSpec packing;
  Real density = 2650, density_scaling = 1;
  EngineParams engine;
  std::vector<StageConfig> stages;
  std::string sample_file;          // a saved sample (sample_<stage>.h5) instead of generating one
  std::string out_dir = "runs/default";
  long output_every = 1000;        // steps between rows of series.csv
  Real snapshot_strain = 0.01;     // axial-strain interval between snapshots in triaxial stages (0: off)
  long checkpoint_every = 100000;  // steps between checkpoints (0: off)
  Real checkpoint_minutes = 10;    // wall-clock minutes between checkpoints (0: off)
  int keep_checkpoints = 2;
  HealthLimits health;             // blow-up detection limits (numerics.max_overlap, max_step_move)
};

RunConfig load_run_config(const std::string& path);
// The same from a parsed document; `path` names it in errors and anchors a relative sample.file.
RunConfig parse_run_config(const YAML::Node& root, const std::string& path);
// Reads a YAML file after screening it (size, NUL bytes, nesting depth); errors name the file.
YAML::Node load_yaml_screened(const std::string& path);
// A path from a config or study file expanded as a shell would: $NAME and ${NAME} (a cluster's $SCRATCH), then a
// leading ~ or ~user (that home directory). No shell reads the file: `dir: ~/runs/a` made a directory named "~" in the
// working directory (which `rm -rf ~` would then mistake for home), `dir: $SCRATCH/a` one named "$SCRATCH". `where`
// ("file: key") names the path in the error where a variable is not set or the home cannot be found.
std::string expand_path(const std::string& path, const std::string& where);
// A study file (top-level `base:`) rather than a run config.
bool is_study_file(const std::string& path);
// A YAML mapping with `stages` (what `grainlab study` of a run config is told).
bool is_run_config_file(const std::string& path);
// The configuration with every default filled in, as YAML (stored in every run's files).
std::string resolved_config_yaml(const RunConfig& c);
// A number as YAML text: the shortest that reads back to the same double, with ".0" before a bare exponent so
// that YAML 1.1 readers (PyYAML) read a float too: 0.3, 190000, 1.0e+08, 2.5e-05.
std::string yaml_number(double v);

}  // namespace grainlab
