#pragma once
// How a cyclic test's permanent strain stops growing (or does not): its rate per cycle over doubling windows of
// cycles, rate ~ N^-m. m > 1: the strain is bounded (the rates' sum converges: shakedown); m = 1: the logarithmic
// law eps_p = a + c ln N (Barksdale 1972), each doubling of N adding the same strain; 0 < m < 1: growth as a power
// of N (a pure power law eps_1 N^b has m = 1 - b, Monismith et al. 1975); m = 0: a constant rate, ratcheting.
// The study report (scripts/grainlab_plot.py rate_windows / rate_decay) takes the same windows and fit from
// cycles.csv; the run's closing line takes them here. Host code.
//  - Windows from the second cycle (the first, the virgin loading's, apart): [2, 4], [4, 8], [8, 16], ..., the last
//    ending at the last cycle, or joined to the window before where it is shorter than half of it. Each window's rate
//    (eps_b - eps_a) / (b - a) is placed at N_m = (b - a) / ln(b / a), the N at which 1/N is the window's mean, so
//    that the logarithmic law's rate c / N is exact there; doubling windows make a power law's slope exact as well
//    (each window the one before scaled by 2).
//  - m and its standard error by least squares in ln rate - ln N_m over three windows at least (10 cycles); none
//    where a window's strain did not rise (no power of N describes it).
#include <cmath>
#include <string>
#include <vector>

namespace grainlab {

struct RateDecay {
  bool ok = false;
  double m = 0, se = 0;         // the exponent and its standard error (the windows' serial correlation: optimistic)
  size_t windows = 0;           // how many windows were fitted (or taken, where none was)
  std::string why;              // where !ok: "under 10 cycles", "no rise over cycles 8-16"
};

// eps[i]: the permanent strain after cycle i + 1 (cycles 1..n, all of them)
inline RateDecay rate_decay(const std::vector<double>& eps) {
  RateDecay r;
  const size_t n = eps.size();
  std::vector<size_t> edges{2};
  while (edges.back() * 2 <= n) edges.push_back(edges.back() * 2);
  if (edges.back() < n) {
    if (edges.size() > 1 && 2 * (n - edges.back()) < edges.back() - edges[edges.size() - 2])
      edges.back() = n;
    else
      edges.push_back(n);
  }
  r.windows = edges.size() - 1;
  if (r.windows < 3) {
    r.why = "under 10 cycles";
    return r;
  }
  std::vector<double> x, y;
  for (size_t w = 0; w + 1 < edges.size(); ++w) {
    const size_t a = edges[w], b = edges[w + 1];
    const double rate = (eps[b - 1] - eps[a - 1]) / double(b - a);
    if (!(rate > 0)) {
      r.why = "no rise over cycles " + std::to_string(a) + "-" + std::to_string(b);
      return r;
    }
    x.push_back(std::log(double(b - a) / std::log(double(b) / double(a))));
    y.push_back(std::log(rate));
  }
  // least squares y = c + s x, s = -m; the slope's standard error from the residual (k - 2 degrees of freedom)
  const double k = double(x.size());
  double xm = 0, ym = 0;
  for (size_t i = 0; i < x.size(); ++i) xm += x[i] / k, ym += y[i] / k;
  double sxx = 0, sxy = 0;
  for (size_t i = 0; i < x.size(); ++i) sxx += (x[i] - xm) * (x[i] - xm), sxy += (x[i] - xm) * (y[i] - ym);
  const double s = sxy / sxx;
  double ss = 0;
  for (size_t i = 0; i < x.size(); ++i) ss += std::pow(y[i] - ym - s * (x[i] - xm), 2);
  r.ok = true;
  // a constant rate's slope comes out +-1e-17: rounded at 1e-12 (and -0.0 made 0.0) so that it prints 0.00, not
  // -0.00, as the report's python twin does
  r.m = std::round(-s * 1e12) / 1e12 + 0.0;
  r.se = std::sqrt(ss / (k - 2) / sxx);
  return r;
}

}  // namespace grainlab
