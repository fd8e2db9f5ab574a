#!/usr/bin/env python3
"""Analytic nominal stress-stretch curves of a box under uniaxial load (the
paper's Fig. 11), an independent reference for the solver's six models.

A homogeneous uniaxial state is F = diag(s, t, t): stretch s along the load
axis 1, lateral stretch t on axes 2 and 3. The lateral faces carry no
traction, P_22 = 0, i.e. dPsi/dt = 2 P_22 = 0 for Psi(diag(s, t, t)). For a
given s this script finds that t > 0 (a scan of t over [1e-3, 1e3] for
brackets where dPsi/dt goes from negative to positive, each refined by
bisection; the lowest-energy one wins) and reports the nominal stress
P_11 = dPsi/ds (first Piola-Kirchhoff, force per undeformed area).

The energy densities are written here from the formulas of DESIGN.md §1,
as functions of the principal stretches (a diagonal F with positive entries
is its own stretch tensor S and has singular values (s, t, t)). Their first
derivatives are taken by complex step, dPsi/dx = Im Psi(x + ih) / h with
h = 1e-30: exact to rounding, no subtraction.

A point is flagged not well-defined (column well_defined = 0 and a warning
on stderr) where no traction-free t > 0 exists or where the curve does not
rise, dP/ds <= 0 (e.g. StVK in compression below s = 1/sqrt(3): under a
prescribed load that branch is unstable and the box collapses).

  tools/uniaxial_reference.py --model neo_hookean --young 1e5 --poisson 0.3 \\
      --stretch-min 0.7 --stretch-max 2.0 --points 27 [--output curve.csv]
  tools/uniaxial_reference.py --model stvk --young 1e5 --poisson 0.3 --inverse=-1e4,2e4
      # stretch reached under each nominal stress (Pa), on the stable branch through s = 1

mooney_rivlin and fung take --c2 (Pa) and fung also --c3 (both default 0).
Output CSV columns: stretch,lateral_stretch,nominal_stress,well_defined.
From other scripts: uniaxial_point(model, s, Material(...)) and
stretch_for_stress(model, p, Material(...)). Standard library only.
"""
import argparse
import cmath
import csv
import math
import sys
from dataclasses import dataclass


@dataclass(frozen=True)
class Material:
    young: float
    poisson: float
    c2: float = 0.0
    c3: float = 0.0

    @property
    def mu(self):
        return self.young / (2 * (1 + self.poisson))

    @property
    def lam(self):
        return self.young * self.poisson / ((1 + self.poisson) * (1 - 2 * self.poisson))

    @property
    def kappa(self):
        return self.lam + 2 * self.mu / 3


# Energy densities of F = diag(a, b, c), a, b, c > 0 (real or complex for the complex step).

def _invariants(a, b, c):
    """J, I1bar, I2bar of F = diag(a, b, c)."""
    j = a * b * c
    i1 = a * a + b * b + c * c
    i2 = 0.5 * (i1 * i1 - (a ** 4 + b ** 4 + c ** 4))
    return j, j ** (-2 / 3) * i1, j ** (-4 / 3) * i2


def stvk(a, b, c, m):
    e = [(x * x - 1) / 2 for x in (a, b, c)]
    return m.mu * sum(x * x for x in e) + m.lam / 2 * sum(e) ** 2


def neo_hookean(a, b, c, m):
    j, i1bar, _ = _invariants(a, b, c)
    return m.mu / 2 * (i1bar - 3) + m.kappa / 2 * (j - 1) ** 2


def mooney_rivlin(a, b, c, m):
    _, _, i2bar = _invariants(a, b, c)
    return neo_hookean(a, b, c, m) + m.c2 * (i2bar - 3)


def fung(a, b, c, m):
    _, i1bar, _ = _invariants(a, b, c)
    return neo_hookean(a, b, c, m) + m.c2 * (cmath.exp(m.c3 * (i1bar - 3)) - 1)


def corotated(a, b, c, m):
    d = [x - 1 for x in (a, b, c)]  # S - I, S = F for a positive diagonal F
    return m.mu * sum(x * x for x in d) + m.lam / 2 * sum(d) ** 2


def arap(a, b, c, m):
    return m.mu * sum((x - 1) ** 2 for x in (a, b, c))


MODELS = {f.__name__: f for f in (stvk, neo_hookean, mooney_rivlin, fung, corotated, arap)}

_H = 1e-30  # complex-step size
_T_SCAN = [10 ** (k / 40) for k in range(-120, 121)]  # lateral stretches tried, 1e-3 .. 1e3
_DS = 1e-5  # relative step of the central difference for dP/ds


def energy(model, s, t, m):
    """Psi(diag(s, t, t))."""
    return complex(MODELS[model](s, t, t, m)).real


def nominal_stress(model, s, t, m):
    """P_11 = dPsi/ds at diag(s, t, t)."""
    return MODELS[model](complex(s, _H), t, t, m).imag / _H


def lateral_derivative(model, s, t, m):
    """dPsi/dt = 2 P_22 at diag(s, t, t) (t moves axes 2 and 3 together); nan on overflow."""
    tc = complex(t, _H)
    try:
        return MODELS[model](s, tc, tc, m).imag / _H
    except OverflowError:  # fung's exponential far from the root
        return math.nan


def _bisect(f, lo, hi):
    """A root of f between lo and hi, where f changes sign, to the last bit."""
    lo_negative = f(lo) < 0
    while True:
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):
            return mid
        if (f(mid) < 0) == lo_negative:
            lo = mid
        else:
            hi = mid


def lateral_stretch(model, s, m):
    """The traction-free t > 0 at stretch s (lowest energy one), None if there is none."""
    g = [lateral_derivative(model, s, t, m) for t in _T_SCAN]
    roots = [_bisect(lambda t: lateral_derivative(model, s, t, m), t0, t1)
             for t0, t1, g0, g1 in zip(_T_SCAN, _T_SCAN[1:], g, g[1:]) if g0 < 0 <= g1]
    return min(roots, key=lambda t: energy(model, s, t, m), default=None)


def stress_at(model, s, m):
    """P_11 at stretch s with traction-free sides, nan where no lateral stretch exists."""
    t = lateral_stretch(model, s, m)
    return math.nan if t is None else nominal_stress(model, s, t, m)


@dataclass(frozen=True)
class Point:
    stretch: float
    lateral_stretch: float
    nominal_stress: float
    slope: float  # dP/ds along the uniaxial path
    well_defined: bool


def uniaxial_point(model, s, m):
    """The uniaxial state at stretch s, with its slope and well-definedness."""
    t = lateral_stretch(model, s, m)
    if t is None:
        return Point(s, math.nan, math.nan, math.nan, False)
    h = _DS * s
    slope = (stress_at(model, s + h, m) - stress_at(model, s - h, m)) / (2 * h)
    return Point(s, t, nominal_stress(model, s, t, m), slope, slope > 0)


def stretch_for_stress(model, p, m, step=1.01):
    """The stretch at which P_11 = p, following the rising branch from s = 1 in
    steps of `step`; None if that branch ends (no lateral root, P stops
    rising, or s leaves [0.01, 100]) before reaching p."""
    if p == 0:
        return 1.0
    ratio = step if p > 0 else 1 / step
    s0, p0 = 1.0, 0.0
    while 0.01 < s0 < 100:
        s1 = s0 * ratio
        p1 = stress_at(model, s1, m)
        if not (p1 - p0) * (ratio - 1) > 0:  # no lateral root (nan) or P not rising
            return None
        if (p1 - p) * (p0 - p) <= 0:
            s = _bisect(lambda x: stress_at(model, x, m) - p, s0, s1)
            return s if uniaxial_point(model, s, m).well_defined else None
        s0, p0 = s1, p1
    return None


def _floats(text):
    return [float(x) for x in text.split(",")]


def _material(args):
    if args.young <= 0 or not -1 < args.poisson < 0.5:
        sys.exit("uniaxial_reference.py: need --young > 0 and -1 < --poisson < 0.5")
    return Material(args.young, args.poisson, args.c2, args.c3)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--model", required=True, choices=sorted(MODELS))
    parser.add_argument("--young", type=float, required=True, help="Young's modulus E (Pa)")
    parser.add_argument("--poisson", type=float, required=True, help="Poisson ratio nu")
    parser.add_argument("--c2", type=float, default=0.0, help="mooney_rivlin / fung coefficient (Pa)")
    parser.add_argument("--c3", type=float, default=0.0, help="fung exponent coefficient")
    parser.add_argument("--stretch-min", type=float, default=0.7)
    parser.add_argument("--stretch-max", type=float, default=2.0)
    parser.add_argument("--points", type=int, default=27)
    parser.add_argument("--inverse", type=_floats, metavar="P[,P...]",
                        help="nominal stresses (force per undeformed area, Pa), comma-separated: report the stretch "
                             "each one reaches (write --inverse=-1e4 when the first one is negative)")
    parser.add_argument("--output", help="CSV file (default: stdout)")
    args = parser.parse_args(argv)
    m = _material(args)

    if args.inverse:
        points = []
        for p in args.inverse:
            s = stretch_for_stress(args.model, p, m)
            points.append(uniaxial_point(args.model, s, m) if s is not None
                          else Point(math.nan, math.nan, p, math.nan, False))
    else:
        n = args.points
        if n < 1 or args.stretch_min <= 0 or args.stretch_max < args.stretch_min:
            sys.exit("uniaxial_reference.py: need --points >= 1 and 0 < --stretch-min <= --stretch-max")
        span = args.stretch_max - args.stretch_min
        points = [uniaxial_point(args.model, args.stretch_min + span * i / max(n - 1, 1), m) for i in range(n)]

    bad = [p for p in points if not p.well_defined]
    if bad:
        what = "nominal stress" if args.inverse else "stretch"
        values = ", ".join(f"{p.nominal_stress if args.inverse else p.stretch:.6g}" for p in bad)
        print(f"warning: {args.model} is not well-defined (no traction-free lateral stretch, or dP/ds <= 0) "
              f"at {what} {values}", file=sys.stderr)

    out = open(args.output, "w", newline="") if args.output else sys.stdout
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(["stretch", "lateral_stretch", "nominal_stress", "well_defined"])
    for p in points:
        writer.writerow([f"{p.stretch:.12g}", f"{p.lateral_stretch:.12g}", f"{p.nominal_stress:.12g}",
                         int(p.well_defined)])
    if args.output:
        out.close()


if __name__ == "__main__":
    main()
