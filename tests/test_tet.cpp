// Tetrahedral meshes (tetrahedralize/tet_mesh.hpp) and the tetrahedral slicer (tet_slice.hpp).
// Oracles: analytic tetrahedron counts, the cells' own volumes (simplicial chains of the
// complex), the face triangulation (conformity), the CW section path and the B-spline
// cross-section formula.
#include <sys/wait.h>
#include <catch2/catch.hpp>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>

#include "cw4d/complex/builder.hpp"
#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/off_io.hpp"
#include "cw4d/complex/operators.hpp"
#include "cw4d/complex/validate.hpp"
#include "cw4d/section/hyperplane.hpp"
#include "cw4d/section/section.hpp"
#include "cw4d/section/triangulate.hpp"
#include "cw4d/tetrahedralize/catalogue.hpp"
#include "cw4d/tetrahedralize/tet_io.hpp"
#include "cw4d/tetrahedralize/tet_mesh.hpp"
#include "cw4d/tetrahedralize/tet_slice.hpp"
#include "support/oracle.hpp"
#include "support/temp_dir.hpp"

using namespace cw4d;

namespace {

struct Shape {
  std::string name;
  Complex complex;
};

// An L-shaped prism (area 3 x height 1, volume 3) with two non-convex hexagonal faces.
const char* kLPrismObj =
    "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\n"
    "v 0 0 1\nv 2 0 1\nv 2 1 1\nv 1 1 1\nv 1 2 1\nv 0 2 1\n"
    "f 6 5 4 3 2 1\nf 7 8 9 10 11 12\n"
    "f 1 2 8 7\nf 2 3 9 8\nf 3 4 10 9\nf 4 5 11 10\nf 5 6 12 11\nf 6 1 7 12\n";

const std::vector<Shape>& convex_shapes() {
  static const std::vector<Shape> shapes = [] {
    std::vector<Shape> s;
    for (std::string spec : {"5-cell",
                             "tesseract",
                             "16-cell",
                             "24-cell",
                             "120-cell",
                             "600-cell",
                             "duoprism:3,4",
                             "duoprism:5,7",
                             "prism:simplex:3",
                             "truncated tesseract",
                             "rectified 5-cell",
                             "snub 24-cell",
                             "grand antiprism",
                             "pyramid:cube:3",
                             "duocylinder:1,9",
                             "spherinder:1,8",
                             "cubinder:1,6",
                             "glome:1,3",
                             "prism:antiprism:5",
                             "cone:sphere:1,6",
                             "dual:24-cell",
                             "dual:tesseract",
                             "product:polygon:5*polygon:8",
                             "wythoff:x4o3o3o",
                             "omnitruncated tesseract",
                             "cantellated 5-cell",
                             "runcinated tesseract",
                             "cantitruncated 24-cell",
                             "prism:orthoplex:3",
                             "prism:cube:3"})
      s.push_back({spec, load_model(spec, default_catalogue())});
    // Models made from mesh files: the prism over a cube, and a cube in x >= 1 spun in 7 steps.
    static const test::TempDir dir("tet_shapes");
    dir.write("cube.obj", test::read_text(std::string(CW4D_TEST_DATA_DIR) + "/cube.obj"));
    std::string shifted;
    std::istringstream in(test::read_text(std::string(CW4D_TEST_DATA_DIR) + "/cube.obj"));
    for (std::string line; std::getline(in, line);) {
      if (line.rfind("v ", 0) == 0) {
        std::istringstream ls(line.substr(2));
        double x, y, z;
        ls >> x >> y >> z;
        line = "v " + std::to_string(x + 2.0) + " " + std::to_string(y) + " " + std::to_string(z);
      }
      shifted += line + "\n";
    }
    dir.write("shifted.obj", shifted);
    s.push_back({"extrude:cube.obj",
                 load_model("extrude:" + (dir / "cube.obj").string(), default_catalogue())});
    s.push_back({"spin:shifted.obj,7",
                 load_model("spin:" + (dir / "shifted.obj").string() + ",7", default_catalogue())});
    return s;
  }();
  return shapes;
}

const Shape& l_prism() {
  static const Shape shape = [] {
    static const test::TempDir dir("tet_lprism");
    dir.write("l.obj", kLPrismObj);
    return Shape{"extrude:L",
                 load_model("extrude:" + (dir / "l.obj").string(), default_catalogue())};
  }();
  return shape;
}

double diameter(const Complex& c) {
  return 2.0 * max_radius(c);
}

Eigen::Vector4d random_unit(std::mt19937& rng) {
  std::normal_distribution<double> g;
  Eigen::Vector4d v(g(rng), g(rng), g(rng), g(rng));
  return v.normalized();
}

// Signed 3-volume of cell `c` as the chain of simplices of the complex (independent of the
// tetrahedralization; valid for non-convex cells too).
double cell_volume_chain(const Complex& m, std::uint32_t c) {
  const Eigen::Vector4d n = m.facet_normals().col(c);
  const auto& p = m.positions();
  double v = 0.0;
  for_each_simplex(m, 3, c, [&](std::span<const std::uint32_t> s, int sign) {
    Eigen::Matrix4d a;
    a << n, p.col(s[1]) - p.col(s[0]), p.col(s[2]) - p.col(s[0]), p.col(s[3]) - p.col(s[0]);
    v += sign * a.determinant();
  });
  return std::abs(v) / 6.0;
}

using Tri = std::array<std::uint32_t, 3>;
Tri sorted(Tri t) {
  std::sort(t.begin(), t.end());
  return t;
}
// +1 / -1: whether t is an even / odd permutation of sorted(t).
int parity(Tri t) {
  int swaps = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = i + 1; j < 3; ++j)
      if (t[static_cast<std::size_t>(i)] > t[static_cast<std::size_t>(j)]) ++swaps;
  return swaps % 2 == 0 ? 1 : -1;
}

// Every property of a tetrahedralization, against the complex.
void check_mesh(const Shape& shape, const TetMesh& mesh) {
  INFO(shape.name);
  const Complex& m = shape.complex;
  const double scale = diameter(m);
  REQUIRE(mesh.tet_cell.size() == mesh.size());
  REQUIRE(static_cast<std::size_t>(mesh.corner_uvw.cols()) == 4 * mesh.size());
  REQUIRE(mesh.cell_count() == m.count(3));
  REQUIRE((mesh.positions.leftCols(static_cast<Eigen::Index>(m.count(0))) - m.positions()).norm() ==
          0.0);

  // No tetrahedron degenerate or inverted: positive volume w.r.t. the cell's outward normal,
  // and each lies in its cell's hyperplane.
  std::vector<double> per_cell(m.count(3), 0.0);
  for (std::size_t t = 0; t < mesh.size(); ++t) {
    const double v = mesh.tet_signed_volume(t);
    REQUIRE(v > 1e-9 * std::pow(scale, 3));
    per_cell[mesh.tet_cell[t]] += v;
    const std::uint32_t c = mesh.tet_cell[t];
    const Eigen::Vector4d n = m.facet_normals().col(c);
    const double level = n.dot(m.position(m.first_vertex(3, c)));
    for (int k = 0; k < 4; ++k)
      REQUIRE(std::abs(n.dot(mesh.corner_position(t, k)) - level) <= 1e-9 * scale);
  }
  // The tetrahedra of each cell sum to the cell's 3-volume.
  for (std::uint32_t c = 0; c < m.count(3); ++c) {
    INFO("cell " << c);
    REQUIRE(per_cell[c] == Approx(cell_volume_chain(m, c)).epsilon(1e-9));
  }

  // Conformity: within a cell every triangle of its tetrahedra appears twice with opposite
  // orientations, except the boundary ones, which are exactly the cell's face triangles (the
  // one global triangulation) with the cell's orientation; so neighbouring cells share them.
  const auto faces = triangulate_faces(m);
  std::map<Tri, int> boundary_of_cell;
  std::size_t t0 = 0;
  while (t0 < mesh.size()) {
    const std::uint32_t c = mesh.tet_cell[t0];
    std::map<Tri, int> count;  // sorted triangle -> sum of orientations
    std::map<Tri, int> seen;
    std::size_t t1 = t0;
    for (; t1 < mesh.size() && mesh.tet_cell[t1] == c; ++t1) {
      const auto& v = mesh.tets[t1];
      // Chain boundary of [v0 v1 v2 v3] (outward tetrahedra are positive chains of the cell).
      const std::array<std::pair<Tri, int>, 4> fs{{{{v[1], v[2], v[3]}, 1},
                                                   {{v[0], v[2], v[3]}, -1},
                                                   {{v[0], v[1], v[3]}, 1},
                                                   {{v[0], v[1], v[2]}, -1}}};
      for (const auto& [tri, s] : fs) {
        count[sorted(tri)] += s * parity(tri);
        ++seen[sorted(tri)];
      }
    }
    std::map<Tri, int> expect;
    const auto ids = m.boundary(3).ids(c);
    const auto signs = m.boundary(3).signs(c);
    for (std::size_t j = 0; j < ids.size(); ++j)
      for (const auto& tri : faces[ids[j]]) expect[sorted(tri)] += signs[j] * parity(tri);
    for (const auto& [tri, n] : seen) {
      INFO("cell " << c << " triangle " << tri[0] << " " << tri[1] << " " << tri[2]);
      const auto it = expect.find(tri);
      if (it == expect.end()) {
        REQUIRE(n == 2);
        REQUIRE(count[tri] == 0);
      } else {
        REQUIRE(n == 1);
        REQUIRE(count[tri] == it->second);
      }
    }
    for (const auto& [tri, s] : expect) REQUIRE(seen.count(tri) == 1);
    t0 = t1;
  }

  // Box UVW lies in [0,1]^3 (parametric mappings are checked separately).
  for (Eigen::Index i = 0; i < mesh.corner_uvw.cols(); ++i) {
    REQUIRE(mesh.corner_uvw.col(i).minCoeff() >= -1e-12);
    REQUIRE(mesh.corner_uvw.col(i).maxCoeff() <= 1.0 + 1e-12);
  }
}

double cw_area(const Section& s) {
  double a = 0.0;
  for (std::uint32_t f = 0; f < s.complex.count(2); ++f) a += element_volume(s.complex, 2, f);
  return a;
}

std::size_t cw_triangles(const Section& s) {
  std::size_t n = 0;
  for (std::uint32_t f = 0; f < s.complex.count(2); ++f) n += s.complex.boundary(2).row_size(f) - 2;
  return n;
}

}  // namespace

TEST_CASE("tet: counts of the regular polychora", "[tet]") {
  struct Expect {
    std::string spec;
    std::size_t tets;
  };
  // 5-cell and 16-cell: one tetrahedron per cell. Tesseract: 8 cubes x 5 (the 5-tetrahedron
  // split with a global vertex parity). 24-cell: octahedra coned from a vertex over the 4 faces
  // away from it. 120-cell: dodecahedra coned over the 9 pentagons away from the apex, 3 each =
  // 27. 600-cell: 600 tetrahedra.
  for (const Expect& e :
       {Expect{"5-cell", 5}, Expect{"16-cell", 16}, Expect{"tesseract", 40}, Expect{"24-cell", 96},
        Expect{"120-cell", 3240}, Expect{"600-cell", 600}}) {
    INFO(e.spec);
    const Complex m = load_model(e.spec, default_catalogue());
    TetStats stats;
    const TetMesh mesh = tetrahedralize(m, {}, &stats);
    CHECK(mesh.size() == e.tets);
    CHECK(stats.tetgen_cells == 0);
    CHECK(stats.steiner_points == 0);
    std::vector<std::size_t> per_cell(m.count(3), 0);
    for (auto c : mesh.tet_cell) ++per_cell[c];
    if (e.spec == "120-cell") CHECK(*std::max_element(per_cell.begin(), per_cell.end()) <= 27);
    if (e.spec == "tesseract") CHECK(stats.cube_split_cells == 8);
  }
  // Without the cube split the tesseract's cubes are coned: 6 each.
  TetOptions no_split;
  no_split.five_tet_cubes = false;
  CHECK(tetrahedralize(load_model("tesseract", default_catalogue()), no_split).size() == 48);
}

TEST_CASE("tet: every convex shape tetrahedralizes into exact, conforming, outward tetrahedra",
          "[tet]") {
  for (const Shape& shape : convex_shapes()) {
    TetStats stats;
    const TetMesh mesh = tetrahedralize(shape.complex, {}, &stats);
    CHECK(stats.tetgen_cells == 0);
    check_mesh(shape, mesh);
    // Convex cells: the oracle element_volume agrees too.
    for (std::uint32_t c = 0; c < shape.complex.count(3); c += 7) {
      double sum = 0.0;
      for (std::size_t t = 0; t < mesh.size(); ++t)
        if (mesh.tet_cell[t] == c) sum += mesh.tet_volume(t);
      CHECK(sum == Approx(element_volume(shape.complex, 3, c)).epsilon(1e-9));
    }
  }
}

TEST_CASE("tet: non-convex cells go through TetGen and stay conforming", "[tet][tetgen]") {
  const Shape& shape = l_prism();
  TetStats stats;
  const TetMesh mesh = tetrahedralize(shape.complex, {}, &stats);
  // The two L-shaped solids and the two prisms over the L faces are not convex.
  CHECK(stats.tetgen_cells == 4);
  check_mesh(shape, mesh);
  double total = 0.0;
  for (std::size_t t = 0; t < mesh.size(); ++t) total += mesh.tet_volume(t);
  // Boundary 3-volume: two L solids (3 each) + prisms over the L faces (3 x 2 each) + the six
  // rectangles x [-1, 1] (perimeter 8 x height 1 x 2).
  CHECK(total == Approx(3 + 3 + 6 + 6 + 16).epsilon(1e-12));
}

// The great dodecahedron {5,5/2}: 12 convex pentagons through the five neighbours of each
// icosahedron vertex; they pass through each other.
Complex great_dodecahedron() {
  const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> v;
  for (double a : {1.0, -1.0})
    for (double b : {phi, -phi}) {
      v.emplace_back(0, a, b);
      v.emplace_back(a, b, 0);
      v.emplace_back(b, 0, a);
    }
  ComplexSoup soup;
  soup.ambient_dim = 3;
  soup.positions.resize(3, 12);
  for (int i = 0; i < 12; ++i) soup.positions.col(i) = v[static_cast<std::size_t>(i)];
  for (std::size_t i = 0; i < 12; ++i) {
    const Eigen::Vector3d c = v[i].normalized();
    const Eigen::Vector3d u = c.cross(Eigen::Vector3d(0.3, 0.5, 0.7)).normalized(), w = c.cross(u);
    std::vector<std::uint32_t> ring;
    for (std::size_t j = 0; j < 12; ++j)
      if (std::abs((v[i] - v[j]).squaredNorm() - 4.0) < 1e-9)
        ring.push_back(static_cast<std::uint32_t>(j));
    std::sort(ring.begin(), ring.end(), [&](auto a, auto b) {
      return std::atan2(v[a].dot(w), v[a].dot(u)) < std::atan2(v[b].dot(w), v[b].dot(u));
    });
    soup.faces.push_back(ring);
  }
  return build_complex(soup);
}

// Schönhardt's twisted prism: two triangles, the top one turned by 30 degrees, each side quad
// split along its reflex diagonal. No tetrahedralization without a Steiner point exists.
Complex schoenhardt() {
  ComplexSoup soup;
  soup.ambient_dim = 3;
  soup.positions.resize(3, 6);
  const double pi = std::acos(-1.0);
  for (int i = 0; i < 3; ++i) {
    const double a = 2 * pi * i / 3, b = a + pi / 6;
    soup.positions.col(i) = Eigen::Vector3d(std::cos(a), std::sin(a), 0);
    soup.positions.col(i + 3) = Eigen::Vector3d(std::cos(b), std::sin(b), 1);
  }
  const Eigen::Vector3d g = soup.positions.rowwise().mean();
  soup.faces = {{0, 2, 1}, {3, 4, 5}};
  for (std::uint32_t i = 0; i < 3; ++i) {
    const std::uint32_t b0 = i, b1 = (i + 1) % 3, t0 = i + 3, t1 = (i + 1) % 3 + 3;
    // Split along b0-t1 when t0 lies outside the plane of (b0, b1, t1): then b0-t1 is a reflex
    // edge; otherwise the other diagonal is the reflex one.
    const Eigen::Vector3d a = soup.positions.col(b0), b = soup.positions.col(b1),
                          c = soup.positions.col(t1);
    Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.dot(a - g) < 0) n = -n;
    if (n.dot(soup.positions.col(t0) - a) > 0) {
      soup.faces.push_back({b0, b1, t1});
      soup.faces.push_back({b0, t1, t0});
    } else {
      soup.faces.push_back({b0, b1, t0});
      soup.faces.push_back({b1, t1, t0});
    }
  }
  return build_complex(soup);
}

TEST_CASE("tet: a cell that needs an interior Steiner point (Schönhardt prism)", "[tet][tetgen]") {
  const Shape shape{"prism:schoenhardt", make_prism(schoenhardt(), 2.0)};
  REQUIRE(validate(shape.complex).ok());
  TetStats stats;
  const TetMesh mesh = tetrahedralize(shape.complex, {}, &stats);
  CHECK(stats.tetgen_cells >= 2);  // the two twisted prisms (the side prisms may be convex)
  CHECK(stats.steiner_points >= 2);
  CHECK(static_cast<std::size_t>(mesh.positions.cols()) ==
        shape.complex.count(0) + stats.steiner_points);
  check_mesh(shape, mesh);
  std::mt19937 rng(99);
  for (int trial = 0; trial < 100; ++trial) {
    const Eigen::Vector4d u = random_unit(rng);
    const Eigen::RowVectorXd h = u.transpose() * shape.complex.positions();
    const double d = std::uniform_real_distribution<double>(h.minCoeff(), h.maxCoeff())(rng);
    INFO("trial " << trial);
    CHECK(slice_tets(mesh, Hyperplane::from(u, d)).volume() ==
          Approx(test::bspline_section_volume(shape.complex, u, d)).epsilon(1e-9).margin(1e-12));
  }
}

TEST_CASE("tet: TetGen failures become MeshingError", "[tet][tetgen]") {
  // The prism over the great dodecahedron: its two great-dodecahedron cells self-intersect.
  const Complex m = make_prism(great_dodecahedron(), 2.0);
  REQUIRE(validate(m).ok());
  try {
    (void)tetrahedralize(m);
    FAIL("no error");
  } catch (const MeshingError& e) {
    INFO(e.what());
    CHECK(e.rank() == 3);
    REQUIRE(e.ids().size() == 1);
    CHECK(e.ids()[0] < m.count(3));
    CHECK(m.vertices_of(3, e.ids()[0]).size() == 12);  // a great dodecahedron
    CHECK(e.tetgen_code() == 3);  // TetGen's self-intersection code (found by its -d pass)
    CHECK(std::string(e.what()).find("intersects itself") != std::string::npos);
    CHECK(std::string(e.what()).find("cell " + std::to_string(e.ids()[0])) != std::string::npos);
  }
  CHECK_THROWS_AS(tetrahedralize(make_cube(3)), InputError);
  CHECK_THROWS_AS(tetrahedralize(make_cube(5)), InputError);
}

TEST_CASE("tet: a model whose tables name missing elements is refused, not read", "[tet]") {
  // Each defect also fails validate().
  Complex face_beyond = make_cube(4);
  face_beyond.boundary_mut(2).ids_mut(0)[0] = 999999u;
  Complex cell_beyond = make_cube(4);
  cell_beyond.boundary_mut(3).ids_mut(2)[1] = 999999u;
  for (const Complex* c : {&face_beyond, &cell_beyond}) {
    REQUIRE_FALSE(validate(*c).ok());
    CHECK_THROWS_AS(tetrahedralize(*c), InputError);
  }
  CHECK_THROWS_WITH(tetrahedralize(face_beyond), Catch::Contains("rank-2 boundary table"));
  CHECK_THROWS_WITH(tetrahedralize(cell_beyond), Catch::Contains("rank-3 boundary table"));
}

TEST_CASE("tet: box UVW maps each cell onto [0,1]^3 affinely", "[tet][uvw]") {
  const Complex m = load_model("tesseract", default_catalogue());
  const TetMesh mesh = tetrahedralize(m);
  for (std::uint32_t c = 0; c < m.count(3); ++c) {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(2), hi = Eigen::Vector3d::Constant(-1);
    for (std::size_t t = 0; t < mesh.size(); ++t) {
      if (mesh.tet_cell[t] != c) continue;
      for (int k = 0; k < 4; ++k) {
        lo = lo.cwiseMin(mesh.corner_uvw_of(t, k));
        hi = hi.cwiseMax(mesh.corner_uvw_of(t, k));
        // A cube's corners map to corners of the unit cube.
        for (int i = 0; i < 3; ++i) {
          const double u = mesh.corner_uvw_of(t, k)(i);
          CHECK((std::abs(u) < 1e-12 || std::abs(u - 1) < 1e-12));
        }
      }
    }
    CHECK(lo.norm() < 1e-12);
    CHECK((hi - Eigen::Vector3d::Ones()).norm() < 1e-12);
  }
}

TEST_CASE("tet: parametric UVW of the glome, spherinder and duocylinder", "[tet][uvw]") {
  REQUIRE(uvw_mapping_for_spec("glome:2,3")->kind == UvwMapping::Kind::Glome);
  REQUIRE(uvw_mapping_for_spec("glome:2,3")->radius == 2.0);
  REQUIRE(uvw_mapping_for_spec("Spherinder:1.5,8")->kind == UvwMapping::Kind::Spherinder);
  REQUIRE(uvw_mapping_for_spec("duocylinder:1,12")->kind == UvwMapping::Kind::Duocylinder);
  REQUIRE_FALSE(uvw_mapping_for_spec("tesseract").has_value());
  CHECK_THROWS_AS(uvw_mapping_for_spec("glome:x,3"), InputError);

  for (std::string spec : {"glome:2,4", "spherinder:1.5,8", "duocylinder:1,12"}) {
    INFO(spec);
    const Complex m = load_model(spec, default_catalogue());
    TetOptions opt;
    opt.uvw = *uvw_mapping_for_spec(spec);
    const TetMesh mesh = tetrahedralize(m, opt);
    check_mesh({spec, m}, tetrahedralize(m));
    std::size_t parametric = 0;
    for (std::size_t t = 0; t < mesh.size(); ++t) {
      const Eigen::Vector4d n = mesh.tet_normal(t);
      std::array<bool, 3> periodic{};
      bool has_parameters = true;
      for (int k = 0; k < 4; ++k) {
        const auto expect = parametric_uvw(opt.uvw, mesh.corner_position(t, k), n, periodic);
        if (!expect) {  // spherinder caps: box mapping
          has_parameters = false;
          continue;
        }
        ++parametric;
        const Eigen::Vector3d got = mesh.corner_uvw_of(t, k);
        for (int i = 0; i < 3; ++i) {
          const double e = (*expect)(i);
          if (std::isnan(e)) continue;  // an angle on its axis: taken from the other corners
          double diff = got(i) - e;
          if (periodic[static_cast<std::size_t>(i)]) diff -= std::round(diff);  // unwrapped
          REQUIRE(std::abs(diff) < 1e-12);
        }
      }
      if (!has_parameters) continue;
      // Unwrapped: the angles of one tetrahedron's corners are within half a turn of each other.
      const auto block = mesh.corner_uvw.middleCols(static_cast<Eigen::Index>(4 * t), 4);
      for (int i = 0; i < 3; ++i)
        if (periodic[static_cast<std::size_t>(i)])
          REQUIRE(block.row(i).maxCoeff() - block.row(i).minCoeff() <= 0.5 + 1e-12);
    }
    CHECK(parametric > mesh.size());
  }
  // Glome: the third parameter is the Hopf angle a / (pi/2): 0 on the circle z = w = 0.
  std::array<bool, 3> periodic{};
  const UvwMapping glome{UvwMapping::Kind::Glome, 2.0};
  const auto u =
      parametric_uvw(glome, Eigen::Vector4d(0, 2, 0, 0), Eigen::Vector4d(0, 1, 0, 0), periodic);
  REQUIRE(u);
  CHECK((*u)(0) == Approx(0.25));
  CHECK(std::isnan((*u)(1)));
  CHECK((*u)(2) == Approx(0.0).margin(1e-15));
}

TEST_CASE("tet slicer: the 16-case table", "[tet][slice]") {
  for (int mask = 0; mask < 16; ++mask) {
    const TetCutCase& c = kTetCutTable[static_cast<std::size_t>(mask)];
    const int positives = __builtin_popcount(static_cast<unsigned>(mask));
    CHECK(c.count == (positives == 0 || positives == 4 ? 0 : positives == 2 ? 4 : 3));
    for (int e = 0; e < c.count; ++e) {
      const auto [a, b] = c.edges[static_cast<std::size_t>(e)];
      CHECK(((mask >> a) & 1) != ((mask >> b) & 1));  // every cut edge crosses the plane
      if (c.count == 4) {  // consecutive quad corners share a tetrahedron vertex
        const auto [a2, b2] = c.edges[static_cast<std::size_t>((e + 1) % 4)];
        CHECK((a == a2 || b == b2));
      }
    }
  }
}

namespace {

struct Totals {
  std::size_t cw = 0, tet = 0, planes = 0;
};

void compare_paths(const Shape& shape, const TetMesh& mesh, const Hyperplane& plane, Totals& totals,
                   const std::string& what) {
  INFO(shape.name << ": " << what << " n = (" << plane.normal.transpose()
                  << "), d = " << plane.offset);
  const double scale = diameter(shape.complex);
  const Section cw = section(shape.complex, plane);
  const TetSection ts = slice_tets(mesh, plane);
  const double cw_volume = cw.empty() ? 0.0 : signed_volume(cw.complex);
  CHECK(ts.volume() == Approx(cw_volume).epsilon(1e-9).margin(1e-11 * std::pow(scale, 3)));
  CHECK(ts.area() ==
        Approx(cw.empty() ? 0.0 : cw_area(cw)).epsilon(1e-9).margin(1e-11 * std::pow(scale, 2)));
  // The same polygons, in more pieces: a k-gon needs at least k - 2 triangles.
  CHECK(ts.triangle_count() >= cw_triangles(cw));
  totals.cw += cw_triangles(cw);
  totals.tet += ts.triangle_count();
  ++totals.planes;
  // Every slice corner lies on the plane and its normal is unit.
  for (Eigen::Index i = 0; i < ts.positions.cols(); ++i) {
    REQUIRE(std::abs(plane.signed_distance(ts.frame.lift(ts.positions.col(i)))) <= 1e-9 * scale);
    REQUIRE(ts.normals.col(i).norm() == Approx(1.0));
  }
}

}  // namespace

TEST_CASE("tet slicer: same section volume and area as the CW path", "[tet][slice]") {
  std::mt19937 rng(5150);
  Totals all;
  std::vector<Shape> shapes = convex_shapes();
  for (const Shape& shape : shapes) {
    const TetMesh mesh = tetrahedralize(shape.complex);
    Totals totals;
    const int trials = shape.complex.count(0) > 300 ? 25 : 60;
    for (int trial = 0; trial < trials; ++trial) {
      const Eigen::Vector4d u = random_unit(rng);
      const Eigen::RowVectorXd h = u.transpose() * shape.complex.positions();
      const double lo = h.minCoeff(), hi = h.maxCoeff();
      const double d =
          std::uniform_real_distribution<double>(lo - 0.05 * (hi - lo), hi + 0.05 * (hi - lo))(rng);
      compare_paths(shape, mesh, Hyperplane::from(u, d), totals, "random");
    }
    // Degenerate planes: through a vertex, and axis planes through the vertices (w = const
    // contains whole cells of the tesseract).
    for (int trial = 0; trial < 10; ++trial) {
      const auto v = std::uniform_int_distribution<std::uint32_t>(
          0, static_cast<std::uint32_t>(shape.complex.count(0) - 1))(rng);
      const Eigen::Vector4d u = random_unit(rng);
      compare_paths(shape, mesh, Hyperplane::from(u, u.dot(shape.complex.position(v))), totals,
                    "through a vertex");
      const Eigen::Vector4d axis = Eigen::Vector4d::Unit(trial % 4);
      compare_paths(shape, mesh, Hyperplane::from(axis, axis.dot(shape.complex.position(v))),
                    totals, "axis plane");
      // Lattice normals from {-1,0,1}^4: planes containing edges, faces and the diagonals the
      // tetrahedralization added (e.g. the inner faces of the tesseract's 5-tetrahedron cubes).
      Eigen::Vector4d lattice = Eigen::Vector4d::Zero();
      while (lattice.isZero())
        for (int i = 0; i < 4; ++i) lattice(i) = std::uniform_int_distribution<int>(-1, 1)(rng);
      const Eigen::Vector4d ln = lattice.normalized();
      compare_paths(shape, mesh, Hyperplane::from(ln, ln.dot(shape.complex.position(v))), totals,
                    "lattice plane");
    }
    std::printf("tet slicer %-22s %4zu planes: CW %7zu triangles, tet %7zu (x%.2f)\n",
                shape.name.c_str(), totals.planes, totals.cw, totals.tet,
                totals.cw ? static_cast<double>(totals.tet) / static_cast<double>(totals.cw) : 0.0);
    all.cw += totals.cw;
    all.tet += totals.tet;
    all.planes += totals.planes;
  }
  std::printf("tet slicer, all shapes, %zu planes: CW %zu triangles, tet %zu (x%.2f)\n", all.planes,
              all.cw, all.tet, static_cast<double>(all.tet) / static_cast<double>(all.cw));
  CHECK(all.tet > all.cw);
}

TEST_CASE("tet slicer: the non-convex L prism against the B-spline oracle",
          "[tet][slice][tetgen]") {
  const Shape& shape = l_prism();
  const TetMesh mesh = tetrahedralize(shape.complex);
  std::mt19937 rng(77);
  for (int trial = 0; trial < 100; ++trial) {
    const Eigen::Vector4d u = random_unit(rng);
    const Eigen::RowVectorXd h = u.transpose() * shape.complex.positions();
    const double d = std::uniform_real_distribution<double>(h.minCoeff(), h.maxCoeff())(rng);
    const TetSection ts = slice_tets(mesh, Hyperplane::from(u, d));
    INFO("trial " << trial);
    CHECK(ts.volume() ==
          Approx(test::bspline_section_volume(shape.complex, u, d)).epsilon(1e-9).margin(1e-12));
  }
}

TEST_CASE("tet slicer: interpolated UVW is the cell's box map of the slice point",
          "[tet][slice][uvw]") {
  const Complex m = load_model("24-cell", default_catalogue());
  const TetMesh mesh = tetrahedralize(m);
  // The box map of each cell, recomputed here from the cell's vertices.
  struct Box {
    Eigen::MatrixXd basis;
    Eigen::Vector3d lo, extent;
  };
  std::vector<Box> boxes;
  for (std::uint32_t c = 0; c < m.count(3); ++c) {
    Box b;
    b.basis = hyperplane_basis(Eigen::VectorXd(m.facet_normals().col(c)));
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
    for (auto v : m.vertices_of(3, c)) {
      const Eigen::Vector3d y = b.basis.transpose() * m.position(v);
      lo = lo.cwiseMin(y);
      hi = hi.cwiseMax(y);
    }
    b.lo = lo;
    b.extent = hi - lo;
    boxes.push_back(b);
  }
  std::mt19937 rng(31);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Vector4d u = random_unit(rng);
    const TetSection ts = slice_tets(
        mesh, Hyperplane::from(u, std::uniform_real_distribution<double>(-1.5, 1.5)(rng)));
    for (std::size_t i = 0; i < ts.triangle_count(); ++i)
      for (int k = 0; k < 3; ++k) {
        const auto col = static_cast<Eigen::Index>(3 * i + static_cast<std::size_t>(k));
        const Box& b = boxes[ts.cell[i]];
        const Eigen::Vector3d y = b.basis.transpose() * ts.frame.lift(ts.positions.col(col));
        const Eigen::Vector3d expect = (y - b.lo).cwiseQuotient(b.extent);
        REQUIRE((ts.uvw.col(col) - expect).norm() < 1e-9);
        // The normal is the cell's outward normal projected into the plane.
        const Eigen::Vector3d pn =
            (ts.frame.basis.transpose() * m.facet_normals().col(ts.cell[i])).normalized();
        REQUIRE((ts.normals.col(col) - pn).norm() < 1e-9);
      }
  }
}

TEST_CASE("tet slicer: transforms, the Section view, and plane misses", "[tet][slice]") {
  const Complex m = load_model("tesseract", default_catalogue());
  const TetMesh mesh = tetrahedralize(m);
  const AffineTransform xf = AffineTransform::translation(Eigen::Vector4d(0.5, 0, 0, 0.25)) *
                             AffineTransform::rotation(4, 0, 3, 0.3);
  const Hyperplane plane = Hyperplane::from(Eigen::Vector4d(0.2, -0.4, 0.1, 1.0), 0.4);
  const TetSection ts = slice_tets(mesh, plane, xf);
  const Section cw = section(m, plane, xf);
  CHECK(ts.volume() == Approx(signed_volume(cw.complex)).epsilon(1e-12));
  const Section as_section = to_section(ts, m);
  for (std::uint32_t v = 0; v < as_section.complex.count(0); ++v) {
    const VertexSource& src = as_section.vertex_source[v];
    if (src.rank != 1 || src.element == no_index) continue;
    const auto e = m.edge(src.element);  // a model edge: the vertex is its point at t
    const Eigen::Vector4d x = xf.apply((1 - src.t) * m.position(e[0]) + src.t * m.position(e[1]));
    REQUIRE((as_section.world_position(v) - x).norm() < 1e-12);
  }
  CHECK(signed_volume(as_section.complex) == Approx(ts.volume()).epsilon(1e-12));
  CHECK(as_section.complex.count(2) == ts.triangle_count());
  // Closed surface of welded vertices: V - E + F = 2.
  const auto f = as_section.complex.fvector();
  CHECK(static_cast<long>(f[0]) - static_cast<long>(f[1]) + static_cast<long>(f[2]) == 2);
  CHECK(slice_tets(mesh, Hyperplane::from(Eigen::Vector4d(0, 0, 0, 1), 5.0)).empty());
  CHECK_THROWS_AS(slice_tets(mesh, Hyperplane::from(Eigen::Vector3d(0, 0, 1), 0.0)), InputError);
  // A plane containing a facet returns that facet (like the CW path): the cube w = 1, volume 8.
  CHECK(slice_tets(mesh, Hyperplane::from(Eigen::Vector4d(0, 0, 0, 1), 1.0)).volume() ==
        Approx(8.0));
  CHECK(slice_tets(mesh, Hyperplane::from(Eigen::Vector4d(0, 0, 0, 1), -1.0)).volume() ==
        Approx(8.0));
}

TEST_CASE("tet export: .4do, .node/.ele, .bin/.json and .vtu read back", "[tet][export]") {
  const TetMesh mesh = tetrahedralize(load_model("tesseract", default_catalogue()));
  const test::TempDir dir("tet_export");
  // .4do: records in order, zero-based, every t references earlier data.
  write_tet_mesh((dir / "m.4do").string(), mesh);
  {
    std::istringstream in(test::read_text(dir / "m.4do"));
    std::string line;
    std::getline(in, line);
    CHECK(line == "4DO 1");
    std::size_t v = 0, vn = 0, vt = 0, t = 0, c = 0, cell_tets = 0;
    bool tformat = false;
    while (std::getline(in, line)) {
      std::istringstream ls(line);
      std::string key;
      ls >> key;
      if (key == "v") {
        double x[4];
        ls >> x[0] >> x[1] >> x[2] >> x[3];
        for (int i = 0; i < 4; ++i) CHECK(x[i] == mesh.positions(i, static_cast<Eigen::Index>(v)));
        ++v;
      } else if (key == "vn") {
        ++vn;
      } else if (key == "vt") {
        ++vt;
      } else if (key == "tformat") {
        ls >> key;
        CHECK(key == "v/vn/vt");
        tformat = true;
      } else if (key == "t") {
        REQUIRE(tformat);
        for (std::size_t k = 0; k < 4; ++k) {
          std::string corner;
          ls >> corner;
          unsigned a = 0, b = 0, cc = 0;
          REQUIRE(std::sscanf(corner.c_str(), "%u/%u/%u", &a, &b, &cc) == 3);
          CHECK(a == mesh.tets[t][k]);
          CHECK(a < v);
          CHECK(b == mesh.tet_cell[t]);
          CHECK(b < vn);
          CHECK(cc == 4 * t + k);
          CHECK(cc < vt);
        }
        ++t;
      } else if (key == "c") {
        std::size_t id;
        while (ls >> id) {
          CHECK(mesh.tet_cell[id] == c);
          ++cell_tets;
        }
        ++c;
      }
    }
    CHECK(v == 16);
    CHECK(vn == 8);
    CHECK(vt == 160);
    CHECK(t == 40);
    CHECK(c == 8);
    CHECK(cell_tets == 40);
  }
  // TetGen files: both written from either name.
  write_tet_mesh((dir / "m.ele").string(), mesh);
  REQUIRE(dir.exists("m.node"));
  {
    std::istringstream node(test::read_text(dir / "m.node"));
    std::string comment;
    std::getline(node, comment);
    std::size_t n = 0, d = 0, attrs = 0, markers = 0;
    node >> n >> d >> attrs >> markers;
    CHECK(n == 16);
    CHECK(d == 3);
    CHECK(attrs == 1);
    std::istringstream ele(test::read_text(dir / "m.ele"));
    std::getline(ele, comment);
    std::size_t nt = 0, corners = 0;
    ele >> nt >> corners >> attrs;
    CHECK(nt == 40);
    CHECK(corners == 4);
    std::size_t id, a, b, c, e, cell;
    ele >> id >> a >> b >> c >> e >> cell;
    CHECK(id == 0);
    CHECK(std::array<std::size_t, 4>{a, b, c, e} ==
          std::array<std::size_t, 4>{mesh.tets[0][0], mesh.tets[0][1], mesh.tets[0][2],
                                     mesh.tets[0][3]});
    CHECK(cell == mesh.tet_cell[0]);
  }
  // GPU buffer: 192 bytes per tetrahedron, interleaved as the header says.
  write_tet_mesh((dir / "m.json").string(), mesh);
  {
    const std::string bin = test::read_text(dir / "m.bin");
    REQUIRE(bin.size() == 192 * mesh.size());
    const auto header = nlohmann::json::parse(test::read_text(dir / "m.json"));
    CHECK(header["tetrahedra"] == mesh.size());
    CHECK(header["byte_length"] == bin.size());
    CHECK(header["buffer"] == "m.bin");
    CHECK(header["stride_bytes"] == 48);
    for (std::size_t t = 0; t < mesh.size(); t += 7)
      for (int k = 0; k < 4; ++k) {
        float f[12];
        std::memcpy(f, bin.data() + 192 * t + 48 * static_cast<std::size_t>(k), sizeof f);
        for (int i = 0; i < 4; ++i) {
          CHECK(f[i] == static_cast<float>(mesh.corner_position(t, k)(i)));
          CHECK(f[4 + i] == static_cast<float>(mesh.tet_normal(t)(i)));
        }
        for (int i = 0; i < 3; ++i)
          CHECK(f[8 + i] == static_cast<float>(mesh.corner_uvw_of(t, k)(i)));
        CHECK(f[11] == static_cast<float>(mesh.tet_cell[t]));
      }
  }
  // .vtu: counts in the header; ASCII and base64 (VTK's own reader: test_tet_vtk.py).
  for (bool binary : {false, true}) {
    write_tet_mesh((dir / "m.vtu").string(), mesh, binary);
    const std::string vtu = test::read_text(dir / "m.vtu");
    CHECK(vtu.find("NumberOfPoints=\"160\" NumberOfCells=\"40\"") != std::string::npos);
    CHECK((vtu.find("format=\"binary\"") != std::string::npos) == binary);
  }
  // Bad paths: a typed error and nothing left behind.
  CHECK_THROWS_AS(write_tet_mesh((dir / "m.xyz").string(), mesh), InputError);
  const std::size_t before = dir.entries();
  CHECK_THROWS_AS(write_tet_mesh((dir / "missing" / "m.vtu").string(), mesh), IoError);
  CHECK_THROWS_AS(write_tet_mesh((dir / "missing" / "m.bin").string(), mesh), IoError);
  CHECK(dir.entries() == before);
}

TEST_CASE("tet CLI: tetrahedralize and slice --method tet", "[tet][cli]") {
  const test::TempDir dir("tet_cli");
  const std::string exe = CW4D_EXE;
  auto run = [&](const std::string& args) {
    const std::string cmd = exe + " " + args + " > " + (dir / "out.txt").string() + " 2>&1";
    const int status = std::system(cmd.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  CHECK(run("tetrahedralize 24-cell -o " + (dir / "a.4do").string()) == 0);
  CHECK(test::read_text(dir / "out.txt").find("96 tetrahedra") != std::string::npos);
  CHECK(run("tetrahedralize glome:1,3 --uvw param -o " + (dir / "g.bin").string()) == 0);
  CHECK(dir.exists("g.json"));
  CHECK(run("tetrahedralize tesseract --uvw param -o " + (dir / "t.vtu").string()) == 1);
  CHECK(run("tetrahedralize tesseract -o " + (dir / "t.txt").string()) == 1);
  CHECK(run("tetrahedralize cube:3 -o " + (dir / "c.vtu").string()) == 1);
  CHECK(run("tetrahedralize tesseract --binary -o " + (dir / "t.4do").string()) == 1);
  CHECK_FALSE(dir.exists("t.vtu"));
  // Both methods write the same volume.
  const std::string plane = " --normal 0.1,0.2,0.3,1 --offset 0.5 --rotate xw:20 ";
  REQUIRE(run("slice 600-cell" + plane + "--method tet -o " + (dir / "tet.obj").string()) == 0);
  const std::string tet_out = test::read_text(dir / "out.txt");
  REQUIRE(run("slice 600-cell" + plane + "-o " + (dir / "cw.obj").string()) == 0);
  const std::string cw_out = test::read_text(dir / "out.txt");
  const auto volume = [](const std::string& s) { return s.substr(s.find("volume")); };
  CHECK(volume(tet_out).substr(0, 16) == volume(cw_out).substr(0, 16));
  CHECK(run("slice tesseract --normal 0,0,0,1 --offset 0 --method nope -o " +
            (dir / "x.obj").string()) == 1);
  // A cell TetGen rejects: exit 3 (invalid complex) naming the cell, nothing written.
  write_off_file((dir / "gd.4off").string(), make_prism(great_dodecahedron(), 2.0));
  CHECK(run("tetrahedralize " + (dir / "gd.4off").string() + " -o " + (dir / "gd.vtu").string()) ==
        3);
  CHECK(test::read_text(dir / "out.txt").find("intersects itself") != std::string::npos);
  CHECK_FALSE(dir.exists("gd.vtu"));
}

// The Schlegel diagram the .vtu files use as their 3D points: for a convex polytope the images of
// the cells behind the front cell tile the front cell's image, so their 3D volumes add up to it,
// every image keeps its orientation, and exactly one cell faces the eye.
TEST_CASE("Schlegel view: the cells behind the front cell tile its image", "[tet][export]") {
  for (const char* spec : {"tesseract", "5-cell", "24-cell", "120-cell", "600-cell", "duoprism:5,7",
                           "prism:wythoff:x5o3o"}) {
    INFO(spec);
    const TetMesh mesh = tetrahedralize(load_model(spec, default_catalogue()));
    const SchlegelView view = schlegel_view(mesh);
    CHECK((view.basis.transpose() * view.basis - Eigen::Matrix3d::Identity()).norm() < 1e-12);
    CHECK((view.basis.transpose() * view.normal).cwiseAbs().maxCoeff() < 1e-12);
    double front = 0.0, behind = 0.0;
    int front_cells = 0;
    std::vector<int> sign_of_cell(mesh.cell_count(), 0);
    for (std::uint32_t c = 0; c < mesh.cell_count(); ++c) front_cells += view.faces_eye(mesh, c);
    CHECK(front_cells == 1);
    CHECK(view.faces_eye(mesh, view.front_cell));
    for (std::size_t t = 0; t < mesh.size(); ++t) {
      std::array<Eigen::Vector3d, 4> p;
      for (int k = 0; k < 4; ++k) p[k] = view.project(mesh.corner_position(t, k));
      const double v = (p[1] - p[0]).cross(p[2] - p[0]).dot(p[3] - p[0]) / 6.0;
      REQUIRE(v != 0.0);
      // Orientation is the same for all tetrahedra of one cell, opposite for the front cell.
      int& s = sign_of_cell[mesh.tet_cell[t]];
      if (s == 0) s = v > 0 ? 1 : -1;
      CHECK(s == (v > 0 ? 1 : -1));
      (mesh.tet_cell[t] == view.front_cell ? front : behind) += std::abs(v);
    }
    for (std::uint32_t c = 0; c < mesh.cell_count(); ++c)
      if (c != view.front_cell) CHECK(sign_of_cell[c] == -sign_of_cell[view.front_cell]);
    CHECK_THAT(behind, Catch::Matchers::WithinRel(front, 1e-9));
  }
}

TEST_CASE(".vtu points are the Schlegel diagram, every tetrahedron with positive volume",
          "[tet][export]") {
  const TetMesh mesh = tetrahedralize(load_model("24-cell", default_catalogue()));
  const SchlegelView view = schlegel_view(mesh);
  std::istringstream text(vtu_text(mesh));
  std::string all((std::istreambuf_iterator<char>(text)), std::istreambuf_iterator<char>());
  const auto array_values = [&](const std::string& name) {
    const std::size_t at = all.find("Name=\"" + name + "\"");
    REQUIRE(at != std::string::npos);
    const std::size_t open = all.find('>', at) + 1;
    std::istringstream in(all.substr(open, all.find('<', open) - open));
    std::vector<double> v;
    for (double x; in >> x;) v.push_back(x);
    return v;
  };
  const std::vector<double> points = array_values("Points"), pos4 = array_values("position4");
  const std::vector<double> front = array_values("front");
  REQUIRE(points.size() == 12 * mesh.size());
  REQUIRE(pos4.size() == 16 * mesh.size());
  REQUIRE(front.size() == mesh.size());
  double front_volume = 0.0, behind_volume = 0.0;
  for (std::size_t t = 0; t < mesh.size(); ++t) {
    std::array<Eigen::Vector3d, 4> p;
    for (int k = 0; k < 4; ++k) {
      const std::size_t i = 4 * t + static_cast<std::size_t>(k);
      p[k] = Eigen::Vector3d(points[3 * i], points[3 * i + 1], points[3 * i + 2]);
      const Eigen::Vector4d x(pos4[4 * i], pos4[4 * i + 1], pos4[4 * i + 2], pos4[4 * i + 3]);
      CHECK((view.project(x) - p[k]).norm() < 1e-12);  // each point is its corner's image
    }
    const double v = (p[1] - p[0]).cross(p[2] - p[0]).dot(p[3] - p[0]) / 6.0;
    CHECK(v > 0.0);
    (front[t] == 1.0 ? front_volume : behind_volume) += v;
  }
  CHECK_THAT(behind_volume, Catch::Matchers::WithinRel(front_volume, 1e-9));
}
