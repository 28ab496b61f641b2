// Model families built from convex hulls: point files, the snub cube and snub dodecahedron,
// the snub 24-cell, the grand antiprism and polytopal glomes. Only the public hull API is used
// here (no CGAL headers).
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/LU>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/input_file.hpp"
#include "cw4d/complex/text.hpp"
#include "cw4d/complex/wythoff.hpp"
#include "cw4d/tetrahedralize/hull.hpp"

namespace cw4d {

namespace {

constexpr double kPhi = std::numbers::phi;

Eigen::MatrixXd to_matrix(const std::vector<Eigen::Vector4d>& points) {
  Eigen::MatrixXd m(4, static_cast<Eigen::Index>(points.size()));
  for (std::size_t i = 0; i < points.size(); ++i) m.col(static_cast<Eigen::Index>(i)) = points[i];
  return m;
}

// The 12 even permutations of 4 positions.
std::vector<std::array<int, 4>> even_permutations() {
  std::vector<std::array<int, 4>> out;
  std::array<int, 4> p{0, 1, 2, 3};
  do {
    int inversions = 0;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) inversions += p[i] > p[j];
    if (inversions % 2 == 0) out.push_back(p);
  } while (std::next_permutation(p.begin(), p.end()));
  return out;
}

// Every even permutation of `values` with every choice of signs of its non-zero entries.
void add_even_signed(const std::array<double, 4>& values, std::vector<Eigen::Vector4d>& out) {
  for (const auto& perm : even_permutations())
    for (int signs = 0; signs < 16; ++signs) {
      Eigen::Vector4d v;
      bool skip = false;
      for (int i = 0; i < 4; ++i) {
        const bool negative = (signs >> i) & 1;
        if (negative && values[i] == 0.0) skip = true;  // -0 is +0: count each point once
        v(perm[i]) = negative ? -values[i] : values[i];
      }
      if (!skip) out.push_back(v);
    }
}

// The 120 vertices of the 600-cell with circumradius 1.
std::vector<Eigen::Vector4d> hexacosichoron_vertices() {
  std::vector<Eigen::Vector4d> v;
  for (int i = 0; i < 4; ++i)
    for (double s : {1.0, -1.0}) {
      Eigen::Vector4d e = Eigen::Vector4d::Zero();
      e(i) = s;
      v.push_back(e);
    }
  for (int signs = 0; signs < 16; ++signs) {
    Eigen::Vector4d h;
    for (int i = 0; i < 4; ++i) h(i) = (signs >> i) & 1 ? -0.5 : 0.5;
    v.push_back(h);
  }
  add_even_signed({kPhi / 2, 0.5, 0.5 / kPhi, 0.0}, v);
  return v;
}

// The snub of the rank-3 Coxeter group [p, q] with edge length 2: the orbit of one point under
// the rotation subgroup (products of two reflections), chosen so that all its edges are equal.
// Linear Wythoff ringings cannot give it (the snub is not the orbit of the full group).
Complex make_snub_polyhedron(int p, int q, std::size_t expected_vertices, const char* name) {
  const double pi = std::numbers::pi;
  // Unit simple roots as the rows of the Cholesky factor of the Gram matrix (as in wythoff.cpp).
  Eigen::Matrix3d gram;
  const double cp = std::cos(pi / p), cq = std::cos(pi / q);
  gram << 1, -cp, 0, -cp, 1, -cq, 0, -cq, 1;
  const Eigen::Matrix3d roots = gram.llt().matrixL();
  std::array<Eigen::Matrix3d, 3> s;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d a = roots.row(i).transpose();
    s[i] = Eigen::Matrix3d::Identity() - 2.0 * a * a.transpose();
  }
  // Rotations about the axes of the p-gons, the q-gons and the 2-fold axes; the snub vertex x
  // is joined to r1 x, r2 x and r3 x (and r1^-1 x, r2^-1 x).
  const std::array<Eigen::Matrix3d, 3> r = {s[0] * s[1], s[1] * s[2], s[0] * s[2]};
  // |x - R x|^2 = 2 - x^T (R + R^T) x on the unit sphere: equal edges are two quadratic equations.
  const auto sym = [](const Eigen::Matrix3d& m) -> Eigen::Matrix3d { return m + m.transpose(); };
  const Eigen::Matrix3d a1 = sym(r[0]) - sym(r[2]), a2 = sym(r[1]) - sym(r[2]);
  // Newton on (x^T A1 x, x^T A2 x, |x|^2 - 1) from the incentre of the fundamental chamber, which
  // lies inside the rotation group's fundamental domain next to the wanted solution.
  Eigen::Vector3d x = roots.triangularView<Eigen::Lower>().solve(Eigen::Vector3d::Ones());
  x.normalize();
  for (int it = 0; it < 100; ++it) {
    const Eigen::Vector3d f(x.dot(a1 * x), x.dot(a2 * x), x.squaredNorm() - 1.0);
    if (f.norm() < 1e-15) break;
    Eigen::Matrix3d jac;
    jac.row(0) = 2.0 * (a1 * x).transpose();
    jac.row(1) = 2.0 * (a2 * x).transpose();
    jac.row(2) = 2.0 * x.transpose();
    x -= jac.partialPivLu().solve(f);
  }
  const double edge = (x - r[2] * x).norm();
  if (!(edge > 1e-6) || std::abs((x - r[0] * x).norm() - edge) > 1e-12 * edge ||
      std::abs((x - r[1] * x).norm() - edge) > 1e-12 * edge)
    throw Error(std::string(name) + ": the equal-edge snub point was not found");
  x *= 2.0 / edge;
  // Orbit under r1, r2 (they generate the rotation group), deduplicated by distance.
  std::vector<Eigen::Vector3d> orbit{x};
  for (std::size_t i = 0; i < orbit.size(); ++i)
    for (int g = 0; g < 2; ++g) {
      const Eigen::Vector3d y = r[g] * orbit[i];
      const bool seen = std::any_of(orbit.begin(), orbit.end(), [&](const Eigen::Vector3d& z) {
        return (z - y).norm() < 1e-9;
      });
      if (!seen) orbit.push_back(y);
    }
  if (orbit.size() != expected_vertices)
    throw Error(std::string(name) + ": unexpected orbit size " + std::to_string(orbit.size()));
  Eigen::MatrixXd m(3, static_cast<Eigen::Index>(orbit.size()));
  for (std::size_t i = 0; i < orbit.size(); ++i) m.col(static_cast<Eigen::Index>(i)) = orbit[i];
  return convex_hull(m);
}

double parse_double(std::string_view text, bool* ok) {
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  *ok = ec == std::errc() && ptr == text.data() + text.size() && std::isfinite(value);
  return value;
}

Complex make_glome_spec(const std::string& spec, std::string_view args) {
  const auto comma = args.find(',');
  bool ok = comma != std::string_view::npos;
  const double r = ok ? parse_double(args.substr(0, comma), &ok) : 0.0;
  if (!ok)
    throw InputError("model spec " + quote_user_text(spec) +
                     ": expected glome:R,N with a number R");
  const auto n = parse_ints(args.substr(comma + 1), spec, 1)[0];
  return make_glome(r, n);
}

}  // namespace

Eigen::MatrixXd read_point_file(const std::string& path) {
  // Only regular files of bounded size (a FIFO or /dev/zero would hang or fill the memory).
  const std::string text = read_input_file(path);
  std::istringstream in(text);
  std::vector<double> coords;
  int dim = 0;
  std::size_t line_no = 0;
  std::string line;
  while (std::getline(in, line)) {
    ++line_no;
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream fields(line);
    std::string token;
    int count = 0;
    while (fields >> token) {
      bool ok = false;
      const double value = parse_double(token, &ok);
      if (!ok) throw ParseError(path, line_no, quote_user_text(token) + " is not a finite number");
      coords.push_back(value);
      ++count;
    }
    if (count == 0) continue;
    if (dim == 0) {
      if (count != 3 && count != 4)
        throw ParseError(path, line_no,
                         "a point needs 3 or 4 coordinates, got " + std::to_string(count));
      dim = count;
    } else if (count != dim) {
      throw ParseError(path, line_no,
                       "expected " + std::to_string(dim) +
                           " coordinates like the first point, got " + std::to_string(count));
    }
  }
  if (in.bad()) throw ParseError(path, line_no, "read error");
  if (dim == 0) throw ParseError(path, line_no, "no points in file");
  return Eigen::Map<const Eigen::MatrixXd>(coords.data(), dim,
                                           static_cast<Eigen::Index>(coords.size() / dim));
}

Complex make_snub_cube() {
  return make_snub_polyhedron(4, 3, 24, "snub cube");
}

Complex make_snub_dodecahedron() {
  return make_snub_polyhedron(5, 3, 60, "snub dodecahedron");
}

Complex make_snub_24_cell() {
  std::vector<Eigen::Vector4d> v;
  add_even_signed({0.0, 1.0, kPhi, kPhi * kPhi}, v);
  return convex_hull(to_matrix(v));
}

Complex make_grand_antiprism() {
  // Two completely orthogonal planes, each through a great decagon of the 600-cell: the first
  // through e1 and its neighbour (phi, 1, 1/phi, 0) / 2, the second its orthogonal complement.
  const Eigen::Vector4d a1(1, 0, 0, 0), a2 = Eigen::Vector4d(0, 1, 1 / kPhi, 0).normalized();
  const Eigen::Vector4d b1 = Eigen::Vector4d(0, -1 / kPhi, 1, 0).normalized(), b2(0, 0, 0, 1);
  const auto in_plane = [](const Eigen::Vector4d& v, const Eigen::Vector4d& e1,
                           const Eigen::Vector4d& e2) {
    return std::abs(v.dot(e1) * v.dot(e1) + v.dot(e2) * v.dot(e2) - 1.0) < 1e-9;
  };
  std::vector<Eigen::Vector4d> kept;
  for (const auto& v : hexacosichoron_vertices())
    if (!in_plane(v, a1, a2) && !in_plane(v, b1, b2)) kept.push_back(v);
  if (kept.size() != 100) throw Error("grand antiprism: the two decagons were not found");
  return convex_hull(to_matrix(kept));
}

Complex make_glome(double r, int n) {
  if (!std::isfinite(r) || r <= 0.0)
    throw InputError("glome:R,N needs a radius R > 0, got " + std::to_string(r));
  if (n < 1 || n > max_glome_resolution)
    throw InputError("glome:R,N needs a resolution N of 1.." +
                     std::to_string(max_glome_resolution) + ", got " + std::to_string(n));
  std::vector<Eigen::Vector4d> points;
  const double pi = std::numbers::pi;
  for (int i = 0; i <= n; ++i) {
    const double a = 0.5 * pi * i / n;
    // Exact zeros on the two Hopf circles: one point per angle, not a ring of near-duplicates.
    const double ca = i == n ? 0.0 : std::cos(a), sa = i == 0 ? 0.0 : std::sin(a);
    const int mb = i == n ? 1 : std::max(3, static_cast<int>(std::ceil(4.0 * n * ca)));
    const int mc = i == 0 ? 1 : std::max(3, static_cast<int>(std::ceil(4.0 * n * sa)));
    const double shift = 0.5 * (i % 2);  // staggered tori give better-shaped cells
    for (int j = 0; j < mb; ++j)
      for (int k = 0; k < mc; ++k) {
        const double b = 2.0 * pi * (j + shift) / mb, c = 2.0 * pi * (k + shift) / mc;
        points.emplace_back(r * ca * std::cos(b), r * ca * std::sin(b), r * sa * std::cos(c),
                            r * sa * std::sin(c));
      }
  }
  return convex_hull(to_matrix(points));
}

std::vector<ModelFamily> hull_families() {
  std::vector<ModelFamily> f;
  f.push_back(parametric_family(
      "hull", "hull:FILE",
      "convex hull of the points in FILE (one point per line, 3 or 4 coordinates separated by "
      "spaces or commas, # comments)",
      [](const std::string&, std::string_view path) {
        const std::string file(path);
        const Eigen::MatrixXd points = read_point_file(file);
        try {
          return convex_hull(points);
        } catch (const InputError& e) {
          // The points parse but have no full-dimensional hull: an input error (exit 1),
          // naming the file they came from.
          std::string reason = e.what();
          if (reason.rfind("convex_hull: ", 0) == 0) reason.erase(0, 13);
          throw InputError(file + ": no convex hull: " + reason);
        }
      }));
  f.push_back(named_family({"snub cube", "snub-cube", "snic", "wythoff:s4s3s"},
                           "snub cube s4s3s: 32 triangles and 6 squares, edge 2", make_snub_cube));
  f.push_back(named_family({"snub dodecahedron", "snub-dodecahedron", "snid", "wythoff:s5s3s"},
                           "snub dodecahedron s5s3s: 80 triangles and 12 pentagons, "
                           "edge 2",
                           make_snub_dodecahedron));
  f.push_back(named_family({"snub 24-cell", "snub-24-cell", "sadi", "wythoff:s3s4o3o"},
                           "snub 24-cell s3s4o3o: hull of the even permutations of "
                           "(0, +-1, +-phi, +-phi^2), edge 2",
                           make_snub_24_cell));
  f.push_back(named_family({"grand antiprism", "gap"},
                           "grand antiprism: the 600-cell (circumradius 1) without two "
                           "completely orthogonal decagons",
                           make_grand_antiprism));
  // Replaces the core family of this usage: Miratope's "semisnub icositetrachoron" and the
  // other names of the two polychora above load too.
  f.push_back(uniform_polychoron_family(true));
  f.push_back(parametric_family(
      "glome", "glome:R,N",
      "convex polytope inscribed in the 3-sphere of radius R, Hopf-coordinate grid of "
      "resolution N = 1..12 (volume -> pi^2 R^4 / 2)",
      make_glome_spec));
  return f;
}

}  // namespace cw4d
