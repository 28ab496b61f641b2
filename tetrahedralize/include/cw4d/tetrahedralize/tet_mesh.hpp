#pragma once
// Tetrahedral meshes of the 3-cells of a closed 4D complex: what GPU 4D renderers consume, and
// the second, independent section path (tet_slice.hpp).
//
// Every polygonal face of the complex is triangulated once for the whole complex (convex faces
// fan out from their first vertex in a global vertex order, other faces are ear-clipped), so two
// cells sharing a face see the same triangles and the mesh is conforming. Convex cells are coned
// from their first vertex in that order over the triangles of the faces that do not contain it
// (the faces that contain it are then fanned from that same vertex, so both agree); combinatorial
// cubes use the 5-tetrahedron split when their face diagonals allow it. The global order puts
// one colour class of a 2-colouring of the edge graph first when the graph is bipartite, so every
// square face of the tesseract gets its "even" diagonal: 40 tetrahedra, not 48. Non-convex cells
// go through TetGen (-pY: no Steiner points on the boundary, so it stays conforming). TetGen runs
// in a forked child process (Debian's build keeps assert()s that abort on bad input, and it
// prints): a failure or a crash there becomes a MeshingError here, never an exit.
#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "cw4d/complex/complex.hpp"
#include "cw4d/complex/error.hpp"

namespace cw4d {

/// Tetrahedralizing a cell failed (TetGen rejected its boundary: self-intersecting, not closed,
/// ...). rank() is 3 and ids() the offending cell; tetgen_code() is TetGen's error code (0 when
/// the failure was detected before calling TetGen).
class MeshingError : public TopologyError {
 public:
  MeshingError(std::uint32_t cell, int tetgen_code, const std::string& message)
      : TopologyError(3, {cell}, message), tetgen_code_(tetgen_code) {}
  int tetgen_code() const { return tetgen_code_; }

 private:
  int tetgen_code_;
};

/// A tetrahedral mesh of the boundary 3-cells of a 4D complex, with per-corner attributes.
/// Corner k (0..3) of tetrahedron t is entry 4 t + k of the corner arrays.
struct TetMesh {
  /// 4 x V. The first count(0) columns are the model's vertices (same ids); TetGen's interior
  /// Steiner points of non-convex cells follow.
  Eigen::Matrix4Xd positions;
  /// Vertex ids of each tetrahedron, oriented with its cell's outward normal N:
  /// det(N, p1 - p0, p2 - p0, p3 - p0) > 0 (the Stokes convention of complex.hpp).
  std::vector<std::array<std::uint32_t, 4>> tets;
  /// Source 3-cell of each tetrahedron.
  std::vector<std::uint32_t> tet_cell;
  /// Outward unit 4D normal of each model cell, 4 x C (copied from the complex).
  Eigen::Matrix4Xd cell_normals;
  /// Texture coordinate of each corner, 3 x 4T (see UvwMapping).
  Eigen::Matrix3Xd corner_uvw;
  /// The edges of the tetrahedra, each once, as vertex pairs {a, b} with a < b, numbered in order
  /// of first appearance (tetrahedron by tetrahedron, corner pairs in kTetEdgeCorners order).
  /// Filled by tetrahedralize; index_tet_edges rebuilds them after `tets` was changed.
  std::vector<std::array<std::uint32_t, 2>> edges;
  /// Edge ids of each tetrahedron's six corner pairs, in kTetEdgeCorners order.
  std::vector<std::array<std::uint32_t, 6>> tet_edges;
  /// Runs of consecutive tetrahedra of one cell ("blocks"): block b is the tetrahedra
  /// [block_first[b], block_first[b + 1]). The slicer skips a block whose vertices are all on one
  /// side without looking at its tetrahedra.
  std::vector<std::uint32_t> block_first;
  /// The distinct vertices of block b: block_vertices[block_vertex_first[b] ..
  /// block_vertex_first[b + 1]).
  std::vector<std::uint32_t> block_vertex_first, block_vertices;

  /// The corner pairs of a tetrahedron's edges, in the order of tet_edges.
  static constexpr std::array<std::array<int, 2>, 6> kTetEdgeCorners = {
      {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}}};
  /// Whether edges, tet_edges and the blocks describe the current tets and tet_cell (every edge's
  /// ends, every block's range and vertices).
  bool has_edge_index() const;

  std::size_t size() const { return tets.size(); }
  std::size_t cell_count() const { return static_cast<std::size_t>(cell_normals.cols()); }
  Eigen::Vector4d corner_position(std::size_t t, int k) const {
    return positions.col(tets[t][static_cast<std::size_t>(k)]);
  }
  Eigen::Vector4d tet_normal(std::size_t t) const { return cell_normals.col(tet_cell[t]); }
  Eigen::Vector3d corner_uvw_of(std::size_t t, int k) const {
    return corner_uvw.col(static_cast<Eigen::Index>(4 * t + static_cast<std::size_t>(k)));
  }
  /// Unsigned 3-volume of tetrahedron t.
  double tet_volume(std::size_t t) const;
  /// det(N, p1 - p0, p2 - p0, p3 - p0) / 6: the volume, positive when oriented outward.
  double tet_signed_volume(std::size_t t) const;
};

/// How texture coordinates are assigned to the corners of a cell's tetrahedra.
struct UvwMapping {
  enum class Kind {
    /// The cell's own box mapping: coordinates in an orthonormal frame of the cell's hyperplane
    /// (hyperplane_basis of its normal), scaled per axis so the cell's bounding box is [0,1]^3;
    /// the map of section/uvw.hpp (facet_texture_maps), so both section paths agree.
    CellBox,
    /// Parameters of a round shape (see parametric_uvw); falls back to CellBox per cell where
    /// a shape has no parameters (e.g. the flat caps of the spherinder).
    Glome,
    Spherinder,
    Duocylinder,
  };
  Kind kind = Kind::CellBox;
  /// Radius R of the round shape (the R of glome:R,N, spherinder:R,N, duocylinder:R,N).
  double radius = 1.0;
};

/// The parametric mapping of a model spec: glome:R,N -> Glome, spherinder:R,N -> Spherinder,
/// duocylinder:R,N -> Duocylinder (radius R); nothing for other specs.
std::optional<UvwMapping> uvw_mapping_for_spec(const std::string& spec);

/// Parameters of a round shape at point x of a cell with outward normal n, each in [0, 1]
/// (angles divided by their period; angular components are unwrapped per tetrahedron by the
/// caller, so values slightly outside [0,1] occur on seams: sample with "repeat"):
///  * Glome (Hopf coordinates x = R (cos a cos b, cos a sin b, sin a cos c, sin a sin c)):
///    (b / 2pi, c / 2pi, a / (pi/2)).
///  * Spherinder (sphere x sweep [-R, R] in w), side cells: (azimuth / 2pi, polar / pi,
///    (w / R + 1) / 2).
///  * Duocylinder, cells on the first circle (normal in the xy plane): (atan2(y, x) / 2pi,
///    (z / R + 1) / 2, (w / R + 1) / 2); cells on the second circle: (atan2(w, z) / 2pi,
///    (x / R + 1) / 2, (y / R + 1) / 2).
/// Returns nothing where the shape has no parameters (spherinder caps). Which components are
/// periodic is returned in `periodic`.
std::optional<Eigen::Vector3d> parametric_uvw(const UvwMapping& mapping, const Eigen::Vector4d& x,
                                              const Eigen::Vector4d& n,
                                              std::array<bool, 3>& periodic);

struct TetOptions {
  UvwMapping uvw;
  /// Split combinatorial cubes into 5 tetrahedra where the face diagonals allow it (else 6).
  bool five_tet_cubes = true;
};

/// Per-cell statistics of a tetrahedralization.
struct TetStats {
  std::size_t coned_cells = 0;
  std::size_t cube_split_cells = 0;
  std::size_t tetgen_cells = 0;  ///< cells given to the non-convex cell mesher
  std::size_t steiner_points = 0;
  /// Non-convex cells left out (tetrahedralize_cells without a mesher): no tetrahedra.
  std::size_t skipped_cells = 0;
};

/// The tetrahedra of one non-convex cell, as a NonConvexCellMesher returns them: local ids,
/// 0 .. vertices.size() - 1 the cell's vertices in the order passed, higher ids
/// steiner[id - vertices.size()] (interior points in R^4, in the cell). Any orientation.
struct CellTets {
  std::vector<std::array<std::uint32_t, 4>> tets;
  std::vector<Eigen::Vector4d> steiner;
};

/// Tetrahedralizes the polyhedron of cell `cell` bounded by `boundary` (outward triangles of
/// model vertex ids, all among the sorted `vertices`), in the hyperplane with outward normal
/// `normal`, keeping the boundary triangles (so the mesh stays conforming).
/// \throw MeshingError naming the cell when it cannot.
using NonConvexCellMesher = std::function<CellTets(
    const Complex& complex, std::uint32_t cell, const std::vector<std::uint32_t>& vertices,
    const std::vector<std::array<std::uint32_t, 3>>& boundary, const Eigen::Vector4d& normal)>;

/// Tetrahedralizes every 3-cell of a closed 4D complex (ambient dimension 4, with facet
/// normals). The union of a cell's tetrahedra is the cell; shared faces get the same triangles.
/// Non-convex cells go to TetGen: this function is defined in the fenced library
/// cw4d_tetrahedralize (cw4d::tetrahedralize, AGPL through TetGen), not in cw4d_tetra.
/// \throw InputError when the complex is not 4D, has no 3-cells or no facet normals.
/// \throw MeshingError when a non-convex cell cannot be tetrahedralized (TetGen's failure,
///        never a crash or an exit).
TetMesh tetrahedralize(const Complex& complex, const TetOptions& options = {},
                       TetStats* stats = nullptr);

/// tetrahedralize() with the mesher of non-convex cells given by the caller (cw4d_tetra, Eigen
/// only, also in WebAssembly). Convex cells are coned and cubes split exactly as tetrahedralize
/// does; a non-convex cell goes to `nonconvex` or, when it is empty, is left out (no
/// tetrahedra; counted in stats->skipped_cells).
/// \throw InputError as tetrahedralize; whatever `nonconvex` throws.
TetMesh tetrahedralize_cells(const Complex& complex, const TetOptions& options,
                             const NonConvexCellMesher& nonconvex, TetStats* stats = nullptr);

/// Fills mesh.edges and mesh.tet_edges from mesh.tets (each corner pair of each tetrahedron gets
/// the id of its edge; ids in order of first appearance), and the blocks from mesh.tets and
/// mesh.tet_cell. tetrahedralize calls it; call it again after changing tets or tet_cell (the
/// slicer only checks the sizes).
void index_tet_edges(TetMesh& mesh);

/// The triangles of every face of the complex in the global triangulation tetrahedralize uses:
/// entry f holds face f's triangles (vertex ids) in the face's orientation.
std::vector<std::vector<std::array<std::uint32_t, 3>>> triangulate_faces(const Complex& complex);

}  // namespace cw4d
