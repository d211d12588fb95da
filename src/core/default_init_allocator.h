// A std::vector allocator whose construct() without arguments
// default-initializes. A vector of trivial records resized to millions of
// entries then leaves its pages untouched, so that the threads which fill the
// records fault the pages in side by side, instead of one thread zeroing
// hundreds of MB first (planSlices' records of a 410k-crossing garment).
#pragma once

#include <memory>
#include <new>
#include <type_traits>
#include <utility>

namespace yv {

template <typename T, typename Base = std::allocator<T>>
class DefaultInitAllocator : public Base {
    using Traits = std::allocator_traits<Base>;

  public:
    template <typename U>
    struct rebind {
        using other = DefaultInitAllocator<U, typename Traits::template rebind_alloc<U>>;
    };

    using Base::Base;

    template <typename U>
    void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
        ::new (static_cast<void*>(p)) U;
    }
    template <typename U, typename... Args>
    void construct(U* p, Args&&... args) {
        Traits::construct(static_cast<Base&>(*this), p, std::forward<Args>(args)...);
    }
};

} // namespace yv
