#pragma once
// A fast reader of whitespace-separated text records, one record per line, for
// the mesh readers. The whole file is in memory; numbers are parsed with
// std::from_chars. Every failure is an InputError "path:line: message", with
// the 1-based line of the record being read.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace descent::mesh_io_detail {

// The whole content of a file. Throws InputError naming the path when it
// cannot be read.
std::string read_whole_file(const std::string& path);

class LineScanner {
 public:
  // `comment` starts a comment that runs to the end of the line; '\0' for none.
  LineScanner(std::string_view text, std::string path, char comment);

  // Moves to the next line that holds a token, dropping what is left of the
  // current one and skipping blank and comment lines. False at the end of the
  // text (the line number then stays at the last line).
  bool next_line();

  // Whether the current line has another token.
  bool has_token();
  // The next token of the current line without consuming it; empty if none.
  std::string_view peek_token();

  // The next token of the current line; `what` names it for the error when the
  // line has no more tokens.
  std::string_view token(std::string_view what);
  std::int64_t integer(std::string_view what);
  double real(std::string_view what);  // accepts nan and inf; callers check finiteness
  // A count of records declared by the file: an integer in [0, max].
  std::int64_t count(std::string_view what, std::int64_t max);

  // The first token of the next line (see next_line), read as a count; for
  // "Keyword\nN" layouts as well as "Keyword N".
  std::int64_t count_here_or_on_next_line(std::string_view what, std::int64_t max);

  std::int64_t line() const { return line_; }
  const std::string& path() const { return path_; }
  // Bytes after the current position: no more records than this can follow.
  std::size_t bytes_left() const { return text_.size() - cursor_; }

  [[noreturn]] void fail(const std::string& message) const;
  // For a message about an earlier line of the same file.
  [[noreturn]] void fail_at(std::int64_t line, const std::string& message) const;

 private:
  void skip_blanks();

  std::string_view text_;
  std::string path_;
  char comment_;
  std::size_t cursor_ = 0;     // next unread character of the current line
  std::size_t line_end_ = 0;   // end of the current line's content (before any comment)
  std::size_t next_line_ = 0;  // first character of the following line
  std::int64_t line_ = 0;      // 1-based number of the current line
};

// How many records to reserve room for: the declared count, but no more than
// could fit in what is left of the file, so a corrupt count of 10^15 does not
// allocate absurdly (the reader then reports the truncation when it gets there).
inline std::size_t bounded_reserve(std::int64_t declared, const LineScanner& scanner,
                                   std::size_t min_bytes_per_record) {
  const std::size_t fits = scanner.bytes_left() / min_bytes_per_record + 1;
  return declared < 0 ? 0 : std::min(static_cast<std::size_t>(declared), fits);
}

}  // namespace descent::mesh_io_detail
