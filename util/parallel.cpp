#include "parallel.h"

#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

namespace retroprism {

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
    std::atomic<std::size_t> next{0};
    std::vector<std::thread> pool;
    for (std::size_t k = 0; k < t; ++k)
        pool.emplace_back([&] {
            for (std::size_t i = next++; i < n; i = next++)
                body(i);
        });
    for (std::thread& th : pool)
        th.join();
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
    std::vector<std::thread> pool;
    for (std::size_t k = 0; k < t; ++k) {
        const std::size_t b = n * k / t, e = n * (k + 1) / t;
        pool.emplace_back([&body, b, e] { body(b, e); });
    }
    for (std::thread& th : pool)
        th.join();
}

} // namespace retroprism
