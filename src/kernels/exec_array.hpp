#pragma once
// Memory of an execution (kernels/execution.hpp), released with the array;
// or a view of host memory another object owns (releases nothing). The
// iteration engine and the multilevel preconditioner keep their data in
// these.
#include <cstddef>
#include <utility>

namespace descent {

template <class Exec, class T>
class ExecArray {
 public:
  ExecArray() = default;
  ExecArray(Exec* exec, std::size_t n, bool pinned)
      : exec_(exec),
        n_(n),
        pinned_(pinned),
        p_(static_cast<T*>(pinned ? exec->allocate_pinned(n * sizeof(T))
                                  : exec->allocate(n * sizeof(T)))) {}
  static ExecArray view(const T* p, std::size_t n) {
    ExecArray a;
    a.n_ = n;
    a.p_ = const_cast<T*>(p);  // read only: views are made of constant data
    return a;
  }
  ExecArray(ExecArray&& o) noexcept { *this = std::move(o); }
  ExecArray& operator=(ExecArray&& o) noexcept {
    std::swap(exec_, o.exec_);
    std::swap(n_, o.n_);
    std::swap(pinned_, o.pinned_);
    std::swap(p_, o.p_);
    return *this;
  }
  ~ExecArray() {
    if (!p_ || !exec_) return;
    if (pinned_)
      exec_->release_pinned(p_);
    else
      exec_->release(p_);
  }
  T* data() const { return p_; }
  std::size_t size() const { return n_; }
  std::size_t bytes() const { return n_ * sizeof(T); }

 private:
  Exec* exec_ = nullptr;  // null for a view
  std::size_t n_ = 0;
  bool pinned_ = false;
  T* p_ = nullptr;
};

}  // namespace descent
