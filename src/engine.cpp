#include "engine.hpp"
#include "../kernels/huge_pages.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace grainlab {

WallSet make_box_walls(const Vec3d& lo, const Vec3d& hi) {
  WallSet ws;
  ws.count = 6;
  for (int a = 0; a < 3; ++a) {
    Vec3 n;
    n = Vec3(a == 0, a == 1, a == 2);
    ws.w[2 * a].n = n;  // lower face, normal +e_a: n.x = lo
    ws.w[2 * a].offset = lo[a];
    ws.w[2 * a + 1].n = -n;  // upper face, normal -e_a: -x_a = -hi
    ws.w[2 * a + 1].offset = -hi[a];
  }
  return ws;
}

bool box_of_walls(const WallSet& ws, Vec3d& lo, Vec3d& hi) {
  if (ws.count != 6) return false;
  for (int a = 0; a < 3; ++a) {
    lo[a] = ws.w[2 * a].offset;
    hi[a] = -ws.w[2 * a + 1].offset;
  }
  return true;
}

template <class V>
std::vector<Vec3d> Engine::to_host(const V& v) {
  auto h = Kokkos::create_mirror_view_and_copy(HostSpace(), v);
  std::vector<Vec3d> out(v.extent(0));
  for (size_t i = 0; i < out.size(); ++i) out[i] = {h(i, 0), h(i, 1), h(i, 2)};
  return out;
}

std::vector<Vec3d> Engine::contact_forces() const {
  auto out = to_host(pf_.f);
  out.resize(size_t(lists_[cur_].npairs));  // the View has grow-only slack
  return out;
}

StableStep stable_step(const std::vector<Real>& r, Real density, Real density_scaling, const EngineParams& p) {
  StableStep st;
  if (r.empty()) return st;
  Real r_min = r[0], r_max = r[0], I_min = 0;
  for (size_t i = 0; i < r.size(); ++i) {
    const Real m = particle_mass(r[i], density, density_scaling, p.fines_mass_radius);
    const Real I = Real(0.4 * m * r[i] * r[i]);
    st.m_min = i == 0 ? m : std::min(st.m_min, m);
    I_min = i == 0 ? I : std::min(I_min, I);
    r_min = std::min(r_min, r[i]);
    r_max = std::max(r_max, r[i]);
  }
  // SPEC §4: dt = f sqrt(m_min / k_max), k_max the stiffest spring a particle can feel.
  const Real E_wall = p.E_wall > 0 ? p.E_wall : p.contact.E;
  st.k_max = std::max(p.contact.E * std::max<Real>(1, p.contact.kappa), E_wall) * r_max;
  st.trans = std::sqrt(st.m_min / st.k_max);
  // (choice, extends SPEC §4) With rolling resistance the rolling spring k_r = k_t rbar^2 acts on the
  // inertia I = 2/5 m r^2 of the smaller sphere of a pair; against the largest sphere this can be much
  // stiffer per inertia than any translational spring (41x at size ratio 10, 6.7x at ratio 3), so the
  // limit is the smaller of the two periods. Worst case: the smallest sphere touching the largest.
  const Real rbar = 0.5 * (r_min + r_max);
  const Real kr = p.contact.kappa * p.contact.E * rbar * rbar * rbar;
  st.roll = std::sqrt(I_min / kr);
  return st;
}

Real choose_time_step(const StableStep& st, const EngineParams& p) {
  const bool rolling = p.contact.mu_r > 0;
  const Real limit = st.limit(rolling);
  if (p.contact.dt <= 0) return p.dt_factor * limit;
  if (p.contact.dt > limit) {
    std::ostringstream os;
    os << "numerics.dt = " << p.contact.dt << " s is above the stable limit " << limit
       << " s (translational sqrt(m_min/k_max) = " << st.trans << " s with m_min = " << st.m_min
       << " kg, k_max = " << st.k_max << " N/m";
    if (rolling) os << "; rolling sqrt(I_min/k_r) = " << st.roll << " s";
    os << "); use dt <= " << p.dt_factor * limit << " s (dt_factor " << p.dt_factor << ") or leave dt unset";
    throw ParameterError(os.str());
  }
  return p.contact.dt;
}

Engine::Engine(const ParticleSetup& s, const EngineParams& params, const WallSet& walls, bool walls_are_box)
    : params_(params), walls_(walls), box_(walls_are_box) {
  const int n = int(s.r.size());
  if (s.x.size() != s.r.size()) throw ParameterError("particle positions and radii differ in count");
  if (!(s.density > 0)) throw ParameterError("density must be > 0");
  if (!(s.density_scaling >= 1)) throw ParameterError("density_scaling must be >= 1 (SPEC §1)");
  if (!(params_.fines_mass_radius >= 0)) throw ParameterError("numerics.fines_mass_radius must be >= 0 (0 = off)");
  if (params_.E_wall <= 0) params_.E_wall = params_.contact.E;
  if (box_ && walls_.count != 6) throw ParameterError("a box needs exactly 6 walls");
  if (params_.pair_kernel == PairKernel::Lanes && !kPairLanesBuilt)
    throw ParameterError("pair_kernel Lanes is not built here (host backend with AVX2/AVX-512 and GRAINLAB_PAIR_LANES=ON)");
  P_.n = n;
  // x, v, w, r, m, inertia and id are filled from the setup below (every entry); f, t and x_ref start at zero.
  P_.x = huge_page_view<VecView>("grainlab::particles::x", n, false);
  P_.v = huge_page_view<VecView>("grainlab::particles::v", n, false);
  P_.w = huge_page_view<VecView>("grainlab::particles::w", n, false);
  P_.f = huge_page_view<VecView>("grainlab::particles::f", n, true);
  P_.t = huge_page_view<VecView>("grainlab::particles::t", n, true);
  P_.x_ref = huge_page_view<VecView>("grainlab::particles::x_ref", n, true);
  P_.r = huge_page_view<RealView>("grainlab::particles::r", n, false);
  P_.m = huge_page_view<RealView>("grainlab::particles::m", n, false);
  P_.inertia = huge_page_view<RealView>("grainlab::particles::inertia", n, false);
  P_.id = huge_page_view<IntView>("grainlab::particles::id", n, false);
  auto hx = Kokkos::create_mirror_view(P_.x);
  auto hv = Kokkos::create_mirror_view(P_.v);
  auto hw = Kokkos::create_mirror_view(P_.w);
  auto hr = Kokkos::create_mirror_view(P_.r);
  auto hm = Kokkos::create_mirror_view(P_.m);
  auto hI = Kokkos::create_mirror_view(P_.inertia);
  auto hid = Kokkos::create_mirror_view(P_.id);
  r_min_ = n ? s.r[0] : 0;
  r_max_ = n ? s.r[0] : 0;
  for (int i = 0; i < n; ++i) {
    if (!(s.r[i] > 0)) throw ParameterError("particle " + std::to_string(i) + " has a radius <= 0");
    for (int k = 0; k < 3; ++k) {
      hx(i, k) = s.x[i][k];
      hv(i, k) = s.v.empty() ? 0 : s.v[i][k];
      hw(i, k) = s.w.empty() ? 0 : s.w[i][k];
    }
    hr(i) = s.r[i];
    // SPEC §1: I = 2/5 m r^2, both times the density scaling factor (and a fine's by its mass scaling: the same
    // factor on m and I, as s, so its rotation keeps the translation's period ratio).
    hm(i) = particle_mass(s.r[i], s.density, s.density_scaling, params_.fines_mass_radius);
    hI(i) = 0.4 * hm(i) * s.r[i] * s.r[i];
    hid(i) = i;
    r_min_ = std::min(r_min_, s.r[i]);
    r_max_ = std::max(r_max_, s.r[i]);
  }
  Kokkos::deep_copy(P_.x, hx);
  Kokkos::deep_copy(P_.v, hv);
  Kokkos::deep_copy(P_.w, hw);
  Kokkos::deep_copy(P_.r, hr);
  Kokkos::deep_copy(P_.m, hm);
  Kokkos::deep_copy(P_.inertia, hI);
  Kokkos::deep_copy(P_.id, hid);

  if (!(params_.dt_factor > 0 && params_.dt_factor <= 1)) {
    std::ostringstream os;
    os << "numerics.dt_factor = " << params_.dt_factor << " is outside the allowed range (0, 1]";
    throw ParameterError(os.str());
  }
  const StableStep st = stable_step(s.r, s.density, s.density_scaling, params_);
  dt_trans_ = st.trans;
  dt_roll_ = st.roll;
  dt_crit_ = stable_dt(params_.contact.mu_r > 0);
  params_.contact.dt = choose_time_step(st, params_);
  if (!(params_.skin > 0)) throw ParameterError("skin must be > 0");
  if (!(params_.inner_skin >= 0 && params_.inner_skin < 1)) {
    std::ostringstream os;
    os << "numerics.inner_skin = " << params_.inner_skin << " is outside the allowed range [0, 1) (a fraction of skin)";
    throw ParameterError(os.str());
  }
  rebuild();
  evaluate_forces();
}

void Engine::set_friction(Real mu, Real mu_r) {
  if (!(mu >= 0) || !(mu_r >= 0)) throw ParameterError("friction coefficients must be >= 0");
  if (params_.contact.dt > stable_dt(mu_r > 0)) {
    std::ostringstream os;
    os << "dt = " << params_.contact.dt << " s is above the stable limit " << stable_dt(mu_r > 0)
       << " s once rolling resistance (mu_r = " << mu_r << ") is on; choose dt for the stiffest stage";
    throw ParameterError(os.str());
  }
  dt_crit_ = stable_dt(mu_r > 0);
  // Turning rolling resistance off drops the stored moments: the kernel without rolling neither reads
  // nor clears them, and a stale moment must not come back if a later stage turns rolling on again.
  if (params_.contact.mu_r > 0 && !(mu_r > 0)) Kokkos::deep_copy(hist_[cur_].mr, Real(0));
  params_.contact.mu = mu;
  params_.contact.mu_r = mu_r;
}

void Engine::build_lists(int next) {
  if (inner_list()) {
    nstats_ = build_neighbor_list(P_.x, P_.r, params_.skin, grid_, outer_, /*transposed=*/false);
    filter_pair_list(P_.x, P_.r, params_.inner_skin * params_.skin, outer_, lists_[next]);
    outer_drift_ = 0;
  } else {
    nstats_ = build_neighbor_list(P_.x, P_.r, params_.skin, grid_, lists_[next]);
  }
}

void Engine::install(int next, const PairList& old, const PairHistory& old_h) {
  ensure_pair_arrays(hist_[next], lists_[next].npairs);
  ensure_pair_arrays(pf_, lists_[next].npairs, P_.n, params_.pair_kernel);
  transfer_history(old, old_h, lists_[next], hist_[next]);
  cur_ = next;
  Kokkos::deep_copy(P_.x_ref, P_.x);
}

void Engine::rebuild() {
  const int next = 1 - cur_;
  build_lists(next);
  install(next, lists_[cur_], hist_[cur_]);
  ++rebuilds_;
}

void Engine::refilter() {
  const int next = 1 - cur_;
  filter_pair_list(P_.x, P_.r, params_.inner_skin * params_.skin, outer_, lists_[next]);
  install(next, lists_[cur_], hist_[cur_]);
  ++refilters_;
}

void Engine::evaluate_forces() {
  // Forces at the current positions without advancing: a zero-dt pass through the same kernels would
  // also move nothing, but history must not be incremented twice, so only the wall loads and pair
  // forces are refreshed here by a step of the contact kernel with dt = 0.
  ContactParams cp = params_.contact;
  cp.dt = 0;
  ContactFeatures feat{params_.contact.mu_r > 0, params_.contact.normal_damping > 0};
  compute_pair_forces(P_, lists_[cur_], hist_[cur_], pf_, cp, feat, params_.pair_kernel);
  loads_ = reduce_wall_loads(P_, walls_, params_.E_wall, red_);
}

void Engine::evaluate() {
  const ContactParams& cp = params_.contact;
  const ContactFeatures feat{cp.mu_r > 0, cp.normal_damping > 0};
  // 1. Pair forces at x(t) from v(t - dt/2): v dt is the slip since the last evaluation.
  compute_pair_forces(P_, lists_[cur_], hist_[cur_], pf_, cp, feat, params_.pair_kernel);
  // 2. Wall loads at x(t) (deterministic sums: they drive the servo).
  loads_ = reduce_wall_loads(P_, walls_, params_.E_wall, red_);
  evaluated_ = true;
  forces_current_ = false;  // P.f, P.t are the last instant's until a gather (diagnostics(), damping_moment())
}

void Engine::load_walls_now() { loads_ = reduce_wall_loads(P_, walls_, params_.E_wall, red_); }

void Engine::fused_step(DragMeasure* drag) {
  const ContactParams& cp = params_.contact;
  compute_pair_forces(P_, lists_[cur_], hist_[cur_], pf_, cp, ContactFeatures{cp.mu_r > 0, cp.normal_damping > 0},
                      params_.pair_kernel);
  // Steps 2 and 3 together: the loads at x(t) are summed before the particles drift, in the integration's pass
  // on a host backend, and on a GPU brought over with the displacement max in one copy (perf/NOTES.md).
  const Real maxd2 = gather_integrate_and_load_walls(P_, lists_[cur_], hist_[cur_].flags, pf_, walls_, params_.E_wall,
                                                     params_.damping, cp.dt, params_.pair_kernel, red_, loads_, drag);
  forces_current_ = false;
  finish_step(maxd2);
}

Vec3d Engine::step_measuring_drag(const Vec3d& c) {
  if constexpr (kHostBackend) {
    DragMeasure d{Vec3(c[0], c[1], c[2]), Vec3()};
    fused_step(&d);
    return {d.moment.x, d.moment.y, d.moment.z};
  } else {
    evaluate();
    const Vec3d m = damping_moment(c);
    advance();
    return m;
  }
}

void Engine::advance_impl(bool store_forces) {
  if (!evaluated_) throw std::logic_error("Engine::advance() without evaluate()");
  evaluated_ = false;
  const ContactParams& cp = params_.contact;
  // 3. Gather, damp, kick, drift: x(t + dt), v(t + dt/2).
  const Real maxd2 = gather_and_integrate(P_, lists_[cur_], hist_[cur_].flags, pf_, walls_, params_.E_wall, params_.damping, cp.dt,
                                         params_.pair_kernel, store_forces);
  forces_current_ = store_forces;
  finish_step(maxd2);
}

void Engine::set_affine_box(bool on) {
  if (on && !box_) throw std::logic_error("Engine::set_affine_box needs box walls");
  affine_box_ = on;
}

void Engine::finish_step(Real maxd2) {
  const ContactParams& cp = params_.contact;
  time_ += cp.dt;
  ++step_;
  // 4. Walls to t + dt from the loads measured at t; with the affine box the positions follow them, and the
  // displacement max is taken again after the remap (it moves every particle).
  if (affine_box_) {
    Real lo0[3], len0[3], lo1[3], scale[3];
    for (int a = 0; a < 3; ++a) lo0[a] = wall_position(2 * a), len0[a] = wall_position(2 * a + 1) - lo0[a];
    move_walls();
    for (int a = 0; a < 3; ++a) lo1[a] = wall_position(2 * a), scale[a] = (wall_position(2 * a + 1) - lo1[a]) / len0[a];
    maxd2 = remap_affine(P_, Vec3(lo0[0], lo0[1], lo0[2]), Vec3(scale[0], scale[1], scale[2]),
                         Vec3(lo1[0], lo1[1], lo1[2]));
  } else {
    move_walls();
  }
  // 5. Neighbour list when any particle moved more than skin/2 since the last build (SPEC §5). With the
  // inner list, maxd2 is measured from the last filter; the displacement since the Verlet build is at
  // most outer_drift_ + sqrt(maxd2) (triangle inequality over the filter intervals), so that bound
  // decides the Verlet rebuild, and inner_skin * skin / 2 the filter.
  const Real half = 0.5 * params_.skin;
  if (inner_list()) {
    const Real d = std::sqrt(maxd2);
    if (rebuild_every_step_ || outer_drift_ + d > half) {
      rebuild();
    } else if (d > 0.5 * params_.inner_skin * params_.skin) {
      outer_drift_ += d;
      refilter();
    }
  } else if (rebuild_every_step_ || maxd2 > half * half) {
    rebuild();
  }
}

Real Engine::wall_position(int k) const {
  const Wall& w = walls_.w[k];
  return (k % 2 == 0) ? w.offset : -w.offset;
}

void Engine::set_wall_position(int k, Real pos) {
  if (!box_) throw std::logic_error("set_wall_position needs box walls");
  walls_.w[k].offset = (k % 2 == 0) ? pos : -pos;
  forces_current_ = false;  // the walls' share of P.f changed
}

Real Engine::wall_area(int k) const {
  if (!box_) return control_.at(k).area;
  const int a = k / 2;
  Real area = 1;
  for (int b = 0; b < 3; ++b)
    if (b != a) area *= wall_position(2 * b + 1) - wall_position(2 * b);
  return area;
}

Real Engine::box_volume() const {
  if (!box_) return 0;
  Real v = 1;
  for (int a = 0; a < 3; ++a) v *= wall_position(2 * a + 1) - wall_position(2 * a);
  return v;
}

Real Engine::solid_volume_in(const Vec3d& lo, const Vec3d& hi) {
  auto x = P_.x;
  auto r = P_.r;
  const Vec3 l(lo[0], lo[1], lo[2]), h(hi[0], hi[1], hi[2]);
  Real v = 0;
  // An output-row measure, not the dynamics, but summed as the rest (fixed chunks in a fixed order): a plain Sum's
  // order was the backend's, and e_inner and e_core differed between 1 and 2 threads in their last bit (session 70).
  red_.run(
      "grainlab::analysis::solid_in_box", P_.n, 1,
      KOKKOS_LAMBDA(int i, Real* acc) { acc[0] += sphere_volume_in_box(Vec3(x(i, 0), x(i, 1), x(i, 2)), r(i), l, h); },
      &v);
  return v;
}

void Engine::move_walls() {
  const Real dt = params_.contact.dt;
  const Real smax = params_.servo_max_step * r_min_;
  for (int k = 0; k < walls_.count; ++k) {
    WallControl& c = control_[k];
    Real s = 0;  // displacement along the inward normal this step
    if (c.mode == WallMode::Velocity) {
      s = c.velocity * dt;
    } else if (c.mode == WallMode::Servo) {
      // SPEC §3: v = G (sigma_target - sigma) inward, with G = gain * A / (K_w dt): each step corrects
      // the fraction `gain` of the force error at the measured wall stiffness K_w; bounded by smax.
      const Real area = wall_area(k);
      const Real ferr = (c.target_stress * area - loads_.force[k]);
      const Real sp = loads_.stiffness[k] > 0 ? c.gain * ferr / loads_.stiffness[k] : (ferr > 0 ? smax : -smax);
      s = std::max(-smax, std::min(smax, sp + c.drift));
      // Integral action (WallControl::integral): learned only while the step is not at its bound, and only from
      // a wall in contact (a free wall's sp is the bound itself, not an error measured): no wind-up while the
      // wall closes a gap at smax, or while smax holds it back.
      if (c.integral > 0 && loads_.stiffness[k] > 0 && std::abs(sp + c.drift) < smax)
        c.drift = std::max(-smax, std::min(smax, c.drift + c.integral * sp));
    }
    walls_.w[k].offset += s;  // plane n.x = offset moves by s along n
  }
}

namespace {
// A centre in the half-open box [lo, hi) (Engine::stress_in): boxes that tile space hold each centre once.
KOKKOS_INLINE_FUNCTION bool in_box(const Vec3& x, const Vec3& lo, const Vec3& hi) {
  return x.x >= lo.x && x.x < hi.x && x.y >= lo.y && x.y < hi.y && x.z >= lo.z && x.z < hi.z;
}
// Index of (a, b), a <= b, in the 6 stored entries of a symmetric 3x3 matrix (row by row: xx xy xz yy yz zz).
KOKKOS_INLINE_FUNCTION constexpr int kSym(int a, int b) { return a == 0 ? b : a == 1 ? 2 + b : 5; }
constexpr int kMoments = 23;  // the moments Engine::diagnostics sums for kinetic_fluct

// Half the mass-weighted squared residual of the velocities about their least-squares affine field v = a + L x,
// from the moments of Diagnostics (pa[4..26]). With r = x - X about the centre of mass X and u = v - V about the
// mean velocity V: S_rr = sum m r r^T, S_ur = sum m u r^T; the minimiser is L = S_ur S_rr^-1, a = V - L X, and the
// residual sum m |u - L r|^2 = sum m |u|^2 - tr(S_ur S_rr^-1 S_ur^T) (normal equations). Cancellation leaves it
// good to ~1e-16 of sum m |v|^2; clamped at 0. Fewer than four spheres, or all in a plane (S_rr singular): about
// the mean velocity alone.
Real affine_residual(const Real* mo) {
  const double M = mo[0];
  if (!(M > 0)) return 0;
  double X[3], V[3], S[3][3], U[3][3];
  for (int a = 0; a < 3; ++a) X[a] = mo[1 + a] / M, V[a] = mo[4 + a] / M;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      S[a][b] = mo[7 + kSym(std::min(a, b), std::max(a, b))] - M * X[a] * X[b];
      U[a][b] = mo[13 + 3 * a + b] - M * V[a] * X[b];
    }
  double res = mo[22] - M * (V[0] * V[0] + V[1] * V[1] + V[2] * V[2]);
  // S_rr^-1 by its adjugate (host code, 3x3: no library; the engine is also compiled by nvcc)
  double C[3][3];
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      const int a1 = (a + 1) % 3, a2 = (a + 2) % 3, b1 = (b + 1) % 3, b2 = (b + 2) % 3;
      C[b][a] = S[a1][b1] * S[a2][b2] - S[a1][b2] * S[a2][b1];  // transposed cofactor
    }
  const double det = S[0][0] * C[0][0] + S[0][1] * C[1][0] + S[0][2] * C[2][0];
  const double tr = S[0][0] + S[1][1] + S[2][2];
  if (det > 1e-12 * tr * tr * tr) {  // not (nearly) planar
    for (int a = 0; a < 3; ++a)     // tr(U S^-1 U^T) = sum_a u_a^T S^-1 u_a over the rows u_a of U
      for (int b = 0; b < 3; ++b)
        for (int c = 0; c < 3; ++c) res -= U[a][b] * C[b][c] * U[a][c] / det;
  }
  return Real(std::max(0.0, 0.5 * res));
}
}  // namespace

Diagnostics Engine::diagnostics() {
  // Between evaluate() and advance() P.f still holds the previous step's forces (the gather runs in
  // advance()), so the unbalanced force would lag the contacts by one step: gather them at this instant.
  if (evaluated_ && !forces_current_) {
    gather_forces(P_, lists_[cur_], hist_[cur_].flags, pf_, walls_, params_.E_wall, params_.pair_kernel);
    forces_current_ = true;
  }
  Diagnostics d;
  auto v = P_.v;
  auto w = P_.w;
  auto f = P_.f;
  auto x = P_.x;
  auto r = P_.r;
  auto m = P_.m;
  auto I = P_.inertia;
  const WallSet ws = walls_;
  const Real Ew = params_.E_wall;
  const PairList& L = lists_[cur_];
  const PairHistory& H = hist_[cur_];
  const TouchCounter touch{L.offsets, L.t_offsets, L.t_pairs, H.flags};
  // pa[4..26]: the skeleton's mass moments for kinetic_fluct: sum m, m x (3), m v (3), m x x^T (6, upper), m v x^T (9),
  // m v.v (1).
  Real pa[4 + kMoments] = {};
  red_.run(
      "grainlab::diag::particles", P_.n, 4 + kMoments,
      KOKKOS_LAMBDA(int i, Real* acc) {
        const Real kt = 0.5 * m(i) * norm2(load(v, i));
        acc[0] += kt + 0.5 * I(i) * norm2(load(w, i));
        acc[1] += norm(load(f, i));
        const Vec3 xi = load(x, i);
        int touching = 0;
        for (int k = 0; k < ws.count; ++k) {
          const Real dw = WallLaw::overlap(ws.w[k], xi, r(i));
          if (dw > 0) {
            acc[2] += 0.5 * WallLaw::stiffness(Ew, r(i)) * dw * dw;
            ++touching;
          }
        }
        if (!touching) touching = touch(i, 1);
        if (touching) {
          acc[3] += kt;  // the load-bearing skeleton's translational kinetic energy
          const Vec3 vi = load(v, i);
          const Real mi = m(i), xv[3] = {xi.x, xi.y, xi.z}, vv[3] = {vi.x, vi.y, vi.z};
          Real* mo = acc + 4;
          mo[0] += mi;
          for (int a = 0; a < 3; ++a) {
            mo[1 + a] += mi * xv[a];
            mo[4 + a] += mi * vv[a];
            for (int b = a; b < 3; ++b) mo[7 + kSym(a, b)] += mi * xv[a] * xv[b];
            for (int b = 0; b < 3; ++b) mo[13 + 3 * a + b] += mi * vv[a] * xv[b];
          }
          mo[22] += 2 * kt;
        }
      },
      pa);
  auto pi = L.pair_i;
  auto pj = L.pair_j;
  auto fl = H.flags;
  auto ft = H.ft;
  auto mr = H.mr;
  auto fc = pf_.f;
  const ContactParams cp = params_.contact;
  const bool rolling = cp.mu_r > 0;
  auto off = L.offsets;
  Real ca[6] = {};
  // Per particle over its row, chunked by particle: sums independent of the list's non-touching pairs
  // (bitwise the same after a restart; the unbalanced-force ratio decides when a stage ends).
  red_.run(
      "grainlab::diag::pairs", P_.n, 6,
      KOKKOS_LAMBDA(int row, Real* acc) {
        for (int p = off(row); p < off(row + 1); ++p) {
        const int i = pi(p), j = pj(p);
        const Real rbar = 0.5 * (r(i) + r(j));
        const Real kn = cp.E * rbar, kt = cp.kappa * kn;
        // Normal spring energy from the current geometry (not from last step's flags).
        const Real delta = r(i) + r(j) - norm(load(x, j) - load(x, i));
        if (delta > 0) acc[4] += 0.5 * kn * delta * delta;
        const std::uint8_t fp = fl(p);
        if (!(fp & kTouching)) continue;
        acc[0] += 1;
        acc[1] += (fp & kSliding) ? 1 : 0;
        acc[2] += (fp & kRollingSliding) ? 1 : 0;
        acc[3] += norm(load(fc, p));
        acc[5] += 0.5 * norm2(load(ft, p)) / kt;
        if (rolling) acc[5] += 0.5 * norm2(load(mr, p)) / (kt * rbar * rbar);
        }
      },
      ca);
  d.kinetic = pa[0];
  d.kinetic_skeleton = pa[3];
  d.kinetic_fluct = affine_residual(pa + 4);
  d.contacts = int(ca[0]);
  d.sliding = int(ca[1]);
  d.rolling_sliding = int(ca[2]);
  d.mean_contact_force = d.contacts ? ca[3] / d.contacts : 0;
  d.potential = pa[2] + ca[4] + ca[5];
  // After step() (forces() not updated) the particle forces of the contacts' instant are not at hand: NaN
  // says so rather than a ratio of two instants. The laboratory measures between the halves.
  d.unbalanced_ratio = !forces_current_ ? std::numeric_limits<Real>::quiet_NaN()
                       : (d.contacts && P_.n && ca[3] > 0) ? (pa[1] / P_.n) / (ca[3] / d.contacts) : 0;
  return d;
}

HealthReport Engine::check_health(const HealthLimits& lim) const {
  HealthReport rep;
  const int n = P_.n;
  auto x = P_.x;
  auto v = P_.v;
  auto w = P_.w;
  auto r = P_.r;
  const Real dt = params_.contact.dt;
  const Real half_dt_suggest = 0.5 * dt;
  // suggest_dt: the time step is a likely cause (instability, tunnelling, impacts), so the line ends with
  // a smaller one. A slow squeeze of soft contacts gets its own advice instead: a smaller dt cannot help.
  auto fail = [&](const std::string& m, const std::string& cause, bool suggest_dt = true) {
    std::ostringstream os;
    os << "numerical blow-up at step " << step_ << ": " << m << "; " << cause;
    if (suggest_dt)
      os << "; suggested: dt <= " << half_dt_suggest << " s (half the current " << dt
         << " s, via numerics.dt or numerics.dt_factor)";
    rep.ok = false;
    rep.what = os.str();
    return rep;
  };
  const std::string unstable = "the integration is unstable";
  // 1. Non-finite state: the first particle (lowest index) with a NaN or Inf.
  int bad = n;
  Kokkos::parallel_reduce(
      "grainlab::health::finite", Kokkos::RangePolicy<ExecSpace>(0, n),
      KOKKOS_LAMBDA(int i, int& m) {
        bool fin = true;
        for (int k = 0; k < 3; ++k)
          fin = fin && math::isfinite(x(i, k)) && math::isfinite(v(i, k)) && math::isfinite(w(i, k));
        if (!fin && i < m) m = i;
      },
      Kokkos::Min<int>(bad));
  if (bad < n) {
    const auto hx = positions(), hv = velocities();
    std::ostringstream os;
    os << "particle " << bad << " has a non-finite state (x = " << hx[bad][0] << ", " << hx[bad][1] << ", "
       << hx[bad][2] << "; v = " << hv[bad][0] << ", " << hv[bad][1] << ", " << hv[bad][2] << ")";
    return fail(os.str(), unstable);
  }
  // 2. Tunnelling speed: a particle moving more than max_step_move radii (or radians) per step.
  {
    const Real rmin = r_min_;
    Kokkos::MaxLoc<Real, int>::value_type mv;
    Kokkos::parallel_reduce(
        "grainlab::health::speed", Kokkos::RangePolicy<ExecSpace>(0, n),
        KOKKOS_LAMBDA(int i, Kokkos::MaxLoc<Real, int>::value_type& m) {
          const Real a = norm(load(v, i)) * dt / rmin, b = norm(load(w, i)) * dt;
          const Real q = a > b ? a : b;
          if (q > m.val || (q == m.val && i < m.loc)) {
            m.val = q;
            m.loc = i;
          }
        },
        Kokkos::MaxLoc<Real, int>(mv));
    if (n > 0 && mv.val > lim.max_step_move) {
      std::ostringstream os;
      os << "particle " << mv.loc << " moves " << mv.val << " r_min (or rad) per step (limit " << lim.max_step_move
         << "): kinetic energy is exploding";
      return fail(os.str(), unstable);
    }
  }
  // 3. Escape (a centre beyond a wall by more than its radius) or a wall overlap above the limit.
  {
    const WallSet ws = walls_;
    const Real lim_ov = lim.max_overlap;
    int esc = n, deep = n;
    Kokkos::parallel_reduce(
        "grainlab::health::escape", Kokkos::RangePolicy<ExecSpace>(0, n),
        KOKKOS_LAMBDA(int i, int& m) {
          for (int k = 0; k < ws.count; ++k)
            if (dot(ws.w[k].n, load(x, i)) - ws.w[k].offset < -r(i) && i < m) m = i;
        },
        Kokkos::Min<int>(esc));
    Kokkos::parallel_reduce(
        "grainlab::health::wall_overlap", Kokkos::RangePolicy<ExecSpace>(0, n),
        KOKKOS_LAMBDA(int i, int& m) {
          for (int k = 0; k < ws.count; ++k)
            if (WallLaw::overlap(ws.w[k], load(x, i), r(i)) > lim_ov * r(i) && i < m) m = i;
        },
        Kokkos::Min<int>(deep));
    if (esc == n && deep < n) {
      std::ostringstream os;
      os << "particle " << deep << " overlaps a wall by more than " << lim.max_overlap << " of its radius";
      return fail(os.str(), "the walls are too soft for the load (raise material.E_wall or lower the pressure)");
    }
    if (esc < n) {
      const auto hx = positions();
      std::ostringstream os;
      os << "particle " << esc << " escaped through a wall (centre at " << hx[esc][0] << ", " << hx[esc][1] << ", "
         << hx[esc][2] << ")";
      return fail(os.str(), "a wall moved too fast for the time step (lower the strain rate or servo_max_step)");
    }
  }
  // 4. Overlaps: the largest delta / min(r_i, r_j) over the listed pairs.
  if (const DeepestOverlap mo = deepest_overlap(); mo.i >= 0 && mo.ratio > lim.max_overlap) {
    // Impact or squeeze? The pair's closing speed says: an impact closes a large part of the overlap per
    // step, a static strong contact under a slowly rising load a tiny part (the H100's UR1 run tripped
    // the limit at 0.2013 with the sample quasi-static, kinetic/elastic energy 2e-3: perf/gpu/runs/
    // 2026-11-23-h100-92a3235). kSqueeze: closing by under 1 % of the overlap per step, the overlap took
    // > 100 steps to build. An impact builds it in a quarter period of the contact spring, which the stable
    // step resolves in few steps (SPEC §4: dt = f sqrt(m_min/k_max); a quarter period is
    // (pi/2) sqrt(m_min/(2 k_max)) = 1.1/f steps: 5.6 at f = 0.2, 22 at f = 0.05), closing ~5-20 % per step.
    constexpr Real kSqueeze = 0.01;
    const auto hx = positions(), hv = velocities();
    Real ri = 0, rj = 0;
    Kokkos::deep_copy(ri, Kokkos::subview(r, mo.i));
    Kokkos::deep_copy(rj, Kokkos::subview(r, mo.j));
    Vec3d dx, dv;
    for (int k = 0; k < 3; ++k) {
      dx[k] = hx[mo.j][k] - hx[mo.i][k];
      dv[k] = hv[mo.j][k] - hv[mo.i][k];
    }
    const Real dist = std::sqrt(dx[0] * dx[0] + dx[1] * dx[1] + dx[2] * dx[2]);
    const Real delta = ri + rj - dist;
    const Real closing = -(dv[0] * dx[0] + dv[1] * dx[1] + dv[2] * dx[2]) / dist;  // > 0 while approaching
    const Real per_step = closing * dt / delta;
    const Real kn = params_.contact.E * 0.5 * (ri + rj);
    std::ostringstream os;
    os << "particles " << mo.i << " and " << mo.j << " overlap by " << mo.ratio << " of the smaller radius (limit "
       << lim.max_overlap << "), normal force " << kn * delta << " N (radii " << 1e3 * ri << " and " << 1e3 * rj
       << " mm), closing by " << 100 * per_step
       << " % of the overlap per step";
    rep.squeeze = per_step < kSqueeze;
    if (rep.squeeze)
      return fail(os.str(),
                  "a slow squeeze, not an impact: the contacts are too soft for the load (raise material.E, lower "
                  "the pressure, or allow deeper overlaps with numerics.max_overlap); a smaller dt will not help",
                  false);
    return fail(os.str(), "the contacts are too soft for the load (raise material.E or lower the pressure), "
                          "or impacts are too fast for the time step");
  }
  return rep;
}

Engine::DeepestOverlap Engine::deepest_overlap() const {
  const PairList& L = lists_[cur_];
  DeepestOverlap out;
  if (L.npairs == 0) return out;
  auto pi = L.pair_i;
  auto pj = L.pair_j;
  auto x = P_.x;
  auto r = P_.r;
  Kokkos::MaxLoc<Real, int>::value_type mo;
  Kokkos::parallel_reduce(
      "grainlab::health::overlap", Kokkos::RangePolicy<ExecSpace>(0, L.npairs),
      KOKKOS_LAMBDA(int p, Kokkos::MaxLoc<Real, int>::value_type& m) {
        const int i = pi(p), j = pj(p);
        const Real d = r(i) + r(j) - norm(load(x, j) - load(x, i));
        const Real q = d / (r(i) < r(j) ? r(i) : r(j));
        if (q > m.val || (q == m.val && p < m.loc)) {
          m.val = q;
          m.loc = p;
        }
      },
      Kokkos::MaxLoc<Real, int>(mo));
  out.ratio = mo.val;
  Kokkos::deep_copy(out.i, Kokkos::subview(L.pair_i, mo.loc));
  Kokkos::deep_copy(out.j, Kokkos::subview(L.pair_j, mo.loc));
  return out;
}

Descriptors Engine::analyze(Real volume) {
  const PairList& L = lists_[cur_];
  const EngineContacts src{P_.x, pf_.f, L.pair_i, L.pair_j, hist_[cur_].flags};
  Descriptors D = compute_descriptors(src, L.offsets, P_.n, P_.n, volume > 0 ? volume : box_volume(), red_);
  count_rattlers(P_, L, hist_[cur_], red_, D.rattlers0, D.rattlers1);
  // Boundary contacts: per wall, sum of k_w delta (r - delta/2) along the wall normal.
  {
    auto x = P_.x;
    auto r = P_.r;
    const WallSet ws = walls_;
    const int nw = ws.count;
    const Real Ew = params_.E_wall;
    Real mom[kMaxWalls] = {};
    red_.run(
        "grainlab::analysis::wall_moments", P_.n, nw,
        KOKKOS_LAMBDA(int i, Real* acc) {
          const Vec3 xi = load(x, i);
          for (int k = 0; k < nw; ++k) {
            const Real dw = WallLaw::overlap(ws.w[k], xi, r(i));
            if (dw > 0) acc[k] += WallLaw::stiffness(Ew, r(i)) * dw * (r(i) - 0.5 * dw);
          }
        },
        mom);
    const Real V = volume > 0 ? volume : box_volume();
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        Real t = 0;
        for (int k = 0; k < nw; ++k) t += mom[k] * walls_.w[k].n[a] * walls_.w[k].n[b];
        D.sigma_walls[a][b] = D.sigma[a][b] + (V > 0 ? t / V : 0);
      }
    stress_invariants(Sym::symmetric_part(D.sigma_walls), D.p_walls, D.q_walls);
  }
  // Mechanical coordination (Thornton 2000): rattlers with fewer than 2 contacts removed.
  const int active = P_.n - D.rattlers0 - D.rattlers1;
  D.z_mech = active > 0 ? Real(2 * D.nc - D.rattlers1) / active : 0;
  return D;
}

Sym Engine::stress_in(const Vec3d& lo_, const Vec3d& hi_) {
  Real V = 1;
  for (int a = 0; a < 3; ++a) V *= std::max(Real(0), hi_[a] - lo_[a]);
  Sym out;
  if (!(V > 0)) return out;
  const PairList& L = lists_[cur_];
  const auto x = P_.x;
  const auto r = P_.r;
  const auto f = pf_.f;
  const auto off = L.offsets;
  const auto pj = L.pair_j;
  const auto flags = hist_[cur_].flags;
  const Vec3 lo{lo_[0], lo_[1], lo_[2]}, hi{hi_[0], hi_[1], hi_[2]};
  Real s[6] = {};
  // Rows are the particles i of the half list (analyze()'s order): the same sums on any thread count.
  red_.run(
      "grainlab::analysis::stress_in", P_.n, 6,
      KOKKOS_LAMBDA(int i, Real* acc) {
        const Vec3 xi = load(x, i);
        const bool in_i = in_box(xi, lo, hi);
        for (int p = off(i); p < off(i + 1); ++p) {
          if (!(flags(p) & kTouching)) continue;
          const int j = pj(p);
          const Vec3 xj = load(x, j);
          const bool in_j = in_box(xj, lo, hi);
          if (!in_i && !in_j) continue;
          const Vec3 d = xj - xi;
          const Real l = norm(d);
          // Levers to the contact point: a_i = r_i - delta/2 with delta = r_i + r_j - l, a_j = l - a_i.
          const Real ai = Real(0.5) * (l + r(i) - r(j));
          const Real w = ((in_i ? ai : Real(0)) + (in_j ? l - ai : Real(0))) / l;
          detail::add_sym(acc, load(f, p), d, w);  // f on j (x) w d: analyze()'s f (x) d where w = 1
        }
      },
      s);
  for (int k = 0; k < 6; ++k) out.v[k] = s[k] / V;
  return out;
}

Vec3d Engine::damping_moment(const Vec3d& c_) {
  if (!evaluated_) throw std::logic_error("Engine::damping_moment() outside evaluate() .. advance()");
  if (!forces_current_) {  // the forces the next kick damps: this instant's (as diagnostics())
    gather_forces(P_, lists_[cur_], hist_[cur_].flags, pf_, walls_, params_.E_wall, params_.pair_kernel);
    forces_current_ = true;
  }
  Vec3d out{0, 0, 0};
  const Real alpha = params_.damping;
  if (!(alpha > 0)) return out;
  const auto x = P_.x;
  const auto v = P_.v;
  const auto f = P_.f;
  const Vec3 c{c_[0], c_[1], c_[2]};
  Real s[3] = {};
  red_.run(
      "grainlab::analysis::damping_moment", P_.n, 3,
      KOKKOS_LAMBDA(int i, Real* acc) {
        const Vec3 fi = load(f, i);
        const Vec3 drag = CundallDamping::damped(fi, load(v, i), alpha) - fi;
        const Vec3 d = load(x, i) - c;
        acc[0] += d.x * drag.x;
        acc[1] += d.y * drag.y;
        acc[2] += d.z * drag.z;
      },
      s);
  for (int a = 0; a < 3; ++a) out[a] = s[a];
  return out;
}

EngineState Engine::capture() const {
  EngineState s;
  s.step = step_;
  s.time = time_;
  s.dt = params_.contact.dt;
  s.mu = params_.contact.mu;
  s.mu_r = params_.contact.mu_r;
  s.damping = params_.damping;
  s.x = positions();
  s.v = velocities();
  s.w = angular_velocities();
  s.f = forces();
  s.t = torques();
  {
    auto hr = Kokkos::create_mirror_view_and_copy(HostSpace(), P_.r);
    s.r.assign(hr.data(), hr.data() + P_.n);
  }
  const PairList& L = lists_[cur_];
  const PairHistory& H = hist_[cur_];
  auto pi = Kokkos::create_mirror_view_and_copy(HostSpace(), L.pair_i);
  auto pj = Kokkos::create_mirror_view_and_copy(HostSpace(), L.pair_j);
  auto fl = Kokkos::create_mirror_view_and_copy(HostSpace(), H.flags);
  auto ft = Kokkos::create_mirror_view_and_copy(HostSpace(), H.ft);
  auto mr = Kokkos::create_mirror_view_and_copy(HostSpace(), H.mr);
  for (int p = 0; p < L.npairs; ++p) {
    // Only touching pairs carry history (a separated pair has lost it: SPEC §2).
    if (!(fl(p) & kTouching)) continue;
    s.pair_i.push_back(pi(p));
    s.pair_j.push_back(pj(p));
    s.ft.push_back({ft(p, 0), ft(p, 1), ft(p, 2)});
    s.mr.push_back({mr(p, 0), mr(p, 1), mr(p, 2)});
    s.flags.push_back(fl(p));
  }
  s.walls = walls_;
  s.control = control_;
  s.loads = loads_;
  s.walls_are_box = box_;
  return s;
}

void Engine::restore(const EngineState& s) {
  const int n = P_.n;
  if (int(s.x.size()) != n || int(s.r.size()) != n || s.v.size() != s.x.size() || s.w.size() != s.x.size())
    throw ParameterError("state has " + std::to_string(s.x.size()) + " particles, the engine " + std::to_string(n));
  {
    auto hr = Kokkos::create_mirror_view_and_copy(HostSpace(), P_.r);
    for (int i = 0; i < n; ++i)
      if (hr(i) != s.r[i]) throw ParameterError("state radii differ from the engine's (particle " + std::to_string(i) + ")");
  }
  const size_t m = s.pair_i.size();
  if (s.pair_j.size() != m || s.ft.size() != m || s.mr.size() != m || s.flags.size() != m)
    throw ParameterError("state contact arrays differ in length");
  auto put = [n](const VecView& v, const std::vector<Vec3d>& src) {
    auto h = Kokkos::create_mirror_view(v);
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k) h(i, k) = src.empty() ? 0 : src[i][k];
    Kokkos::deep_copy(v, h);
  };
  put(P_.x, s.x);
  put(P_.v, s.v);
  put(P_.w, s.w);
  put(P_.f, s.f);
  put(P_.t, s.t);
  forces_current_ = false;  // the state does not say whether its f, t were current (output only)
  step_ = s.step;
  time_ = s.time;
  params_.contact.dt = s.dt;
  params_.contact.mu = s.mu;
  params_.contact.mu_r = s.mu_r;
  params_.damping = s.damping;
  dt_crit_ = stable_dt(s.mu_r > 0);
  walls_ = s.walls;
  control_ = s.control;
  loads_ = s.loads;
  box_ = s.walls_are_box;

  // The saved pairs as a sorted CSR list, then the ordinary rebuild + transfer by pair identity.
  PairList old;
  PairHistory oh;
  {
    old.npairs = int(m);
    // Views are reference counted (Kokkos::Impl::SharedAllocationRecord); the analyser does not follow
    // the count and reports the allocations and mirrors of this block as leaks.
    // NOLINTBEGIN(clang-analyzer-cplusplus.NewDeleteLeaks)
    old.offsets = IntView("grainlab::restore::offsets", n + 1);
    old.pair_j = IntView("grainlab::restore::j", std::max<size_t>(m, 1));
    oh.ft = PairVecView("grainlab::restore::ft", std::max<size_t>(m, 1));
    oh.mr = PairVecView("grainlab::restore::mr", std::max<size_t>(m, 1));
    oh.flags = FlagView("grainlab::restore::flags", std::max<size_t>(m, 1));
    auto ho = Kokkos::create_mirror_view(old.offsets);
    auto hj = Kokkos::create_mirror_view(old.pair_j);
    auto hft = Kokkos::create_mirror_view(oh.ft);
    auto hmr = Kokkos::create_mirror_view(oh.mr);
    auto hfl = Kokkos::create_mirror_view(oh.flags);
    std::vector<int> count(n + 1, 0);
    for (size_t p = 0; p < m; ++p) {
      const int i = s.pair_i[p], j = s.pair_j[p];
      if (i < 0 || j <= i || j >= n || (p > 0 && std::make_pair(s.pair_i[p - 1], s.pair_j[p - 1]) >= std::make_pair(i, j)))
        throw ParameterError("state contact list is not a sorted list of pairs i < j < N (corrupt?)");
      ++count[i + 1];
      hj(p) = j;
      for (int k = 0; k < 3; ++k) {
        hft(p, k) = s.ft[p][k];
        hmr(p, k) = s.mr[p][k];
      }
      hfl(p) = s.flags[p];
    }
    for (int i = 0; i < n; ++i) count[i + 1] += count[i];
    for (int i = 0; i <= n; ++i) ho(i) = count[i];
    Kokkos::deep_copy(old.offsets, ho);
    Kokkos::deep_copy(old.pair_j, hj);
    Kokkos::deep_copy(oh.ft, hft);
    Kokkos::deep_copy(oh.mr, hmr);
    Kokkos::deep_copy(oh.flags, hfl);
    // NOLINTEND(clang-analyzer-cplusplus.NewDeleteLeaks)
  }
  const int next = 1 - cur_;
  build_lists(next);
  install(next, old, oh);
}

}  // namespace grainlab
