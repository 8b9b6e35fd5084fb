#pragma once
/// Text a user wrote, made safe to check and to echo in messages.

#include <cstddef>
#include <string>
#include <string_view>

namespace fabkit {

/// Whether `s` is well-formed UTF-8 (no overlong forms, surrogates or code points past
/// U+10FFFF).
bool is_valid_utf8(std::string_view s);

/// `s` with every invalid UTF-8 byte replaced by U+FFFD (valid text is returned as it is): what
/// a diagnostic's message becomes, so that every message can be printed and sent as JSON.
std::string to_valid_utf8(std::string_view s);

/// `s` for a message: invalid UTF-8 bytes replaced by U+FFFD, control characters by '?', and
/// cut after `max_chars` characters with "… (N more bytes)" — so a 1 MB name never becomes a
/// 1 MB error message.
std::string excerpt(std::string_view s, std::size_t max_chars = 60);

}  // namespace fabkit
