#include "io/text_cursor.h"

#include "mesh/error.h"

#include <fmt/format.h>

#include <cctype>
#include <charconv>
#include <cmath>

namespace vesselmesh::io {
namespace {
bool space(char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; }
}  // namespace

std::string_view TextCursor::word() {
  while (pos_ < text_.size() && space(text_[pos_])) {
    if (text_[pos_] == '\n') ++line_;
    ++pos_;
  }
  const size_t start = pos_;
  while (pos_ < text_.size() && !space(text_[pos_])) ++pos_;
  return text_.substr(start, pos_ - start);
}

std::string_view TextCursor::word_on_line() {
  while (pos_ < text_.size() && space(text_[pos_]) && text_[pos_] != '\n') ++pos_;
  const size_t start = pos_;
  while (pos_ < text_.size() && !space(text_[pos_])) ++pos_;
  return text_.substr(start, pos_ - start);
}

std::string_view TextCursor::rest_of_line() {
  const size_t end = std::min(text_.find('\n', pos_), text_.size());
  std::string_view rest = text_.substr(pos_, end - pos_);
  pos_ = end;
  if (pos_ < text_.size()) ++pos_, ++line_;
  while (!rest.empty() && space(rest.front())) rest.remove_prefix(1);
  while (!rest.empty() && space(rest.back())) rest.remove_suffix(1);
  return rest;
}

void TextCursor::expect(std::string_view keyword) {
  const std::string_view w = word();
  if (w != keyword) fail(fmt::format("expected '{}', found {}", keyword, quoted(w)));
}

double TextCursor::parse_number(std::string_view w) const {
  double value = 0.0;
  const char* begin = w.data() + (!w.empty() && w.front() == '+' ? 1 : 0);
  const auto [end, ec] = std::from_chars(begin, w.data() + w.size(), value);
  if (w.empty() || ec != std::errc() || end != w.data() + w.size())
    fail(fmt::format("expected a number, found {}", quoted(w)));
  if (!std::isfinite(value)) fail(fmt::format("non-finite coordinate '{}'", w));
  return value;
}

double TextCursor::number() { return parse_number(word()); }

double TextCursor::number_on_line() { return parse_number(word_on_line()); }

long long TextCursor::integer() {
  const std::string_view w = word();
  long long value = 0;
  const char* begin = w.data() + (!w.empty() && w.front() == '+' ? 1 : 0);
  const auto [end, ec] = std::from_chars(begin, w.data() + w.size(), value);
  if (w.empty() || ec != std::errc() || end != w.data() + w.size())
    fail(fmt::format("expected a whole number, found {}", quoted(w)));
  return value;
}

bool TextCursor::at_end() {
  while (pos_ < text_.size() && space(text_[pos_])) {
    if (text_[pos_] == '\n') ++line_;
    ++pos_;
  }
  return pos_ >= text_.size();
}

void TextCursor::fail(const std::string& what) const {
  throw InputError(fmt::format("{}:{}: {}: {}", name_, line_, format_, what));
}

std::string TextCursor::quoted(std::string_view w) {
  return w.empty() ? "the end of the line or file" : fmt::format("'{}'", w.substr(0, 40));
}

}  // namespace vesselmesh::io
