// The shared peer race (../shared/bench/peers/RESULTS.md §3) on grainlab: the same scene, material,
// walls, dt and step counts as the LAMMPS/LIGGGHTS/YADE inputs, timed the same way (warm-up run,
// then a fenced timed run; reading the scene and building the engine are not timed).
//
//   race_bench --scene scene_32k.txt --box scene_32k_box.txt [--rolling 1] [--warmup 200] [--steps 2000]
//              [--tile K] [--crop F] [--generate N] [--reps R] [--sort 0|1] [--skin M] [--inner F] [--copy 1]
//              [--kernel row|lanes]
//   race_bench --scene ... --box ... [--tile K] [--crop F] --write-scene PREFIX
//
// --write-scene: writes the scene as built (cropped, tiled; `x y z r` per line, %.17g) to PREFIX.txt and its
// walls to PREFIX_box.txt, the shared scene's two formats, and exits: the peers' inputs then run the very
// spheres grainlab runs (perf/scaling_peers.sh). Each file goes to a temporary name first and is renamed
// when complete.
//
// --skin: the Verlet skin (the race fixes 1e-4 m). --inner: EngineParams::inner_skin (default: the engine's,
// 0.1; 0 streams the Verlet list itself, the list the peers loop over; perf/race.sh runs both).
// --kernel: EngineParams::pair_kernel (default: lanes where built, else row; the same bits either way).
//
// Prints one line per rep: `particle_steps_per_s=<rate> ...` with the wall time, the contact count at the
// end (Z = 2 Nc / N, comparable with the peers' table), the kinetic energy and the step's compulsory
// traffic (perf/traffic.hpp). --copy 1 first prints the device's copy bandwidth (2 x 256 MB, median of 20),
// so that a GPU run reports bytes per particle-step against the floor measured in the same process.
//
// Stiffness (the issue lets us choose, we say which): grainlab's contact law is SPEC §2's k_n = E r̄. The
// race uses k_n = k_t = 2e4 N/m for every pair; we set E = 2e4 / <r̄>, with <r̄> the mean pair radius of
// the scene's touching pairs, so the mean pair stiffness is the peers' (spread over the size ratio 3:
// 0.7-2.1x). Rolling: the peers' k_r = k_t R*^2 and M <= 0.1 R* |F_n| (R* = r_i r_j/(r_i+r_j)); ours is
// k_r = k_t r̄^2 and M <= mu_r l |F_n| with l = roll_arm r̄; mu_r = 0.1 and roll_arm = 0.5 give the peers'
// limit for equal spheres (R* = r̄/2). Normal damping: the peers' gamma_n = 4e4 1/s is a damping ratio
// of ~0.06 for a mean pair; ours is the ratio form, beta = 0.06. Walls: frictionless, k_w = E_w r with
// E_w = 2e4 / <r>. No Cundall damping, no gravity. The work per step is the same as the peers'
// (one contact law evaluation per listed pair, history carried, six walls); the constants differ within
// the factors above.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "scene.hpp"
#include "src/h5io.hpp"
#include "traffic.hpp"

using namespace grainlab;

namespace {

struct Args {
  perf::SceneArgs scene;
  int rolling = 1;
  long warmup = 200, steps = 2000;
  int reps = 1;
  double skin = 1e-4;  // the race fixes 0.1 mm; other values only to study the list's cost
  double inner = EngineParams{}.inner_skin;  // the engine's inner list (fraction of skin; 0 = off)
  PairKernel kernel = kDefaultPairKernel;
  int copy = 0;  // 1: first measure the device's copy bandwidth (the floor for bytes_per_particle_step)
  std::string write_scene;  // non-empty: write the built scene to PREFIX.txt / PREFIX_box.txt and exit
};

[[noreturn]] void usage(const std::string& why) {
  std::cerr << "race_bench: " << why
            << "\nusage: race_bench --scene FILE --box FILE [--rolling 0|1] [--warmup N] [--steps N] [--reps R]"
               " [--skin M] [--inner F] [--kernel row|lanes|pairs] [--tile K] [--crop F] [--sort 0|1]\n       race_bench --generate N [...]\n"
               "       race_bench --scene FILE --box FILE [--tile K] [--crop F] --write-scene PREFIX\n";
  std::exit(2);
}

Args parse(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string k = argv[i];
    if (i + 1 >= argc) usage("missing value after " + k);
    const std::string v = argv[++i];
    try {
      if (a.scene.parse(k, v)) continue;
      if (k == "--rolling") a.rolling = std::stoi(v);
      else if (k == "--warmup") a.warmup = std::stol(v);
      else if (k == "--steps") a.steps = std::stol(v);
      else if (k == "--reps") a.reps = std::stoi(v);
      else if (k == "--skin") a.skin = std::stod(v);
      else if (k == "--inner") a.inner = std::stod(v);
      else if (k == "--copy") a.copy = std::stoi(v);
      else if (k == "--write-scene") a.write_scene = v;
      else if (k == "--kernel") {
        if (v != "row" && v != "lanes" && v != "pairs") usage("--kernel is row, lanes or pairs");
        if (v == "lanes" && !kPairLanesBuilt) usage("--kernel lanes: the pair-lane kernel is not built here");
        a.kernel = v == "row" ? PairKernel::Row : v == "lanes" ? PairKernel::Lanes : PairKernel::Pairs;
      }
      else usage("unknown option " + k);
    } catch (const std::logic_error&) {
      usage("bad value '" + v + "' for " + k);
    }
  }
  if (a.steps < 1 || a.warmup < 0 || a.reps < 1 || !(a.skin > 0) || !(a.inner >= 0 && a.inner < 1))
    usage("--steps, --reps >= 1, --warmup >= 0, --skin > 0, 0 <= --inner < 1");
  if (a.copy != 0 && a.copy != 1) usage("--copy is 0 or 1");
  return a;
}

// `path` written through the engine's atomic commit (src/h5io.hpp: a temporary name, fsync, rename), so that a
// reader never finds a half-written scene under the final name.
void write_atomically(const std::string& path, const std::string& text) {
  const std::string tmp = temp_name(path);
  {
    std::ofstream f(tmp, std::ios::trunc);
    f << text;
    f.flush();
    if (!f) {
      std::remove(tmp.c_str());
      throw std::runtime_error("race_bench: cannot write " + tmp);
    }
  }
  commit_atomic(tmp, path);
}

// The scene's spheres and walls in the shared scene's formats (scene_32k.txt, scene_32k_box.txt).
void write_scene(const perf::Scene& sc, const std::string& prefix) {
  std::string spheres;
  char line[160];
  for (size_t q = 0; q < sc.s.r.size(); ++q) {
    std::snprintf(line, sizeof line, "%.17g %.17g %.17g %.17g\n", sc.s.x[q][0], sc.s.x[q][1], sc.s.x[q][2], sc.s.r[q]);
    spheres += line;
  }
  write_atomically(prefix + ".txt", spheres);
  std::snprintf(line, sizeof line, "%.17g %.17g %.17g %.17g %.17g %.17g\n", sc.lo[0], sc.hi[0], sc.lo[1], sc.hi[1],
                sc.lo[2], sc.hi[2]);
  write_atomically(prefix + "_box.txt", line);
}

// Resident set size of the process (/proc/self/status VmRSS): engine arrays, the scene read from the file
// and the runtime; per particle it is an upper bound of the engine's memory per particle.
double resident_bytes() {
  std::ifstream f("/proc/self/status");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind("VmRSS:", 0) == 0) return 1024.0 * std::stod(line.substr(6));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const Args a = parse(argc, argv);
  if (!a.write_scene.empty()) {  // host work only: no Kokkos
    const perf::Scene sc = perf::load_scene(a.scene);
    try {
      write_scene(sc, a.write_scene);
    } catch (const std::exception& e) {
      std::cerr << e.what() << "\n";
      return 1;
    }
    std::printf("wrote %s.txt and %s_box.txt: %zu spheres\n", a.write_scene.c_str(), a.write_scene.c_str(), sc.s.r.size());
    return 0;
  }
  compat::initialize(0);
  int rc = 0;
  {
    if (a.copy) {
      const long n = 32L << 20;  // 256 MB per view: far beyond any cache (H100 L2 50 MB, EPYC L3 32 MB)
      const perf::CopyBandwidth bw = perf::copy_bandwidth(n, 20);
      std::printf("copy_kernel_bytes_per_s=%.4g deep_copy_bytes_per_s=%.4g backend=%s\n", bw.kernel, bw.deep_copy,
                  ExecSpace::name());
      std::fflush(stdout);
    }
    perf::Scene sc = perf::load_scene(a.scene);
    const int n = int(sc.s.r.size());
    // <r̄> over the scene's touching pairs (brute force would be N^2: the engine's list does it).
    EngineParams p;
    p.contact.E = 1;  // placeholder for the pair census below
    p.skin = 1e-4;
    p.dt_factor = 1;
    Real rbar_mean = 0, r_mean = 0;
    for (Real r : sc.s.r) r_mean += r / n;
    {
      Engine probe(sc.s, p, make_box_walls(sc.lo, sc.hi), true);
      const PairList& L = probe.pairs();
      auto hi = Kokkos::create_mirror_view_and_copy(HostSpace(), L.pair_i);
      auto hj = Kokkos::create_mirror_view_and_copy(HostSpace(), L.pair_j);
      long touching = 0;
      for (int q = 0; q < L.npairs; ++q) {
        const int i = hi(q), j = hj(q);
        Real d2 = 0;
        for (int k = 0; k < 3; ++k) d2 += (sc.s.x[j][k] - sc.s.x[i][k]) * (sc.s.x[j][k] - sc.s.x[i][k]);
        const Real sum = sc.s.r[i] + sc.s.r[j];
        if (d2 < sum * sum) {
          rbar_mean += 0.5 * sum;
          ++touching;
        }
      }
      rbar_mean = touching ? rbar_mean / touching : r_mean;
    }
    const Real k = 2.0e4;
    p.contact.E = k / rbar_mean;
    p.contact.kappa = 1;
    p.contact.mu = 0.5;
    p.contact.mu_r = a.rolling ? 0.1 : 0.0;
    p.contact.roll_arm = 0.5;
    p.contact.normal_damping = 0.06;
    p.contact.dt = 1e-7;
    p.E_wall = k / r_mean;
    p.damping = 0;
    p.skin = a.skin;
    p.inner_skin = a.inner;
    p.pair_kernel = a.kernel;
    for (int rep = 0; rep < a.reps; ++rep) {
      Engine eng(sc.s, p, make_box_walls(sc.lo, sc.hi), true);
      eng.wall_control(4) = WallControl{WallMode::Velocity, 0.01};  // bottom, inward
      eng.wall_control(5) = WallControl{WallMode::Velocity, 0.01};  // top, inward
      eng.run(a.warmup);
      const int builds0 = eng.rebuild_count(), filters0 = eng.refilter_count();
      compat::fence("grainlab::race::before");
      const auto t0 = std::chrono::steady_clock::now();
      eng.run(a.steps);
      compat::fence("grainlab::race::after");
      const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const Diagnostics dg = eng.diagnostics();
      const HealthReport h = eng.check_health(HealthLimits{});
      if (!h.ok) {
        std::cerr << "race_bench: unhealthy state: " << h.what << "\n";
        rc = 3;
      }
      std::printf(
          "particle_steps_per_s=%.4g wall_s=%.4f particles=%d steps=%ld rolling=%d threads=%d Z=%.3f "
          "kinetic_J=%.17g listed_pairs=%d verlet_pairs=%d inner_skin=%g kernel=%s rebuilds_timed=%d refilters_timed=%d E=%.5g "
          "E_wall=%.5g rss_bytes_per_particle=%.0f bytes_per_particle_step=%.0f backend=%s\n",
          double(n) * double(a.steps) / wall, wall, n, a.steps, a.rolling, ExecSpace().concurrency(),
          2.0 * dg.contacts / n, dg.kinetic, eng.pairs().npairs, eng.verlet_pairs().npairs, p.inner_skin,
          perf::kernel_name(p.pair_kernel), eng.rebuild_count() - builds0, eng.refilter_count() - filters0, p.contact.E,
          p.E_wall, resident_bytes() / n, perf::step_bytes(eng) / n, ExecSpace::name());
      std::fflush(stdout);
    }
  }
  Kokkos::finalize();
  return rc;
}
