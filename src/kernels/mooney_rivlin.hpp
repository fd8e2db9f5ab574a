#pragma once
// Compressible Mooney-Rivlin energy density (DESIGN §1, paper 1 Eq. 14):
//   Psi(F) = neo-Hookean(F) + c2 (J^(-4/3) I2 - 3),
// I2 = 1/2 (I1^2 - tr C^2) = |cof F|^2 (Frobenius), C = F^T F. The added term
// is isochoric; near F = I it adds 2 c2 to the shear modulus (Ibar2 - 3 ~
// 2 |dev eps|^2), the bulk modulus stays kappa. Like neo-Hookean it is finite
// for J < 0 (real cube root) and infinite at J = 0.
//
// With G = cof F, T = I1 F - F C (so dI2 = 2 T : dF) and w = J^(-4/3):
//   P2 = c2 (2 w T - 4/3 w/J I2 G),
//   dP2/dF = c2 (2 w dT/dF - 8/3 w/J (T (x) G + G (x) T)
//                + 28/9 w/J^2 I2 G (x) G - 4/3 w/J I2 d2J/dF2),
//   dT_ij/dF_kl = 2 F_ij F_kl + I1 delta_ik delta_jl - delta_ik C_lj
//                 - F_il F_kj - (F F^T)_ik delta_jl.
#include <cmath>

#include "kernels/neo_hookean.hpp"
#include "kernels/real_math.hpp"

namespace descent {

template <class Real>
struct MooneyRivlin {
  // Built on J^(-2/3): meaningless for det F <= 0, where element_energy
  // makes it infinite so that no step into inversion is accepted.
  static constexpr bool kInvertible = false;
  NeoHookean<Real> neo_hookean;
  Real c2;

  static MooneyRivlin from_young_poisson(Real young, Real poisson, Real c2) {
    return {NeoHookean<Real>::from_young_poisson(young, poisson), c2};
  }

  // The invariants the I2 term needs, computed once per F.
  struct Terms {
    Mat3<Real> g;  // cof F
    Mat3<Real> t;  // I1 F - F F^T F
    Real j, i1, i2;
    Real w;  // J^(-4/3)
  };

  DESCENT_HOST_DEVICE static Terms terms(const Mat3<Real>& f) {
    Terms r;
    r.g = cofactor(f);
    r.j = f.m[0] * r.g.m[0] + f.m[1] * r.g.m[1] + f.m[2] * r.g.m[2];
    r.i1 = ddot(f, f);
    r.i2 = ddot(r.g, r.g);
    const Real root_j = cube_root(r.j);
    r.w = Real(1) / (root_j * root_j * root_j * root_j);
    Mat3<Real> ft;  // F^T
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) ft.m[3 * i + k] = f.m[3 * k + i];
    const Mat3<Real> ffff = mul(mul(f, ft), f);
    for (int k = 0; k < 9; ++k) r.t.m[k] = r.i1 * f.m[k] - ffff.m[k];
    return r;
  }

  DESCENT_HOST_DEVICE Real energy(const Mat3<Real>& f) const {
    const Mat3<Real> g = cofactor(f);
    const Real j = f.m[0] * g.m[0] + f.m[1] * g.m[1] + f.m[2] * g.m[2];
    const Real root_j = cube_root(j);
    const Real w = Real(1) / (root_j * root_j * root_j * root_j);
    return neo_hookean.energy(f) + c2 * (w * ddot(g, g) - Real(3));
  }

  DESCENT_HOST_DEVICE Mat3<Real> stress(const Mat3<Real>& f) const {
    const Terms r = terms(f);
    const Real a = Real(2) * c2 * r.w;
    const Real b = -Real(4) / Real(3) * c2 * r.w / r.j * r.i2;
    Mat3<Real> p = neo_hookean.stress(f);
    for (int k = 0; k < 9; ++k) p.m[k] += a * r.t.m[k] + b * r.g.m[k];
    return p;
  }

  // Along dF = e_i b^T, d2J = 0 (J is linear in each row) and
  //   dT : dF = (F_i . b)^2 + (I1 - |F_i|^2) |b|^2 - |F b|^2,
  // so the I2 term adds c2 (2 w (that) - 16/3 w/J (T_i . b)(G_i . b)
  //                         + 28/9 w/J^2 I2 (G_i . b)^2).
  DESCENT_HOST_DEVICE void hessian_diagonal(const Mat3<Real>& f, const Vec3<Real> b[4],
                                            Vec3<Real> out[4]) const {
    neo_hookean.hessian_diagonal(f, b, out);
    const Terms r = terms(f);
    const Real w_j = r.w / r.j;
    for (int a = 0; a < 4; ++a) {
      const Vec3<Real> fb = mul(f, b[a]);
      const Real bb = dot(b[a], b[a]);
      Real d[3];
      for (int i = 0; i < 3; ++i) {
        const Vec3<Real> fi = row(f, i);
        const Real fib = dot(fi, b[a]);
        const Real tb = dot(row(r.t, i), b[a]);
        const Real gb = dot(row(r.g, i), b[a]);
        const Real dt = fib * fib + (r.i1 - dot(fi, fi)) * bb - dot(fb, fb);
        d[i] = c2 * (Real(2) * r.w * dt - Real(16) / Real(3) * w_j * tb * gb +
                     Real(28) / Real(9) * w_j / r.j * r.i2 * gb * gb);
      }
      out[a].x += d[0];
      out[a].y += d[1];
      out[a].z += d[2];
    }
  }

  DESCENT_HOST_DEVICE void stress_derivative(const Mat3<Real>& f, Real dpdf[81]) const {
    neo_hookean.stress_derivative(f, dpdf);
    const Terms r = terms(f);
    const Real w_j = r.w / r.j;
    const Real two_w = Real(2) * c2 * r.w;
    for (int i = 0; i < 3; ++i) {
      for (int k = 0; k < 3; ++k) {
        const Real ffik = f.m[3 * i] * f.m[3 * k] + f.m[3 * i + 1] * f.m[3 * k + 1] +
                          f.m[3 * i + 2] * f.m[3 * k + 2];
        for (int j = 0; j < 3; ++j) {
          for (int l = 0; l < 3; ++l) {
            Real dt = Real(2) * f.m[3 * i + j] * f.m[3 * k + l] - f.m[3 * i + l] * f.m[3 * k + j];
            if (i == k) {
              // C_lj = column l of F . column j of F
              dt -= f.m[l] * f.m[j] + f.m[3 + l] * f.m[3 + j] + f.m[6 + l] * f.m[6 + j];
              if (j == l) dt += r.i1;
            }
            if (j == l) dt -= ffik;
            dpdf[(3 * i + j) * 9 + 3 * k + l] += two_w * dt;
          }
        }
      }
    }
    add_symmetric_outer(r.t, r.g, -Real(8) / Real(3) * c2 * w_j, dpdf);
    add_outer(r.g, Real(28) / Real(9) * c2 * w_j / r.j * r.i2, dpdf);
    add_det_hessian(f, -Real(4) / Real(3) * c2 * w_j * r.i2, dpdf);
  }
};

}  // namespace descent
