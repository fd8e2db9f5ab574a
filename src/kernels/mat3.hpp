#pragma once
// Small fixed-size linear algebra for element math: 3-vectors and row-major
// 3x3 matrices of a real type, usable on host and device, no allocation.
#include "kernels/host_device.hpp"

namespace descent {

template <class Real>
struct Vec3 {
  Real x, y, z;
};

// m[3 * row + col]
template <class Real>
struct Mat3 {
  Real m[9];
  DESCENT_HOST_DEVICE Real operator()(int row, int col) const { return m[3 * row + col]; }
  DESCENT_HOST_DEVICE Real& operator()(int row, int col) { return m[3 * row + col]; }
};

template <class Real>
DESCENT_HOST_DEVICE inline Real dot(const Vec3<Real>& a, const Vec3<Real>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}

template <class Real>
DESCENT_HOST_DEVICE inline Vec3<Real> row(const Mat3<Real>& a, int i) {
  return {a.m[3 * i], a.m[3 * i + 1], a.m[3 * i + 2]};
}

template <class Real>
DESCENT_HOST_DEVICE inline Real det(const Mat3<Real>& a) {
  return a.m[0] * (a.m[4] * a.m[8] - a.m[5] * a.m[7]) -
         a.m[1] * (a.m[3] * a.m[8] - a.m[5] * a.m[6]) +
         a.m[2] * (a.m[3] * a.m[7] - a.m[4] * a.m[6]);
}

// Cofactor matrix: cof(A)_ij = d det(A) / d A_ij = det(A) A^-T, defined also
// for singular A.
template <class Real>
DESCENT_HOST_DEVICE inline Mat3<Real> cofactor(const Mat3<Real>& a) {
  return {{a.m[4] * a.m[8] - a.m[5] * a.m[7], a.m[5] * a.m[6] - a.m[3] * a.m[8],
           a.m[3] * a.m[7] - a.m[4] * a.m[6], a.m[2] * a.m[7] - a.m[1] * a.m[8],
           a.m[0] * a.m[8] - a.m[2] * a.m[6], a.m[1] * a.m[6] - a.m[0] * a.m[7],
           a.m[1] * a.m[5] - a.m[2] * a.m[4], a.m[2] * a.m[3] - a.m[0] * a.m[5],
           a.m[0] * a.m[4] - a.m[1] * a.m[3]}};
}

// Frobenius inner product A : B.
template <class Real>
DESCENT_HOST_DEVICE inline Real ddot(const Mat3<Real>& a, const Mat3<Real>& b) {
  Real s = 0;
  for (int k = 0; k < 9; ++k) s += a.m[k] * b.m[k];
  return s;
}

template <class Real>
DESCENT_HOST_DEVICE inline Mat3<Real> mul(const Mat3<Real>& a, const Mat3<Real>& b) {
  Mat3<Real> c;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      c.m[3 * i + j] =
          a.m[3 * i] * b.m[j] + a.m[3 * i + 1] * b.m[3 + j] + a.m[3 * i + 2] * b.m[6 + j];
  return c;
}

template <class Real>
DESCENT_HOST_DEVICE inline Vec3<Real> mul(const Mat3<Real>& a, const Vec3<Real>& v) {
  return {a.m[0] * v.x + a.m[1] * v.y + a.m[2] * v.z, a.m[3] * v.x + a.m[4] * v.y + a.m[5] * v.z,
          a.m[6] * v.x + a.m[7] * v.y + a.m[8] * v.z};
}

}  // namespace descent
