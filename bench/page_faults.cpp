// First touches of fresh memory: a new 2 GiB std::vector<double> filled,
// three times in one process (the first takes pages the process never had,
// the next may reuse what the kernel kept). Seconds per fill. Run by
// bench/page_faults.sh with glibc's malloc as it comes and with transparent
// huge pages on malloc's maps.
#include <chrono>
#include <cstdio>
#include <vector>

int main() {
  constexpr std::size_t kCount = std::size_t(1) << 28;  // 2 GiB of doubles
  for (int fill = 0; fill < 3; ++fill) {
    const auto start = std::chrono::steady_clock::now();
    std::vector<double> v(kCount, 1.0);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    // Reading an element keeps the fill from being optimised away.
    std::printf("%.2f%s", seconds + 0 * v[kCount / 2], fill < 2 ? " " : "\n");
  }
}
