// Allocator plumbing: every large array of a model or body goes through the context's allocator
// callbacks (ssc_context_def::alloc/free), so engines can account for and place our memory.
#pragma once

#include <sscape/sscape.h>

#include <cstddef>
#include <cstdlib>
#include <new>
#include <vector>

namespace ssc {

// The callbacks of one context. A null pointer means "the C heap".
struct Allocator {
    ssc_alloc_fn alloc = nullptr;
    ssc_free_fn free = nullptr;
    void* user = nullptr;

    void* allocate(std::size_t size, std::size_t align) const {
        if (size == 0) size = align;
        void* p = alloc ? alloc(user, size, align) : std::aligned_alloc(align, (size + align - 1) / align * align);
        if (!p) throw std::bad_alloc();
        return p;
    }
    void deallocate(void* p) const {
        if (!p) return;
        if (free) free(user, p); else std::free(p);
    }
};

// std allocator adaptor over Allocator; 64-byte alignment suits SIMD loads and cache lines.
template <class T>
class CAlloc {
public:
    using value_type = T;
    CAlloc() noexcept = default;
    explicit CAlloc(const Allocator* a) noexcept : a_(a) {}
    template <class U>
    CAlloc(const CAlloc<U>& o) noexcept : a_(o.source()) {}

    T* allocate(std::size_t n) {
        if (n > static_cast<std::size_t>(-1) / sizeof(T)) throw std::bad_alloc();
        const Allocator heap;
        return static_cast<T*>((a_ ? *a_ : heap).allocate(n * sizeof(T), 64));
    }
    void deallocate(T* p, std::size_t) noexcept {
        const Allocator heap;
        (a_ ? *a_ : heap).deallocate(p);
    }
    const Allocator* source() const noexcept { return a_; }

    template <class U>
    bool operator==(const CAlloc<U>& o) const noexcept { return a_ == o.source(); }
    template <class U>
    bool operator!=(const CAlloc<U>& o) const noexcept { return a_ != o.source(); }

private:
    const Allocator* a_ = nullptr;
};

template <class T>
using Vec = std::vector<T, CAlloc<T>>;

}  // namespace ssc
