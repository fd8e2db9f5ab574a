#pragma once
// splitmix64 (Steele, Lea, Flood 2014): a 64-bit mix of an integer, for
// values that must be the same on every rank count (drawn by global id) and
// for spreading keys over ranks.
#include <cstdint>

namespace descent {

inline std::uint64_t splitmix64(std::uint64_t x) {
  std::uint64_t z = x + 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// A deterministic value in [-1, 1] for `id`.
inline double unit_noise(std::uint64_t id) {
  return static_cast<double>(splitmix64(id) >> 11) * (2.0 / 9007199254740992.0) - 1.0;
}

}  // namespace descent
