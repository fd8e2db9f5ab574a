// Counts, from the code itself, the floating-point operations each model's
// element math performs per tet: the kernels of src/kernels are instantiated
// on Counted, a double that counts every arithmetic operation and math call
// it takes part in (the kernels call their math unqualified for this:
// kernels/real_math.hpp). Branches follow the real values, so the counts are
// those of the deformation given: a tet deformed by a random rotation and a
// stretch of up to `strain` per axis, averaged over `samples` such tets.
//
// Output (bench/roofline.py reads it): one line per model and kernel,
//   model kernel add mul div sqrt cbrt exp compare other
// per tet (per dof for the vertex kernels), where add counts additions and
// subtractions, cbrt the cube roots (kernels/cube_root.hpp), compare the
// comparisons, other abs, copysign, fmax, frexp and ldexp (bit operations
// on x86, not floating-point arithmetic).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <random>
#include <string>

#include "kernels/cube_root.hpp"
#include "kernels/exponential.hpp"

namespace descent::roofline {

struct OpCounts {
  double add = 0, mul = 0, div = 0, sqrt = 0, cbrt = 0, exp = 0, compare = 0, other = 0;
};

inline OpCounts counts;

// A double that counts the operations made on it (layout: the value alone).
struct Counted {
  double v = 0;
  Counted() = default;
  Counted(double x) : v(x) {}  // NOLINT: literals and Real(2) convert implicitly, as for double
  explicit operator double() const { return v; }

  friend Counted operator+(Counted a, Counted b) { return ++counts.add, Counted(a.v + b.v); }
  friend Counted operator-(Counted a, Counted b) { return ++counts.add, Counted(a.v - b.v); }
  friend Counted operator*(Counted a, Counted b) { return ++counts.mul, Counted(a.v * b.v); }
  friend Counted operator/(Counted a, Counted b) { return ++counts.div, Counted(a.v / b.v); }
  friend Counted operator-(Counted a) { return Counted(-a.v); }  // a sign flip, not counted
  Counted& operator+=(Counted b) { return *this = *this + b; }
  Counted& operator-=(Counted b) { return *this = *this - b; }
  Counted& operator*=(Counted b) { return *this = *this * b; }
  Counted& operator/=(Counted b) { return *this = *this / b; }
  friend bool operator<(Counted a, Counted b) { return ++counts.compare, a.v < b.v; }
  friend bool operator>(Counted a, Counted b) { return ++counts.compare, a.v > b.v; }
  friend bool operator<=(Counted a, Counted b) { return ++counts.compare, a.v <= b.v; }
  friend bool operator>=(Counted a, Counted b) { return ++counts.compare, a.v >= b.v; }
  friend bool operator==(Counted a, Counted b) { return ++counts.compare, a.v == b.v; }
  friend bool operator!=(Counted a, Counted b) { return ++counts.compare, a.v != b.v; }

  friend Counted sqrt(Counted a) { return ++counts.sqrt, Counted(std::sqrt(a.v)); }
  friend Counted cube_root(Counted a) { return ++counts.cbrt, Counted(descent::cube_root(a.v)); }
  friend Counted exponential(Counted a) { return ++counts.exp, Counted(descent::exponential(a.v)); }
  friend Counted abs(Counted a) { return ++counts.other, Counted(std::abs(a.v)); }
  friend Counted copysign(Counted a, Counted b) {
    return ++counts.other, Counted(std::copysign(a.v, b.v));
  }
  friend Counted fmax(Counted a, Counted b) { return ++counts.other, Counted(std::fmax(a.v, b.v)); }
  friend Counted frexp(Counted a, int* e) { return ++counts.other, Counted(std::frexp(a.v, e)); }
  friend Counted ldexp(Counted a, int e) { return ++counts.other, Counted(std::ldexp(a.v, e)); }
};

}  // namespace descent::roofline

// The kernels read epsilon and infinity of their real type.
template <>
struct std::numeric_limits<descent::roofline::Counted> : std::numeric_limits<double> {};

// Included after Counted so that the kernels' unqualified math finds its
// overloads (argument-dependent lookup happens at instantiation either way).
#include "kernels/arap.hpp"
#include "kernels/conversion.hpp"
#include "kernels/corotated.hpp"
#include "kernels/element.hpp"
#include "kernels/fung.hpp"
#include "kernels/mooney_rivlin.hpp"
#include "kernels/neo_hookean.hpp"
#include "kernels/stvk.hpp"
#include "kernels/vertex.hpp"

namespace descent::roofline {
namespace {

using R = Counted;

struct Sample {
  TetRest<R> rest;
  TetCorners<R> corners;
};

Mat3<double> rotation(std::mt19937_64& rng) {
  // A random unit quaternion, as a rotation matrix.
  std::normal_distribution<double> normal;
  double w = normal(rng), x = normal(rng), y = normal(rng), z = normal(rng);
  const double n = std::sqrt(w * w + x * x + y * y + z * z);
  w /= n, x /= n, y /= n, z /= n;
  return {{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),  //
           2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),  //
           2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
}

// A near-regular rest tet and its corners moved by F = R diag(1 + s_i) with
// s_i uniform in [-strain, strain].
Sample make_sample(std::mt19937_64& rng, double strain) {
  std::uniform_real_distribution<double> jitter(-0.1, 0.1), stretch(-strain, strain);
  const double base[4][3] = {{0, 0, 0}, {1, 0, 0}, {0.5, 0.87, 0}, {0.5, 0.29, 0.82}};
  const Mat3<double> rot = rotation(rng);
  const double s[3] = {1 + stretch(rng), 1 + stretch(rng), 1 + stretch(rng)};
  Vec3<R> rest_x[4];
  Sample sample;
  for (int a = 0; a < 4; ++a) {
    double p[3];
    for (int i = 0; i < 3; ++i) p[i] = base[a][i] + jitter(rng);
    rest_x[a] = {p[0], p[1], p[2]};
    double q[3];
    for (int i = 0; i < 3; ++i)
      q[i] = rot(i, 0) * s[0] * p[0] + rot(i, 1) * s[1] * p[1] + rot(i, 2) * s[2] * p[2];
    sample.corners.x[a] = {q[0], q[1], q[2]};
  }
  sample.rest = tet_rest(rest_x[0], rest_x[1], rest_x[2], rest_x[3]);
  return sample;
}

void print(const char* model, const char* kernel, const OpCounts& c, int samples) {
  const double n = samples;
  std::printf("%s %s %.2f %.2f %.2f %.2f %.2f %.2f %.2f %.2f\n", model, kernel, c.add / n,
              c.mul / n, c.div / n, c.sqrt / n, c.cbrt / n, c.exp / n, c.compare / n, c.other / n);
}

// The per-tet kernels of one model: the gradient (every iteration), the
// Hessian diagonal (each refresh), the energy (each check), and with
// conversion the converted gradient alone and with the diagonal, and the
// converted energy at the interpolant the gradient left.
template <class Model>
void count_model(const char* name, const Model& model, const Conversion<R>& conv, int samples,
                 double strain) {
  std::mt19937_64 rng(2026);
  OpCounts gradient, diagonal, energy, converted, converted_diag, converted_e;
  for (int k = 0; k < samples; ++k) {
    const Sample s = make_sample(rng, strain);
    Vec3<R> g[4], d[4];
    const auto measure = [](OpCounts& into, auto&& body) {
      counts = {};
      body();
      into.add += counts.add, into.mul += counts.mul, into.div += counts.div;
      into.sqrt += counts.sqrt, into.cbrt += counts.cbrt, into.exp += counts.exp;
      into.compare += counts.compare, into.other += counts.other;
    };
    measure(gradient, [&] { element_gradient(model, s.rest, s.corners, g); });
    measure(diagonal, [&] { element_hessian_diagonal(model, s.rest, s.corners, d); });
    measure(energy, [&] { element_energy(model, s.rest, s.corners); });
    R l = 0;
    measure(converted, [&] {
      converted_gradient(model, conv, l, s.rest, s.corners, g, static_cast<Vec3<R>*>(nullptr));
    });
    measure(converted_e, [&] { converted_energy(model, conv, l, s.rest, s.corners); });
    l = 0;
    measure(converted_diag, [&] { converted_gradient(model, conv, l, s.rest, s.corners, g, d); });
  }
  print(name, "gradient", gradient, samples);
  print(name, "diagonal", diagonal, samples);
  print(name, "energy", energy, samples);
  print(name, "converted_gradient", converted, samples);
  print(name, "converted_gradient_diagonal", converted_diag, samples);
  print(name, "converted_energy", converted_e, samples);
}

// The per-dof vertex kernels: the Chebyshev update (gradient of the vertex
// terms and the step), the diagonal at a refresh, the energy at a check.
void count_vertex() {
  const VertexTerms<R> terms{900.0, 0.0, {0.0, 0.0, -9.8}};
  OpCounts update, diagonal, energy;
  counts = {};
  const R g = dof_gradient(terms, R(0.1), R(1.0), R(0.5), R(0.4), R(0.45), R(0.0), 2);
  chebyshev_dof(R(0.5), R(0.49), g, R(100.0), R(1.0), R(1.9));
  update = counts;
  counts = {};
  dof_diagonal(terms, R(0.1), R(50.0), R(90.0));
  diagonal = counts;
  counts = {};
  dof_energy(terms, R(0.1), R(0.5), R(0.4), R(0.45), R(0.0), 2);
  energy = counts;
  print("vertex", "update", update, 1);
  print("vertex", "diagonal", diagonal, 1);
  print("vertex", "energy", energy, 1);
}

}  // namespace
}  // namespace descent::roofline

int main(int argc, char** argv) {
  using namespace descent;
  using namespace descent::roofline;
  const int samples = argc > 1 ? std::atoi(argv[1]) : 64;
  const double strain = argc > 2 ? std::atof(argv[2]) : 0.2;
  if (samples < 1 || !(strain >= 0 && strain < 0.9)) {
    std::fprintf(stderr, "usage: %s [samples >= 1] [strain in [0, 0.9)]\n", argv[0]);
    return 2;
  }
  // The helix's material (jobs/helix.toml): E = 1e5 Pa, nu = 0.3; c2 and c3
  // of mooney_rivlin and fung nonzero so that their extra terms are counted.
  const R young = 1e5, poisson = 0.3;
  const Conversion<R> conv{0.05, 0.15, 0.05, Arap<R>::from_young_poisson(young, poisson)};
  std::printf(
      "# model kernel add mul div sqrt cbrt exp compare other (per tet; vertex: per dof)\n");
  std::printf("# samples %d strain %g\n", samples, strain);
  count_model("stvk", StVK<R>::from_young_poisson(young, poisson), conv, samples, strain);
  count_model("neo_hookean", NeoHookean<R>::from_young_poisson(young, poisson), conv, samples,
              strain);
  count_model("mooney_rivlin", MooneyRivlin<R>::from_young_poisson(young, poisson, 1e4), conv,
              samples, strain);
  count_model("fung", Fung<R>::from_young_poisson(young, poisson, 1e4, 2.0), conv, samples, strain);
  count_model("corotated", Corotated<R>::from_young_poisson(young, poisson), conv, samples, strain);
  count_model("arap", Arap<R>::from_young_poisson(young, poisson), conv, samples, strain);
  count_vertex();
  return 0;
}
