#include "cw4d/tetrahedralize/catalogue.hpp"

#include <utility>
#include <vector>

#include "cw4d/export/mesh_import.hpp"
#include "cw4d/tetrahedralize/hull.hpp"

namespace cw4d {

const Catalogue& default_catalogue() {
  // One table per library, in the order `cw4d list` prints them; a static local is initialised
  // once, thread-safely, and never changed.
  static const Catalogue catalogue = [] {
    std::vector<ModelFamily> more = mesh_file_families();
    for (ModelFamily& family : hull_families()) more.push_back(std::move(family));
    return core_catalogue().extended(std::move(more));
  }();
  return catalogue;
}

}  // namespace cw4d
