#pragma once
// The machine's physical memory, for estimates made before a large allocation.

#include <unistd.h>

#include <cstdint>

namespace jointhb::support {

/// Bytes of physical memory (sysconf), or 0 when the system does not say.
inline std::uint64_t physical_memory_bytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES);
  const long page_size = ::sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page_size <= 0) return 0;
  return static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page_size);
}

}  // namespace jointhb::support
