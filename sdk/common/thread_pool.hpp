// A fixed set of worker threads owned by a context. parallel_for hands out indices dynamically;
// the calling thread works too, so a pool of size 1 has no threads at all. Threads poll briefly
// before they sleep (see kSpin in thread_pool.cpp), so batches in quick succession start at once.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace ssc {

class ThreadPool {
public:
    // thread_count includes the caller: 1 = run inline. Threads start on the first parallel_for,
    // so a context that never runs a batch costs no threads.
    explicit ThreadPool(unsigned thread_count) : thread_count_(thread_count ? thread_count : 1) {}
    ~ThreadPool();
    ThreadPool(const ThreadPool&) = delete;
    ThreadPool& operator=(const ThreadPool&) = delete;

    unsigned size() const { return thread_count_; }

    // Calls fn(i, w) for every i in [0, count) across the pool and waits; w < size() names the
    // thread (0 = the caller), so callers can keep per-thread scratch. fn must not throw
    // (callers catch inside and report after the join). Concurrent calls are serialised.
    void parallel_for(std::size_t count, const std::function<void(std::size_t item, unsigned worker)>& fn);

private:
    void worker_loop(unsigned worker);
    void run_items(std::unique_lock<std::mutex>& lock, unsigned worker);

    unsigned thread_count_;
    std::vector<std::thread> workers_;
    std::mutex submit_mutex_;  // one parallel_for at a time
    std::mutex mutex_;
    std::condition_variable wake_, done_;
    const std::function<void(std::size_t, unsigned)>* job_ = nullptr;
    std::size_t count_ = 0, next_ = 0;
    // Written under mutex_; atomic so that the spin phases may read them without it.
    std::atomic<std::size_t> finished_{0};
    std::atomic<unsigned> generation_{0}, busy_{0};
    bool stop_ = false;
};

}  // namespace ssc
