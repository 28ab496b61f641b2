#pragma once
// Public validation of complexes: the report names every offending element.
#include <cstdint>
#include <string>
#include <vector>

#include "cw4d/complex/complex.hpp"

namespace cw4d {

struct ValidationIssue {
  int rank;          ///< rank of the offending element
  std::uint32_t id;  ///< its id
  std::string what;  ///< one-line description
};

struct ValidationReport {
  std::vector<ValidationIssue> issues;
  bool ok() const { return issues.empty(); }
  /// "valid", or the first few issues joined by "; " with a count of the rest.
  std::string summary(std::size_t max_issues = 5) const;
};

struct ValidateOptions {
  /// Require a closed, coherently and outwardly oriented boundary (facets of rank
  /// ambient_dim - 1, each ridge in exactly two facets with opposite signs, positive volume).
  bool require_closed = true;
  /// Require every facet's vertices to lie in one hyperplane.
  bool require_planar_facets = true;
  /// Stop collecting after this many issues.
  std::size_t max_issues = 1000;
};

/// Checks: finite coordinates; ids in range; no repeated boundary entries; edges with two
/// distinct vertices and signs (-1, +1); each face one simple closed cycle in order; every
/// element of rank >= 3 closed with cancelling boundary (d(d) = 0 with signs); and with
/// require_closed: closed, coherent, outward facets and the solid's boundary.
ValidationReport validate(const Complex& complex, const ValidateOptions& options = {});

/// What the cuts and tetrahedralize check of a model before reading it, once per model (one
/// pass over the tables, branch-free): every boundary table well formed (Incidence::well_formed:
/// ids below the count of the rank beneath, offsets in order, signs +-1), every edge with
/// exactly two ends and no element with an empty boundary. The other defects validate()
/// reports are not checked.
/// \throw InputError naming the first table that fails.
void check_tables(const Complex& model);

}  // namespace cw4d
