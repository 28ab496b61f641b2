#pragma once
// From a "soup" (vertex positions, faces as vertex cycles, higher cells as unsigned lists) to a
// Complex with edges, signed boundaries, outward orientation and facet normals.
#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

#include "cw4d/complex/complex.hpp"

namespace cw4d {

struct ComplexSoup {
  int ambient_dim = 4;
  /// ambient_dim x V.
  Eigen::MatrixXd positions;
  /// Explicit edges (only needed where no face provides them, e.g. a polygon's boundary).
  std::vector<std::array<std::uint32_t, 2>> edges;
  /// Rank-2 elements as vertex cycles (>= 3 distinct vertices each).
  std::vector<std::vector<std::uint32_t>> faces;
  /// higher[j] holds the elements of rank j + 3, each as a list of ids of rank j + 2.
  std::vector<std::vector<std::vector<std::uint32_t>>> higher;
  /// Optional colors per face / per element of higher[j] (empty = none).
  std::vector<Rgba> face_colors;
  std::vector<std::vector<Rgba>> higher_colors;
};

struct BuildOptions {
  /// Solve boundary signs, make facets coherent and outward, compute facet normals.
  bool orient = true;
};

/// The work of orienting (and later measuring) a complex, in units of one simplex of a 4D
/// facet decomposition: the number of simplices for_each_simplex cuts the facets into, times
/// (n / 4)^3 for a complex in R^n. Counted without walking them (linear in the incidences).
double orientation_work(const Complex& complex);

/// What build_complex orients at most (about a few seconds of work).
inline constexpr double max_orientation_work = 3e6;

/// Builds a complex from a soup. Edges are the distinct vertex pairs of the face cycles (and the
/// explicit edges), numbered in order of first appearance, each stored as (min id, max id).
/// Orientation never throws: where the structure is not closed or not orientable the signs stay
/// as far as they could be solved, and validate() reports the problem.
/// \throw InputError when orientation_work exceeds max_orientation_work (a model too large to
///        finish in seconds), before orienting.
/// \throw TopologyError when an id is out of range, a face has fewer than 3 vertices or repeats
///        a vertex, or an element lists the same boundary element twice.
Complex build_complex(const ComplexSoup& soup, const BuildOptions& options = {});

/// Solves signs and orientation of an already assembled complex (what build_complex does after
/// assembling): internal signs of ranks >= 3, coherent facets, outward per connected component,
/// solid signs +1, facet normals.
void orient_complex(Complex& complex);

/// Converts a complex back into a soup (faces as vertex cycles, higher ranks as id lists).
ComplexSoup to_soup(const Complex& complex);

}  // namespace cw4d
