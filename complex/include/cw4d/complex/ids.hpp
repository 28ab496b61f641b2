#pragma once
// Strong 32-bit element ids, one type per rank, with an invalid sentinel.
#include <compare>
#include <cstdint>
#include <functional>

namespace cw4d {

template <int Rank>
struct Id {
  static constexpr std::uint32_t invalid_value = 0xffffffffu;
  static constexpr int rank = Rank;
  std::uint32_t value = invalid_value;

  constexpr Id() = default;
  constexpr explicit Id(std::uint32_t v) : value(v) {}
  constexpr bool valid() const { return value != invalid_value; }
  constexpr std::uint32_t idx() const { return value; }
  friend constexpr auto operator<=>(Id, Id) = default;
};

using VertexId = Id<0>;
using EdgeId = Id<1>;
using FaceId = Id<2>;
using CellId = Id<3>;
using Cell4Id = Id<4>;

}  // namespace cw4d

template <int Rank>
struct std::hash<cw4d::Id<Rank>> {
  std::size_t operator()(cw4d::Id<Rank> id) const noexcept { return id.value; }
};
