#!/usr/bin/env python3
"""Writes the render-test scenes of the thin lens (standard library only).

usage: make_camera_scenes.py OUT_DIR

Each has an analytic criterion, stated beside its test in tests/render/CMakeLists.txt. A perspective camera at
z = 2 looks down -Z (yfov 0.7 rad) at black emitters (base colour 0, so nothing but emission reaches the film):
  lens_wall.gltf     an emitter of radiance 1 filling the view at z = 0: every pixel reads 1 through any aperture
                     focused anywhere (every ray from the lens meets the same radiance; no vignetting term).
  lens_checker.gltf  an 8 x 8 checker of emitters (radiance 1 and 0, cells 0.25 wide) at z = 0, 2 units ahead: in
                     focus (focus distance 2) a lens images it as the pinhole does.
  lens_point.gltf    a 0.15 x 0.15 emitter at z = -6, 8 units ahead: out of focus it spreads into the aperture's
                     shape, of the thin-lens diameter c = A |d - s| / (d s) x H / (2 tan(yfov / 2)) pixels.
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "stability" / "render"))
from make_stability_scenes import Gltf, quad  # noqa: E402

YFOV = 0.7
CAMERA_Z = 2.0


def scene_with(emitters):
    """emitters: [(triangles, radiance)], each a black-based emitter; the camera as the module says."""
    g = Gltf()
    for triangles, radiance in emitters:
        material = g.add_material(base=(0.0, 0.0, 0.0), emission=radiance)
        g.add_node({"mesh": g.add_mesh(triangles, material)})
    g.add_perspective_camera({"translation": [0.0, 0.0, CAMERA_Z]}, YFOV)
    return g


def checker():
    cells = ([], [])  # dark, lit: the dark cells are black surfaces, so --focus-on finds them too
    for i in range(8):
        for j in range(8):
            x0, y0 = -1.0 + 0.25 * i, -1.0 + 0.25 * j
            cells[(i + j) % 2 == 0].extend(quad(x0, y0, x0 + 0.25, y0 + 0.25, 0.0))
    return scene_with([(cells[0], 0.0), (cells[1], 1.0)])


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    scenes = {
        "lens_wall": scene_with([(quad(-100.0, -100.0, 100.0, 100.0, 0.0), 1.0)]),
        "lens_checker": checker(),
        "lens_point": scene_with([(quad(-0.075, -0.075, 0.075, 0.075, -6.0), 1.0)]),
    }
    for name, g in scenes.items():
        g.write(out / f"{name}.gltf")


if __name__ == "__main__":
    main()
