#pragma once
// Small pieces every HDF5 file of descent uses: an owning identifier, and
// checks that turn a failed call into an Hdf5Error naming the file and object.
#include <hdf5.h>

#include <string>
#include <utility>

#include "common/error.hpp"

namespace descent::hdf5 {

// Owns one HDF5 identifier and releases it with the matching H5*close.
class Hid {
 public:
  using Close = herr_t (*)(hid_t);
  Hid() = default;
  Hid(hid_t id, Close close) : id_(id), close_(close) {}
  Hid(Hid&& other) noexcept
      : id_(std::exchange(other.id_, H5I_INVALID_HID)), close_(other.close_) {}
  Hid& operator=(Hid&& other) noexcept {
    std::swap(id_, other.id_);
    std::swap(close_, other.close_);
    return *this;
  }
  ~Hid() {
    if (id_ >= 0) close_(id_);  // a failed close cannot be reported from here
  }
  hid_t get() const { return id_; }

 private:
  hid_t id_ = H5I_INVALID_HID;
  Close close_ = nullptr;
};

// HDF5 calls return a negative value on failure; `where` names the file and object.
template <class Result>
Result check(Result result, const char* call, const std::string& where) {
  if (result < 0) throw Hdf5Error(detail::concat(call, " failed for ", where));
  return result;
}

inline Hid owned(hid_t id, Hid::Close close, const char* call, const std::string& where) {
  return Hid(check(id, call, where), close);
}

}  // namespace descent::hdf5
