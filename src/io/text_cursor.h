// Reading whitespace-separated text formats (ASCII STL, PLY, OBJ) with line numbers in every
// error: "<name>:<line>: <format>: <what>".
#pragma once

#include <string>
#include <string_view>

namespace vesselmesh::io {

class TextCursor {
 public:
  TextCursor(std::string_view text, std::string name, std::string format)
      : text_(text), name_(std::move(name)), format_(std::move(format)) {}

  // The next word (skipping whitespace and newlines), or empty at the end of the text.
  std::string_view word();
  // The next word on the current line, or empty at its end (does not cross a newline).
  std::string_view word_on_line();
  // The rest of the current line, trimmed; moves to the next line.
  std::string_view rest_of_line();
  void expect(std::string_view keyword);
  double number();        // finite
  long long integer();    // whole number, any sign
  double number_on_line();  // the next number on this line (error at its end)
  bool at_end();
  int line() const { return line_; }
  size_t position() const { return pos_; }

  [[noreturn]] void fail(const std::string& what) const;
  static std::string quoted(std::string_view w);

 private:
  double parse_number(std::string_view w) const;
  std::string_view text_;
  std::string name_;
  std::string format_;
  size_t pos_ = 0;
  int line_ = 1;
};

}  // namespace vesselmesh::io
