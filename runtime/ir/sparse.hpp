#pragma once

#include <memory>
#include <utility>

namespace snell::ir {

// A value that is almost always T{}: held on the heap only when it is not, so a
// container of millions of records pays one pointer for it, not sizeof(T). Copies
// are deep (value semantics); reads of an absent value see one shared default.
template <class T>
class Sparse {
 public:
  Sparse() = default;
  Sparse(const Sparse& o) : p_(o.p_ ? std::make_unique<T>(*o.p_) : nullptr) {}
  Sparse(Sparse&&) noexcept = default;
  Sparse& operator=(const Sparse& o) {
    if (this != &o) p_ = o.p_ ? std::make_unique<T>(*o.p_) : nullptr;
    return *this;
  }
  Sparse& operator=(Sparse&&) noexcept = default;

  const T& get() const { return p_ ? *p_ : default_value(); }
  bool held() const { return p_ != nullptr; }
  // `is_default` says whether v equals T{} (the caller knows how to tell cheaply).
  void set(T v, bool is_default) {
    if (is_default)
      p_.reset();
    else if (p_)
      *p_ = std::move(v);
    else
      p_ = std::make_unique<T>(std::move(v));
  }

 private:
  static const T& default_value() {
    static const T d{};
    return d;
  }
  std::unique_ptr<T> p_;
};

}  // namespace snell::ir
