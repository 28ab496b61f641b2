// Degeneracy stress test: every 4D built-in family and every convex Miratope file, cut by
// >= 10^4 planes per degenerate family (through a vertex, containing an edge, a face, a cell,
// and planes snapped to a coarse grid). Every section must be closed and outward (validate),
// without duplicate vertices or zero-area polygons, and its volume must be continuous with the
// sections of the nearby generic planes d - delta and d + delta (the independent oracle here:
// the model's volume function, sampled off the degenerate plane). One CTest case per family, so
// `ctest -j2` runs them in parallel; each prints its counts.
//
// CW4D_STRESS_FRACTION (a number in (0, 1], default 1) scales the plane counts down, for the
// sanitizer build where every section costs ten times more; the >= 10^4 requirement is checked
// only at the full count.
#include <Eigen/Dense>
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <numeric>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/off_io.hpp"
#include "cw4d/complex/operators.hpp"
#include "cw4d/complex/validate.hpp"
#include "cw4d/section/section.hpp"
#include "cw4d/section/slicer.hpp"
#include "cw4d/tetrahedralize/catalogue.hpp"
#include "support/planes.hpp"

using namespace cw4d;
using cw4d::test::random_orthogonal;
using cw4d::test::random_unit;
using cw4d::test::spanning;

namespace {

struct Model {
  std::string name;
  Complex complex;
  double scale;  // diameter
  std::size_t elements;
  bool convex;
};

// Every 4D family of the default catalogue (one or two members each) and every convex Miratope
// file.
const std::vector<Model>& models() {
  static const std::vector<Model> all = [] {
    const std::string data = CW4D_TEST_DATA_DIR;
    std::vector<std::string> specs = {"5-cell",
                                      "tesseract",
                                      "16-cell",
                                      "24-cell",
                                      "120-cell",
                                      "600-cell",
                                      "rectified 5-cell",
                                      "truncated tesseract",
                                      "cantellated 5-cell",
                                      "bitruncated 5-cell",
                                      "simplex:4",
                                      "cube:4",
                                      "orthoplex:4",
                                      "duoprism:5,7",
                                      "duoprism:3,12",
                                      "prism:5-cell",
                                      "prism:antiprism:5",
                                      "product:polygon:5*polygon:8",
                                      "pyramid:cube:3",
                                      "cone:sphere:1,8",
                                      "dual:24-cell",
                                      "duocylinder:1,12",
                                      "cubinder:1,8",
                                      "spherinder:1,8",
                                      "wythoff:x3x3x3x",
                                      "wythoff:x4o3x3o",
                                      "snub 24-cell",
                                      "grand antiprism",
                                      "glome:1,3",
                                      "extrude:" + data + "/cube.obj",
                                      "spin:" + data + "/offset_cube.off,12",
                                      "hull:" + data + "/cube_points.txt",
                                      "spheritorus:2,0.7,8",
                                      "torisphere:2,0.7,8",
                                      "ditorus:3,1.2,0.5,8",
                                      "tiger:2,2,0.7,8"};
    std::vector<Model> m;
    auto add = [&](const std::string& name, Complex c) {
      if (c.ambient_dim() != 4) return;
      std::size_t elements = 0;
      for (int k = 0; k <= c.top_rank(); ++k) elements += c.count(k);
      const double scale = 2.0 * max_radius(c);
      const bool convex = is_convex(c);
      m.push_back({name, std::move(c), scale, elements, convex});
    };
    for (const auto& spec : specs) add(spec, load_model(spec, default_catalogue()));
    const std::string dir = std::string(CW4D_TEST_DATA_DIR) + "/miratope/";
    for (const char* name : {"Pentachoron", "Tesseract", "Hexadecachoron", "Icositetrachoron",
                             "Hecatonicosachoron", "Hexacosichoron"})
      add(std::string("regular/") + name, read_off_file(dir + "regular/" + name + ".off"));
    std::vector<std::string> files;
    for (const auto& e : std::filesystem::directory_iterator(dir + "convex uniform"))
      if (e.path().extension() == ".off") files.push_back(e.path().string());
    std::sort(files.begin(), files.end());
    for (const auto& f : files) add(std::filesystem::path(f).filename().string(), read_off_file(f));
    return m;
  }();
  return all;
}

double fraction() {
  const char* env = std::getenv("CW4D_STRESS_FRACTION");
  if (!env) return 1.0;
  const double f = std::atof(env);
  return f > 0.0 && f <= 1.0 ? f : 1.0;
}

// Planes per model: cheap models get many, the 10^4-element ones a few dozen.
int planes_for(const Model& m) {
  const double n = std::clamp(2.0e5 / static_cast<double>(m.elements), 12.0, 240.0);
  return std::max(1, static_cast<int>(n * fraction()));
}

enum class Family { vertex = 0, edge = 1, face = 2, cell = 3, grid = 4 };

struct Counts {
  long planes = 0, empty = 0, sections = 0, vertices = 0, faces = 0;
};

double volume_at(const Complex& c, const Eigen::VectorXd& u, double d) {
  const Section s = section(c, Hyperplane{u, d});
  return s.empty() ? 0.0 : signed_volume(s.complex);
}

// The properties of one degenerate section; returns false (after reporting) on the first
// violation so a failing family names its plane.
void check(const Model& m, const Hyperplane& plane, const std::string& what, Counts& counts) {
  const Complex& c = m.complex;
  const double scale = m.scale;
  const Section s = section(c, plane);
  ++counts.planes;
  const double delta = 1e-7 * scale;
  const double vm = volume_at(c, plane.normal, plane.offset - delta);
  const double vp = volume_at(c, plane.normal, plane.offset + delta);
  // dV/dd stays below ~ 10 scale^2 for these models, so the jump over delta is tiny unless the
  // section is discontinuous (a dropped or doubled face changes it by a face's share).
  const double jump_tol = 1e-5 * std::pow(scale, 3);
  if (s.empty()) {
    ++counts.empty;
    if (std::min(std::abs(vm), std::abs(vp)) > jump_tol) {
      FAIL_CHECK(m.name << ": empty section where a nearby plane is not, " << what << " volumes "
                        << vm << ", " << vp);
    }
    return;
  }
  ++counts.sections;
  const Complex& sc = s.complex;
  counts.vertices += static_cast<long>(sc.count(0));
  counts.faces += static_cast<long>(sc.count(2));
  // A convex model's sections are closed 2-manifolds. A non-convex model's degenerate sections
  // may pinch: a plane containing a reflex edge meets two sheets that touch along one section
  // edge (four faces on it, the limit of the generic sections on either side), so there the
  // surface is checked as a chain: every edge's signed face incidences cancel.
  ValidateOptions options;
  options.require_closed = m.convex;
  const ValidationReport report = validate(sc, options);
  if (!report.ok()) {
    FAIL_CHECK(m.name << ": " << what << ": " << report.summary());
    return;
  }
  if (!m.convex) {
    std::vector<int> sum(sc.count(1), 0);
    const Incidence& faces = sc.boundary(2);
    for (std::uint32_t f = 0; f < faces.size(); ++f) {
      auto ids = faces.ids(f);
      auto signs = faces.signs(f);
      for (std::size_t i = 0; i < ids.size(); ++i) sum[ids[i]] += signs[i];
    }
    for (std::size_t e = 0; e < sum.size(); ++e)
      if (sum[e] != 0) FAIL_CHECK(m.name << ": " << what << ": edge " << e << " is a boundary");
  }
  const double volume = signed_volume(sc);
  if (!(volume > 0.0))
    FAIL_CHECK(m.name << ": " << what << ": volume " << volume << " not outward");
  // Continuity with the nearby generic planes on at least one side: a plane holding a whole
  // facet is the limit from inside (the outside neighbour is empty).
  // Near-parallel planes make V steep (dV/dd ~ 10^3): then V lies between its neighbours.
  const double jump = std::min(std::abs(volume - vm), std::abs(volume - vp));
  const double slack = jump_tol + 1e-6 * volume;
  const bool between = std::min(vm, vp) - slack <= volume && volume <= std::max(vm, vp) + slack;
  if (jump > slack && !between)
    FAIL_CHECK(m.name << ": " << what << ": volume " << volume << " jumps to " << vm << " / " << vp
                      << " at distance " << delta);
  // No duplicate vertices: sweep along x.
  const Eigen::MatrixXd& p = sc.positions();
  std::vector<Eigen::Index> order(static_cast<std::size_t>(p.cols()));
  std::iota(order.begin(), order.end(), Eigen::Index{0});
  std::sort(order.begin(), order.end(), [&](auto a, auto b) { return p(0, a) < p(0, b); });
  const double dup = 1e-11 * scale;
  for (std::size_t i = 0; i < order.size(); ++i)
    for (std::size_t j = i + 1; j < order.size() && p(0, order[j]) - p(0, order[i]) <= dup; ++j)
      if ((p.col(order[i]) - p.col(order[j])).norm() <= dup)
        FAIL_CHECK(m.name << ": " << what << ": vertices " << order[i] << " and " << order[j]
                          << " coincide");
  // No zero-area polygons.
  for (std::uint32_t f = 0; f < sc.count(2); ++f)
    if (!(facet_area_vector(sc, f).norm() > 1e-20 * scale * scale))
      FAIL_CHECK(m.name << ": " << what << ": face " << f << " has zero area");
}

std::string describe(const Hyperplane& p) {
  std::ostringstream out;
  out.precision(17);
  out << "n = (" << p.normal.transpose() << "), d = " << p.offset;
  return out.str();
}

void run_family(Family family, std::uint32_t seed, const char* label) {
  std::mt19937 rng(seed);
  Counts counts;
  for (const Model& m : models()) {
    const Complex& c = m.complex;
    const int planes = planes_for(m);
    if (family == Family::grid) {
      // Normals with small integer entries, offsets on a grid of scale / 16: in the models'
      // own coordinates (integers, halves, golden-ratio multiples) these hit vertices, edges
      // and faces, often several at once.
      std::uniform_int_distribution<int> entry(-2, 2), step(-8, 8);
      for (int t = 0; t < planes; ++t) {
        Eigen::VectorXd nrm(4);
        do {
          for (int i = 0; i < 4; ++i) nrm(i) = entry(rng);
        } while (nrm.isZero());
        const double len = nrm.norm();
        const double d = step(rng) * (m.scale / 16.0);
        const Hyperplane plane{nrm / len, d / len};
        check(m, plane, "grid plane " + describe(plane), counts);
      }
      continue;
    }
    const int rank = static_cast<int>(family);
    for (int t = 0; t < planes; ++t) {
      const auto id = std::uniform_int_distribution<std::uint32_t>(
          0, static_cast<std::uint32_t>(c.count(rank) - 1))(rng);
      Eigen::VectorXd u;
      if (family == Family::cell) {
        // The cell's own hyperplane, approached from either side.
        u = c.facet_normals().col(id) * (t % 2 == 0 ? 1.0 : -1.0);
      } else {
        const Eigen::MatrixXd dirs = rank == 0 ? Eigen::MatrixXd(4, 0) : spanning(c, rank, id);
        u = random_orthogonal(rng, dirs);
      }
      const double d = u.dot(c.position(c.first_vertex(rank, id)));
      const Hyperplane plane{u, d};
      check(m, plane,
            std::string(label) + " element " + std::to_string(id) + ", " + describe(plane), counts);
    }
  }
  std::cout << "stress[" << label << "]: " << counts.planes << " planes over " << models().size()
            << " models: " << counts.sections << " sections (" << counts.vertices << " vertices, "
            << counts.faces << " faces checked), " << counts.empty << " empty\n";
  if (fraction() == 1.0) CHECK(counts.planes >= 10000);
}

}  // namespace

TEST_CASE("stress: the models load and are valid closed complexes", "[stress]") {
  CHECK(models().size() >= 80);
  for (const Model& m : models()) {
    INFO(m.name);
    CHECK(validate(m.complex).ok());
  }
}

TEST_CASE("stress: planes through a vertex", "[stress]") {
  run_family(Family::vertex, 701, "vertex");
}
TEST_CASE("stress: planes containing an edge", "[stress]") {
  run_family(Family::edge, 702, "edge");
}
TEST_CASE("stress: planes containing a face", "[stress]") {
  run_family(Family::face, 703, "face");
}
TEST_CASE("stress: planes containing a cell", "[stress]") {
  run_family(Family::cell, 704, "cell");
}
TEST_CASE("stress: grid-snapped planes", "[stress]") {
  run_family(Family::grid, 705, "grid");
}

namespace {

// Two slices of the same plane, bit for bit.
bool identical(const SliceBuffers& a, const SliceBuffers& b) {
  if (a.general != b.general || a.fallback != b.fallback || a.coords != b.coords ||
      a.source != b.source || a.facet_normals != b.facet_normals ||
      a.vertex_source.size() != b.vertex_source.size() || a.boundary.size() != b.boundary.size())
    return false;
  for (std::size_t i = 0; i < a.vertex_source.size(); ++i)
    if (a.vertex_source[i].element != b.vertex_source[i].element ||
        a.vertex_source[i].rank != b.vertex_source[i].rank ||
        a.vertex_source[i].t != b.vertex_source[i].t)
      return false;
  for (std::size_t r = 0; r < a.boundary.size(); ++r)
    if (a.boundary[r].offsets() != b.boundary[r].offsets() ||
        a.boundary[r].all_ids() != b.boundary[r].all_ids() ||
        a.boundary[r].all_signs() != b.boundary[r].all_signs())
      return false;
  return true;
}

// The fast path's section against the general layered cut (a second algorithm): the same
// elements in the same order with the same provenance, coordinates equal up to rounding.
// `position_tol` is relative to the size.
std::string differs(const Section& fast, const Section& general, double scale,
                    double position_tol) {
  const Complex& a = fast.complex;
  const Complex& b = general.complex;
  if (a.top_rank() != b.top_rank()) return "top rank";
  for (int r = 0; r <= a.top_rank(); ++r)
    if (a.count(r) != b.count(r)) return "count of rank " + std::to_string(r);
  for (int r = 1; r <= a.top_rank(); ++r) {
    if (a.count(r) == 0) continue;
    if (a.boundary(r).all_ids() != b.boundary(r).all_ids() ||
        a.boundary(r).all_signs() != b.boundary(r).all_signs())
      return "boundary of rank " + std::to_string(r);
    if (fast.source[r] != general.source[r]) return "source of rank " + std::to_string(r);
  }
  for (std::size_t i = 0; i < fast.vertex_source.size(); ++i)
    if (fast.vertex_source[i].element != general.vertex_source[i].element ||
        fast.vertex_source[i].rank != general.vertex_source[i].rank)
      return "vertex source " + std::to_string(i);
  if (a.count(0) > 0 &&
      !((a.positions() - b.positions()).cwiseAbs().maxCoeff() <= position_tol * scale)) {
    std::ostringstream o;
    o << "positions, by " << (a.positions() - b.positions()).cwiseAbs().maxCoeff() / scale;
    return o.str();
  }
  if (a.has_facet_normals() != b.has_facet_normals()) return "facet normals";
  if (a.has_facet_normals() && a.facet_normals().cols() > 0 &&
      !((a.facet_normals() - b.facet_normals()).cwiseAbs().maxCoeff() <= 1e-9))
    return "facet normals";
  return {};
}

}  // namespace

// The slicer's specialised kernel (faces to crossing pairs, cells chained through a next map)
// against the generic chain gathering (bit for bit) and against the general layered cut
// (element for element), on every stress model: generic planes, and the planes of every
// degenerate family moved off by 1e-7 of the model's size to either side (the fast path's
// hardest inputs: crossings close to vertices) and on them (the fallback). Seeded; a tenth of
// the stress planes per family, so it runs in seconds. section()'s convexity shortcut is checked
// against self_intersects on the same slices.
TEST_CASE("stress: the fast kernel agrees with the generic gathering and the general path",
          "[stress][kernel]") {
  std::mt19937 rng(706);
  Slicer kernel, generic;
  SliceBuffers a, b;
  SliceOptions plain;
  plain.kernel = false;
  std::size_t slices = 0, fast = 0;
  for (const Model& m : models()) {
    INFO(m.name);
    const Complex& c = m.complex;
    const SliceModel compiled(c, SliceModelOptions::unclustered());
    const int per = std::max(2, planes_for(m) / 10);
    std::vector<Hyperplane> planes;
    for (int t = 0; t < per; ++t) {
      std::uniform_real_distribution<double> u(-0.45, 0.45);
      planes.push_back(Hyperplane{random_unit(rng, 4), u(rng) * m.scale});
      for (int rank = 0; rank < 4; ++rank) {
        const auto id = std::uniform_int_distribution<std::uint32_t>(
            0, static_cast<std::uint32_t>(c.count(rank) - 1))(rng);
        Eigen::VectorXd n;
        if (rank == 3) {
          n = c.facet_normals().col(id);
        } else {
          const Eigen::MatrixXd dirs = rank == 0 ? Eigen::MatrixXd(4, 0) : spanning(c, rank, id);
          n = random_orthogonal(rng, dirs);
        }
        const double d = n.dot(c.position(c.first_vertex(rank, id)));
        for (double shift : {-1e-7, 0.0, 1e-7})
          planes.push_back(Hyperplane{n, d + shift * m.scale});
      }
    }
    for (std::size_t i = 0; i < planes.size(); ++i) {
      const Hyperplane& plane = planes[i];
      kernel.slice(compiled, plane, a);
      generic.slice(compiled, plane, b, plain);
      ++slices;
      if (!identical(a, b))
        FAIL_CHECK(m.name << ": kernel and generic gathering differ, " << describe(plane));
      if (a.general) continue;
      ++fast;
      // The two paths evaluate n.x - d differently; a crossing's t = s_a / (s_a - s_b) is
      // ill-conditioned where the plane nearly contains the edge, which the planes next to a
      // degenerate one do: there the positions agree to 1e-10 of the size, elsewhere to 1e-12.
      const bool near_degenerate = i % 13 != 0;  // (plane 13 j is the generic one)
      const std::string why =
          differs(to_section(a), section_general(c, plane, AffineTransform::identity(4)), m.scale,
                  near_degenerate ? 1e-10 : 1e-12);
      if (!why.empty())
        FAIL_CHECK(m.name << ": fast and general path differ (" << why << "), " << describe(plane));
      // section() skips the self-intersection test for convex models: the same answer.
      if (section(c, plane).self_intersecting != to_section(a).self_intersecting)
        FAIL_CHECK(m.name << ": section() and self_intersects disagree, " << describe(plane));
    }
  }
  std::cout << "stress[kernel]: " << slices << " slices, " << fast << " on the fast path, "
            << kernel.kernel_elements() << " faces and cells cut by the kernel, "
            << kernel.generic_elements() << " by the generic gathering\n";
  CHECK(fast > slices / 2);
  CHECK(kernel.kernel_elements() > 0);
  CHECK(generic.kernel_elements() == 0);
}
