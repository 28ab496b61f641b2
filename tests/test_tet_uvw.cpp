// The tetrahedral slicer's texture coordinates against the CW path's. A point's UVW is a function
// of its 4D position in its cell (the cell's box map, affine), so on a section the UVW of every
// point of a cut cell is the affine function of its section position that the CW polygon's own
// corners define. Every corner of every tet-path triangle (crossings of model edges, of the
// diagonals the tetrahedralization added, model vertices) must lie in its cell's CW polygon's
// plane and carry that function's value: in the library (tet_section_uvw) and in the OBJ files
// both `cw4d slice` methods write.
#include <sys/wait.h>

#include <catch2/catch.hpp>

#include <Eigen/Dense>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/section/hyperplane.hpp"
#include "cw4d/section/section.hpp"
#include "cw4d/section/uvw.hpp"
#include "cw4d/tetrahedralize/catalogue.hpp"
#include "cw4d/tetrahedralize/tet_mesh.hpp"
#include "cw4d/tetrahedralize/tet_slice.hpp"
#include "support/temp_dir.hpp"

using namespace cw4d;

namespace {

// uvw = M [s, t, 1] on the plane of a cut cell's polygon, (s, t) its coordinates in an
// orthonormal frame of that plane; fitted to the polygon's corners (least squares, exact for
// an affine map).
struct AffineUvw {
  Eigen::Vector3d origin, e1, e2, normal;
  Eigen::Matrix3d m;
  double fit_residual = 0.0;

  static AffineUvw fit(const std::vector<Eigen::Vector3d>& p,
                       const std::vector<Eigen::Vector3d>& u) {
    REQUIRE(p.size() >= 3);
    AffineUvw a;
    a.origin = p[0];
    std::size_t far = 1;
    for (std::size_t i = 1; i < p.size(); ++i)
      if ((p[i] - p[0]).norm() > (p[far] - p[0]).norm()) far = i;
    a.e1 = (p[far] - p[0]).normalized();
    Eigen::Vector3d best = Eigen::Vector3d::Zero();
    for (const auto& q : p) {
      const Eigen::Vector3d r = (q - p[0]) - (q - p[0]).dot(a.e1) * a.e1;
      if (r.norm() > best.norm()) best = r;
    }
    REQUIRE(best.norm() > 1e-6);  // not collinear
    a.e2 = best.normalized();
    a.normal = a.e1.cross(a.e2);
    Eigen::MatrixXd A(p.size(), 3), B(p.size(), 3);
    for (std::size_t i = 0; i < p.size(); ++i) {
      const Eigen::Vector3d d = p[i] - a.origin;
      A.row(static_cast<Eigen::Index>(i)) << d.dot(a.e1), d.dot(a.e2), 1.0;
      B.row(static_cast<Eigen::Index>(i)) = u[i].transpose();
    }
    a.m = A.colPivHouseholderQr().solve(B).transpose();
    a.fit_residual = (A * a.m.transpose() - B).cwiseAbs().maxCoeff();
    return a;
  }
  double off_plane(const Eigen::Vector3d& x) const { return std::abs((x - origin).dot(normal)); }
  Eigen::Vector3d operator()(const Eigen::Vector3d& x) const {
    const Eigen::Vector3d d = x - origin;
    return m * Eigen::Vector3d(d.dot(e1), d.dot(e2), 1.0);
  }
};

// Per cut cell: the affine UVW of the CW path's polygon of that cell.
std::map<std::uint32_t, AffineUvw> cw_maps(const Section& cw, const CornerUvw& cu) {
  std::map<std::uint32_t, std::vector<Eigen::Vector3d>> pts, uvs;
  for (std::uint32_t f = 0; f < cw.complex.count(2); ++f) {
    const auto cycle = cw.complex.face_cycle(f);
    const std::uint32_t cell = cw.source[2][f];
    for (std::size_t j = 0; j < cycle.size(); ++j) {
      pts[cell].push_back(cw.complex.position(cycle[j]));
      uvs[cell].push_back(cu.uvw.col(cu.offset[f] + static_cast<Eigen::Index>(j)).cast<double>());
    }
  }
  std::map<std::uint32_t, AffineUvw> out;
  for (const auto& [cell, p] : pts) out.emplace(cell, AffineUvw::fit(p, uvs[cell]));
  return out;
}

// An OBJ file as cut cells: positions and UVW of the face corners in each `g cell_K` group.
std::map<std::uint32_t, std::pair<std::vector<Eigen::Vector3d>, std::vector<Eigen::Vector3d>>>
read_obj_cells(const std::string& path) {
  std::ifstream in(path);
  REQUIRE(in);
  std::vector<Eigen::Vector3d> v, vt;
  std::map<std::uint32_t, std::pair<std::vector<Eigen::Vector3d>, std::vector<Eigen::Vector3d>>>
      cells;
  std::uint32_t cell = 0;
  bool in_cell = false;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string tag;
    s >> tag;
    if (tag == "v" || tag == "vt") {
      Eigen::Vector3d x;
      s >> x(0) >> x(1) >> x(2);
      (tag == "v" ? v : vt).push_back(x);
    } else if (tag == "g") {
      std::string name;
      s >> name;
      in_cell = name.rfind("cell_", 0) == 0;
      if (in_cell) cell = static_cast<std::uint32_t>(std::stoul(name.substr(5)));
    } else if (tag == "f") {
      REQUIRE(in_cell);
      std::string corner;
      while (s >> corner) {
        // v/vt/vn
        const std::size_t a = corner.find('/');
        REQUIRE(a != std::string::npos);
        const std::size_t b = corner.find('/', a + 1);
        const std::size_t iv = std::stoul(corner.substr(0, a));
        const std::size_t it = std::stoul(corner.substr(a + 1, b - a - 1));
        REQUIRE(iv >= 1);
        REQUIRE(iv <= v.size());
        REQUIRE(it >= 1);
        REQUIRE(it <= vt.size());
        cells[cell].first.push_back(v[iv - 1]);
        cells[cell].second.push_back(vt[it - 1]);
      }
    }
  }
  return cells;
}

}  // namespace

TEST_CASE("tet section UVW equals the CW section's at every corner of every cut cell",
          "[tet][uvw]") {
  std::mt19937 rng(20261202);
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> uniform(-0.4, 0.4);
  for (const char* spec : {"tesseract", "24-cell", "120-cell", "duoprism:5,7",
                           "prism:wythoff:x5o3o", "wythoff:x3x3o4o"}) {
    const Complex model = load_model(spec, default_catalogue());
    const TetMesh mesh = tetrahedralize(model);
    double radius = 0.0;
    for (std::uint32_t v = 0; v < model.count(0); ++v)
      radius = std::max(radius, model.position(v).norm());
    std::size_t corners = 0, diagonal_corners = 0;
    for (int trial = 0; trial < 6; ++trial) {
      Eigen::Vector4d n;
      for (int i = 0; i < 4; ++i) n(i) = gauss(rng);
      const Hyperplane plane = Hyperplane::from(n, uniform(rng) * radius);
      INFO(spec << " plane " << trial);
      const TetSection ts = slice_tets(mesh, plane);
      REQUIRE_FALSE(ts.empty());
      const Section sec = to_section(ts, model);
      const CornerUvw uv = tet_section_uvw(ts, sec);
      const Section cw = section(model, plane);
      REQUIRE((cw.frame.basis - sec.frame.basis).cwiseAbs().maxCoeff() < 1e-12);
      const auto maps = cw_maps(cw, section_uvw(cw, {&model}));
      REQUIRE(uv.offset.size() == sec.complex.count(2) + 1);
      for (std::uint32_t f = 0; f < sec.complex.count(2); ++f) {
        const std::uint32_t cell = sec.source[2][f];
        const auto it = maps.find(cell);
        REQUIRE(it != maps.end());  // the CW path cut the same cell
        REQUIRE(it->second.fit_residual < 1e-5);
        const auto cycle = sec.complex.face_cycle(f);
        for (std::size_t j = 0; j < cycle.size(); ++j) {
          const Eigen::Vector3d p = sec.complex.position(cycle[j]);
          const Eigen::Vector3d got =
              uv.uvw.col(uv.offset[f] + static_cast<Eigen::Index>(j)).cast<double>();
          const Eigen::Vector3d want = it->second(p);
          CAPTURE(f, j, got.transpose(), want.transpose());
          REQUIRE(it->second.off_plane(p) < 1e-9);
          CHECK((got - want).cwiseAbs().maxCoeff() < 1e-5);
          ++corners;
          const VertexSource& vs = sec.vertex_source[cycle[j]];
          diagonal_corners += vs.rank == 1 && vs.element == no_index;
        }
      }
    }
    INFO(spec);
    CHECK(corners > 0);
    CHECK(diagonal_corners > 0);  // no model here has only simplicial cells
  }
}

TEST_CASE("cw4d slice writes the same UVW field with --method tet as with --method cw",
          "[tet][uvw][cli]") {
  const test::TempDir dir("tet_uvw_cli");
  const std::string exe = CW4D_EXE;
  auto run = [&](const std::string& args) {
    const std::string cmd = exe + " " + args + " > " + (dir / "out.txt").string() + " 2>&1";
    const int status = std::system(cmd.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  for (const char* model : {"tesseract", "24-cell", "duoprism:4,6"}) {
    INFO(model);
    const std::string plane =
        std::string(model) + " --normal 0.3,-0.5,0.7,1 --offset 0.2 " + "--rotate xw:20 ";
    REQUIRE(run("slice " + plane + "-o " + (dir / "cw.obj").string()) == 0);
    REQUIRE(run("slice " + plane + "--method tet -o " + (dir / "tet.obj").string()) == 0);
    const auto cw = read_obj_cells((dir / "cw.obj").string());
    const auto tet = read_obj_cells((dir / "tet.obj").string());
    REQUIRE(cw.size() == tet.size());
    std::size_t checked = 0;
    for (const auto& [cell, corners] : tet) {
      INFO("cell " << cell);
      const auto c = cw.find(cell);
      REQUIRE(c != cw.end());
      const AffineUvw map = AffineUvw::fit(c->second.first, c->second.second);
      REQUIRE(map.fit_residual < 1e-6);  // the file's 8-digit floats
      for (std::size_t i = 0; i < corners.first.size(); ++i) {
        REQUIRE(map.off_plane(corners.first[i]) < 1e-9);
        CHECK((corners.second[i] - map(corners.first[i])).cwiseAbs().maxCoeff() < 1e-5);
        ++checked;
      }
    }
    CHECK(checked >= 3 * tet.size());
    // glTF carries the full UVW as _UVW on the tet path too.
    REQUIRE(run("slice " + plane + "--method tet -o " + (dir / "tet.gltf").string()) == 0);
    CHECK(test::read_text(dir / "tet.gltf").find("\"_UVW\"") != std::string::npos);
    CHECK(run("slice " + plane + "--method tet --no-uvw -o " + (dir / "plain.gltf").string()) == 0);
    CHECK(test::read_text(dir / "plain.gltf").find("\"_UVW\"") == std::string::npos);
  }
}
