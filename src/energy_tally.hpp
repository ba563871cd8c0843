#pragma once
// Energy bookkeeping of a leapfrog run, shared by tests/test_conservation and perf/energy_drift. The energy
// at step k is PE(x_k) + (KE_{k-1/2} + KE_{k+1/2}) / 2: the half-step velocities' kinetic energies
// averaged to the instant of the positions. Band = (max - min) / E_0; drift = |<E> of the last tenth -
// <E> of the first tenth| / E_0 (the trend, with the oscillation averaged out).
#include <algorithm>
#include <cmath>

#include "kernels/types.hpp"

namespace grainlab {

class EnergyTally {
 public:
  EnergyTally(long steps, Real ke0) : steps_(steps), window_(std::max(1L, steps / 10)), ke_prev_(ke0) {}
  // pe: potential energy before the step; ke: kinetic energy after it.
  void add(Real pe, Real ke) {
    const Real e = pe + Real(0.5) * (ke_prev_ + ke);
    ke_prev_ = ke;
    if (k_ == 0) e0_ = e;
    emax_ = std::max(emax_, e);
    emin_ = std::min(emin_, e);
    if (k_ < window_) first_ += e / Real(window_);
    if (k_ >= steps_ - window_) last_ += e / Real(window_);
    ++k_;
  }
  Real e0() const { return e0_; }
  Real band() const { return (emax_ - emin_) / e0_; }
  Real drift() const { return std::abs(last_ - first_) / e0_; }

 private:
  long steps_, window_, k_ = 0;
  Real ke_prev_, e0_ = 0, emax_ = -1e300, emin_ = 1e300, first_ = 0, last_ = 0;
};

}  // namespace grainlab
