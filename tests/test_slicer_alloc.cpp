// The hot path allocates nothing once warm: global operator new is counted in this executable.
#include <catch2/catch.hpp>

#include <atomic>
#include <cstdlib>
#include <new>
#include <random>
#include <vector>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/section/slicer.hpp"
#include "support/planes.hpp"

namespace {
std::atomic<std::size_t> allocations{0};
}

// Every replaceable form that pairs with free(), so no allocation escapes the count and no
// sanitizer sees an operator new of its own released by ours (or the other way round).
// (The aligned forms are left alone: they allocate and free through their own pair.)
namespace {
void* counted(std::size_t size) {
  ++allocations;
  return std::malloc(size ? size : 1);
}
}  // namespace

void* operator new(std::size_t size) {
  if (void* p = counted(size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) {
  if (void* p = counted(size)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  return counted(size);
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  return counted(size);
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}
void operator delete[](void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}

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
    const std::size_t before = allocations.load();
    run();
    CHECK(allocations.load() - before == 0);
    // All generic planes: nothing fell back to the general path (which allocates).
    CHECK(slicer.fast_slices() + slicer.cached_slices() == 6 * planes.size());
  }
}
