// prefer_huge_pages (process_memory.h): glibc's mallopt and one madvise over the heap's reserve.
#include "process_memory.h"

#include <cstdint>
#include <cstdlib>

#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__)
#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>
#define UNTANGLE_HUGE_PAGES 1
#endif

namespace untangle::app {

void prefer_huge_pages() {
#ifdef UNTANGLE_HUGE_PAGES
  // The reserve the heap grows by at once (address space, not memory: pages are used only when
  // touched). Blocks up to 32 MiB (glibc's largest threshold) come from the heap rather than
  // from a mapping of their own, which would be faulted in page by page and returned at free.
  constexpr std::size_t kReserve = std::size_t{512} << 20;
  constexpr std::size_t kHuge = std::size_t{2} << 20;  // x86-64's transparent huge page
  if (mallopt(M_MMAP_THRESHOLD, 32 << 20) != 1) return;
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  mallopt(M_TOP_PAD, static_cast<int>(kReserve));
  // One allocation makes the heap take its reserve now; the reserve (whole huge pages of it) is
  // then marked for huge pages. Growth beyond it gets ordinary pages.
  const auto before = reinterpret_cast<std::uintptr_t>(sbrk(0));
  void* volatile probe = std::malloc(std::size_t{1} << 20);
  const auto after = reinterpret_cast<std::uintptr_t>(sbrk(0));
  const std::uintptr_t lo = (before + kHuge - 1) & ~(kHuge - 1), hi = after & ~(kHuge - 1);
  if (probe != nullptr && hi > lo) madvise(reinterpret_cast<void*>(lo), hi - lo, MADV_HUGEPAGE);
  std::free(probe);
  // Later growth (beyond the reserve, or where it was refused: a limit on address space) goes
  // in glibc's default steps again.
  mallopt(M_TOP_PAD, 128 * 1024);
#endif
}

}  // namespace untangle::app
