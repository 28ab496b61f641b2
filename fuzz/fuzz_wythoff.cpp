// libFuzzer target: the Coxeter-diagram parser and the Wythoff construction, star (fractional)
// marks included, and the English names of the uniform and star polychora.
//
// fuzz_spec covers the model specs but skips every input with a '/' (a spec with one is a file
// name) and every number above 5, so it never reaches a fractional mark such as "x5/2o3o3o".
// Here the text is a diagram: the parser sees it whole, wythoff_size counts the polytope from
// the group's subgroup orders, and the construction runs only for polytopes small enough to
// build in milliseconds under the sanitizers; whatever it builds must validate.
#include <cstddef>
#include <cstdint>
#include <string>

#include "cw4d/complex/error.hpp"
#include "cw4d/complex/validate.hpp"
#include "cw4d/complex/wythoff.hpp"

namespace {

// The largest polytope built per input: the 120-cell's 600 vertices take ~0.3 s instrumented.
constexpr double kMaxVertices = 360;
constexpr double kMaxWork = 2.0e5;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0 || size > 48) return 0;
  // The first byte chooses the option; the rest is the diagram (or a name).
  const bool fold = (data[0] & 1) != 0;
  const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);

  // Names: lookups only (they never build here), so every text is fair.
  (void)cw4d::uniform_polychoron_diagram(text);
  (void)cw4d::star_polychoron(text);

  try {
    const cw4d::CoxeterDiagram diagram = cw4d::parse_coxeter_diagram(text);
    const auto counted = cw4d::wythoff_size(diagram);
    // An unrecognised fractional group (nullopt) is measured by building it: not here.
    if (!counted || counted->f.empty() || counted->f[0] > kMaxVertices ||
        counted->orientation_work + counted->containment_reads / 50 > kMaxWork)
      return 0;
    cw4d::WythoffOptions options;
    options.fold_coincident_vertices = fold;
    const cw4d::Complex c = cw4d::make_wythoff(diagram, options);
    // make_wythoff's contract: what it returns is a valid complex whose vertex count is the
    // one counted (an upper bound only when a fractional ringing folds coinciding vertices).
    if (!cw4d::validate(c).ok()) __builtin_trap();
    const double vertices = static_cast<double>(c.fvector()[0]);
    if (vertices > counted->f[0] + 0.5) __builtin_trap();
  } catch (const cw4d::Error&) {
  }
  return 0;
}
