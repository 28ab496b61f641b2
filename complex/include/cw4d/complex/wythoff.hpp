#pragma once
// Uniform polytopes by the Wythoff construction from linear Coxeter-Dynkin diagrams.
//
// Notation (linear, as in Klitzing's lists and Miratope): nodes are 'x' (ringed) or 'o'
// (unringed), separated by integer branch labels >= 2 that give the order of the product of
// the two neighbouring reflections; '3' is never omitted and 2 means "not joined". Examples:
// "x5o" pentagon, "x5x" decagon, "x3o3o" tetrahedron, "o3x4o" cuboctahedron, "x4o3o3o"
// tesseract, "x3o4o3o" 24-cell, "x5x3x3x" omnitruncated 120-cell, "x5o2x" pentagonal prism.
// The rank (number of nodes) is the ambient dimension; ranks 2..10 are accepted.
//
// Star polytopes: a branch mark may be a fraction p/q (1 <= q < p, in lowest terms), the mirrors
// of its two nodes then meet at the angle pi q / p ("x5/2o" pentagram, "x5/2o5o" small stellated
// dodecahedron, "x5/2o3o3o" great grand stellated 120-cell, "x4/3x3o3o" quasitruncated
// tesseract). The group must be finite (the Schwarz triangles and Goursat tetrahedra); the
// polytope is the same construction as for integer marks: faces are the polygons {p/q} or
// {2p/q} traversed by the rotation through 2 pi q / p, cells the (possibly non-convex) uniform
// polyhedra of the sub-diagrams, and the result may self-intersect. A ringing whose vertices,
// edges, faces or cells coincide, or whose faces or cells pass through the centre (hemi-faces),
// is refused with an InputError naming the degeneracy.
//
// Convention: the result is centred at the origin and EVERY EDGE HAS LENGTH 2 (the edge of the
// tesseract [-1,1]^4). The coordinate frame is the one in which the simple roots are the rows of
// the Cholesky factor of the Gram matrix, i.e. an arbitrary but fixed rotation of the polytope.
// Vertex 0 is the base point of the construction (inside the fundamental chamber's closure).
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cw4d/complex/complex.hpp"

namespace cw4d {

/// A linear Coxeter-Dynkin diagram with rings.
struct CoxeterDiagram {
  std::vector<bool> ringed;  ///< one entry per node
  std::vector<int> labels;   ///< labels[i] joins node i and node i + 1 (size = nodes - 1)
  /// Denominator q of the mark labels[i] / q; empty (or 1) for integer marks.
  std::vector<int> denominators = {};
  int rank() const { return static_cast<int>(ringed.size()); }
  int denominator(std::size_t i) const { return i < denominators.size() ? denominators[i] : 1; }
};

/// Parses "x4o3o3o". Accepts upper-case X / O.
/// \throw InputError for malformed text (unknown node letter, missing or non-integer label,
///        label outside 2..10000, fewer than 2 or more than 10 nodes, a fraction p/q that is not
///        in lowest terms or not 1 <= q < p).
CoxeterDiagram parse_coxeter_diagram(std::string_view text);

/// The closed uniform polytope of a diagram (ranks 1 .. rank-1 stored, outward oriented, facet
/// normals computed; a rank-2 diagram gives a polygon as edges only).
/// \throw InputError when the diagram is malformed, when some connected component of the diagram
///        has no ringed node (no ring at all, or a lower-dimensional result), when the group is
///        not finite (Gram matrix of the simple roots not positive definite, e.g. "x6o3o"), or
///        when the polytope would have more than 2,000,000 vertices or its build would exceed the
///        orientation-work budget (orientation_work + containment_reads / 50, from wythoff_size,
///        against max_orientation_work); for fractional marks also
///        when the generated group is infinite or the ringing is degenerate (coinciding
///        vertices, edges, faces or cells, hemi-faces through the centre, or elements that do
///        not close up into a valid complex).
Complex make_wythoff(const CoxeterDiagram& diagram);
Complex make_wythoff(std::string_view diagram);

/// The size of make_wythoff(diagram) computed from the orders of the diagram's subgroups,
/// without building anything: make_wythoff checks it first and refuses, in milliseconds, what
/// build_complex would refuse after building (orientation_work above max_orientation_work),
/// what would take longer than that budget once the containment tests are counted
/// (orientation_work + containment_reads / 50 above max_orientation_work: one read costs about
/// a fiftieth of a 4D simplex's orientation) or what has more than 2,000,000 vertices.
struct WythoffSize {
  std::vector<double> f;          ///< f[k]: the number of k-faces, 0 <= k < rank
  double orientation_work = 0.0;  ///< orientation_work() of the built complex
  /// At most how many ids and edges the containment tests of one walk over every facet read
  /// (for_each_simplex skips the cone over a boundary element that holds the apex, found by a
  /// search down to the faces): small against orientation_work in R^4, the larger part of
  /// the work from R^8 on.
  double containment_reads = 0.0;
};
/// Exact for non-degenerate diagrams; for a fractional diagram whose elements coincide the
/// counts are upper bounds. nullopt when a component of the diagram has no ring, or when a
/// fractional diagram's group is not recognised (make_wythoff then builds and measures).
/// \throw InputError when the diagram is malformed or its group is infinite.
std::optional<WythoffSize> wythoff_size(const CoxeterDiagram& diagram);

struct WythoffOptions {
  /// Accept a fractional diagram whose base point lies on more mirrors than the unringed
  /// nodes' (its vertices, and then some edges, coincide) and build the figure with the
  /// coinciding vertices and edges identified, as Miratope and Klitzing list some of them; the
  /// faces and cells must still be distinct and the result must validate. Ignored for rank 2
  /// (a polygon would only be traversed twice).
  bool fold_coincident_vertices = false;
};
Complex make_wythoff(const CoxeterDiagram& diagram, const WythoffOptions& options);
Complex make_wythoff(std::string_view diagram, const WythoffOptions& options);

/// The diagram of a convex uniform polychoron named in English, case-insensitive, words joined
/// by spaces, hyphens or underscores: an optional operation (truncated, rectified, bitruncated,
/// cantellated, runcinated, cantitruncated, runcitruncated, omnitruncated) followed by a regular
/// base (pentachoron / 5-cell, tesseract / 8-cell, hexadecachoron / 16-cell, icositetrachoron /
/// 24-cell, hecatonicosachoron / 120-cell, hexacosichoron / 600-cell). Returns e.g. "x4x3o3o"
/// for "truncated tesseract", nullopt for anything else.
std::optional<std::string> uniform_polychoron_diagram(std::string_view name);

/// A named star polychoron: its diagram, and whether it is the folded figure of that diagram
/// (WythoffOptions::fold_coincident_vertices).
struct NamedDiagram {
  const char* name;
  const char* diagram;
  bool folded = false;
};

/// One uniform polychoron that cw4d builds by name.
struct UniformPolychoron {
  const char* name;  ///< Miratope's name (its library file's), lower case
  /// cw4d's English name when it is not `name` with the Greek base word in English
  /// (pentachoron -> 5-cell, icositetrachoron -> 24-cell, ...), else nullptr.
  const char* english;
  /// Linear Coxeter-Dynkin diagram: x ringed, o unringed, s alternated (snub) nodes; "" for
  /// the grand antiprism, which has none.
  const char* diagram;
  bool convex = true;
  bool folded = false;  ///< built as make_wythoff(diagram, WythoffOptions{true})
  /// The model spec that builds it when make_wythoff does not: the regular convex built-ins
  /// (their own coordinates), and the snub 24-cell and grand antiprism of default_catalogue()
  /// (convex hulls, in cw4d_tetrahedralize); nullptr for make_wythoff(diagram).
  const char* spec = nullptr;
};

/// Every uniform polychoron cw4d builds by name, one entry each, in a fixed order: the 47 convex
/// ones (6 regular, 39 Wythoffian, the snub 24-cell, the grand antiprism), then the ten regular
/// star polychora and the other non-convex uniform ones of Miratope's library.
const std::vector<UniformPolychoron>& uniform_polychora();
/// cw4d's English name of an entry ("quasicantitruncated 24-cell", "great grand stellated
/// 120-cell", "truncated tesseract").
std::string english_name(const UniformPolychoron& polychoron);
/// The entry a name denotes: Miratope's name or the English one, case-insensitive, words
/// joined by spaces, hyphens or underscores, the Greek base words (pentachoron, tesseract,
/// hexadecachoron, icositetrachoron or icosatetrachoron, hecatonicosachoron, hexacosichoron)
/// interchangeable with 5-cell, 8-cell, 16-cell, 24-cell, 120-cell, 600-cell, and
/// runcicantitruncated with omnitruncated. nullopt for anything else.
std::optional<UniformPolychoron> find_uniform_polychoron(std::string_view name);

struct ModelFamily;  // cw4d/complex/catalogue.hpp
/// The model family "UNIFORM-POLYCHORON": every entry of uniform_polychora() by name
/// (find_uniform_polychoron). Without hull_models (core_catalogue()) it leaves out the snub
/// 24-cell and the grand antiprism, which cw4d_tetrahedralize builds as convex hulls; with them
/// (default_catalogue(), where it replaces the core one) those load through their hull families.
ModelFamily uniform_polychoron_family(bool hull_models);

/// The regular star polychora (Schlaefli-Hess: "great grand stellated 120-cell", "grand
/// 600-cell", ..., or the Greek forms "great grand stellated hecatonicosachoron", "grand
/// hexacosichoron") and the named non-convex uniform polychora as Miratope names its files
/// ("quasitruncated tesseract", "rectified great grand hecatonicosachoron", ...);
/// case-insensitive, words joined by spaces, hyphens or underscores. nullopt for anything else.
std::optional<NamedDiagram> star_polychoron(std::string_view name);
/// The diagram of star_polychoron(name).
std::optional<std::string> star_polychoron_diagram(std::string_view name);
/// The polychoron star_polychoron(name) names, built from its diagram (edge 2).
/// \throw InputError for a name star_polychoron does not know.
Complex make_star_polychoron(std::string_view name);

/// One entry per polychoron (lower case, words joined by spaces), in a fixed order: the ten
/// regular ones first.
const std::vector<NamedDiagram>& star_polychoron_names();

}  // namespace cw4d
