#pragma once
// The page of `cw4d view`: the viewer template with the model and the view filled in. A function
// of its inputs alone (no files), so that tests and fuzz targets call it directly.
#include <cstddef>
#include <string>
#include <string_view>

#include "cw4d/complex/complex.hpp"

namespace cw4d::cli {

/// The largest page `cw4d view` writes (256 MiB): browsers load a one-file page whole, and
/// building it holds a few copies of the model's text.
inline constexpr std::size_t kMaxViewPageBytes = std::size_t{256} << 20;

/// Where the template takes the configuration (web/bundle.cmake leaves it in the page).
inline constexpr std::string_view kViewConfigMarker = "/*cw4d:config*/{}";

/// What the page shows besides the model. Any bytes: each is escaped for the page.
struct ViewPageOptions {
  std::string name;    ///< the model's name as shown (file names need not be UTF-8)
  std::string normal;  ///< "0,0,0,1"
  std::string offset;  ///< "0.25"
  std::size_t max_bytes = kMaxViewPageBytes;
};

/// `text` as a JSON string that is safe inside a <script> element: ", \ and control characters
/// escaped as JSON wants, and <, >, &, U+2028 and U+2029 as \u escapes too (so neither "</script"
/// nor "<!--" can appear, and the text is also a JavaScript string literal); bytes that are not
/// valid UTF-8 become U+FFFD.
std::string script_json_string(std::string_view text);

/// An upper bound of the size of the page view_page makes, from the model's counts and the
/// lengths of its coordinates (the page itself is not built).
std::size_t view_page_size_bound(std::string_view templ, const Complex& placed,
                                 const ViewPageOptions& options);

/// The page: `templ` (the viewer page, holding the configuration marker) with the configuration
/// {"off": the model as nOFF text, "name", "n", "d"} in place of the marker.
/// \throw InputError when the template has no marker, or when the page's size bound exceeds
/// options.max_bytes (checked before anything is built)
std::string view_page(std::string_view templ, const Complex& placed,
                      const ViewPageOptions& options);

}  // namespace cw4d::cli
