#pragma once
#include <cmath>
// Kernel part of compute_descriptors (template on the contact source).

namespace grainlab {

namespace detail {
KOKKOS_INLINE_FUNCTION void add_sym(Real* acc, const Vec3& a, const Vec3& b, Real w) {
  // symmetric part of w a (x) b, as (xx, yy, zz, xy, yz, zx)
  acc[0] += w * a.x * b.x;
  acc[1] += w * a.y * b.y;
  acc[2] += w * a.z * b.z;
  acc[3] += w * 0.5 * (a.x * b.y + a.y * b.x);
  acc[4] += w * 0.5 * (a.y * b.z + a.z * b.y);
  acc[5] += w * 0.5 * (a.z * b.x + a.x * b.z);
}
KOKKOS_INLINE_FUNCTION Real nn_contract(const Real* a, const Vec3& n) {  // a:nn for a as (xx,yy,zz,xy,yz,zx)
  return a[0] * n.x * n.x + a[1] * n.y * n.y + a[2] * n.z * n.z +
         2 * (a[3] * n.x * n.y + a[4] * n.y * n.z + a[5] * n.z * n.x);
}
}  // namespace detail

template <class Src>
Descriptors compute_descriptors(const Src& src, const IntView& off, int nrows, int nparticles, Real volume,
                                DeterministicSum& red) {
  Descriptors D;
  D.np = nparticles;
  // Pass 1: counts, mean normal force, Christoffersen stress (full 3x3: sum f_i d_j).
  Real s1[14] = {};
  red.run(
      "grainlab::analysis::stress", nrows, 14,
      KOKKOS_LAMBDA(int row, Real* acc) {
        for (int p = off(row); p < off(row + 1); ++p) {
        Contact c;
        if (!src(p, c)) continue;
        const Real fn = dot(c.f, c.n);
        acc[0] += 1;
        acc[1] += fn;
        acc[2] += (c.flags & kSliding) ? 1 : 0;
        acc[3] += (c.flags & kRollingSliding) ? 1 : 0;
        const Vec3 d = c.l * c.n;
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) acc[4 + 3 * a + b] += c.f[a] * d[b];
        }
      },
      s1);
  D.nc = int(s1[0]);
  D.sliding = int(s1[2]);
  D.rolling_sliding = int(s1[3]);
  D.f_mean = D.nc ? s1[1] / D.nc : 0;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) D.sigma[a][b] = volume > 0 ? s1[4 + 3 * a + b] / volume : 0;
  const Sym sig = Sym::symmetric_part(D.sigma);
  const Sym s_dev = sig.deviator();
  stress_invariants(sig, D.p, D.q);

  // Pass 2: per network (0 all, 1 strong f_n > mean, 2 weak) the count and the fabric sum n n.
  const Real fbar = D.f_mean;
  Real s2[21] = {};
  red.run(
      "grainlab::analysis::fabric", nrows, 21,
      KOKKOS_LAMBDA(int row, Real* acc) {
        for (int p = off(row); p < off(row + 1); ++p) {
        Contact c;
        if (!src(p, c)) continue;
        const int which[2] = {0, dot(c.f, c.n) > fbar ? 1 : 2};  // the whole network and its subnetwork
        for (int m = 0; m < 2; ++m) {
          const int k = which[m];
          acc[7 * k] += 1;
          detail::add_sym(acc + 7 * k + 1, c.n, c.n, 1);
        }
        }
      },
      s2);
  Sym fab[3];
  Network* nets[3] = {&D.all, &D.strong, &D.weak};
  Real acn[3][6];  // each network's a^c, for its weights
  for (int k = 0; k < 3; ++k) {
    nets[k]->nc = int(s2[7 * k]);
    for (int c = 0; c < 6; ++c) fab[k].v[c] = s2[7 * k + 1 + c];
    const Real inv = nets[k]->nc ? Real(1) / nets[k]->nc : 0;
    const Sym ac = fab[k].scaled(inv).deviator().scaled(7.5);
    for (int c = 0; c < 6; ++c) acn[k][c] = ac.v[c];
  }

  // Pass 3: weighted branch, normal-force and tangential-force tensors with w = 1 / (1 + a^c:nn).
  Real s3[58] = {};
  const Real a0[6] = {acn[0][0], acn[0][1], acn[0][2], acn[0][3], acn[0][4], acn[0][5]};
  const Real a1[6] = {acn[1][0], acn[1][1], acn[1][2], acn[1][3], acn[1][4], acn[1][5]};
  const Real a2[6] = {acn[2][0], acn[2][1], acn[2][2], acn[2][3], acn[2][4], acn[2][5]};
  red.run(
      "grainlab::analysis::weighted", nrows, 58,
      KOKKOS_LAMBDA(int row, Real* acc) {
        for (int p = off(row); p < off(row + 1); ++p) {
        Contact c;
        if (!src(p, c)) continue;
        const Real fn = dot(c.f, c.n);
        const Vec3 ft = c.f - fn * c.n;
        const int net = fn > fbar ? 1 : 2;
        const int which[2] = {0, net};
        for (int m = 0; m < 2; ++m) {
          const int k = which[m];
          const Real* a = k == 0 ? a0 : (k == 1 ? a1 : a2);
          const Real w = Real(1) / (Real(1) + detail::nn_contract(a, c.n));
          Real* o = acc + 18 * k;
          detail::add_sym(o, c.n, c.n, w * c.l);
          detail::add_sym(o + 6, c.n, c.n, w * fn);
          detail::add_sym(o + 12, ft, c.n, w);
        }
        if (net == 2) {
          acc[54] += 1;
          acc[55] += (c.flags & kSliding) ? 1 : 0;
        }
        }
      },
      s3);
  for (int k = 0; k < 3; ++k) {
    Sym wd, wn, wt;
    for (int c = 0; c < 6; ++c) {
      wd.v[c] = s3[18 * k + c];
      wn.v[c] = s3[18 * k + 6 + c];
      wt.v[c] = s3[18 * k + 12 + c];
    }
    finish_network(*nets[k], fab[k], wd, wn, wt, s_dev);
  }
  D.weak_count = int(s3[54]);
  D.sliding_weak = int(s3[55]);
  const Network& A = D.all;
  D.sff = 0.4 * (A.a_c + A.a_d + A.a_n + 1.5 * A.a_t);
  const Real terms[4] = {A.a_c, A.a_d, A.a_n, 1.5 * A.a_t};
  const Real sum = terms[0] + terms[1] + terms[2] + terms[3];
  for (int k = 0; k < 4; ++k) D.share[k] = sum != 0 ? terms[k] / sum : 0;
  D.z = D.np ? 2.0 * D.nc / D.np : 0;
  D.weak_frac = D.nc ? Real(D.weak_count) / D.nc : 0;
  D.sliding_frac = D.nc ? Real(D.sliding) / D.nc : 0;
  D.sliding_weak_frac = D.weak_count ? Real(D.sliding_weak) / D.weak_count : 0;
  D.rolling_sliding_frac = D.nc ? Real(D.rolling_sliding) / D.nc : 0;
  return D;
}

}  // namespace grainlab
