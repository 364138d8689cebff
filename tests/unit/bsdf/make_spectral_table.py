#!/usr/bin/env python3
"""Generates shaders/lib/tables/spectral_table.glsl: what the spectral path (EFFECT_SPECTRAL) needs per wavelength.

- Three basis spectra B_r, B_g, B_b (a linear RGB -> spectrum upsampling in the spirit of Mallett & Yuksel 2019,
  "Spectral Primary Decomposition for Rendering with sRGB Reflectance"): the spectrum of a linear Rec.709 colour c
  is c.r B_r + c.g B_g + c.b B_b. The basis sums to 1 at every wavelength (white is the constant spectrum 1) and
  lies in [0, 1] (a reflectance in [0, 1]^3 stays a reflectance at every wavelength), and each B_i seen by the film
  under D65 is exactly primary i. Being linear, the upsampling commutes with the BSDF's linear mix of colours.
- The film's weights W_r, W_g, W_b: linear Rec.709 of a unit of spectral radiance at each wavelength, for light
  whose emitter is D65-white: W = M_XYZ->Rec.709 * cmf(lambda) * D65(lambda) / int(ybar D65), scaled so that
  int W = (1, 1, 1) exactly (the constant spectrum 1 renders white).

Every function is piecewise linear between the nodes 360, 365, ..., 830 nm (as the shader interpolates them), and
the round trip int W_c B_i = delta_ci is imposed on the exact integral of those interpolants, so that a film
that samples wavelengths from any pdf returns an RGB colour unchanged in expectation (tests/unit/test_spectral_table.cpp
checks all of this).

Data: CIE 1931 2-degree colour-matching functions and CIE D65 from the colour-science package (D65 held at its
780 nm value beyond 780 nm, where ybar is below 1e-4 of its peak). Run:
    python3 -m venv /tmp/v && /tmp/v/bin/pip install numpy scipy colour-science
    /tmp/v/bin/python tests/unit/bsdf/make_spectral_table.py shaders/lib/tables/spectral_table.glsl
"""
import sys
import warnings

import numpy as np
from scipy.optimize import minimize

warnings.filterwarnings("ignore")
import colour  # noqa: E402

LAMBDA_MIN, LAMBDA_STEP, NODES = 360.0, 5.0, 95  # 360 ... 830 nm
lam = LAMBDA_MIN + LAMBDA_STEP * np.arange(NODES)


def product_weights(w):
    """q such that int lerp(w) lerp(b) = q . b for functions sampled at the nodes (exact for linear pieces)."""
    h = LAMBDA_STEP
    q = np.zeros(NODES)
    q[:-1] += h / 6.0 * (2.0 * w[:-1] + w[1:])
    q[1:] += h / 6.0 * (w[:-1] + 2.0 * w[1:])
    return q


def integrate(w):
    return product_weights(w).sum()


def make_film_weights():
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    xyz = np.array([cmfs[l] for l in lam])  # (NODES, 3)
    d65_sd = colour.SDS_ILLUMINANTS["D65"]
    d65 = np.array([d65_sd[min(l, 780.0)] for l in lam])
    m = np.array(colour.models.RGB_COLOURSPACE_sRGB.matrix_XYZ_to_RGB)
    rgb = (xyz * d65[:, None]) @ m.T / integrate(xyz[:, 1] * d65)
    white = np.array([integrate(rgb[:, c]) for c in range(3)])
    print(f"film white before balancing: {white} (1 would be exact)", file=sys.stderr)
    return rgb / white


def make_basis(w):
    q = np.array([product_weights(w[:, c]) for c in range(3)])  # (3, NODES)
    # Unknowns: B_r and B_g at each node; B_b = 1 - B_r - B_g.
    def unpack(x):
        r, g = x[:NODES], x[NODES:]
        return np.stack([r, g, 1.0 - r - g], axis=1)

    # Smoothness: squared second differences (curvature), as the upsampled spectra of natural reflectances are.
    d2 = np.diff(np.eye(NODES), 2, axis=0)
    smooth = d2.T @ d2

    def objective(x):
        b = unpack(x)
        return sum(b[:, i] @ smooth @ b[:, i] for i in range(3))

    def gradient(x):
        b = unpack(x)
        g = np.array([2.0 * smooth @ b[:, i] for i in range(3)])
        return np.concatenate([g[0] - g[2], g[1] - g[2]])

    constraints = []
    for c in range(3):
        for i in range(2):  # the third primary follows from int W_c = 1
            a = np.zeros(2 * NODES)
            if i == 0:
                a[:NODES] = q[c]
            else:
                a[NODES:] = q[c]
            target = (1.0 if c == i else 0.0)
            # int W_c B_i = delta_ci, with B_b = 1 - B_r - B_g handled by the remaining equation below.
            constraints.append({"type": "eq", "fun": lambda x, a=a, t=target: a @ x - t, "jac": lambda x, a=a: a})
    # 0 <= B_b = 1 - B_r - B_g.
    ones = np.concatenate([np.eye(NODES), np.eye(NODES)], axis=1)
    constraints.append({"type": "ineq", "fun": lambda x: 1.0 - ones @ x, "jac": lambda x: -ones})
    x0 = np.full(2 * NODES, 1.0 / 3.0)
    result = minimize(objective, x0, jac=gradient, bounds=[(0.0, 1.0)] * (2 * NODES), constraints=constraints,
                      method="SLSQP", options={"maxiter": 2000, "ftol": 1e-15})
    if not result.success:
        raise SystemExit(f"basis optimisation failed: {result.message}")
    b = np.clip(unpack(result.x), 0.0, 1.0)
    b[:, 2] = 1.0 - b[:, 0] - b[:, 1]
    roundtrip = np.array([[q[c] @ b[:, i] for i in range(3)] for c in range(3)])
    print(f"round trip (3x3, identity wanted):\n{roundtrip}", file=sys.stderr)
    return b


def write_table(path, basis, film):
    rows = []
    for n in range(NODES):
        rows.append("    " + ", ".join(f"{v:.9e}f" for v in (*basis[n], 0.0, *film[n], 0.0)) + ",")
    text = f"""// GENERATED by tests/unit/bsdf/make_spectral_table.py: do not edit.
// Per wavelength node lambda = {LAMBDA_MIN:g} + {LAMBDA_STEP:g} n nm (n < {NODES}), two vec4s: the RGB -> spectrum basis
// (B_r, B_g, B_b, 0), then the film's linear Rec.709 weight of a unit of spectral radiance (W_r, W_g, W_b, 0),
// both linear between nodes (see the script for how they are made and tests/unit/test_spectral_table.cpp).
#ifndef FH_SPECTRAL_TABLE_GLSL
#define FH_SPECTRAL_TABLE_GLSL

// The values are C++ only: the host appends them to the albedo tables' uniform buffer
// (BINDING_GGX_ALBEDO_UNIFORM), which spectrum.glsl reads through spectral_node().
const float SPECTRAL_LAMBDA_MIN = {LAMBDA_MIN:.1f}f;
const float SPECTRAL_LAMBDA_STEP = {LAMBDA_STEP:.1f}f;
const int SPECTRAL_NODE_COUNT = {NODES};
const int SPECTRAL_TABLE_SIZE = {NODES * 8};  // floats; a multiple of 4 (std140 vec4 packing)

#ifdef __cplusplus
const float SPECTRAL_TABLE[{NODES * 8}] = {{
{chr(10).join(rows)}
}};
#endif

#endif
"""
    with open(path, "w") as f:
        f.write(text)


def main():
    if len(sys.argv) != 2:
        raise SystemExit("usage: make_spectral_table.py OUT.glsl")
    film = make_film_weights()
    basis = make_basis(film)
    print(f"basis range [{basis.min():.3g}, {basis.max():.3g}]", file=sys.stderr)
    write_table(sys.argv[1], basis, film)


if __name__ == "__main__":
    main()
