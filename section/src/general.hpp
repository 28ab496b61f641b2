#pragma once
// What section.cpp and the slicer files (slicer.cpp, kernel.cpp, sweep.cpp, ...) share: input
// checks and chain arithmetic.
#include "cw4d/section/section.hpp"
#include "cw4d/section/slicer.hpp"

#include <algorithm>
#include <vector>

namespace cw4d {

/// Sorts a chain of terms {id, coef} by id, sums equal ids and drops zero coefficients (the
/// result does not depend on the input order).
template <class Term>
void combine_chain(std::vector<Term>& chain) {
  if (chain.size() <= 16) {  // the usual few terms: insertion sort
    for (std::size_t i = 1; i < chain.size(); ++i)
      for (std::size_t j = i; j > 0 && chain[j].id < chain[j - 1].id; --j)
        std::swap(chain[j], chain[j - 1]);
  } else {
    std::sort(chain.begin(), chain.end(), [](const Term& a, const Term& b) { return a.id < b.id; });
  }
  std::size_t out = 0;
  for (std::size_t i = 0; i < chain.size();) {
    std::size_t j = i;
    int sum = 0;
    while (j < chain.size() && chain[j].id == chain[i].id) sum += chain[j++].coef;
    if (sum != 0) chain[out++] = {chain[i].id, sum};
    i = j;
  }
  chain.resize(out);
}

/// to_section without the self-intersection test (self_intersecting stays false).
Section to_section_untested(const SliceBuffers& buffers);

/// \throw InputError when dimensions disagree or the model is not at least 2-dimensional.
void check_section_input(const Complex& model, const Hyperplane& plane, const AffineTransform& xf);

/// section_general without check_tables (validate.hpp), for callers whose model was checked
/// when it was compiled (section(), the slicer's general path). test_self_intersection = false
/// leaves Section::self_intersecting false, for callers that do not keep it (SliceBuffers has
/// no such field: to_section tests the buffers).
Section general_cut(const Complex& model, const Hyperplane& plane, const AffineTransform& xf,
                    bool test_self_intersection = true);

}  // namespace cw4d
