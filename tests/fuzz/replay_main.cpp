// A main for the fuzz targets where libFuzzer is not available (gcc, CI):
// runs every file of a corpus directory through LLVMFuzzerTestOneInput, then
// ITERATIONS deterministic mutations of them, round robin over the files.
//
//   replay CORPUS_DIR [ITERATIONS [SEED [MAX_SECONDS]]]
//
// Stops mutating after MAX_SECONDS (saying so). A crash, an abort, a
// sanitizer report, an uncaught exception or one input running longer than
// kInputSeconds saves the input to replay-finding.bin in the working
// directory, so it can be replayed with the libFuzzer binary or a debugger.
#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "tests/fuzz/fuzz_common.hpp"
#include "tests/fuzz/mutator.hpp"

// Set by the sanitizer runtimes only; null in a plain build.
extern "C" void __sanitizer_set_death_callback(void (*callback)()) __attribute__((weak));

namespace {

constexpr unsigned kInputSeconds = 20;  // one input longer than this is a hang
constexpr const char kFindingPath[] = "replay-finding.bin";

// The input being run, for the handlers below, which may only use
// async-signal-safe calls.
const std::string* g_current = nullptr;

void save_current_input() {
  static const char kSaved[] = "replay: the input is saved in replay-finding.bin\n";
  if (!g_current) return;
  const int fd = ::open(kFindingPath, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0) return;
  for (std::size_t done = 0; done < g_current->size();) {
    const ssize_t n = ::write(fd, g_current->data() + done, g_current->size() - done);
    if (n <= 0) break;
    done += static_cast<std::size_t>(n);
  }
  ::close(fd);
  [[maybe_unused]] const ssize_t ignored = ::write(STDERR_FILENO, kSaved, sizeof kSaved - 1);
}

void on_signal(int signal) {
  if (signal == SIGALRM) {
    static const char kHang[] = "replay: an input ran too long (hang)\n";
    [[maybe_unused]] const ssize_t ignored = ::write(STDERR_FILENO, kHang, sizeof kHang - 1);
  }
  save_current_input();
  // Die by the signal itself (a hang by SIGABRT), with no second save.
  std::signal(signal, SIG_DFL);
  std::signal(SIGABRT, SIG_DFL);
  std::raise(signal == SIGALRM ? SIGABRT : signal);
}

void install_handlers() {
  // A stack overflow (deep recursion on nested input) leaves no stack for
  // the handler, so it runs on its own.
  static char alternate_stack[1 << 16];
  stack_t stack{};
  stack.ss_sp = alternate_stack;
  stack.ss_size = sizeof alternate_stack;
  ::sigaltstack(&stack, nullptr);
  struct sigaction action {};
  action.sa_handler = on_signal;
  action.sa_flags = SA_ONSTACK;
  sigemptyset(&action.sa_mask);
  for (const int signal : {SIGABRT, SIGALRM}) ::sigaction(signal, &action, nullptr);
  if (__sanitizer_set_death_callback) {
    // A sanitizer reports crashes itself, with the stack, and then exits
    // without a signal: save the input from its death callback instead.
    __sanitizer_set_death_callback(save_current_input);
  } else {
    for (const int signal : {SIGSEGV, SIGBUS, SIGFPE, SIGILL})
      ::sigaction(signal, &action, nullptr);
  }
}

std::vector<std::string> read_corpus(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> paths;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    if (entry.is_regular_file()) paths.push_back(entry.path());
  std::sort(paths.begin(), paths.end());  // directory order is not deterministic
  std::vector<std::string> inputs;
  for (const auto& path : paths) {
    std::ifstream file(path, std::ios::binary);
    inputs.emplace_back(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
  }
  return inputs;
}

// Runs one input; an exception that escapes the target is a finding.
void run(const std::string& input) {
  g_current = &input;
  ::alarm(kInputSeconds);
  try {
    LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(input.data()), input.size());
  } catch (const std::exception& error) {
    std::fprintf(stderr, "replay: finding: uncaught exception: %s\n", error.what());
    save_current_input();
    std::exit(1);
  } catch (...) {
    std::fprintf(stderr, "replay: finding: uncaught exception of unknown type\n");
    save_current_input();
    std::exit(1);
  }
  ::alarm(0);
  g_current = nullptr;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || argc > 5) {
    std::fprintf(stderr, "usage: %s CORPUS_DIR [ITERATIONS [SEED [MAX_SECONDS]]]\n", argv[0]);
    return 2;
  }
  const std::filesystem::path dir = argv[1];
  const unsigned long long iterations = argc > 2 ? std::strtoull(argv[2], nullptr, 10) : 3000;
  const unsigned long long seed = argc > 3 ? std::strtoull(argv[3], nullptr, 10) : 1;
  const double max_seconds = argc > 4 ? std::strtod(argv[4], nullptr) : 50;

  std::vector<std::string> corpus;
  try {
    corpus = read_corpus(dir);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "replay: cannot read the corpus %s: %s\n", dir.c_str(), error.what());
    return 2;
  }
  if (corpus.empty()) {
    std::fprintf(stderr, "replay: the corpus %s holds no files\n", dir.c_str());
    return 2;
  }
  install_handlers();

  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  const auto seconds = [&start] {
    return std::chrono::duration<double>(Clock::now() - start).count();
  };

  for (const std::string& input : corpus) run(input);
  const std::size_t corpus_accepted = descent::fuzz::accepted_inputs;

  descent::fuzz::Rng rng(seed);
  unsigned long long done = 0;
  bool out_of_time = false;
  for (; done < iterations; ++done) {
    // The clock is cheap, but not free next to a 20-byte input.
    if (done % 64 == 0 && seconds() > max_seconds) {
      out_of_time = true;
      break;
    }
    run(descent::fuzz::mutate(corpus[done % corpus.size()], corpus, rng));
  }

  std::printf(
      "replay: %zu corpus inputs (%zu accepted), %llu mutated inputs (%zu accepted), "
      "seed %llu, %.1f s%s\n",
      corpus.size(), corpus_accepted, done, descent::fuzz::accepted_inputs - corpus_accepted, seed,
      seconds(), out_of_time ? " (stopped at the time cap)" : "");
  return 0;
}
