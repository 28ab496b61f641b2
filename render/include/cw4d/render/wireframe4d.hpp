#pragma once
// 4D wireframes with frustum clipping and occlusion culling ([wxyhly 2024], "线框渲染").
//
// A 4D camera projects points to a 3D "retina" (perspective: x_i / depth); the retina cube is
// then drawn by an ordinary 3D camera. Edges are clipped against the 4D view frustum, and each
// convex polytope of the scene hides the parts of edges that lie in its shadow: seen from an
// eye outside, the shadow is bounded by the facets facing the eye and by the hyperplanes
// through the eye and each silhouette ridge (a ridge between a front and a back facet); with
// the eye inside, everything outside the polytope is hidden. Hidden parts are exact parameter
// intervals on each edge (Liang-Barsky against those half-spaces), not pixels.
//
// Dimension-generic: points are Eigen vectors of any size n >= 2 (a 4D scene has n = 4; a 3D
// scene with polyhedra works the same with ridges = edges).
#include <Eigen/Core>

#include <utility>
#include <vector>

#include "cw4d/complex/complex.hpp"
#include "cw4d/complex/scene.hpp"
#include "cw4d/render/camera.hpp"
#include "cw4d/render/image.hpp"
#include "cw4d/render/raster.hpp"
#include "cw4d/render/tolerances.hpp"
#include "cw4d/section/section.hpp"

namespace cw4d::render {

/// {x : normal . x <= offset}, normal of unit length.
struct HalfSpace {
  Eigen::VectorXd normal;
  double offset = 0.0;
  double value(const Eigen::VectorXd& x) const { return normal.dot(x) - offset; }
};

/// A sorted list of disjoint parameter intervals [t0, t1] within [0, 1] of a segment.
using Intervals = std::vector<std::pair<double, double>>;

/// The part of segment a + t (b - a), t in [0, 1], inside every half-space (empty list when
/// none): the Liang-Barsky parameter interval.
Intervals clip_to_halfspaces(const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                             const std::vector<HalfSpace>& halfspaces);

/// A closed convex polytope as facet half-spaces plus facet adjacency across ridges.
class ConvexOccluder {
 public:
  /// From a closed, outward-oriented complex in world coordinates (facet planes from the
  /// facets' oriented volume vectors).
  /// \throw InputError when the complex is not convex (a vertex outside a facet's half-space
  ///        beyond tolerance), has no facets, or a ridge does not bound exactly two facets.
  static ConvexOccluder from(const Complex& world);

  /// What this polytope hides from `eye`, after shrinking the hidden region by `margin`
  /// (world units) so that edges lying on the polytope's own surface stay visible.
  struct Shadow {
    bool eye_inside = false;
    /// eye outside: the hidden region is inside all of these (front facets + silhouette cones);
    /// eye inside: the *visible* region is inside all of these (the facets).
    std::vector<HalfSpace> planes;
  };
  Shadow shadow(const Eigen::VectorXd& eye, double margin) const;

  /// The visible intervals of `visible` (intervals of segment a-b) after this polytope, seen
  /// from `eye`.
  Intervals cull(const Eigen::VectorXd& a, const Eigen::VectorXd& b, const Intervals& visible,
                 const Shadow& shadow) const;

  const std::vector<HalfSpace>& facets() const { return facets_; }
  double radius() const { return radius_; }  ///< of the bounding sphere about centre()
  const Eigen::VectorXd& centre() const { return centre_; }

 private:
  std::vector<HalfSpace> facets_;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> ridge_facets_;  // per ridge
  Eigen::VectorXd centre_;
  double radius_ = 0.0;
};

/// The 4D (n-D) pinhole camera: eye, an orthonormal frame whose last column is the viewing
/// direction and whose other columns are the retina axes, and a field of view.
struct Camera4 {
  Eigen::VectorXd eye;
  Eigen::MatrixXd frame;      ///< n x n orthonormal; columns: retina axes, then forward
  double fov_degrees = 60.0;  ///< full angle of the frustum along every retina axis
  double near_plane = 0.05;
  double far_plane = 1e6;

  /// A camera at `eye` looking at `target`; the retina axes are the standard axes made
  /// orthogonal to the view direction (Gram-Schmidt, the axis most parallel to it dropped).
  /// \throw InputError when eye == target or the sizes differ.
  static Camera4 look_at(const Eigen::VectorXd& eye, const Eigen::VectorXd& target,
                         double fov_degrees = 60.0);
  int dim() const { return static_cast<int>(eye.size()); }
  /// Camera coordinates (retina axes..., depth).
  Eigen::VectorXd to_camera(const Eigen::VectorXd& x) const {
    return frame.transpose() * (x - eye);
  }
  /// The frustum as world half-spaces: near, far and two per retina axis.
  std::vector<HalfSpace> frustum() const;
  /// Retina coordinates in [-1, 1]^(n-1) of a point inside the frustum.
  Eigen::VectorXd project(const Eigen::VectorXd& x) const;
};

/// One visible piece of an edge, in world coordinates.
struct VisibleSegment {
  Eigen::VectorXd a, b;
  std::uint32_t object = 0, edge = 0;
};

/// The visible pieces of every edge of every object: clipped to the frustum, then culled by
/// every object that is convex (non-convex objects are drawn but hide nothing).
/// `margin_rel` shrinks each shadow by that fraction of the occluder's radius. With
/// `bounding_pretests`, an occluder is skipped for an object or an edge whose bounding ball
/// its shadow cone (from the eye through its bounding ball) misses: the same result, with the
/// exact culling run only where it may hide something (scenes of hundreds of objects).
std::vector<VisibleSegment> visible_edges(const Scene& scene, const Camera4& camera,
                                          bool occlusion = true,
                                          double margin_rel = tol::shadow_margin_rel,
                                          bool bounding_pretests = true);

struct WireframeOptions {
  RasterOptions raster;
  /// The 3D camera looking at the retina cube [-1, 1]^3 (retina y up).
  glm::vec3 view_from{0.55f, 0.45f, 1.6f};
  Projection projection = Projection::Perspective;
  float line_width = 2.0f;
  bool occlusion = true;
  bool retina_box = true;      ///< draw the retina cube's edges
  glm::vec3 background{1.0f};  ///< linear
  /// Also draw this section of the scene (world-space hyperplane; e.g. section_scene) inside
  /// the wireframe: its faces lifted to 4D, projected to the retina like the edges, in their
  /// colors at `section_opacity`, lit in the retina's 3D space. Triangles with a corner outside
  /// the 4D frustum are left out; the section hides no edge and no occluder hides the section.
  const Section* section = nullptr;
  float section_opacity = 0.55f;
};

/// The picture: visible edges projected to the retina, colored by 4D depth (near warm, far
/// cool), seen by a 3D camera. \throw InputError when the scene is not 4-dimensional.
Image render_wireframe(const Scene& scene, const Camera4& camera, const WireframeOptions& options);

/// Side-by-side stereo pair of the wireframe (left eye left, 2 * width wide): the retina cube
/// seen from view_from turned by -/+ angle/2 about the retina's up axis.
Image render_wireframe_stereo_pair(const Scene& scene, const Camera4& camera,
                                   const WireframeOptions& options, float angle_degrees = 6.0f);

/// A camera looking at the scene's bounding sphere from direction `from` (4 components), far
/// enough that the whole sphere fits the frustum.
Camera4 frame_scene(const Scene& scene, const Eigen::VectorXd& from, double fov_degrees = 60.0);

}  // namespace cw4d::render
