#pragma once
// Built-in polytopes (all centred at the origin, closed, outward oriented) and the model-spec
// parser shared by the CLI.
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cw4d/complex/catalogue.hpp"
#include "cw4d/complex/complex.hpp"

namespace cw4d {

/// Regular n-simplex (n >= 2) with circumradius 1: the n+1 standard basis vectors of R^(n+1),
/// centred and written in the Helmert basis of the hyperplane they span, scaled to radius 1.
Complex make_simplex(int n);
/// n-cube [-1, 1]^n (n >= 2).
Complex make_cube(int n);
/// n-orthoplex (cross-polytope) with vertices +-e_i (n >= 2).
Complex make_orthoplex(int n);
/// Regular p-gon in the plane, circumradius 1, first vertex at (1, 0) (p >= 3).
Complex make_polygon(int p);
/// Cartesian product P x Q of two closed complexes (the boundary of the product solid), in
/// R^(dim P + dim Q). Products with a segment make prisms.
Complex make_product(const Complex& p, const Complex& q);
/// The segment [-1, 1] as a closed 1-dimensional complex (two vertices).
Complex make_segment();
/// p,q-duoprism: product of a regular p-gon and a regular q-gon.
Complex make_duoprism(int p, int q);

/// "1,2,3" -> integers, exactly `count` of them. \throw InputError naming the spec.
std::vector<int> parse_ints(std::string_view args, std::string_view spec, std::size_t count);

/// Every family of the catalogue, then the file entry (what `cw4d list` prints).
std::vector<BuiltinInfo> builtin_list(const Catalogue& catalogue = core_catalogue());

/// The usage string of the family a spec belongs to (e.g. "duoprism:P,Q" for "duoprism:5,7"),
/// or nothing for file names.
std::optional<std::string> model_family(std::string_view spec,
                                        const Catalogue& catalogue = core_catalogue());

/// True when spec names a built-in ("5-cell", "cube:5", ...), false when it should be a path.
bool is_builtin_spec(std::string_view spec, const Catalogue& catalogue = core_catalogue());

/// The candidate closest to `word` (ignoring case, '-', '_' and spaces; at most a third of the
/// letters edited), or "" when none is close. For "did you mean" messages.
std::string closest_name(std::string_view word, const std::vector<std::string>& candidates);

/// How deep operators may nest in a spec (prism:dual:prism:... counts 3).
inline constexpr int max_model_nesting = 32;

/// Builds the model named by a spec: a family of the catalogue, or a path to a .4off / .off
/// file. Operators nest at most max_model_nesting deep. The default, core_catalogue(), knows
/// the families of complex/; pass default_catalogue() (cw4d/tetrahedralize/catalogue.hpp) for
/// every family of `cw4d list` (hulls, snubs, glome:, extrude:, spin:).
/// \throw InputError for an unknown or malformed built-in spec (or one nested too deep);
///        ParseError / IoError for files.
Complex load_model(const std::string& spec, const Catalogue& catalogue = core_catalogue());

}  // namespace cw4d
