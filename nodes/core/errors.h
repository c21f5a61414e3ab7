// The error hierarchy shared by nodes and engine. Nodes throw these for broken preconditions and unreadable input;
// expected numerical outcomes (no convergence, an empty result) are data in a node's Result instead.
#pragma once

#include <stdexcept>
#include <string>

namespace scanfill {

// Base of every error scanfill reports to the user as one line.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A configuration key or value is wrong.
class ConfigError : public Error {
 public:
  using Error::Error;
};

// A file cannot be read or written, or its content is malformed. The message names the file.
class IoError : public Error {
 public:
  using Error::Error;
};

// An input is readable but unfit for the operation asked (too few points, degenerate geometry).
class InputError : public Error {
 public:
  using Error::Error;
};

// An internal invariant does not hold (a bug, not a user error).
class InvariantError : public Error {
 public:
  using Error::Error;
};

}  // namespace scanfill
