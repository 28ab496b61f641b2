#pragma once
// The layered hyperplane section of [wxyhly 2024] (docs/REFERENCES.md): vertices -> edges ->
// faces -> cells, for complexes of any dimension; cutting a closed complex in R^n gives a closed
// complex in R^(n-1).
#include <cstdint>
#include <vector>

#include "cw4d/complex/complex.hpp"
#include "cw4d/complex/transform.hpp"
#include "cw4d/section/hyperplane.hpp"

namespace cw4d {

/// Where a section vertex comes from.
struct VertexSource {
  std::uint32_t element = 0;  ///< model vertex (rank 0) or model edge (rank 1)
  std::uint8_t rank = 0;      ///< 0: a model vertex on the plane; 1: an edge crossing it
  double t = 0.0;             ///< for rank 1: position = (1 - t) * tail + t * head
};

struct Section {
  /// The section in R^(n-1), coordinates in frame.basis. Closed and outward oriented when the
  /// model is; facet normals are the model facets' outward normals projected into the plane.
  Complex complex{3};
  /// The world-space hyperplane and its basis.
  HyperplaneFrame frame;
  /// One entry per section vertex.
  std::vector<VertexSource> vertex_source;
  /// source[k][i]: the model element of rank k + 1 whose cut is section element i of rank k
  /// (k >= 1; source[0] is empty). For a 4D model, source[2][f] is the cell of face f.
  std::vector<std::vector<std::uint32_t>> source;
  /// Set by section_scene: the scene object each face (rank-2 element) was cut from, i.e. whose
  /// model the ids in `source` refer to. Empty for the section of a single model.
  std::vector<std::uint32_t> object_of_face;
  /// A fingerprint of the model(s) the ids in vertex_source and source refer to
  /// (models_fingerprint, provenance.hpp): the readers of provenance check it against the
  /// model they are given, which catches a model of another shape even when its ids are in
  /// range. 0: not known (a section built by hand), not checked.
  std::uint64_t source_fingerprint = 0;

  /// Set by section() for a 3D section that is not an embedded surface (self_intersects):
  /// the cut of a star polychoron or of self-intersecting cells. The faces are still right as
  /// chains (their sum is the section, volumes count with winding numbers): a polygon soup for
  /// the non-zero winding rule, reported instead of rejected.
  bool self_intersecting = false;

  bool empty() const { return complex.count(0) == 0; }
  /// World-space position of section vertex v (on the hyperplane).
  Eigen::VectorXd world_position(std::uint32_t v) const { return frame.lift(complex.position(v)); }
};

/// Cuts `model`, placed in the world by x_world = model_to_world(x_model), with a world-space
/// hyperplane. The plane is moved into model space ((A^T n) . x = d - n . t); only the section's
/// own vertices are transformed. Degenerate planes (through vertices, containing edges, faces
/// or cells) give a closed outward surface without duplicate vertices or zero-area faces, or
/// an empty section: on-plane vertices count as lying on the positive side (the limit of the
/// plane moved by -epsilon along n); when that leaves nothing, as on the negative side, so a
/// plane containing a facet returns that facet as a solid. Coincident pieces cancel as chains.
/// The model is compiled once per thread and state (Complex::revision()): after writing through
/// a reference kept from a *_mut() accessor, call model.touch() before the next section().
/// \throw InputError when dimensions disagree, the model is not at least 2-dimensional, or a
/// boundary table names an element that does not exist (ids out of range, offsets out of
/// order: checked when the model is compiled). The other defects validate() reports (open
/// cells, wrong orientations, ...) are not checked here.
Section section(const Complex& model, const Hyperplane& plane,
                const AffineTransform& model_to_world);
Section section(const Complex& model, const Hyperplane& plane);

/// The general layered cut alone, without the slicer's fast path (slicer.hpp) that section()
/// takes when it can: every dimension and every degenerate plane. Where the fast path answers,
/// it gives the same complex (same elements in the same order) with coordinates equal up to
/// rounding; the tests use this as the second algorithm. (The fast path decides sides with a
/// fixed-order dot product, this one with plane_value: for a vertex within a few ulps of the ON
/// band's edge, or a crossing at the weld distance, the two may decide differently; both
/// results are valid sections.) \throw InputError as section().
Section section_general(const Complex& model, const Hyperplane& plane,
                        const AffineTransform& model_to_world);

/// Whether a closed polygon surface in R^3 is not embedded: a face that is not a simple polygon
/// (is_simple_face), or a boundary edge of one face passing through the interior of another
/// face (beyond tol::self_intersection_rel). For faces sharing vertices, the edges ending at a
/// shared vertex are not tested (they meet the other face's plane there), so faces crossing
/// beyond a shared vertex are found. False for complexes of other dimensions.
bool self_intersects(const Complex& surface);

}  // namespace cw4d
