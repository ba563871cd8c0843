// Attempt 54's probe (perf/NOTES.md, Session 21): does the per-pair memory layout change how the step scales
// with N on this machine? A synthetic step with the engine's pair-side streams and nothing of the engine:
//   phase 1 ("contact"): per pair read j's x, v, w, read-modify-write the history (ft, mr) and write three
//            outputs (fo, tj, ti): 48 B read + 48 B written history, 72 B written outputs, as kernels/dem.cpp;
//   phase 2 ("integration"): per particle sum its row's fo, ti and its transposed pairs' fo, tj, then kick
//            and drift x, v, w.
// 5 pairs per particle, j = i + 1, 4, 7, 10, 13 (Morton-like near neighbours), every 37th row's last pair
// 20 000 particles away (the ~1 % far pairs of perf/order_locality.py).
// Layout 0: five arrays of 3 doubles per pair (the engine's PairVecView, LayoutRight).
// Layout 1: one 128-B record per pair [fo tj ti ft mr pad], so the integration's transposed read of fo, tj
//           touches one cache line instead of two, and the outputs' lines are already owned (read for ft, mr).
// LAW=1: a sqrt and a division per component (compute about that of the vectorised law); LAW=0: a multiply-add.
// Build and run (2 threads, medians of R rounds, sizes interleaved so a slow minute hits every size alike):
//   g++ -O3 -march=native -fopenmp perf/attempts/54-pair-record-probe.cpp -o /tmp/probe54
//   for law in 1 0; do OMP_NUM_THREADS=2 /tmp/probe54 $law 5; done
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace {

constexpr int K = 5;
int g_law = 1;

inline double law(double a, double b) {
  if (g_law == 0) return a * 0.25 + b * 0.5;
  const double s = std::sqrt(a * a + b * b + 1.0);
  return a / s + b * 0.5;
}

struct Scene {
  long n = 0;
  std::vector<int> pj, toff, tp;
  std::vector<double> x, v, w;
  std::vector<double> ft, mr, fo, tj, ti;  // layout 0
  std::vector<double> rec;                 // layout 1
};

Scene make(long n) {
  Scene s;
  s.n = n;
  const long P = n * K;
  s.pj.resize(P);
  for (long i = 0; i < n; ++i)
    for (int k = 0; k < K; ++k) {
      long j = i + 1 + 3 * k;
      if (k == K - 1 && i % 37 == 0) j = i + 20000;
      s.pj[i * K + k] = int(j % n);
    }
  s.toff.assign(n + 1, 0);
  s.tp.resize(P);
  for (long p = 0; p < P; ++p) s.toff[s.pj[p] + 1]++;
  for (long i = 0; i < n; ++i) s.toff[i + 1] += s.toff[i];
  std::vector<int> c(s.toff.begin(), s.toff.end() - 1);
  for (long p = 0; p < P; ++p) s.tp[c[s.pj[p]]++] = int(p);
  s.x.assign(3 * n, 1.0);
  for (long i = 0; i < 3 * n; ++i) s.x[i] = 1.0 + 1e-3 * double(i % 7);
  s.v.assign(3 * n, 0.1);
  s.w.assign(3 * n, 0.2);
  s.ft.assign(3 * P, 0.0);
  s.mr = s.fo = s.tj = s.ti = s.ft;
  s.rec.assign(16 * P, 0.0);
  return s;
}

template <int Layout>
void step(Scene& s) {
  const long n = s.n;
#pragma omp parallel for schedule(static)
  for (long i = 0; i < n; ++i)
    for (long p = i * K; p < (i + 1) * K; ++p) {
      const long j = s.pj[p];
      for (int d = 0; d < 3; ++d) {
        const double dx = s.x[3 * j + d] - s.x[3 * i + d] + s.v[3 * j + d] + s.w[3 * j + d];
        double* r = &s.rec[16 * p];
        double& hft = Layout == 0 ? s.ft[3 * p + d] : r[9 + d];
        double& hmr = Layout == 0 ? s.mr[3 * p + d] : r[12 + d];
        const double ft = hft * 0.999 + law(dx, hmr);
        const double mr = hmr * 0.999 + 1e-9 * dx;
        hft = ft;
        hmr = mr;
        (Layout == 0 ? s.fo[3 * p + d] : r[d]) = ft + dx;
        (Layout == 0 ? s.tj[3 * p + d] : r[3 + d]) = ft - mr;
        (Layout == 0 ? s.ti[3 * p + d] : r[6 + d]) = ft * mr;
      }
    }
#pragma omp parallel for schedule(static)
  for (long i = 0; i < n; ++i) {
    double f[3] = {0, 0, 0}, t[3] = {0, 0, 0};
    for (long p = i * K; p < (i + 1) * K; ++p)
      for (int d = 0; d < 3; ++d) {
        f[d] -= Layout == 0 ? s.fo[3 * p + d] : s.rec[16 * p + d];
        t[d] += Layout == 0 ? s.ti[3 * p + d] : s.rec[16 * p + 6 + d];
      }
    for (int q = s.toff[i]; q < s.toff[i + 1]; ++q) {
      const long p = s.tp[q];
      for (int d = 0; d < 3; ++d) {
        f[d] += Layout == 0 ? s.fo[3 * p + d] : s.rec[16 * p + d];
        t[d] += Layout == 0 ? s.tj[3 * p + d] : s.rec[16 * p + 3 + d];
      }
    }
    for (int d = 0; d < 3; ++d) {
      s.v[3 * i + d] += 1e-12 * f[d];
      s.w[3 * i + d] += 1e-12 * t[d];
      s.x[3 * i + d] += 1e-12 * s.v[3 * i + d];
    }
  }
}

double time_ns(Scene& s, int layout) {
  const int steps = int(std::max(20L, 20000000L / s.n));
  for (int k = 0; k < 5; ++k) layout == 0 ? step<0>(s) : step<1>(s);
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < steps; ++k) layout == 0 ? step<0>(s) : step<1>(s);
  const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return dt / steps / double(s.n) * 1e9;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3 || (std::atoi(argv[1]) != 0 && std::atoi(argv[1]) != 1) || std::atoi(argv[2]) < 1) {
    std::fprintf(stderr, "usage: %s LAW(0|1) ROUNDS(>=1)\n", argv[0]);
    return 2;
  }
  g_law = std::atoi(argv[1]);
  const int rounds = std::atoi(argv[2]);
  const long sizes[] = {10000, 32000, 256000, 864000};
  std::vector<double> t[4][2];
  for (int r = 0; r < rounds; ++r)
    for (int k = 0; k < 4; ++k) {
      Scene s = make(sizes[k]);
      for (int layout = 0; layout < 2; ++layout) t[k][layout].push_back(time_ns(s, layout));
    }
  std::printf("law=%d threads=%d rounds=%d (medians, ns per particle-step)\n", g_law, omp_get_max_threads(), rounds);
  double lo[2] = {1e300, 1e300}, hi[2] = {0, 0};
  for (int k = 0; k < 4; ++k) {
    std::printf("n=%-7ld", sizes[k]);
    for (int layout = 0; layout < 2; ++layout) {
      auto& v = t[k][layout];
      std::sort(v.begin(), v.end());
      const double med = v[v.size() / 2];
      lo[layout] = std::min(lo[layout], med);
      hi[layout] = std::max(hi[layout], med);
      std::printf("  layout%d %6.2f (%.2f-%.2f)", layout, med, v.front(), v.back());
    }
    std::printf("\n");
  }
  std::printf("spread layout0 %.2f layout1 %.2f\n", hi[0] / lo[0], hi[1] / lo[1]);
}
