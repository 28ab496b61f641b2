// libFuzzer target: nesting, in model specs and in scene documents. Each input byte picks one
// level: an operator head (prism:, dual:, cone:, pyramid:, product:), a JSON array or object
// around a scene, so that inputs reach far past the nesting limits (max_model_nesting,
// max_scene_nesting). What must hold: no crash, no stack overflow, and every refusal is a
// cw4d::Error; a spec within the limits builds (the bases are tiny, so building is quick).
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0 || size > 4096) return 0;
  // Specs: heads chosen by the low bits; product: takes a second operand after the base.
  static const char* const heads[] = {"prism:", "dual:", "cone:", "pyramid:", "product:"};
  std::string spec, tail;
  int dim = 2;  // of the result: polygon:3 is 2D, prism/cone/pyramid add 1, product 2
  for (std::size_t i = 0; i + 1 < size; ++i) {
    const int h = data[i] % 5;
    spec += heads[h];
    dim += h == 1 ? 0 : h == 4 ? 2 : 1;
    if (h == 4) tail += "*polygon:3";
  }
  spec += data[size - 1] & 1 ? "polygon:3" : "nosuch";
  spec += tail;
  // Deep specs are refused before anything is built; shallow ones that add many dimensions
  // would build a large complex (each level multiplies the size), which is the size limits'
  // business, not this target's.
  if (size <= cw4d::max_model_nesting && dim > 5) return 0;
  try {
    const cw4d::Complex c = cw4d::load_model(spec);
    (void)c.fvector();
  } catch (const cw4d::Error&) {
  }
  // Scenes: the same bytes as brackets around a valid scene's object list.
  std::string open, close;
  for (std::size_t i = 0; i < size; ++i) {
    if (data[i] & 1) {
      open += "[";
      close.insert(0, "]");
    } else {
      open += "{\"k\": ";
      close.insert(0, "}");
    }
  }
  std::istringstream in("{\"objects\": [{\"model\": \"5-cell\"}], \"x\": " + open + "0" + close +
                        "}");
  try {
    (void)cw4d::read_scene(in, "fuzz.json", "/nonexistent-cw4d-fuzz-dir");
  } catch (const cw4d::Error&) {
  }
  return 0;
}
