#include "cw4d/section/triangulate.hpp"

namespace cw4d {

std::vector<Triangle> fan_triangulate(const Complex& complex) {
  std::vector<Triangle> out;
  if (complex.top_rank() < 2) return out;
  for (std::uint32_t f = 0; f < complex.count(2); ++f) {
    auto cyc = complex.face_cycle(f);
    for (std::size_t k = 1; k + 1 < cyc.size(); ++k) out.push_back({{cyc[0], cyc[k], cyc[k + 1]}, f});
  }
  return out;
}

}  // namespace cw4d
