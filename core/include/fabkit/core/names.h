#pragma once
/// "Did you mean …?" for names a user typed.

#include <string>
#include <string_view>
#include <vector>

namespace fabkit {

/// The candidate closest to `name` (case-insensitive edit distance, a swap of two neighbours
/// counting once), or "" when none is reasonably close: at most a third of the name's length
/// may differ (at least 1, at most 3 edits).
std::string closest_name(std::string_view name, const std::vector<std::string>& candidates);

}  // namespace fabkit
