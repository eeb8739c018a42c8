#!/usr/bin/env python3
"""Elongation of a hanging strip under an edge load and its own weight (docs/physics-reference.md
section 4.1).

Run: python3 docs/derivations/hanging_strip.py
A strip of width b, length L and areal density rho hangs from a clamped top edge; a force P is spread
along its bottom edge. At height s above the bottom the strip carries P plus the weight below s, so
the force per width is f(s) = (P + rho g b s) / b and the elongation is the integral over the length
of eps(f(s)), eps the inverse of the tensile curve (force per width against strain). For a linear
curve of stiffness k: dL = (P L + rho g b L^2 / 2) / (k b).

Prints the elongation of the paper's 20 x 38 cm strip for 0.4-2.4 N with four tensile laws: the
power-law and exponential reconstructions of Kumari & Khurana's denim B (kes_curves.py) and linear
laws at the two small-strain stiffnesses of Wang et al.'s 11 oz denim; then the power law as
libs/textile builds it (with its floor tangent) for the test composite of validation 1 and the
linear soft knit. Standard library only.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import kes_curves  # noqa: E402  (beside this script)

G = 9.81            # the tests' gravity [m/s^2]
WIDTH_M = 0.20
LENGTH_M = 0.38
LOADS_N = (0.0, 0.4, 0.8, 1.2, 1.6, 2.0, 2.4)


def elongation(strain_of_force_per_width, load_N, rho_kg_per_m2, intervals=2000):
    """Midpoint rule over the length; strain_of_force_per_width takes N/m."""
    h = LENGTH_M / intervals
    total = 0.0
    for i in range(intervals):
        s = (i + 0.5) * h
        total += strain_of_force_per_width((load_N + rho_kg_per_m2 * G * WIDTH_M * s) / WIDTH_M) * h
    return total


def inverse(force, upper=1.0):
    """Strain at which a monotone force(strain) law reaches f (bisection)."""
    def strain(f):
        lo, hi = 0.0, upper
        for _ in range(100):
            mid = 0.5 * (lo + hi)
            if force(mid) < f:
                lo = mid
            else:
                hi = mid
        return 0.5 * (lo + hi)
    return strain


def main():
    to_n_per_m = kes_curves.GF_PER_CM_TO_N_PER_M
    emt, lt = kes_curves.KUMARI_2016["B"][:2]
    _, _, pow_strain = kes_curves.power_law(emt, lt)
    _, _, exp_strain = kes_curves.exponential(emt, lt)
    laws = {
        "power law (denim B)": lambda f: pow_strain(f / to_n_per_m),
        "exponential (denim B)": lambda f: exp_strain(f / to_n_per_m),
        "linear 411 N/m": lambda f: f / 411.0,
        "linear 2028 N/m": lambda f: f / 2028.0,
    }
    rho = 0.30  # a typical denim, 300 g/m^2
    print(f"20 x 38 cm strip, rho = {rho} kg/m^2 (self-weight {rho * G * WIDTH_M * LENGTH_M:.4f} N); elongation [mm]:")
    print("P [N] | " + " | ".join(laws))
    results = {}
    for p in LOADS_N:
        row = [1000 * elongation(law, p, rho) for law in laws.values()]
        results[p] = row
        print(f"{p:.1f} | " + " | ".join(f"{v:6.2f}" for v in row))
    assert round(results[2.4][0], 1) == 3.7 and round(results[0.4][0], 1) == 1.7
    assert round(results[2.4][1], 1) == 1.9 and round(results[0.4][1], 1) == 0.4
    assert round(results[2.4][2], 1) == 11.6 and round(results[2.4][3], 1) == 2.4

    # Validation 1's two fabrics: the power law with libs/textile's floor tangent (2 % of the secant
    # Fm / em), mass of the Wang 11 oz denim; and the linear Wang soft knit.
    em = emt / 100.0
    fm = kes_curves.FM_GF_PER_CM * to_n_per_m
    n = 2.0 / lt - 1.0
    floor = 0.02 * fm / em
    composite = inverse(lambda e: max(fm * (e / em) ** n, floor * e))
    knit = lambda f: f / 25.0  # noqa: E731  (the data file's 25 N/m: 2 c11, rounded)
    print("\nValidation 1 (rho 0.324 composite denim; rho 0.224 knit at 25 N/m), elongation [mm]:")
    for p in LOADS_N[1:]:
        print(f"{p:.1f} | composite {1000 * elongation(composite, p, 0.324):8.4f} | knit {1000 * elongation(knit, p, 0.224):9.4f}")


if __name__ == "__main__":
    main()
