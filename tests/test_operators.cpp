// Tests of complex/operators and export/mesh_import: pyramids, polar duals, antiprisms, the
// round shapes (convex, converging to their analytic volumes), mesh files read through OpenMesh
// and their extrusions and solids of revolution, and the model specs of all of them.
#include <catch2/catch.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

#include "cw4d/complex/builder.hpp"
#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/complex.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/operators.hpp"
#include "cw4d/complex/validate.hpp"
#include "cw4d/complex/wythoff.hpp"
#include "cw4d/export/mesh_import.hpp"

using namespace cw4d;

namespace {

using FVector = std::vector<std::size_t>;
constexpr double pi = std::numbers::pi;

// The core families with export/'s mesh-file families (extrude:, spin:), as a program that links
// cw4d::export but not cw4d::tetrahedralize would build it.
const Catalogue& mesh_catalogue() {
  static const Catalogue catalogue = core_catalogue().extended(mesh_file_families());
  return catalogue;
}

void require_valid(const Complex& c) {
  const ValidationReport report = validate(c);
  INFO(report.summary());
  REQUIRE(report.ok());
}

// Area of the regular N-gon of circumradius r.
double polygon_area(int n, double r = 1.0) {
  return 0.5 * n * r * r * std::sin(2.0 * pi / n);
}

// Every edge length of a complex, as min and max.
std::pair<double, double> edge_length_range(const Complex& c) {
  double lo = 1e300, hi = 0.0;
  for (std::uint32_t e = 0; e < c.count(1); ++e) {
    const auto [a, b] = c.edge(e);
    const double len = (c.position(a) - c.position(b)).norm();
    lo = std::min(lo, len);
    hi = std::max(hi, len);
  }
  return {lo, hi};
}

// A scratch directory for mesh files, removed at the end of the test.
struct TempDir {
  std::filesystem::path path;
  explicit TempDir(const std::string& name)
      : path(std::filesystem::temp_directory_path() / ("cw4d_test_operators_" + name)) {
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~TempDir() { std::filesystem::remove_all(path); }
  std::string write(const std::string& file, const std::string& text) const {
    const auto p = path / file;
    std::ofstream(p) << text;
    return p.string();
  }
};

// The cube [0,2]^3 translated by (x0, -1, -1): quads, one face per line.
std::string cube_obj(double x0) {
  std::string s = "# cube\n";
  for (int i = 0; i < 8; ++i)
    s += "v " + std::to_string(x0 + 2.0 * (i & 1)) + " " + std::to_string((i & 2) ? 1 : -1) + " " +
         std::to_string((i & 4) ? 1 : -1) + "\n";
  s += "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
  return s;
}

// Triangular prism: right triangle (0,0) (2,0) (0,2) in xy, z in [0, 3]; volume 6.
const char* prism_off =
    "OFF\n6 5 0\n0 0 0\n2 0 0\n0 2 0\n0 0 3\n2 0 3\n0 2 3\n"
    "3 0 2 1\n3 3 4 5\n4 0 1 4 3\n4 1 2 5 4\n4 2 0 3 5\n";

}  // namespace

// ---------------------------------------------------------------------------------------------
// pyramid and prism

TEST_CASE("pyramid over the cube is the 4D cube pyramid", "[operators][pyramid]") {
  for (double h : {1.0, 2.5, -1.5}) {
    INFO("height " << h);
    const Complex p = make_pyramid(make_cube(3), h);
    require_valid(p);
    CHECK(p.fvector() == FVector{9, 20, 18, 7});
    CHECK(signed_volume(p) == Approx(8.0 * std::abs(h) / 4.0));
    CHECK(p.position(8)(3) == Approx(h));
  }
}

TEST_CASE("pyramids in other dimensions", "[operators][pyramid]") {
  const Complex square = make_pyramid(make_cube(2), 3.0);
  require_valid(square);
  CHECK(square.fvector() == FVector{5, 8, 5});
  CHECK(signed_volume(square) == Approx(4.0 * 3.0 / 3.0));
  const Complex penta = make_pyramid(make_cube(4), 1.0);
  require_valid(penta);
  CHECK(penta.fvector() == FVector{17, 48, 56, 32, 9});
  CHECK(signed_volume(penta) == Approx(16.0 / 5.0));
  // The pyramid over a tetrahedron is a 4-simplex.
  const Complex simplex = make_pyramid(make_simplex(3), 2.0);
  require_valid(simplex);
  CHECK(simplex.fvector() == make_simplex(4).fvector());
  CHECK_THROWS_AS(make_pyramid(make_cube(3), 0.0), InputError);
  CHECK_THROWS_AS(make_pyramid(make_cube(3), std::nan("")), InputError);
}

TEST_CASE("make_prism takes a height", "[operators][prism]") {
  const Complex p = make_prism(make_cube(3), 5.0);
  require_valid(p);
  CHECK(p.fvector() == make_cube(4).fvector());
  CHECK(signed_volume(p) == Approx(40.0));
  CHECK_THROWS_AS(make_prism(make_cube(3), -1.0), InputError);
}

// ---------------------------------------------------------------------------------------------
// polar dual

TEST_CASE("duals of the regular polychora", "[operators][dual]") {
  const Complex d16 = make_dual(make_cube(4));
  require_valid(d16);
  CHECK(d16.fvector() == FVector{8, 24, 32, 16});
  CHECK(signed_volume(d16) == Approx(2.0 / 3.0));  // the 16-cell with vertices +-e_i
  CHECK(is_convex(d16));

  const Complex d24 = make_dual(make_wythoff("x3o4o3o"));
  require_valid(d24);
  CHECK(d24.fvector() == FVector{24, 96, 96, 24});

  const Complex d600 = make_dual(make_wythoff("x5o3o3o"));
  require_valid(d600);
  CHECK(d600.fvector() == FVector{120, 720, 1200, 600});
  const auto [lo, hi] = edge_length_range(d600);
  CHECK(lo == Approx(hi));  // regular: all edges equal

  CHECK(make_dual(make_simplex(4)).fvector() == make_simplex(4).fvector());

  // dual:MODEL keeps the circumradius; for regular polytopes the dual of the dual is the original.
  const Complex c120 = make_wythoff("x5o3o3o");
  const Complex same = load_model("dual:120-cell", mesh_catalogue());
  CHECK(max_radius(same) == Approx(max_radius(c120)));
  CHECK(signed_volume(load_model("dual:dual:120-cell", mesh_catalogue())) ==
        Approx(signed_volume(c120)));
  const Complex t = make_dual_same_size(make_dual_same_size(make_cube(4)));
  CHECK((t.positions().cwiseAbs().array() - 1.0).abs().maxCoeff() < 1e-12);
}

TEST_CASE("the dual of the dual has the original f-vector and shape", "[operators][dual]") {
  for (const char* diagram : {"x4o3o3o", "x3x3o3o", "o3x4o3o", "x5o3x", "x3o3o5o"}) {
    INFO(diagram);
    const Complex p = make_wythoff(diagram);
    const Complex d = make_dual(p);
    require_valid(d);
    const Complex dd = make_dual(d);
    require_valid(dd);
    CHECK(dd.fvector() == p.fvector());
    // Centrally symmetric or not, these are centred at the origin: the poles come back.
    CHECK(signed_volume(dd) == Approx(signed_volume(p)));
    CHECK(max_radius(dd) == Approx(max_radius(p)));
  }
  // A polygon and a 3D solid: cube <-> octahedron, rank 2 = cycles of faces around vertices.
  CHECK(make_dual(make_polygon(7)).fvector() == FVector{7, 7});
  const Complex octa = make_dual(make_cube(3), 2.0);
  require_valid(octa);
  CHECK(octa.fvector() == FVector{6, 12, 8});
  CHECK(max_radius(octa) == Approx(4.0));
}

TEST_CASE("dual rejects non-convex input and bad radii", "[operators][dual][errors]") {
  // An L-shaped hexagon.
  ComplexSoup soup;
  soup.ambient_dim = 2;
  soup.positions.resize(2, 6);
  soup.positions << 0, 2, 2, 1, 1, 0,  //
      0, 0, 1, 1, 2, 2;
  for (std::uint32_t i = 0; i < 6; ++i) soup.edges.push_back({i, (i + 1) % 6});
  const Complex l_shape = build_complex(soup);
  REQUIRE(validate(l_shape).ok());
  CHECK_FALSE(is_convex(l_shape));
  CHECK_THROWS_AS(make_dual(l_shape), InputError);
  CHECK_THROWS_AS(make_dual(make_cube(3), 0.0), InputError);
  CHECK_THROWS_AS(load_model("dual:spin:nothing,3", mesh_catalogue()), Error);
}

// ---------------------------------------------------------------------------------------------
// antiprisms

double antiprism_volume(int n) {  // edge 2
  return n * 8.0 * std::sqrt(4.0 * std::pow(std::cos(pi / (2 * n)), 2) - 1.0) *
         std::sin(3 * pi / (2 * n)) / (12.0 * std::pow(std::sin(pi / n), 2));
}

TEST_CASE("uniform antiprisms and antiprismatic prisms", "[operators][antiprism]") {
  for (int n : {3, 4, 5, 7, 12}) {
    INFO("N = " << n);
    const Complex a = make_antiprism(n);
    require_valid(a);
    const std::size_t un = n;
    CHECK(a.fvector() == FVector{2 * un, 4 * un, 2 * un + 2});
    auto [lo, hi] = edge_length_range(a);
    CHECK(lo == Approx(2.0));
    CHECK(hi == Approx(2.0));
    CHECK(signed_volume(a) == Approx(antiprism_volume(n)));
    CHECK(is_convex(a));

    const Complex p = load_model("prism:antiprism:" + std::to_string(n), mesh_catalogue());
    require_valid(p);
    CHECK(p.fvector() == FVector{4 * un, 10 * un, 8 * un + 4, 2 * un + 4});
    std::tie(lo, hi) = edge_length_range(p);
    CHECK(lo == Approx(2.0));
    CHECK(hi == Approx(2.0));
    CHECK(signed_volume(p) == Approx(2.0 * antiprism_volume(n)));
  }
  CHECK(signed_volume(make_antiprism(3)) == Approx(8.0 * std::sqrt(2.0) / 3.0));  // octahedron
  CHECK_THROWS_AS(make_antiprism(2), InputError);
}

// ---------------------------------------------------------------------------------------------
// round shapes

namespace {

struct RoundCase {
  std::string name;
  std::function<Complex(int)> make;
  double volume;  // the limit
};

std::vector<RoundCase> round_cases(double r) {
  const double sphere = 4.0 / 3.0 * pi * r * r * r;
  return {
      {"sphere", [r](int n) { return make_uv_sphere(r, n); }, sphere},
      {"cylinder", [r](int n) { return make_cylinder(r, n); }, 2.0 * pi * r * r * r},
      {"duocylinder", [r](int n) { return make_duocylinder(r, n); }, pi * pi * std::pow(r, 4)},
      {"cubinder", [r](int n) { return make_cubinder(r, n); }, 4.0 * pi * std::pow(r, 4)},
      {"spherinder", [r](int n) { return make_spherinder(r, n); }, 8.0 / 3.0 * pi * std::pow(r, 4)},
      {"spherone", [r](int n) { return make_cone(make_uv_sphere(r, n)); }, sphere * r / 4.0},
      {"cylindrone", [r](int n) { return make_cone(make_cylinder(r, n)); },
       2.0 * pi * r * r * r * r / 4.0},
  };
}

}  // namespace

TEST_CASE("round shapes are valid, convex and converge monotonically to their volumes",
          "[operators][round][volume]") {
  for (double r : {1.0, 1.7}) {
    for (const auto& rc : round_cases(r)) {
      INFO(rc.name << " r = " << r);
      double previous_error = 1e300;
      for (int n : {8, 16, 32}) {
        INFO("N = " << n);
        const Complex c = rc.make(n);
        require_valid(c);
        CHECK(is_convex(c));
        const double error = std::abs(signed_volume(c) - rc.volume);
        CHECK(error < previous_error);
        previous_error = error;
      }
      CHECK(previous_error < 0.03 * rc.volume);
    }
  }
}

TEST_CASE("round shapes: exact counts and volumes", "[operators][round]") {
  // UV sphere: N segments, N/2 bands -> 2 + N (N/2 - 1) vertices, N (N/2) faces.
  const Complex s = make_uv_sphere(1.0, 16);
  CHECK(s.fvector() == FVector{2 + 16 * 7, 16 * 7 + 16 * 8, 16 * 8});
  CHECK(make_uv_sphere(1.0, 3).fvector() == FVector{5, 9, 6});  // triangular bipyramid
  CHECK(signed_volume(make_duocylinder(2.0, 10)) == Approx(std::pow(polygon_area(10, 2.0), 2)));
  CHECK(signed_volume(make_cubinder(2.0, 10)) == Approx(polygon_area(10, 2.0) * 16.0));
  CHECK(make_duocylinder(1.0, 5).fvector() == FVector{25, 50, 35, 10});
  // The cone apex sits above the centroid at the radius.
  const Complex cone = make_cone(make_uv_sphere(2.0, 8));
  CHECK(cone.position(static_cast<std::uint32_t>(cone.count(0) - 1))(3) == Approx(2.0));
  for (const char* bad :
       {"sphere:0,8", "sphere:-1,8", "sphere:1,2", "sphere:1,1001", "sphere:1", "sphere:x,8",
        "sphere:1,8.5", "duocylinder:1", "cubinder:,8", "cylinder:nan,8", "spherinder:1,8,2"}) {
    INFO(bad);
    CHECK_THROWS_AS(load_model(bad, mesh_catalogue()), InputError);
  }
}

// ---------------------------------------------------------------------------------------------
// mesh files, extrusion, spin

TEST_CASE("read_polyhedron reads OBJ, OFF and STL and keeps polygons", "[mesh_import]") {
  TempDir dir("read");
  const Complex cube = read_polyhedron(dir.write("cube.obj", cube_obj(-1.0)));
  require_valid(cube);
  CHECK(cube.fvector() == FVector{8, 12, 6});
  CHECK(signed_volume(cube) == Approx(8.0));

  const Complex prism = read_polyhedron(dir.write("prism.off", prism_off));
  require_valid(prism);
  CHECK(prism.fvector() == FVector{6, 9, 5});
  CHECK(signed_volume(prism) == Approx(6.0));

  // ASCII STL: a triangle soup; shared vertices are merged by position.
  const std::string stl =
      "solid t\n"
      "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 1 0 0\nendloop\n"
      "endfacet\n"
      "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 0 1\nendloop\n"
      "endfacet\n"
      "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 1\nvertex 0 1 0\nendloop\n"
      "endfacet\n"
      "facet normal 0 0 0\nouter loop\nvertex 1 0 0\nvertex 0 1 0\nvertex 0 0 1\nendloop\n"
      "endfacet\nendsolid t\n";
  const Complex tet = read_polyhedron(dir.write("tet.stl", stl));
  require_valid(tet);
  CHECK(tet.fvector() == FVector{4, 6, 4});
  CHECK(signed_volume(tet) == Approx(1.0 / 6.0));

  // A face listed clockwise is re-oriented by the builder rather than rejected.
  std::string flipped = cube_obj(-1.0);
  flipped.replace(flipped.find("f 1 3 4 2"), 9, "f 2 4 3 1");
  const Complex c2 = read_polyhedron(dir.write("flipped.obj", flipped));
  CHECK(c2.fvector() == FVector{8, 12, 6});
  CHECK(signed_volume(c2) == Approx(8.0));

  // Non-planar quads (the three around a moved vertex) are fan-triangulated.
  std::string bent = cube_obj(-1.0);
  bent.replace(bent.find("v 1.000000 1 1"), 14, "v 1.3 1.2 1.1");
  const Complex c3 = read_polyhedron(dir.write("bent.obj", bent));
  require_valid(c3);
  CHECK(c3.count(2) == 9);
}

TEST_CASE("read_polyhedron errors name the file", "[mesh_import][errors]") {
  TempDir dir("errors");
  const std::string missing = (dir.path / "missing.obj").string();
  // A missing input is bad input (exit 2 in the CLI), not a write failure.
  CHECK_THROWS_AS(read_polyhedron(missing), ParseError);
  std::string open = cube_obj(-1.0);
  open.erase(open.find("f 2 4 8 6"));
  const std::string open_path = dir.write("open.obj", open);
  CHECK_THROWS_AS(read_polyhedron(open_path), ParseError);
  try {
    read_polyhedron(open_path);
  } catch (const ParseError& e) {
    CHECK(e.file() == open_path);
  }
  CHECK_THROWS_AS(read_polyhedron(dir.write("cube.xyz", cube_obj(-1.0))), ParseError);
  CHECK_THROWS_AS(read_polyhedron(dir.write("empty.obj", "# nothing\n")), ParseError);
  CHECK_THROWS_AS(load_model("extrude:" + missing, mesh_catalogue()), ParseError);
}

TEST_CASE("extrusions of mesh files are prisms", "[mesh_import][extrude]") {
  TempDir dir("extrude");
  const Complex t =
      load_model("extrude:" + dir.write("cube.obj", cube_obj(-1.0)), mesh_catalogue());
  require_valid(t);
  CHECK(t.fvector() == make_cube(4).fvector());
  CHECK(signed_volume(t) == Approx(16.0));
  const Complex p = load_model("extrude:" + dir.write("prism.off", prism_off), mesh_catalogue());
  require_valid(p);
  CHECK(p.fvector() == FVector{12, 24, 19, 7});
  CHECK(signed_volume(p) == Approx(6.0 * 2.0));
}

TEST_CASE("spin: polytopal solids of revolution", "[operators][spin]") {
  TempDir dir("spin");
  for (int steps : {3, 8, 13}) {
    INFO("steps " << steps);
    // Cube [1,3] x [-1,1]^2, away from the axis: integral of x = 16.
    const Complex ring =
        load_model("spin:" + dir.write("ring.obj", cube_obj(1.0)) + "," + std::to_string(steps),
                   mesh_catalogue());
    require_valid(ring);
    const std::size_t s = steps;
    CHECK(ring.fvector() == FVector{8 * s, 20 * s, 18 * s, 6 * s});
    CHECK(signed_volume(ring) == Approx(2.0 * polygon_area(steps) * 16.0));

    // Cube [0,2] x [-1,1]^2 with a face on the axis plane: (2-gon ball) x square.
    const Complex solid = make_spin(read_polyhedron(dir.write("solid.obj", cube_obj(0.0))), steps);
    require_valid(solid);
    CHECK(solid.count(0) == 4 + 4 * s);
    CHECK(signed_volume(solid) == Approx(2.0 * polygon_area(steps) * 8.0));
    CHECK(signed_volume(solid) == Approx(polygon_area(steps, 2.0) * 4.0));
  }
  // A tetrahedron touching the axis along an edge still gives a closed complex.
  const Complex tet = read_polyhedron(dir.write(
      "tet.off", "OFF\n4 4 0\n0 0 0\n0 1 0\n1 0 1\n1 1 0\n3 0 1 2\n3 1 3 2\n3 0 2 3\n3 0 3 1\n"));
  require_valid(make_spin(tet, 6));
  // Spinning converges to Pappus: 2 pi * integral of x.
  const Complex fine =
      load_model("spin:" + dir.write("r.obj", cube_obj(1.0)) + ",400", mesh_catalogue());
  CHECK(signed_volume(fine) == Approx(2.0 * pi * 16.0).epsilon(1e-3));

  CHECK_THROWS_AS(make_spin(read_polyhedron(dir.write("neg.obj", cube_obj(-1.0))), 8), InputError);
  CHECK_THROWS_AS(make_spin(make_cube(3), 2), InputError);
  CHECK_THROWS_AS(make_spin(make_cube(4), 8), InputError);
  CHECK_THROWS_AS(load_model("spin:" + dir.write("x.obj", cube_obj(1.0)), mesh_catalogue()),
                  InputError);
}

// ---------------------------------------------------------------------------------------------
// model specs

TEST_CASE("operator and round-shape specs are registered and listed", "[operators][spec]") {
  CHECK(load_model("pyramid:cube:3", mesh_catalogue()).fvector() == FVector{9, 20, 18, 7});
  CHECK(load_model("dual:tesseract", mesh_catalogue()).fvector() == FVector{8, 24, 32, 16});
  CHECK(load_model("dual:dual:tesseract", mesh_catalogue()).fvector() == make_cube(4).fvector());
  CHECK(load_model("antiprism:5", mesh_catalogue()).fvector() == FVector{10, 20, 12});
  CHECK(load_model("Duocylinder:1.5,6", mesh_catalogue()).fvector() == FVector{36, 72, 48, 12});
  CHECK(load_model("cubinder:1,6", mesh_catalogue()).fvector() ==
        make_product(make_polygon(6), make_cube(2)).fvector());
  CHECK(load_model("cylinder:1,6", mesh_catalogue()).fvector() == FVector{12, 18, 8});
  CHECK(signed_volume(load_model("cone:sphere:1,16", mesh_catalogue())) ==
        Approx(signed_volume(make_uv_sphere(1.0, 16)) / 4.0));
  CHECK(signed_volume(load_model("cone:cylinder:2,16", mesh_catalogue())) ==
        Approx(signed_volume(make_cylinder(2.0, 16)) * 2.0 / 4.0));
  CHECK(validate(load_model("spherinder:1,8", mesh_catalogue())).ok());
  for (const char* spec : {"pyramid:cube:3", "dual:24-cell", "antiprism:4", "sphere:1,8",
                           "extrude:x.obj", "spin:x.obj,8", "cone:sphere:1,8"})
    CHECK(is_builtin_spec(spec, mesh_catalogue()));
  std::vector<std::string> usages;
  for (const auto& info : builtin_list(mesh_catalogue())) usages.push_back(info.spec);
  for (const char* usage :
       {"pyramid:MODEL", "cone:MODEL", "dual:MODEL", "antiprism:N", "cylinder:R,N", "sphere:R,N",
        "duocylinder:R,N", "cubinder:R,N", "spherinder:R,N", "extrude:FILE", "spin:FILE,STEPS"})
    CHECK(std::find(usages.begin(), usages.end(), usage) != usages.end());
  CHECK_THROWS_AS(load_model("pyramid:nothing", mesh_catalogue()), InputError);
  CHECK_THROWS_AS(load_model("antiprism:x", mesh_catalogue()), InputError);
}
