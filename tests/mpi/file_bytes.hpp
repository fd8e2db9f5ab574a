#pragma once
// A file's raw bytes, read and written whole: the tests that damage files
// byte by byte (checkpoints) share these.
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace descent::testing {

inline std::vector<char> read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<char>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

inline void write_bytes(const std::string& path, const std::vector<char>& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

}  // namespace descent::testing
