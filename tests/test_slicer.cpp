// The slicer's fast path against the general layered cut (a second algorithm), and the speed
// features against the plain call: sweeps, threads, culling and the topology cache must give
// exactly (bit for bit) the buffers of Slicer::slice with a fresh plane.
#include <Eigen/Dense>
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/scene.hpp"
#include "cw4d/complex/tolerances.hpp"
#include "cw4d/section/scene_section.hpp"
#include "cw4d/section/section.hpp"
#include "cw4d/section/slicer.hpp"
#include "support/planes.hpp"

using namespace cw4d;

namespace {

// Everything a SliceBuffers exposes, compared exactly.
void require_identical(const SliceBuffers& a, const SliceBuffers& b) {
  REQUIRE(a.dim == b.dim);
  REQUIRE(a.general == b.general);
  REQUIRE(a.plane.normal == b.plane.normal);
  REQUIRE(a.plane.offset == b.plane.offset);
  REQUIRE(a.coords == b.coords);
  REQUIRE(a.vertex_source.size() == b.vertex_source.size());
  for (std::size_t i = 0; i < a.vertex_source.size(); ++i) {
    REQUIRE(a.vertex_source[i].element == b.vertex_source[i].element);
    REQUIRE(a.vertex_source[i].rank == b.vertex_source[i].rank);
    REQUIRE(a.vertex_source[i].t == b.vertex_source[i].t);
  }
  REQUIRE(a.boundary.size() == b.boundary.size());
  for (std::size_t r = 0; r < a.boundary.size(); ++r) {
    REQUIRE(a.boundary[r].offsets() == b.boundary[r].offsets());
    REQUIRE(a.boundary[r].all_ids() == b.boundary[r].all_ids());
    REQUIRE(a.boundary[r].all_signs() == b.boundary[r].all_signs());
  }
  REQUIRE(a.source == b.source);
  REQUIRE(a.facet_normals == b.facet_normals);
}

// The general path's complex equals the fast path's: the same elements in the same order, the
// same provenance; coordinates and normals equal up to rounding.
void require_same_section(const Section& fast, const Section& general, double scale) {
  const Complex& a = fast.complex;
  const Complex& b = general.complex;
  REQUIRE(a.top_rank() == b.top_rank());
  REQUIRE(fast.source.size() == general.source.size());
  const int top = a.top_rank();
  for (int r = 0; r <= top; ++r) REQUIRE(a.count(r) == b.count(r));
  for (int r = 1; r <= top; ++r) {
    if (a.count(r) == 0) continue;
    REQUIRE(a.boundary(r).all_ids() == b.boundary(r).all_ids());
    REQUIRE(a.boundary(r).all_signs() == b.boundary(r).all_signs());
    REQUIRE(fast.source[r] == general.source[r]);
  }
  REQUIRE(fast.vertex_source.size() == general.vertex_source.size());
  for (std::size_t i = 0; i < fast.vertex_source.size(); ++i) {
    REQUIRE(fast.vertex_source[i].element == general.vertex_source[i].element);
    REQUIRE(fast.vertex_source[i].rank == general.vertex_source[i].rank);
  }
  if (a.count(0) > 0)
    REQUIRE((a.positions() - b.positions()).cwiseAbs().maxCoeff() <= 1e-12 * scale);
  REQUIRE(a.has_facet_normals() == b.has_facet_normals());
  if (a.has_facet_normals() && a.facet_normals().cols() > 0)
    REQUIRE((a.facet_normals() - b.facet_normals()).cwiseAbs().maxCoeff() <= 1e-9);
  REQUIRE(fast.self_intersecting == general.self_intersecting);
}

AffineTransform random_placement(std::mt19937& rng, int n, bool mirror) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd m(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) m(i, j) = u(rng);
  m += 2.0 * Eigen::MatrixXd::Identity(n, n);  // well conditioned
  if (mirror) m.row(0) = -m.row(0);
  if ((m.determinant() < 0) != mirror) m.row(1) = -m.row(1);
  Eigen::VectorXd t(n);
  for (int i = 0; i < n; ++i) t(i) = u(rng);
  return AffineTransform(m, t);
}

// Two copies of a model, the second moved by `shift`: a model with two components.
Complex disjoint_union(const Complex& a, const Eigen::VectorXd& shift) {
  const int n = a.ambient_dim();
  Complex u(n);
  const Eigen::Index nv = a.positions().cols();
  Eigen::MatrixXd pos(n, 2 * nv);
  pos.leftCols(nv) = a.positions();
  pos.rightCols(nv) = a.positions().colwise() + shift;
  u.set_positions(pos);
  for (int r = 1; r <= a.top_rank(); ++r) {
    const Incidence& t = a.boundary(r);
    Incidence& dst = u.boundary_mut(r);
    const auto base = static_cast<std::uint32_t>(a.count(r - 1));
    for (std::uint32_t copy = 0; copy < 2; ++copy)
      for (std::uint32_t x = 0; x < t.size(); ++x) {
        std::vector<std::uint32_t> ids(t.ids(x).begin(), t.ids(x).end());
        for (auto& id : ids) id += copy * base;
        dst.add_row(ids, t.signs(x));
      }
  }
  const Eigen::MatrixXd& fn = a.facet_normals();
  Eigen::MatrixXd normals(n, 2 * fn.cols());
  normals << fn, fn;
  u.set_facet_normals(normals);
  return u;
}

Hyperplane random_plane(std::mt19937& rng, int n, double reach) {
  std::uniform_real_distribution<double> u(-0.95, 0.95);
  return Hyperplane::from(test::random_unit(rng, n), u(rng) * reach);
}

const std::vector<std::string>& models_4d() {
  static const std::vector<std::string> specs = {
      "tesseract", "24-cell", "120-cell", "600-cell", "5-cell", "duoprism:5,7", "16-cell"};
  return specs;
}

}  // namespace

TEST_CASE("the fast path builds the general path's section", "[slicer]") {
  std::mt19937 rng(8101);
  std::size_t fast = 0, total = 0;
  for (const std::string& spec : models_4d()) {
    INFO(spec);
    const Complex model = load_model(spec);
    const SliceModel compiled(model, {std::size_t(-1), 256});
    REQUIRE(compiled.fast());
    Slicer slicer;
    SliceBuffers buffers;
    for (int i = 0; i < 60; ++i) {
      const bool placed = i % 3 != 0;
      const AffineTransform xf =
          placed ? random_placement(rng, 4, i % 3 == 2) : AffineTransform::identity(4);
      const Hyperplane plane = random_plane(rng, 4, 4.0 * compiled.radius());
      slicer.slice(compiled, plane, xf, buffers);
      const Section general = section_general(model, plane, xf);
      require_same_section(to_section(buffers), general, 10.0 * compiled.radius());
      fast += !buffers.general;
      ++total;
    }
  }
  // Generic planes take the fast path (this would catch a fast path that always gives up).
  CHECK(fast == total);
}

TEST_CASE("polyhedra in R^3 take the fast path and match the general path", "[slicer]") {
  std::mt19937 rng(8102);
  for (const std::string spec : {"cube:3", "simplex:3", "orthoplex:3"}) {
    INFO(spec);
    const Complex model = load_model(spec);
    const SliceModel compiled(model);
    REQUIRE(compiled.fast());
    Slicer slicer;
    SliceBuffers buffers;
    for (int i = 0; i < 40; ++i) {
      const AffineTransform xf = random_placement(rng, 3, i % 2 == 1);
      const Hyperplane plane = random_plane(rng, 3, 4.0 * compiled.radius());
      slicer.slice(compiled, plane, xf, buffers);
      REQUIRE_FALSE(buffers.general);
      require_same_section(to_section(buffers), section_general(model, plane, xf), 10.0);
    }
  }
}

TEST_CASE("a polyhedron with its solid cuts into closed polygons", "[slicer]") {
  // Regression: the known cut of a single solid is a set of facets only from R^4 up; in R^3
  // the solid's cut is a polygon whose edges must be chained into loops.
  std::mt19937 rng(8108);
  Complex cube = load_model("cube:3");
  std::vector<std::uint32_t> all(cube.count(2));
  for (std::uint32_t i = 0; i < all.size(); ++i) all[i] = i;
  if (cube.top_rank() < 3)
    cube.boundary_mut(3).add_row(all, std::vector<std::int8_t>(all.size(), 1));
  const SliceModel compiled(cube);
  REQUIRE(compiled.fast());
  Slicer slicer;
  SliceBuffers out;
  for (int i = 0; i < 50; ++i) {
    const Hyperplane plane = random_plane(rng, 3, 1.7);
    slicer.slice(compiled, plane, out);
    require_same_section(to_section(out),
                         section_general(cube, plane, AffineTransform::identity(3)), 10.0);
  }
}

TEST_CASE("edges stored against the convention take the general path", "[slicer]") {
  // An edge row [head, tail] with signs [+1, -1] is the chain of [tail, head] with [-1, +1],
  // but a compiled model keeps only its edges' ends (offsets and signs implied): such a model is
  // not fast(), and its slices are the general path's, as section_general cuts it.
  std::mt19937 rng(8121);
  for (const std::string spec : {"tesseract", "24-cell", "cube:3"}) {
    INFO(spec);
    const Complex model = load_model(spec);
    const int n = model.ambient_dim();
    Complex flipped = model;
    for (std::uint32_t e = 0; e < flipped.count(1); e += 3) {
      auto ids = flipped.boundary_mut(1).ids_mut(e);
      auto signs = flipped.boundary_mut(1).signs_mut(e);
      std::swap(ids[0], ids[1]);
      std::swap(signs[0], signs[1]);
    }
    const SliceModel compiled(flipped);
    CHECK_FALSE(compiled.fast());
    Slicer slicer;
    SliceBuffers buffers;
    for (int i = 0; i < 20; ++i) {
      const AffineTransform xf = random_placement(rng, n, i % 2 == 1);
      const Hyperplane plane = random_plane(rng, n, 2.0 * compiled.radius());
      slicer.slice(compiled, plane, xf, buffers);
      REQUIRE(buffers.general);
      CHECK(buffers.fallback == FallbackReason::Model);
      require_same_section(to_section(buffers), section_general(flipped, plane, xf), 10.0);
    }
    // compiled_from sees a flip made after the compile (the implied signs no longer hold).
    Complex changed = model;
    const SliceModel before(changed);
    REQUIRE(before.compiled_from(changed));
    std::swap(changed.boundary_mut(1).signs_mut(0)[0], changed.boundary_mut(1).signs_mut(0)[1]);
    CHECK_FALSE(before.compiled_from(changed));
  }
}

TEST_CASE("elements with different numbers of cofaces slice as the general path", "[slicer]") {
  // A tesseract with its solid beside a 600-cell: edges in 3 and in 5 faces, cells in one solid
  // and in none (the compiled coface lists keep their offsets), faces in two cells each (implied
  // offsets); unclustered and clustered.
  std::mt19937 rng(8122);
  Complex a = load_model("tesseract");
  std::vector<std::uint32_t> cells(a.count(3));
  for (std::uint32_t i = 0; i < cells.size(); ++i) cells[i] = i;
  a.boundary_mut(4).add_row(cells, std::vector<std::int8_t>(cells.size(), 1));
  const Complex b = load_model("600-cell");
  Complex u(4);
  const Eigen::Index na = a.positions().cols(), nb = b.positions().cols();
  Eigen::MatrixXd pos(4, na + nb);
  pos.leftCols(na) = a.positions();
  pos.rightCols(nb) = b.positions().colwise() + Eigen::Vector4d(0.5, 2.5, 0.0, 0.0);
  u.set_positions(pos);
  for (int r = 1; r <= 4; ++r) {
    Incidence& dst = u.boundary_mut(r);
    const auto base = static_cast<std::uint32_t>(a.count(r - 1));
    for (std::uint32_t x = 0; x < a.boundary(r).size(); ++x)
      dst.add_row(a.boundary(r).ids(x), a.boundary(r).signs(x));
    if (r > b.top_rank()) continue;
    for (std::uint32_t x = 0; x < b.boundary(r).size(); ++x) {
      std::vector<std::uint32_t> ids(b.boundary(r).ids(x).begin(), b.boundary(r).ids(x).end());
      for (auto& id : ids) id += base;
      dst.add_row(ids, b.boundary(r).signs(x));
    }
  }
  Eigen::MatrixXd normals(4, a.facet_normals().cols() + b.facet_normals().cols());
  normals << a.facet_normals(), b.facet_normals();
  u.set_facet_normals(normals);
  for (const SliceModelOptions options :
       {SliceModelOptions::unclustered(), SliceModelOptions{16, 8}}) {
    const SliceModel compiled(u, options);
    REQUIRE(compiled.fast());
    Slicer slicer;
    SliceBuffers buffers;
    std::size_t fast = 0;
    for (int i = 0; i < 60; ++i) {
      const AffineTransform xf = random_placement(rng, 4, i % 2 == 1);
      const Hyperplane plane = random_plane(rng, 4, 4.0 * compiled.radius());
      slicer.slice(compiled, plane, xf, buffers);
      fast += !buffers.general;
      const Section cut = to_section(buffers), general = section_general(u, plane, xf);
      if (options.cluster_threshold == SliceModelOptions::unclustered().cluster_threshold) {
        require_same_section(cut, general, 10.0 * compiled.radius());
      } else {  // renumbered: the same solid
        REQUIRE(cut.complex.count(3) == general.complex.count(3));
        REQUIRE(std::abs(signed_volume(cut.complex) - signed_volume(general.complex)) <= 1e-10);
      }
    }
    CHECK(fast == 60);
  }
}

TEST_CASE("degenerate planes fall back to the general path", "[slicer]") {
  const Complex tesseract = load_model("tesseract");
  const SliceModel compiled(tesseract);
  Slicer slicer;
  SliceBuffers buffers;
  Eigen::VectorXd w(4);
  w << 0, 0, 0, 1;
  // Through a facet (every vertex of a cell on the plane): the general path returns the cell.
  slicer.slice(compiled, Hyperplane::from(w, 1.0), buffers);
  CHECK(buffers.general);
  const Section s = to_section(buffers);
  CHECK(std::abs(signed_volume(s.complex) - 8.0) < 1e-12);
  // Generic: the fast path, the same cube.
  slicer.slice(compiled, Hyperplane::from(w, 0.25), buffers);
  CHECK_FALSE(buffers.general);
  CHECK(std::abs(signed_volume(to_section(buffers).complex) - 8.0) < 1e-12);
}

TEST_CASE("a sweep gives every layer exactly as a single slice", "[slicer][sweep]") {
  std::mt19937 rng(8103);
  for (const std::string& spec : models_4d()) {
    INFO(spec);
    const Complex model = load_model(spec);
    const SliceModel compiled(model);
    for (int round = 0; round < 4; ++round) {
      const Eigen::VectorXd normal = test::random_unit(rng, 4) * (round + 1.0);
      const AffineTransform xf =
          round == 0 ? AffineTransform::identity(4) : random_placement(rng, 4, round == 3);
      // Unsorted offsets, some repeated, some outside the model.
      std::uniform_real_distribution<double> u(-6.0, 6.0);
      std::vector<double> offsets(37);
      for (double& d : offsets) d = u(rng);
      offsets[5] = offsets[9];
      Slicer sweeper, single;
      std::vector<SliceBuffers> layers;
      sweeper.sweep(compiled, normal, offsets, xf, layers);
      REQUIRE(layers.size() == offsets.size());
      SliceBuffers one;
      for (std::size_t k = 0; k < offsets.size(); ++k) {
        single.slice(compiled, Hyperplane::from(normal, offsets[k]), xf, one);
        require_identical(layers[k], one);
      }
      // Threads: the same buffers.
      std::vector<SliceBuffers> threaded;
      Slicer().sweep(compiled, normal, offsets, xf, threaded, 3);
      for (std::size_t k = 0; k < offsets.size(); ++k) require_identical(threaded[k], layers[k]);
    }
  }
}

TEST_CASE("a sweep through vertices cuts its degenerate layers like slice()", "[slicer][sweep]") {
  const Complex tesseract = load_model("tesseract");
  const SliceModel compiled(tesseract);
  Eigen::VectorXd n(4);
  n << 0, 0, 0, 2;  // vertex heights -1 and 1: three layers through facets, one within rounding
  const std::vector<double> offsets = {-2.0, -1.0, -0.5, 0.0, 0.7, 1.0, 1.0 + 1e-17, 2.5};
  Slicer slicer;
  std::vector<SliceBuffers> layers;
  slicer.sweep(compiled, n, offsets, AffineTransform::identity(4), layers);
  SliceBuffers one;
  int general = 0;
  for (std::size_t k = 0; k < offsets.size(); ++k) {
    Slicer().slice(compiled, Hyperplane::from(n, offsets[k]), one);
    require_identical(layers[k], one);
    general += layers[k].general;
  }
  CHECK(general == 3);  // the layers through the facets
}

TEST_CASE("cluster culling gives the unculled buffers", "[slicer][cull]") {
  std::mt19937 rng(8104);
  for (const std::string spec : {"120-cell", "600-cell"}) {
    INFO(spec);
    const Complex model = load_model(spec);
    const SliceModel clustered(model, {16, 8});
    REQUIRE(clustered.cluster_count() > 10);
    Slicer slicer;
    SliceBuffers culled, unculled;
    SliceOptions no_cull;
    no_cull.cull = false;
    double total_volume = 0.0;
    for (int i = 0; i < 80; ++i) {
      const Hyperplane plane = random_plane(rng, 4, 1.3 * clustered.radius());
      slicer.slice(clustered, plane, culled);
      slicer.slice(clustered, plane, unculled, no_cull);
      require_identical(culled, unculled);
      // Renumbered, but the same solid as the unclustered path.
      const Section a = to_section(culled), b = section(model, plane);
      REQUIRE(a.complex.count(2) == b.complex.count(2));
      REQUIRE(std::abs(signed_volume(a.complex) - signed_volume(b.complex)) <= 1e-10);
      total_volume += signed_volume(a.complex);
    }
    CHECK(total_volume > 0.0);
    // A sweep of the clustered model: its layers are the (culled) slices, bit for bit.
    const Eigen::VectorXd n = test::random_unit(rng, 4);
    std::vector<double> offsets;
    for (int i = 0; i < 24; ++i)
      offsets.push_back(-1.2 * clustered.radius() + 0.1 * i * clustered.radius());
    std::vector<SliceBuffers> layers;
    slicer.sweep(clustered, n, offsets, AffineTransform::identity(4), layers, 2);
    for (std::size_t k = 0; k < offsets.size(); ++k) {
      slicer.slice(clustered, Hyperplane::from(n, offsets[k]), culled);
      require_identical(layers[k], culled);
    }
  }
}

TEST_CASE("the topology cache reuses connectivity only when it is exact", "[slicer][cache]") {
  std::mt19937 rng(8105);
  for (const std::string spec : {"120-cell", "tesseract", "duoprism:5,7"}) {
    INFO(spec);
    const Complex model = load_model(spec);
    const SliceModel compiled(model);
    Slicer cached, fresh;
    SliceBuffers anim, ref;
    SliceOptions reuse;
    reuse.reuse_topology = true;
    const Eigen::VectorXd n = test::random_unit(rng, 4);
    // An animation: the plane drifts slowly and the object turns a little each frame.
    for (int frame = 0; frame < 120; ++frame) {
      const double d = 0.3 + 1e-5 * frame + (frame % 40 == 39 ? 0.5 : 0.0);
      const AffineTransform xf = AffineTransform::rotation(4, 0, 3, 1e-4 * frame);
      const Hyperplane plane = Hyperplane::from(n, d);
      cached.slice(compiled, plane, xf, anim, reuse);
      fresh.slice(compiled, plane, xf, ref);
      require_identical(anim, ref);
    }
    CHECK(cached.cached_slices() > 60);   // most frames keep their sides
    CHECK(cached.cached_slices() < 120);  // the jumps do not
  }
}

// count objects placed at random in the box [-half, half]^4, turned and (every mirror_every-th)
// mirrored; object i shows model(i).
Scene random_scene(std::mt19937& rng, int count, double half,
                   const std::function<std::shared_ptr<const Complex>(int)>& model,
                   int mirror_every) {
  Scene scene;
  std::uniform_real_distribution<double> u(-half, half);
  for (int i = 0; i < count; ++i) {
    SceneObject obj;
    obj.complex = model(i);
    obj.model = "m";
    Eigen::VectorXd t(4);
    t << u(rng), u(rng), u(rng), u(rng);
    obj.transform =
        AffineTransform::translation(t) * random_placement(rng, 4, i % mirror_every == 0);
    scene.objects.push_back(obj);
  }
  return scene;
}

// The object indices a SceneSlice holds, checked against the slicer's own list.
void require_listed(const SceneSlice& out, const SceneSlicer& slicer) {
  REQUIRE(out.buffers.size() == out.objects.size());
  REQUIRE(std::is_sorted(out.objects.begin(), out.objects.end()));
  REQUIRE(std::adjacent_find(out.objects.begin(), out.objects.end()) == out.objects.end());
  const auto list = slicer.touched_objects();
  REQUIRE(list.size() == slicer.touched());
  REQUIRE(std::equal(list.begin(), list.end(), out.objects.begin(), out.objects.end()));
}

TEST_CASE("scenes: culling and threads give the plain buffers", "[slicer][scene]") {
  std::mt19937 rng(8106);
  auto tesseract = std::make_shared<const Complex>(load_model("tesseract"));
  auto cell24 = std::make_shared<const Complex>(load_model("24-cell"));
  const Scene scene = random_scene(
      rng, 300, 20.0, [&](int i) { return i % 3 == 0 ? cell24 : tesseract; }, 7);
  SceneSlicer slicer(scene);
  SliceOptions plain;
  plain.cull = false;
  std::size_t touched = 0;
  for (int i = 0; i < 10; ++i) {
    const Hyperplane plane = random_plane(rng, 4, 20.0);
    SceneSlice a, b, c;
    slicer.slice(plane, a, 1);
    require_listed(a, slicer);
    touched += slicer.touched();
    slicer.slice(plane, b, 1, plain);
    require_listed(b, slicer);
    REQUIRE(b.size() == scene.objects.size());
    slicer.slice(plane, c, 2);
    REQUIRE(c.objects == a.objects);
    // Every object in b; the culled ones (not in a) with the empty section.
    std::size_t k = 0;
    for (std::size_t obj = 0; obj < scene.objects.size(); ++obj) {
      REQUIRE(b.objects[obj] == obj);
      if (k < a.size() && a.objects[k] == obj) {
        require_identical(a.buffers[k], b.buffers[obj]);
        require_identical(a.buffers[k], c.buffers[k]);
        ++k;
      } else {
        REQUIRE(b.buffers[obj].empty());
      }
    }
    REQUIRE(k == a.size());
    // And the Section API (section_objects) agrees with the per-object section().
    const auto pieces = section_objects(scene, plane);
    REQUIRE(pieces.size() == scene.objects.size());
    for (std::size_t k = 0; k < pieces.size(); ++k) {
      const Section one = section(*scene.objects[k].complex, plane, scene.objects[k].transform);
      REQUIRE(pieces[k].complex.count(2) == one.complex.count(2));
      REQUIRE(pieces[k].complex.positions() == one.complex.positions());
    }
  }
  CHECK(touched < 10 * scene.objects.size() / 2);  // the culling did skip objects
}

TEST_CASE("scenes with the topology cache stay exact across culled frames",
          "[slicer][scene][cache]") {
  // Regression: a culled frame emptied an object's buffers but left its cache valid, so the
  // next frame reused connectivity that was no longer there.
  Scene scene;
  SceneObject obj;
  obj.model = "tesseract";
  obj.complex = std::make_shared<const Complex>(load_model("tesseract"));
  for (int i = 0; i < 3; ++i) {
    Eigen::VectorXd t = Eigen::VectorXd::Zero(4);
    t(3) = 3.0 * i;
    obj.transform = AffineTransform::translation(t);
    scene.objects.push_back(obj);
  }
  SceneSlicer cached(scene), fresh(scene);
  SliceOptions reuse;
  reuse.reuse_topology = true;
  Eigen::VectorXd n(4);
  n << 0.3, 0.2, 0.1, 1.0;
  SceneSlice a, b;
  const double offsets[] = {0.1, 0.1001, 50.0, 0.1, 3.2, 0.1002, 6.1, 6.1001, -9.0, 6.1};
  for (double d : offsets) {
    const Hyperplane plane = Hyperplane::from(n, d);
    cached.slice(plane, a, 1, reuse);
    fresh.slice(plane, b, 1);
    REQUIRE(a.objects == b.objects);
    for (std::size_t k = 0; k < a.size(); ++k) require_identical(a.buffers[k], b.buffers[k]);
  }
}

TEST_CASE("scenes: the touched objects' buffers are exactly slice()'s, the others' empty",
          "[slicer][scene]") {
  // One SceneSlice reused across planes: animations of the offset (the placements are kept),
  // then new normals. Every touched object must be exactly Slicer::slice of its own model by
  // its own Slicer (the oracle); every object left out must have the empty section there
  // (culling never drops a cut); the list is increasing and the same for 1 and 2 threads.
  std::mt19937 rng(8110);
  auto tesseract = std::make_shared<const Complex>(load_model("tesseract"));
  auto cell24 = std::make_shared<const Complex>(load_model("24-cell"));
  auto cell600 = std::make_shared<const Complex>(load_model("600-cell"));
  // (from 256 objects a repeated normal culls by height)
  const Scene scene = random_scene(
      rng, 300, 12.0, [&](int i) { return i % 5 == 0   ? cell600
                                          : i % 3 == 0 ? cell24
                                                       : tesseract; },
      7);
  std::vector<std::unique_ptr<SliceModel>> models;
  std::vector<Slicer> oracle(scene.objects.size());
  for (const SceneObject& obj : scene.objects)
    models.push_back(std::make_unique<SliceModel>(*obj.complex));
  SceneSlicer slicer(scene), threaded(scene);
  SceneSlice out, out2;
  SliceBuffers one;
  std::size_t touched_total = 0, culled_total = 0, sizes_seen = 0;
  std::size_t last_size = 0;
  for (int normal_round = 0; normal_round < 4; ++normal_round) {
    const Eigen::VectorXd n = test::random_unit(rng, 4);
    for (int step = 0; step < 12; ++step) {
      const Hyperplane plane = Hyperplane::from(n, -12.0 + 2.0 * step + 0.37 * normal_round);
      slicer.slice(plane, out, 1);
      require_listed(out, slicer);
      threaded.slice(plane, out2, 2);
      require_listed(out2, threaded);
      REQUIRE(out2.objects == out.objects);
      // A new SceneSlicer tests every sphere (its first call): the same list.
      SceneSlicer once(scene);
      SceneSlice first;
      once.slice(plane, first, 1);
      REQUIRE(first.objects == out.objects);
      REQUIRE(out.plane.normal == plane.normal);
      REQUIRE(out.plane.offset == plane.offset);
      sizes_seen += out.size() != last_size;
      last_size = out.size();
      std::size_t k = 0;
      for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        INFO("object " << i);
        oracle[i].slice(*models[i], plane, scene.objects[i].transform, one);
        if (k < out.size() && out.objects[k] == i) {
          require_identical(out.buffers[k], one);
          REQUIRE(out.buffers[k].fallback == one.fallback);
          REQUIRE(out.buffers[k].reused_topology == false);
          require_identical(out2.buffers[k], one);
          ++k;
          ++touched_total;
        } else {
          REQUIRE(one.empty());
          ++culled_total;
        }
      }
    }
  }
  CHECK(touched_total > 500);
  CHECK(culled_total > 5000);
  CHECK(sizes_seen > 20);  // the touched list grew and shrank
  // to_sections: one Section per object, to_section of the touched ones' buffers, the empty
  // section in the plane's frame for the others (as section() of a missed object).
  const auto pieces = to_sections(out, scene.objects.size());
  REQUIRE(pieces.size() == scene.objects.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const bool listed = k < out.size() && out.objects[k] == i;
    const Section expect =
        listed ? to_section(out.buffers[k++])
               : section(*scene.objects[i].complex, out.plane, scene.objects[i].transform);
    REQUIRE(pieces[i].complex.fvector() == expect.complex.fvector());
    REQUIRE(pieces[i].complex.ambient_dim() == 3);
    REQUIRE(pieces[i].complex.positions() == expect.complex.positions());
    REQUIRE(pieces[i].source == expect.source);
    REQUIRE(pieces[i].frame.plane.normal == out.plane.normal);
    REQUIRE(pieces[i].frame.basis == expect.frame.basis);
  }
}

TEST_CASE("scenes: culling by height decides as the sphere test at the spheres' edges",
          "[slicer][scene]") {
  // Objects whose bounding spheres end within a few ulps of the plane (and others far from
  // it), so that rounding decides: the repeated normal's culling (objects sorted by height)
  // must give the list of the full sphere test of a first call, object for object.
  std::mt19937 rng(8117);
  const auto tesseract = std::make_shared<const Complex>(load_model("tesseract"));
  const SliceModel model(*tesseract);
  const double r = model.radius();
  REQUIRE(model.centre().norm() == 0.0);  // the centre is the translation
  const Eigen::VectorXd n = test::random_unit(rng, 4);
  const double d = 3.7;
  std::uniform_real_distribution<double> u(-30.0, 30.0);
  std::uniform_int_distribution<int> ulps(-6, 6);
  Scene scene;
  std::size_t near = 0;
  for (int i = 0; i < 400; ++i) {
    Eigen::VectorXd p(4);
    p << u(rng), u(rng), u(rng), u(rng);
    p -= n.dot(p) * n;  // across the normal
    double h = u(rng);
    if (i % 2 == 0) {
      // Height d +- reach, the reach as SceneSlicer computes it (rigid: the model's radius),
      // then moved by a few ulps.
      const double side = i % 4 == 0 ? 1.0 : -1.0;
      for (int it = 0; it < 4; ++it) {
        const Eigen::VectorXd c = p + h * n;
        const double reach = r + tol::bounding_sphere_margin_rel * (r + c.norm());
        h = d + side * reach;
      }
      for (int k = ulps(rng); k != 0; k += k > 0 ? -1 : 1)
        h = std::nextafter(h, k > 0 ? 1e300 : -1e300);
      ++near;
    }
    SceneObject obj;
    obj.complex = tesseract;
    obj.model = "tesseract";
    obj.transform = AffineTransform::translation(p + h * n);
    scene.objects.push_back(obj);
  }
  SceneSlicer by_height(scene);
  SceneSlice out;
  by_height.slice(Hyperplane::from(n, d + 1.0), out, 1);  // the first call with the normal
  std::size_t in = 0;
  for (double e : {0.0, 1e-15, -1e-15, 4e-16}) {
    const Hyperplane plane = Hyperplane::from(n, d + e);
    by_height.slice(plane, out, 1);
    SceneSlicer full(scene);
    SceneSlice first;
    full.slice(plane, first, 1);
    REQUIRE(out.objects == first.objects);
    in += out.size();
  }
  CHECK(near == 200);
  CHECK(in > 40);       // some spheres at the edge are kept,
  CHECK(in < 4 * 150);  // some are not
}

TEST_CASE("scenes: an object cut again keeps its buffers and their topology cache",
          "[slicer][scene][cache]") {
  // The same plane culled, unculled (every object: the list changes, the positions shift),
  // culled again, and into outputs whose lists were changed by the caller: the buffers stay
  // exact, and each object whose buffers were a fast slice with the cache before is answered
  // by the cache (the sides cannot change for the same plane).
  std::mt19937 rng(8114);
  auto tesseract = std::make_shared<const Complex>(load_model("tesseract"));
  auto cell24 = std::make_shared<const Complex>(load_model("24-cell"));
  const Scene scene = random_scene(
      rng, 280, 10.0, [&](int i) { return i % 4 == 0 ? cell24 : tesseract; }, 5);
  std::vector<std::unique_ptr<SliceModel>> models;
  for (const SceneObject& obj : scene.objects) {
    models.push_back(std::make_unique<SliceModel>(*obj.complex));
    REQUIRE(models.back()->cluster_count() == 1);
  }
  Slicer oracle;
  SliceBuffers one;
  auto require_exact = [&](const SceneSlice& out, const Hyperplane& plane) {
    for (std::size_t k = 0; k < out.size(); ++k) {
      const std::uint32_t i = out.objects[k];
      oracle.slice(*models[i], plane, scene.objects[i].transform, one);
      require_identical(out.buffers[k], one);
    }
  };
  SceneSlicer slicer(scene);
  SliceOptions reuse, all;
  reuse.reuse_topology = true;
  all.reuse_topology = true;
  all.cull = false;
  const Hyperplane plane = random_plane(rng, 4, 10.0);
  SceneSlice out;
  std::size_t answered = 0;
  // The objects the last call cut on the fast path (with the cache). Only cut ones: an empty
  // slice with culling touched none of the model's clusters, one without touched them all (one
  // cluster per model here, so a cut model touches the same one either way).
  auto cached = [&](const SceneSlice& s) {
    std::vector<char> c(scene.objects.size(), 0);
    for (std::size_t k = 0; k < s.size(); ++k)
      c[s.objects[k]] = !s.buffers[k].general && !s.buffers[k].empty();
    return c;
  };
  for (int round = 0; round < 3; ++round) {
    for (const SliceOptions& o : {reuse, all, reuse}) {
      const std::vector<char> before = cached(out);
      slicer.slice(plane, out, 1, o);
      require_listed(out, slicer);
      require_exact(out, plane);
      for (std::size_t k = 0; k < out.size(); ++k)
        if (before[out.objects[k]]) {
          REQUIRE(out.buffers[k].reused_topology);
          ++answered;
        }
    }
    // A caller's changes to the output: its list reversed, one buffer more or one less; the
    // result is exact all the same.
    std::reverse(out.objects.begin(), out.objects.end());
    if (round == 0) out.buffers.emplace_back();
    if (round == 1 && !out.buffers.empty()) out.buffers.pop_back();
    if (round == 2) out.objects.clear();
    slicer.slice(plane, out, 1, reuse);
    require_listed(out, slicer);
    require_exact(out, plane);
  }
  CHECK(answered > 300);
}

TEST_CASE("a model in two pieces: planes between, through and beside them", "[slicer]") {
  // Regression: between the components no edge crosses although vertices lie on both sides;
  // both paths must give the empty section.
  Eigen::VectorXd shift = Eigen::VectorXd::Zero(4);
  shift(3) = 5.0;
  const Complex two = disjoint_union(load_model("tesseract"), shift);
  const SliceModel compiled(two);
  REQUIRE(compiled.fast());
  Slicer slicer;
  SliceBuffers out;
  Eigen::VectorXd n(4);
  n << 0.1, -0.2, 0.05, 1.0;
  for (double d : {2.5, 0.3, 5.2, -3.0}) {
    const Hyperplane plane = Hyperplane::from(n, d);
    slicer.slice(compiled, plane, out);
    REQUIRE_FALSE(out.general);
    const Section general = section_general(two, plane, AffineTransform::identity(4));
    require_same_section(to_section(out), general, 20.0);
    CHECK(out.empty() == (d == 2.5 || d == -3.0));
  }
}

TEST_CASE("one Slicer serves models of different sizes in turn", "[slicer][cache]") {
  std::mt19937 rng(8109);
  const Complex big = load_model("120-cell"), small = load_model("tesseract");
  const SliceModel a(big, {16, 8}), b(small);
  Slicer shared;
  SliceBuffers out, ref;
  SliceOptions reuse;
  reuse.reuse_topology = true;
  for (int i = 0; i < 60; ++i) {
    const SliceModel& m = (i / 3) % 2 == 0 ? a : b;  // three frames each, alternating
    const Hyperplane plane = Hyperplane::from(test::random_unit(rng, 4), 0.2 + 1e-6 * i);
    shared.slice(m, plane, out, reuse);
    Slicer().slice(m, plane, ref);
    require_identical(out, ref);
  }
}

TEST_CASE("one Slicer alternates tetrahedral models and models of small cells", "[slicer][cache]") {
  // The 600-cell's tetrahedra are cut from a table that reads only cut faces, the prism over a
  // tetrahedron's tetrahedra (4 faces, beside 5-face prisms) by chains that read every face:
  // whatever the first leaves behind must not reach the second (a section edge left from a
  // 600-cell slice would index past the prism's own, small, buffers: a sanitizer build reports
  // it). Each slice of the shared Slicer is compared with a Slicer that never saw the other
  // model, and with the general path.
  std::mt19937 rng(4431);
  const Complex tets = load_model("600-cell"), mixed = load_model("prism:simplex:3");
  const SliceModel a(tets), b(mixed);
  REQUIRE(!b.complex().boundary(3).empty());
  Slicer shared;
  SliceBuffers out_a, out_b, ref;
  std::size_t fast_mixed = 0;
  for (int i = 0; i < 80; ++i) {
    const bool first = (i / 2) % 2 == 0;  // two slices each, alternating
    const SliceModel& m = first ? a : b;
    SliceBuffers& out = first ? out_a : out_b;
    const Hyperplane plane = random_plane(rng, 4, first ? 0.8 : 0.6);
    const std::size_t generic_before = shared.generic_elements();
    shared.slice(m, plane, out);
    Slicer fresh;
    fresh.slice(m, plane, ref);
    require_identical(out, ref);
    REQUIRE(shared.generic_elements() - generic_before == fresh.generic_elements());
    if (!out.general && !first) ++fast_mixed;
    const Section general = section_general(m.complex(), plane, AffineTransform::identity(4));
    require_same_section(to_section(out), general, 2.0);
  }
  REQUIRE(fast_mixed >= 30);  // the mixed model's slices took the kernel's chains
}
