#!/usr/bin/env python3
"""The heavy elastica: a strip bending under its own weight (docs/physics-reference.md section 4.2).

Run: python3 docs/derivations/heavy_elastica.py
An inextensible strip of overhang l, weight w per area and bending rigidity B per width, clamped
horizontally at s = 0 and free at s = l, with the moment M = B kappa. The moment at s carries the
weight beyond s; differentiating once, with t = s / l and theta the slope angle below horizontal:

    theta''(t) = -lambda (1 - t) cos(theta(t)),   theta(0) = 0,   theta'(1) = 0,   lambda = w l^3 / B

solved by shooting on theta'(0) with a fixed-step fourth-order Runge-Kutta integration, which also
carries the tip position (x' = cos theta, y' = sin theta). Prints the chord angle (clamp edge to tip)
against lambda, the lambda of Peirce's 41.5 deg, and the small-deflection check y/l = lambda / 8.
Standard library only.
"""
import math


def _rates(t, state, lam):
    theta, kappa, _, _ = state
    return (kappa, -lam * (1.0 - t) * math.cos(theta), math.cos(theta), math.sin(theta))


def integrate(lam, clamp_curvature, steps):
    """(theta, theta', x, y) at the tip, lengths in units of l."""
    state = (0.0, clamp_curvature, 0.0, 0.0)
    h = 1.0 / steps
    for i in range(steps):
        t = i * h
        k1 = _rates(t, state, lam)
        k2 = _rates(t + h / 2, tuple(s + h / 2 * k for s, k in zip(state, k1)), lam)
        k3 = _rates(t + h / 2, tuple(s + h / 2 * k for s, k in zip(state, k2)), lam)
        k4 = _rates(t + h, tuple(s + h * k for s, k in zip(state, k3)), lam)
        state = tuple(s + h / 6 * (a + 2 * b + 2 * c + d) for s, a, b, c, d in zip(state, k1, k2, k3, k4))
    return state


def solve(lam, steps=4000):
    """Clamp curvature (times l) with a moment-free tip, and the chord angle in degrees."""
    # theta'(0) = lambda * integral of (1 - t) cos(theta) lies in [0, lambda / 2]; theta'(1) grows with it.
    lo, hi = 0.0, lam / 2
    for _ in range(48):
        mid = 0.5 * (lo + hi)
        if integrate(lam, mid, 400)[1] > 0.0:
            hi = mid
        else:
            lo = mid
    k0 = 0.5 * (lo + hi)
    theta, _, x, y = integrate(lam, k0, steps)
    return k0, theta, x, y, math.degrees(math.atan2(y, x))


def lambda_for_chord(angle_deg):
    lo, hi = 1.0, 30.0
    for _ in range(30):
        mid = 0.5 * (lo + hi)
        if solve(mid, 2000)[4] < angle_deg:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def main():
    print("lambda = w l^3 / B | chord angle [deg] | tip slope [deg] | tip x/l | tip y/l")
    table = {}
    for lam in (1, 2, 4, 6, 8, 10, 16, 30):
        _, theta, x, y, chord = solve(lam)
        table[lam] = chord
        print(f"{lam:5d} | {chord:6.2f} | {math.degrees(theta):6.2f} | {x:.4f} | {y:.4f}")
    lam = lambda_for_chord(41.5)
    print(f"\nchord at 41.5 deg: lambda = {lam:.3f}, so l = {lam ** (1 / 3):.4f} (B / w)^(1/3);"
          " Peirce: l = 2 c, c = (B / w)^(1/3), lambda = 8")
    y_small = solve(0.05)[3]
    print(f"small deflection, lambda = 0.05: tip y/l = {y_small:.6f}, linear theory lambda / 8 = {0.05 / 8:.6f}")
    assert abs(table[8] - 41.49) < 0.005
    assert abs(lam - 8.004) < 0.002
    assert abs(lam ** (1 / 3) / 2 - 1) < 2.5e-4          # Peirce's l = 2c within 0.02 %
    assert abs(y_small / (0.05 / 8) - 1) < 0.01


if __name__ == "__main__":
    main()
