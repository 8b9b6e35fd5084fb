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

/// `s` with the ASCII letters A–Z made lower case (names compare case-blind, whatever the
/// locale; other bytes, UTF-8 included, are kept).
std::string ascii_lower(std::string_view s);

/// Whether `s` is an identifier: a letter or '_' first, then letters, digits and '_'.
bool is_identifier(std::string_view s);

/// `s` as XML 1.0 (or HTML) text or an attribute value: & < > " escaped, and the control
/// characters XML forbids (all below U+0020 but tab, line feed and carriage return) dropped.
std::string xml_escape(std::string_view s);

}  // namespace fabkit
