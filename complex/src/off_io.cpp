#include "cw4d/complex/off_io.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <fstream>
#include <istream>
#include <iterator>
#include <optional>
#include <ostream>
#include <sstream>
#include <string>
#include <string_view>
#include <unordered_set>
#include <utility>
#include <vector>

#include "cw4d/complex/atomic_file.hpp"
#include "cw4d/complex/builder.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/input_file.hpp"

namespace cw4d {

namespace {

constexpr int max_off_dim = 9;

struct Line {
  std::size_t number;
  std::vector<std::string_view> tokens;
};

// Reads the text line by line: each call of next() splits one more non-empty line (comments
// removed) into tokens that view the text. Nothing is held per line of the file, so memory
// stays that of the text plus what the parser keeps.
class LineReader {
 public:
  LineReader() = default;
  explicit LineReader(std::string_view text) : text_(text) {
    // A UTF-8 byte-order mark (written by some Windows editors) is not part of the header.
    if (text_.substr(0, 3) == "\xEF\xBB\xBF") pos_ = 3;
  }

  // The next non-empty line, or false at the end of the text.
  bool next(Line& out) {
    while (pos_ <= text_.size() && !done_) {
      std::size_t end = text_.find('\n', pos_);
      if (end == std::string_view::npos) end = text_.size();
      ++number_;
      std::string_view line = text_.substr(pos_, end - pos_);
      if (end == text_.size()) done_ = true;
      pos_ = end + 1;
      out.number = number_;
      out.tokens.clear();
      split(line, &out.tokens);
      if (!out.tokens.empty()) return true;
    }
    return false;
  }

  // The number of non-empty lines after the current one, counted without storing them, and
  // the number the line after the last of them would have.
  std::size_t count_remaining(std::size_t* end_line) const {
    LineReader copy = *this;
    std::size_t n = 0, last = number_;
    while (copy.pos_ <= copy.text_.size() && !copy.done_) {
      std::size_t end = copy.text_.find('\n', copy.pos_);
      if (end == std::string_view::npos) end = copy.text_.size();
      ++copy.number_;
      if (end == copy.text_.size()) copy.done_ = true;
      if (!blank(copy.text_.substr(copy.pos_, end - copy.pos_))) {
        ++n;
        last = copy.number_;
      }
      copy.pos_ = end + 1;
    }
    if (end_line) *end_line = last + 1;
    return n;
  }

 private:
  static std::string_view strip(std::string_view line) {
    if (auto hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    return line;
  }
  static bool blank(std::string_view line) {
    for (char ch : strip(line))
      if (!std::isspace(static_cast<unsigned char>(ch))) return false;
    return true;
  }
  static void split(std::string_view line, std::vector<std::string_view>* tokens) {
    line = strip(line);
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
      std::size_t j = i;
      while (j < line.size() && !std::isspace(static_cast<unsigned char>(line[j]))) ++j;
      if (j > i) tokens->push_back(line.substr(i, j - i));
      i = j;
    }
  }

  std::string_view text_;
  std::size_t pos_ = 0, number_ = 0;
  bool done_ = false;
};

// A token as shown in a message: quoted, with control and non-ASCII bytes (which may not be
// UTF-8) escaped as \xNN, and cut after 40 bytes, so that every message is one printable line.
std::string show(std::string_view tok) {
  static const char* hex = "0123456789abcdef";
  std::string out = "'";
  for (std::size_t i = 0; i < tok.size() && i < 40; ++i) {
    const auto ch = static_cast<unsigned char>(tok[i]);
    if (ch >= 0x20 && ch < 0x7f) {
      out += static_cast<char>(ch);
    } else {
      out += "\\x";
      out += hex[ch >> 4];
      out += hex[ch & 15];
    }
  }
  return out + (tok.size() > 40 ? "...'" : "'");
}

// The counts a body splits into (OFF and 4OFF) when they disagree with the header: every line
// classified once as a vertex (n numbers, perhaps with a color) and as a list ("k id ... [color]"),
// then the one split into vertices, faces (lists of >= 3 vertex ids) and cells (lists of face
// ids) that every line fits, preferring the header's own counts where they fit. Nothing when
// no split fits, or when the choice is not clear.
struct LineShape {
  bool vertex = false;
  bool list = false;
  std::uint64_t k = 0, max_id = 0;
};

bool is_number(std::string_view tok) {
  double v = 0;
  auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
  return ec == std::errc() && ptr == tok.data() + tok.size() && std::isfinite(v);
}

bool is_index(std::string_view tok, std::uint64_t* v) {
  auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), *v);
  return ec == std::errc() && ptr == tok.data() + tok.size();
}

LineShape classify(const std::vector<std::string_view>& t, int dim) {
  LineShape s;
  const std::size_t n = t.size(), d = static_cast<std::size_t>(dim);
  s.vertex = (n == d || n == d + 3 || n == d + 4) && std::all_of(t.begin(), t.end(), is_number);
  if (n >= 2 && is_index(t[0], &s.k) && s.k >= 1 &&
      (n == s.k + 1 || n == s.k + 4 || n == s.k + 5)) {
    s.list = true;
    for (std::size_t i = 1; i < n && s.list; ++i) {
      std::uint64_t v = 0;
      if (i <= s.k) {
        s.list = is_index(t[i], &v);
        s.max_id = std::max(s.max_id, v);
      } else {
        s.list = is_number(t[i]);
      }
    }
  }
  return s;
}

std::optional<std::vector<std::uint64_t>> infer_counts(LineReader reader, const Line* first,
                                                       int dim,
                                                       const std::vector<std::uint64_t>& header) {
  if (dim != 3 && dim != 4) return std::nullopt;
  std::vector<LineShape> shape;
  if (first) shape.push_back(classify(first->tokens, dim));
  for (Line l; reader.next(l);) shape.push_back(classify(l.tokens, dim));
  const std::size_t n = shape.size();
  std::size_t p = 0;  // the longest prefix of vertex lines
  while (p < n && shape[p].vertex) ++p;
  for (std::size_t i = p; i < n; ++i)
    if (!shape[i].list) return std::nullopt;
  std::size_t lo = p;  // vertex lines at its end that could also be lists
  while (lo > 0 && shape[lo - 1].list) --lo;
  // suffix_max[i]: the largest id in lines i..n-1; suffix_k[i]: the sum of their sizes.
  std::vector<std::uint64_t> suffix_max(n + 1, 0), suffix_k(n + 1, 0);
  std::vector<std::uint64_t> suffix_min_k(n + 1, UINT64_MAX);
  for (std::size_t i = n; i-- > 0;) {
    suffix_max[i] = std::max(suffix_max[i + 1], shape[i].max_id);
    suffix_k[i] = suffix_k[i + 1] + shape[i].k;
    suffix_min_k[i] = std::min(suffix_min_k[i + 1], shape[i].k);
  }
  // The header's vertex count where it fits, else the shortest vertex block: lines that read
  // both ways (in 4OFF "3 0 1 2" is a triangle or a point) are faces after it.
  std::vector<std::size_t> candidates;
  if (header[0] >= lo && header[0] <= p) candidates.push_back(header[0]);
  if (candidates.empty() || candidates.front() != lo) candidates.push_back(lo);
  for (const std::size_t nv : candidates) {
    if (nv < static_cast<std::size_t>(dim) + 1 || nv >= n) continue;
    if (dim == 3) {
      if (suffix_max[nv] + 1 == nv && suffix_min_k[nv] >= 3)
        return std::vector<std::uint64_t>{nv, n - nv, header[2]};
      continue;
    }
    // 4OFF: faces nv .. nv+nf-1, cells after them.
    std::vector<std::size_t> fits;
    std::uint64_t face_max = 0, face_min_k = UINT64_MAX;
    for (std::size_t nf = 1; nv + nf < n; ++nf) {
      face_max = std::max(face_max, shape[nv + nf - 1].max_id);
      face_min_k = std::min(face_min_k, shape[nv + nf - 1].k);
      if (face_max >= nv || face_min_k < 3) break;
      // The last vertex is used (a line that reads as a point but is no face's corner is not
      // taken for a vertex), every cell's faces exist.
      if (face_max + 1 == nv && suffix_max[nv + nf] < nf && suffix_min_k[nv + nf] >= 2)
        fits.push_back(nf);
    }
    if (fits.empty()) continue;
    auto fits_nf = [&](std::uint64_t nf) {
      return std::find(fits.begin(), fits.end(), nf) != fits.end();
    };
    std::optional<std::size_t> nf;
    // A closed complex has every face in exactly two cells: the one such split wins, then the
    // header's face count, then its cell count; nothing else is guessed.
    std::vector<std::size_t> closed;
    for (std::size_t f : fits)
      if (suffix_k[nv + f] == 2 * f) closed.push_back(f);
    if (closed.size() == 1) {
      nf = closed.front();
    } else if (fits_nf(header[1])) {
      nf = header[1];
    } else if (header[3] < n - nv && fits_nf(n - nv - header[3])) {
      nf = n - nv - header[3];
    }
    if (nf) return std::vector<std::uint64_t>{nv, *nf, header[2], n - nv - *nf};
  }
  return std::nullopt;
}

class Parser {
 public:
  Parser(std::string name, std::string_view text,
         std::optional<std::vector<std::uint64_t>> counts = std::nullopt)
      : name_(std::move(name)), reader_(text), forced_(std::move(counts)) {
    have_ = reader_.next(ahead_);
  }

  // After parse() failed reading the elements: the counts the body holds, when they differ
  // from the header's and the body splits clearly; also the line of the header's counts.
  std::optional<std::vector<std::uint64_t>> body_counts(std::size_t* count_line) const {
    if (!in_body_) return std::nullopt;
    *count_line = count_line_;
    auto c = infer_counts(body_reader_, have_body_ ? &body_first_ : nullptr, dim_, header_);
    if (c && *c == header_) return std::nullopt;
    return c;
  }
  const std::vector<std::uint64_t>& header_counts() const { return header_; }

  [[noreturn]] void fail(std::size_t line, const std::string& message) const {
    throw ParseError(name_, line, message);
  }

  // The next non-empty line; valid until the following call.
  const Line& next(const std::string& expected) {
    if (!have_) fail(eof_line_, "unexpected end of file: expected " + expected);
    std::swap(current_, ahead_);
    have_ = reader_.next(ahead_);
    if (!have_) eof_line_ = current_.number + 1;
    return current_;
  }
  bool at_end() const { return !have_; }
  std::size_t remaining() const { return have_ ? 1 + reader_.count_remaining(nullptr) : 0; }

  std::uint64_t parse_count(std::string_view tok, std::size_t line, const char* what) const {
    std::uint64_t v = 0;
    auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
    if (ec != std::errc() || ptr != tok.data() + tok.size())
      fail(line, std::string(what) + " " + show(tok) + " is not a non-negative integer");
    return v;
  }

  double parse_double(std::string_view tok, std::size_t line, const std::string& what) const {
    double v = 0;
    auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
    if (ec == std::errc::result_out_of_range)
      fail(line, what + " " + show(tok) + " is out of range");
    if (ec != std::errc() || ptr != tok.data() + tok.size())
      fail(line, what + " " + show(tok) + " is not a number");
    if (!std::isfinite(v)) fail(line, what + " " + show(tok) + " is not finite");
    return v;
  }

  // Trailing color: 3 or 4 components; integers are bytes 0..255, decimals (a '.' or an
  // exponent in any component) are on the 0..1 scale.
  Rgba parse_color(const Line& l, std::size_t first, const std::string& what) const {
    const std::size_t n = l.tokens.size() - first;
    if (n != 3 && n != 4)
      fail(l.number, what + " has " + std::to_string(n) +
                         " values after its indices (expected none, or a color of 3 or 4)");
    double c[4] = {1, 1, 1, 1};
    bool integral = true;
    for (std::size_t i = 0; i < n; ++i) {
      c[i] = parse_double(l.tokens[first + i], l.number, what + " color component");
      if (c[i] < 0 || c[i] > 255) fail(l.number, what + " color component out of range 0..255");
      integral = integral && l.tokens[first + i].find_first_of(".eE") == std::string_view::npos;
    }
    if (integral) {
      for (std::size_t i = 0; i < n; ++i) c[i] /= 255.0;
    } else {
      for (std::size_t i = 0; i < n; ++i)
        if (c[i] > 1) fail(l.number, what + " color mixes 0..1 decimals and 0..255 integers");
    }
    return {static_cast<float>(c[0]), static_cast<float>(c[1]), static_cast<float>(c[2]),
            static_cast<float>(c[3])};
  }

  // "k id_0 ... id_{k-1} [color]" with ids < bound, all distinct.
  std::vector<std::uint32_t> parse_list(const Line& l, std::uint64_t bound, const std::string& what,
                                        const char* child, std::size_t min_size, Rgba* color,
                                        bool* has_color) {
    const std::uint64_t k = parse_count(l.tokens[0], l.number, (what + " size").c_str());
    if (k < min_size)
      fail(l.number, what + " has " + std::to_string(k) + " entries, at least " +
                         std::to_string(min_size) + " needed");
    if (l.tokens.size() - 1 < k)
      fail(l.number, what + " announces " + std::to_string(k) + " entries but the line has " +
                         std::to_string(l.tokens.size() - 1));
    std::vector<std::uint32_t> ids;
    ids.reserve(k);
    for (std::size_t i = 1; i <= k; ++i) {
      const std::uint64_t v = parse_count(l.tokens[i], l.number, (what + " entry").c_str());
      if (v >= bound)
        fail(l.number, what + " refers to " + child + " " + std::to_string(v) +
                           ", but there are only " + std::to_string(bound));
      ids.push_back(static_cast<std::uint32_t>(v));
    }
    std::vector<std::uint32_t> sorted = ids;
    std::sort(sorted.begin(), sorted.end());
    if (auto d = std::adjacent_find(sorted.begin(), sorted.end()); d != sorted.end())
      fail(l.number, what + " lists " + child + " " + std::to_string(*d) + " twice");
    *has_color = l.tokens.size() > k + 1;
    if (*has_color) *color = parse_color(l, k + 1, what);
    return ids;
  }

  Complex parse() {
    const Line& head = next("a header (OFF, 4OFF or nOFF)");
    std::string_view h = head.tokens[0];
    int dim = 0;
    if (h == "OFF") {
      dim = 3;
    } else if (h.size() >= 4 && h.substr(h.size() - 3) == "OFF") {
      int v = 0;
      auto [ptr, ec] = std::from_chars(h.data(), h.data() + h.size() - 3, v);
      if (ec == std::errc() && ptr == h.data() + h.size() - 3) dim = v;
    }
    // Miratope writes points, segments and polygons as 0OFF, 1OFF and 2OFF: named as such, so
    // that the refusal does not read like a corrupt file.
    if (h == "0OFF" || h == "1OFF" || h == "2OFF")
      fail(head.number, "header " + show(h) + " is Miratope's file of a " +
                            (h[0] == '0'   ? "point"
                             : h[0] == '1' ? "segment"
                                           : "polygon") +
                            ", which cw4d does not read (it reads OFF and 4OFF to " +
                            std::to_string(max_off_dim) +
                            "OFF; polygon:P builds regular polygons)");
    if (dim < 3 || dim > max_off_dim)
      fail(head.number, "header " + show(h) + " is not OFF, 4OFF or nOFF with n = 3.." +
                            std::to_string(max_off_dim));
    // Counts may follow the header on the same line.
    std::vector<std::string_view> count_tokens(head.tokens.begin() + 1, head.tokens.end());
    std::size_t count_line = head.number;
    if (count_tokens.empty()) {
      const Line& l = next("the element counts");
      count_tokens = l.tokens;
      count_line = l.number;
    }
    if (count_tokens.size() != static_cast<std::size_t>(dim))
      fail(count_line, "expected " + std::to_string(dim) + " counts (V F E" +
                           (dim > 3 ? " C" : "") + (dim > 4 ? " ..." : "") + "), found " +
                           std::to_string(count_tokens.size()));
    std::vector<std::uint64_t> counts;
    for (auto tok : count_tokens) counts.push_back(parse_count(tok, count_line, "count"));
    header_ = counts;
    count_line_ = count_line;
    dim_ = dim;
    body_reader_ = reader_;
    body_first_ = ahead_;
    have_body_ = have_;
    in_body_ = true;
    if (forced_) counts = *forced_;
    const std::uint64_t nv = counts[0], nf = counts[1];
    // counts[2] (edges) is informational.
    // Counts never drive allocation before the data is seen to exist: the announced element
    // lines (a saturating sum, so huge counts cannot wrap) must all be in the file.
    std::uint64_t announced = 0;
    for (int k = 0; k < dim; ++k) {
      if (k == 2) continue;  // the edge count is informational
      announced = counts[k] > UINT64_MAX - announced ? UINT64_MAX : announced + counts[k];
    }
    if (announced > remaining())
      fail(count_line, "counts announce " + std::to_string(announced) +
                           " element lines but the file has only " + std::to_string(remaining()));

    ComplexSoup soup;
    soup.ambient_dim = dim;
    where_.lines.assign(static_cast<std::size_t>(dim), {});
    soup.positions.resize(dim, static_cast<Eigen::Index>(nv));
    for (std::uint64_t v = 0; v < nv; ++v) {
      const Line& l = next("vertex " + std::to_string(v));
      const std::size_t nt = l.tokens.size(), d = static_cast<std::size_t>(dim);
      if (nt != d && nt != d + 3 && nt != d + 4)
        fail(l.number, "vertex " + std::to_string(v) + " has " + std::to_string(l.tokens.size()) +
                           " coordinates, expected " + std::to_string(dim) +
                           " (or a color of 3 or 4 after them)");
      if (nt > d) parse_color(l, d, "vertex " + std::to_string(v));  // read, not kept
      for (int i = 0; i < dim; ++i)
        soup.positions(i, static_cast<Eigen::Index>(v)) =
            parse_double(l.tokens[i], l.number, "vertex " + std::to_string(v) + " coordinate");
      where_.lines[0].push_back(l.number);
    }
    std::vector<Rgba> colors;
    bool any_color = false;
    soup.faces.reserve(nf);
    for (std::uint64_t f = 0; f < nf; ++f) {
      const Line& l = next("face " + std::to_string(f));
      Rgba color;
      bool has = false;
      soup.faces.push_back(
          parse_list(l, nv, "face " + std::to_string(f), "vertex", 3, &color, &has));
      colors.push_back(color);
      any_color = any_color || has;
      where_.lines[2].push_back(l.number);
    }
    locate_edges(soup.faces);
    if (any_color) soup.face_colors = colors;
    for (int k = 3; k < dim; ++k) {
      const std::uint64_t below = k == 3 ? nf : counts[k - 1];
      const std::string kind = k == 3 ? "cell" : "rank-" + std::to_string(k) + " element";
      const char* child = k == 3 ? "face" : (k == 4 ? "cell" : "element");
      auto& level = soup.higher.emplace_back();
      level.reserve(counts[k]);
      colors.clear();
      any_color = false;
      for (std::uint64_t x = 0; x < counts[k]; ++x) {
        const Line& l = next(kind + " " + std::to_string(x));
        Rgba color;
        bool has = false;
        level.push_back(
            parse_list(l, below, kind + " " + std::to_string(x), child, 2, &color, &has));
        colors.push_back(color);
        any_color = any_color || has;
        where_.lines[k].push_back(l.number);
      }
      soup.higher_colors.push_back(any_color ? colors : std::vector<Rgba>{});
    }
    if (!at_end()) fail(ahead_.number, "unexpected data after the last element");
    in_body_ = false;
    try {
      return build_complex(soup);
    } catch (const TopologyError& e) {
      const std::size_t line = e.ids().empty() ? 0 : where_.line_of(e.rank(), e.ids().front());
      fail(line ? line : count_line, e.what());
    }
  }

  const OffLines& where() const { return where_; }

 private:
  // Edges in build_complex's numbering (distinct vertex pairs in order of first appearance in
  // the face cycles), each at the line of that face.
  void locate_edges(const std::vector<std::vector<std::uint32_t>>& faces) {
    std::unordered_set<std::uint64_t> seen;
    for (std::size_t f = 0; f < faces.size(); ++f) {
      const auto& cyc = faces[f];
      for (std::size_t i = 0; i < cyc.size(); ++i) {
        const std::uint64_t a = cyc[i], b = cyc[(i + 1) % cyc.size()];
        if (seen.insert(std::min(a, b) << 32 | std::max(a, b)).second)
          where_.lines[1].push_back(where_.lines[2][f]);
      }
    }
  }

  std::string name_;
  LineReader reader_;
  Line current_, ahead_;
  bool have_ = false;
  std::size_t eof_line_ = 1;
  OffLines where_;
  std::optional<std::vector<std::uint64_t>> forced_;
  // The state after the counts, for body_counts().
  std::vector<std::uint64_t> header_;
  std::size_t count_line_ = 0;
  int dim_ = 0;
  LineReader body_reader_;
  Line body_first_;
  bool have_body_ = false, in_body_ = false;
};

thread_local OffReadOptions current_options;

std::string count_text(const std::vector<std::uint64_t>& c) {
  std::string out;
  for (auto x : c) out += (out.empty() ? "" : " ") + std::to_string(x);
  return out;
}

Complex parse_text(const std::string& name, std::string_view text, OffLines* lines) {
  Parser parser(name, text);
  std::optional<std::vector<std::uint64_t>> body;
  std::size_t line = 0;
  std::exception_ptr original;
  try {
    Complex c = parser.parse();
    if (lines) *lines = parser.where();
    return c;
  } catch (const ParseError&) {
    body = parser.body_counts(&line);
    if (!body) throw;
    original = std::current_exception();
  }
  const auto& h = parser.header_counts();
  std::string what = "header counts " + count_text(h) + " disagree with the body, which holds " +
                     std::to_string((*body)[0]) + " vertices, " + std::to_string((*body)[1]) +
                     " faces" +
                     (body->size() > 3 ? ", " + std::to_string((*body)[3]) + " cells" : "");
  Parser again(name, text, body);
  Complex c;
  try {
    c = again.parse();
  } catch (const ParseError&) {
    std::rethrow_exception(original);  // the split did not hold: the header's problem it is
  }
  if (current_options.strict) throw ParseError(name, line, what + " (refused: strict reading)");
  if (lines) *lines = again.where();
  if (current_options.warn)
    current_options.warn(name + ":" + std::to_string(line) + ": " + what +
                         "; read as the body stands");
  return c;
}

void append_number(std::string& out, double v) {
  char buf[64];
  auto [ptr, ec] = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, ptr);
}

}  // namespace

ScopedOffReadOptions::ScopedOffReadOptions(OffReadOptions options)
    : previous_(std::exchange(current_options, std::move(options))) {}
ScopedOffReadOptions::~ScopedOffReadOptions() {
  current_options = std::move(previous_);
}
const OffReadOptions& off_read_options() {
  return current_options;
}

Complex read_off(std::istream& in, const std::string& name, OffLines* lines) {
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw ParseError(name, 0, "read error");
  return parse_text(name, text, lines);
}

Complex read_off_file(const std::string& path, OffLines* lines) {
  const std::string text = read_input_file(path);  // the tokens are views into it
  return parse_text(path, text, lines);
}

namespace {

std::string off_text(const Complex& c) {
  const int n = c.ambient_dim();
  if (n < 3 || n > max_off_dim)
    throw InputError("nOFF needs a complex in R^3 .. R^" + std::to_string(max_off_dim) +
                     ", this one is in R^" + std::to_string(n));
  std::string out;
  out += n == 3 ? "OFF" : std::to_string(n) + "OFF";
  out += "\n# written by cw4d\n";
  for (int k = 0; k < n; ++k) {
    const int rank = k == 0 ? 0 : (k == 1 ? 2 : (k == 2 ? 1 : k));
    if (k) out += ' ';
    out += std::to_string(c.count(rank));
  }
  out += "\n\n# Vertices\n";
  const auto& p = c.positions();
  for (Eigen::Index v = 0; v < p.cols(); ++v) {
    for (int i = 0; i < n; ++i) {
      if (i) out += ' ';
      append_number(out, p(i, v));
    }
    out += '\n';
  }
  auto append_color = [&](const std::vector<Rgba>& colors, std::uint32_t i) {
    if (colors.empty()) return;
    const Rgba& col = colors[i];
    for (float x : {col.r, col.g, col.b, col.a}) {
      out += ' ';
      const std::size_t at = out.size();
      append_number(out, x);
      // Decimals, so that they read back on the 0..1 scale (integers are bytes).
      if (out.find_first_of(".eE", at) == std::string::npos) out += ".0";
    }
  };
  out += "\n# Faces\n";
  for (std::uint32_t f = 0; f < c.count(2); ++f) {
    auto cyc = c.face_cycle(f);
    out += std::to_string(cyc.size());
    for (auto v : cyc) out += ' ' + std::to_string(v);
    append_color(c.colors(2), f);
    out += '\n';
  }
  for (int k = 3; k < n; ++k) {
    out += k == 3 ? "\n# Cells\n" : "\n# Rank " + std::to_string(k) + "\n";
    const Incidence& t = c.boundary(k);
    for (std::uint32_t x = 0; x < t.size(); ++x) {
      auto ids = t.ids(x);
      out += std::to_string(ids.size());
      for (auto id : ids) out += ' ' + std::to_string(id);
      append_color(c.colors(k), x);
      out += '\n';
    }
  }
  return out;
}

}  // namespace

void write_off(std::ostream& out, const Complex& complex) {
  const std::string text = off_text(complex);
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
}

void write_off_file(const std::string& path, const Complex& complex) {
  write_file_atomically(path, off_text(complex));
}

}  // namespace cw4d
