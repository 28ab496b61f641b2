#include "view_page.hpp"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <sstream>

#include "cw4d/complex/error.hpp"
#include "cw4d/complex/off_io.hpp"
#include "cw4d/complex/text.hpp"

namespace cw4d::cli {

namespace {

std::size_t digits(std::size_t v) {
  std::size_t n = 1;
  while (v >= 10) {
    v /= 10;
    ++n;
  }
  return n;
}

// The most bytes a piece of text takes once escaped by script_json_string: 6 per byte (a \u
// escape) is the worst case.
constexpr std::size_t kWorstEscape = 6;

}  // namespace

std::string script_json_string(std::string_view text) {
  std::string out;
  out.reserve(text.size() + text.size() / 8 + 2);
  out += '"';
  char esc[8];
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c < 0x80) {
      switch (c) {
        case '"':
          out += "\\\"";
          break;
        case '\\':
          out += "\\\\";
          break;
        case '\n':
          out += "\\n";
          break;
        case '\r':
          out += "\\r";
          break;
        case '\t':
          out += "\\t";
          break;
        default:
          // Control characters as JSON demands; < > & so that no "</script", "<!--" or "]]>"
          // (nor an entity) can form inside the script element.
          if (c < 0x20 || c == '<' || c == '>' || c == '&') {
            std::snprintf(esc, sizeof esc, "\\u%04x", c);
            out += esc;
          } else {
            out += static_cast<char>(c);
          }
      }
      ++i;
      continue;
    }
    const std::size_t len = utf8_sequence_length(text, i);
    if (len == 0) {
      out += "\\ufffd";
      ++i;
    } else if (len == 3 && c == 0xE2 && static_cast<unsigned char>(text[i + 1]) == 0x80 &&
               (static_cast<unsigned char>(text[i + 2]) & 0xFE) == 0xA8) {
      // U+2028 and U+2029 end a line in older JavaScript engines.
      out += static_cast<unsigned char>(text[i + 2]) == 0xA8 ? "\\u2028" : "\\u2029";
      i += 3;
    } else {
      out.append(text.substr(i, len));
      i += len;
    }
  }
  out += '"';
  return out;
}

std::size_t view_page_size_bound(std::string_view templ, const Complex& placed,
                                 const ViewPageOptions& options) {
  // The nOFF text: each coordinate at most its shortest round-trip length, each id its digits,
  // each colour four floats of at most 16 bytes; every line's newline escaped as two bytes.
  std::size_t off = 64;  // header, counts, comments
  const int n = placed.ambient_dim();
  for (int k = 0; k <= n; ++k) off += 24 + digits(placed.count(k));
  const auto& p = placed.positions();
  char buf[64];
  for (Eigen::Index v = 0; v < p.cols(); ++v) {
    for (Eigen::Index i = 0; i < p.rows(); ++i) {
      const auto r = std::to_chars(buf, buf + sizeof buf, p(i, v));
      off += static_cast<std::size_t>(r.ptr - buf) + 1;
    }
    off += 1;  // the newline's second byte
  }
  for (int k = 2; k <= placed.top_rank(); ++k) {
    const std::size_t rows = placed.count(k);
    if (rows == 0) continue;
    const Incidence& t = placed.boundary(k);
    // (faces are written as vertex cycles, other ranks by the ids of their boundary)
    const std::size_t id_digits =
        std::max(digits(placed.count(0)), digits(placed.count(k - 1))) + 1;
    std::size_t longest = 0;
    for (std::size_t x = 0; x < rows; ++x) longest = std::max(longest, t.row_size(x));
    off += t.entries() * id_digits + rows * (digits(longest) + 2);
    if (!placed.colors(k).empty()) off += rows * 4 * 17;
  }
  const std::size_t strings =
      (options.name.size() + options.normal.size() + options.offset.size()) * kWorstEscape + 64;
  return templ.size() + off + strings;
}

std::string view_page(std::string_view templ, const Complex& placed,
                      const ViewPageOptions& options) {
  const std::size_t at = templ.find(kViewConfigMarker);
  if (at == std::string_view::npos)
    throw InputError("the viewer page has no configuration marker " +
                     std::string(kViewConfigMarker));
  const std::size_t bound = view_page_size_bound(templ, placed, options);
  if (bound > options.max_bytes)
    throw InputError("the page would take up to " + std::to_string(bound >> 20) +
                     " MiB, beyond the limit of " + std::to_string(options.max_bytes >> 20) +
                     " MiB for a one-file viewer page: view a smaller model (or a section of it, "
                     "'cw4d slice')");
  std::string page;
  page.reserve(bound);
  page.append(templ.substr(0, at));
  page += "{\"off\":";
  {
    std::ostringstream off;
    write_off(off, placed);
    page += script_json_string(std::move(off).str());
  }
  page += ",\"name\":";
  page += script_json_string(options.name);
  page += ",\"n\":";
  page += script_json_string(options.normal);
  page += ",\"d\":";
  page += script_json_string(options.offset);
  page += '}';
  page.append(templ.substr(at + kViewConfigMarker.size()));
  return page;
}

}  // namespace cw4d::cli
