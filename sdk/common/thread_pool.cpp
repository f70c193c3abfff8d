#include "thread_pool.hpp"

namespace ssc {

ThreadPool::~ThreadPool() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    for (auto& t : workers_) t.join();
}

// Takes items until none are left. Entered and left with `lock` held.
void ThreadPool::run_items(std::unique_lock<std::mutex>& lock, unsigned worker) {
    while (next_ < count_) {
        const std::size_t i = next_++;
        const auto* job = job_;
        lock.unlock();
        (*job)(i, worker);
        lock.lock();
        ++finished_;
    }
}

void ThreadPool::worker_loop(unsigned worker) {
    unsigned seen = 0;
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
        wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
        if (stop_) return;
        seen = generation_;
        ++busy_;
        run_items(lock, worker);
        --busy_;
        if (finished_ == count_ && busy_ == 0) done_.notify_all();
    }
}

void ThreadPool::parallel_for(std::size_t count, const std::function<void(std::size_t, unsigned)>& fn) {
    if (count == 0) return;
    if (thread_count_ == 1 || count == 1) {
        for (std::size_t i = 0; i < count; ++i) fn(i, 0);
        return;
    }
    std::lock_guard<std::mutex> submit(submit_mutex_);
    // A thread that fails to start leaves fewer workers; the caller still finishes every item.
    while (workers_.size() + 1 < thread_count_) {
        const auto id = static_cast<unsigned>(workers_.size()) + 1;
        workers_.emplace_back([this, id] { worker_loop(id); });
    }
    std::unique_lock<std::mutex> lock(mutex_);
    job_ = &fn;
    count_ = count;
    next_ = 0;
    finished_ = 0;
    ++generation_;
    wake_.notify_all();
    run_items(lock, 0);
    // Workers that woke late still hold no item; wait for those that do.
    done_.wait(lock, [&] { return finished_ == count_ && busy_ == 0; });
    job_ = nullptr;
}

}  // namespace ssc
