#pragma once
// Element indices. cw4d names every element by a plain std::uint32_t index into flat arrays
// (vertex columns, incidence rows), the layout shared zero-copy with numpy and JavaScript typed
// arrays; no_index is the one value meaning "no element".
#include <cstdint>

namespace cw4d {

/// "No element": an unset index, a missing neighbour, a crossing with no model edge.
inline constexpr std::uint32_t no_index = 0xffffffffu;

}  // namespace cw4d
