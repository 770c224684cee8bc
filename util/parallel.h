// parallel.h: the project's one way to spread work over threads. Work items are computed alone
// and written to their own slots, so results never depend on the thread count. The calls run on
// a pool of one worker per core but the caller's, started at the first call and kept for the
// process's life (a call after the first starts no thread and allocates nothing), and on the
// calling thread; `threads` caps how many of them work at once. A call made inside another's
// work runs on its own thread; a call made while another thread's call holds the pool runs on
// threads of its own.
#pragma once

#include <cstddef>
#include <functional>

namespace retroprism {

// The number of threads to use for `requested` (0 or less: one per core).
int thread_count(int requested);

// body(i) for every i in [0, n) on up to `threads` threads (0: one per core), items handed out
// one at a time as threads become free; returns when all are done.
void parallel_for(std::size_t n, int threads, const std::function<void(std::size_t)>& body);

// body(begin, end) over contiguous ranges that cover [0, n), on up to `threads` threads (0: one
// per core) and in ranges of at least `grain` items (the ranges depend on n, threads and grain
// only, not on the threads that run them).
void parallel_ranges(std::size_t n, int threads, std::size_t grain,
                     const std::function<void(std::size_t, std::size_t)>& body);

} // namespace retroprism
