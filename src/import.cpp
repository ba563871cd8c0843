// `grainlab import` (a text packing, a LAMMPS/LIGGGHTS dump or data file as a sample file) and `grainlab export` (a
// sample as text for another code): import.hpp.
#include "import.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "h5io.hpp"
#include "packing.hpp"
#include "simulation.hpp"

namespace grainlab {
namespace fs = std::filesystem;

namespace {
std::string num(Real v, int digits = 4) {
  std::ostringstream os;
  os.precision(digits);
  os << v;
  return os.str();
}
std::string mm(Real v) { return num(v * 1e3) + " mm"; }
// A box as an option takes it, xlo xhi ylo yhi zlo zhi, each number the shortest that reads back as the same double
std::string box_text(const Vec3d& lo, const Vec3d& hi) {
  std::string out;
  for (int a = 0; a < 6; ++a) {
    const Real v = a % 2 ? hi[a / 2] : lo[a / 2];
    std::string t;
    for (int digits = 1; digits <= 17; ++digits)
      if (t = num(v, digits); std::strtod(t.c_str(), nullptr) == v) break;
    out += (a ? " " : "") + t;
  }
  return out;
}
// A line as an error quotes it: its first 80 characters, without the line end.
std::string quoted(std::string s) {
  while (!s.empty() && (s.back() == '\r' || s.back() == '\n')) s.pop_back();
  return "'" + (s.size() > 80 ? s.substr(0, 77) + "..." : s) + "'";
}

struct Read {
  std::vector<Vec3d> x;
  std::vector<Real> r;
  std::vector<long> line;  // each sphere's line in the file (1-based), for messages
  // a LAMMPS or LIGGGHTS dump: its last snapshot's timestep, how many it holds, its box and its atoms' ids
  bool dump = false;
  long timestep = 0, snapshots = 0;
  std::string periodic;  // the last snapshot's periodic axes ("x, z" for BOX BOUNDS pp ff pp), "" for none
  Vec3d file_lo{}, file_hi{};  // its box bounds as the file gives them (before --scale): the note's --crop
  Vec3d lo{}, hi{};
  std::vector<long> id;
  // a LAMMPS data file (read_data's): its box and ids as a dump's, and its first atom's density (at density_lines[0];
  // density_lines[1] > 0: the first line whose density differs)
  bool data = false;
  Real density = 0;
  long density_lines[2] = {0, 0};
  // a text packing: what the first line printed adds (the columns read, a header line skipped)
  std::string how;
};

// The box the spheres fill: min(x - r) to max(x + r) on each axis (non-empty x).
void bounding_box(const std::vector<Vec3d>& x, const std::vector<Real>& r, Vec3d& lo, Vec3d& hi) {
  for (int a = 0; a < 3; ++a) lo[a] = hi[a] = x[0][a];
  for (size_t i = 0; i < r.size(); ++i)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], x[i][a] - r[i]);
      hi[a] = std::max(hi[a], x[i][a] + r[i]);
    }
}

[[noreturn]] void bad(const std::string& path, long ln, const std::string& why) {
  throw std::runtime_error(path + ":" + std::to_string(ln) + ": " + why);
}

// A sphere's values as read: finite, r > 0, r <= 1 m after the scale (sample.r_max's range: a radius past 1 m is a
// file in other units far more often than a sample of boulders).
void add_sphere(Read& in, const std::string& path, long ln, const Real v[4], Real scale) {
  const char* names[4] = {"x", "y", "z", "r"};
  for (int c = 0; c < 4; ++c)
    if (!std::isfinite(v[c])) bad(path, ln, std::string(names[c]) + " = " + num(v[c]) + " is not a finite number");
  if (!(v[3] > 0)) bad(path, ln, "r = " + num(v[3]) + " must be > 0");
  if (in.r.size() >= 100000000)
    throw std::runtime_error(path + ": more than 100000000 spheres (sample.count's range is [1, 1e8])");
  if (v[3] * scale > 1)
    bad(path, ln,
        "r = " + num(v[3] * scale) + " m" + (scale != 1 ? " (after --scale " + num(scale) + ")" : std::string()) +
            " is above 1 m (sample.r_max's range is (0, 1]): a file in mm takes --scale 1e-3");
  in.x.push_back({v[0] * scale, v[1] * scale, v[2] * scale});
  in.r.push_back(v[3] * scale);
  in.line.push_back(ln);
}

// The numbers of a line (blanks between them); false where a token is not a number.
bool numbers(const std::string& s, std::vector<double>& out) {
  out.clear();
  const char* p = s.c_str();
  for (;;) {
    while (*p == ' ' || *p == '\t' || *p == '\r') ++p;
    if (!*p) return true;
    char* end = nullptr;
    const double d = std::strtod(p, &end);
    if (end == p || (*end && *end != ' ' && *end != '\t' && *end != '\r')) return false;
    out.push_back(d);
    p = end;
  }
}

// A LAMMPS or LIGGGHTS text dump (`dump custom` with x y z, or xs ys zs, or xu yu zu, and radius or diameter): its
// last snapshot, the box bounds as the walls (an orthogonal box; a triclinic one is refused).
Read read_dump(std::ifstream& f, const std::string& path, Real scale) {
  Read in;
  std::string text;
  long ln = 0;
  std::vector<double> v;
  auto next = [&](const char* what) {
    if (!std::getline(f, text))
      throw std::runtime_error(path + ": ends after line " + std::to_string(ln) + ", " + what +
                               " expected (a dump cut short?)");
    ++ln;
  };
  long natoms = -1;
  Vec3d lo{}, hi{};
  bool box = false;
  bool other = false;  // within an ITEM: this reader skips, until the next ITEM:
  while (std::getline(f, text)) {
    ++ln;
    if (text.rfind("ITEM:", 0) == 0) other = false;
    if (text.rfind("ITEM: TIMESTEP", 0) == 0) {
      next("the timestep");
      if (!numbers(text, v) || v.size() != 1) bad(path, ln, quoted(text) + " is not a timestep");
      in.timestep = long(v[0]);
      ++in.snapshots;
      natoms = -1;
      box = false;
    } else if (text.rfind("ITEM: NUMBER OF ATOMS", 0) == 0) {
      next("the number of atoms");
      if (!numbers(text, v) || v.size() != 1 || !(v[0] >= 1) || v[0] > 1e8)
        bad(path, ln, quoted(text) + " is not a number of atoms in [1, 1e8]");
      natoms = long(v[0]);
    } else if (text.rfind("ITEM: BOX BOUNDS", 0) == 0) {
      if (text.find("xy") != std::string::npos)
        bad(path, ln, "a triclinic box: the walls are an orthogonal box (give it with --box)");
      // the boundary flags, one an axis (pp periodic; ff, fs, fm, ss, ... walls or shrink-wrapped)
      std::istringstream flags(text.substr(16));
      in.periodic.clear();
      std::string flag;
      for (int a = 0; a < 3 && flags >> flag; ++a)
        if (flag == "pp") in.periodic += std::string(in.periodic.empty() ? "" : ", ") + "xyz"[a];
      for (int a = 0; a < 3; ++a) {
        next("the box bounds");
        if (!numbers(text, v) || v.size() != 2) bad(path, ln, quoted(text) + " is not two bounds lo hi");
        lo[a] = v[0];
        hi[a] = v[1];
      }
      box = true;
    } else if (text.rfind("ITEM: ATOMS", 0) == 0) {
      if (natoms < 0 || !box) bad(path, ln, "ITEM: ATOMS before the snapshot's NUMBER OF ATOMS and BOX BOUNDS");
      std::istringstream cols(text.substr(11));
      std::vector<std::string> names;
      for (std::string c; cols >> c;) names.push_back(c);
      auto col = [&](std::initializer_list<const char*> any) {
        for (const char* a : any)
          if (auto it = std::find(names.begin(), names.end(), a); it != names.end()) return int(it - names.begin());
        return -1;
      };
      const int cx[3] = {col({"x", "xu", "xs"}), col({"y", "yu", "ys"}), col({"z", "zu", "zs"})};
      const int cr = col({"radius"}), cd = col({"diameter"}), cid = col({"id"});
      if (cx[0] < 0 || cx[1] < 0 || cx[2] < 0 || (cr < 0 && cd < 0))
        bad(path, ln,
            "ITEM: ATOMS has no x y z (or xs ys zs, xu yu zu) and radius (or diameter) columns: dump it "
            "with `dump custom ... id x y z radius`");
      bool scaled[3];
      for (int a = 0; a < 3; ++a) scaled[a] = names[size_t(cx[a])][1] == 's';
      Read snap;
      snap.x.reserve(size_t(natoms));
      for (long k = 0; k < natoms; ++k) {
        next("an atom line");
        if (!numbers(text, v) || v.size() != names.size())
          bad(path, ln,
              quoted(text) + " is not " + std::to_string(names.size()) +
                  " numbers, one for each column of "
                  "ITEM: ATOMS");
        Real sphere[4];
        for (int a = 0; a < 3; ++a) {
          const Real c = v[size_t(cx[a])];
          sphere[a] = scaled[a] ? lo[a] + c * (hi[a] - lo[a]) : c;
        }
        sphere[3] = cr >= 0 ? v[size_t(cr)] : 0.5 * v[size_t(cd)];
        add_sphere(snap, path, ln, sphere, scale);
        if (cid >= 0) snap.id.push_back(long(v[size_t(cid)]));
      }
      snap.dump = true;
      snap.timestep = in.timestep;
      snap.snapshots = in.snapshots;
      snap.periodic = in.periodic;
      for (int a = 0; a < 3; ++a) {
        snap.lo[a] = lo[a] * scale;
        snap.hi[a] = hi[a] * scale;
        snap.file_lo[a] = lo[a];
        snap.file_hi[a] = hi[a];
      }
      in = std::move(snap);
    } else if (text.rfind("ITEM:", 0) == 0) {
      other = true;  // ITEM: TIME, ITEM: UNITS (dump_modify time / units yes): values nothing here needs
    } else if (!other && text.find_first_not_of(" \t\r") != std::string::npos) {
      bad(path, ln, quoted(text) + " is no part of a LAMMPS dump (ITEM: lines, then their values)");
    }
  }
  if (f.bad()) throw std::runtime_error(path + ": read error");
  if (in.r.empty()) throw std::runtime_error(path + ": a dump without an ITEM: ATOMS snapshot");
  return in;
}

// A line's first word, and whether it starts with a letter (a data file's section or header keyword).
std::string first_word(const std::string& text) {
  std::istringstream is(text);
  std::string w;
  is >> w;
  return w;
}
bool is_word(const std::string& w) { return !w.empty() && std::isalpha(static_cast<unsigned char>(w[0])); }

// A LAMMPS data file (read_data's; LIGGGHTS's the same) of atom_style sphere or granular: the header's atom count and
// box (an orthogonal one), then the Atoms section's rows `id type diameter density x y z` (and image flags ix iy iz);
// other sections skipped.
Read read_data(std::ifstream& f, const std::string& path, Real scale) {
  Read in;
  in.data = true;
  std::string text;
  long ln = 1, natoms = -1;
  std::getline(f, text);  // the title line
  bool bounds[3] = {false, false, false};
  std::vector<double> v;
  std::string section;  // the section being read ("" in the header)
  long rows = 0;
  while (std::getline(f, text)) {
    ++ln;
    const std::string body = text.substr(0, text.find('#'));
    const std::string w = first_word(body);
    if (w.empty()) continue;
    if (is_word(w)) {  // a section's keyword
      section = w;
      if (section == "Atoms") {
        if (natoms < 0) bad(path, ln, "an Atoms section before the header's `N atoms`");
        const size_t hash = text.find('#');
        const std::string style = hash == std::string::npos ? "" : first_word(text.substr(hash + 1));
        if (!style.empty() && style != "sphere" && style != "granular")
          bad(path, ln,
              "atom_style " + style +
                  ": only sphere or granular atoms (id type diameter density x y z) "
                  "carry radii");
      }
      continue;
    }
    if (section.empty()) {  // the header: counts and box bounds
      std::istringstream is(body);
      std::vector<std::string> t;
      for (std::string x; is >> x;) t.push_back(x);
      if (t.size() == 2 && t[1] == "atoms") {
        if (!numbers(t[0], v) || v.size() != 1 || !(v[0] >= 1) || v[0] > 1e8)
          bad(path, ln, quoted(text) + " is not a number of atoms in [1, 1e8]");
        natoms = long(v[0]);
      } else if (t.size() == 4 && (t[2] == "xlo" || t[2] == "ylo" || t[2] == "zlo") &&
                 t[3] == t[2].substr(0, 1) + "hi") {
        const int a = t[2][0] - 'x';
        if (!numbers(t[0] + " " + t[1], v) || v.size() != 2) bad(path, ln, quoted(text) + " is not two bounds lo hi");
        in.lo[a] = v[0] * scale;
        in.hi[a] = v[1] * scale;
        bounds[a] = true;
      } else if (t.size() == 6 && t[3] == "xy") {
        bad(path, ln, "a triclinic box: the walls are an orthogonal box (give it with --box)");
      }
      continue;
    }
    if (section != "Atoms") continue;  // Velocities, Masses, ...: nothing a sample at rest needs
    if (!numbers(body, v) || (v.size() != 7 && v.size() != 10))
      bad(path, ln, quoted(text) + " is not an atom_style sphere row: id type diameter density x y z (ix iy iz)");
    if (++rows > natoms) bad(path, ln, "more Atoms rows than the header's " + std::to_string(natoms) + " atoms");
    const Real sphere[4] = {v[4], v[5], v[6], 0.5 * v[2]};
    add_sphere(in, path, ln, sphere, scale);
    in.id.push_back(long(v[0]));
    if (in.r.size() == 1) {
      in.density = v[3];
      in.density_lines[0] = ln;
    } else if (v[3] != in.density && in.density_lines[1] == 0) {
      in.density_lines[1] = ln;
    }
  }
  if (f.bad()) throw std::runtime_error(path + ": read error");
  if (natoms < 0) throw std::runtime_error(path + ": a LAMMPS data file without `N atoms` in its header");
  if (rows != natoms)
    throw std::runtime_error(path + ": " + std::to_string(rows) + " Atoms rows for the header's " +
                             std::to_string(natoms) + " atoms (a file cut short?)");
  for (int a = 0; a < 3; ++a)
    if (!bounds[a])
      throw std::runtime_error(path + ": no `" + std::string(1, char('x' + a)) + "lo " + std::string(1, char('x' + a)) +
                               "hi` line in the header");
  return in;
}

// Whether a file (not a dump) is a LAMMPS data file: `N atoms` on a line of its first 20 (a packing's lines are
// numbers only).
bool looks_like_data(std::ifstream& f) {
  std::string text;
  bool data = false;
  for (int k = 0; k < 20 && std::getline(f, text); ++k) {
    std::istringstream is(text.substr(0, text.find('#')));
    std::string n, w, rest;
    if (is >> n >> w && w == "atoms" && !(is >> rest) && n.find_first_not_of("0123456789") == std::string::npos) {
      data = true;
      break;
    }
  }
  f.clear();
  f.seekg(0);
  return data;
}

// A text line's fields: blanks or commas between them; a field in double quotes (a CSV header's "X [mm]") may hold
// either, and is read without its quotes.
std::vector<std::string> fields(const std::string& text) {
  std::vector<std::string> out;
  std::string cur;
  bool in_field = false, quoted_field = false;
  for (const char ch : text + " ") {
    if (ch == '"') {
      quoted_field = !quoted_field;
      in_field = true;
    } else if (!quoted_field && (ch == ' ' || ch == '\t' || ch == '\r' || ch == ',')) {
      if (in_field) out.push_back(cur);
      cur.clear();
      in_field = false;
    } else {
      cur += ch;
      in_field = true;
    }
  }
  return out;
}
bool is_number(const std::string& t, double& v) {
  char* end = nullptr;
  v = std::strtod(t.c_str(), &end);
  return !t.empty() && end == t.c_str() + t.size();
}

// One sphere a line: four numbers x y z r (blanks or commas between them), or with --columns the four of more fields
// it names (1-based numbers, or names of the header); blank lines and lines starting with # skipped, and a first line
// of names alone (a CSV's header: ParaView's "Points:0","Points:1",...) read as the header. A file whose first line
// starts with "ITEM:" is a LAMMPS or LIGGGHTS dump (read_dump), one with `N atoms` in its header a LAMMPS data file
// (read_data).
Read read_packing(const std::string& path, Real scale, const std::vector<std::string>& columns, bool diameter) {
  std::ifstream f(path);
  if (!f) throw std::runtime_error(path + ": cannot read it (" + std::strerror(errno) + ")");
  const auto no_columns = [&](const char* what) {
    if (!columns.empty() || diameter)
      throw std::runtime_error(path + ": " + what + ", which names its columns itself: " +
                               (columns.empty() ? "--size" : "--columns") + " is for a text packing");
  };
  if (f.peek() == 'I') {
    std::string first;
    std::getline(f, first);
    f.seekg(0);
    if (first.rfind("ITEM:", 0) == 0) {
      no_columns("a LAMMPS dump");
      return read_dump(f, path, scale);
    }
  }
  if (looks_like_data(f)) {
    no_columns("a LAMMPS data file");
    return read_data(f, path, scale);
  }
  Read in;
  std::string text;
  long ln = 0, header_ln = 0;
  std::vector<std::string> header;
  std::vector<size_t> col;  // the four fields read (0-based), once known
  std::vector<double> nv;
  while (std::getline(f, text)) {
    ++ln;
    if (ln == 1 && text.rfind("\xEF\xBB\xBF", 0) == 0) text.erase(0, 3);  // a UTF-8 byte order mark (Excel's CSV)
    const size_t b = text.find_first_not_of(" \t\r");
    if (b == std::string::npos || text[b] == '#') continue;
    if (columns.empty()) {  // the common line, four numbers x y z r, read as before (the race scene's 864 000 in ~2 s)
      std::string s = text;
      std::replace(s.begin(), s.end(), ',', ' ');
      if (numbers(s, nv) && nv.size() == 4) {
        col = {0, 1, 2, 3};
        if (diameter) nv[3] *= 0.5;
        add_sphere(in, path, ln, nv.data(), scale);
        continue;
      }
    }
    const std::vector<std::string> t = fields(text);
    double v[4];
    if (col.empty()) {
      // the first line of data, or a header before it: a line without one number is names
      const bool names = in.r.empty() && header.empty() && std::none_of(t.begin(), t.end(), [&](const std::string& x) {
                           return is_number(x, v[0]);
                         });
      if (names) {
        header = t;
        header_ln = ln;
        in.how = "; header line " + std::to_string(ln) + " " + quoted(text) + " skipped";
        // Without --columns the header must say x y z r in that order (each name's first letter, any case: "X [m]",
        // "radius"; d for a diameter with --size diameter): one in another order, or of other quantities, would be
        // read wrong without a word.
        const char* want = diameter ? "xyzd" : "xyzr";
        bool xyzr = t.size() == 4;
        for (size_t c = 0; xyzr && c < 4; ++c) xyzr = std::tolower(static_cast<unsigned char>(t[c][0])) == want[c];
        if (columns.empty() && !xyzr)
          bad(path, ln, "the header " + quoted(text) + " does not name x y z " + (diameter ? "d" : "r") +
                            " in that order: pick the four with --columns X,Y,Z,R (numbers from 1, or these names)" +
                            (diameter ? "" : "; a diameter with --size diameter"));
        continue;
      }
      if (columns.empty()) {
        col = {0, 1, 2, 3};
      } else {
        for (const std::string& c : columns) {
          double k = 0;
          if (is_number(c, k)) {
            if (!(k >= 1 && k <= 1000 && k == std::floor(k)))
              throw std::runtime_error("--columns: '" + c + "' is not a column number in [1, 1000] or a name");
            col.push_back(size_t(k) - 1);
            continue;
          }
          const auto it = std::find(header.begin(), header.end(), c);
          // messages built by append: operator+ chains in a loop make a temporary a step (clang-tidy's
          // performance-inefficient-string-concatenation under make check)
          std::string msg = "--columns: '";
          msg.append(c);
          if (header.empty())
            throw std::runtime_error(msg.append("' is a name, and ").append(path).append(
                " has no header line (a first line of names) to find it in"));
          if (it == header.end()) {
            std::string known;
            for (const std::string& h : header) known.append(known.empty() ? "" : ", ").append(h);
            throw std::runtime_error(msg.append("' is not a name of ").append(path).append("'s header (line ")
                                         .append(std::to_string(header_ln)).append(": ").append(known).append(")"));
          }
          col.push_back(size_t(it - header.begin()));
        }
        in.how = "; columns " + std::to_string(col[0] + 1) + ", " + std::to_string(col[1] + 1) + ", " +
                 std::to_string(col[2] + 1) + ", " + std::to_string(col[3] + 1) + " as x y z r" + in.how;
      }
    }
    const size_t need = *std::max_element(col.begin(), col.end()) + 1;
    if (columns.empty() && t.size() != 4) {
      bool all = true;
      for (const std::string& x : t) all = all && is_number(x, v[0]);
      if (!all)
        bad(path, ln,
            quoted(text) + " is not four numbers x y z r (metres, blanks or commas between; a header line starts with "
                           "#, or is the first line, of names alone)");
      bad(path, ln,
          std::to_string(t.size()) + " numbers in " + quoted(text) +
              ", four expected: x y z r (one sphere a line; pick four of more columns with --columns, or start the "
              "line with #)");
    }
    if (t.size() < need)
      bad(path, ln, std::to_string(t.size()) + " fields in " + quoted(text) + ", and --columns reads field " +
                        std::to_string(need));
    for (int c = 0; c < 4; ++c)
      if (!is_number(t[col[size_t(c)]], v[c]))
        bad(path, ln,
            columns.empty() ? quoted(text) + " is not four numbers x y z r (metres, blanks or commas between; a header "
                                             "line starts with #, or is the first line, of names alone)"
                            : "field " + std::to_string(col[size_t(c)] + 1) + " (" + "xyzr"[c] + ") " +
                                  quoted(t[col[size_t(c)]]) + " is not a number");
    if (diameter) v[3] *= 0.5;
    add_sphere(in, path, ln, v, scale);
  }
  if (f.bad()) throw std::runtime_error(path + ": read error");
  if (in.r.empty()) throw std::runtime_error(path + ": no spheres in it (one a line: x y z r, in metres)");
  return in;
}
}  // namespace

PackingContacts packing_contacts(const std::vector<Vec3d>& x, const std::vector<Real>& r, const Vec3d& lo,
                                 const Vec3d& hi) {
  PackingContacts pc;
  const size_t n = r.size();
  if (n == 0) return pc;
  const Real rmax = *std::max_element(r.begin(), r.end());
  // Two spheres overlap only where their centres are closer than r_i + r_j <= 2 r_max: cells at least that wide, so a
  // sphere's partners lie in its own cell and the 26 around it; at most ~8 N cells (a few spheres in a large box).
  const Real cap = std::cbrt(8.0 * double(n)) + 1;
  int nc[3];
  Real edge[3];
  for (int a = 0; a < 3; ++a) {
    const Real L = hi[a] - lo[a];
    nc[a] = int(std::max<Real>(1, std::min<Real>(cap, std::floor(L / (2 * rmax)))));
    edge[a] = L / nc[a];
  }
  auto cell_of = [&](const Vec3d& p, int a) { return std::min(nc[a] - 1, std::max(0, int((p[a] - lo[a]) / edge[a]))); };
  const size_t ncell = size_t(nc[0]) * nc[1] * nc[2];
  std::vector<size_t> start(ncell + 1, 0), cell(n);
  for (size_t i = 0; i < n; ++i) {
    cell[i] = (size_t(cell_of(x[i], 2)) * nc[1] + cell_of(x[i], 1)) * nc[0] + cell_of(x[i], 0);
    ++start[cell[i] + 1];
  }
  for (size_t c = 0; c < ncell; ++c) start[c + 1] += start[c];
  std::vector<size_t> fill(start.begin(), start.end() - 1), in_cell(n);
  for (size_t i = 0; i < n; ++i) in_cell[fill[cell[i]]++] = i;
  for (size_t i = 0; i < n; ++i) {
    const int cx = cell_of(x[i], 0), cy = cell_of(x[i], 1), cz = cell_of(x[i], 2);
    for (int Z = std::max(0, cz - 1); Z <= std::min(nc[2] - 1, cz + 1); ++Z)
      for (int Y = std::max(0, cy - 1); Y <= std::min(nc[1] - 1, cy + 1); ++Y)
        for (int X = std::max(0, cx - 1); X <= std::min(nc[0] - 1, cx + 1); ++X) {
          const size_t c = (size_t(Z) * nc[1] + Y) * nc[0] + X;
          for (size_t k = start[c]; k < start[c + 1]; ++k) {
            const size_t j = in_cell[k];
            if (j <= i) continue;  // each pair once
            Real d2 = 0;
            for (int a = 0; a < 3; ++a) d2 += (x[j][a] - x[i][a]) * (x[j][a] - x[i][a]);
            const Real s = r[i] + r[j];
            if (d2 >= s * s) continue;
            ++pc.touching;
            const Real ov = (s - std::sqrt(d2)) / std::min(r[i], r[j]);
            if (ov > pc.max_overlap) {
              pc.max_overlap = ov;
              pc.max_i = int(i);
              pc.max_j = int(j);
            }
          }
        }
    // below 1e-12 of a radius: the round-off of a bounding box's own x - r, not a sphere pressing the wall
    for (int a = 0; a < 3; ++a)
      for (const Real gap : {x[i][a] - lo[a], hi[a] - x[i][a]})
        if (const Real ov = (r[i] - gap) / r[i]; ov > 1e-12) {
          ++pc.wall_touching;
          pc.max_wall_overlap = std::max(pc.max_wall_overlap, ov);
        }
  }
  return pc;
}

std::vector<std::string> import_packing(const ImportOptions& opt) {
  if (!(opt.scale > 0) || !std::isfinite(opt.scale))
    throw std::runtime_error("--scale = " + num(opt.scale) + " must be a number > 0 (1e-3 for a file in mm)");
  if (!(opt.density > 0 && opt.density <= 1e6))
    throw std::runtime_error("--density = " + num(opt.density) + " kg/m^3 is outside sample.density's range (0, 1e6]");
  if (!(opt.density_scaling >= 1 && opt.density_scaling <= 1e12))
    throw std::runtime_error("--density-scaling = " + num(opt.density_scaling) +
                             " is outside sample.density_scaling's range [1, 1e12]");
  const char* axis = "xyz";
  if (opt.box_given && opt.crop)
    throw std::runtime_error("--box and --crop: the crop box is the walls; give one of them");
  const auto check_box = [&](const char* what, const Vec3d& blo, const Vec3d& bhi) {
    for (int a = 0; a < 3; ++a)
      if (!(blo[a] < bhi[a]) || !std::isfinite(blo[a]) || !std::isfinite(bhi[a]))
        throw std::runtime_error(std::string(what) + ": " + axis[a] + "lo = " + num(blo[a]) + " must be below " +
                                 axis[a] + "hi = " + num(bhi[a]) + " (six numbers: xlo xhi ylo yhi zlo zhi, m)");
  };
  if (opt.box_given) check_box("--box", opt.lo, opt.hi);
  if (opt.crop) check_box("--crop", opt.crop_lo, opt.crop_hi);
  std::error_code ec;
  if (fs::exists(opt.out, ec))
    throw std::runtime_error(opt.out + ": exists; import never replaces a file: remove it or name another --out");
  Read in = read_packing(opt.packing, opt.scale, opt.columns, opt.diameter);
  // row[k]: sphere k's row in the file (0-based over the sphere lines; in.line and in.id are by row). --crop keeps the
  // spheres wholly inside its box, which no wall then cuts: a sphere across a face would press its wall by up to its
  // radius, past numerics.max_overlap
  std::vector<int> row;
  const size_t n_file = in.r.size();
  if (opt.crop) {
    std::vector<Vec3d> x;
    std::vector<Real> r;
    for (size_t i = 0; i < n_file; ++i) {
      bool inside = true;
      for (int a = 0; a < 3; ++a)
        inside = inside && in.x[i][a] - in.r[i] >= opt.crop_lo[a] && in.x[i][a] + in.r[i] <= opt.crop_hi[a];
      if (!inside) continue;
      x.push_back(in.x[i]);
      r.push_back(in.r[i]);
      row.push_back(int(i));
    }
    if (r.empty())
      throw std::runtime_error(opt.packing + ": no sphere of its " + std::to_string(n_file) +
                               " lies wholly inside --crop [" + num(opt.crop_lo[0], 6) + ", " + num(opt.crop_hi[0], 6) +
                               "] x [" + num(opt.crop_lo[1], 6) + ", " + num(opt.crop_hi[1], 6) + "] x [" +
                               num(opt.crop_lo[2], 6) + ", " + num(opt.crop_hi[2], 6) + "] m");
    in.x.swap(x);
    in.r.swap(r);
  } else {
    row.resize(n_file);
    for (size_t i = 0; i < n_file; ++i) row[i] = int(i);
  }
  const size_t n = in.r.size();
  // The density: --density, else a data file's atoms' (one for all: grainlab has one), else sample.density's default.
  Real density = opt.density;
  if (in.data && !opt.density_given) {
    if (in.density_lines[1] > 0)
      throw std::runtime_error(opt.packing + ": the atoms' densities differ (lines " +
                               std::to_string(in.density_lines[0]) + " and " + std::to_string(in.density_lines[1]) +
                               "): a sample has one density, give it with --density");
    density = in.density;
    if (!(density > 0 && density <= 1e6))
      throw std::runtime_error(opt.packing + ":" + std::to_string(in.density_lines[0]) + ": density " + num(density) +
                               " kg/m^3 is outside sample.density's range (0, 1e6] (give --density)");
  }

  Vec3d lo = opt.crop ? opt.crop_lo : opt.lo, hi = opt.crop ? opt.crop_hi : opt.hi;
  // the walls: --box or --crop, else a dump's or data file's box bounds, else the spheres' bounding box
  const bool given = opt.box_given || opt.crop;
  const std::string box_from = opt.crop        ? "--crop"
                               : opt.box_given ? "--box"
                               : in.dump     ? "the dump's box bounds"
                               : in.data     ? "the data file's box"
                                             : "the spheres' bounding box";
  if (!given && (in.dump || in.data)) {
    lo = in.lo;
    hi = in.hi;
    for (int a = 0; a < 3; ++a)
      if (!(lo[a] < hi[a]))
        throw std::runtime_error(opt.packing + ": the " + (in.dump ? "dump's" : "data file's") + " box bounds on " +
                                 axis[a] + " are not lo < hi (give --box)");
  } else if (!given) {  // each wall touches the outermost sphere on its side: no sphere presses a wall yet
    bounding_box(in.x, in.r, lo, hi);
  }
  for (size_t i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a)
      if (!(in.x[i][a] > lo[a] && in.x[i][a] < hi[a]))
        throw std::runtime_error(opt.packing + ":" + std::to_string(in.line[size_t(row[i])]) + ": the centre's " +
                                 axis[a] + " = " +
                                 num(in.x[i][a], 6) + " m is outside the box's [" + num(lo[a], 6) + ", " +
                                 num(hi[a], 6) + "] m (" + box_from + "): every centre must lie between the walls");

  // Spatial (Morton) order: a file's order is often random in space, and the contact kernel's neighbour reads need
  // neighbours close in memory (perf/NOTES.md attempt 3a: 1.7x on the race scene, whose file order is random).
  Real rmean = 0;
  for (Real ri : in.r) rmean += ri;
  rmean /= Real(n);
  const std::vector<int> order = spatial_order(in.x, 2 * rmean);
  EngineState s;
  s.x.resize(n);
  s.r.resize(n);
  s.v.assign(n, Vec3d{0, 0, 0});
  s.w = s.f = s.t = s.v;
  std::vector<int> index(n);
  for (size_t k = 0; k < n; ++k) {
    s.x[k] = in.x[size_t(order[k])];
    s.r[k] = in.r[size_t(order[k])];
    index[k] = row[size_t(order[k])];
  }
  s.walls = make_box_walls(lo, hi);
  s.walls_are_box = true;

  Real Vs = 0;
  for (Real ri : s.r) Vs += 4.0 / 3.0 * M_PI * ri * ri * ri;
  const Real V = (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
  const PackingContacts pc = packing_contacts(s.x, s.r, lo, hi);
  const GradingIndices gi = grading_indices(s.r);
  const std::string from = fs::absolute(opt.packing, ec).lexically_normal().string();
  write_h5_atomic(opt.out, [&](H5Writer& w) {
    write_state(w, s);
    w.attr("density", density);
    w.attr("density_scaling", opt.density_scaling);
    w.attr("stage", std::string("import"));
    w.attr("imported_from", from);
    w.attr("import_scale", opt.scale);
    w.attr("e", (V - Vs) / Vs);
    w.attr("build", version_line());
    // sphere k of the sample is sphere index[k] of the file (0-based, counting sphere lines only: numpy.loadtxt's
    // row), so that results can be laid beside the file's own columns
    w.group("/import");
    w.write("/import/index", index);
    if (!in.id.empty()) {  // a dump's or data file's atom ids (LAMMPS's `id`), sphere by sphere of the sample
      std::vector<std::int64_t> ids(n);
      for (size_t k = 0; k < n; ++k) ids[k] = in.id[size_t(index[k])];
      w.write("/import/id", ids);
      if (in.dump) w.attr("import_timestep", double(in.timestep));
    }
  });

  const auto [rmin, rmax] = std::minmax_element(s.r.begin(), s.r.end());
  std::vector<std::string> lines;
  lines.push_back("imported " + std::to_string(n) + " sphere" + (n == 1 ? "" : "s") + " from " + opt.packing +
                  (in.dump ? " (timestep " + std::to_string(in.timestep) + ", the last of " +
                                 std::to_string(in.snapshots) + " snapshot" + (in.snapshots > 1 ? "s" : "") + ")"
                   : in.data ? " (a LAMMPS data file, density " + num(density) + " kg/m^3)"
                   : !in.how.empty() || opt.diameter
                       ? " (" + (in.how + (opt.diameter ? "; the fourth a diameter, halved" : "")).substr(2) + ")"
                             : std::string()) +
                  ": diameters " + mm(2 * *rmin) + " to " + mm(2 * *rmax) + "; by mass d50 " + mm(gi.d50) + ", Cu " +
                  num(gi.cu, 3));
  if (opt.crop)
    lines.push_back("cropped: " + std::to_string(n) + " of the file's " + std::to_string(n_file) +
                    " spheres lie wholly inside --crop, the walls");
  lines.push_back("box " + mm(hi[0] - lo[0]) + " x " + mm(hi[1] - lo[1]) + " x " + mm(hi[2] - lo[2]) + " (" + box_from +
                  "): solid fraction " + num(Vs / V, 4) + ", void ratio e " + num((V - Vs) / Vs, 4));
  std::string c = "contacts: " + std::to_string(pc.touching) + " overlapping pairs (Z " +
                  num(2.0 * double(pc.touching) / double(n), 3) + ")";
  const long line_i = pc.touching > 0 ? in.line[size_t(index[size_t(pc.max_i)])] : 0;
  const long line_j = pc.touching > 0 ? in.line[size_t(index[size_t(pc.max_j)])] : 0;
  if (pc.touching > 0)
    c += ", the largest overlap " + num(pc.max_overlap, 3) + " of the smaller radius (lines " +
         std::to_string(std::min(line_i, line_j)) + " and " + std::to_string(std::max(line_i, line_j)) + ")";
  c += pc.wall_touching > 0 ? "; " + std::to_string(pc.wall_touching) + " sphere-wall overlaps, the largest " +
                                  num(pc.max_wall_overlap, 3) + " of the sphere's radius"
                            : "; no sphere presses a wall";
  lines.push_back(c);
  // A periodic box's spheres cross its faces, which walls cannot: say so, and how to cut a walled sample out of it.
  if (!given && in.dump && !in.periodic.empty() && pc.wall_touching > 0)
    lines.push_back("note: the dump's box is periodic in " + in.periodic + " (pp): its spheres across those faces "
                    "press the walls here; --crop " + box_text(in.file_lo, in.file_hi) +
                    " (its box) keeps those wholly inside it");
  // numerics.max_overlap's default: a run stops with a diagnosis where an overlap passes it
  if (std::max(pc.max_overlap, pc.max_wall_overlap) > 0.2)
    lines.push_back("warning: an overlap of " + num(std::max(pc.max_overlap, pc.max_wall_overlap), 3) +
                    " is past numerics.max_overlap's default 0.2: a run from this sample stops at its first step "
                    "unless its config raises numerics.max_overlap (or the file is in other units: --scale)");
  lines.push_back("sample: " + opt.out + " (start a run from it with sample: {file: " + opt.out + "})");
  return lines;
}

namespace {
// One instant of a run as export writes it: a sample file's, a checkpoint's or a snapshot's spheres, the walls' box
// where the file has it (a state's walls; a snapshot's /walls/box, written since session 64), the density.
struct Frame {
  std::vector<Vec3d> x, v, w;
  std::vector<Real> r;
  bool box = false;
  Vec3d lo{}, hi{};
  Real density = 0, scaling = 1;
  double step = 0, time = 0;
  std::string what;
};
Frame read_frame(const std::string& path) {
  Frame fr;
  const H5Reader h(path);
  if (h.has("/state")) {  // a sample file or a checkpoint (read_state's checks and messages)
    const EngineState s = read_state(h);
    fr.x = s.x;
    fr.v = s.v;
    fr.w = s.w;
    fr.r = s.r;
    fr.step = double(s.step);
    fr.time = s.time;
    fr.box = s.walls_are_box && box_of_walls(s.walls, fr.lo, fr.hi);
    if (h.has("density")) {
      fr.density = h.attr_double("density");
      fr.scaling = h.attr_double("density_scaling");
      fr.what = "a sample";
    } else {
      fr.what = "a checkpoint";
      if (h.has("sample_density")) fr.density = h.attr_double("sample_density");
    }
  } else if (h.has("/particles")) {  // a snapshot
    fr.x = h.vec3("/particles/x");
    fr.v = h.vec3("/particles/v");
    fr.w = h.vec3("/particles/w");
    fr.r = h.doubles("/particles/r");
    fr.step = h.attr_double("step");
    fr.time = h.attr_double("time");
    if (h.has("/walls/box")) {
      const std::vector<double> b = h.doubles("/walls/box");
      if (b.size() != 6) throw std::runtime_error(path + ": /walls/box is not six numbers (corrupt file?)");
      fr.box = true;
      for (int a = 0; a < 3; ++a) {
        fr.lo[a] = b[2 * size_t(a)];
        fr.hi[a] = b[2 * size_t(a) + 1];
      }
    }
    fr.what = "a snapshot";
  } else if (h.has("/series")) {
    throw std::runtime_error(path +
                             ": a run's series (run.h5), no spheres: export the run's sample file, one of "
                             "its checkpoints or a snapshot (or the run's directory with --format dump)");
  } else {
    throw std::runtime_error(path + ": neither a sample, a checkpoint nor a snapshot of grainlab's");
  }
  if (fr.r.empty() || fr.x.size() != fr.r.size()) throw std::runtime_error(path + ": no spheres in it");
  return fr;
}
std::string g17(Real v) {  // 17 significant digits: read back, the same double
  char b[32];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}
}  // namespace

// --format dump: a LAMMPS text dump (OVITO, LAMMPS's tools and `grainlab import` read it), a frame per snapshot of a
// run directory (snapshots/snap_*.h5, in order) or one frame of one file. Streamed to a temporary file and renamed.
std::vector<std::string> export_dump(const ExportOptions& opt) {
  std::vector<std::string> files;
  std::error_code ec;
  const bool run_dir = fs::is_directory(opt.in, ec);
  if (run_dir) {
    for (auto& f : fs::directory_iterator(opt.in + "/snapshots", ec))
      if (f.path().filename().string().rfind("snap_", 0) == 0 && f.path().extension() == ".h5")
        files.push_back(f.path().string());
    std::sort(files.begin(), files.end());  // snap_NNNNN: by name is by time
    if (files.empty())
      throw std::runtime_error(opt.in +
                               ": no snapshots/snap_*.h5 in it (a run directory, or one sample, checkpoint "
                               "or snapshot file)");
  } else {
    files.push_back(opt.in);
  }
  if (fs::exists(opt.out, ec))
    throw std::runtime_error(opt.out + ": exists; export never replaces a file: remove it or name another --out");
  const std::string tmp = temp_name(opt.out);
  long no_box = 0;
  size_t n = 0;
  try {
    std::ofstream o(tmp);
    if (!o) throw std::runtime_error(opt.out + ": cannot write (directory missing or not writable)");
    for (const std::string& path : files) {
      const Frame fr = read_frame(path);
      n = fr.r.size();
      Vec3d lo = fr.lo, hi = fr.hi;
      if (!fr.box) {  // a snapshot from before session 64: the spheres' bounding box stands in for the walls
        ++no_box;
        bounding_box(fr.x, fr.r, lo, hi);
      }
      o << "ITEM: TIME\n"
        << g17(fr.time) << "\nITEM: TIMESTEP\n"
        << long(fr.step) << "\nITEM: NUMBER OF ATOMS\n"
        << n << "\nITEM: BOX BOUNDS ff ff ff\n";
      for (int a = 0; a < 3; ++a) o << g17(lo[a]) << " " << g17(hi[a]) << "\n";
      o << "ITEM: ATOMS id x y z radius vx vy vz omegax omegay omegaz\n";
      for (size_t i = 0; i < n; ++i) {
        o << i + 1;
        for (const Real c : {fr.x[i][0], fr.x[i][1], fr.x[i][2], fr.r[i], fr.v[i][0], fr.v[i][1], fr.v[i][2],
                             fr.w[i][0], fr.w[i][1], fr.w[i][2]})
          o << " " << g17(c);
        o << "\n";
      }
    }
    o.close();
    if (!o) throw std::runtime_error(opt.out + ": write error (disk full?)");
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
  commit_atomic(tmp, opt.out);
  const std::string frames = std::to_string(files.size()) + " frame" + (files.size() == 1 ? "" : "s");
  std::vector<std::string> lines{"exported " + frames + " of " + std::to_string(n) + " spheres to " + opt.out +
                                 " (a LAMMPS text dump, for OVITO; `grainlab import` takes its last frame)"};
  if (no_box > 0)
    lines.push_back("note: " + std::to_string(no_box) +
                    " of them without walls recorded (snapshots before session "
                    "64): their box is the spheres' bounding box");
  return lines;
}

std::vector<std::string> export_sample(const ExportOptions& opt) {
  if (opt.format != "xyzr" && opt.format != "lammps" && opt.format != "dump")
    throw std::runtime_error("--format " + opt.format + ": xyzr, lammps or dump");
  std::error_code ec;
  if (fs::is_directory(opt.in, ec)) {
    if (opt.format != "dump")
      throw std::runtime_error(opt.in +
                               ": a directory: --format dump writes a run's snapshots as the frames of one "
                               "dump; xyzr and lammps take one file (a sample, checkpoint or snapshot)");
    return export_dump(opt);
  }
  if (opt.format == "dump") return export_dump(opt);
  const Frame fr = read_frame(opt.in);
  const std::vector<Vec3d>& x = fr.x;
  const std::vector<Real>& r = fr.r;
  const bool box = fr.box;
  const Vec3d lo = fr.lo, hi = fr.hi;
  const Real density = fr.density, scaling = fr.scaling;
  const std::string& what = fr.what;
  const size_t n = r.size();
  if (n == 0 || x.size() != n) throw std::runtime_error(opt.in + ": no spheres in it");
  if (opt.format == "lammps" && !box)
    throw std::runtime_error(opt.in + ": " + what +
                             " without its box walls: a LAMMPS data file needs the box (export a "
                             "sample file or checkpoint of the run)");
  if (opt.format == "lammps" && !(density > 0))
    throw std::runtime_error(opt.in + ": " + what +
                             " that records no density (a LAMMPS data file gives each atom's): "
                             "export the run's sample file");
  const fs::path op(opt.out);
  const std::string box_out = (op.parent_path() / (op.stem().string() + "_box.txt")).string();
  const bool two = box && opt.format == "xyzr";
  for (const std::string& f : {opt.out, box_out})
    if ((f == opt.out || two) && fs::exists(f, ec))
      throw std::runtime_error(f + ": exists; export never replaces a file: remove it or name another --out");
  std::string text;
  text.reserve(n * 100);
  const std::string src = fs::absolute(opt.in, ec).lexically_normal().string();
  std::vector<std::string> lines;
  if (opt.format == "xyzr") {
    text += "# x y z r [m]: " + std::to_string(n) + " spheres of " + src + " (grainlab export)\n";
    for (size_t i = 0; i < n; ++i)
      text += g17(x[i][0]) + " " + g17(x[i][1]) + " " + g17(x[i][2]) + " " + g17(r[i]) + "\n";
    if (box) {  // first: a crash between the two leaves no sphere file that lacks its box
      std::string b;
      for (int a = 0; a < 3; ++a) b += g17(lo[a]) + " " + g17(hi[a]) + (a < 2 ? " " : "\n");
      write_file_atomic(box_out, b);
    }
    write_file_atomic(opt.out, text);
    lines.push_back("exported " + std::to_string(n) + " spheres of " + what + " to " + opt.out +
                    (box ? " and its walls to " + box_out + " (grainlab import " + opt.out + " --box " + box_out +
                               " reads them back to the bit)"
                         : " (no walls recorded: a snapshot from before session 64)"));
  } else {
    // atom_style sphere (LAMMPS) / granular (LIGGGHTS): id type diameter density x y z. The physical density:
    // grainlab's density_scaling is a time-step device of its own, said in the header.
    text += "LAMMPS data file: " + std::to_string(n) + " spheres of " + src +
            " (grainlab export; the box is its walls; "
            "density_scaling " +
            g17(scaling) + " not applied)\n\n";
    text += std::to_string(n) + " atoms\n1 atom types\n\n";
    const char* ax[3] = {"x", "y", "z"};
    for (int a = 0; a < 3; ++a) text += g17(lo[a]) + " " + g17(hi[a]) + " " + ax[a] + "lo " + ax[a] + "hi\n";
    text += "\nAtoms # sphere\n\n";
    for (size_t i = 0; i < n; ++i)
      text += std::to_string(i + 1) + " 1 " + g17(2 * r[i]) + " " + g17(density) + " " + g17(x[i][0]) + " " +
              g17(x[i][1]) + " " + g17(x[i][2]) + "\n";
    write_file_atomic(opt.out, text);
    lines.push_back("exported " + std::to_string(n) + " spheres of " + what + " to " + opt.out +
                    " (LAMMPS data, atom_style sphere: read_data " + opt.out + "; the walls are the box faces)");
  }
  return lines;
}

}  // namespace grainlab
