#include "support/registration.hpp"

#include "cw4d/tetrahedralize/hull.hpp"

namespace cw4d::test {

void register_optional_models() {
  register_hull_models();
}

}  // namespace cw4d::test
