#pragma once
// Where descent's messages go, so every command speaks alike: progress and
// results on stdout, warnings and errors on stderr, each line prefixed
// "descent: " ("descent: warning: ", "descent: error: "). Lines are flushed
// at once: a job log read while the run goes on shows what has happened.
namespace descent {

// One line on stdout: "descent: " + the formatted text.
void inform(const char* format, ...) __attribute__((format(printf, 1, 2)));

// One line on stderr: "descent: warning: " + the formatted text.
void warn(const char* format, ...) __attribute__((format(printf, 1, 2)));

// One line on stderr: "descent: error: " + the formatted text.
void report_error(const char* format, ...) __attribute__((format(printf, 1, 2)));

}  // namespace descent
