// Analytic single-contact checks of the contact law (SPEC §2), evaluated through the same
// LinearRollingContact the kernels use. Issue 2 items 3 (friction), 4 (rolling), 5 (objectivity).
#include <gtest/gtest.h>

#include <random>

#include "helpers.hpp"

using namespace grainlab;

namespace {
// Round-off bound for a handful of double operations on O(1) quantities; the exact-arithmetic
// answers below differ from the computed ones only by rounding.
constexpr Real kRoundoff = 1e-12;

struct Pair {
  Real ri = 0.3e-3, rj = 0.3e-3, mi, mj;
  Vec3 d, vi, vj, wi, wj;
  Pair() : mi(test::sphere_mass(0.3e-3)), mj(test::sphere_mass(0.3e-3)) {}
};

template <bool R>
ContactResult eval(const ContactParams& P, const Pair& s, ContactHistory& h) {
  return LinearRollingContact<R, false>::evaluate(P, s.ri, s.rj, s.mi, s.mj, s.d, norm(s.d), s.vi, s.vj, s.wi, s.wj, h);
}

Vec3 rotate(const Vec3& axis_unit, Real ang, const Vec3& v) {  // Rodrigues
  const Real c = std::cos(ang), s = std::sin(ang);
  return c * v + s * cross(axis_unit, v) + (1 - c) * dot(axis_unit, v) * axis_unit;
}
}  // namespace

// Item 3: pushed tangentially at constant slip rate, F_t = k_t u while k_t u < mu F_n (stick, flag off),
// then exactly mu F_n with the sliding flag; reversing unloads elastically and clears the flag.
TEST(ContactLaw, FrictionSticksThenSlidesAtExactlyMuFn) {
  ContactParams P = test::reference_contact();
  P.dt = 1e-7;
  Pair s;
  const Real delta = 1e-6;
  s.d = Vec3(s.ri + s.rj - delta, 0, 0);
  s.vj = Vec3(0, 0.01, 0);  // slip of j relative to i along +y
  const Real kn = P.E * 0.5 * (s.ri + s.rj), kt = P.kappa * kn;
  const Real fn = kn * delta, cap = P.mu * fn;
  ContactHistory h;
  int stick_steps = 0, slide_steps = 0;
  for (int k = 1; k <= 1000; ++k) {
    const ContactResult c = eval<false>(P, s, h);
    const Real u = k * 0.01 * P.dt;  // accumulated slip
    EXPECT_NEAR(dot(c.f, Vec3(1, 0, 0)), fn, kRoundoff * fn);
    if (kt * u < cap * (1 - 1e-9)) {
      EXPECT_NEAR(h.ft.y, -kt * u, kRoundoff * cap) << "step " << k;
      EXPECT_FALSE(c.flags & kSliding) << "sliding flag set while sticking, step " << k;
      ++stick_steps;
    } else if (kt * u > cap * (1 + 1e-9)) {
      EXPECT_NEAR(norm(h.ft), cap, kRoundoff * cap) << "step " << k;
      EXPECT_TRUE(c.flags & kSliding) << "step " << k;
      ++slide_steps;
    }
  }
  ASSERT_GT(stick_steps, 50);
  ASSERT_GT(slide_steps, 50);
  // Reverse: elastic unloading from the cap with slope k_t, flag cleared at once.
  s.vj = Vec3(0, -0.01, 0);
  for (int k = 1; k <= 20; ++k) {
    const ContactResult c = eval<false>(P, s, h);
    EXPECT_NEAR(h.ft.y, -cap + kt * k * 0.01 * P.dt, kRoundoff * cap);
    EXPECT_FALSE(c.flags & kSliding);
  }
}

// Item 4: pure rolling (no slip at the contact point) with relative rotation rate 2 Omega: M_r = k_r theta
// up to mu_r F_n l, then stays at the cap (rolling-sliding flag); reversing unloads with slope k_r.
TEST(ContactLaw, RollingMomentGrowsCapsAndUnloads) {
  ContactParams P = test::reference_contact();
  P.dt = 1e-7;
  P.mu_r = 0.3;
  Pair s;
  const Real delta = 1e-6;
  s.d = Vec3(s.ri + s.rj - delta, 0, 0);
  const Real Om = 1.0;  // rad/s: the cap is reached after ~250 steps
  s.wi = Vec3(0, 0, Om);
  s.wj = Vec3(0, 0, -Om);  // equal arms: contact points move together, no slip
  const Real rbar = 0.5 * (s.ri + s.rj), kn = P.E * rbar, kt = P.kappa * kn, kr = kt * rbar * rbar;
  const Real cap = P.mu_r * kn * delta * P.roll_arm * rbar;
  ContactHistory h;
  int elastic = 0, capped = 0;
  for (int k = 1; k <= 2000; ++k) {
    const ContactResult c = eval<true>(P, s, h);
    EXPECT_NEAR(norm(h.ft), 0, 1e-9 * cap / rbar) << "pure rolling loaded the tangential spring";
    const Real theta = 2 * Om * P.dt * k;
    if (kr * theta < cap * (1 - 1e-9)) {
      EXPECT_NEAR(h.mr.z, -kr * theta, kRoundoff * cap);
      EXPECT_FALSE(c.flags & kRollingSliding);
      ++elastic;
    } else if (kr * theta > cap * (1 + 1e-9)) {
      EXPECT_NEAR(norm(h.mr), cap, kRoundoff * cap);
      EXPECT_TRUE(c.flags & kRollingSliding);
      ++capped;
    }
    // The moment acts on i as +M_r and on j as -M_r, on top of the force couple.
    EXPECT_NEAR(c.ti.z + c.tj.z, 0, kRoundoff * cap);
  }
  ASSERT_GT(elastic, 100);
  ASSERT_GT(capped, 100);
  s.wi = Vec3(0, 0, -Om);
  s.wj = Vec3(0, 0, Om);
  for (int k = 1; k <= 50; ++k) {
    const ContactResult c = eval<true>(P, s, h);
    EXPECT_NEAR(h.mr.z, -cap + kr * 2 * Om * P.dt * k, kRoundoff * cap);
    EXPECT_FALSE(c.flags & kRollingSliding);
  }
}

// mu_r = 0: the rolling-free instantiation leaves the moment history untouched (no rolling work).
TEST(ContactLaw, NoRollingCodeWhenOff) {
  ContactParams P = test::reference_contact();
  P.dt = 1e-7;
  Pair s;
  s.d = Vec3(s.ri + s.rj - 1e-6, 0, 0);
  s.wi = Vec3(0, 0, 50);
  ContactHistory h;
  h.mr = Vec3(1, 2, 3);
  const ContactResult c = eval<false>(P, s, h);
  EXPECT_EQ(h.mr.x, 1);
  EXPECT_EQ(h.mr.z, 3);
  EXPECT_FALSE(c.flags & kRollingSliding);
}

// Item 5a: rotating the whole configuration (positions, velocities, spins and history) by R rotates
// every output by R: the law has no preferred frame.
TEST(ContactLaw, FrameIndifferentUnderRigidRotation) {
  ContactParams P = test::reference_contact();
  P.dt = 1e-7;
  P.mu_r = 0.2;
  std::mt19937_64 g(7);
  std::uniform_real_distribution<Real> U(-1, 1);
  for (int trial = 0; trial < 50; ++trial) {
    Pair s;
    s.rj = 0.5e-3;
    s.mj = test::sphere_mass(s.rj);
    Vec3 dir(U(g), U(g), U(g));
    dir = (1 / norm(dir)) * dir;
    s.d = (s.ri + s.rj - 2e-6) * dir;
    s.vi = Vec3(U(g), U(g), U(g)) * 0.01;
    s.vj = Vec3(U(g), U(g), U(g)) * 0.01;
    s.wi = Vec3(U(g), U(g), U(g)) * 30;
    s.wj = Vec3(U(g), U(g), U(g)) * 30;
    ContactHistory h0;
    h0.ft = to_tangent_plane(Vec3(U(g), U(g), U(g)) * 1e-3, dir);
    h0.mr = to_tangent_plane(Vec3(U(g), U(g), U(g)) * 1e-8, dir);
    Vec3 axis(U(g), U(g), U(g));
    axis = (1 / norm(axis)) * axis;
    const Real ang = 3 * U(g);
    auto Rt = [&](const Vec3& v) { return rotate(axis, ang, v); };
    Pair t = s;
    t.d = Rt(s.d);
    t.vi = Rt(s.vi);
    t.vj = Rt(s.vj);
    t.wi = Rt(s.wi);
    t.wj = Rt(s.wj);
    ContactHistory h1{Rt(h0.ft), Rt(h0.mr)};
    ContactHistory hs = h0;
    const ContactResult a = eval<true>(P, s, hs);
    const ContactResult b = eval<true>(P, t, h1);
    const Real fs = norm(a.f), ts = norm(a.ti) + norm(a.tj);
    EXPECT_LT(norm(b.f - Rt(a.f)), kRoundoff * 100 * fs);
    EXPECT_LT(norm(b.ti - Rt(a.ti)), kRoundoff * 100 * ts);
    EXPECT_LT(norm(b.tj - Rt(a.tj)), kRoundoff * 100 * ts);
    EXPECT_LT(norm(h1.mr - Rt(hs.mr)), kRoundoff * 100 * norm(hs.mr));
    EXPECT_EQ(a.flags, b.flags);
  }
}

// Item 5b: a loaded contact carried through a 90-degree rigid rotation (about an axis normal to n, with
// no relative motion) keeps |F_t| and |M_r| exactly and turns them with the pair. Projection plus
// rescaling is exact for the in-plane and axial parts separately; mixed, the direction error per step is
// O(dtheta^2), so the total is <= theta * dtheta and shrinks with the step (checked at two steps).
TEST(ContactLaw, HistoryFollowsRigidRotationOfThePair) {
  ContactParams P = test::reference_contact();
  P.dt = 1e-7;
  P.mu_r = 0.5;
  const Vec3 axis(0, 0, 1);
  const Real total = M_PI / 2;
  Real err_prev = 1e9;
  for (int nsteps : {90, 900}) {
    Pair s;
    s.d = Vec3(s.ri + s.rj - 2e-6, 0, 0);
    ContactHistory h;
    const Vec3 ft0 = Vec3(0, 1, 1) * 2e-3, mr0 = Vec3(0, 1, -1) * 1e-8;
    h.ft = ft0;
    h.mr = mr0;
    const Real fmag = norm(ft0), mmag = norm(mr0);
    for (int k = 1; k <= nsteps; ++k) {
      Pair t = s;
      t.d = rotate(axis, total * k / nsteps, s.d);
      eval<true>(P, t, h);
      EXPECT_NEAR(norm(h.ft), fmag, kRoundoff * fmag);
      EXPECT_NEAR(norm(h.mr), mmag, kRoundoff * mmag);
    }
    const Real dth = total / nsteps;
    const Real err_f = norm((1 / fmag) * h.ft - (1 / fmag) * rotate(axis, total, ft0));
    const Real err_m = norm((1 / mmag) * h.mr - (1 / mmag) * rotate(axis, total, mr0));
    EXPECT_LT(err_f, total * dth) << nsteps << " steps";
    EXPECT_LT(err_m, total * dth) << nsteps << " steps";
    EXPECT_LT(err_f, err_prev / 5) << "direction error does not shrink with the rotation step";
    err_prev = err_f;
  }
}

// Item 5c: a rigid spin of the pair (v = Omega x X, omega = Omega) does not load the springs: the
// contact point is shared, so the relative velocity there vanishes (the midpoint choice in SPEC §2).
TEST(ContactLaw, RigidSpinDoesNotLoadSprings) {
  ContactParams P = test::reference_contact();
  P.dt = 1e-6;
  P.mu_r = 0.3;
  Pair s;
  s.rj = 0.45e-3;
  s.mj = test::sphere_mass(s.rj);
  const Vec3 xi(1e-3, 2e-3, -1e-3);
  s.d = (s.ri + s.rj - 3e-6) * Vec3(0.6, 0.8, 0);
  const Vec3 Om(10, -40, 25);
  s.vi = cross(Om, xi);
  s.vj = cross(Om, xi + s.d);
  s.wi = s.wj = Om;
  ContactHistory h;
  h.ft = Vec3(0, 0, 1e-3);
  h.mr = Vec3(0, 0, 1e-9);
  const ContactHistory h0 = h;
  eval<true>(P, s, h);
  const Real slip_scale = 0.5 * (s.ri + s.rj) * P.E * norm(Om) * norm(s.d) * P.dt;  // k_t |v| dt
  EXPECT_LT(norm(h.ft - h0.ft), kRoundoff * slip_scale);
  EXPECT_LT(norm(h.mr - h0.mr), kRoundoff * slip_scale * s.ri);
}

// The law compiled for the execution space gives the host's answers (same source, one law). The device part
// lives in free functions: CUDA forbids device lambdas inside a gtest body (a private member function).
namespace grainlab_test {
using namespace grainlab;
using Outputs = Kokkos::View<Real* [15], MemSpace>;

template <class V>
KOKKOS_INLINE_FUNCTION void law_case(const ContactParams& p, const V& src, int k, Real* o) {
  const Real ri = 0.3e-3, rj = 0.4e-3;
  const Vec3 d = Vec3(1 + 0.1 * src(k, 0), 0.1 * src(k, 1), 0.1 * src(k, 2)) * (ri + rj - 2e-6);
  ContactHistory h;
  h.ft = Vec3(src(k, 9), src(k, 10), src(k, 11)) * 1e-3;
  h.mr = Vec3(src(k, 10), src(k, 11), src(k, 9)) * 1e-9;
  const ContactResult c = LinearRollingContact<true, true>::evaluate(
      p, ri, rj, 1e-7, 2e-7, d, norm(d), Vec3(src(k, 3), 0, 0) * 0.01, Vec3(0, src(k, 4), 0) * 0.01,
      Vec3(src(k, 5), src(k, 6), 0) * 10, Vec3(0, src(k, 7), src(k, 8)) * 10, h);
  const Vec3 all[5] = {c.f, c.ti, c.tj, h.ft, h.mr};
  for (int a = 0; a < 5; ++a)
    for (int b = 0; b < 3; ++b) o[3 * a + b] = all[a][b];
}

template <class Inputs>  // any layout: the host view's mirror keeps the host layout
void law_on_device(const ContactParams& P, const Inputs& din, const Outputs& dout) {
  Kokkos::parallel_for(
      "test::law_on_device", Kokkos::RangePolicy<ExecSpace>(0, int(din.extent(0))), KOKKOS_LAMBDA(int k) {
        Real o[15];
        law_case(P, din, k, o);
        for (int c = 0; c < 15; ++c) dout(k, c) = o[c];
      });
}
}  // namespace grainlab_test

TEST(ContactLaw, DeviceMatchesHost) {
  ContactParams P = test::reference_contact();
  P.dt = 1e-7;
  P.mu_r = 0.2;
  P.normal_damping = 0.1;
  const int n = 256;
  Kokkos::View<Real* [12], HostSpace> in("in", n);
  std::mt19937_64 g(3);
  std::uniform_real_distribution<Real> U(-1, 1);
  for (int k = 0; k < n; ++k)
    for (int c = 0; c < 12; ++c) in(k, c) = U(g);
  auto din = Kokkos::create_mirror_view_and_copy(MemSpace(), in);
  grainlab_test::Outputs dout("out", n);
  grainlab_test::law_on_device(P, din, dout);
  auto hout = Kokkos::create_mirror_view_and_copy(HostSpace(), dout);
  for (int k = 0; k < n; ++k) {
    Real o[15];
    grainlab_test::law_case(P, in, k, o);
    // Bitwise on a CPU backend; a GPU compiler may contract a*b+c into an FMA: 1e-12 relative covers it.
    for (int c = 0; c < 15; ++c) EXPECT_NEAR(hout(k, c), o[c], 1e-12 * (std::abs(o[c]) + 1e-300)) << k << "," << c;
  }
}
