// Writing a file whole or not at all: write to a temporary file beside the target, then
// rename it over the target. A failure (or an exception in the writer) leaves no file and
// no temporary behind.
#pragma once

#include <functional>
#include <string>

namespace vesselmesh::io {

// Calls write(temporary_path) and renames the temporary file to `path` when it returns.
// The temporary keeps the target's extension (writers that pick a format by extension work).
// Throws InputError when the folder cannot be written; rethrows what `write` throws.
void write_atomically(const std::string& path, const std::function<void(const std::string&)>& write);

// Writes `text` to `path` atomically (write_atomically); InputError when it cannot.
void write_text(const std::string& path, const std::string& text);

// Reads a whole file into memory. Throws InputError naming the file when it cannot be read.
std::string read_file(const std::string& path);

// A name that may become part of a file name: letters, digits, '_', '-', '.' (not empty).
bool is_file_name_safe(const std::string& name);

}  // namespace vesselmesh::io
