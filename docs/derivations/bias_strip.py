#!/usr/bin/env python3
"""Stiffness of a strip cut at an angle to the warp, at small strain (docs/fabric-model.md
section 4, the material angle; tests/textile/validation_bias_strip_test.cc).

Run: python3 docs/derivations/bias_strip.py

The model's measures, per triangle, with U and V the deformed warp and weft vectors (unit at rest):
  warp strain  e_1 = |U| - 1,  weft strain  e_2 = |V| - 1,  shear  gamma = U . V.
To first order in the displacement gradient, with the small-strain tensor eps in the material
frame (1 = warp, 2 = weft):
  e_1 = eps_11,  e_2 = eps_22,  gamma = U.V = cos(angle between the yarns) = 2 eps_12,
so gamma is the engineering shear strain: the change of the warp/weft angle in radians, which is
also what KES's G is measured against (force per width per radian of shear angle). The forces are
the gradients of the energy per area
  W = k_u e_1^2 / 2 + k_v e_2^2 / 2 + G gamma^2 / 2
(k_u, k_v: tensile stiffness per width at zero strain [N/m], G: shear stiffness per width per rad
at zero shear [N/m]). Its stresses per width are N_11 = k_u e_1, N_22 = k_v e_2 and the shear
N_12 = dW/dgamma = G gamma, so the compliance in engineering notation is diagonal:
  eps_11 = N_11 / k_u,  eps_22 = N_22 / k_v,  gamma = N_12 / G.

Uniaxial tension N per width along a direction at angle theta from the warp, nothing else (a free
strip: no clamp restrains its narrowing or shear): with c = cos theta, s = sin theta, the stress in
the material frame is N_11 = N c^2, N_22 = N s^2, N_12 = N c s. The strain along the load is
  eps_load = eps_11 c^2 + eps_22 s^2 + gamma c s = N (c^4 / k_u + s^4 / k_v + c^2 s^2 / G),
so the strip's stiffness per width is
  k(theta) = 1 / (c^4 / k_u + s^4 / k_v + c^2 s^2 / G),
and at 45 deg (c^2 = s^2 = 1/2)
  k45 = 4 / (1/k_u + 1/k_v + 1/G).
At 90 deg k = k_v: warp and weft swap. Had gamma been the tensor shear eps_12 (half the angle), the
last term would read 1/(4G) instead of 1/G; the code's gamma = U.V makes it 1/G.

This script checks the closed form against a direct evaluation of the same energy: it stretches a
material element along theta by a small strain, minimises W over the free lateral and shear
components of the displacement gradient (a free strip), and compares the force with k(theta).
Standard library only.
"""
import math

STRAIN = 1e-6  # small: the measures above are linear in it


def measures(F, theta_deg, along_deg=0.0):
    """Warp/weft strains and shear of a deformation gradient F (2 x 2, grid frame) for a fabric
    whose warp is at theta_deg from the grid's u axis."""
    t = math.radians(theta_deg)
    warp = (math.cos(t), math.sin(t))
    weft = (-math.sin(t), math.cos(t))
    U = (F[0][0] * warp[0] + F[0][1] * warp[1], F[1][0] * warp[0] + F[1][1] * warp[1])
    V = (F[0][0] * weft[0] + F[0][1] * weft[1], F[1][0] * weft[0] + F[1][1] * weft[1])
    return math.hypot(*U) - 1.0, math.hypot(*V) - 1.0, U[0] * V[0] + U[1] * V[1]


def energy(F, theta_deg, k_u, k_v, g):
    e1, e2, gamma = measures(F, theta_deg)
    return 0.5 * (k_u * e1 * e1 + k_v * e2 * e2 + g * gamma * gamma)


def free_strip_stiffness(theta_deg, k_u, k_v, g):
    """Stretch along u by STRAIN; the lateral strain b and shear q of F = [[1+e, q], [0, 1+b]] are
    free (a rigid rotation is removed by F[1][0] = 0). W is quadratic in (b, q) to first order:
    minimise it by Newton with finite differences, then k = dW/de / e."""
    e = STRAIN
    x = [0.0, 0.0]  # b, q
    h = 1e-4 * e

    def w(b, q, ee=e):
        return energy([[1.0 + ee, q], [0.0, 1.0 + b]], theta_deg, k_u, k_v, g)

    for _ in range(20):
        b, q = x
        gb = (w(b + h, q) - w(b - h, q)) / (2 * h)
        gq = (w(b, q + h) - w(b, q - h)) / (2 * h)
        hbb = (w(b + h, q) - 2 * w(b, q) + w(b - h, q)) / h ** 2
        hqq = (w(b, q + h) - 2 * w(b, q) + w(b, q - h)) / h ** 2
        hbq = (w(b + h, q + h) - w(b + h, q - h) - w(b - h, q + h) + w(b - h, q - h)) / (4 * h * h)
        det = hbb * hqq - hbq * hbq
        x = [b - (hqq * gb - hbq * gq) / det, q - (hbb * gq - hbq * gb) / det]
    b, q = x
    force = (w(b, q, e + h) - w(b, q, e - h)) / (2 * h)  # N per width (energy per area / strain)
    return force / e


def closed_form(theta_deg, k_u, k_v, g):
    c, s = math.cos(math.radians(theta_deg)), math.sin(math.radians(theta_deg))
    return 1.0 / (c ** 4 / k_u + s ** 4 / k_v + c * c * s * s / g)


def main():
    # Wang et al.'s 11 oz denim as libs/textile reads data/fabrics/wang2011_black_denim_11oz
    # (20.9552 and 103.399 gf/cm at 5 %, G 0.475191 gf/(cm deg)); the test uses the same fabric.
    denim = (20.9552 * 0.980665 / 0.05, 103.399 * 0.980665 / 0.05, 0.475191 * 56.18796561619688)
    cases = [("11 oz denim", *denim),
             ("balanced, k 1000, G 1000", 1000.0, 1000.0, 1000.0)]
    for name, k_u, k_v, g in cases:
        for theta in (0.0, 30.0, 45.0, -45.0, 90.0):
            direct = free_strip_stiffness(theta, k_u, k_v, g)
            formula = closed_form(theta, k_u, k_v, g)
            print(f"{name}: theta {theta:6.1f} deg  energy minimum {direct:10.4f} N/m  "
                  f"closed form {formula:10.4f} N/m")
            assert abs(direct / formula - 1.0) < 1e-3, (name, theta, direct, formula)
        k45 = 4.0 / (1.0 / k_u + 1.0 / k_v + 1.0 / g)
        assert abs(closed_form(45.0, k_u, k_v, g) / k45 - 1.0) < 1e-12
        assert abs(closed_form(90.0, k_u, k_v, g) / k_v - 1.0) < 1e-12
        print(f"{name}: k45 = 4 / (1/k_u + 1/k_v + 1/G) = {k45:.4f} N/m")


if __name__ == "__main__":
    main()
