// Typed errors of the library. Messages say what is wrong, where (file, element index,
// coordinates) and what to do; they are one line, ready to show a user.
//
// InputError: the input data (a file, a mesh handed in) cannot be used.   CLI exit code 2.
// OptionError: an option or parameter is out of its domain.                CLI exit code 2.
// InternalError: an invariant of ours broke (a bug).                       CLI exit code 1.
// ComputationError: a computation on valid input failed (a diverging flow). CLI exit code 1.
#pragma once

#include <stdexcept>
#include <string>

namespace vesselmesh {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class InputError : public Error {
 public:
  using Error::Error;
};

class OptionError : public Error {
 public:
  using Error::Error;
};

class InternalError : public Error {
 public:
  using Error::Error;
};

class ComputationError : public Error {
 public:
  using Error::Error;
};

// A long run stopped by a signal (SIGTERM, SIGINT) once it had saved what it needs to go on.
class StoppedError : public Error {
 public:
  StoppedError(const std::string& message, int signal) : Error(message), signal_(signal) {}
  int signal() const { return signal_; }

 private:
  int signal_;
};

[[noreturn]] void throw_internal(const char* condition, const char* file, int line,
                                 const std::string& message);

}  // namespace vesselmesh

// Always-on invariant check, also in release builds.
#define VM_CHECK(condition, message)                                              \
  do {                                                                            \
    if (!(condition)) ::vesselmesh::throw_internal(#condition, __FILE__, __LINE__, \
                                                   (message));                    \
  } while (false)
