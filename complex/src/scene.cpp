#include "cw4d/complex/scene.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <ios>
#include <iterator>
#include <numbers>
#include <sstream>
#include <string_view>
#include <unordered_map>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/input_file.hpp"

namespace cw4d {

namespace {

using json = nlohmann::json;
namespace fs = std::filesystem;

// nlohmann's DOM keeps no source positions. The lexer reads the text through this iterator,
// which records how far it got, so each SAX event can be given the line it was read on.
class CountingIterator {
 public:
  using iterator_category = std::input_iterator_tag;
  using value_type = char;
  using difference_type = std::ptrdiff_t;
  using pointer = const char*;
  using reference = const char&;

  CountingIterator() = default;
  CountingIterator(const char* p, const char** read_end) : p_(p), read_end_(read_end) {}
  reference operator*() const { return *p_; }
  CountingIterator& operator++() {
    ++p_;
    if (read_end_) *read_end_ = p_;
    return *this;
  }
  CountingIterator operator++(int) {
    CountingIterator old = *this;
    ++*this;
    return old;
  }
  friend bool operator==(const CountingIterator& a, const CountingIterator& b) {
    return a.p_ == b.p_;
  }

 private:
  const char* p_ = nullptr;
  const char** read_end_ = nullptr;
};

// Line numbers of byte offsets in a text.
class Lines {
 public:
  explicit Lines(std::string_view text) : text_(text) {
    for (std::size_t i = 0; i < text.size(); ++i)
      if (text[i] == '\n') newlines_.push_back(i);
  }
  // 1-based line of the last non-blank character before `end`. The lexer may have read one
  // character past a number (a newline, say), so blanks at the end do not count.
  std::size_t line_before(std::size_t end) const {
    end = std::min(end, text_.size());
    while (end > 0 && std::strchr(" \t\r\n", text_[end - 1])) --end;
    if (end == 0) return 1;
    const std::size_t at = end - 1;
    return static_cast<std::size_t>(std::lower_bound(newlines_.begin(), newlines_.end(), at) -
                                    newlines_.begin()) +
           1;
  }

 private:
  std::string_view text_;
  std::vector<std::size_t> newlines_;
};

// Paths of values in the document, in JSON-pointer syntax ("/objects/0/rotate/1").
std::string child(const std::string& path, const std::string& token) {
  std::string out = path + '/';
  for (char ch : token) {
    if (ch == '~')
      out += "~0";
    else if (ch == '/')
      out += "~1";
    else
      out += ch;
  }
  return out;
}
std::string child(const std::string& path, std::size_t index) {
  return path + '/' + std::to_string(index);
}

// A parsed document with the line of every value and of every object key.
struct Document {
  std::string name;
  json root;
  std::unordered_map<std::string, std::size_t> value_line, key_line;

  std::size_t line(const std::string& path) const {
    const auto it = value_line.find(path);
    return it == value_line.end() ? 1 : it->second;
  }
  [[noreturn]] void fail(const std::string& path, const std::string& message) const {
    throw ParseError(name, line(path), message);
  }
  [[noreturn]] void fail_key(const std::string& path, const std::string& message) const {
    const auto it = key_line.find(path);
    throw ParseError(name, it == key_line.end() ? line(path) : it->second, message);
  }
};

// Builds the DOM from SAX events, recording lines; rejects duplicate keys (which nlohmann's own
// DOM parser silently overwrites).
class Builder final : public nlohmann::json_sax<json> {
 public:
  Builder(Document& doc, const Lines& lines, const char* begin, const char* const* read_end)
      : doc_(doc), lines_(lines), begin_(begin), read_end_(read_end) {}

  bool null() override { return put(nullptr) != nullptr; }
  bool boolean(bool v) override { return put(v) != nullptr; }
  bool number_integer(number_integer_t v) override { return put(v) != nullptr; }
  bool number_unsigned(number_unsigned_t v) override { return put(v) != nullptr; }
  bool number_float(number_float_t v, const string_t&) override { return put(v) != nullptr; }
  bool string(string_t& v) override { return put(v) != nullptr; }
  bool binary(binary_t& v) override { return put(json::binary(v)) != nullptr; }
  bool start_object(std::size_t) override { return open(json::object()); }
  bool start_array(std::size_t) override { return open(json::array()); }
  bool end_object() override { return close(); }
  bool end_array() override { return close(); }
  bool key(string_t& k) override {
    const std::string path = child(paths_.back(), k);
    if (stack_.back()->contains(k))
      throw ParseError(doc_.name, line_now(), "duplicate key \"" + k + "\"");
    doc_.key_line[path] = line_now();
    key_ = k;
    return true;
  }
  bool parse_error(std::size_t position, const std::string&,
                   const nlohmann::detail::exception& ex) override {
    // what() is "[json.exception.parse_error.101] parse error at line L, column C: <reason>";
    // keep the reason, the line is ours.
    std::string reason = ex.what();
    const std::size_t column = reason.find(", column ");
    const std::size_t colon = column == std::string::npos ? column : reason.find(": ", column);
    if (colon != std::string::npos) reason = reason.substr(colon + 2);
    // The reason quotes the input ("last read: ..."), which may hold bytes that are not UTF-8
    // or not printable: escape them, so the message stays one printable line.
    std::string printable;
    for (const char ch : reason) {
      const auto b = static_cast<unsigned char>(ch);
      if (b >= 0x20 && b < 0x7f) {
        printable += ch;
      } else {
        static const char* hex = "0123456789abcdef";
        printable += {'\\', 'x', hex[b >> 4], hex[b & 15]};
      }
    }
    throw ParseError(doc_.name, lines_.line_before(position), "invalid JSON: " + printable);
  }

 private:
  std::size_t line_now() const {
    return lines_.line_before(static_cast<std::size_t>(*read_end_ - begin_));
  }
  // Stores a value at the current place; returns it.
  json* put(json v) {
    std::string path;
    json* slot = nullptr;
    if (stack_.empty()) {
      doc_.root = std::move(v);
      slot = &doc_.root;
    } else if (stack_.back()->is_array()) {
      json& parent = *stack_.back();
      path = child(paths_.back(), parent.size());
      parent.push_back(std::move(v));
      slot = &parent.back();
    } else {
      path = child(paths_.back(), key_);
      slot = &((*stack_.back())[key_] = std::move(v));
    }
    doc_.value_line[path] = line_now();
    last_path_ = std::move(path);
    return slot;
  }
  // A container's children are added only while it is the innermost one, so the pointer to it
  // stays valid until it is closed.
  bool open(json container) {
    // A scene is a few levels deep; each level holds its path (of length ~ depth), so a
    // document nested 10^5 deep would take gigabytes before any check could reject it.
    if (stack_.size() >= max_scene_nesting)
      throw ParseError(doc_.name, line_now(),
                       "arrays and objects nest more than " + std::to_string(max_scene_nesting) +
                           " deep (a scene needs a few levels)");
    json* slot = put(std::move(container));
    stack_.push_back(slot);
    paths_.push_back(last_path_);
    return true;
  }
  bool close() {
    stack_.pop_back();
    paths_.pop_back();
    return true;
  }

  Document& doc_;
  const Lines& lines_;
  const char* begin_;
  const char* const* read_end_;
  std::vector<json*> stack_;
  std::vector<std::string> paths_;
  std::string key_, last_path_;
};

Document parse_document(const std::string& text, const std::string& name) {
  Document doc;
  doc.name = name;
  const Lines lines(text);
  const char* read_end = text.data();
  Builder builder(doc, lines, text.data(), &read_end);
  json::sax_parse(CountingIterator(text.data(), &read_end),
                  CountingIterator(text.data() + text.size(), nullptr), &builder,
                  json::input_format_t::json, /*strict=*/true, /*ignore_comments=*/true);
  return doc;
}

// --- checking the document ---------------------------------------------------------------

const char* type_name(const json& j) {
  if (j.is_number()) return "a number";
  if (j.is_string()) return "a string";
  if (j.is_array()) return "an array";
  if (j.is_object()) return "an object";
  if (j.is_boolean()) return "a boolean";
  return "null";
}

std::string join(const std::vector<std::string>& words) {
  std::string out;
  for (const auto& w : words) out += (out.empty() ? "" : ", ") + w;
  return out;
}

class SceneReader {
 public:
  SceneReader(const Document& doc, std::string base, const Catalogue& catalogue)
      : doc_(doc), base_(std::move(base)), catalogue_(catalogue) {}

  Scene read() {
    const json& root = doc_.root;
    if (!root.is_object())
      doc_.fail(
          "", std::string("a scene is a JSON object {\"objects\": [...]}, not ") + type_name(root));
    check_keys(root, "", {"objects"}, "the scene");
    if (!root.contains("objects")) doc_.fail("", "the scene has no \"objects\" array");
    const std::string path = "/objects";
    const json& objects = root.at("objects");
    if (!objects.is_array())
      doc_.fail(path, std::string("\"objects\" must be an array, not ") + type_name(objects));
    if (objects.empty()) doc_.fail(path, "the scene has no objects");
    Scene scene;
    for (std::size_t i = 0; i < objects.size(); ++i)
      scene.objects.push_back(read_object(objects[i], child(path, i), i, scene));
    return scene;
  }

 private:
  [[noreturn]] void fail(const std::string& path, const std::string& message) const {
    doc_.fail(path, where_ + message);
  }

  void check_keys(const json& object, const std::string& path,
                  const std::vector<std::string>& allowed, const std::string& what) const {
    for (const auto& item : object.items())
      if (std::find(allowed.begin(), allowed.end(), item.key()) == allowed.end())
        doc_.fail_key(child(path, item.key()), where_ + "unknown key \"" + item.key() + "\" in " +
                                                   what + " (allowed: " + join(allowed) + ")");
  }

  double number(const json& j, const std::string& path, const std::string& what) const {
    if (!j.is_number()) fail(path, what + " must be a number, not " + type_name(j));
    const double v = j.get<double>();
    if (!std::isfinite(v)) fail(path, what + " is not finite");
    return v;
  }

  // A number per axis of the model.
  Eigen::VectorXd vector(const json& j, const std::string& path, const std::string& what,
                         int dim) const {
    if (!j.is_array() || j.size() != static_cast<std::size_t>(dim))
      fail(path, what + " must be an array of " + std::to_string(dim) +
                     " numbers (one per axis of the model)");
    Eigen::VectorXd v(dim);
    for (int i = 0; i < dim; ++i)
      v(i) = number(j[i], child(path, i), what + " component " + std::to_string(i + 1));
    return v;
  }

  Rgba color(const json& j, const std::string& path, const std::string& what, float opacity) const {
    const std::string expected = " (expected \"#rrggbb\" or [r, g, b] with components in 0..1)";
    Rgba c;
    c.a = opacity;
    if (j.is_string()) {
      const std::string s = j.get<std::string>();
      auto hex = [](char ch) {
        if (ch >= '0' && ch <= '9') return ch - '0';
        if (ch >= 'a' && ch <= 'f') return ch - 'a' + 10;
        if (ch >= 'A' && ch <= 'F') return ch - 'A' + 10;
        return -1;
      };
      bool ok = s.size() == 7 && s[0] == '#';
      float rgb[3] = {0, 0, 0};
      for (int i = 0; ok && i < 3; ++i) {
        const int hi = hex(s[1 + 2 * i]), lo = hex(s[2 + 2 * i]);
        ok = hi >= 0 && lo >= 0;
        rgb[i] = static_cast<float>(hi * 16 + lo) / 255.0f;
      }
      if (!ok) fail(path, "bad " + what + " \"" + s + "\"" + expected);
      c.r = rgb[0], c.g = rgb[1], c.b = rgb[2];
      return c;
    }
    if (!j.is_array() || j.size() != 3) fail(path, "bad " + what + expected);
    float rgb[3];
    for (int i = 0; i < 3; ++i) {
      const double v = number(j[i], child(path, i), what + " component " + std::to_string(i + 1));
      if (v < 0.0 || v > 1.0)
        fail(child(path, i), what + " component " + std::to_string(i + 1) + " is outside 0..1");
      rgb[i] = static_cast<float>(v);
    }
    c.r = rgb[0], c.g = rgb[1], c.b = rgb[2];
    return c;
  }

  std::shared_ptr<const Complex> load(const std::string& spec, const std::string& path) {
    // Only what load_model would take for a file name moves to the scene's directory, so that
    // a misspelt built-in stays an "unknown model" error.
    std::string resolved = spec;
    std::error_code ec;
    if (!base_.empty() && !catalogue_.find(spec) && fs::path(spec).is_relative() &&
        (spec.find_first_of("/.") != std::string::npos || fs::exists(fs::path(base_) / spec, ec)))
      resolved = (fs::path(base_) / spec).lexically_normal().string();
    if (const auto it = cache_.find(resolved); it != cache_.end()) return it->second;
    std::shared_ptr<const Complex> model;
    try {
      model = std::make_shared<const Complex>(catalogue_.load(resolved));
    } catch (const InputError& e) {
      // An unknown or malformed built-in spec is a mistake in the scene: report its line.
      fail(path, e.what());
    } catch (const std::ios_base::failure& e) {
      // A directory opens as a stream but cannot be read.
      throw ParseError(resolved, 0, std::string("cannot read: ") + e.what());
    }
    cache_.emplace(resolved, model);
    return model;
  }

  SceneObject read_object(const json& j, const std::string& path, std::size_t index,
                          const Scene& scene) {
    where_ = "object " + std::to_string(index) + ": ";
    if (!j.is_object()) fail(path, std::string("must be an object, not ") + type_name(j));
    check_keys(j, path,
               {"model", "name", "scale", "rotate", "translate", "color", "opacity", "cell_colors"},
               "an object");
    SceneObject obj;
    const std::string model_path = child(path, "model");
    if (!j.contains("model")) fail(path, "has no \"model\"");
    if (!j["model"].is_string() || j["model"].get<std::string>().empty())
      fail(model_path, "\"model\" must be a non-empty string (a built-in spec or a file)");
    obj.model = j["model"].get<std::string>();
    where_ = "object " + std::to_string(index) + " (" + obj.model + "): ";
    obj.complex = load(obj.model, model_path);
    const int dim = obj.complex->ambient_dim();
    if (!scene.objects.empty() && scene.dim() != dim)
      fail(model_path, "the model lives in R^" + std::to_string(dim) + " but object 0's in R^" +
                           std::to_string(scene.dim()) + "; a scene has one dimension");

    if (j.contains("name")) {
      if (!j["name"].is_string())
        fail(child(path, "name"),
             std::string("\"name\" must be a string, not ") + type_name(j["name"]));
      obj.name = j["name"].get<std::string>();
    }

    AffineTransform xf = AffineTransform::identity(dim);
    if (j.contains("scale")) {
      const std::string p = child(path, "scale");
      const json& s = j["scale"];
      Eigen::VectorXd factors = s.is_array()
                                    ? vector(s, p, "\"scale\"", dim)
                                    : Eigen::VectorXd::Constant(dim, number(s, p, "\"scale\""));
      for (int i = 0; i < dim; ++i)
        if (factors(i) == 0.0)
          fail(s.is_array() ? child(p, i) : p, "\"scale\" must not be zero (a flat object)");
      xf = AffineTransform::scale(factors);
    }
    if (j.contains("rotate")) {
      const std::string p = child(path, "rotate");
      const json& r = j["rotate"];
      const std::string expected = " (expected [[\"xw\", 30], ...]: planes and degrees)";
      if (!r.is_array()) fail(p, "\"rotate\" must be an array of [plane, degrees]" + expected);
      for (std::size_t k = 0; k < r.size(); ++k) {
        const std::string pk = child(p, k);
        if (!r[k].is_array() || r[k].size() != 2 || !r[k][0].is_string())
          fail(pk, "rotation " + std::to_string(k + 1) + " is not [plane, degrees]" + expected);
        const std::string plane = r[k][0].get<std::string>();
        std::pair<int, int> axes;
        try {
          axes = parse_rotation_plane(plane);
        } catch (const InputError& e) {
          fail(child(pk, 0), e.what());
        }
        if (axes.first >= dim || axes.second >= dim)
          fail(child(pk, 0), "rotation plane \"" + plane + "\" needs an axis the model (R^" +
                                 std::to_string(dim) + ") does not have");
        const double degrees =
            number(r[k][1], child(pk, 1), "the angle of rotation " + std::to_string(k + 1));
        xf = AffineTransform::rotation(dim, axes.first, axes.second,
                                       degrees * std::numbers::pi / 180.0) *
             xf;
      }
    }
    if (j.contains("translate"))
      xf = AffineTransform::translation(
               vector(j["translate"], child(path, "translate"), "\"translate\"", dim)) *
           xf;
    obj.transform = xf;

    float opacity = 1.0f;
    if (j.contains("opacity")) {
      const std::string p = child(path, "opacity");
      const double o = number(j["opacity"], p, "\"opacity\"");
      if (o < 0.0 || o > 1.0) fail(p, "\"opacity\" must lie in [0, 1]");
      opacity = static_cast<float>(o);
    }
    obj.color.a = opacity;
    if (j.contains("color")) obj.color = color(j["color"], child(path, "color"), "color", opacity);

    if (j.contains("cell_colors")) {
      const std::string p = child(path, "cell_colors");
      const json& cc = j["cell_colors"];
      if (!cc.is_object())
        fail(p, "\"cell_colors\" must be an object {\"<cell id>\": color, ...}, not " +
                    std::string(type_name(cc)));
      const std::size_t cells = obj.complex->top_rank() >= 3 ? obj.complex->count(3) : 0;
      for (const auto& item : cc.items()) {
        const std::string& key = item.key();
        const std::string pk = child(p, key);
        std::uint32_t id = 0;
        const bool digits =
            !key.empty() && key.size() <= 9 &&
            std::all_of(key.begin(), key.end(), [](char ch) { return ch >= '0' && ch <= '9'; });
        if (digits) id = static_cast<std::uint32_t>(std::stoul(key));
        if (!digits || id >= cells)
          doc_.fail_key(pk, where_ + "cell id \"" + key + "\" is not in 0.." +
                                (cells ? std::to_string(cells - 1) : std::string("(none)")) +
                                " (the model has " + std::to_string(cells) + " 3-cells)");
        obj.cell_colors[id] = color(item.value(), pk, "color of cell " + key, opacity);
      }
    }
    where_.clear();
    return obj;
  }

  const Document& doc_;
  std::string base_;
  const Catalogue& catalogue_;
  std::map<std::string, std::shared_ptr<const Complex>> cache_;
  std::string where_;  // "object i (model): ", prefixed to messages about an object
};

}  // namespace

Scene read_scene(std::istream& in, const std::string& name, const std::string& base_directory,
                 const Catalogue& catalogue) {
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw ParseError(name, 0, "cannot read");
  const Document doc = parse_document(text.str(), name);
  return SceneReader(doc, base_directory, catalogue).read();
}

Scene read_scene_file(const std::string& path, const Catalogue& catalogue) {
  const std::string text = read_input_file(path);
  const std::string dir = fs::path(path).parent_path().string();
  return SceneReader(parse_document(text, path), dir.empty() ? "." : dir, catalogue).read();
}

}  // namespace cw4d
