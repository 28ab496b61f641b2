#pragma once
// Registers the model families that live outside complex/ (e.g. CGAL hulls), when the test
// executable links them; see registration.cpp.
namespace cw4d::test {
void register_optional_models();
}
