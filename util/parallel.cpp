#include "parallel.h"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

#include <unistd.h>

namespace retroprism {

namespace {

// True on a thread that runs a share of a parallel call (a pool worker, or a caller while it
// takes part): a parallel call made there runs on that thread alone instead of waiting for a
// pool that is running its parent.
thread_local bool tInParallel = false;

// Marks the calling thread as taking part in a parallel call while it lives.
struct Participating {
    Participating() { tInParallel = true; }
    ~Participating() { tInParallel = false; }
    Participating(const Participating&) = delete;
    Participating& operator=(const Participating&) = delete;
};

// One worker per core but the caller's, started at the first parallel call and kept for the
// life of the process, so that a call after the first starts no thread and allocates nothing.
// A call hands the workers a function and its context (no copy of the caller's callable); the
// caller takes part and returns when every worker has finished with it.
class Pool {
  public:
    static Pool& instance() {
        static Pool pool;
        return pool;
    }

    // fn(ctx) on the calling thread and on up to `helpers` workers at once; false, with nothing
    // run, when another thread's call holds the pool.
    bool run(std::size_t helpers, void (*fn)(void*), void* ctx) {
        std::unique_lock<std::mutex> busy(busy_, std::try_to_lock);
        if (!busy.owns_lock()) return false;
        {
            std::lock_guard<std::mutex> lock(m_);
            fn_ = fn;
            ctx_ = ctx;
            seats_ = std::min(helpers, workers_.size());
            finished_ = 0;
            ++generation_;
        }
        wake_.notify_all();
        // The workers read ctx (the caller's): they are waited for before this returns or, if
        // fn throws, unwinds.
        struct Wait {
            Pool& pool;
            ~Wait() { pool.wait_workers(); }
        } wait{*this};
        Participating here;
        fn(ctx);
        return true;
    }

    std::size_t workers() const { return workers_.size(); }
    // The process that started the workers: a child forked from it has none of them.
    pid_t owner() const { return owner_; }

    Pool(const Pool&) = delete;
    Pool& operator=(const Pool&) = delete;

    ~Pool() {
        {
            std::lock_guard<std::mutex> lock(m_);
            stop_ = true;
        }
        wake_.notify_all();
        for (std::thread& t : workers_)
            t.join();
    }

  private:
    Pool() : owner_(getpid()) {
        const unsigned cores = std::thread::hardware_concurrency();
        for (unsigned k = 1; k < cores; ++k)
            workers_.emplace_back([this] { work(); });
    }

    void wait_workers() {
        std::unique_lock<std::mutex> lock(m_);
        done_.wait(lock, [&] { return finished_ == workers_.size(); });
    }

    // Every worker answers every call (a call waits for all of them, so none misses the next);
    // the first `seats_` run its function.
    void work() {
        Participating here;
        std::uint64_t seen = 0;
        std::unique_lock<std::mutex> lock(m_);
        for (;;) {
            wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
            if (stop_) return;
            seen = generation_;
            const bool take = seats_ > 0;
            if (take) --seats_;
            void (*fn)(void*) = fn_;
            void* ctx = ctx_;
            lock.unlock();
            if (take) fn(ctx);
            lock.lock();
            if (++finished_ == workers_.size()) done_.notify_one();
        }
    }

    std::mutex busy_; // held by the call in progress
    std::mutex m_;    // guards the fields below
    std::condition_variable wake_, done_;
    std::vector<std::thread> workers_;
    const pid_t owner_;
    void (*fn_)(void*) = nullptr;
    void* ctx_ = nullptr;
    std::size_t seats_ = 0;
    std::size_t finished_ = 0;
    std::uint64_t generation_ = 0;
    bool stop_ = false;
};

// Runs fn(ctx) on `t` threads at most (the caller and t - 1 others): on the pool; on the caller
// alone inside a parallel call, without other cores, or in a child process forked after the pool
// started (e.g. Python's multiprocessing: the child has the pool's state but not its threads);
// on threads of its own when another thread's call holds the pool.
void run_shared(std::size_t t, void (*fn)(void*), void* ctx) {
    if (tInParallel) {
        fn(ctx);
        return;
    }
    Pool& pool = Pool::instance();
    if (pool.workers() == 0 || pool.owner() != getpid()) {
        fn(ctx);
        return;
    }
    if (pool.run(t - 1, fn, ctx)) return;
    std::vector<std::thread> threads;
    // Joined before this returns or, if fn throws on this thread, unwinds.
    struct Join {
        std::vector<std::thread>& threads;
        ~Join() {
            for (std::thread& th : threads)
                th.join();
        }
    } join{threads};
    for (std::size_t k = 1; k < t; ++k)
        threads.emplace_back([fn, ctx] {
            Participating here;
            fn(ctx);
        });
    Participating here;
    fn(ctx);
}

struct ForJob {
    const std::function<void(std::size_t)>* body;
    std::size_t n;
    std::atomic<std::size_t> next{0};
};

void run_for(void* p) {
    ForJob& job = *static_cast<ForJob*>(p);
    for (std::size_t i = job.next++; i < job.n; i = job.next++)
        (*job.body)(i);
}

// Range k of t is [n k / t, n (k + 1) / t): the ranges do not depend on which thread runs them.
struct RangesJob {
    const std::function<void(std::size_t, std::size_t)>* body;
    std::size_t n, t;
    std::atomic<std::size_t> next{0};
};

void run_ranges(void* p) {
    RangesJob& job = *static_cast<RangesJob*>(p);
    for (std::size_t k = job.next++; k < job.t; k = job.next++)
        (*job.body)(job.n * k / job.t, job.n * (k + 1) / job.t);
}

} // namespace

int thread_count(int requested) {
    if (requested > 0) return requested;
    const unsigned hc = std::thread::hardware_concurrency();
    return hc > 0 ? int(hc) : 1;
}

void parallel_for(std::size_t n, int threads, const std::function<void(std::size_t)>& body) {
    const std::size_t t = std::min<std::size_t>(std::size_t(thread_count(threads)), n);
    if (t <= 1) {
        for (std::size_t i = 0; i < n; ++i)
            body(i);
        return;
    }
    ForJob job;
    job.body = &body;
    job.n = n;
    run_shared(t, run_for, &job);
}

void parallel_ranges(std::size_t n, int threads, std::size_t grain,
                     const std::function<void(std::size_t, std::size_t)>& body) {
    const std::size_t t =
        std::max<std::size_t>(1, std::min<std::size_t>(std::size_t(thread_count(threads)),
                                                       n / std::max<std::size_t>(grain, 1) + 1));
    if (t == 1) {
        body(0, n);
        return;
    }
    RangesJob job;
    job.body = &body;
    job.n = n;
    job.t = t;
    run_shared(t, run_ranges, &job);
}

} // namespace retroprism
