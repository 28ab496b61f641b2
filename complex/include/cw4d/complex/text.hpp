#pragma once
// Text from the user in messages and in generated files: shortened when echoed, made valid UTF-8
// where a format demands it (JSON).
#include <cstddef>
#include <string>
#include <string_view>

namespace cw4d {

/// How many bytes of user text an error message echoes before it cuts.
inline constexpr std::size_t kEchoBytes = 100;

/// `text` in single quotes for an error message: whole when short, else its first kEchoBytes
/// bytes (cut on a UTF-8 boundary) and "...' (N bytes)". Newlines become spaces (every error is
/// one line). Every message that echoes a name, spec, path or value the user gave uses it, so a
/// 6 MB spec gives a short error line.
std::string quote_user_text(std::string_view text);

/// The length of the valid UTF-8 sequence starting at s[i] (1..4), or 0 when the bytes there
/// are not one (a stray continuation byte, an overlong form, a surrogate, beyond U+10FFFF, cut
/// short).
std::size_t utf8_sequence_length(std::string_view s, std::size_t i);

/// `s` with every byte that is not part of a valid UTF-8 sequence replaced by U+FFFD (JSON and
/// glTF hold only valid UTF-8; file names need not be).
std::string to_valid_utf8(std::string_view s);

}  // namespace cw4d
