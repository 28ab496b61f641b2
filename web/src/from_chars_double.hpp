#pragma once
// std::from_chars and std::to_chars for double, which the libc++ of Debian's emscripten (LLVM 14)
// declares only for integers. Force-included into the WebAssembly build
// (web/wasm_dependencies.cmake) so that complex/ parses numbers there as it does natively. Same
// contract as the standard function for chars_format::general: no leading whitespace or '+',
// decimal digits with an optional exponent, "inf"/"infinity"/"nan" (no hexadecimal: "0x1" reads as
// 0 and stops at the x); invalid_argument when nothing is read, result_out_of_range when the value
// overflows. The conversion itself is strtod's (the "C" locale: emscripten has no other), correctly
// rounded. to_chars writes the shortest %g text that reads back as the same double (the round-trip
// guarantee of the standard's shortest form; the choice between fixed and exponent notation
// is printf's, which may differ from the standard's in length, never in value).
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <system_error>

namespace std {

inline from_chars_result from_chars(const char* first, const char* last, double& value,
                                    chars_format = chars_format::general) {
  // The longest prefix that looks like a decimal floating-point number or inf/nan.
  const char* p = first;
  if (p != last && *p == '-') ++p;
  const auto lower = [](char c) { return static_cast<char>(c | 0x20); };
  const auto word = [&](const char* w) {
    const char* q = p;
    for (; *w; ++w, ++q)
      if (q == last || lower(*q) != *w) return static_cast<const char*>(nullptr);
    return q;
  };
  const char* end = nullptr;
  if (const char* q = word("infinity"))
    end = q;
  else if (const char* q2 = word("inf"))
    end = q2;
  else if (const char* q3 = word("nan"))
    end = q3;
  else {
    const char* q = p;
    bool digits = false;
    while (q != last && *q >= '0' && *q <= '9') ++q, digits = true;
    if (q != last && *q == '.') {
      ++q;
      while (q != last && *q >= '0' && *q <= '9') ++q, digits = true;
    }
    if (!digits) return {first, errc::invalid_argument};
    if (q != last && lower(*q) == 'e') {
      const char* e = q + 1;
      if (e != last && (*e == '+' || *e == '-')) ++e;
      const char* d = e;
      while (d != last && *d >= '0' && *d <= '9') ++d;
      if (d != e) q = d;
    }
    end = q;
  }
  const std::string text(first, end);
  errno = 0;
  char* stop = nullptr;
  const double v = std::strtod(text.c_str(), &stop);
  if (stop != text.c_str() + text.size()) return {first, errc::invalid_argument};
  if (errno == ERANGE && std::isinf(v)) return {end, errc::result_out_of_range};
  value = v;
  return {end, errc{}};
}

inline to_chars_result to_chars(char* first, char* last, double value) {
  char buf[40];
  int n = 0;
  for (int precision = 1; precision <= 17; ++precision) {
    n = std::snprintf(buf, sizeof buf, "%.*g", precision, value);
    if (!std::isfinite(value) || std::strtod(buf, nullptr) == value) break;
  }
  if (n < 0 || n > last - first) return {last, errc::value_too_large};
  for (int i = 0; i < n; ++i) first[i] = buf[i];
  return {first + n, errc{}};
}

}  // namespace std
