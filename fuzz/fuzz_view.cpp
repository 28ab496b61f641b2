// libFuzzer target: the page of `cw4d view` (cw4d::cli::view_page) from a model and names of
// arbitrary bytes.
//
// Input: one byte choosing the lengths of the name, the normal and the offset (and whether the
// page budget is tiny), those three texts, and an nOFF model. Whatever the bytes, the
// configuration the page carries must be one JSON object that a JSON parser reads back to the
// same model and names (non-UTF-8 bytes as U+FFFD), holding no '<' and no line separator that
// could end the script element or a JavaScript line; the page must stay within its size bound,
// and a budget below that bound must be refused before anything is built.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "cw4d/complex/error.hpp"
#include "cw4d/complex/off_io.hpp"
#include "cw4d/complex/text.hpp"
#include "view_page.hpp"

namespace {

constexpr std::string_view kBefore = "<!doctype html><script>const config = ";
constexpr std::string_view kAfter = ";</script>";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::string_view in(reinterpret_cast<const char*>(data + 1), size - 1);
  const std::size_t name_len = std::min<std::size_t>(data[0] & 0x1f, in.size());
  const std::size_t normal_len = std::min<std::size_t>((data[0] >> 5) & 0x3, in.size() - name_len);
  const bool tiny_budget = (data[0] & 0x80) != 0;

  cw4d::cli::ViewPageOptions options;
  options.name = std::string(in.substr(0, name_len));
  options.normal = std::string(in.substr(name_len, normal_len * 4));
  options.offset = std::string(in.substr(name_len + options.normal.size(), 4));
  const std::size_t used = name_len + options.normal.size() + options.offset.size();
  std::istringstream off{std::string(in.substr(std::min(used, in.size())))};

  cw4d::Complex model;
  try {
    model = cw4d::read_off(off, "fuzz.off");
  } catch (const cw4d::Error&) {
    return 0;
  }
  std::string templ(kBefore);
  templ += cw4d::cli::kViewConfigMarker;
  templ += kAfter;
  const std::size_t bound = cw4d::cli::view_page_size_bound(templ, model, options);
  if (tiny_budget) options.max_bytes = bound / 2;

  std::string page;
  try {
    page = cw4d::cli::view_page(templ, model, options);
  } catch (const cw4d::InputError&) {
    if (!tiny_budget) __builtin_trap();  // the template has its marker: only the budget refuses
    return 0;
  }
  if (tiny_budget) __builtin_trap();
  if (page.size() > bound) __builtin_trap();
  if (page.compare(0, kBefore.size(), kBefore) != 0) __builtin_trap();
  if (page.compare(page.size() - kAfter.size(), kAfter.size(), kAfter) != 0) __builtin_trap();
  const std::string_view config =
      std::string_view(page).substr(kBefore.size(), page.size() - kBefore.size() - kAfter.size());
  // Nothing in the configuration can close the script or open a comment, nor end a line of
  // JavaScript (U+2028 and U+2029 are E2 80 A8/A9).
  if (config.find('<') != std::string_view::npos || config.find('\n') != std::string_view::npos ||
      config.find("\xE2\x80\xA8") != std::string_view::npos ||
      config.find("\xE2\x80\xA9") != std::string_view::npos)
    __builtin_trap();

  const nlohmann::json json = nlohmann::json::parse(config, nullptr, /*allow_exceptions=*/false);
  if (!json.is_object() || json.size() != 4) __builtin_trap();
  if (json.value("name", std::string("\x01")) != cw4d::to_valid_utf8(options.name) ||
      json.value("n", std::string("\x01")) != cw4d::to_valid_utf8(options.normal) ||
      json.value("d", std::string("\x01")) != cw4d::to_valid_utf8(options.offset))
    __builtin_trap();
  // The model read back from the page is the model written.
  std::istringstream back(json.value("off", std::string()));
  const cw4d::Complex again = cw4d::read_off(back, "page.off");
  if (again.ambient_dim() != model.ambient_dim() || again.fvector() != model.fvector() ||
      again.positions() != model.positions())
    __builtin_trap();
  return 0;
}
