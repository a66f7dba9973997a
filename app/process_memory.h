// How the untangle process asks the C library for memory. The library never touches this: a
// program that links it keeps its own allocator settings.
#pragma once

namespace untangle::app {

// Lets the main heap grow in one large reservation backed by transparent huge pages (where the
// kernel offers them on request, /sys/kernel/mm/transparent_hugepage/enabled = madvise or
// always), and keeps freed memory for reuse instead of returning it to the system. Without it a
// `check` of a garment on its body spends about a fifth of its CPU time in first-touch page faults
// (3,800 faults of 4 KiB; about 270 with it, the heap below its first huge page filled;
// docs/PERFORMANCE.md, *Huge pages* and *The heap's first huge page*). Only memory
// that is touched is used. Does nothing under AddressSanitizer (its own allocator) or where the
// calls are refused; the results are the same either way. Call it first in main.
void prefer_huge_pages();

}  // namespace untangle::app
