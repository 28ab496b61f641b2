#pragma once
// The tetrahedral slicer: each tetrahedron of a TetMesh cut by a hyperplane gives nothing, a
// triangle or a quad (two triangles), looked up in a 16-case sign table, with the corners'
// 4D normals and UVW interpolated along the cut edges. The CPU twin of a GPU slicing shader and
// the second, independent section path beside cw4d::section.
#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

#include "cw4d/complex/transform.hpp"
#include "cw4d/section/hyperplane.hpp"
#include "cw4d/section/section.hpp"
#include "cw4d/section/uvw.hpp"
#include "cw4d/tetrahedralize/tet_mesh.hpp"

namespace cw4d {

/// Where a corner of a slice triangle comes from: a crossing of mesh edge (a, b) at parameter t
/// (position (1 - t) p_a + t p_b, a < b), or mesh vertex a itself (a == b, t = 0) when it lies on
/// the plane.
struct TetCutPoint {
  std::uint32_t a = 0, b = 0;
  double t = 0.0;
  friend bool operator==(const TetCutPoint& x, const TetCutPoint& y) {
    return x.a == y.a && x.b == y.b;
  }
};

/// A triangle soup: corner k of triangle i is column / entry 3 i + k. Triangles are oriented
/// outward (counter-clockwise seen from outside the section solid, in frame coordinates): the
/// table gives the corners in cycle order, and each polygon is turned so that its normal points
/// along its cell's outward normal projected into the plane.
struct TetSection {
  HyperplaneFrame frame;
  Eigen::Matrix3Xd positions;  ///< 3 x 3T, section coordinates (frame.basis)
  Eigen::Matrix3Xd normals;  ///< 3 x 3T, the interpolated 4D normal projected into the plane, unit
  Eigen::Matrix3Xd uvw;  ///< 3 x 3T, interpolated texture coordinates (3 x 0 when not asked for)
  std::vector<TetCutPoint> corners;  ///< 3T
  std::vector<std::uint32_t> tet;    ///< T: source tetrahedron
  std::vector<std::uint32_t> cell;   ///< T: source 3-cell of the model

  std::size_t triangle_count() const { return tet.size(); }
  bool empty() const { return tet.empty(); }
  /// Volume enclosed by the triangles (divergence theorem; positive for an outward surface).
  double volume() const;
  /// Total triangle area.
  double area() const;
};

/// The allocator of TetSliceMesh's arrays: std::allocator, except that an element made without a
/// value is default-initialised rather than value-initialised, so that `resize` to a larger size
/// leaves the new doubles and integers unwritten (classes such as TetCutPoint still run their
/// default constructor). The slicer writes every element of its output, and a slice larger than
/// the one before then costs no zero fill of the arrays' new part. Code that resizes such an
/// array itself must write the new elements before reading them.
template <class T>
struct DefaultInitAllocator : std::allocator<T> {
  using value_type = T;
  template <class U>
  struct rebind {
    using other = DefaultInitAllocator<U>;
  };
  DefaultInitAllocator() noexcept = default;
  template <class U>
  DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}
  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

/// A TetSliceMesh array: a std::vector whose growth does not zero-fill (DefaultInitAllocator).
/// Compare it with a std::vector through std::ranges::equal or its iterators.
template <class T>
using TetSliceArray = std::vector<T, DefaultInitAllocator<T>>;

/// The same slice as an indexed triangle mesh: one vertex per mesh edge crossing the plane (and
/// per mesh vertex on it), triangles as vertex ids. The crossing of an edge is computed once and
/// shared by every tetrahedron around that edge, so neighbouring triangles are welded. Flat
/// arrays whose storage is kept between slices. The triangles are TetSection's, in the same
/// order with the same corner order, sources, normals and uvw (the same bits: the soup computes
/// each crossing per tetrahedron by the same formulas); to_soup gives the soup of this mesh
/// exactly. Vertex
/// order is deterministic but otherwise unspecified.
struct TetSliceMesh {
  HyperplaneFrame frame;
  /// 3V: vertex v at [3v, 3v + 3), section coordinates (frame.basis).
  TetSliceArray<double> positions;
  /// V: where each vertex comes from (a crossing of mesh edge (a, b), a < b, at t, or mesh
  /// vertex a on the plane, a == b). No two vertices have the same (a, b).
  TetSliceArray<TetCutPoint> vertex_source;
  /// 3T: the vertex ids of triangle i at [3i, 3i + 3), counter-clockwise seen from outside.
  TetSliceArray<std::uint32_t> triangles;
  /// 3T: the unit normal of triangle i (its cell's outward normal projected into the plane).
  TetSliceArray<double> normals;
  /// 9T: texture coordinates of corner k of triangle i at [9i + 3k, 9i + 3k + 3), interpolated
  /// along the cut edge of the source tetrahedron (corners of different cells differ); empty
  /// when the slicer's options leave UVW out.
  TetSliceArray<double> uvw;
  TetSliceArray<std::uint32_t> tet;   ///< T: source tetrahedron
  TetSliceArray<std::uint32_t> cell;  ///< T: source 3-cell of the model

  std::size_t vertex_count() const { return vertex_source.size(); }
  std::size_t triangle_count() const { return tet.size(); }
  bool empty() const { return tet.empty(); }
  /// Empties every array, keeping their storage (the frame is left as it is).
  void clear() {
    positions.clear();
    vertex_source.clear();
    triangles.clear();
    normals.clear();
    uvw.clear();
    tet.clear();
    cell.clear();
  }
  Eigen::Map<const Eigen::Matrix3Xd> position_matrix() const {
    return {positions.data(), 3, static_cast<Eigen::Index>(vertex_count())};
  }
  Eigen::Vector3d position(std::size_t v) const {
    return {positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]};
  }
};

/// The triangle soup of an indexed slice: corner k of triangle i gets the position and source of
/// its vertex, the triangle's normal and its own uvw (none when the slice has none).
void to_soup(const TetSliceMesh& slice, TetSection& out);

/// The 16-case table: for the sign mask m (bit k set when corner k is on the positive side),
/// kTetCutTable[m] lists the cut edges (corner pairs) in cycle order; 0, 3 or 4 entries.
struct TetCutCase {
  int count;
  std::array<std::array<int, 2>, 4> edges;
};
extern const std::array<TetCutCase, 16> kTetCutTable;

/// What a TetSlicer computes besides the triangles, their positions, normals and sources.
struct TetSliceOptions {
  /// Per-corner texture coordinates (TetSection::uvw, TetSliceMesh::uvw). Off, those arrays are
  /// left empty and a slice costs about 30 % less (the interpolation and its 9 doubles per
  /// triangle are most of the triangle pass); everything else is the same, bit for bit.
  bool uvw = true;
};

/// The tetrahedral slicer: the cut of a TetMesh by a hyperplane, with every scratch buffer it
/// needs kept from one slice to the next. The caller owns it (one per thread: a TetSlicer is not
/// shared between threads) and the output buffers; once both have grown to a model's largest
/// slice, slicing into a TetSliceMesh or a TetSection allocates nothing when no mesh vertex lies
/// on the plane (planes through vertices take the general loop, which allocates).
///
/// Sides are decided by classify_side with the tolerance cw4d::section uses; on-plane vertices
/// count as positive, and when that leaves nothing, as negative (a plane containing a facet
/// returns that facet), exactly like cw4d::section. Degenerate triangles (two corners from the
/// same on-plane vertex) are dropped. Precondition: the mesh's own arrays agree (tets and
/// tet_cell with ids below the vertex and cell counts, 4 corner_uvw columns per tetrahedron), as
/// tetrahedralize leaves them; they are not checked per slice (a pass over the ids would add
/// 5-7 % to a 120- or 600-cell slice). Its edge index is checked (below).
/// \throw InputError when the plane or transform is not 4D.
class TetSlicer {
 public:
  TetSlicer();
  explicit TetSlicer(TetSliceOptions options);
  /// What the next slices compute (the output buffers keep their storage when it changes).
  void set_options(TetSliceOptions options) { options_ = options; }
  const TetSliceOptions& options() const { return options_; }
  ~TetSlicer();
  TetSlicer(TetSlicer&&) noexcept;
  TetSlicer& operator=(TetSlicer&&) noexcept;
  TetSlicer(const TetSlicer&) = delete;
  TetSlicer& operator=(const TetSlicer&) = delete;

  /// The indexed slice (the fast form: each crossing computed once per slice, from the mesh's
  /// edge ids, and shared by every tetrahedron around the edge; polygons turned by the sign
  /// table's combinatorial orientation), written into `out`, whose storage is reused. Planes
  /// through mesh vertices take the general loop, welded. Precondition: the mesh's edge and
  /// block index describes its tets (as tetrahedralize leaves it; call index_tet_edges after
  /// editing `tets` or `tet_cell` in place, or clear `tet_edges` to have the slicer index a
  /// copy). An index with ids out of range is noticed and a copy indexed instead; one whose ids
  /// are in range but name other corners (TetMesh::has_edge_index false) gives a wrong section.
  void slice(const TetMesh& mesh, const Hyperplane& plane, const AffineTransform& model_to_world,
             TetSliceMesh& out);
  void slice(const TetMesh& mesh, const Hyperplane& plane, TetSliceMesh& out);
  /// The triangle soup, each tetrahedron cut on its own (its crossings the same bits as the
  /// indexed slice's), written into `out`, whose storage is reused.
  void slice(const TetMesh& mesh, const Hyperplane& plane, const AffineTransform& model_to_world,
             TetSection& out);
  void slice(const TetMesh& mesh, const Hyperplane& plane, TetSection& out);
  /// The soup in a new TetSection (its arrays allocated for this slice).
  TetSection slice(const TetMesh& mesh, const Hyperplane& plane,
                   const AffineTransform& model_to_world);
  TetSection slice(const TetMesh& mesh, const Hyperplane& plane);

  struct Scratch;  ///< (internal)

 private:
  std::unique_ptr<Scratch> scratch_;
  TetSliceOptions options_;
};

/// The slices of TetSlicer through one TetSlicer per thread (kept between calls).
TetSection slice_tets(const TetMesh& mesh, const Hyperplane& plane,
                      const AffineTransform& model_to_world);
TetSection slice_tets(const TetMesh& mesh, const Hyperplane& plane);
void slice_tets(const TetMesh& mesh, const Hyperplane& plane, const AffineTransform& model_to_world,
                TetSection& out);
void slice_tets(const TetMesh& mesh, const Hyperplane& plane, TetSection& out);
void slice_tets(const TetMesh& mesh, const Hyperplane& plane, const AffineTransform& model_to_world,
                TetSliceMesh& out);
void slice_tets(const TetMesh& mesh, const Hyperplane& plane, TetSliceMesh& out);

/// The slice as a Section of `model` (the complex the mesh was made from): a 3D complex of the
/// triangles with welded vertices, source cells in source[2], facet normals (the projected cell
/// normals), so every section writer can write it. vertex_source: rank 0 for a model vertex (or
/// a Steiner point id >= model.count(0)); rank 1 with the model edge and its t for crossings of
/// model edges, and element no_index (t along the tetrahedron edge) for crossings of
/// the diagonals the tetrahedralization added: consumers that look up model edges must skip
/// those (section_uvw cannot be used on it; the slice carries its own uvw).
Section to_section(const TetSection& slice, const Complex& model);

/// The texture coordinates of `section` = to_section(slice, model), corner by corner from the
/// slice's own UVW (interpolated along the cut tetrahedron edges), in the layout section_uvw
/// gives for the CW path, so that the exporters write both alike.
/// \throw InputError when `section` is not to_section(slice, ...) (other face count or corners).
CornerUvw tet_section_uvw(const TetSection& slice, const Section& section);

}  // namespace cw4d
