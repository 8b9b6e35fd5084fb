#include "fabkit/core/names.h"

#include <algorithm>

#include "fabkit/core/text.h"

namespace fabkit {
namespace {

// Optimal-string-alignment distance: insertions, deletions, substitutions and adjacent
// transpositions ("Mgu" -> "Mug") each cost 1.
std::size_t edit_distance(std::string_view a, std::string_view b) {
  const std::size_t n = a.size();
  const std::size_t m = b.size();
  std::vector<std::vector<std::size_t>> d(n + 1, std::vector<std::size_t>(m + 1, 0));
  for (std::size_t i = 0; i <= n; ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= m; ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= n; ++i) {
    for (std::size_t j = 1; j <= m; ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) {
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
      }
    }
  }
  return d[n][m];
}

}  // namespace

std::string closest_name(std::string_view name, const std::vector<std::string>& candidates) {
  const std::string l = ascii_lower(name);
  const std::size_t limit = std::clamp<std::size_t>(l.size() / 3, 1, 3);
  std::string best;
  std::size_t best_d = limit + 1;
  for (const std::string& c : candidates) {
    // More than `limit` characters longer or shorter cannot be within `limit` edits; skipping
    // them also keeps a huge typed name from costing len × len work.
    const std::size_t gap = l.size() > c.size() ? l.size() - c.size() : c.size() - l.size();
    if (gap > limit) continue;
    const std::size_t dist = edit_distance(l, ascii_lower(c));
    if (dist < best_d && dist < std::max<std::size_t>(l.size(), 1)) {
      best = c;
      best_d = dist;
    }
  }
  return best;
}

}  // namespace fabkit
