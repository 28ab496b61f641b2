// Degenerate planes on the regular star polychora and non-convex uniform ones: planes through a
// vertex, containing an edge, a face or a cell, and planes tilted 1e-12 rad off a cell's
// hyperplane. Each section must be a closed chain (every segment between two section vertices
// carries signed polygon incidences that cancel) whose winding-weighted signed volume is the
// limit of the volumes of the nearby generic planes. The limit is computed independently of the
// section algorithm: the B-spline volume oracle (support/oracle.hpp) at d +- 1e-7 and +- 1e-8 of
// the model's size; at a plane holding a cell the volume function jumps, and the section is the
// limit from the side the symbolic perturbation takes (docs/ARCHITECTURE.md: ON vertices count
// as Positive, the plane moved by -epsilon along n; the other side only when that is empty).
//
// CW4D_STRESS_FRACTION (in (0, 1], default 1) scales the plane counts down, as in
// test_stress.cpp.
#include <Eigen/Dense>
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/wythoff.hpp"
#include "cw4d/section/section.hpp"
#include "support/oracle.hpp"
#include "support/planes.hpp"

using namespace cw4d;
using cw4d::test::random_orthogonal;
using cw4d::test::spanning;

namespace {

double fraction() {
  const char* env = std::getenv("CW4D_STRESS_FRACTION");
  if (!env) return 1.0;
  const double f = std::atof(env);
  return f > 0.0 && f <= 1.0 ? f : 1.0;
}

std::string describe(const Hyperplane& p) {
  std::ostringstream out;
  out.precision(17);
  out << "n = (" << p.normal.transpose() << "), d = " << p.offset;
  return out.str();
}

// Sum over the polygons of their signed incidences on each unordered pair of section vertices
// (an edge walked tail -> head counts +1 on the pair (min, max) when tail < head): zero on every
// pair for a closed chain, whatever ids the section gave its edges.
bool closed_chain(const Complex& sc, std::string* why) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> sum;
  const Incidence& faces = sc.boundary(2);
  for (std::uint32_t f = 0; f < faces.size(); ++f) {
    auto ids = faces.ids(f);
    auto signs = faces.signs(f);
    for (std::size_t i = 0; i < ids.size(); ++i) {
      const auto [a, b] = sc.edge(ids[i]);
      sum[{std::min(a, b), std::max(a, b)}] += a < b ? signs[i] : -signs[i];
    }
  }
  for (const auto& [pair, s] : sum)
    if (s != 0) {
      *why = "segment " + std::to_string(pair.first) + "-" + std::to_string(pair.second) +
             " has incidence " + std::to_string(s);
      return false;
    }
  return true;
}

double oracle(const Complex& c, const Eigen::VectorXd& u, double d) {
  return test::bspline_section_volume(c, u, d);
}

// support/oracle.cpp's B-spline volume with the knots and the recurrence in 113-bit arithmetic
// (__float128), for planes nearly parallel to a cell: there the knots of the cell's vertices lie
// within 1e-12 of the size of each other, and the recurrence divides by their differences.
using Quad = __float128;

Quad quad_bspline(std::vector<Quad> x, Quad t) {
  std::sort(x.begin(), x.end());
  const int k_max = static_cast<int>(x.size()) - 1;
  if (t < x.front() || t >= x.back()) return 0;
  std::vector<Quad> m(x.size() - 1);
  for (std::size_t i = 0; i + 1 < x.size(); ++i)
    m[i] = (x[i] <= t && t < x[i + 1] && x[i + 1] > x[i]) ? 1 / (x[i + 1] - x[i]) : 0;
  for (int k = 2; k <= k_max; ++k)
    for (std::size_t i = 0; i + k < x.size(); ++i) {
      const Quad span = x[i + k] - x[i];
      m[i] = span > 0 ? k * ((t - x[i]) * m[i] + (x[i + k] - t) * m[i + 1]) / ((k - 1) * span) : 0;
    }
  return m[0];
}

double quad_oracle(const Complex& c, const Eigen::VectorXd& u, double d) {
  const auto& p = c.positions();
  const Eigen::VectorXd centre = p.rowwise().mean();
  auto dot = [&](const Eigen::VectorXd& x) {
    Quad sum = 0;
    for (int i = 0; i < 4; ++i) sum += Quad(u[i]) * Quad(x[i]);
    return sum;
  };
  Quad total = 0;
  std::vector<Quad> knots(5);
  Eigen::Matrix4d m;
  for (std::uint32_t f = 0; f < c.count(3); ++f)
    for_each_simplex(c, 3, f, [&](std::span<const std::uint32_t> v, int sign) {
      for (int j = 0; j < 4; ++j) m.col(j) = p.col(v[j]) - centre;
      const double vol = sign * m.determinant() / 24.0;
      if (std::abs(vol) < 1e-300) return;
      knots[0] = dot(centre);
      for (int j = 0; j < 4; ++j) knots[j + 1] = dot(p.col(v[j]));
      total += Quad(vol) * quad_bspline(knots, Quad(d));
    });
  return static_cast<double>(total);
}

struct Stats {
  int planes = 0, sections = 0;
  double worst = 0.0;  // largest |volume - limit| / scale^3
};

// One degenerate plane: closed, and the volume is the limit of the generic planes nearby
// (`cell`: the volume function may jump there; the limit from below, or from above when the
// section is empty from below).
void check(const std::string& name, const Complex& c, double scale, const Hyperplane& plane,
           bool cell, double tilt, double conditioning, const std::string& what, Stats& stats) {
  INFO(name << ": " << what << ", " << describe(plane));
  const Section s = section(c, plane);
  ++stats.planes;
  const double s3 = std::pow(scale, 3);
  const Eigen::VectorXd& u = plane.normal;
  const double d = plane.offset;
  // One-sided limits, extrapolated linearly from d -+ 1e-8 and d -+ 2e-8 of the size (the
  // volume is a polynomial of degree 3 on either side: the error is ~1e-16 of the size's cube
  // times the second derivative, while the mean of two sides would carry half the jump of the
  // first derivative at a plane containing a face).
  const double h = 1e-8 * scale;
  const double below = 2.0 * oracle(c, u, d - h) - oracle(c, u, d - 2.0 * h);
  const double above = 2.0 * oracle(c, u, d + h) - oracle(c, u, d + 2.0 * h);
  // Where the volume function jumps (a plane holding a cell) the section is the limit from
  // below, or from above where that is empty; elsewhere both sides agree.
  double limit = !cell ? 0.5 * (below + above) : std::abs(below) > 1e-9 * s3 ? below : above;
  // A plane tilted off a cell: no jump, but the volume sweeps the cell's within 1e-12 of the
  // size, so the oracle is taken at the plane itself.
  if (tilt > 0.0) limit = quad_oracle(c, u, d);
  INFO("limit " << limit);
  if (s.empty()) {
    CHECK(std::abs(limit) <= 1e-9 * s3);
    return;
  }
  ++stats.sections;
  std::string why;
  const bool closed = closed_chain(s.complex, &why);
  INFO(why);
  CHECK(closed);
  const double volume = signed_volume(s.complex);
  // The defects this guards against are whole polygons (0.1 % to 1 % of the volume); the limit
  // itself is good to ~1e-7 of the size (a kink of the volume function at the plane).
  stats.worst = std::max(stats.worst, std::abs(volume - limit) / s3);
  CHECK(std::abs(volume - limit) <= 1e-9 * s3 + conditioning);
}

struct StarModel {
  std::string name;
  Complex complex;
  double scale;
};

// The ten regular star polychora and non-convex uniform ones of a few thousand elements.
const std::vector<StarModel>& star_models() {
  static const std::vector<StarModel> all = [] {
    std::vector<StarModel> out;
    std::vector<std::string> names;
    for (const auto& e : star_polychoron_names()) names.push_back(e.name);
    names.resize(10);  // the regular ones
    for (const char* extra :
         {"quasitruncated tesseract", "quasiruncinated tesseract",
          "rectified great grand hecatonicosachoron", "quasicantellated tesseract"})
      names.push_back(extra);
    for (const auto& n : names) {
      Complex c = make_star_polychoron(n);
      const double scale = 2.0 * max_radius(c);
      out.push_back({n, std::move(c), scale});
    }
    return out;
  }();
  return all;
}

enum class Family { vertex = 0, edge = 1, face = 2, cell = 3, tilted = 4 };

void run_family(Family family, std::uint32_t seed) {
  std::mt19937 rng(seed);
  const int per = std::max(2, static_cast<int>(24 * fraction()));
  for (const StarModel& m : star_models()) {
    const Complex& c = m.complex;
    Stats stats;
    const int rank = family == Family::tilted ? 3 : static_cast<int>(family);
    for (int t = 0; t < per; ++t) {
      const auto id = std::uniform_int_distribution<std::uint32_t>(
          0, static_cast<std::uint32_t>(c.count(rank) - 1))(rng);
      Eigen::VectorXd u;
      double tilt = 0.0, conditioning = 0.0;
      if (rank == 3) {
        u = c.facet_normals().col(id) * (t % 2 == 0 ? 1.0 : -1.0);
        if (family == Family::tilted) {
          tilt = 1e-12;
          const Eigen::VectorXd w = random_orthogonal(rng, Eigen::MatrixXd(u));
          u = (u + tilt * w).normalized();
          // Where the plane meets the cell's hyperplane is known only to (the rounding of
          // the cell's vertices) / tilt: 16 ulps of the radius moved by that across the cell.
          double size = 0.0;
          const auto verts = c.vertices_of(3, id);
          for (auto a : verts)
            for (auto b : verts) size = std::max(size, (c.position(a) - c.position(b)).norm());
          conditioning =
              size * size * 16.0 * std::numeric_limits<double>::epsilon() * (0.5 * m.scale) / tilt;
        }
      } else {
        const Eigen::MatrixXd dirs = rank == 0 ? Eigen::MatrixXd(4, 0) : spanning(c, rank, id);
        u = random_orthogonal(rng, dirs);
      }
      const double d = u.dot(c.position(c.first_vertex(rank, id)));
      check(m.name, c, m.scale, Hyperplane{u, d}, family == Family::cell, tilt, conditioning,
            "element " + std::to_string(id) + " of rank " + std::to_string(rank), stats);
    }
    std::cout << "star degenerate [" << static_cast<int>(family) << "] " << m.name << ": "
              << stats.sections << "/" << stats.planes << " sections, worst " << stats.worst
              << "\n";
  }
}

}  // namespace

TEST_CASE("star: planes through a vertex", "[star][degenerate]") {
  run_family(Family::vertex, 901);
}
TEST_CASE("star: planes containing an edge", "[star][degenerate]") {
  run_family(Family::edge, 902);
}
TEST_CASE("star: planes containing a face", "[star][degenerate]") {
  run_family(Family::face, 903);
}
TEST_CASE("star: planes containing a cell", "[star][degenerate]") {
  run_family(Family::cell, 904);
}
TEST_CASE("star: planes tilted 1e-12 rad off a cell", "[star][degenerate]") {
  run_family(Family::tilted, 905);
}
