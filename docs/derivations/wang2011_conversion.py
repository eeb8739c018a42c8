#!/usr/bin/env python3
"""Wang, O'Brien, Ramamoorthi 2011 cloth measurements as KES-unit fabric files (docs/physics-reference.md
section 1.3).

Run: python3 docs/derivations/wang2011_conversion.py [--check data/fabrics]
The raw numbers are the zero-strain entries of the ARCSim material files (materials/*.json) that ship
the paper's data: per material the areal density, the first stretching row (c11, c12, c22, c33) and
the bending stiffness at zero curvature of the three bending rows (0, 45 and 90 deg to the material u
axis). Reading of ARCSim (docs/physics-reference.md section 1.3): tensile stiffness k_u = 2 c11,
k_v = 2 c22 [N/m]; shear modulus G = c33 / 2 [N/m per rad]; bending rigidity B = ke / 4 [N m].

Prints the conversion table. With --check DIR it also derives, from the table's printed (rounded)
values, each fabric file's numbers (the loading-curve point at 5 % strain, G, both B, W) and compares
them with DIR/wang2011_*.textproto; exit status 1 on a mismatch. Standard library only.
"""
import os
import re
import sys

GF_PER_CM_TO_N_PER_M = 0.980665
GF_PER_CM_DEG_TO_N_PER_M_RAD = 56.188      # rounded, as the fabric files' notes state
GFCM2_PER_CM_TO_NM = 9.80665e-5
CURVE_STRAIN = 0.05                        # the files' second loading-curve point

# material: (file name, rho_A kg/m^2, (c11, c12, c22, c33), ke at 0 / 45 / 90 deg)
MATERIALS = {
    "ivory-rib-knit": ("wang2011_ivory_rib_knit", 0.276,
                       (42.871021, -0.234556, 65.166023, 83.175644), (46.237591e-6, 30.015930e-6, 32.243889e-6)),
    "pink-ribbon-brown": ("wang2011_pink_ribbon_brown", 0.228,
                          (151.503906, 106.028160, 244.830673, 30.250183), (117.070122e-6, 87.509773e-6, 59.774277e-6)),
    "white-dots-on-blk": ("wang2011_white_dots_on_blk", 0.128,
                          (2002.08618, 0.345588, 2027.48559, 19.189022), (51.713814e-6, 40.659470e-6, 31.282822e-6)),
    "navy-sparkle-sweat": ("wang2011_navy_sparkle_sweat", 0.224,
                           (12.486332, -19.875324, 3.272434, 17.616289), (59.469658e-6, 40.072277e-6, 45.625023e-6)),
    "camel-ponte-roma": ("wang2011_camel_ponte_roma", 0.284,
                         (31.146198, -12.802702, 44.028667, 31.896357), (36.348366e-6, 33.013252e-6, 37.157593e-6)),
    "gray-interlock": ("wang2011_gray_interlock", 0.187,
                       (16.593832, -14.695990, 34.477123, 36.860302), (23.191698e-6, 24.749964e-6, 14.267624e-6)),
    "11oz-black-denim": ("wang2011_black_denim_11oz", 0.324,
                         (205.352005, 10.234077, 1013.88629, 53.387184), (64.196457e-6, 73.384567e-6, 96.951576e-6)),
    "white-swim-solid": ("wang2011_white_swim_solid", 0.204,
                         (47.971176, 6.834521, 104.615456, 60.773663), (60.237942e-6, 58.803211e-6, 51.018833e-6)),
    "tango-red-jet-set": ("wang2011_tango_red_jet_set", 0.113,
                          (43.067627, 54.373299, 171.424835, 14.314700), (14.293814e-6, 21.951700e-6, 20.345654e-6)),
    "royal-target": ("wang2011_royal_target", 0.220,
                     (2016.55456, 9.170511, 2034.97644, 104.759674), (125.409805e-6, 107.997696e-6, 125.409805e-6)),
}


def printed(material):
    """The table's values as printed: k in whole N/m, G to 0.1 N/m per rad, ke to 0.1e-6."""
    _, rho, (c11, _, c22, c33), ke = MATERIALS[material]
    return rho, round(2 * c11), round(2 * c22), round(c33 / 2, 1), tuple(round(k * 1e6, 1) for k in ke)


def file_values(material):
    """The numbers a fabric file holds, derived from the printed table values."""
    rho, k_u, k_v, g, ke = printed(material)
    to_b = lambda k: k * 1e-6 / 4 / GFCM2_PER_CM_TO_NM  # noqa: E731
    return {
        "warp_tensile.loading_curve[1].y": k_u * CURVE_STRAIN / GF_PER_CM_TO_N_PER_M,
        "weft_tensile.loading_curve[1].y": k_v * CURVE_STRAIN / GF_PER_CM_TO_N_PER_M,
        "shear.g_gf_per_cm_deg": g / GF_PER_CM_DEG_TO_N_PER_M_RAD,
        "warp_bending.b_gfcm2_per_cm": to_b(ke[0]),
        "weft_bending.b_gfcm2_per_cm": to_b(ke[2]),
        "weight_mg_per_cm2": rho * 100,
    }


def read_fabric_file(path):
    """The few fields above from a text-format haptex.v1.Fabric (enough for these flat files)."""
    text = open(path, encoding="utf-8").read()
    text = re.sub(r"#[^\n]*", "", text)
    out = {}
    for block in ("warp_tensile", "weft_tensile"):
        body = re.search(block + r"\s*\{(.*?)\n\}", text, re.S).group(1)
        ys = [float(y) for y in re.findall(r"loading_curve\s*\{\s*x:\s*[-0-9.e]+\s+y:\s*([-0-9.e]+)", body)]
        out[block + ".loading_curve[1].y"] = ys[1]
    out["shear.g_gf_per_cm_deg"] = float(re.search(r"g_gf_per_cm_deg:\s*([-0-9.e]+)", text).group(1))
    for block in ("warp_bending", "weft_bending"):
        body = re.search(block + r"\s*\{(.*?)\}", text, re.S).group(1)
        out[block + ".b_gfcm2_per_cm"] = float(re.search(r"b_gfcm2_per_cm:\s*([-0-9.e]+)", body).group(1))
    out["weight_mg_per_cm2"] = float(re.search(r"\nweight_mg_per_cm2:\s*([-0-9.e]+)", text).group(1))
    return out


def main(argv):
    print("| material | rho_A kg/m^2 | k_u0 N/m | k_v0 N/m | G0 N/m per rad (gf/(cm deg)) "
          "| ke x 1e-6 at 0/45/90 deg | B = ke/4 at 0/45/90 deg (gf cm^2/cm) |")
    for material in MATERIALS:
        rho, k_u, k_v, g, ke = printed(material)
        b = "/".join(f"{k * 1e-6 / 4 / GFCM2_PER_CM_TO_NM:.3f}" for k in ke)
        print(f"| {material} | {rho:.3f} | {k_u} | {k_v} | {g:.1f} ({g / GF_PER_CM_DEG_TO_N_PER_M_RAD:.2f}) "
              f"| {ke[0]:.1f}/{ke[1]:.1f}/{ke[2]:.1f} | {b} |")
    if len(argv) == 3 and argv[1] == "--check":
        bad = 0
        for material, (name, *_rest) in MATERIALS.items():
            stored = read_fabric_file(os.path.join(argv[2], name + ".textproto"))
            for field, value in file_values(material).items():
                if abs(stored[field] - value) > 1e-5 * abs(value):
                    print(f"{name}: {field} is {stored[field]}, the conversion gives {value:.6g}")
                    bad += 1
        print(f"checked {len(MATERIALS)} fabric files: " + ("all match" if bad == 0 else f"{bad} mismatches"))
        return 1 if bad else 0
    if len(argv) > 1:
        print(__doc__)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
