#pragma once
// Small pieces every HDF5 file of descent uses: an owning identifier, and
// checks that turn a failed call into an Hdf5Error naming the file, the
// object and HDF5's own reason, never HDF5's printed error stack.
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

// Turns off HDF5's automatic printing of its error stack (on stderr, before
// and beside our own one-line error). Called wherever descent opens or
// creates an HDF5 file; the setting is per thread and costs nothing to repeat.
inline void quiet_errors() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }

// The innermost description on HDF5's error stack (where the failure began,
// e.g. "addr overflow" or an MPI-IO error string), or "" when it is empty.
inline std::string innermost_error() {
  std::string reason;
  auto take = [](unsigned, const H5E_error2_t* entry, void* text) -> herr_t {
    if (entry->desc != nullptr && entry->desc[0] != '\0')
      *static_cast<std::string*>(text) = entry->desc;
    return 1;  // the first entry walked upward is the innermost: stop there
  };
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, take, &reason);
  return reason;
}

// HDF5 calls return a negative value on failure; `where` names the file and object.
template <class Result>
Result check(Result result, const char* call, const std::string& where) {
  if (result < 0) {
    const std::string reason = innermost_error();
    throw Hdf5Error(
        detail::concat(where, ": ", call, " failed", reason.empty() ? "" : ": ", reason));
  }
  return result;
}

inline Hid owned(hid_t id, Hid::Close close, const char* call, const std::string& where) {
  return Hid(check(id, call, where), close);
}

}  // namespace descent::hdf5
