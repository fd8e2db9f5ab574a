#include "io/line_scanner.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>

#include "common/error.hpp"

namespace descent::mesh_io_detail {

namespace {

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

std::string quoted(std::string_view token) {
  constexpr std::size_t kMaxShown = 40;  // a binary blob must not flood the message
  if (token.size() > kMaxShown) return detail::concat("'", token.substr(0, kMaxShown), "...'");
  return detail::concat("'", token, "'");
}

}  // namespace

std::string read_whole_file(const std::string& path) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error))
    throw InputError(detail::concat(path, ": cannot read: it is a directory"));
  const std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"),
                                                             &std::fclose);
  if (!file) throw InputError(detail::concat(path, ": cannot open: ", std::strerror(errno)));
  const auto size = std::filesystem::file_size(path, error);
  if (error) throw InputError(detail::concat(path, ": cannot read: ", error.message()));
  std::string text(size, '\0');
  if (std::fread(text.data(), 1, size, file.get()) != size)
    throw InputError(detail::concat(path, ": cannot read: ", std::strerror(errno)));
  return text;
}

LineScanner::LineScanner(std::string_view text, std::string path, char comment)
    : text_(text), path_(std::move(path)), comment_(comment) {}

bool LineScanner::next_line() {
  while (next_line_ < text_.size()) {
    ++line_;
    const std::size_t begin = next_line_;
    const void* newline = std::memchr(text_.data() + begin, '\n', text_.size() - begin);
    const std::size_t end =
        newline ? static_cast<const char*>(newline) - text_.data() : text_.size();
    next_line_ = end + 1;
    line_end_ = end;
    if (comment_ != '\0') {
      const void* hash = std::memchr(text_.data() + begin, comment_, end - begin);
      if (hash) line_end_ = static_cast<const char*>(hash) - text_.data();
    }
    cursor_ = begin;
    if (has_token()) return true;
  }
  cursor_ = line_end_ = text_.size();
  return false;
}

void LineScanner::skip_blanks() {
  while (cursor_ < line_end_ && is_blank(text_[cursor_])) ++cursor_;
}

bool LineScanner::has_token() {
  skip_blanks();
  return cursor_ < line_end_;
}

std::string_view LineScanner::peek_token() {
  if (!has_token()) return {};
  const std::size_t saved = cursor_;
  const std::string_view next = token("a token");
  cursor_ = saved;
  return next;
}

std::string_view LineScanner::token(std::string_view what) {
  if (!has_token()) fail(detail::concat("expected ", what, ", but the line ends"));
  const std::size_t begin = cursor_;
  while (cursor_ < line_end_ && !is_blank(text_[cursor_])) ++cursor_;
  return text_.substr(begin, cursor_ - begin);
}

std::int64_t LineScanner::integer(std::string_view what) {
  const std::string_view text = token(what);
  std::int64_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size())
    fail(detail::concat("expected ", what, " (an integer), found ", quoted(text)));
  return value;
}

double LineScanner::real(std::string_view what) {
  std::string_view text = token(what);
  // from_chars takes no leading '+', which some writers emit.
  if (text.size() > 1 && text[0] == '+' && text[1] != '-') text.remove_prefix(1);
  double value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size())
    fail(detail::concat("expected ", what, " (a number), found ", quoted(text)));
  return value;
}

std::int64_t LineScanner::count(std::string_view what, std::int64_t max) {
  const std::int64_t value = integer(what);
  if (value < 0 || value > max)
    fail(detail::concat(what, " is ", value, ", outside the supported range 0 to ", max));
  return value;
}

std::int64_t LineScanner::count_here_or_on_next_line(std::string_view what, std::int64_t max) {
  if (!has_token() && !next_line())
    fail(detail::concat("expected ", what, ", but the file ended (truncated file)"));
  return count(what, max);
}

void LineScanner::fail(const std::string& message) const {
  // Line 0 only before the first line is read: an empty file.
  fail_at(std::max<std::int64_t>(line_, 1), message);
}

void LineScanner::fail_at(std::int64_t line, const std::string& message) const {
  throw InputError(detail::concat(path_, ":", line, ": ", message));
}

}  // namespace descent::mesh_io_detail
