#pragma once
// Cheaper first touch of large float arrays that a reader is about to fill.
//
// A fresh anonymous page costs a page fault on its first write. On the project's VM that is
// ~20-25 us per 4 KiB page (measured: 4 MiB touched page by page in 23-36 ms), which makes the
// decoded float output of a radar read (4 bytes per gate, where the file stores 1-2) cost more
// than reading and inflating the file. Asking the kernel to populate a whole range in one call
// (madvise MADV_POPULATE_WRITE, Linux >= 5.14) costs a fraction of that (measured: 4 MiB in
// 2.5-7.5 ms); elsewhere the call is a no-op and the pages fault as before.
#include <cstddef>
#include <vector>

namespace atmoglobe::io {

/// Asks the kernel to back the whole pages inside [data, data + bytes) with writable memory
/// now, in one call, instead of one page fault per page on first write. Only ranges of at
/// least `minBytes` are populated (smaller ones fault in a few pages anyway). Best effort:
/// failure (old kernel, not Linux) changes nothing but speed. Contents are unchanged.
void populatePages(void* data, std::size_t bytes, std::size_t minBytes = std::size_t{64} << 10);

/// values.assign(n, fill) with the storage populated in one call first (populatePages) when
/// the vector has to allocate. Same result as assign().
void assignPopulated(std::vector<float>& values, std::size_t n, float fill);

}  // namespace atmoglobe::io
