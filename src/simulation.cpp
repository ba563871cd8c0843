#include "simulation.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace grainlab {
namespace fs = std::filesystem;

void write_file_atomic(const std::string& path, const std::string& content) {
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(path + ": cannot write (" + tmp + " could not be created)");
    out << content;
    out.flush();
    if (!out) {
      out.close();
      std::remove(tmp.c_str());
      throw std::runtime_error(path + ": write failed (disk full?); the previous file is untouched");
    }
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw std::runtime_error(path + ": rename failed: " + ec.message());
  }
}

namespace {

struct Sample {
  Real Vs = 0;  // solid volume [m^3]
};

struct State {
  Real sx = 0, sy = 0, sz = 0, p = 0, q = 0, V = 0, e = 0;
};

State wall_state(const Engine& eng, const Sample& s) {
  State st;
  st.sx = 0.5 * (eng.wall_stress(0) + eng.wall_stress(1));
  st.sy = 0.5 * (eng.wall_stress(2) + eng.wall_stress(3));
  st.sz = 0.5 * (eng.wall_stress(4) + eng.wall_stress(5));
  st.p = (st.sx + st.sy + st.sz) / 3;
  st.q = st.sz - 0.5 * (st.sx + st.sy);  // triaxial deviator, axial = z
  st.V = eng.box_volume();
  st.e = (st.V - s.Vs) / s.Vs;
  return st;
}

class Series {
 public:
  explicit Series(std::string path) : path_(std::move(path)) {
    os_ << "time,step,stage,eps_a,eps_v,e,p,q,u,sigma_x,sigma_y,sigma_z,z,kinetic_energy,ufr,"
           "sliding_frac,rolling_sliding_frac,dt,density_scaling\n";
  }
  void row(const Engine& eng, const std::string& stage, const State& st, const Diagnostics& d, Real eps_a,
           Real eps_v, Real u, Real density_scaling) {
    const int np = eng.num_particles();
    os_ << std::setprecision(10) << eng.time() << ',' << eng.step_count() << ',' << stage << ',' << eps_a << ','
        << eps_v << ',' << st.e << ',' << st.p << ',' << st.q << ',' << u << ',' << st.sx << ',' << st.sy << ','
        << st.sz << ',' << (np ? 2.0 * d.contacts / np : 0) << ',' << d.kinetic << ',' << d.unbalanced_ratio << ','
        << (d.contacts ? Real(d.sliding) / d.contacts : 0) << ','
        << (d.contacts ? Real(d.rolling_sliding) / d.contacts : 0) << ',' << eng.dt() << ',' << density_scaling
        << '\n';
  }
  void flush() { write_file_atomic(path_, os_.str()); }

 private:
  std::string path_;
  std::ostringstream os_;
};

class Progress {
 public:
  explicit Progress(bool quiet) : quiet_(quiet), tty_(::isatty(STDOUT_FILENO)) {}
  void show(const std::string& line) {
    if (quiet_) return;
    if (tty_) {
      std::printf("\r%-110s", line.c_str());
      std::fflush(stdout);
    } else {
      std::printf("%s\n", line.c_str());
    }
  }
  void done() {
    if (!quiet_ && tty_) std::printf("\n");
  }

 private:
  bool quiet_, tty_;
};

}  // namespace

std::vector<StageResult> run_simulation(const RunConfig& cfg, const RunOptions& opt) {
  const std::string out = opt.out_dir.empty() ? cfg.out_dir : opt.out_dir;
  fs::create_directories(out);
  Packing pk = generate_packing(cfg.packing);
  ParticleSetup setup;
  setup.x = pk.x;
  setup.r = pk.r;
  setup.density = cfg.density;
  setup.density_scaling = cfg.density_scaling;
  Sample sample;
  for (Real r : pk.r) sample.Vs += 4.0 / 3.0 * M_PI * r * r * r;
  // The time step is chosen once for the whole run, for its stiffest stage (rolling on in any stage).
  EngineParams ep = cfg.engine;
  for (const StageConfig& sc : cfg.stages) ep.contact.mu_r = std::max(ep.contact.mu_r, sc.mu_r);
  Engine eng(setup, ep, make_box_walls(pk.lo, pk.hi), true);
  if (!opt.quiet)
    std::printf("grainlab %s | Kokkos %d | %s x %d threads | %d particles | dt = %.4g s (%.3g of the limit)\n",
                GRAINLAB_VERSION, KOKKOS_VERSION, ExecSpace::name(), ExecSpace().concurrency(),
                eng.num_particles(), eng.dt(), eng.dt() / eng.critical_dt());

  Series series(out + "/series.csv");
  Progress progress(opt.quiet);
  std::vector<StageResult> results;
  auto clock = std::chrono::steady_clock::now;

  for (const StageConfig& sc : cfg.stages) {
    eng.set_friction(sc.mu, sc.mu_r);
    eng.set_damping(sc.damping);
    StageResult res;
    res.name = sc.name;
    const State st0 = wall_state(eng, sample);
    const Real H0 = eng.wall_position(5) - eng.wall_position(4);
    const Real V0 = st0.V;
    const Real p0 = sc.type == StageType::Isotropic ? sc.pressure : std::max<Real>(st0.p, 1e-30);
    const Real aspect = (eng.wall_position(1) - eng.wall_position(0)) / (eng.wall_position(3) - eng.wall_position(2));
    for (int k = 0; k < 6; ++k) {
      WallControl& c = eng.wall_control(k);
      c = WallControl{};
      c.gain = sc.servo_gain;
      if (sc.type == StageType::Isotropic) {
        c.mode = WallMode::Servo;
        c.target_stress = sc.pressure;
      } else if (k >= 4) {
        c.mode = WallMode::Velocity;  // axial walls approach each other at the strain rate
        c.velocity = 0.5 * sc.axial_strain_rate * H0;
      } else if (sc.drainage == Drainage::Drained) {
        c.mode = WallMode::Servo;
        c.target_stress = p0;  // sigma_3 = p'_0 (SPEC §6.3)
      } else {
        c.mode = WallMode::Fixed;  // placed analytically below
      }
    }
    auto t_start = clock();
    long s = 0;
    Real eps_a = 0, eps_v = 0, u = 0;
    for (; s < sc.max_steps; ++s) {
      eng.step();
      if (sc.type == StageType::Triaxial) {
        const Real H = eng.wall_position(5) - eng.wall_position(4);
        if (sc.drainage == Drainage::Undrained) {
          // Exact constant volume: lateral walls placed every step so Lx Ly H = V0 at a fixed aspect.
          const Real cx = 0.5 * (eng.wall_position(0) + eng.wall_position(1));
          const Real cy = 0.5 * (eng.wall_position(2) + eng.wall_position(3));
          const Real Ly = std::sqrt(V0 / (H * aspect));
          const Real Lx = V0 / (H * Ly);
          eng.set_wall_position(0, cx - 0.5 * Lx);
          eng.set_wall_position(1, cx + 0.5 * Lx);
          eng.set_wall_position(2, cy - 0.5 * Ly);
          eng.set_wall_position(3, cy + 0.5 * Ly);
        }
        eps_a = (H0 - H) / H0;
        eps_v = (V0 - eng.box_volume()) / V0;
      }
      const bool report = (eng.step_count() % cfg.output_every) == 0;
      const bool check = ((s + 1) % sc.check_every) == 0;
      if (!(report || check)) continue;
      const State st = wall_state(eng, sample);
      const Diagnostics d = eng.diagnostics();
      if (sc.type == StageType::Triaxial && sc.drainage == Drainage::Undrained)
        u = (p0 + st.q / 3) - st.p;  // SPEC §6.3: u = p_total - p', p_total = p'_0 + q/3
      if (report) {
        series.row(eng, sc.name, st, d, eps_a, eps_v, u, cfg.density_scaling);
        const double el = std::chrono::duration<double>(clock() - t_start).count();
        std::ostringstream line;
        line << std::setprecision(4) << sc.name << " | step " << eng.step_count() << " | p = " << st.p / 1e3
             << " kPa | q = " << st.q / 1e3 << " kPa | e = " << st.e;
        if (sc.type == StageType::Triaxial) line << " | eps_a = " << eps_a;
        line << " | ufr = " << d.unbalanced_ratio << " | " << std::setprecision(3) << (s + 1) / std::max(el, 1e-9)
             << " steps/s";
        progress.show(line.str());
      }
      if (check) {
        bool done;
        if (sc.type == StageType::Isotropic) {
          // SPEC §6.2: pressure within tolerance and equilibrium (unbalanced force and kinetic energy).
          bool walls_ok = true;
          for (int k = 0; k < 6; ++k)
            walls_ok = walls_ok && std::abs(eng.wall_stress(k) - sc.pressure) <= sc.pressure_tolerance * sc.pressure;
          done = walls_ok && d.unbalanced_ratio < sc.ufr_tolerance && d.kinetic < sc.ke_tolerance * d.potential;
        } else {
          done = eps_a >= sc.max_axial_strain;
        }
        if (done) {
          res.converged = true;
          ++s;
          break;
        }
      }
    }
    progress.done();
    const State st = wall_state(eng, sample);
    res.steps = s;
    res.p = st.p;
    res.q = st.q;
    res.e = st.e;
    series.row(eng, sc.name, st, eng.diagnostics(), eps_a, eps_v, u, cfg.density_scaling);
    series.flush();
    if (!opt.quiet)
      std::printf("stage %s: %s after %ld steps, p = %.4g kPa, q = %.4g kPa, e = %.4f\n", sc.name.c_str(),
                  res.converged ? "done" : "NOT converged (max_steps reached)", s, st.p / 1e3, st.q / 1e3, st.e);
    results.push_back(res);
  }
  if (!opt.quiet) std::printf("series: %s/series.csv\n", out.c_str());
  return results;
}

}  // namespace grainlab
