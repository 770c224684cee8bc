// parallel.h: the project's one way to spread work over threads. Work items are computed alone
// and written to their own slots, so results never depend on the thread count.
#pragma once

#include <cstddef>
#include <functional>

namespace retroprism {

// The number of threads to use for `requested` (0 or less: one per core).
int thread_count(int requested);

// body(i) for every i in [0, n) on `threads` threads (0: one per core), items handed out one
// at a time as threads become free; returns when all are done.
void parallel_for(std::size_t n, int threads, const std::function<void(std::size_t)>& body);

// body(begin, end) over contiguous ranges that cover [0, n), on `threads` threads (0: one per
// core) and in ranges of at least `grain` items.
void parallel_ranges(std::size_t n, int threads, std::size_t grain,
                     const std::function<void(std::size_t, std::size_t)>& body);

} // namespace retroprism
