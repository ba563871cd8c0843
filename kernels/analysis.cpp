#include "analysis.hpp"

#include <cmath>

namespace grainlab {

Real Sym::operator()(int i, int j) const {
  if (i == j) return v[i];
  const int a = i < j ? i : j, b = i < j ? j : i;
  return a == 0 && b == 1 ? v[3] : (a == 1 && b == 2 ? v[4] : v[5]);
}
Sym Sym::deviator() const {
  Sym d = *this;
  const Real t = trace() / 3;
  for (int k = 0; k < 3; ++k) d.v[k] -= t;
  return d;
}
Real Sym::ddot(const Sym& o) const {
  return v[0] * o.v[0] + v[1] * o.v[1] + v[2] * o.v[2] + 2 * (v[3] * o.v[3] + v[4] * o.v[4] + v[5] * o.v[5]);
}
Sym Sym::scaled(Real s) const {
  Sym r = *this;
  for (auto& x : r.v) x *= s;
  return r;
}

Sym Sym::symmetric_part(const Real (&m)[3][3]) {
  Sym r;
  r.v[0] = m[0][0];
  r.v[1] = m[1][1];
  r.v[2] = m[2][2];
  r.v[3] = 0.5 * (m[0][1] + m[1][0]);
  r.v[4] = 0.5 * (m[1][2] + m[2][1]);
  r.v[5] = 0.5 * (m[2][0] + m[0][2]);
  return r;
}

void stress_invariants(const Sym& sigma, Real& p, Real& q) {
  p = sigma.trace() / 3;
  const Sym d = sigma.deviator();
  q = std::sqrt(1.5 * d.ddot(d));
}

Real signed_invariant(const Sym& a, const Sym& s_dev) {
  const Real aa = a.ddot(a);
  const Real mag = std::sqrt(1.5 * aa);
  const Real sr = a.ddot(s_dev);  // sign of S_r = a:s / (|a||s|)
  return sr < 0 ? -mag : mag;
}

void finish_network(Network& net, const Sym& fabric_sum, const Sym& wd, const Sym& wn, const Sym& wt, const Sym& s_dev) {
  const Real inv = net.nc ? Real(1) / net.nc : 0;
  net.ac = fabric_sum.scaled(inv).deviator().scaled(7.5);  // a^c = 15/2 phi'
  const Sym d = wd.scaled(inv), chn = wn.scaled(inv), cht = wt.scaled(inv);
  net.d0 = d.trace();
  net.f0 = chn.trace();
  net.ad = net.d0 != 0 ? d.deviator().scaled(7.5 / net.d0) : Sym();       // a^d = 15/2 d'/d0
  net.an = net.f0 != 0 ? chn.deviator().scaled(7.5 / net.f0) : Sym();     // a^n = 15/2 chi_n'/f0
  net.at = net.f0 != 0 ? cht.deviator().scaled(5.0 / net.f0) : Sym();     // a^t = 15/3 chi_t'/f0
  net.a_c = signed_invariant(net.ac, s_dev);
  net.a_d = signed_invariant(net.ad, s_dev);
  net.a_n = signed_invariant(net.an, s_dev);
  net.a_t = signed_invariant(net.at, s_dev);
}

void count_rattlers(const Particles& P, const PairList& L, const PairHistory& H, DeterministicSum& red, int& n0,
                    int& n1) {
  const TouchCounter touch{L.offsets, L.t_offsets, L.t_pairs, H.flags};
  Real out[2] = {};
  red.run(
      "grainlab::analysis::rattlers", P.n, 2,
      KOKKOS_LAMBDA(int i, Real* acc) {
        const int c = touch(i, 2);
        if (c == 0) acc[0] += 1;
        if (c == 1) acc[1] += 1;
      },
      out);
  n0 = int(out[0]);
  n1 = int(out[1]);
}

}  // namespace grainlab
