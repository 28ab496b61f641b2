#pragma once
// The catalogue of model families: which specs ("tesseract", "duoprism:5,7", "prism:MODEL", ...)
// load_model and the scene reader accept. A Catalogue is an immutable value: built once from a
// table of families, then only read, so one catalogue may serve any number of threads.
//
// core_catalogue() (here, complex/) holds the families complex/ builds alone. A library with
// families of its own offers them as a table (e.g. hull_families() in tetrahedralize/,
// mesh_file_families() in export/), and default_catalogue() in cw4d/tetrahedralize/catalogue.hpp
// is the core catalogue extended by every family the libraries provide (what `cw4d list` shows).
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "cw4d/complex/complex.hpp"

namespace cw4d {

class Catalogue;

/// One entry of the list of built-in model specs.
struct BuiltinInfo {
  std::string spec;  ///< e.g. "duoprism:P,Q"
  std::string description;
};

/// A family of model specs: a name with aliases ("tesseract", "8-cell") or "HEAD:ARGS".
struct ModelFamily {
  std::string usage;  ///< as listed, e.g. "duoprism:P,Q"; also the family's identity
  std::string description;
  /// Whether a lower-cased spec belongs to this family.
  std::function<bool(std::string_view lowered)> matches;
  /// Builds the model of a spec (as the user wrote it); operators (prism:MODEL ...) load their
  /// operands from `catalogue`, the one the spec is loaded with. \throw InputError for bad
  /// arguments.
  std::function<Complex(const std::string& spec, const Catalogue& catalogue)> make;
  /// Exact names win over patterns: "wythoff:s3s4o3o" (the snub 24-cell) is tried before the
  /// "wythoff:DIAGRAM" family.
  bool exact = false;
  /// The names a user may type (aliases, or "head:"), for "did you mean" suggestions.
  std::vector<std::string> names;
};

/// A family of one name with aliases (lower case); `names.front()` is its usage.
ModelFamily named_family(std::vector<std::string> names, std::string description,
                         std::function<Complex()> make);
/// A family of specs "HEAD:ARGS" (head in lower case); make gets the spec and the ARGS part.
ModelFamily parametric_family(
    std::string head, std::string usage, std::string description,
    std::function<Complex(const std::string& spec, std::string_view args)> make);
/// A parametric family whose ARGS name other models (prism:MODEL, product:MODEL*MODEL): make
/// also gets the catalogue to load them from.
ModelFamily operator_family(
    std::string head, std::string usage, std::string description,
    std::function<Complex(const std::string& spec, std::string_view args, const Catalogue&)> make);

/// An immutable table of model families. Families are tried in table order, exact names before
/// patterns; a later family with the usage of an earlier one replaces it in place.
class Catalogue {
 public:
  /// The empty catalogue (only file names load).
  Catalogue() = default;
  /// \throw InputError for a family without `matches` or `make`.
  explicit Catalogue(std::vector<ModelFamily> families);

  /// This catalogue with `more` families added (or replacing those of the same usage).
  Catalogue extended(std::vector<ModelFamily> more) const;

  const std::vector<ModelFamily>& families() const noexcept { return families_; }
  /// The family a spec belongs to, or nullptr (file names, unknown specs).
  const ModelFamily* find(std::string_view spec) const;
  /// Every family's usage and description, then the file entry (what `cw4d list` prints).
  std::vector<BuiltinInfo> list() const;
  /// Builds the model named by a spec: one of this catalogue's families, or a path to a
  /// .4off / .off file; see load_model.
  Complex load(const std::string& spec) const;

 private:
  std::vector<ModelFamily> families_;
};

/// The families complex/ provides alone: regular polytopes and families, Wythoff
/// constructions, operators, round shapes, toratopes (`cw4d list` without the hull and
/// mesh-file families). Built on first use; thread-safe.
const Catalogue& core_catalogue();

}  // namespace cw4d
