#pragma once
// The kits the command line knows, each with its check and build. A kit's commands live in
// cli/src/<kit>_commands.cpp and only parse, call the kit's library and print.

#include <span>
#include <string>
#include <string_view>

#include "commands.h"

namespace fabkit::cli {

/// A design file handed to a kit: its settings and its text (already read, bounded).
struct DesignInput {
  const DesignSettings& settings;
  std::string text;
};

struct KitCommands {
  std::string_view kit;          ///< the name in the `fabkit:` header ("hacks")
  std::string_view description;  ///< one line for `fabkit --help` and error messages
  int (*check)(const DesignInput& input);
  int (*build)(const DesignInput& input);
};

/// Every kit this fabkit was built with, in a fixed order.
std::span<const KitCommands> kits();

// The kits' entry points.
int hacks_check(const DesignInput& input);
int hacks_build(const DesignInput& input);
int flatpack_check(const DesignInput& input);
int flatpack_build(const DesignInput& input);
int rods_check(const DesignInput& input);
int rods_build(const DesignInput& input);

/// `fabkit flatpack burn-test`: a sheet of test joints over ranges of kerf and interference.
struct BurnTestSettings {
  std::string output_dir;
  std::string material = "plywood";
  double thickness_mm = 3;
  std::string kerfs = "0.05:0.2:0.05";       ///< value, list "a,b" or range "start:stop:step"
  std::string interferences = "0:0.2:0.05";  ///< likewise
  double finger_width_mm = 0;                ///< 0: 3 × thickness
};
int flatpack_burn_test(const BurnTestSettings& settings);
int templates_check(const DesignInput& input);
int templates_build(const DesignInput& input);

}  // namespace fabkit::cli
