#pragma once
// The arrays a SliceModel compiles (slice_model.cpp) and the slicer's passes read. Private to
// section/src (not installed).
#include <Eigen/Core>

#include <cstdint>
#include <span>
#include <vector>

#include "cw4d/section/slicer.hpp"

namespace cw4d {

struct SliceModel::Compiled {
  Compiled(const Complex& model, const SliceModelOptions& options);

  const Complex& complex() const { return *model_; }
  int dim() const { return dim_; }
  bool fast() const { return fast_; }
  std::size_t cluster_count() const { return cluster_vertex_.size() - 1; }
  bool compiled_from(const Complex& model) const;
  std::size_t bytes() const;

  struct Rank {
    std::size_t count = 0;  // elements
    // Rank 1 (the edges, [tail, head] with signs [-1, +1] in a fast model) keeps only its ids:
    // its offsets (2 i) and signs are implied, those vectors empty.
    std::vector<std::uint32_t> offsets, ids;
    std::vector<std::int8_t> signs;
    std::vector<std::uint32_t> model_id;  // internal id -> model id (empty: identity)
  };
  const Complex* model_;
  std::uint64_t serial_;           // unique per SliceModel constructed, for the topology cache
  std::uint64_t fingerprint_ = 0;  // model_fingerprint(*model_), handed to every slice
  int dim_ = 0;
  int top_ = 0;
  bool fast_ = false;
  // Vertices keep the model's ids. dim_ per vertex: a copy of the model's positions, or
  // (clustered models) empty, the model's own read instead.
  std::vector<double> positions_;
  std::size_t nv_ = 0;
  bool clustered_ = false;
  const double* positions() const {
    return positions_.empty() ? model_->positions().data() : positions_.data();
  }
  std::vector<Rank> ranks_;  // ranks_[k], k = 1..top_ (ranks_[0] unused)
  // up_offsets_[k], up_ids_[k]: the rank k + 1 elements whose boundary holds each element of
  // rank k (1 <= k < top_), so a slice visits only the elements its crossings reach; the top
  // bit of an up_ids_ entry is set when the element's sign in that boundary is negative.
  // When every element of rank k has the same number of cofaces, up_stride_[k] (else 0), its
  // offsets are implied and up_offsets_[k] is empty: read them through up(k).
  std::vector<std::vector<std::uint32_t>> up_offsets_, up_ids_;
  std::vector<std::uint32_t> up_stride_;
  struct Up {
    const std::uint32_t* offsets;
    const std::uint32_t* ids;
    std::uint32_t stride;
    std::uint32_t begin(std::uint32_t x) const { return stride ? x * stride : offsets[x]; }
    std::uint32_t end(std::uint32_t x) const { return stride ? (x + 1) * stride : offsets[x + 1]; }
  };
  Up up(int k) const { return {up_offsets_[k].data(), up_ids_[k].data(), up_stride_[k]}; }
  static constexpr std::uint32_t kUpIndex = 0x7fffffffu, kUpNegative = 0x80000000u;
  bool unit_signs_ = true;  // every sign of ranks 2 and 3 is +-1
  // Some cell (rank 3) has at most four faces: the R^4 kernel chains such a cell at a fixed
  // width, reading every one of its faces' section edges (uncut faces' too).
  bool small_cells_ = false;
  // Every face (rank 2) has at most three edges: the R^4 kernel hands a face at most three
  // crossings, so it counts them without a cap.
  bool triangle_faces_ = false;
  void build_cofaces();
  // One solid (rank dim_) whose boundary holds every facet exactly once: its cut is known.
  bool single_solid_ = false;
  std::vector<std::int8_t> solid_sign_;  // R^3: each facet's sign in the single solid
  void find_single_solid();
  // dim_ per internal facet; empty when clustered (the complex's are read through the facets'
  // model ids: renumbered models are never compared against the complex, see compiled_from).
  std::vector<double> facet_normals_;
  // The shortest and longest edge (slicer_detail::edge_length; NaN lengths left out): with them
  // a crossing's weld and near-parallel tests (CrossingTest, src/slicer_detail.hpp) need the
  // edge's own length only near the thresholds.
  double edge_min_ = 0.0, edge_max_ = 0.0;
  struct CrossingTest;
  CrossingTest crossing_test(double near_parallel) const;
  // R^4 models whose every cell is a tetrahedron: per cell its four vertices (ascending) and,
  // per pattern of their sides (bit k: vertex k above), its polygon as the kernel writes it:
  // bits 0-2 the length (3 or 4; 7: left to the generic gathering), bits 3 + 2 k and 4 + 2 k
  // entry k's face (its position in the cell's boundary), bit 11 + k set when that face's
  // section edge enters with -1 (the four signs one nibble, read at once). Empty otherwise.
  std::vector<std::uint32_t> tet_vertices_;
  std::vector<std::uint16_t> tet_cases_;
  void build_tet_tables();
  // Clusters: cluster c holds internal elements [begin_[k][c], begin_[k][c+1]) of rank k for
  // 1 <= k <= dim_-1 and needs the vertices listed in cluster_vertices_[cluster_vertex_[c] ...
  // cluster_vertex_[c + 1]); ranks above the facets are always processed. One cluster (no
  // reordering) for small models. A cluster's list is its vertex ids in increasing order, each
  // as its difference from the previous one (the first from -1) in one 16-bit word, or in two
  // when it is 2^15 or more (the first with the top bit set, holding the high bits).
  std::vector<std::vector<std::uint32_t>> begin_;
  std::vector<std::uint32_t> cluster_vertex_;
  std::vector<std::uint16_t> cluster_vertices_;
  void add_cluster(std::span<const std::uint32_t> vertices);  // (ascending)
  // Calls f(v) for the vertices of cluster c in increasing order while it returns true; false
  // when it stopped.
  template <class F>
  bool each_cluster_vertex(std::uint32_t c, F&& f) const {
    const std::uint16_t* w = cluster_vertices_.data();
    std::uint32_t v = 0xffffffffu;
    for (std::uint32_t i = cluster_vertex_[c], end = cluster_vertex_[c + 1]; i < end;) {
      std::uint32_t d = w[i++];
      if (d & 0x8000u) d = (d & 0x7fffu) << 16 | w[i++];
      v += d;
      if (!f(v)) return false;
    }
    return true;
  }
  std::vector<double> cluster_sphere_;  // (dim_ centre, radius) per cluster
  Eigen::VectorXd centre_;
  double radius_ = 0.0;
  double max_norm_ = 0.0;  // sqrt of the largest squared vertex norm (tolerance scale)
  double weld_ = 0.0;      // tol::weld_rel * bounding-box diagonal
};

}  // namespace cw4d
