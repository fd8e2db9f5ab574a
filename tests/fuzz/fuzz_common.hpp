#pragma once
// What the fuzz targets share with the replay driver. Both targets are built
// two ways: with libFuzzer's own main (clang -fsanitize=fuzzer) and with
// replay_main.cpp (any compiler), so nothing here may depend on either.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace descent::fuzz {

// Inputs the code under test accepted (returned without throwing). The replay
// driver prints it: a corpus that is all rejected fuzzes only the first lines.
inline std::size_t accepted_inputs = 0;

// A result that breaks what the API promises for accepted input: reported
// like a crash, so libFuzzer and the replay driver both keep the input.
[[noreturn]] inline void broken_promise(const char* what) {
  std::fprintf(stderr, "fuzz finding: accepted input, but %s\n", what);
  std::abort();
}

}  // namespace descent::fuzz
