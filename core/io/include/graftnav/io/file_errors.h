#pragma once
// The error of an input file or folder that is not there (or cannot be opened): its own type, so
// that a caller can tell it from a bad value without reading the message (the Python module
// raises FileNotFoundError for it). The message is the same as before: it names the path.
#include <stdexcept>
#include <string>

namespace graftnav {

class MissingFileError : public std::runtime_error {
 public:
  MissingFileError(std::string path, const std::string& message)
      : std::runtime_error(message), path_(std::move(path)) {}
  const std::string& path() const noexcept { return path_; }

 private:
  std::string path_;
};

}  // namespace graftnav
