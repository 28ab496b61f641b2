#pragma once
// The one check of where a model is placed before it is cut: the CLI, the Python module and
// the scene slicers share it, so the same input is refused everywhere with the same words.
#include <string>

#include "cw4d/complex/complex.hpp"
#include "cw4d/complex/transform.hpp"

namespace cw4d {

/// Coordinates are used as doubles: squared distances and 3-volumes of sections stay finite and
/// nonzero only for sizes within 1e-100 .. 1e100, so a model is cut only when, once placed, its
/// coordinates lie within this bound of the origin ...
inline constexpr double max_placed_coordinate = 1e100;
/// ... and it spans at least this much along some axis.
inline constexpr double min_placed_extent = 1e-100;

/// Refuses a placement that would give a meaningless (typically empty) section instead of an
/// error: a transform with a NaN or infinite entry, a model whose placed coordinates exceed
/// max_placed_coordinate (a scale of 1e300, a file in units of 1e200) or whose placed extent is
/// below min_placed_extent (an all-zero or nearly singular linear part). `what` names the model
/// in the message ("model 'tesseract'", "object 2 (24-cell) of scene 'a.json'"). The answer
/// depends only on the model's positions and the transform: the last few accepted pairs are
/// remembered per thread by (Complex::revision(), transform), so a loop that cuts one placed
/// model again and again pays for one pass over its vertices.
/// \throw InputError when the transform's dimension is not the model's, or as above.
void check_placement(const Complex& model, const AffineTransform& model_to_world,
                     const std::string& what);

}  // namespace cw4d
