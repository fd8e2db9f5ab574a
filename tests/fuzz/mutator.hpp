#pragma once
// Deterministic input mutations for the replay driver, which fuzzes without
// libFuzzer: a fixed seed gives the same inputs on every machine, so a
// finding in CI can be replayed anywhere.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace descent::fuzz {

// splitmix64. std::mt19937 with std::uniform_int_distribution would do, but
// the distribution is not specified bit for bit across standard libraries.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  // In [0, n); n > 0. The modulo bias is irrelevant here.
  std::size_t below(std::size_t n) { return static_cast<std::size_t>(next() % n); }

 private:
  std::uint64_t state_;
};

// `input` with one to four random edits: bit flips, truncation, insertion or
// replacement of tokens that break readers (huge numbers, nan, inf, section
// markers, quotes, invalid UTF-8), duplicated, deleted or swapped lines, and
// splices with another corpus input.
std::string mutate(const std::string& input, const std::vector<std::string>& corpus, Rng& rng);

}  // namespace descent::fuzz
