#pragma once
// The section atlas of a model along one direction: every offset d at which the plane
// n.x = d passes a vertex (a critical offset), and for each open interval between two
// consecutive critical offsets the section's f-vector, which is the same for every plane in
// the interval (the combinatorics of a section change only where the plane passes a vertex),
// with one representative section cut at the interval's midpoint.
#include <Eigen/Core>

#include <cstddef>
#include <vector>

#include "cw4d/complex/complex.hpp"
#include "cw4d/complex/transform.hpp"
#include "cw4d/section/section.hpp"

namespace cw4d {

/// Vertex heights closer than this fraction of the model's radius (the largest distance of a
/// placed vertex from the origin, the scale of the heights' rounding) are one critical offset:
/// far above the rounding of a height (a few ulps of that radius) and far below the gap
/// between distinct heights of any built-in model.
inline constexpr double atlas_merge_rel = 1e-9;

/// One section of the atlas: its plane's offset and the section's f-vector (counts of ranks
/// 0..n-2 of the section of a model in R^n; zeros when the plane misses the model).
struct AtlasSection {
  double offset = 0.0;
  std::vector<std::size_t> fvector;
  /// At a critical offset whose section is empty (the plane only touches the model, as at
  /// either end of a convex model): the f-vector of the model's elements that lie in the plane,
  /// ranks 0..n-2 as `fvector` (a vertex (1, 0, 0), an edge (2, 1, 0), a square (4, 4, 1)).
  /// Empty otherwise: for a section that is not empty, and for every interval's section.
  std::vector<std::size_t> contact;
};

/// An open interval (from, to) of offsets between two consecutive critical offsets; `section`
/// is cut at its midpoint, offset = (from + to) / 2.
struct AtlasInterval {
  double from = 0.0, to = 0.0;
  AtlasSection section;
};

struct Atlas {
  Eigen::VectorXd normal;  ///< the unit normal (world space)
  double tolerance = 0.0;  ///< heights closer than this were merged (atlas_merge_rel x radius)
  /// The distinct vertex heights n.x in increasing order (of the heights merged into one, the
  /// value computed most often, else their median).
  std::vector<double> critical_offsets;
  /// The section at each critical offset (a degenerate plane: it passes a vertex; cut with the
  /// rules of section(), which count a vertex on the plane as above it).
  std::vector<AtlasSection> critical;
  /// One per pair of consecutive critical offsets.
  std::vector<AtlasInterval> intervals;
  /// With AtlasOptions::keep_sections: the representative section of each interval.
  std::vector<Section> sections;
};

struct AtlasOptions {
  /// Keep each interval's representative Section (Atlas::sections), e.g. to draw them.
  bool keep_sections = false;
  /// Also cut at every critical offset (Atlas::critical).
  bool critical_sections = true;
};

/// The vertex heights n.x of the placed model, sorted and merged (atlas_merge_rel).
/// \throw InputError when the normal is zero or not finite or its dimension differs.
std::vector<double> critical_offsets(const Complex& model, const Eigen::VectorXd& normal,
                                     const AffineTransform& model_to_world,
                                     double* tolerance = nullptr);

/// The atlas of `model` placed by model_to_world, along `normal` (any length; offsets are
/// distances along normal / |normal|, as in section()).
/// \throw InputError as section() and critical_offsets().
Atlas section_atlas(const Complex& model, const Eigen::VectorXd& normal,
                    const AffineTransform& model_to_world, const AtlasOptions& options = {});
Atlas section_atlas(const Complex& model, const Eigen::VectorXd& normal,
                    const AtlasOptions& options = {});

}  // namespace cw4d
