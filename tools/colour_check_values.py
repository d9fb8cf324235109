#!/usr/bin/env python3
"""Print check values for tests/spectrum_material/spectrum_colour.rs, computed with
colour-science (an implementation independent of spar's):

  - CIE XYZ (D65 white at Y = 1) of D65 times three analytic reflectances,
    integrated at 1 nm over 380-780 nm;
  - the D65 white point chromaticity by the 1 nm summation over 360-830 nm.

Run:  python3 tools/colour_check_values.py
"""

import warnings

import numpy as np

warnings.filterwarnings("ignore")
import colour  # noqa: E402

SHAPE = colour.SpectralShape(380, 780, 1)
CMFS = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"].copy().trim(SHAPE)
D65 = colour.SDS_ILLUMINANTS["D65"].copy().interpolate(colour.SpectralShape(300, 780, 1), interpolator=colour.LinearInterpolator).trim(SHAPE)

REFLECTANCES = {
    # name: function of wavelength in nm (the Rust test evaluates the same)
    "gauss_550_40": lambda l: np.exp(-(((l - 550.0) / 40.0) ** 2)),
    "ramp_up": lambda l: (l - 380.0) / 400.0,
    "blue_step": lambda l: np.where(l < 500.0, 0.9, 0.1),
}


def main():
    wl = np.arange(380, 781, 1.0)
    s = D65.values
    cmf = CMFS.values
    # Trapezoid weights (spar's 1 nm set has half weights at both ends).
    w = np.ones_like(wl)
    w[0] = w[-1] = 0.5
    k = 1.0 / np.sum(w * s * cmf[:, 1])
    for name, f in REFLECTANCES.items():
        r = f(wl)
        xyz = k * np.sum((w * s * r)[:, None] * cmf, axis=0)
        print(f"{name}: XYZ = [{xyz[0]:.12f}, {xyz[1]:.12f}, {xyz[2]:.12f}]")
        # Cross-check against colour's own integration (rectangle rule, k = 100).
        sd = colour.SpectralDistribution(dict(zip(wl, r)))
        xyz_c = colour.sd_to_XYZ(sd, CMFS, D65, method="Integration") / 100.0
        print(f"   colour.sd_to_XYZ / 100 = {xyz_c}")
    full = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    d65_full = colour.SDS_ILLUMINANTS["D65"].copy().align(full.shape, interpolator=colour.LinearInterpolator, extrapolator_kwargs={"method": "Constant", "left": None, "right": None})
    xyz = colour.sd_to_XYZ(d65_full, full, method="Integration")
    print("D65 xy (colour, 360-830 nm, D65 extrapolated past 780 nm):", colour.XYZ_to_xy(xyz))


if __name__ == "__main__":
    main()
