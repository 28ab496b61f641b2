#pragma once
// The error hierarchy of cw4d. The library never prints and never exits: it throws one of
// these, and the CLI maps each class to a documented exit code.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace cw4d {

/// Base of every error cw4d throws on purpose.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A caller passed an argument that makes no sense (zero normal, unknown model spec, ...).
class InputError : public Error {
 public:
  using Error::Error;
};

/// A file could not be parsed. what() is "FILE:LINE: message"; the parts are kept too.
class ParseError : public Error {
 public:
  ParseError(std::string file, std::size_t line, const std::string& message)
      : Error(file + ":" + std::to_string(line) + ": " + message),
        file_(std::move(file)),
        line_(line),
        message_(message) {}
  const std::string& file() const { return file_; }
  std::size_t line() const { return line_; }  ///< 1-based; 0 when the file could not be opened
  const std::string& message() const { return message_; }

 private:
  std::string file_;
  std::size_t line_;
  std::string message_;
};

/// The structure of a complex is broken (a face that is not a cycle, a cell that is not
/// closed, ...). Names the rank and the offending ids.
class TopologyError : public Error {
 public:
  TopologyError(int rank, std::vector<std::uint32_t> ids, const std::string& message)
      : Error(message), rank_(rank), ids_(std::move(ids)) {}
  int rank() const { return rank_; }
  const std::vector<std::uint32_t>& ids() const { return ids_; }

 private:
  int rank_;
  std::vector<std::uint32_t> ids_;
};

/// Reading or writing a file failed at the operating-system level.
class IoError : public Error {
 public:
  using Error::Error;
};

}  // namespace cw4d
