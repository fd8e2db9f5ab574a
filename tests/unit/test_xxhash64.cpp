// XXH64 (common/xxhash64.hpp) against digests of the reference library
// (libxxhash 0.8.1's XXH64, seed 0), and the same digest however the bytes
// are split into update calls, as a checkpoint writer splits them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "common/xxhash64.hpp"

namespace descent {
namespace {

// Byte k of the test input: (7 k + 3) mod 256.
std::vector<unsigned char> input(std::size_t size) {
  std::vector<unsigned char> bytes(size);
  for (std::size_t k = 0; k < size; ++k) bytes[k] = static_cast<unsigned char>(7 * k + 3);
  return bytes;
}

std::uint64_t digest_of(const std::vector<unsigned char>& bytes, std::size_t size) {
  XxHash64 hash;
  hash.update(bytes.data(), size);
  return hash.digest();
}

TEST(XxHash64, MatchesTheReferenceLibrary) {
  const std::vector<unsigned char> bytes = input(1000);
  // Each length reaches another path: empty, tail bytes, a 4-byte tail, an
  // 8-byte tail, below, at and past one 32-byte stripe, many stripes.
  const std::pair<std::size_t, std::uint64_t> expected[] = {
      {0, 0xef46db3751d8e999ULL},   {1, 0x1f25c8d0bc1f4bb6ULL},   {3, 0x31d2363f52e564c9ULL},
      {4, 0x9bb64b7d66ee9fdaULL},   {7, 0x9a7b149959ce60d8ULL},   {8, 0xdab99d95c6f90092ULL},
      {31, 0xa2aa5f33cc4a6119ULL},  {32, 0x23c3c17ef790fd97ULL},  {33, 0x50a7cfc7ba588784ULL},
      {100, 0xa61f8d4c170fe531ULL}, {1000, 0x5f235fa033f1a3fbULL}};
  for (const auto& [size, digest] : expected)
    EXPECT_EQ(digest_of(bytes, size), digest) << size << " bytes";
}

TEST(XxHash64, AnySplitGivesTheSameDigest) {
  const std::vector<unsigned char> bytes = input(1000);
  const std::uint64_t whole = digest_of(bytes, bytes.size());
  for (const std::size_t piece :
       {std::size_t{1}, std::size_t{5}, std::size_t{31}, std::size_t{64}, std::size_t{333}}) {
    XxHash64 hash;
    for (std::size_t at = 0; at < bytes.size(); at += piece)
      hash.update(bytes.data() + at, std::min(piece, bytes.size() - at));
    EXPECT_EQ(hash.digest(), whole) << "pieces of " << piece;
  }
  // One changed bit changes the digest.
  std::vector<unsigned char> changed = bytes;
  changed[500] ^= 1;
  EXPECT_NE(digest_of(changed, changed.size()), whole);
}

}  // namespace
}  // namespace descent
