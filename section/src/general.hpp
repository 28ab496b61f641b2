#pragma once
// Input checks shared by section.cpp and slicer.cpp.
#include "cw4d/section/section.hpp"

namespace cw4d {

/// \throw InputError when dimensions disagree or the model is not at least 2-dimensional.
void check_section_input(const Complex& model, const Hyperplane& plane, const AffineTransform& xf);

}  // namespace cw4d
