#pragma once
// Scenes: several placed, colored instances of models, read from a JSON file.
//
//   {
//     "objects": [
//       {"model": "tesseract", "name": "left",
//        "scale": 0.5,                          // or one factor per axis: [sx, sy, sz, sw]
//        "rotate": [["xw", 30], ["yz", 15]],    // degrees, the first pair is applied first
//        "translate": [-1.5, 0, 0, 0],
//        "color": "#ff8000",                    // or [r, g, b] with components in 0..1
//        "opacity": 0.5,                        // 0..1, default 1
//        "cell_colors": {"3": "#ff0000", "5": [0, 0, 1]}},
//       {"model": "tesseract", "translate": [1.5, 0, 0, 0]},
//       {"model": "shapes/my.4off"}             // relative to the scene file's directory
//     ]
//   }
//
// Only "model" is required. An object is placed by x_world = T R_k ... R_1 S x_model (scale,
// then the rotations in the order listed, then the translation); the transform has the model's
// dimension, so "translate" and a per-axis "scale" take one number per axis. "cell_colors"
// keys are ids of the model's 3-cells (its facets for a 4D model); a cell without an entry
// takes the object's color, default white. Every color's alpha is the object's opacity.
// Comments (// and /* */) are allowed. Unknown keys are rejected, so a typo cannot be ignored.
// Objects whose model specs are equal (after resolving relative paths) share one Complex.
#include <cstdint>
#include <iosfwd>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "cw4d/complex/catalogue.hpp"
#include "cw4d/complex/complex.hpp"
#include "cw4d/complex/transform.hpp"

namespace cw4d {

struct SceneObject {
  /// The model spec as written in the scene (a built-in spec or a path).
  std::string model;
  /// The loaded model, shared by every object with the same spec.
  std::shared_ptr<const Complex> complex;
  /// model -> world.
  AffineTransform transform;
  /// Color of the whole object; a is the opacity.
  Rgba color;
  /// Colors of single 3-cells of the model (ids < complex->count(3)); a is the opacity.
  std::map<std::uint32_t, Rgba> cell_colors;
  /// Optional label (empty when not given).
  std::string name;

  /// Color of the cut of 3-cell `cell`: its own color if given, else the object's.
  Rgba color_of_cell(std::uint32_t cell) const {
    const auto it = cell_colors.find(cell);
    return it == cell_colors.end() ? color : it->second;
  }
};

struct Scene {
  std::vector<SceneObject> objects;
  /// Dimension of the objects' models (all equal), 0 for a scene without objects.
  int dim() const { return objects.empty() ? 0 : objects.front().complex->ambient_dim(); }
};

/// How deep arrays and objects may nest in a scene document (a scene uses 4 levels).
inline constexpr std::size_t max_scene_nesting = 64;

/// Reads a scene from JSON text. `name` is used in error messages ("name:line: ..."); relative
/// model paths are resolved against `base_directory` (the working directory when empty). Model
/// specs are looked up in `catalogue` (default_catalogue() in cw4d/tetrahedralize/catalogue.hpp
/// for every family of `cw4d list`).
/// \throw ParseError naming name:line for malformed JSON, unknown keys, wrong types, bad colors,
///        cell ids out of range, opacity outside [0, 1], zero scales, rotation planes or vectors
///        that do not fit the model's dimension, models of different dimensions, an unknown
///        built-in model spec, or a scene without objects.
/// \throw ParseError / IoError from reading a model file (naming that file).
Scene read_scene(std::istream& in, const std::string& name, const std::string& base_directory = {},
                 const Catalogue& catalogue = core_catalogue());
/// Reads a scene file; model paths are relative to its directory.
/// \throw as read_scene; ParseError with line 0 when the file cannot be opened.
Scene read_scene_file(const std::string& path, const Catalogue& catalogue = core_catalogue());

}  // namespace cw4d
