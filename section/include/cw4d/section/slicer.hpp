#pragma once
// The hot path of the section: a model compiled once (SliceModel), a Slicer that owns every
// scratch buffer, and flat output (SliceBuffers) whose storage is reused, so that after the
// first slices of a model no memory is allocated. Culling, the topology cache for animation
// frames, sweeps and threads all give exactly (bit for bit) the buffers of the plain call
// Slicer::slice(model, plane, xf, out); section() is to_section() of that call.
//
// The fast path covers valid complexes in R^3 and R^4 with facet normals whose faces are cut in
// at most two points (cells may be non-convex). Anything else goes through the general layered
// cut (section_general), whose result is copied into the buffers: SliceBuffers::general is then
// true and SliceBuffers::fallback says why.
#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "cw4d/complex/complex.hpp"
#include "cw4d/complex/scene.hpp"
#include "cw4d/complex/transform.hpp"
#include "cw4d/section/hyperplane.hpp"
#include "cw4d/section/section.hpp"

namespace cw4d {

/// Why a slice left the fast path for the general layered cut (SliceBuffers::fallback).
enum class FallbackReason : std::uint8_t {
  None,          ///< the fast path made the buffers
  Model,         ///< the model is not fast() (dimension, no facet normals, ...)
  OnPlane,       ///< a vertex lies within the ON band of the plane
  Weld,          ///< a crossing lies within the weld distance of an edge's end
  FaceCut,       ///< a face cut in more than two points (or whose cut does not cancel)
  CellCut,       ///< a cell cut whose loops pinch or do not close
  Multiplicity,  ///< a chain coefficient other than +-1
  NearParallel,  ///< a facet nearly parallel to the plane (projected normal below the cut-off)
};
inline constexpr int kFallbackReasonCount = 8;
const char* to_string(FallbackReason r);

struct SliceModelOptions {
  /// Models with at least this many facets are split into clusters of cells for culling.
  std::size_t cluster_threshold = 4096;
  /// Facets per cluster.
  std::size_t cluster_size = 256;
  /// No clusters: elements keep the model's order, as section() numbers them.
  static SliceModelOptions unclustered() { return {static_cast<std::size_t>(-1), 256}; }
};

/// A complex compiled for slicing: its elements in flat compressed rows, renumbered cluster by
/// cluster when it is big (clusters of spatially close facets with a bounding sphere each, so a
/// plane skips the clusters it misses; vertices keep their ids), the bounding sphere, the
/// largest vertex norm and the weld distance. Immutable after construction and safe to share
/// between threads. Keeps a reference to `model`, which must outlive it unchanged (the general
/// path cuts the model itself, and a clustered model's slices read its positions and facet
/// normals); a moved-from SliceModel must not be sliced. The fast path assumes a valid complex
/// (validate()).
class SliceModel {
 public:
  /// \throw InputError when a boundary table of `model` names an element that does not exist
  /// (Incidence::well_formed fails: ids out of range, offsets out of order, signs not +-1).
  explicit SliceModel(const Complex& model, const SliceModelOptions& options = {});
  ~SliceModel();
  SliceModel(SliceModel&&) noexcept;
  SliceModel& operator=(SliceModel&&) noexcept;
  SliceModel(const SliceModel& other);
  SliceModel& operator=(const SliceModel& other);

  /// The model this was compiled from.
  const Complex& complex() const;
  /// Its ambient dimension.
  int dim() const;
  /// Whether the fast path can run on this model at all (R^3 or R^4, facet normals, every
  /// element below the facets bounds some element above, top rank n-1 or n).
  bool fast() const;
  /// Clusters of cells culled as a whole (1 when the model is not clustered).
  std::size_t cluster_count() const;
  /// Centre and radius of the model's bounding sphere (model space).
  const Eigen::VectorXd& centre() const;
  double radius() const;
  /// Whether this is the unclustered compilation of `model` as it is now: the same object and
  /// bit for bit the same positions, boundary tables and facet normals (a cheap linear check,
  /// for caches of compiled models).
  bool compiled_from(const Complex& model) const;
  /// Bytes of the compiled arrays (not counting the model).
  std::size_t bytes() const;

 private:
  friend class Slicer;
  friend class SceneSlicer;
  struct Compiled;  // the compiled arrays (src/slice_model_compiled.hpp)
  std::unique_ptr<Compiled> compiled_;
};

/// The flat section a Slicer writes: the same complex, frame, provenance and facet normals as
/// the Section that to_section() makes of it (model ids in vertex_source and source). Reusing
/// one SliceBuffers for the slices of an animation keeps its storage and lets the topology
/// cache reuse the previous slice's connectivity.
struct SliceBuffers {
  int dim = 0;                 ///< dimension of the section (the model's minus one)
  Hyperplane plane;            ///< the world-space plane
  std::vector<double> coords;  ///< dim per vertex, coordinates in HyperplaneFrame(plane)
  std::vector<VertexSource> vertex_source;
  std::vector<Incidence> boundary;  ///< boundary[r - 1]: the section's elements of rank r
  std::vector<std::vector<std::uint32_t>> source;  ///< source[r]: model element of rank r + 1
  std::vector<double> facet_normals;               ///< dim per facet (rank dim - 1), unit
  bool general = false;  ///< true when the general path made these buffers
  FallbackReason fallback = FallbackReason::None;  ///< why, when general
  bool reused_topology = false;          ///< true when the topology cache answered the last slice
  std::uint64_t source_fingerprint = 0;  ///< model_fingerprint of the model sliced

  std::size_t count(int rank) const {
    if (rank < 0) return 0;
    return rank == 0                                   ? vertex_source.size()
           : rank <= static_cast<int>(boundary.size()) ? boundary[rank - 1].size()
                                                       : 0;
  }
  bool empty() const { return vertex_source.empty(); }
  /// Triangles of a fan over every polygon (rank 2), what a GPU would draw.
  std::size_t fan_triangles() const;
  /// Resizes boundary to `top` tables and source to top + 1 lists, all empty; storage of
  /// dropped tables is kept for later slices.
  void set_ranks(int top);
  /// Drops the topology cache (the next slice into these buffers builds its own).
  void forget_topology() { cache_valid_ = false; }

 private:
  friend class Slicer;
  std::vector<Incidence> spare_tables_;
  std::vector<std::vector<std::uint32_t>> spare_sources_;
  // Topology cache: what the last fast slice decided.
  std::uint64_t cache_model_ = 0;  // SliceModel::serial_ (never reused, unlike addresses)
  std::vector<std::uint32_t> cache_touched_;  // clusters touched
  std::vector<std::int8_t> cache_side_;       // sides of their vertices, in that order
  std::vector<std::uint32_t> cache_edge_;     // internal edge of each section vertex
  std::vector<std::uint32_t> cache_facet_;    // internal facet of each section facet
  bool cache_reflect_ = false;
  bool cache_valid_ = false;
  // The section frame's basis (hyperplane_basis of frame_normal_, column-major), computed by
  // the slice for its placement and handed to to_section when the plane still has that normal.
  std::vector<double> frame_normal_, frame_basis_;
  friend Section to_section_untested(const SliceBuffers& buffers);
};

/// The Section of the buffers (as section() returns it, including self_intersecting).
Section to_section(const SliceBuffers& buffers);

struct SliceOptions {
  /// Skip clusters (and, in scenes, objects) whose bounding sphere misses the plane.
  bool cull = true;
  /// Reuse the connectivity already in `out` when the previous slice into `out` also asked for
  /// it, came from the same model, and no vertex changed side (only the crossing parameters,
  /// positions and normals are recomputed). Slices that do not ask keep no cache.
  bool reuse_topology = false;
  /// Cut faces and cells with the specialised kernel (face -> crossing pair, cell -> one loop
  /// through a next map); false uses only the generic chain gathering, which gives the same
  /// buffers bit for bit (for tests and benchmarks).
  bool kernel = true;
};

/// Scratch space for slicing, owned by the caller: one per thread, not thread-safe itself.
/// Keep one Slicer (and one SliceBuffers per output) for the slices of a model or an animation:
/// its buffers grow to the model's size once, after which slicing allocates nothing. Cheap to
/// move; copying copies the scratch.
class Slicer {
 public:
  Slicer();
  ~Slicer();
  Slicer(Slicer&&) noexcept;
  Slicer& operator=(Slicer&&) noexcept;
  Slicer(const Slicer& other);
  Slicer& operator=(const Slicer& other);

  /// Cuts `model` placed by model_to_world with the world-space plane into `out`.
  /// \throw InputError as section().
  void slice(const SliceModel& model, const Hyperplane& plane,
             const AffineTransform& model_to_world, SliceBuffers& out,
             const SliceOptions& options = {});
  /// Cuts `model` in place (the identity placement) with the plane into `out`.
  void slice(const SliceModel& model, const Hyperplane& plane, SliceBuffers& out,
             const SliceOptions& options = {});

  /// The sections with the planes {x : normal . x = offsets[i]} (normal need not be unit; it
  /// is normalised as Hyperplane::from does) in one pass over the model, output-sensitive in
  /// R^4: vertex heights are computed once, and the section's structure (crossing edges, cut
  /// faces, each cut cell's loop) is kept from layer to layer in offset order and renewed only
  /// around the vertices the plane passes; a layer that passes none copies the previous layer's
  /// connectivity and normals and computes only its crossing parameters and positions. (In R^3
  /// each layer is built from its active edges, bucketed by the first layer they cross, by the
  /// slice's own code.) out[i] is exactly what slice() gives for plane i; layers that need the
  /// general path, or the generic gathering, are cut by slice().
  /// threads > 1 splits the layers, in offset order, into that many groups of consecutive
  /// layers swept at once on their own threads (0: std::thread::hardware_concurrency()); the
  /// buffers are identical for every thread count.
  /// \throw InputError when the normal is zero or not finite, an offset is not finite, or the
  ///        dimensions disagree.
  void sweep(const SliceModel& model, const Eigen::VectorXd& normal,
             std::span<const double> offsets, const AffineTransform& model_to_world,
             std::vector<SliceBuffers>& out, unsigned threads = 1);

  /// Fast-path slices since construction.
  std::size_t fast_slices() const;
  /// Of those, the slices the topology cache answered.
  std::size_t cached_slices() const;
  /// Faces and cells the specialised kernel cut since construction.
  std::size_t kernel_elements() const;
  /// Faces and cells the kernel passed to the generic gathering since construction.
  std::size_t generic_elements() const;

 private:
  friend class SceneSlicer;
  struct Placement;  // the plane in model space and the output maps (src/slicer_detail.hpp)
  class Impl;        // the scratch, the sweep state and the passes (src/slicer_impl.hpp)
  std::unique_ptr<Impl> impl_;
};

/// What SceneSlicer::slice gives: the sections of the objects it did not cull, in increasing
/// object order. Culled objects (their bounding sphere misses the plane) have no entry: their
/// section is empty. Reuse one SceneSlice from call to call: its buffers' storage is kept, and
/// an object cut by consecutive calls keeps its buffers (and their topology cache).
struct SceneSlice {
  Hyperplane plane;                    ///< the world-space plane of the last slice
  std::vector<std::uint32_t> objects;  ///< the objects cut, increasing scene indices
  std::vector<SliceBuffers> buffers;   ///< buffers[k]: the section of object objects[k]
  std::size_t size() const { return objects.size(); }
};

/// One Section per object of a scene of `count` objects: to_section of its buffers for the
/// objects in slice.objects (each below count), the empty section in the frame of slice.plane
/// for the others.
std::vector<Section> to_sections(const SceneSlice& slice, std::size_t count);

/// A scene compiled for repeated slicing: one SliceModel per distinct model, a copy of every
/// object's placement and its world-space bounding sphere. A snapshot: objects moved later are
/// not seen (build a new SceneSlicer, or slice their models with a Slicer). Keeps references to
/// the scene's models, which must outlive it. Holds its own Slicers and spare buffers; one per
/// thread of the caller, not thread-safe itself.
class SceneSlicer {
 public:
  explicit SceneSlicer(const Scene& scene, const SliceModelOptions& options = {});
  ~SceneSlicer();
  SceneSlicer(SceneSlicer&&) noexcept;
  SceneSlicer& operator=(SceneSlicer&&) noexcept;

  /// The number of objects of the scene.
  std::size_t size() const;
  /// Cuts the objects whose bounding sphere meets the plane (every object when options.cull is
  /// false) into `out`: out.objects lists them, out.buffers[k] is exactly what Slicer::slice
  /// gives for object out.objects[k] (identical for every thread count and with or without
  /// culling; the objects left out have empty sections). A culled object costs only its sphere
  /// test, and with the same normal as the previous call not even that when its height is far
  /// from the offset (the objects are sorted by height once per normal). An object in
  /// out.objects before the call and after it keeps its buffers (moved to its new position), so
  /// SliceOptions::reuse_topology carries across calls; buffers no longer needed are kept by
  /// the SceneSlicer for later objects. threads = 0 uses std::thread::hardware_concurrency().
  /// Each touched object's placement of the plane in model space is kept while the normal
  /// stays the same (the transforms are fixed), so a sweep or animation of offsets redoes only
  /// the offset's part.
  /// \throw InputError when the plane's dimension differs from the scene's.
  void slice(const Hyperplane& plane, SceneSlice& out, unsigned threads = 1,
             const SliceOptions& options = {});
  /// Objects the last slice() did not cull.
  std::size_t touched() const;
  /// Their indices, increasing (the last slice's SceneSlice::objects).
  std::span<const std::uint32_t> touched_objects() const;

 private:
  class Impl;  // models, placements, culling state, slicers and spare buffers (scene_slicer.cpp)
  std::unique_ptr<Impl> impl_;
};

}  // namespace cw4d
