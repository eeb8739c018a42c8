#!/usr/bin/env python3
"""KES-f units and tensile curves rebuilt from summary values (docs/physics-reference.md sections 1-2).

Run: python3 docs/derivations/kes_curves.py
Prints the exact unit factors, both reconstructions of a loading curve from (EMT, LT), the six
Kumari & Khurana 2016 denims, and the worked example for their sample B; asserts the figures that
docs and tests quote. Standard library only; hanging_strip.py imports this module.
"""
import math

G_N = 9.80665e-3          # one gram-force in newtons (standard gravity, exact)
FM_GF_PER_CM = 500.0      # KES-FB1 standard maximum tensile load

# Unit factors, each from its definition: force per width, energy per area, moment per width.
GF_PER_CM_TO_N_PER_M = G_N / 1e-2                   # gf/cm -> N/m
GFCM_PER_CM2_TO_J_PER_M2 = G_N * 1e-2 / 1e-4        # gf cm/cm^2 -> J/m^2 (numerically N/m)
GFCM2_PER_CM_TO_NM = G_N * 1e-4 / 1e-2              # gf cm^2/cm -> N m
GFCM_PER_CM_TO_N = G_N * 1e-2 / 1e-2                # gf cm/cm -> N m/m
GF_PER_CM_DEG_TO_N_PER_M_RAD = GF_PER_CM_TO_N_PER_M * 180.0 / math.pi  # per degree -> per radian
MG_PER_CM2_TO_KG_PER_M2 = 1e-6 / 1e-4               # mg/cm^2 -> kg/m^2


def power_law(emt_percent, lt):
    """F = Fm (e/em)^n with n = 2/LT - 1 (F in gf/cm). Returns (n, force(e), strain(F))."""
    em = emt_percent / 100.0
    n = 2.0 / lt - 1.0
    return (n,
            lambda e: FM_GF_PER_CM * (max(e, 0.0) / em) ** n,
            lambda f: em * (f / FM_GF_PER_CM) ** (1.0 / n))


def _exponential_lt(x):
    """LT of F = A (exp(b e) - 1) on [0, em], as a function of x = b em."""
    return 2.0 * (math.expm1(x) - x) / (x * math.expm1(x))


def exponential(emt_percent, lt):
    """F = A (exp(b e) - 1) through (em, Fm) with linearity LT (< 1). Returns ((A, b), force, strain)."""
    if not 0.0 < lt < 1.0:
        raise ValueError("the exponential form needs 0 < LT < 1")
    em = emt_percent / 100.0
    lo, hi = 1e-9, 500.0          # _exponential_lt falls from 1 (x -> 0) towards 0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if _exponential_lt(mid) > lt:
            lo = mid
        else:
            hi = mid
    x = 0.5 * (lo + hi)
    b = x / em
    a = FM_GF_PER_CM / math.expm1(x)
    return (a, b), (lambda e: a * math.expm1(b * e)), (lambda f: math.log1p(f / a) / b)


# Kumari & Khurana 2016, Table 5 (doi:10.1155/2016/4614168), as printed. WT None: misprinted.
KUMARI_2016 = {
    #     EMT %   LT     WT      B gf cm2/cm  G gf/(cm deg)  SMD um  T mm
    "A": (5.515, 0.712, 0.825, 0.172, 2.180, 3.673, 1.066),
    "B": (5.735, 0.655, 9.400, 0.144, 1.538, 6.493, 1.188),
    "C": (4.695, 0.780, 8.975, 0.227, 3.398, 2.177, 0.801),
    "D": (5.135, 0.676, 8.675, 0.147, 1.613, 3.462, 1.040),
    "E": (4.710, 0.720, 0.475, 0.207, 1.538, 3.103, 0.887),
    "F": (5.455, 0.657, 8.950, 0.148, 1.500, 3.618, 0.973),
}

# Boettcher et al. 2008, section 6: 0.4-2.4 N on a 20 cm wide strip.
STRIP_WIDTH_M = 0.20
STRIP_LENGTH_M = 0.38
LOADS_N = (0.4, 2.4)


def main():
    print("Unit factors (exact):")
    print(f"  1 gf/cm        = {GF_PER_CM_TO_N_PER_M:.6f} N/m   (Fm = 500 gf/cm = {500 * GF_PER_CM_TO_N_PER_M:.4f} N/m)")
    print(f"  1 gf cm/cm^2   = {GFCM_PER_CM2_TO_J_PER_M2:.6f} J/m^2")
    print(f"  1 gf cm^2/cm   = {GFCM2_PER_CM_TO_NM:.5e} N m")
    print(f"  1 gf cm/cm     = {GFCM_PER_CM_TO_N:.8f} N m/m")
    print(f"  1 gf/(cm deg)  = {GF_PER_CM_DEG_TO_N_PER_M_RAD!r} N/m per rad")
    print(f"  1 mg/cm^2      = {MG_PER_CM2_TO_KG_PER_M2:g} kg/m^2")
    assert abs(GF_PER_CM_TO_N_PER_M - 0.980665) < 1e-15
    assert abs(GFCM2_PER_CM_TO_NM - 9.80665e-5) < 1e-18
    assert abs(GF_PER_CM_DEG_TO_N_PER_M_RAD - 56.18796561619688) < 1e-10

    lo, hi = (p / STRIP_WIDTH_M for p in LOADS_N)
    print(f"\nValidation load range: {lo:.1f}-{hi:.1f} N/m = {lo / GF_PER_CM_TO_N_PER_M:.2f}-"
          f"{hi / GF_PER_CM_TO_N_PER_M:.2f} gf/cm = {100 * lo / GF_PER_CM_TO_N_PER_M / FM_GF_PER_CM:.1f}-"
          f"{100 * hi / GF_PER_CM_TO_N_PER_M / FM_GF_PER_CM:.1f} % of Fm")

    f_top = hi / GF_PER_CM_TO_N_PER_M          # 12.24 gf/cm
    print("\nKumari & Khurana 2016 denims (direction not stated by the source):")
    print("  sample | WT printed | 2.5 LT EMT | n (power) | b (exp) | strain at 12.2 gf/cm: power / exp"
          " | secant at Fm N/m | G N/m/rad | B N m")
    for name, (emt, lt, wt, b_kes, g_kes, _smd, _t) in KUMARI_2016.items():
        n, _, strain_pow = power_law(emt, lt)
        (_, b), _, strain_exp = exponential(emt, lt)
        wt_identity = 2.5 * lt * emt
        flag = "" if abs(wt - wt_identity) < 0.03 * wt_identity else "  <- misprint"
        print(f"  {name} | {wt:6.3f} | {wt_identity:6.2f}{flag} | {n:5.3f} | {b:5.1f} | "
              f"{100 * strain_pow(f_top):.3f} % / {100 * strain_exp(f_top):.3f} % | "
              f"{FM_GF_PER_CM * GF_PER_CM_TO_N_PER_M / (emt / 100):7.0f} | "
              f"{g_kes * GF_PER_CM_DEG_TO_N_PER_M_RAD:5.1f} | {b_kes * GFCM2_PER_CM_TO_NM:.2e}")

    # The worked example (sample B) that tests/textile/kumari2016_denim_test.cc checks.
    emt, lt = KUMARI_2016["B"][:2]
    n, force_pow, strain_pow = power_law(emt, lt)
    (a, b), force_exp, strain_exp = exponential(emt, lt)
    e_pow, e_exp = strain_pow(12.2), strain_exp(12.2)
    print(f"\nWorked example, sample B (EMT {emt} %, LT {lt}) at 12.2 gf/cm:")
    print(f"  power law   n = {n:.3f}: strain {100 * e_pow:.3f} % = {1000 * e_pow * STRIP_LENGTH_M:.2f} mm on 38 cm")
    print(f"  exponential b = {b:.1f}: strain {100 * e_exp:.3f} % = {1000 * e_exp * STRIP_LENGTH_M:.2f} mm on 38 cm")
    assert round(n, 2) == 2.05 and round(100 * e_pow, 2) == 0.94 and round(1000 * e_pow * STRIP_LENGTH_M, 1) == 3.6
    assert round(b, 1) == 39.0 and round(100 * e_exp, 2) == 0.48 and round(1000 * e_exp * STRIP_LENGTH_M, 1) == 1.8
    # Both curves reproduce EMT (F(em) = Fm) and LT (WT / (Fm em / 2)).
    em = emt / 100.0
    for force in (force_pow, force_exp):
        assert abs(force(em) - FM_GF_PER_CM) < 1e-6 * FM_GF_PER_CM
        steps = 20000
        wt = sum(force((i + 0.5) * em / steps) for i in range(steps)) * em / steps
        assert abs(wt / (FM_GF_PER_CM * em / 2) - lt) < 1e-4
    print("  both reproduce EMT and LT; they differ by "
          f"{e_pow / e_exp:.1f}x in strain at this load")


if __name__ == "__main__":
    main()
