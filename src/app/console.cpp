#include "app/console.hpp"

#include <cstdarg>
#include <cstdio>

namespace descent {

namespace {

void print_line(std::FILE* stream, const char* prefix, const char* format, std::va_list args) {
  std::fputs(prefix, stream);
  std::vfprintf(stream, format, args);
  std::fputc('\n', stream);
  std::fflush(stream);
}

}  // namespace

void inform(const char* format, ...) {
  std::va_list args;
  va_start(args, format);
  print_line(stdout, "descent: ", format, args);
  va_end(args);
}

void warn(const char* format, ...) {
  std::va_list args;
  va_start(args, format);
  print_line(stderr, "descent: warning: ", format, args);
  va_end(args);
}

void report_error(const char* format, ...) {
  std::va_list args;
  va_start(args, format);
  print_line(stderr, "descent: error: ", format, args);
  va_end(args);
}

}  // namespace descent
