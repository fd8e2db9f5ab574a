#!/usr/bin/env python3
"""Checks of tools/uniaxial_reference.py against closed forms (standard library only).

  python3 tools/test_uniaxial_reference.py

Closed forms used (mu, lambda, kappa from E, nu as in DESIGN.md §1):
- Small strain, any isotropic model with shear modulus mu0 and bulk modulus
  kappa: slope dP/ds(1) = E0 = 9 kappa mu0 / (3 kappa + mu0) and lateral
  stretch t = 1 - nu0 e with nu0 = (3 kappa - 2 mu0) / (2 (3 kappa + mu0)).
  neo_hookean, stvk, corotated: mu0 = mu, so E0 = E and nu0 = nu.
  mooney_rivlin: mu0 = mu + 2 c2 (Ibar1 - 3 and Ibar2 - 3 both equal
  2 tr(dev eps^2) to second order). fung: mu0 = mu + 2 c2 c3 (the exponential
  is c2 c3 (Ibar1 - 3) to second order in strain).
- arap, exactly: t = 1 and P = 2 mu (s - 1), so E0 = 2 mu = E / (1 + nu).
- corotated, exactly (linear in the stretches): t = 1 - nu (s - 1), P = E (s - 1).
- stvk, exactly: t^2 = 1 - nu (s^2 - 1), P = E s (s^2 - 1) / 2; dP/ds =
  E (3 s^2 - 1) / 2 <= 0 below s = 1/sqrt(3), no lateral root above
  s = sqrt(1 + 1/nu).
- neo_hookean with nu -> 1/2: volume preserved, t = s^(-1/2), and the
  incompressible neo-Hookean curve P = mu (s - s^-2).
"""
import csv
import math
import os
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from uniaxial_reference import MODELS, Material, main, stress_at, stretch_for_stress, uniaxial_point  # noqa: E402

E, NU = 1e5, 0.3
MAT = Material(E, NU, c2=5e3, c3=2.0)


def small_strain_moduli(model, m):
    """(E0, nu0) of the model's small-strain limit, from the closed forms above."""
    mu0 = {"mooney_rivlin": m.mu + 2 * m.c2, "fung": m.mu + 2 * m.c2 * m.c3}.get(model, m.mu)
    if model == "arap":
        return 2 * m.mu, 0.0
    return 9 * m.kappa * mu0 / (3 * m.kappa + mu0), (3 * m.kappa - 2 * mu0) / (2 * (3 * m.kappa + mu0))


class SmallStrain(unittest.TestCase):
    def test_rest_state_is_stress_free(self):
        for model in MODELS:
            p = uniaxial_point(model, 1.0, MAT)
            self.assertTrue(p.well_defined, model)
            self.assertAlmostEqual(p.lateral_stretch, 1.0, delta=1e-12, msg=model)
            self.assertAlmostEqual(p.nominal_stress, 0.0, delta=1e-9 * E, msg=model)

    def test_slope_is_young_modulus(self):
        for model in ("stvk", "neo_hookean", "corotated"):
            self.assertAlmostEqual(uniaxial_point(model, 1.0, MAT).slope / E, 1.0, delta=1e-3, msg=model)

    def test_slope_closed_forms(self):
        for model in ("arap", "mooney_rivlin", "fung"):
            e0, _ = small_strain_moduli(model, MAT)
            self.assertAlmostEqual(uniaxial_point(model, 1.0, MAT).slope / e0, 1.0, delta=1e-3, msg=model)

    def test_lateral_contraction(self):
        e = 1e-4
        for model in MODELS:
            _, nu0 = small_strain_moduli(model, MAT)
            t = uniaxial_point(model, 1.0 + e, MAT).lateral_stretch
            self.assertAlmostEqual((1.0 - t) / e, nu0, delta=1e-3, msg=model)


class ExactCurves(unittest.TestCase):
    stretches = (0.6, 0.8, 1.2, 1.5, 2.0)

    def test_arap(self):
        for s in self.stretches:
            p = uniaxial_point("arap", s, MAT)
            self.assertAlmostEqual(p.lateral_stretch, 1.0, delta=1e-12)
            self.assertAlmostEqual(p.nominal_stress, 2 * MAT.mu * (s - 1), delta=1e-9 * E)

    def test_corotated(self):
        for s in self.stretches:
            p = uniaxial_point("corotated", s, MAT)
            self.assertAlmostEqual(p.lateral_stretch, 1 - NU * (s - 1), delta=1e-12)
            self.assertAlmostEqual(p.nominal_stress, E * (s - 1), delta=1e-9 * E)

    def test_stvk(self):
        for s in self.stretches:
            p = uniaxial_point("stvk", s, MAT)
            self.assertTrue(p.well_defined, s)
            self.assertAlmostEqual(p.lateral_stretch, math.sqrt(1 - NU * (s * s - 1)), delta=1e-12)
            self.assertAlmostEqual(p.nominal_stress, E * s * (s * s - 1) / 2, delta=1e-9 * E)

    def test_stvk_ill_defined_ends(self):
        compressed = uniaxial_point("stvk", 0.5, MAT)  # below 1/sqrt(3): dP/ds < 0
        self.assertFalse(compressed.well_defined)
        self.assertLess(compressed.slope, 0)
        stretched = uniaxial_point("stvk", 2.2, MAT)  # above sqrt(1 + 1/nu): no lateral root
        self.assertFalse(stretched.well_defined)
        self.assertTrue(math.isnan(stretched.lateral_stretch))

    def test_neo_hookean_near_incompressible(self):
        m = Material(E, 0.4999)
        for s in (0.7, 1.5, 2.0):
            p = uniaxial_point("neo_hookean", s, m)
            self.assertAlmostEqual(p.lateral_stretch / s ** -0.5, 1.0, delta=1e-3)
            self.assertAlmostEqual(p.nominal_stress / (m.mu * (s - s ** -2)), 1.0, delta=1e-3)


class Inverse(unittest.TestCase):
    def test_inverse_matches_forward(self):
        for model in MODELS:
            for s in (0.8, 0.95, 1.1, 1.6):
                found = stretch_for_stress(model, stress_at(model, s, MAT), MAT)
                self.assertAlmostEqual(found, s, delta=1e-9, msg=model)

    def test_stvk_beyond_limit_load(self):
        limit = E * 3 ** -0.5 * (1 / 3 - 1) / 2  # P at s = 1/sqrt(3), the most compressive load
        self.assertIsNone(stretch_for_stress("stvk", 1.01 * limit, MAT))
        self.assertIsNotNone(stretch_for_stress("stvk", 0.9 * limit, MAT))

    def test_cli(self):
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "curve.csv")
            main(["--model", "corotated", "--young", str(E), "--poisson", str(NU), "--inverse=-2e4,3e4",
                  "--output", path])
            with open(path) as f:
                rows = list(csv.DictReader(f))
        self.assertEqual([float(r["stretch"]) for r in rows], [0.8, 1.3])
        self.assertEqual([r["well_defined"] for r in rows], ["1", "1"])


if __name__ == "__main__":
    unittest.main()
