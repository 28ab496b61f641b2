// A client of cw4d::section alone: the tesseract [-1, 1]^4 cut by w = 0.25 is the cube
// [-1, 1]^3 (volume 8, f-vector 8, 12, 6). Exit 0 when that holds.
#include <cmath>
#include <cstdio>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/section/section.hpp"

int main() {
  const cw4d::Complex tesseract = cw4d::load_model("tesseract");
  const cw4d::Section cut =
      cw4d::section(tesseract, cw4d::Hyperplane::from(Eigen::Vector4d(0, 0, 0, 1), 0.25));
  const double volume = cw4d::signed_volume(cut.complex);
  const auto f = cut.complex.fvector();
  std::printf("section of the tesseract: volume %.12g, %zu vertices\n", volume, f.at(0));
  return std::abs(volume - 8.0) < 1e-12 && f.size() == 3 && f[0] == 8 && f[1] == 12 && f[2] == 6
             ? 0
             : 1;
}
