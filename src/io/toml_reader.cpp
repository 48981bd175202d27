#include "io/toml_reader.h"

#include "mesh/error.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace vesselmesh::io {

toml::table parse_toml(const std::string& text, const std::string& path) {
  try {
    return toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    throw InputError(fmt::format("{}:{}:{}: {}", path, e.source().begin.line, e.source().begin.column,
                                 std::string(e.description())));
  }
}

std::string resolve_path(const std::string& base, const std::string& file) {
  namespace fs = std::filesystem;
  const fs::path p(file);
  if (p.is_absolute()) return file;
  return (fs::path(base).parent_path() / p).lexically_normal().string();
}

void TomlReader::fail(const std::string& key, const std::string& what) const {
  throw InputError(fmt::format("{}: {}: {}", path, key, what));
}

double TomlReader::number(const TomlView& node, const std::string& key, double fallback, bool positive) const {
  if (!node) return fallback;
  const auto value = node.value<double>();
  if (!value || !std::isfinite(*value)) fail(key, "expected a number");
  if (positive && *value <= 0.0) fail(key, fmt::format("must be positive (found {})", *value));
  return *value;
}

int TomlReader::integer(const TomlView& node, const std::string& key, int fallback, int least) const {
  if (!node) return fallback;
  const auto value = node.value<int64_t>();
  if (!value || !node.is_integer()) fail(key, "expected an integer");
  if (*value < least || *value > 1000000000) fail(key, fmt::format("must be at least {} (found {})", least, *value));
  return static_cast<int>(*value);
}

std::string TomlReader::text(const TomlView& node, const std::string& key, const std::string& fallback) const {
  if (!node) return fallback;
  const auto value = node.value<std::string>();
  if (!value || !node.is_string()) fail(key, "expected a string");
  return *value;
}

bool TomlReader::flag(const TomlView& node, const std::string& key, bool fallback) const {
  if (!node) return fallback;
  const auto value = node.value<bool>();
  if (!value || !node.is_boolean()) fail(key, "expected true or false");
  return *value;
}

Vec3 TomlReader::point(const TomlView& node, const std::string& key) const {
  const toml::array* array = node.as_array();
  if (!array || array->size() != 3) fail(key, "expected three numbers, [x, y, z]");
  Vec3 p;
  for (int k = 0; k < 3; ++k) {
    const auto v = (*array)[static_cast<size_t>(k)].value<double>();
    if (!v || !std::isfinite(*v)) fail(key, "expected three numbers, [x, y, z]");
    p[k] = *v;
  }
  return p;
}

std::vector<std::string> TomlReader::strings(const TomlView& node, const std::string& key) const {
  std::vector<std::string> out;
  if (!node) return out;
  const toml::array* array = node.as_array();
  if (!array) fail(key, "expected an array of strings");
  for (const toml::node& item : *array) {
    const auto v = item.value<std::string>();
    if (!v || !item.is_string()) fail(key, "expected an array of strings");
    out.push_back(*v);
  }
  return out;
}

std::vector<TomlReader::Entry> TomlReader::tables(const toml::table& root, const std::string& key) const {
  std::vector<Entry> entries;
  const toml::node* node = root.get(key);
  if (!node) return entries;
  const toml::array* array = node->as_array();
  if (!array || !array->is_array_of_tables()) fail(key, fmt::format("expected [[{}]] tables", key));
  for (size_t k = 0; k < array->size(); ++k) entries.push_back({fmt::format("{}[{}]", key, k), (*array)[k].as_table()});
  return entries;
}

void TomlReader::known_keys(const toml::table& table, const std::string& where,
                            std::initializer_list<const char*> keys) const {
  for (const auto& [key, value] : table) {
    (void)value;
    const std::string name(key.str());
    if (std::none_of(keys.begin(), keys.end(), [&](const char* k) { return name == k; })) {
      std::string list;
      for (const char* k : keys) list += (list.empty() ? "" : ", ") + std::string(k);
      fail(where.empty() ? name : where + "." + name, fmt::format("unknown key (known here: {})", list));
    }
  }
}

}  // namespace vesselmesh::io
