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

#ifdef UNTANGLE_HUGE_PAGES
namespace {
// The block that fills the heap below its first huge page (prefer_huge_pages), kept here so that
// it stays reachable: never touched, never freed.
void* volatile below_huge_pages = nullptr;
}  // namespace
#endif

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
  // Where the probe began, taken before it is freed (a freed pointer's value is not to be used).
  const auto first = reinterpret_cast<std::uintptr_t>(probe);
  std::free(probe);
  // The heap below `lo` (up to 2 MiB from where the probe began) can only have ordinary pages, and
  // the first allocations, the meshes as read, would land there: a fault per 4 KiB. One block
  // filling it, never touched and never freed (kept reachable above), sends them above `lo`. And
  // taking the probe from the heap wrote the header of the heap's free top a megabyte on, in the
  // first huge page when the heap began less than that below it, before that page was marked: the
  // 4 KiB page faulted in there kept the whole first huge page in ordinary pages. The probe went
  // back to the free top (its header now below `lo`, where the probe began), so nothing lives in
  // that huge page: it is dropped, to be faulted in again whole. Together they took a `check` of
  // the shipped MakeHuman pair from 580 to 1,000 faults (by where the heap happened to start) to
  // about 270 (issue 24).
  if (first != 0 && hi > lo && first < lo) {
    madvise(reinterpret_cast<void*>(lo), kHuge, MADV_DONTNEED);
    below_huge_pages = std::malloc(lo - first);
  }
  // Later growth (beyond the reserve, or where it was refused: a limit on address space) goes
  // in glibc's default steps again.
  mallopt(M_TOP_PAD, 128 * 1024);
#endif
}

}  // namespace untangle::app
