#include "tests/fuzz/mutator.hpp"

#include <algorithm>
#include <string_view>
#include <utility>

namespace descent::fuzz {

namespace {

// Tokens that sit at the edges of what the readers parse: integer and double
// overflow, the 32-bit index limit, non-finite values, negative counts,
// section markers of each format and TOML syntax, and bytes that are not UTF-8.
constexpr std::string_view kTokens[] = {"99999999999999999999",
                                        "-99999999999999999999",
                                        "9223372036854775807",
                                        "-9223372036854775808",
                                        "2147483647",
                                        "2147483648",
                                        "-2147483649",
                                        "4294967296",
                                        "-1",
                                        "0",
                                        "1",
                                        "-0",
                                        "nan",
                                        "-nan",
                                        "inf",
                                        "-inf",
                                        "1e308",
                                        "-1e308",
                                        "1e309",
                                        "1e-320",
                                        "0x10",
                                        "+1",
                                        "1.5",
                                        "1e",
                                        ".",
                                        "\xff",
                                        "\xfe",
                                        "\xff\xfe",
                                        "\xc3\x28",
                                        "\x00",
                                        "\t",
                                        "\r",
                                        "\n",
                                        " ",
                                        "#",
                                        "=",
                                        "\"",
                                        "'",
                                        "\"\"\"",
                                        "'''",
                                        "\\",
                                        "\\u0000",
                                        "[",
                                        "]",
                                        "{",
                                        "}",
                                        ",",
                                        "[[fixed]]",
                                        "[[load]]",
                                        "[mesh]",
                                        "[mesh.helix]",
                                        "[mesh.box]",
                                        "[fixed.motion]",
                                        "[solver]",
                                        "[material.conversion]",
                                        "fixed.0.",
                                        "load.1.",
                                        "mesh.file",
                                        "mesh.generator",
                                        "--set ",
                                        "[]",
                                        "[[]]",
                                        "{}",
                                        "1979-05-27T07:32:00Z",
                                        "true",
                                        "false",
                                        "$MeshFormat",
                                        "$EndMeshFormat",
                                        "$Nodes",
                                        "$EndNodes",
                                        "$Elements",
                                        "$EndElements",
                                        "$Entities",
                                        "$PhysicalNames",
                                        "$End",
                                        "$",
                                        "2.2 0 8",
                                        "4.1 0 8",
                                        "4",
                                        "10",
                                        "Vertices",
                                        "Tetrahedra",
                                        "Triangles",
                                        "Dimension",
                                        "End",
                                        "@@"};

std::string_view random_token(Rng& rng) {
  const std::string_view token = kTokens[rng.below(std::size(kTokens))];
  // "\x00" as a string_view literal is empty; a NUL byte must be spelled out.
  return token.empty() ? std::string_view("\0", 1) : token;
}

// [begin, end) of the line holding byte `at`, newline included.
std::pair<std::size_t, std::size_t> line_around(const std::string& text, std::size_t at) {
  const std::size_t newline_before = at == 0 ? std::string::npos : text.rfind('\n', at - 1);
  const std::size_t begin = newline_before == std::string::npos ? 0 : newline_before + 1;
  const std::size_t newline = text.find('\n', at);
  return {begin, newline == std::string::npos ? text.size() : newline + 1};
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

// [begin, end) of the whitespace-separated token at or after byte `at`.
std::pair<std::size_t, std::size_t> token_around(const std::string& text, std::size_t at) {
  while (at < text.size() && is_space(text[at])) ++at;
  std::size_t begin = at;
  while (begin > 0 && !is_space(text[begin - 1])) --begin;
  std::size_t end = at;
  while (end < text.size() && !is_space(text[end])) ++end;
  return {begin, end};
}

void mutate_once(std::string& text, const std::vector<std::string>& corpus, Rng& rng) {
  // An empty text can only grow.
  const std::size_t kind = text.empty() ? 3 : rng.below(11);
  const std::size_t at = text.empty() ? 0 : rng.below(text.size());
  switch (kind) {
    case 0:  // flip one bit
      text[at] = static_cast<char>(text[at] ^ (1u << rng.below(8)));
      break;
    case 1:  // overwrite a byte
      text[at] = static_cast<char>(rng.below(256));
      break;
    case 2:  // truncate
      text.resize(at);
      break;
    case 3: {  // insert a token
      // Two draws in one call would be made in an unspecified order (gcc and
      // clang differ), breaking the promise of one sequence per seed.
      const std::size_t where = rng.below(text.size() + 1);
      text.insert(where, random_token(rng));
      break;
    }
    case 4:
    case 5: {  // replace a token: numbers and keywords are where the parsers decide
      const auto [begin, end] = token_around(text, at);
      text.replace(begin, end - begin, random_token(rng));
      break;
    }
    case 6: {  // duplicate a line
      const auto [begin, end] = line_around(text, at);
      text.insert(end, text.substr(begin, end - begin));
      break;
    }
    case 7: {  // delete a line
      const auto [begin, end] = line_around(text, at);
      text.erase(begin, end - begin);
      break;
    }
    case 8: {  // swap a line with a later one
      const auto [begin, end] = line_around(text, at);
      if (end >= text.size()) break;
      const auto [later_begin, later_end] = line_around(text, end + rng.below(text.size() - end));
      const std::string later = text.substr(later_begin, later_end - later_begin);
      const std::string line = text.substr(begin, end - begin);
      text.replace(later_begin, later_end - later_begin, line);
      text.replace(begin, end - begin, later);
      break;
    }
    case 9: {  // erase a short range
      text.erase(at, 1 + rng.below(std::min<std::size_t>(64, text.size() - at)));
      break;
    }
    default: {  // splice: this input's head with another input's tail
      const std::string& other = corpus[rng.below(corpus.size())];
      const std::size_t from = other.empty() ? 0 : rng.below(other.size());
      text.replace(at, std::string::npos, other, from, std::string::npos);
      break;
    }
  }
}

}  // namespace

std::string mutate(const std::string& input, const std::vector<std::string>& corpus, Rng& rng) {
  std::string text = input;
  const std::size_t edits = 1 + rng.below(4);
  for (std::size_t i = 0; i < edits; ++i) mutate_once(text, corpus, rng);
  return text;
}

}  // namespace descent::fuzz
