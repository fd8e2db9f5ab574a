#pragma once
// XXH64 (Yann Collet's xxHash, 64-bit variant, seed 0), computed as bytes
// stream by, for checksums of the files descent writes (io/checkpoint.hpp).
// Written out here, in portable C++, rather than taken from libxxhash-dev:
// the algorithm is 60 lines, and the project then needs no new package.
//
// Why XXH64 and not CRC32C: it runs at several GB/s per core from plain
// 64-bit multiplies and rotations on any CPU, while CRC32C is that fast only
// through the SSE4.2 / ARMv8 CRC instructions (a table-driven CRC32C is about
// five times slower), which would need a second, CPU-specific code path. A
// 64-bit checksum also leaves a damaged file undetected with probability
// 2^-64, against 2^-32 for a CRC32C.
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace descent {

class XxHash64 {
 public:
  // Adds `size` bytes at `data`; any split of a byte stream into calls gives
  // the same digest.
  void update(const void* data, std::size_t size) {
    if (size == 0) return;  // `data` may then be null (an empty vector's), no memcpy from it
    const auto* p = static_cast<const unsigned char*>(data);
    total_ += size;
    if (buffered_ + size < kStripe) {  // not a whole stripe yet: keep the bytes
      std::memcpy(buffer_ + buffered_, p, size);
      buffered_ += size;
      return;
    }
    if (buffered_ > 0) {  // complete the stripe kept from earlier calls
      const std::size_t fill = kStripe - buffered_;
      std::memcpy(buffer_ + buffered_, p, fill);
      consume_stripe(buffer_);
      p += fill;
      size -= fill;
      buffered_ = 0;
    }
    for (; size >= kStripe; p += kStripe, size -= kStripe) consume_stripe(p);
    std::memcpy(buffer_, p, size);
    buffered_ = size;
  }

  std::uint64_t digest() const {
    std::uint64_t h;
    if (total_ >= kStripe) {
      h = rotl(lane_[0], 1) + rotl(lane_[1], 7) + rotl(lane_[2], 12) + rotl(lane_[3], 18);
      for (const std::uint64_t lane : lane_) h = (h ^ round(0, lane)) * kPrime1 + kPrime4;
    } else {
      h = kPrime5;
    }
    h += total_;
    const unsigned char* p = buffer_;
    std::size_t left = buffered_;
    for (; left >= 8; p += 8, left -= 8) h = rotl(h ^ round(0, load64(p)), 27) * kPrime1 + kPrime4;
    if (left >= 4) {
      h = rotl(h ^ (load32(p) * kPrime1), 23) * kPrime2 + kPrime3;
      p += 4;
      left -= 4;
    }
    for (; left > 0; ++p, --left) h = rotl(h ^ (*p * kPrime5), 11) * kPrime1;
    h ^= h >> 33;
    h *= kPrime2;
    h ^= h >> 29;
    h *= kPrime3;
    h ^= h >> 32;
    return h;
  }

 private:
  static constexpr std::uint64_t kPrime1 = 0x9E3779B185EBCA87ULL;
  static constexpr std::uint64_t kPrime2 = 0xC2B2AE3D27D4EB4FULL;
  static constexpr std::uint64_t kPrime3 = 0x165667B19E3779F9ULL;
  static constexpr std::uint64_t kPrime4 = 0x85EBCA77C2B2AE63ULL;
  static constexpr std::uint64_t kPrime5 = 0x27D4EB2F165667C5ULL;
  static constexpr std::size_t kStripe = 32;  // four 8-byte lanes

  static std::uint64_t rotl(std::uint64_t x, int r) { return (x << r) | (x >> (64 - r)); }
  static std::uint64_t round(std::uint64_t acc, std::uint64_t input) {
    return rotl(acc + input * kPrime2, 31) * kPrime1;
  }
  // Little-endian loads, as the algorithm defines them (memcpy: any alignment).
  static std::uint64_t load64(const unsigned char* p) {
    std::uint64_t v;
    std::memcpy(&v, p, sizeof v);
#if __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
    v = __builtin_bswap64(v);
#endif
    return v;
  }
  static std::uint64_t load32(const unsigned char* p) {
    std::uint32_t v;
    std::memcpy(&v, p, sizeof v);
#if __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
    v = __builtin_bswap32(v);
#endif
    return v;
  }
  void consume_stripe(const unsigned char* p) {
    for (int k = 0; k < 4; ++k) lane_[k] = round(lane_[k], load64(p + 8 * k));
  }

  std::uint64_t lane_[4] = {kPrime1 + kPrime2, kPrime2, 0, 0 - kPrime1};
  unsigned char buffer_[kStripe] = {};
  std::size_t buffered_ = 0;
  std::uint64_t total_ = 0;
};

}  // namespace descent
