// A client of every cw4d component: the default catalogue (hull families from
// cw4d::tetrahedralize), the OBJ writer of cw4d::export and the PNG encoder of cw4d::render.
// Exit 0 when the published and analytic values hold.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/export/obj.hpp"
#include "cw4d/render/image.hpp"
#include "cw4d/section/section.hpp"
#include "cw4d/tetrahedralize/catalogue.hpp"

int main() {
  int failures = 0;
  // The snub 24-cell, f-vector (96, 432, 480, 144) (Klitzing, "Polytopes & their incidence
  // matrices"), known only to the default catalogue.
  const cw4d::Complex sadi = cw4d::load_model("snub 24-cell", cw4d::default_catalogue());
  failures += sadi.fvector() != std::vector<std::size_t>{96, 432, 480, 144};
  // The tesseract cut by w = 0.25 is the cube [-1, 1]^3: 8 vertices ("v" lines) in the OBJ.
  const cw4d::Section cut = cw4d::section(
      cw4d::load_model("tesseract"), cw4d::Hyperplane::from(Eigen::Vector4d(0, 0, 0, 1), 0.25));
  failures += std::abs(cw4d::signed_volume(cut.complex) - 8.0) > 1e-12;
  const std::string obj = cw4d::obj_text(cut);
  std::size_t vertices = 0;
  for (std::size_t at = 0; (at = obj.find("\nv ", at)) != std::string::npos; ++at) ++vertices;
  failures += vertices + (obj.rfind("v ", 0) == 0) != 8;
  // A 2 x 1 image encodes to a PNG (its 8-byte signature).
  cw4d::render::Image8 image;
  image.width = 2;
  image.height = 1;
  image.channels = 3;
  image.bytes.assign(6, 255);
  failures += cw4d::render::encode_png(image).rfind("\x89PNG\r\n\x1a\n", 0) != 0;
  std::printf("cw4d consumer: %d failure(s)\n", failures);
  return failures == 0 ? 0 : 1;
}
