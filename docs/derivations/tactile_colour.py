#!/usr/bin/env python3
"""Threshold tables, tactile-colour matching and the demo denim's surface (docs/tactile.md sections
1, 3 and 6).

Run: python3 docs/derivations/tactile_colour.py
1. The default detection thresholds of libs/tactile (dB re 1 um peak, piecewise linear over log2 f)
   at the two primaries.
2. Worked examples of matching: a pin's excitation in each channel is the energy sum of its spectral
   lines in threshold units, E_c = sqrt(sum (a_n / T_c(f_n))^2); the primaries' amplitudes
   (A40, A320) solve E_c^2 = (A40 / T_c(40))^2 + (A320 / T_c(320))^2 for both channels, a linear
   system in the squares; a negative square is out of gamut (that primary 0, the other matches its
   own channel). The "naive" mapping A40 = E_RA T_RA(40), A320 = E_PC T_PC(320) is shown beside it.
3. The demo scene's denim surface: thread pitches from threads per inch, yarn diameter from the
   cotton count.
Asserts the figures that docs and tests quote. Standard library only.
"""
import math

RA_TABLE = [(10, 18), (20, 13), (40, 10), (80, 13), (160, 20), (320, 28), (640, 36)]
PC_TABLE = [(10, 36), (20, 24), (40, 12), (80, 1), (160, -8), (250, -10), (320, -9), (640, 0)]


def threshold_um(table, f):
    """Piecewise linear in dB over log2 f, extended linearly beyond both ends."""
    i = 0
    while i < len(table) - 2 and f > table[i + 1][0]:
        i += 1
    (f0, d0), (f1, d1) = table[i], table[i + 1]
    t = (math.log2(f) - math.log2(f0)) / (math.log2(f1) - math.log2(f0))
    return 10.0 ** ((d0 + t * (d1 - d0)) / 20.0)


def excitations(lines):
    """(E_RA, E_PC) of spectral lines [(f Hz, amplitude um peak)]."""
    return tuple(math.sqrt(sum((a / threshold_um(tab, f)) ** 2 for f, a in lines)) for tab in (RA_TABLE, PC_TABLE))


def match(e_ra, e_pc):
    """(A40, A320, out_of_gamut) reproducing both excitations with the two primaries."""
    w = [[1 / threshold_um(tab, f) ** 2 for f in (40, 320)] for tab in (RA_TABLE, PC_TABLE)]
    det = w[0][0] * w[1][1] - w[0][1] * w[1][0]
    x = (e_ra ** 2 * w[1][1] - e_pc ** 2 * w[0][1]) / det      # A40^2
    y = (e_pc ** 2 * w[0][0] - e_ra ** 2 * w[1][0]) / det      # A320^2
    if x < 0:
        return 0.0, e_pc * threshold_um(PC_TABLE, 320), True
    if y < 0:
        return e_ra * threshold_um(RA_TABLE, 40), 0.0, True
    return math.sqrt(x), math.sqrt(y), False


def main():
    t = {(name, f): threshold_um(tab, f) for name, tab in (("RA", RA_TABLE), ("PC", PC_TABLE)) for f in (40, 320)}
    print("thresholds [um peak]: " + ", ".join(f"T_{c}({f}) = {v:.3g}" for (c, f), v in t.items()))
    assert [round(t[k], 3) for k in (("RA", 40), ("PC", 40), ("PC", 320))] == [3.162, 3.981, 0.355]
    assert round(t[("RA", 320)], 1) == 25.1

    cases = [
        ("grating 0.5 mm, 5 um, 100 mm/s (200 Hz)", [(100 / 0.5, 5.0)]),
        ("grating 1.0 mm, 20 um, 40 mm/s (40 Hz)", [(40 / 1.0, 20.0)]),
        ("grating 0.25 mm, 2 um, 80 mm/s (320 Hz)", [(80 / 0.25, 2.0)]),
        ("40 Hz 10 um + 320 Hz 1 um", [(40, 10.0), (320, 1.0)]),
    ]
    print("\ninput (one pin) | E_RA | E_PC | matched A40 / A320 [um] | naive A40 / A320 [um]")
    results = []
    for name, lines in cases:
        e_ra, e_pc = excitations(lines)
        a40, a320, out = match(e_ra, e_pc)
        naive = (e_ra * t[("RA", 40)], e_pc * t[("PC", 320)])
        results.append((e_ra, e_pc, a40, a320))
        print(f"{name} | {e_ra:.2f} | {e_pc:.2f} | {a40:.2f} / {a320:.2f}{' (out of gamut)' if out else ''} | "
              f"{naive[0]:.2f} / {naive[1]:.2f}")
    assert [round(v, 2) for v in results[0]] == [0.37, 14.09, 0.99, 5.00]
    assert [round(v, 2) for v in results[3]] == [3.16, 3.78, 10.00, 1.00]

    # The demo's denim (launch/scenes/demo.textproto): 60 x 40 threads per inch, 6.5 Ne warp.
    warp_pitch, weft_pitch = 25.4 / 60, 25.4 / 40
    tex = 590.5 / 6.5                    # English cotton count Ne -> tex (g per km)
    rho_yarn = 0.85                      # g/cm^3, spun cotton 0.8-0.9
    d_mm = math.sqrt(4 * tex * 1e-3 / (math.pi * rho_yarn))   # circular section of the yarn's mass
    print(f"\ndemo denim: pitches {warp_pitch:.4f} / {weft_pitch:.3f} mm; warp {tex:.1f} tex, "
          f"diameter sqrt(4 tex / (pi rho)) = {d_mm:.3f} mm (= 0.0357 sqrt(tex / rho) mm)")
    assert round(warp_pitch, 4) == 0.4233 and round(weft_pitch, 3) == 0.635 and round(d_mm, 3) == 0.369


if __name__ == "__main__":
    main()
