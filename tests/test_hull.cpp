// Tests of the CGAL convex hull and the models built on it: hulls of the vertices of every
// Wythoff polychoron against the Wythoff complex (two independent constructions), hulls of the
// Miratope files against their headers, the snub 24-cell and grand antiprism against published
// counts and the Miratope coordinates, the snub cube and snub dodecahedron, 3D cases, degenerate
// input, glome volumes, point files.
//
// CW4D_STRESS_FRACTION (a number in (0, 1), unset in the normal suite) makes the two loops over
// every Wythoff polychoron and every Miratope file take only every fourth one, evenly spread
// over the families (the sanitizer build, where a hull costs ten times more and the normal suite
// has already compared all of them).
#include <catch2/catch.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/complex.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/off_io.hpp"
#include "cw4d/complex/validate.hpp"
#include "cw4d/tetrahedralize/catalogue.hpp"
#include "cw4d/tetrahedralize/hull.hpp"
#include "support/stride.hpp"

using namespace cw4d;
using FVector = std::vector<std::size_t>;
namespace fs = std::filesystem;

namespace {

const fs::path kMiratope = fs::path(CW4D_TEST_DATA_DIR) / "miratope" / "convex uniform";

Eigen::MatrixXd columns(std::initializer_list<std::vector<double>> pts) {
  Eigen::MatrixXd m(static_cast<Eigen::Index>(pts.begin()->size()),
                    static_cast<Eigen::Index>(pts.size()));
  Eigen::Index j = 0;
  for (const auto& p : pts) {
    for (std::size_t i = 0; i < p.size(); ++i) m(static_cast<Eigen::Index>(i), j) = p[i];
    ++j;
  }
  return m;
}

Eigen::MatrixXd append(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  Eigen::MatrixXd m(a.rows(), a.cols() + b.cols());
  m << a, b;
  return m;
}

void check_valid(const Complex& c) {
  const ValidationReport report = validate(c);
  INFO(report.summary());
  CHECK(report.ok());
}

// Edge lengths of a complex.
std::vector<double> edge_lengths(const Complex& c) {
  std::vector<double> out;
  for (std::uint32_t e = 0; e < c.count(1); ++e) {
    const auto [a, b] = c.edge(e);
    out.push_back((c.position(a) - c.position(b)).norm());
  }
  return out;
}

// Sorted distances between all pairs of points, divided by the largest distance from the
// centroid: equal lists mean congruent up to scale, in practice.
std::vector<double> distance_profile(const Eigen::MatrixXd& p) {
  const Eigen::VectorXd c = p.rowwise().mean();
  const double r = (p.colwise() - c).colwise().norm().maxCoeff();
  std::vector<double> d;
  for (Eigen::Index i = 0; i < p.cols(); ++i)
    for (Eigen::Index j = i + 1; j < p.cols(); ++j) d.push_back((p.col(i) - p.col(j)).norm() / r);
  std::sort(d.begin(), d.end());
  return d;
}

void check_congruent(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  REQUIRE(a.cols() == b.cols());
  const auto da = distance_profile(a), db = distance_profile(b);
  double worst = 0.0;
  for (std::size_t i = 0; i < da.size(); ++i) worst = std::max(worst, std::abs(da[i] - db[i]));
  CHECK(worst < 1e-9);
}

std::string diagram(unsigned mask, const std::string& labels) {
  std::string out;
  for (int i = 0; i < 4; ++i) {
    if (i > 0) out += labels[i - 1];
    out += (mask >> i) & 1u ? 'x' : 'o';
  }
  return out;
}

// A scratch directory for point files, removed at the end of each test.
struct TempDir {
  fs::path path;
  explicit TempDir(const std::string& name)
      : path(fs::temp_directory_path() / ("cw4d_test_hull_" + name)) {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  std::string write(const std::string& file, const std::string& text) const {
    std::ofstream(path / file) << text;
    return (path / file).string();
  }
};

}  // namespace

TEST_CASE("the hull of every Wythoff polychoron's vertices is the Wythoff complex", "[hull]") {
  // A4, B4, F4, H4, each with all 15 ringings (with a stride of 4 over the 60, each family
  // keeps 3 or 4 ringings, different ones in each, as 15 and 4 are coprime).
  const std::size_t stride = test::loop_stride();
  std::size_t index = 0;
  for (const std::string labels : {"333", "433", "343", "533"}) {
    for (unsigned mask = 1; mask < 16; ++mask) {
      if (index++ % stride != 0) continue;
      const std::string d = diagram(mask, labels);
      INFO(d);
      const Complex w = load_model("wythoff:" + d, default_catalogue());
      const Complex h = convex_hull(w.positions());
      CHECK(h.fvector() == w.fvector());
      check_valid(h);
      CHECK(signed_volume(h) == Approx(signed_volume(w)).epsilon(1e-9));
    }
  }
}

TEST_CASE("the 120-cell's vertices give 120 dodecahedra of pentagons", "[hull]") {
  const Complex h = convex_hull(load_model("120-cell", default_catalogue()).positions());
  CHECK(h.fvector() == FVector{600, 1200, 720, 120});
  for (std::uint32_t f = 0; f < h.count(2); ++f) CHECK(h.boundary(2).row_size(f) == 5);
  for (std::uint32_t c = 0; c < h.count(3); ++c) CHECK(h.boundary(3).row_size(c) == 12);
}

TEST_CASE("hulls of the Miratope convex uniform vertex sets match the files' counts",
          "[hull][data]") {
  REQUIRE(fs::is_directory(kMiratope));
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(kMiratope))
    if (entry.path().extension() == ".off") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  const std::size_t stride = test::loop_stride();
  int compared = 0;
  for (std::size_t i = 0; i < files.size(); i += stride) {
    const fs::path& path = files[i];
    INFO(path.filename().string());
    const Complex file = read_off_file(path.string());
    const Complex h = convex_hull(file.positions());
    CHECK(h.fvector() == file.fvector());
    check_valid(h);
    ++compared;
  }
  CHECK(files.size() >= 41);
  CHECK(static_cast<std::size_t>(compared) == test::strided_count(files.size(), stride));
}

TEST_CASE("the snub 24-cell has the published counts, equal edges, and is Miratope's",
          "[hull][models]") {
  const Complex s = make_snub_24_cell();
  CHECK(s.fvector() == FVector{96, 432, 480, 144});
  check_valid(s);
  for (double len : edge_lengths(s)) CHECK(len == Approx(2.0).epsilon(1e-12));
  // 24 icosahedra and 120 tetrahedra.
  int icosahedra = 0, tetrahedra = 0;
  for (std::uint32_t c = 0; c < s.count(3); ++c) {
    icosahedra += s.boundary(3).row_size(c) == 20;
    tetrahedra += s.boundary(3).row_size(c) == 4;
  }
  CHECK(icosahedra == 24);
  CHECK(tetrahedra == 120);
  const Complex file = read_off_file((kMiratope / "Semisnub icositetrachoron.off").string());
  CHECK(file.fvector() == s.fvector());
  check_congruent(s.positions(), file.positions());
}

TEST_CASE("the grand antiprism has the published counts and is Miratope's", "[hull][models]") {
  const Complex g = make_grand_antiprism();
  CHECK(g.fvector() == FVector{100, 500, 720, 320});
  check_valid(g);
  const auto lengths = edge_lengths(g);
  const double edge = 1.0 / std::numbers::phi;  // the 600-cell's edge at circumradius 1
  for (double len : lengths) CHECK(len == Approx(edge).epsilon(1e-12));
  // 20 pentagonal antiprisms and 300 tetrahedra.
  int antiprisms = 0, tetrahedra = 0;
  for (std::uint32_t c = 0; c < g.count(3); ++c) {
    antiprisms += g.boundary(3).row_size(c) == 12;
    tetrahedra += g.boundary(3).row_size(c) == 4;
  }
  CHECK(antiprisms == 20);
  CHECK(tetrahedra == 300);
  const Complex file = read_off_file((kMiratope / "Grand antiprism.off").string());
  CHECK(file.fvector() == g.fvector());
  check_congruent(g.positions(), file.positions());
}

namespace {

// Snub polyhedra: f-vector, faces by number of edges, equal edges 2, one circumradius, valid.
void check_snub(const Complex& c, const FVector& fvector, std::size_t triangles, int n_gon,
                std::size_t n_gons) {
  CHECK(c.ambient_dim() == 3);
  CHECK(c.fvector() == fvector);
  check_valid(c);
  std::map<std::size_t, std::size_t> sizes;
  for (std::uint32_t f = 0; f < c.count(2); ++f) ++sizes[c.boundary(2).row_size(f)];
  CHECK(sizes == std::map<std::size_t, std::size_t>{{3, triangles},
                                                    {static_cast<std::size_t>(n_gon), n_gons}});
  for (double len : edge_lengths(c)) CHECK(std::abs(len - 2.0) < 1e-9);
  const Eigen::VectorXd centroid = c.positions().rowwise().mean();
  CHECK(centroid.norm() < 1e-9);
  const double r = c.position(0).norm();
  for (std::uint32_t v = 0; v < c.count(0); ++v) CHECK(std::abs(c.position(v).norm() - r) < 1e-9);
}

}  // namespace

TEST_CASE("the snub cube has 32 triangles and 6 squares of edge 2", "[hull][models][3d]") {
  const Complex c = make_snub_cube();
  check_snub(c, FVector{24, 60, 38}, 32, 4, 6);
  // Circumradius of the unit-edge snub cube: 1.3437133737446...
  CHECK(c.position(0).norm() == Approx(2.0 * 1.3437133737446).epsilon(1e-10));
}

TEST_CASE("the snub dodecahedron has 80 triangles and 12 pentagons of edge 2",
          "[hull][models][3d]") {
  const Complex c = make_snub_dodecahedron();
  check_snub(c, FVector{60, 150, 92}, 80, 5, 12);
  // Circumradius of the unit-edge snub dodecahedron: 2.1558373751156...
  CHECK(c.position(0).norm() == Approx(2.0 * 2.1558373751156).epsilon(1e-10));
}

TEST_CASE("3D: a cube with interior and face-centre points is a cube", "[hull][3d]") {
  const Eigen::MatrixXd cube = make_cube(3).positions();
  const Eigen::MatrixXd extra = columns({{0, 0, 0},
                                         {0.3, -0.2, 0.5},
                                         {-0.9, 0.9, -0.9},
                                         {1, 0, 0},
                                         {-1, 0, 0},
                                         {0, 1, 0},
                                         {0, -1, 0},
                                         {0, 0, 1},
                                         {0, 0, -1},
                                         {1, 0.25, -0.5}});
  const Complex h = convex_hull(append(extra, cube));
  CHECK(h.fvector() == FVector{8, 12, 6});
  check_valid(h);
  CHECK(signed_volume(h) == Approx(8.0));
  for (std::uint32_t f = 0; f < h.count(2); ++f) CHECK(h.boundary(2).row_size(f) == 4);
  // Only cube corners remain.
  for (Eigen::Index v = 0; v < h.positions().cols(); ++v)
    CHECK(h.positions().col(v).cwiseAbs().minCoeff() == 1.0);
}

TEST_CASE("3D: random points on a sphere give a simplicial polytope", "[hull][3d]") {
  std::mt19937 rng(20240611);
  std::normal_distribution<double> normal;
  for (int n : {4, 10, 50, 400}) {
    Eigen::MatrixXd p(3, n);
    for (int j = 0; j < n; ++j) {
      Eigen::Vector3d x(normal(rng), normal(rng), normal(rng));
      p.col(j) = x.normalized();
    }
    INFO(n);
    const Complex h = convex_hull(p);
    check_valid(h);
    const auto f = h.fvector();
    REQUIRE(f.size() == 3);
    CHECK(f[0] == static_cast<std::size_t>(n));
    CHECK(static_cast<long>(f[0]) - static_cast<long>(f[1]) + static_cast<long>(f[2]) == 2);
    CHECK(2 * f[1] == 3 * f[2]);
  }
}

TEST_CASE("duplicates and points on edges, faces and cells are dropped", "[hull][robust]") {
  const Eigen::MatrixXd t = make_cube(4).positions();
  Eigen::MatrixXd extra(4, 0);
  // Exact and near duplicates (within the coplanarity tolerance), edge midpoints, square
  // centres, cube centres, the centre, and points inside faces off-centre.
  Eigen::MatrixXd near = t.leftCols(4);
  near(0, 0) += 1e-13;
  near(3, 2) -= 1e-12;
  const Complex tess = make_cube(4);
  Eigen::MatrixXd mids(4, static_cast<Eigen::Index>(tess.count(1)));
  for (std::uint32_t e = 0; e < tess.count(1); ++e) {
    const auto [a, b] = tess.edge(e);
    mids.col(e) = 0.25 * t.col(a) + 0.75 * t.col(b);
  }
  Eigen::MatrixXd centres(4, static_cast<Eigen::Index>(tess.count(2) + tess.count(3) + 1));
  Eigen::Index j = 0;
  for (int rank : {2, 3}) {
    for (std::uint32_t i = 0; i < tess.count(rank); ++i) {
      const auto vs = tess.vertices_of(rank, i);
      Eigen::VectorXd c = Eigen::VectorXd::Zero(4);
      for (auto v : vs) c += t.col(v);
      centres.col(j++) = c / static_cast<double>(vs.size());
    }
  }
  centres.col(j) = Eigen::VectorXd::Zero(4);
  const Eigen::MatrixXd all = append(append(append(append(mids, t), t), near), centres);
  const Complex h = convex_hull(all);
  CHECK(h.fvector() == tess.fvector());
  check_valid(h);
  CHECK(signed_volume(h) == Approx(16.0));
  // The kept vertices are the first copies (the midpoints come first and are all dropped).
  CHECK(h.positions() == t);
}

TEST_CASE("rounded centres of golden-ratio faces, slightly outside, are dropped",
          "[hull][robust]") {
  // The centroids of the 120-cell's edges, pentagons and dodecahedra, computed in double and
  // pushed out by 1e-12 (relative): CGAL sees some of them as hull vertices; the merge must not.
  const Complex c = load_model("120-cell", default_catalogue());
  const Eigen::MatrixXd& v = c.positions();
  std::vector<Eigen::VectorXd> centres;
  for (int rank : {1, 2, 3})
    for (std::uint32_t i = 0; i < c.count(rank); ++i) {
      Eigen::VectorXd m = Eigen::VectorXd::Zero(4);
      const auto ids = c.vertices_of(rank, i);
      for (auto id : ids) m += v.col(id);
      centres.push_back(m / static_cast<double>(ids.size()) * (1.0 + 1e-12));
    }
  Eigen::MatrixXd extra(4, static_cast<Eigen::Index>(centres.size()));
  for (std::size_t i = 0; i < centres.size(); ++i)
    extra.col(static_cast<Eigen::Index>(i)) = centres[i];
  const Complex h = convex_hull(append(v, extra));
  CHECK(h.fvector() == c.fvector());
  check_valid(h);
  CHECK(h.positions() == v);
}

TEST_CASE("degenerate input throws InputError", "[hull][errors]") {
  // Too few points.
  CHECK_THROWS_AS(convex_hull(columns({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}})), InputError);
  CHECK_THROWS_AS(convex_hull(make_simplex(4).positions().leftCols(4)), InputError);
  // Wrong dimension.
  CHECK_THROWS_AS(convex_hull(make_polygon(5).positions()), InputError);
  CHECK_THROWS_AS(convex_hull(make_cube(5).positions()), InputError);
  // Not finite.
  Eigen::MatrixXd bad = make_cube(3).positions();
  bad(1, 3) = std::nan("");
  CHECK_THROWS_AS(convex_hull(bad), InputError);
  bad(1, 3) = INFINITY;
  CHECK_THROWS_AS(convex_hull(bad), InputError);
  // All in a plane of R^3, a line, one point; a 3-flat of R^4; enough points, but duplicates.
  CHECK_THROWS_AS(convex_hull(columns({{0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}, {5, 7, 1}})),
                  InputError);
  CHECK_THROWS_AS(convex_hull(columns({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}})), InputError);
  CHECK_THROWS_AS(convex_hull(Eigen::MatrixXd::Ones(3, 10)), InputError);
  Eigen::MatrixXd flat = make_cube(4).positions();
  flat.row(2) = flat.row(0) + 0.5 * flat.row(1);  // a 3-flat through the origin
  CHECK_THROWS_AS(convex_hull(flat), InputError);
  CHECK_THROWS_AS(convex_hull(columns({{0, 0, 0}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}})), InputError);
  // Nearly flat: a tetrahedron of height 1e-12 (below the tolerance).
  CHECK_THROWS_AS(convex_hull(columns({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.2, 0.2, 1e-12}})),
                  InputError);
}

TEST_CASE("glome volumes approach pi^2 R^4 / 2", "[hull][models]") {
  const double exact = std::numbers::pi * std::numbers::pi / 2.0;
  double previous_error = 1.0;
  for (int n : {1, 2, 4, 8, 12}) {
    INFO("glome:1," << n);
    const Complex g = make_glome(1.0, n);
    check_valid(g);
    CHECK(max_radius(g) == Approx(1.0).epsilon(1e-12));
    const double volume = signed_volume(g);
    const double error = (exact - volume) / exact;
    CHECK(error > 0.0);  // inscribed
    CHECK(error < previous_error);
    previous_error = error;
  }
  CHECK(previous_error < 0.02);
  // Volume scales with R^4; the spec goes through the default catalogue.
  const double v1 = signed_volume(load_model("glome:1,3", default_catalogue()));
  const double v2 = signed_volume(load_model("glome:2.5,3", default_catalogue()));
  CHECK(v2 == Approx(std::pow(2.5, 4) * v1).epsilon(1e-9));
  CHECK_THROWS_AS(load_model("glome:0,3", default_catalogue()), InputError);
  CHECK_THROWS_AS(load_model("glome:1,0", default_catalogue()), InputError);
  // Beyond the resolution whose hull builds in seconds: refused before any point is made.
  CHECK_THROWS_AS(
      load_model("glome:1," + std::to_string(max_glome_resolution + 1), default_catalogue()),
      InputError);
  CHECK_THROWS_AS(load_model("glome:1", default_catalogue()), InputError);
  CHECK_THROWS_AS(load_model("glome:x,3", default_catalogue()), InputError);
}

TEST_CASE("hull:FILE reads points and reports bad lines with their numbers", "[hull][file]") {
  const TempDir dir("file");
  const std::string good = dir.write("cube.txt",
                                     "# the cube, with an interior point\n"
                                     "-1 -1 -1\n 1,-1,-1\n-1, 1 ,-1  # comment\n1 1 -1\n\n"
                                     "-1 -1 1\n1 -1 1\n-1 1 1\n1 1 1\n0 0 0.5\n");
  const Complex c = load_model("hull:" + good, default_catalogue());
  CHECK(c.fvector() == FVector{8, 12, 6});
  check_valid(c);
  const Eigen::MatrixXd p = read_point_file(good);
  CHECK(p.rows() == 3);
  CHECK(p.cols() == 9);

  const auto line_of = [&](const std::string& name, const std::string& text) {
    const std::string path = dir.write(name, text);
    try {
      load_model("hull:" + path, default_catalogue());
    } catch (const ParseError& e) {
      CHECK(e.file() == path);
      CHECK(std::string(e.what()).find(path + ":" + std::to_string(e.line()) + ": ") == 0);
      return e.line();
    }
    FAIL("no ParseError for " << name);
    return std::size_t{999};
  };
  CHECK(line_of("number.txt", "# x\n0 0 0\n1 0 zero\n0 1 0\n0 0 1\n") == 3);
  CHECK(line_of("nan.txt", "0 0 0\n1 0 0\n0 nan 0\n0 0 1\n") == 3);
  CHECK(line_of("mixed.txt", "0 0 0\n1 0 0\n\n0 1 0 0\n0 0 1\n") == 4);
  CHECK(line_of("dim5.txt", "# five\n0 0 0 0 0\n") == 2);
  CHECK(line_of("dim2.txt", "0 0\n1 0\n") == 1);
  CHECK(line_of("empty.txt", "# nothing\n\n") == 2);
  CHECK(line_of("missing.txt-does-not-exist/none", "") == 0);
  // Parsable but degenerate: an input error, not a parse error.
  const std::string flat = dir.write("flat.txt", "0 0 0\n1 0 0\n0 1 0\n1 1 0\n");
  CHECK_THROWS_AS(load_model("hull:" + flat, default_catalogue()), InputError);
}

TEST_CASE("the hull models are registered under their names and aliases", "[hull][models]") {
  for (const char* spec :
       {"snub cube", "snic", "snub dodecahedron", "snid", "snub 24-cell", "Snub-24-Cell", "sadi",
        "grand antiprism", "GAP", "glome:1,2", "hull:x.txt"})
    CHECK(is_builtin_spec(spec, default_catalogue()));
  CHECK(load_model("sadi", default_catalogue()).fvector() == FVector{96, 432, 480, 144});
  CHECK(load_model("gap", default_catalogue()).fvector() == FVector{100, 500, 720, 320});
  CHECK(load_model("snic", default_catalogue()).fvector() == FVector{24, 60, 38});
  CHECK(load_model("Snub-Dodecahedron", default_catalogue()).fvector() == FVector{60, 150, 92});
  // Prism over (V, E, F): (2V, 2E + V, 2F + E, F + 2).
  const Complex prism = load_model("prism:snub cube", default_catalogue());
  CHECK(prism.fvector() == FVector{48, 144, 136, 40});
  check_valid(prism);
  int hull_entries = 0;
  for (const auto& info : builtin_list(default_catalogue()))
    hull_entries += info.spec == "hull:FILE";
  CHECK(hull_entries == 1);
}

TEST_CASE("hull timing of the omnitruncated 120-cell (informational)", "[hull][.timing]") {
  const Complex w = load_model("wythoff:x5x3x3x", default_catalogue());
  const auto start = std::chrono::steady_clock::now();
  const Complex h = convex_hull(w.positions());
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  WARN("convex_hull of " << w.count(0) << " points: " << seconds << " s");
  CHECK(h.fvector() == w.fvector());
}
