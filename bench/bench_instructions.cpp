// A driver for counting instructions (valgrind --tool=callgrind), the figure that does not drift
// with a shared machine's load: bench/compare.sh with COUNT=1 runs it from both builds (an older
// commit and the working tree) and prints the instructions per operation of each.
//
//   bench_instructions MODE MODEL ROUNDS
//
// One warm-up operation, then ROUNDS rounds of 256 operations of MODE on MODEL, the same work as
// bench_compare's case of that name:
//   slice    Slicer::slice over bench::generic_planes (256 generic planes)
//   section  cw4d::section(model, plane) over the same planes
//   tet      a TetSlicer over the model's tetrahedral mesh, the same planes, into one reused
//            TetSliceMesh
//   tet-nouvw  the same with TetSliceOptions::uvw off (trees that have the option)
//   sweep    Slicer::sweep of 256 parallel layers (bench_compare's sweep), one sweep a round
//   sweep-slices  the same 256 layers as 256 calls of Slicer::slice, a round
//   sweep-copy    the same 256 layers copied (SliceBuffers assignment into buffers kept from
//            round to round) from one sweep made before counting: the cost of writing the
//            output alone, the floor of any sweep that writes every layer's arrays
//   atlas    section_atlas along the sweep's normal, one atlas a round (so the count of one
//            atlas is (ROUNDS = 3 minus ROUNDS = 1) / 2, not / 512)
//   general  Slicer::slice over 256 degenerate planes (the general path): plane i is normal to
//            coordinate axis i mod n through model vertex 37 i mod V, the kind of plane a viewer
//            meets at d = 0 (every vertex and edge in the plane is cut exactly)
// The count of one operation is (count at ROUNDS = 3 minus count at ROUNDS = 1) / 512: the
// model's loading, compilation and the warm-up cancel out. Only API that both trees have is
// used (newer entry points where the headers announce them), as in bench_compare.cpp.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "bench_options.hpp"
#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/transform.hpp"
#include "cw4d/section/atlas.hpp"
#include "cw4d/section/section.hpp"
#include "cw4d/section/slicer.hpp"
#include "cw4d/tetrahedralize/tet_mesh.hpp"
#include "cw4d/tetrahedralize/tet_slice.hpp"

namespace cw4d {
struct TetSliceOptions;  // (complete where the headers have it: compare.sh builds older trees too)
}  // namespace cw4d

namespace {

// A TetSlicer with UVW on or off; false where the headers have no TetSliceOptions (then only
// with UVW).
template <class Options = cw4d::TetSliceOptions>
bool set_tet_uvw(cw4d::TetSlicer& slicer, bool uvw) {
  if constexpr (requires { sizeof(Options); }) {
    slicer.set_options(Options{uvw});
    return true;
  } else {
    return uvw;
  }
}

int usage() {
  std::fprintf(stderr,
               "usage: bench_instructions "
               "slice|section|tet|tet-nouvw|sweep|sweep-slices|sweep-copy|atlas|general "
               "MODEL "
               "ROUNDS\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) return usage();
  const std::string mode = argv[1];
  const int rounds = std::atoi(argv[3]);
  if (rounds < 0) return usage();
  const cw4d::Complex model = cw4d::load_model(argv[2]);
  const std::vector<cw4d::Hyperplane> planes = cw4d::bench::generic_planes(model, 256, 20240401u);
  std::size_t sink = 0;
  if (mode == "slice") {
    const cw4d::SliceModel compiled(model, cw4d::SliceModelOptions::unclustered());
    cw4d::Slicer slicer;
    cw4d::SliceBuffers out;
    slicer.slice(compiled, planes[0], out);
    for (int r = 0; r < rounds; ++r)
      for (const auto& p : planes) {
        slicer.slice(compiled, p, out);
        sink += out.vertex_source.size();
      }
  } else if (mode == "general") {
    const cw4d::SliceModel compiled(model, cw4d::SliceModelOptions::unclustered());
    const int n = model.ambient_dim();
    std::vector<cw4d::Hyperplane> through;
    for (std::uint32_t i = 0; i < 256; ++i) {
      Eigen::VectorXd axis = Eigen::VectorXd::Zero(n);
      axis[static_cast<Eigen::Index>(i % static_cast<std::uint32_t>(n))] = 1.0;
      const auto v = static_cast<Eigen::Index>((37u * i) % model.count(0));
      through.push_back(cw4d::Hyperplane::from(axis, axis.dot(model.positions().col(v))));
    }
    cw4d::Slicer slicer;
    cw4d::SliceBuffers out;
    slicer.slice(compiled, through[0], out);
    for (int r = 0; r < rounds; ++r)
      for (const auto& p : through) {
        slicer.slice(compiled, p, out);
        sink += out.vertex_source.size() + (out.general ? 1 : 0);
      }
  } else if (mode == "section") {
    sink += cw4d::section(model, planes[0]).vertex_source.size();
    for (int r = 0; r < rounds; ++r)
      for (const auto& p : planes) sink += cw4d::section(model, p).vertex_source.size();
  } else if (mode == "tet" || mode == "tet-nouvw") {
    const cw4d::TetMesh mesh = cw4d::tetrahedralize(model);
    cw4d::TetSliceMesh out;
    cw4d::TetSlicer slicer;
    if (!set_tet_uvw(slicer, mode == "tet")) {
      std::fprintf(stderr, "bench_instructions: this tree's TetSlicer always computes UVW\n");
      return 2;
    }
    auto cut = [&](const cw4d::Hyperplane& p) { slicer.slice(mesh, p, out); };
    cut(planes[0]);
    for (int r = 0; r < rounds; ++r)
      for (const auto& p : planes) {
        cut(p);
        sink += out.triangle_count();
      }
  } else if (mode == "sweep" || mode == "sweep-slices" || mode == "sweep-copy") {
    const cw4d::SliceModel compiled(model, cw4d::SliceModelOptions::unclustered());
    cw4d::Slicer slicer;
    Eigen::VectorXd normal(4);
    normal << 0.5377, 1.8339, -2.2588, 0.8622;
    normal.normalize();
    const double radius = cw4d::max_radius(model);
    std::vector<double> offsets(256);
    for (std::size_t i = 0; i < offsets.size(); ++i)
      offsets[i] = radius * (-0.95 + 1.9 * (static_cast<double>(i) + 0.5) / 256.0);
    const cw4d::AffineTransform id = cw4d::AffineTransform::identity(4);
    std::vector<cw4d::SliceBuffers> layers;
    const bool sweep = mode == "sweep";
    std::vector<cw4d::SliceBuffers> made;
    if (mode == "sweep-copy") slicer.sweep(compiled, normal, offsets, id, made);
    auto round = [&] {
      if (!made.empty()) {
        layers.resize(made.size());
        for (std::size_t i = 0; i < made.size(); ++i) layers[i] = made[i];
      } else if (sweep) {
        slicer.sweep(compiled, normal, offsets, id, layers);
      } else {
        layers.resize(offsets.size());
        for (std::size_t i = 0; i < offsets.size(); ++i)
          slicer.slice(compiled, cw4d::Hyperplane::from(normal, offsets[i]), layers[i]);
      }
      sink += layers.size();
    };
    round();
    for (int r = 0; r < rounds; ++r) round();
  } else if (mode == "atlas") {
    Eigen::VectorXd normal(4);
    normal << 0.5377, 1.8339, -2.2588, 0.8622;
    sink += cw4d::section_atlas(model, normal).intervals.size();
    for (int r = 0; r < rounds; ++r) sink += cw4d::section_atlas(model, normal).intervals.size();
  } else {
    return usage();
  }
  std::printf("%zu\n", sink);
  return 0;
}
