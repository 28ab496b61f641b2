#include "support/registration.hpp"

namespace cw4d::test {

void register_optional_models() {}

}  // namespace cw4d::test
