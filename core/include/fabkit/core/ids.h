#pragma once
/// Typed ids: a part, a primitive of a part, a connection — never confused with each other
/// or with a bare int (geometry-central's mesh_data.h idea).

#include <compare>
#include <cstddef>

namespace fabkit {

template <class Tag>
struct Id {
  int value = -1;
  constexpr Id() = default;
  constexpr explicit Id(int v) : value(v) {}
  constexpr bool valid() const { return value >= 0; }
  /// The id as an index into the vector that holds its objects.
  constexpr std::size_t index() const { return static_cast<std::size_t>(value); }
  constexpr auto operator<=>(const Id&) const = default;
};

using PartId = Id<struct PartTag>;
using PrimitiveId = Id<struct PrimitiveTag>;  ///< a primitive's index within its part
using ConnectionId = Id<struct ConnectionTag>;

}  // namespace fabkit
