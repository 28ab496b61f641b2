// The hot path allocates nothing once warm: global operator new is counted in this executable.
#include <catch2/catch.hpp>

#include <random>
#include <vector>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/section/section.hpp"
#include "cw4d/section/slicer.hpp"
#include "support/counting_new.hpp"
#include "support/planes.hpp"

using namespace cw4d;

TEST_CASE("slicing allocates nothing after warm-up", "[slicer][alloc]") {
  for (const char* spec : {"120-cell", "600-cell", "tesseract"}) {
    INFO(spec);
    const Complex model = load_model(spec);
    const SliceModel compiled(model, {16, 8});  // clustered, so culling runs too
    std::mt19937 rng(8107);
    std::vector<Hyperplane> planes;
    for (int i = 0; i < 200; ++i)
      planes.push_back(
          Hyperplane::from(test::random_unit(rng, 4),
                           std::uniform_real_distribution<double>(-1, 1)(rng) * compiled.radius()));
    const AffineTransform xf = AffineTransform::rotation(4, 0, 3, 0.3);
    Slicer slicer;
    SliceBuffers out;
    SliceOptions reuse;
    reuse.reuse_topology = true;
    auto run = [&] {
      for (const auto& p : planes) slicer.slice(compiled, p, xf, out);
      for (const auto& p : planes) slicer.slice(compiled, p, xf, out, reuse);
      for (const auto& p : planes) slicer.slice(compiled, p, out);  // identity placement
    };
    run();  // warm-up: the buffers grow to their largest
    const std::size_t before = test::allocation_count();
    run();
    CHECK(test::allocation_count() - before == 0);
    // All generic planes: nothing fell back to the general path (which allocates).
    CHECK(slicer.fast_slices() + slicer.cached_slices() == 6 * planes.size());
  }
}

TEST_CASE("section() allocates only the arrays of the Section it returns", "[slicer][alloc]") {
  // The oracle: the std::vector arrays reachable from the returned Section that hold anything
  // (its boundary tables, provenance lists, vertex sources, the complex's table and color
  // lists); a new table of a Complex allocates nothing until it is filled. Eigen's
  // matrices (positions, facet normals, the frame) allocate through their own aligned pair and
  // are not counted here.
  for (const char* spec : {"tesseract", "24-cell", "600-cell"}) {
    INFO(spec);
    const Complex model = load_model(spec);
    std::mt19937 rng(4411);
    std::vector<Hyperplane> planes;
    for (int i = 0; i < 50; ++i)
      planes.push_back(Hyperplane::from(test::random_unit(rng, 4),
                                        std::uniform_real_distribution<double>(-0.5, 0.5)(rng)));
    for (const auto& p : planes) (void)section(model, p);  // warm-up: scratch and compiled model
    for (const auto& p : planes) {
      const std::size_t before = test::allocation_count();
      const Section s = section(model, p);
      const std::size_t made = test::allocation_count() - before;
      std::size_t arrays = 0;
      const auto count = [&](const auto& v) { arrays += v.empty() ? 0 : 1; };
      const Complex& c = s.complex;
      arrays += c.top_rank() > 0 ? 1 : 0;  // the list of tables
      for (int r = 1; r <= c.top_rank(); ++r) {
        count(c.boundary(r).all_ids());
        count(c.boundary(r).all_signs());
        count(c.boundary(r).offsets());
      }
      count(s.vertex_source);
      count(s.source);
      for (const auto& v : s.source) count(v);
      count(s.object_of_face);
      CHECK(made <= arrays);
    }
  }
}

TEST_CASE("a new complex and a new boundary table allocate nothing", "[complex][alloc]") {
  const std::size_t before = test::allocation_count();
  const Incidence table;
  CHECK(test::allocation_count() - before == 0);
  Complex c(3);  // no tables, no colors: nothing allocated either
  CHECK(test::allocation_count() - before == 0);
  const std::size_t with_complex = test::allocation_count();
  c.boundary_mut(3);  // three empty tables: only the list that holds them is allocated
  CHECK(test::allocation_count() - with_complex == 1);
  CHECK(c.top_rank() == 3);
  for (int r = 1; r <= 3; ++r) CHECK(c.boundary(r).offsets() == std::vector<std::uint32_t>{0});
}
