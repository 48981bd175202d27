// Reading checked values from TOML files (toml++), shared by the case and the study files:
// every mistake is an InputError "FILE: KEY: what is wrong".
#pragma once

#include "mesh/trimesh.h"

#include <toml++/toml.h>

#include <initializer_list>
#include <string>
#include <vector>

namespace vesselmesh::io {

using TomlView = toml::node_view<const toml::node>;

// Parses TOML text; a syntax error is an InputError "PATH:LINE:COLUMN: what".
toml::table parse_toml(const std::string& text, const std::string& path);

// `file` relative to the folder of `base` (a file), unless absolute.
std::string resolve_path(const std::string& base, const std::string& file);

struct TomlReader {
  std::string path;

  [[noreturn]] void fail(const std::string& key, const std::string& what) const;
  // A finite number (an integer is accepted), positive unless `positive` is false.
  double number(const TomlView& node, const std::string& key, double fallback, bool positive = true) const;
  int integer(const TomlView& node, const std::string& key, int fallback, int least) const;
  std::string text(const TomlView& node, const std::string& key, const std::string& fallback) const;
  bool flag(const TomlView& node, const std::string& key, bool fallback) const;
  // An array of three numbers.
  Vec3 point(const TomlView& node, const std::string& key) const;
  std::vector<std::string> strings(const TomlView& node, const std::string& key) const;
  // The [[key]] tables of `root` in order, each with its name for messages ("key[i]"); none
  // when the key is absent; fails when it is not an array of tables.
  struct Entry {
    std::string where;
    const toml::table* table;
  };
  std::vector<Entry> tables(const toml::table& root, const std::string& key) const;
  // Fails on a key of `table` not in `keys`, listing those.
  void known_keys(const toml::table& table, const std::string& where, std::initializer_list<const char*> keys) const;
};

}  // namespace vesselmesh::io
