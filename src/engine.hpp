#pragma once
// Host orchestration of one DEM system: owns the device state, runs the step (SPEC §2-5) and the wall
// controllers (SPEC §3), and exposes deterministic diagnostics. No physics lives here: it calls the
// kernels in kernels/.
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "../kernels/analysis.hpp"
#include "../kernels/dem.hpp"

namespace grainlab {

using Vec3d = std::array<Real, 3>;

struct ParticleSetup {
  std::vector<Vec3d> x, v, w;  // v and w may be empty (zero)
  std::vector<Real> r;
  Real density = 2650;         // [kg/m^3]
  Real density_scaling = 1;    // s >= 1 multiplies m and I (SPEC §1)
};

enum class WallMode { Fixed, Velocity, Servo };

struct WallControl {
  WallMode mode = WallMode::Fixed;
  Real velocity = 0;       // along the inward normal (positive = into the sample)   [m/s]
  Real target_stress = 0;  // servo target (compression positive)                     [Pa]
  Real gain = 0.5;         // servo relaxation: fraction of the force error corrected per step, using
                           // the measured wall stiffness (choice; bounded by servo_max_step)   [-]
  Real area = 0;           // used only when the walls are not a box                  [m^2]
  // Integral action (choice, beyond SPEC §3; 0 = off, the proportional servo alone): each step adds this
  // fraction of the step's proportional displacement to `drift`, a displacement the wall then keeps making
  // every step. A proportional servo follows a target that needs its wall to keep moving (a drained shear's
  // lateral walls, out as the sample shortens and dilates) only by keeping the error that makes it move:
  // e / sigma = v dt / (gain delta_w), delta_w the mean wall overlap. `drift` learns that speed instead, so the
  // error decays to zero on a steady ramp. On a wall that answers its own stiffness at once the loop is
  // e' = (1 - gain) e - K drift, drift' = drift + integral gain e / K: stable for integral < 1 (the product of
  // the roots is 1 - gain + integral * gain). A packing answers slower than its wall contacts, so stages take
  // [0, 0.5] (config.cpp): on the tests' sample 0.1 removes a drained shear's lag (Lab.IntegralServoRemovesThe-
  // ProportionalLag), and 0.5 made the 2 000-sphere b = 1 shear ring (1.1 % rms against 0.19 % at 0.1).
  Real integral = 0;       // [-]
  Real drift = 0;          // state: the learned displacement a step (inward positive)   [m]
};

struct EngineParams {
  ContactParams contact;      // contact.dt = 0: dt = dt_factor * sqrt(m_min / k_max)
  Real dt_factor = 0.2;       // SPEC §4 safety factor f
  Real E_wall = 0;            // 0: same as contact.E                                    [Pa]
  Real damping = 0.7;         // Cundall alpha                                           [-]
  Real skin = 1e-4;           // Verlet skin                                             [m]
  // Two-level list (choice, beyond SPEC §5; perf/NOTES.md attempt 18): the kernels stream an inner list
  // of the Verlet pairs closer than r_i + r_j + inner_skin * skin, filtered from the Verlet list (no cell
  // search) whenever a particle moved more than inner_skin * skin / 2 since the last filter. The Verlet
  // list itself keeps SPEC's skin and rebuild rule. 0 = off: the kernels stream the Verlet list. Either
  // way the dynamics are the same bits (the list holds every touching pair; rows are sorted).
  // 0.05 since session 11 (was 0.1): with the pair-lane kernel a listed non-touching pair costs a whole
  // lane of the law, so the smaller list pays for more filters (race: 1.037x at 1 thread, 1.031x at 2;
  // configs/quick.yaml, a dynamic run, the same within noise; perf/NOTES.md attempt 29).
  Real inner_skin = 0.05;     // fraction of skin, [0, 1)                                [-]
  Real servo_max_step = 1e-3; // a servoed wall moves at most this fraction of r_min per step (SPEC §3)
  // The fines' mass scaling (choice, beyond SPEC §1's one factor s; 0 = off): a sphere smaller than this radius
  // weighs as a sphere of this radius (its m and I = 2/5 m r^2 times (r_f / r)^3, on top of s), so the stable step
  // (SPEC §4, set by the lightest sphere against the stiffest spring) is that of a sphere of radius r_f. A wide
  // grading's step is the fines', most of which are rattlers in the coarse grains' voids (configs/README.md).  [m]
  Real fines_mass_radius = 0;
  // Which contact kernel (kernels/dem.hpp): both give the same bits, so this is a speed choice only; the
  // tests run both. Lanes where it is built, else Row.
  PairKernel pair_kernel = kDefaultPairKernel;
};

// SPEC §4: the stable time step of a set of spheres, from their radii alone (no positions): what the engine
// takes, and what `grainlab validate` and a run's start check before anything is placed or written. One
// formula for both, so the two agree to the bit.
struct StableStep {
  Real trans = 0;      // sqrt(m_min / k_max)                                       [s]
  Real roll = 0;       // sqrt(I_min / k_r), the rolling spring on the lightest inertia [s]
  Real m_min = 0, k_max = 0;
  Real limit(bool rolling) const { return rolling ? std::min(trans, roll) : trans; }
};
// SPEC §1: m = 4/3 pi r^3 rho, times the density scaling factor.
inline Real sphere_mass(Real r, Real density, Real density_scaling) {
  return Real(4.0 / 3.0 * M_PI * r * r * r * density * density_scaling);
}
// The mass the engine gives a sphere of radius r: sphere_mass, a sphere under fines_mass_radius weighing as one of
// that radius (EngineParams::fines_mass_radius; 0: SPEC §1's mass, to the bit).
inline Real particle_mass(Real r, Real density, Real density_scaling, Real fines_mass_radius) {
  return sphere_mass(r < fines_mass_radius ? fines_mass_radius : r, density, density_scaling);
}
StableStep stable_step(const std::vector<Real>& r, Real density, Real density_scaling, const EngineParams& p);
// The step a run takes: p.contact.dt if set (refused above the limit, with the numbers and the fix), else
// p.dt_factor times the limit. Rolling counts when p.contact.mu_r > 0. Throws ParameterError.
Real choose_time_step(const StableStep& s, const EngineParams& p);

struct Diagnostics {
  Real kinetic = 0;        // translational + rotational (half-step velocities)   [J]
  Real kinetic_skeleton = 0;  // translational KE of particles touching something (sphere or wall): the
                              // equilibrium measure. A rattler's free flight and any free spin cannot
                              // be damped (Cundall damping acts on forces) and carry no stress  [J]
  // kinetic_skeleton less the part of the skeleton's motion that a homogeneous deformation explains: the
  // translational KE of its velocities about their mass-weighted least-squares affine field v = a + L x (choice,
  // beyond SPEC §6.3, whose quasi-static check names the kinetic / elastic ratio without saying about what). A
  // specimen the walls deform steadily moves affinely as a whole; that motion is the imposed loading, not inertia,
  // and grows with the wall speeds (86 % of kinetic_skeleton at 35 % strain in a drained b = 1 test). [J]
  Real kinetic_fluct = 0;
  Real potential = 0;      // normal + tangential + rolling + wall springs        [J]
  int contacts = 0;        // touching sphere-sphere pairs
  int sliding = 0;         // of which at the Coulomb cap
  int rolling_sliding = 0; // of which at the rolling cap
  Real mean_contact_force = 0;  // [N]
  Real unbalanced_ratio = 0;    // mean |F_particle| / mean |F_contact| (PFC's definition)
};

// Everything that determines the future of a run (SPEC §2: history belongs to the pair), on the host.
// Capturing and restoring gives bitwise the same continuation (tests/test_restart.cpp).
struct EngineState {
  long step = 0;
  Real time = 0, dt = 0;
  Real mu = 0, mu_r = 0, damping = 0;
  std::vector<Vec3d> x, v, w, f, t;
  std::vector<Real> r;
  std::vector<int> pair_i, pair_j;  // pairs carrying history, sorted by (i, j)
  std::vector<Vec3d> ft, mr;
  std::vector<std::uint8_t> flags;
  WallSet walls;
  std::array<WallControl, kMaxWalls> control{};
  WallLoads loads;
  bool walls_are_box = false;
};

// Numerical blow-up detection (issue 7): what is checked and the limits.
struct HealthLimits {
  Real max_overlap = 0.2;    // delta / min(r_i, r_j) of any pair, or delta / r against a wall
  Real max_step_move = 0.5;  // |v| dt / r_min and |w| dt (rad): beyond this contacts are tunnelled
};
struct HealthReport {
  bool ok = true;
  std::string what;  // one line: step, particle ids, offending quantity, suggested dt
  bool squeeze = false;  // the overlap limit passed in a slow squeeze: the load, not the time step (the caller may
                         // know which load: Laboratory::assert_healthy)
};

// Thrown for a parameter outside its valid range; the message says which, the range, and a fix.
struct ParameterError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// Six axis-aligned walls with inward normals: 0 -x, 1 +x, 2 -y, 3 +y, 4 -z, 5 +z.
WallSet make_box_walls(const Vec3d& lo, const Vec3d& hi);
// make_box_walls' inverse: the box of six walls it made (false for another set of walls)
bool box_of_walls(const WallSet& ws, Vec3d& lo, Vec3d& hi);

class Engine {
 public:
  Engine(const ParticleSetup& setup, const EngineParams& params, const WallSet& walls, bool walls_are_box);

  // One step = evaluate() then advance(). Between the two, positions, pair forces, history and wall
  // loads all belong to the same instant t: the place to measure (analysis, snapshots).
  // step() computes the same bits as evaluate() + advance() through gather_integrate_and_load_walls: on host
  // backends the wall loads come from the integration's own pass (one pass over the particles fewer); on a
  // GPU they stay on the device until one copy brings them over with the displacement max.
  // step() does not update forces()/torques() (they are output, not state: the fused step skips their
  // stores, perf/NOTES.md attempt 27); advance() does, and so does diagnostics() between the halves.
  void step() { fused_step(nullptr); }
  // step(), bitwise, returning damping_moment(c) of its instant: on a host backend from the fused pass itself (three
  // more sums in it, no gather pass of its own), on a GPU as evaluate(), damping_moment(c), advance(). A cyclic
  // stage's loops less the drag take it every step (CycleLoop).
  Vec3d step_measuring_drag(const Vec3d& c);
  void evaluate();
  void advance() { advance_impl(true); }
  void run(long nsteps) {
    for (long s = 0; s < nsteps; ++s) step();
  }

  // Stage parameters (SPEC §6: each stage sets its own mu, mu_r, damping).
  void set_friction(Real mu, Real mu_r);
  void set_damping(Real alpha) { params_.damping = alpha; }
  void set_rebuild_every_step(bool on) { rebuild_every_step_ = on; }
  // Affine box (beyond SPEC §6.2; an isotropic stage's `affine`): after the walls move, every position is remapped
  // with the box (remap_affine), so a loose gas is compressed homogeneously and jams everywhere at once. Without it a
  // frictional gas jams first in a crust along the walls that then shields the core: 10 000 spheres consolidated at
  // mu = 0.5 end with solid fraction 0.62 one to three diameters from the walls and 0.58 at the centre. Box walls only.
  // The tangential springs grow from relative velocities (SPEC §2), which the remap leaves alone: they see none of its
  // relative motion, normal to each contact where the axes scale alike (the isotropic servo), as in LAMMPS.
  void set_affine_box(bool on);
  bool affine_box() const { return affine_box_; }

  const EngineParams& params() const { return params_; }
  Real dt() const { return params_.contact.dt; }
  Real critical_dt() const { return dt_crit_; }  // stable limit for the current features (f = 1)
  Real stable_dt(bool rolling) const { return rolling ? std::min(dt_trans_, dt_roll_) : dt_trans_; }
  Real time() const { return time_; }
  long step_count() const { return step_; }
  int num_particles() const { return P_.n; }
  Real r_min() const { return r_min_; }
  Real r_max() const { return r_max_; }

  WallSet& walls() { return walls_; }
  const WallSet& walls() const { return walls_; }
  WallControl& wall_control(int k) { return control_.at(k); }
  const WallLoads& wall_loads() const { return loads_; }
  // The wall loads of the positions as they are (no step, nothing else changed): for a state that carries no record of
  // them, a packing imported from elsewhere, whose first stage measures its stress from them (Laboratory::build_engine).
  void load_walls_now();
  bool walls_are_box() const { return box_; }
  Real wall_position(int k) const;  // box walls: the coordinate of the plane along its axis
  void set_wall_position(int k, Real pos);
  Real wall_area(int k) const;
  Real wall_stress(int k) const { return loads_.force[k] / wall_area(k); }
  Real box_volume() const;
  // The solid volume inside the box [lo, hi]: each sphere's part in it, exact (sphere_volume_in_box: caps, and the
  // octants of a ball for a sphere on an edge or a corner). The interior void ratio's solids (series e_inner) and the
  // core's (Laboratory::grading). Centre counting, which it replaces, is unbiased but counts a cut sphere whole or not
  // at all: in the central eighth of a 10 000-sphere sample that made e wrong by about 0.02, the size of the grading it
  // is meant to show.
  Real solid_volume_in(const Vec3d& lo, const Vec3d& hi);

  Diagnostics diagnostics();
  // Checks the current state for NaN/Inf, excessive overlaps, escaped particles and tunnelling speeds.
  HealthReport check_health(const HealthLimits& lim) const;
  // The deepest sphere-sphere overlap over the listed pairs, as delta / min(r_i, r_j) (the measure of
  // numerics.max_overlap), and its pair; {0, -1, -1} without pairs. Lowest pair index on ties.
  struct DeepestOverlap {
    Real ratio = 0;
    int i = -1, j = -1;
  };
  DeepestOverlap deepest_overlap() const;
  // SPEC §7 descriptors of the current evaluation (call between evaluate() and advance() for
  // positions and forces of one instant). Volume: the box's, or `volume` when given.
  Descriptors analyze(Real volume = 0);
  // The stress of the spheres whose centres lie in the box [lo, hi]: each one's Love-Weber moment sum over its
  // contacts, sum_c (x_c - x_i) (x) f_c, over the box's volume (Christoffersen et al. 1981; Bagi 1996). A contact's
  // branch vector splits at the contact point, levers r_i - delta/2 and r_j - delta/2 along n, so a box around every
  // centre gives analyze()'s sigma (its symmetric part, compression positive) and boxes that tile the sample add up
  // to it. Sphere-wall contacts are not counted: the interior box it is meant for is inset from the walls by more
  // than a radius. Zero for an empty box.
  Sym stress_in(const Vec3d& lo, const Vec3d& hi);
  // The local damping's drag (SPEC §4) as a first moment about the point c: per axis a, sum_i (x_i - c)_a d_i,a, where
  // d_i = CundallDamping::damped(F_i, v_i, alpha) - F_i is the force the damping adds in the next kick (F_i the
  // undamped total force at this instant, v_i = v(t - dt/2)). Why: the first moments of the kick balance,
  //   sum_i (x_i - c) (x) m_i a_i = sum_c d^c (x) f^c + sum_i (x_i - c) (x) f_i^walls + sum_i (x_i - c) (x) d_i,
  // so about the box's centre, over its volume V, the walls' mean stress along an axis is the contacts' stress with
  // the sphere-wall contacts (analyze()'s sigma_walls, levers to the contact point; the remaining delta^2/2 terms are
  // O(delta/r)) plus this drag minus the inertial term. On a flowing sample the drag grows with the sample's length
  // (configs/damping-drag.yaml): Laboratory::row's series p_drag, q_drag. Between evaluate() and advance() only
  // (std::logic_error otherwise); zero without damping.
  Vec3d damping_moment(const Vec3d& c);

  const Particles& particles() const { return P_; }
  const PairList& pairs() const { return lists_[cur_]; }
  const PairHistory& history() const { return hist_[cur_]; }
  const PairForces& pair_forces() const { return pf_; }
  int rebuild_count() const { return rebuilds_; }   // Verlet list builds (cell search)
  int refilter_count() const { return refilters_; } // inner list filters between builds
  bool inner_list() const { return params_.inner_skin > 0; }
  // The list built with SPEC §5's skin (pairs() is the inner list when inner_skin > 0).
  const PairList& verlet_pairs() const { return inner_list() ? outer_ : lists_[cur_]; }
  const NeighborStats& last_build() const { return nstats_; }

  // Host copies of the state (tests and output).
  std::vector<Vec3d> positions() const { return to_host(P_.x); }
  std::vector<Vec3d> velocities() const { return to_host(P_.v); }
  std::vector<Vec3d> angular_velocities() const { return to_host(P_.w); }
  // Total (undamped) force and torque on each particle at the last instant that advance(), or
  // diagnostics() between evaluate() and advance(), gathered; step() leaves them as they were.
  std::vector<Vec3d> forces() const { return to_host(P_.f); }
  std::vector<Vec3d> torques() const { return to_host(P_.t); }
  template <class V>
  static std::vector<Vec3d> to_host(const V& v);  // VecView or PairVecView
  // Force on j of every listed pair; meaningful where the pair's flags have kTouching.
  std::vector<Vec3d> contact_forces() const;

  EngineState capture() const;
  // Restores a captured state of the same particle set (same count and radii); throws otherwise.
  void restore(const EngineState& s);

 private:
  // Contact forces and wall loads at the start positions without advancing history (dt = 0), so the
  // first servo move and diagnostics have loads to read.
  void evaluate_forces();
  void advance_impl(bool store_forces);
  void rebuild();   // Verlet list (and inner list) from the current positions, history carried over
  void refilter();  // inner list only, from the current Verlet list
  // Builds the kernels' next list into lists_[next] from the current positions.
  void build_lists(int next);
  // Makes lists_[next] current: history carried over from (old, old_h) by pair identity, x_ref = x.
  void install(int next, const PairList& old, const PairHistory& old_h);
  void move_walls();
  void fused_step(DragMeasure* drag);  // step(); with drag, the drag's moment too (host backends)
  void finish_step(Real maxd2);  // steps 4-5 of a step after the integration (time, walls, lists)

  EngineParams params_;
  Particles P_;
  PairList lists_[2];  // the kernels' list (current and next); the inner list when inner_skin > 0
  PairList outer_;     // the Verlet list when inner_skin > 0 (no transposed index, no history)
  PairHistory hist_[2];
  PairForces pf_;
  int cur_ = 0;
  CellGrid grid_;
  NeighborStats nstats_;
  DeterministicSum red_;
  WallSet walls_;
  std::array<WallControl, kMaxWalls> control_{};
  WallLoads loads_;
  bool box_ = false;
  bool rebuild_every_step_ = false;
  bool affine_box_ = false;
  bool evaluated_ = false;
  bool forces_current_ = false;  // P.f, P.t belong to the last evaluated instant (see forces())
  int rebuilds_ = 0;
  int refilters_ = 0;
  Real outer_drift_ = 0;  // bound on any displacement since the Verlet build, from the finished filter
                          // intervals (the sum of their maximum displacements)               [m]
  Real r_min_ = 0, r_max_ = 0, dt_crit_ = 0, dt_trans_ = 0, dt_roll_ = 0, time_ = 0;
  long step_ = 0;
};

}  // namespace grainlab
