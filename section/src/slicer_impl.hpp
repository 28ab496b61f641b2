#pragma once
// The engine room behind the Slicer facade: every scratch buffer, the sweep's state and the
// passes of a slice (slicer.cpp: dispatch, the generic gathering, the topology cache, geometry;
// kernel.cpp: the R^4 kernel; sweep.cpp: sweeps). One Impl per Slicer, owned by it; a sweep's
// extra threads each own one more (helpers_). Private to section/src (not installed).
#include <cstdint>
#include <span>
#include <vector>

#include "slicer_detail.hpp"

namespace cw4d {

class Slicer::Impl {
 public:
  // --- what Slicer forwards to -------------------------------------------------------------
  void slice(const SliceModel::Compiled& model, const Hyperplane& plane,
             const AffineTransform& model_to_world, SliceBuffers& out,
             const SliceOptions& options = {});
  void slice(const SliceModel::Compiled& model, const Hyperplane& plane, SliceBuffers& out,
             const SliceOptions& options = {});
  void sweep(const SliceModel::Compiled& model, const Eigen::VectorXd& normal,
             std::span<const double> offsets, const AffineTransform& model_to_world,
             std::vector<SliceBuffers>& out, unsigned threads = 1);

  // --- the passes and their scratch ----------------------------------------------------------
  struct Term {
    std::uint32_t id;
    int coef;
  };
  struct Image {
    std::uint32_t gen = 0, begin = 0, count = 0;
  };
  struct Step {
    std::uint32_t tail, head, edge;
    int sign;
    bool used;
  };
  bool fast_slice(const SliceModel::Compiled& m, const Placement& pl, const SliceOptions& options,
                  SliceBuffers& out);
  void prepare(const SliceModel::Compiled& m);
  void size_images(const SliceModel::Compiled& m);  // (prepare leaves ranks 1, 2 to it in R^4)
  void clear_marks(const SliceModel::Compiled& m);
  void start_buffers(const SliceModel::Compiled& m, const Placement& pl, SliceBuffers& out);
  void start_kernel_buffers(const SliceModel::Compiled& m, const Placement& pl, SliceBuffers& out);
  // The crossing parameter of edge e from s_; false when it lies within the weld distance of
  // an end (the general path welds it).
  bool crossing(const SliceModel::Compiled& m, std::uint32_t e, double* t) const;
  bool add_crossing(const SliceModel::Compiled& m, std::uint32_t e, SliceBuffers& out);
  bool cut_upper(const SliceModel::Compiled& m, const Placement& pl, SliceBuffers& out,
                 int from = 2);
  // What the R^4 kernel made of a slice: the buffers (Done), a slice for the general path
  // (General, reason_ set), or something only the generic gathering decides (Generic: the
  // caller clears the marks and runs that instead).
  enum class KernelResult : std::uint8_t { Done, General, Generic };
  // The specialised kernel of a slice in R^4 (after the vertex pass). marked_edges: the
  // crossing edges are those marked in mark_[1] (a sweep's active edges).
  KernelResult kernel_slice(const SliceModel::Compiled& m, const Placement& pl, SliceBuffers& out,
                            bool marked_edges = false);
  bool reuse(const SliceModel::Compiled& m, const Placement& pl, const SliceOptions& options,
             SliceBuffers& out);
  void slice_placed(const SliceModel::Compiled& m, const Hyperplane& plane,
                    const AffineTransform* xf, SliceBuffers& out, const SliceOptions& options);
  void general_slice(const SliceModel::Compiled& m, const Hyperplane& plane,
                     const AffineTransform& xf, SliceBuffers& out);
  bool emit_element(const SliceModel::Compiled& m, int k, std::uint32_t x, SliceBuffers& out,
                    std::vector<std::uint32_t>& facets, std::vector<Term>& image);
  bool emit_loops(std::span<Term> chain, std::uint32_t source, SliceBuffers& out,
                  std::vector<Term>& image);
  bool finish_fast(const SliceModel::Compiled& m, const Placement& pl, SliceBuffers& out,
                   std::span<const std::uint32_t> section_edge,
                   std::span<const std::uint32_t> facet_internal);
  // The section vertices' positions and (facets: true) the facet normals of facet_internal;
  // facets: false leaves out.facet_normals as it is (a sweep writes them itself).
  bool write_geometry(const SliceModel::Compiled& m, const Placement& pl, SliceBuffers& out,
                      std::span<const std::uint32_t> section_edge,
                      std::span<const std::uint32_t> facet_internal, bool facets = true);
  void remember(const SliceModel::Compiled& m, const Placement& pl, SliceBuffers& out);
  void sweep_layers(const SliceModel::Compiled& m, const Hyperplane& plane,
                    const AffineTransform& xf, std::span<const double> offsets,
                    std::span<const std::uint32_t> layers, std::vector<SliceBuffers>& out);

  std::uint32_t gen_ = 0;
  // tol::near_parallel_edge * |A^T n|: a crossing edge with |s_a - s_b| below this times its
  // length is nearly parallel to the plane, left to the general path (section_general).
  double near_parallel_ = 0.0;
  std::vector<double> s_;
  std::vector<Side> side_;  // per vertex, Negative or Positive (On leaves the fast path)
  std::vector<std::vector<Image>> images_;  // images_[k][internal element of rank k]
  std::vector<std::vector<Term>> terms_;    // terms_[k]: storage of the images of rank k
  std::vector<Term> chain_, image_;
  std::vector<Step> steps_;
  std::vector<std::uint32_t> touched_;
  std::vector<std::vector<std::uint64_t>> mark_;  // mark_[k]: rank k elements to visit (bits)
  void mark_parents(const SliceModel::Compiled& m, int k, std::uint32_t x);
  bool fast_slice_marked(const SliceModel::Compiled& m, const Placement& pl,
                         const SliceOptions& options, SliceBuffers& out);
  std::vector<std::uint32_t> section_edge_;    // internal model edge of each section vertex
  std::vector<std::uint32_t> facet_internal_;  // internal model facet of each section facet
  std::vector<std::uint32_t> row_ids_;
  std::vector<std::int8_t> row_signs_;
  // sweep scratch: vertex heights, per layer (in offset order) the model-space offset and ON
  // band, the edges bucketed by the layer where they start crossing, the active edges.
  std::vector<double> height_, layer_d_, layer_tol_, edge_top_;
  std::vector<std::uint32_t> edge_start_, bucket_offsets_, bucket_ids_, active_, bucket_fill_;
  std::vector<char> layer_bad_;
  std::vector<std::uint32_t> sweep_order_;
  std::vector<Impl> helpers_;  // one per extra sweep thread, kept between sweeps
  // The output-sensitive sweep in R^4 (src/sweep.cpp): the section's structure in model terms
  // (crossing edges, each cut face's two crossing edges, each cut cell's loop of faces), kept
  // from layer to layer and updated only in the star of each vertex the plane passes.
  struct SweepSlot {
    std::uint32_t element, index;
  };
  struct SweepState {
    // The model's incidences, built once per model (serial): the (edge, other end) at each
    // vertex, the (face, row entry) of each edge, the (cell, row entry) of each face, and the
    // rows' entries in the form the passes read (see sweep_incidences).
    std::uint64_t model = 0;
    std::vector<std::uint32_t> vertex_edge_offsets, edge_face_offsets, face_cell_offsets;
    std::vector<SweepSlot> vertex_edges, edge_faces, face_cells, face_entries;
    std::vector<std::uint32_t> cell_entries;
    // Per sweep: the layer (in the thread's offset order) from which each vertex is below the
    // plane, the vertices grouped by that layer.
    std::vector<std::uint32_t> vertex_layer, layer_vertex_offsets, by_layer;
    std::vector<std::uint8_t> edge_in, face_state, cell_state;  // 0 uncut, 1 cut, 2 not kernel
    // Row entries (bits over the face rows' and cell rows' entries) whose edge crosses, whose
    // face is cut: a face or cell reads only those.
    std::vector<std::uint64_t> face_row_bits, cell_row_bits;
    std::vector<std::uint32_t> edges, faces, cells;                     // the cut ones, ascending
    std::vector<std::uint32_t> face_ends, cell_loop, cell_size, loops;  // face_ends: tail, head
    std::vector<std::int8_t> loop_signs, merged_signs;  // each loop entry's sign in its polygon
    std::vector<std::uint32_t> stamp_f, stamp_c, loop_stamp, loop_head, loop_entry;
    std::vector<std::uint32_t> near_f, near_c, merged, steps;
    std::vector<std::uint32_t> vertex_index, edge_index;
    std::vector<std::uint64_t> edge_bits, face_bits, cell_bits;  // the cut ones (when rebuilding)
    std::vector<std::uint32_t> toggled, spare;  // ids whose membership switched; list scratch
    // Each cell's section facet normal for the sweep's normal, and 1 (0: nearly parallel).
    std::vector<double> cell_normal;
    std::size_t live = 0;  // entries of the cut cells' loops
    std::uint32_t stamp = 0, loop_gen = 0, bad = 0;
  };
  SweepState sweep_;
  void sweep_events(const SliceModel::Compiled& m, Placement& pl, std::span<const double> offsets,
                    std::span<const std::uint32_t> layers, std::vector<SliceBuffers>& out,
                    const AffineTransform& xf, const Hyperplane& plane);
  void sweep_update(const SliceModel::Compiled& m, std::span<const std::uint32_t> moved,
                    bool rebuild);
  // slice() from the normal's part of the placement on (made by slice_placed, or cached by a
  // SceneSlicer); xf == nullptr: the identity.
  void slice_with(const SliceModel::Compiled& m, Placement& pl, const Hyperplane& plane,
                  const AffineTransform* xf, SliceBuffers& out, const SliceOptions& options);
  void general_from(const SliceModel::Compiled& m, const Hyperplane& plane,
                    const AffineTransform* xf, SliceBuffers& out);
  std::uint8_t sweep_face(const SliceModel::Compiled& m, std::uint32_t f);
  std::uint8_t sweep_cell(const SliceModel::Compiled& m, std::uint32_t c);
  void sweep_incidences(const SliceModel::Compiled& m);
  void sweep_normals(const SliceModel::Compiled& m, const Placement& pl);
  std::size_t fast_count_ = 0, cached_count_ = 0, kernel_count_ = 0, generic_count_ = 0;
  FallbackReason reason_ = FallbackReason::None;
  bool fail(FallbackReason r) {
    reason_ = r;
    return false;
  }
  bool kernel_ = true;
  // Kernel scratch: per section vertex the step leaving it in the current cell (stamped), per
  // section edge a stamp (a face listed twice in a cell goes to the generic gathering).
  std::uint32_t stamp_ = 0;
  std::vector<std::uint32_t> vertex_stamp_, vertex_next_, edge_stamp_;
  // kernel_slice scratch: per model face the crossings handed to it (count in face_mark_, the
  // two section vertices | coefficient bit in face_ends_) and, while its cells are cut, its
  // section edge (face_edge_; no_index when uncut), per model cell a mark (cell_mark_), per
  // section vertex the step leaving it in the current cell (stamped; large cells only).
  struct LoopStep {
    std::uint32_t stamp, head, edge;  // edge: section edge | 0x80000000 when reversed
  };
  std::vector<std::uint32_t> face_ends_, face_edge_;
  bool face_edge_stale_ = false;  // a slice without fixed-width chains left face_edge_ unreset
  std::vector<std::uint32_t> face_list_;   // the faces to cut
  std::vector<std::uint32_t> visit_list_;  // the cells to cut
  std::vector<std::uint32_t> crossing_ids_;
  std::vector<std::uint8_t> face_mark_, cell_mark_;
  std::vector<LoopStep> loop_step_;
  // Per cut cell (not a table's tetrahedron) of the slice the steps its cut faces handed it,
  // in cell_steps_ from cell_start_ up to cell_fill_ (placed by the cell's first cut face,
  // with room for its whole row; valid while the cell is marked).
  struct CellStep {
    std::uint32_t tail, head, edge;
  };
  std::vector<CellStep> cell_steps_;
  std::vector<std::uint32_t> cell_fill_, cell_start_;
  // When cell_steps_ has room for every cell's row (small models), each cut cell's bucket is at
  // its row instead, holding cell_taken_ steps (zero for every cell between slices).
  std::vector<std::uint32_t> cell_taken_;
  // The kernel's pass over the cut faces (kernel.cpp): Stride is the number of cells above
  // every face when the model has one (2 in a closed manifold), 0 when it varies; RoomChecked:
  // the buckets may be too small (else they have room for every cell's row). Returns the
  // first face not done: nse, or a face whose cells' buckets did not fit (room to grow).
  struct FaceHand;
  template <bool Buckets, bool RoomChecked, std::uint32_t Stride>
  static std::uint32_t hand_faces(FaceHand& h, std::uint32_t se);
  // stamp_ wrapped: clears the stamps of vertex_stamp_, edge_stamp_ and loop_step_.
  void forget_stamps();
};

}  // namespace cw4d
