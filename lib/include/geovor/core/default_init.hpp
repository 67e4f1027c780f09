#pragma once
/// @file default_init.hpp
/// An allocator for std::vector whose resize() leaves elements default-initialised (trivial
/// types: not written), for arrays of which every element is written before it is read: no
/// pass of zeros, and each page is first touched by the thread that fills it.

#include <memory>
#include <new>
#include <type_traits>
#include <utility>

namespace geovor {

template <typename T, typename A = std::allocator<T>>
class DefaultInitAllocator : public A {
  using Traits = std::allocator_traits<A>;

 public:
  template <typename U>
  struct rebind {
    using other = DefaultInitAllocator<U, typename Traits::template rebind_alloc<U>>;
  };
  using A::A;

  template <typename U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    Traits::construct(static_cast<A&>(*this), p, std::forward<Args>(args)...);
  }
};

}  // namespace geovor
