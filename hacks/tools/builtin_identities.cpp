// Reads the built-in part file's identities (each entry's name, aliases, description and
// category) at build time and writes them as a C++ table (hacks/CMakeLists.txt), so that a
// process does not parse them with yaml-cpp at every start: they were a quarter of a small
// design's `fabkit check`. Checks what the library would check of them and fails the build,
// naming the file and line, where one is wrong.
//
// Usage: fabkit_builtin_identities <parts.yaml> <output header>

#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "fabkit/core/text.h"

namespace {

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char code[8];
      std::snprintf(code, sizeof code, "\\%03o", static_cast<unsigned char>(c));
      out += code;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string lower(std::string s) {
  for (char& c : s) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s <parts.yaml> <output header>\n", argv[0]);
    return 2;
  }
  const std::string file = argv[1];
  bool ok = true;
  auto fail = [&](const YAML::Node& at, const std::string& what) {
    std::fprintf(stderr, "%s:%d: %s\n", file.c_str(), at.Mark().line + 1, what.c_str());
    ok = false;
  };
  YAML::Node root;
  try {
    root = YAML::LoadFile(file);
  } catch (const YAML::Exception& e) {
    std::fprintf(stderr, "%s: %s\n", file.c_str(), e.what());
    return 1;
  }
  const YAML::Node parts = root["parts"];
  if (!parts || !parts.IsSequence()) {
    std::fprintf(stderr, "%s: no 'parts' list\n", file.c_str());
    return 1;
  }
  std::ostringstream table;
  std::set<std::string> names;  // lower case: the library's lookups ignore case
  auto scalar = [&](const YAML::Node& entry, const char* key, std::string& out) {
    const YAML::Node n = entry[key];
    if (!n) return false;
    if (!n.IsScalar()) {
      fail(n, std::string(key) + " must be a string");
      return false;
    }
    out = n.Scalar();
    return true;
  };
  for (const YAML::Node& entry : parts) {
    std::string name, description, category;
    if (!scalar(entry, "name", name) || !fabkit::is_identifier(name)) {
      fail(entry, "each part needs a 'name' that is an identifier");
      continue;
    }
    std::vector<std::string> aliases{name};
    if (const YAML::Node list = entry["aliases"]) {
      if (!list.IsSequence()) fail(list, "'aliases' of " + name + " must be a list");
      for (const YAML::Node& a : list) {
        if (!a.IsScalar() || !fabkit::is_identifier(a.Scalar())) {
          fail(a, "an alias of " + name + " is not an identifier");
        } else {
          aliases.push_back(a.Scalar());
        }
      }
    }
    for (const std::string& a : aliases) {
      if (!names.insert(lower(a)).second) fail(entry, "'" + a + "' names two parts");
    }
    scalar(entry, "description", description);
    if (scalar(entry, "category", category)) {
      const std::string c = lower(category);
      if (c != "environment" && c != "hack" && c != "both" && c != "other") {
        fail(entry["category"], "unknown category '" + category + "' of " + name);
      }
    }
    table << "    {" << quoted(name) << ", {";
    for (std::size_t i = 1; i < aliases.size(); ++i) {
      table << (i > 1 ? ", " : "") << quoted(aliases[i]);
    }
    table << "}, " << quoted(description) << ", " << quoted(lower(category)) << "},\n";
  }
  if (!ok) return 1;
  std::ofstream out(argv[2], std::ios::binary);
  out << "#pragma once\n"
      << "// Generated from hacks/data/parts.yaml by fabkit_builtin_identities; do not edit.\n"
      << "#include <string_view>\n#include <vector>\n\n"
      << "namespace fabkit::hacks::builtin {\n\n"
      << "struct Identity {\n"
      << "  std::string_view name;\n"
      << "  std::vector<std::string_view> aliases;\n"
      << "  std::string_view description;\n"
      << "  std::string_view category;  // lower case; empty when the entry has none\n"
      << "};\n\n"
      << "// In the file's order, one per entry of its 'parts' list.\n"
      << "inline const std::vector<Identity> kIdentities = {\n"
      << table.str() << "};\n\n"
      << "}  // namespace fabkit::hacks::builtin\n";
  out.close();
  if (!out) {
    std::fprintf(stderr, "cannot write %s\n", argv[2]);
    return 1;
  }
  return 0;
}
