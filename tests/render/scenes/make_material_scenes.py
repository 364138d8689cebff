#!/usr/bin/env python3
"""Writes the render-test scenes for the KHR material extensions other than glass: KHR_materials_clearcoat,
KHR_materials_sheen, KHR_materials_diffuse_transmission, KHR_materials_anisotropy, KHR_materials_iridescence,
KHR_materials_unlit, KHR_materials_specular's textures and KHR_materials_pbrSpecularGlossiness (standard library only).

usage: make_material_scenes.py OUT_DIR

Rendered under a white environment of radiance 1 (--background 1,1,1) unless said otherwise; each has an analytic
criterion, stated beside its test in tests/render/CMakeLists.txt:
  coat_black_quad.gltf  a smooth clear coat (clearcoatFactor 1, roughness 0) over a black base without specular,
                        seen head-on by an orthographic camera: only the coat reflects, its Fresnel at normal
                        incidence ((1.5 - 1) / (1.5 + 1))^2 = 0.04.
  coat_furnace.gltf     a white dielectric sphere (roughness 0.5) under a clear coat of roughness 0.3, seen in
                        perspective: the coat and the base it lets through keep all the energy, so every pixel,
                        sphere and background alike, reads 1 (a white furnace).
  sheen_black_quad.gltf a white sheen of roughness 1 over a black base without specular (specularFactor 0), seen
                        head-on: only the sheen reflects, its directional albedo at normal incidence, 0.1638 (the
                        Charlie lobe integrated in double precision: tests/unit/bsdf/sheen_albedo_reference.h).
  diffuse_sheet.gltf    a sheet that transmits all of its diffuse lobe (diffuseTransmissionFactor 1, colour 0.6;
                        black base, no specular) seen head-on, over a large emitter of radiance 1 facing it, no
                        environment: the camera sees only light sent through, 0.6 x the emitter's share of the
                        cosine-weighted hemisphere below (0.99992 for a square 200 wide at distance 1).
  anisotropy_0.gltf, anisotropy_90.gltf
                        a white metal square (roughness 0.3) with anisotropyStrength 0.6 along its tangent (+x: the
                        texture's u) turned by anisotropyRotation 0 or pi/2, seen from above by an orthographic camera
                        under a point light 0.5 above its centre, no environment: the rougher direction
                        (alpha_t = 0.09 + 0.91 x 0.36 = 0.42 against alpha = 0.09) stretches the highlight along +x,
                        or along +y when turned.
  anisotropy_furnace.gltf
                        a large white metal quad (roughness 0.3, anisotropyStrength 1 along its tangent: alpha_t = 1)
                        seen in perspective from 1 above, 0 to about 50 degrees: with --microfacet compensated the
                        anisotropic table's lobe gives back what the stretched lobe loses, so every pixel reads 1 in
                        a white furnace; single scattering keeps about 0.53 head-on.
  isotropic_highlight.gltf
                        the same without anisotropy: a round highlight.
  film_black_quad.gltf  a smooth black dielectric (ior 1.5, f0 0.04, no diffuse) under a thin film of index 1.8,
                        300 nm thick (KHR_materials_iridescence, factor 1), seen head-on: the film's reflectance at
                        normal incidence, coloured by interference, (0.0949, 0.0432, 0.1217) in linear Rec.709 (the
                        extension's formula in double precision), where the bare base reflects a grey 0.04.
  metal_furnace_r30.gltf, metal_furnace_r100.gltf
                        a white metal sphere (metallic 1, roughness 0.3 or 1: the glTF default material), seen in
                        perspective: with --microfacet compensated it keeps all the energy, so every pixel reads 1
                        (a white furnace); the spec's single scattering keeps about 0.9 and 0.4 of it.
  specular_texture_quad.gltf
                        a smooth black dielectric of ior 0 (f0 = 1 before KHR_materials_specular) whose specularTexture
                        and specularColorTexture are one texel (255, 188, 0, 128), seen head-on: it reflects
                        f0 = specularColor x specular = (1, 0.50289, 0) x 128/255 = (0.50196, 0.25243, 0), the colour
                        decoded from sRGB and the factor read linear from alpha.
  gloss_quad.gltf       a KHR_materials_pbrSpecularGlossiness material (diffuse black, specularFactor (0.9, 0.6, 0.3),
                        glossiness 1) whose specularGlossinessTexture is one texel (255, 188, 0, 255), seen head-on:
                        a mirror of f0 = specular, (0.9, 0.6 x 0.50289, 0) = (0.9, 0.30173, 0).
  gloss_highlight_texture.gltf, gloss_highlight_factor.gltf
                        a white-specular, black-diffuse specular-glossiness square under a point light, as the
                        anisotropy scenes: glossiness 0.25 from the texture's alpha (64/255 with glossinessFactor 1)
                        or from glossinessFactor 64/255 without a texture; the same highlight (roughness 0.749).
  unlit_quad_animated.gltf
                        unlit_quad whose baseColorFactor KHR_animation_pointer animates from black at t = 0 to white at
                        t = 1 (LINEAR): at --time 0.25 every pixel reads 0.25.
  pointer_animated.gltf, pointer_static.gltf
                        a quad of base colour 0.25 -> 0.75 and emissive strength 1 -> 3 between t = 0 and 1, seen by a
                        camera of yfov 0.5 -> 0.75, all through KHR_animation_pointer; and the same file with the values
                        at t = 0.5 written in (base colour 0.5, strength 2, yfov 0.625; all exact in binary): at
                        --time 0.5 the two render the same bits.
  layer_furnace_r100.gltf
                        a black dielectric sphere (roughness 1) whose specular layer has f0 = 1 (KHR_materials_ior 0),
                        seen in perspective: with --microfacet compensated the layer's multiple-scattering lobe keeps
                        all the energy, as a white metal's does, so every pixel reads 1.
  unlit_quad.gltf       an unlit quad of base colour 0.5 (with an emissiveFactor of 1, which unlit ignores), seen
                        head-on: every camera ray sees exactly its base colour, 0.5, whatever lights the scene.
"""
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "stability" / "render"))
from make_stability_scenes import Gltf, icosphere, quad  # noqa: E402
from make_asset_scenes import AssetGltf, quad_uv  # noqa: E402


def coated(base, roughness, clearcoat, clearcoat_roughness, specular=1.0):
    return {"pbrMetallicRoughness": {"baseColorFactor": [*base, 1.0], "metallicFactor": 0.0,
                                     "roughnessFactor": roughness},
            "extensions": {"KHR_materials_specular": {"specularFactor": specular},
                           "KHR_materials_clearcoat": {"clearcoatFactor": clearcoat,
                                                       "clearcoatRoughnessFactor": clearcoat_roughness}}}


def mirror_layer(roughness):
    return {"pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0], "metallicFactor": 0.0,
                                     "roughnessFactor": roughness},
            "extensions": {"KHR_materials_ior": {"ior": 0.0}}}


def white_metal(roughness):
    return {"pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 1.0], "metallicFactor": 1.0,
                                     "roughnessFactor": roughness}}


def scene(material, shape, camera):
    g = Gltf()
    g.doc["extensionsUsed"] += ["KHR_materials_clearcoat", "KHR_materials_sheen", "KHR_materials_specular"]
    g.doc["materials"].append(material)
    g.add_node({"mesh": g.add_mesh(shape, 0)})
    camera(g)
    return g


def sheened(base, sheen_color, sheen_roughness, specular=1.0):
    return {"pbrMetallicRoughness": {"baseColorFactor": [*base, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.5},
            "extensions": {"KHR_materials_specular": {"specularFactor": specular},
                           "KHR_materials_sheen": {"sheenColorFactor": list(sheen_color),
                                                   "sheenRoughnessFactor": sheen_roughness}}}


def diffuse_sheet():
    g = Gltf()
    g.doc["extensionsUsed"] += ["KHR_materials_diffuse_transmission", "KHR_materials_specular"]
    g.doc["materials"].append({"pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0], "metallicFactor": 0.0},
                               "extensions": {"KHR_materials_specular": {"specularFactor": 0.0},
                                              "KHR_materials_diffuse_transmission": {
                                                  "diffuseTransmissionFactor": 1.0,
                                                  "diffuseTransmissionColorFactor": [0.6, 0.6, 0.6]}}})
    g.doc["materials"].append({"pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0]},
                               "emissiveFactor": [1.0, 1.0, 1.0]})
    g.add_node({"mesh": g.add_mesh(quad(-10, -10, 10, 10, 0.0), 0)})
    g.add_node({"mesh": g.add_mesh(quad(-100, -100, 100, 100, -1.0), 1)})
    g.add_orthographic_camera({"translation": [0.0, 0.0, 3.0]}, 1.0)
    return g


def highlight(strength, rotation):
    g = AssetGltf()
    g.doc["extensionsUsed"] += ["KHR_materials_anisotropy", "KHR_lights_punctual"]
    material = {"pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 1.0], "metallicFactor": 1.0,
                                         "roughnessFactor": 0.3}}
    if strength > 0.0:
        material["extensions"] = {"KHR_materials_anisotropy": {"anisotropyStrength": strength,
                                                               "anisotropyRotation": rotation}}
    g.add_raw_material(material)
    g.add_node({"mesh": g.add_uv_mesh(quad(-1, -1, 1, 1, 0.0), quad_uv(), 0)})
    g.add_light({"type": "point", "intensity": 1.0}, {"translation": [0.0, 0.0, 0.5]})
    g.add_orthographic_camera({"translation": [0.0, 0.0, 2.0]}, 1.0)
    return g


def anisotropy_furnace():
    g = AssetGltf()
    g.doc["extensionsUsed"] += ["KHR_materials_anisotropy"]
    g.add_raw_material({"pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 1.0], "metallicFactor": 1.0,
                                                 "roughnessFactor": 0.3},
                        "extensions": {"KHR_materials_anisotropy": {"anisotropyStrength": 1.0}}})
    g.add_node({"mesh": g.add_uv_mesh(quad(-20, -20, 20, 20, 0.0), quad_uv(), 0)})
    g.add_perspective_camera({"translation": [0.0, 0.0, 1.0]}, 1.4)
    return g


def film_black_quad():
    g = Gltf()
    g.doc["extensionsUsed"] += ["KHR_materials_iridescence"]
    g.doc["materials"].append({"pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0], "metallicFactor": 0.0,
                                                        "roughnessFactor": 0.0},
                               "extensions": {"KHR_materials_iridescence": {
                                   "iridescenceFactor": 1.0, "iridescenceIor": 1.8,
                                   "iridescenceThicknessMaximum": 300.0}}})
    g.add_node({"mesh": g.add_mesh(quad(-10, -10, 10, 10, 0.0), 0)})
    g.add_orthographic_camera({"translation": [0.0, 0.0, 3.0]}, 1.0)
    return g


SPECULAR_TEXEL = (255, 188, 0, 128)  # sRGB 188: linear 0.50289


def specular_texture_quad():
    g = AssetGltf()
    g.doc["extensionsUsed"] += ["KHR_materials_specular", "KHR_materials_ior"]
    texture = g.add_texture(1, 1, [SPECULAR_TEXEL])
    g.add_raw_material({"pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0], "metallicFactor": 0.0,
                                                 "roughnessFactor": 0.0},
                        "extensions": {"KHR_materials_ior": {"ior": 0.0},
                                       "KHR_materials_specular": {"specularTexture": {"index": texture},
                                                                  "specularColorTexture": {"index": texture}}}})
    g.add_node({"mesh": g.add_uv_mesh(quad(-10, -10, 10, 10, 0.0), quad_uv(), 0)})
    g.add_orthographic_camera({"translation": [0.0, 0.0, 3.0]}, 1.0)
    return g


def specular_glossiness(g, specular, glossiness, texel=None):
    gloss = {"diffuseFactor": [0.0, 0.0, 0.0, 1.0], "specularFactor": list(specular), "glossinessFactor": glossiness}
    if texel is not None:
        gloss["specularGlossinessTexture"] = {"index": g.add_texture(1, 1, [texel])}
    g.doc["extensionsUsed"] += ["KHR_materials_pbrSpecularGlossiness"]
    g.doc["extensionsRequired"] = ["KHR_materials_pbrSpecularGlossiness"]
    # The metallic-roughness fallback a viewer without the extension would show: red, rough; never rendered here.
    return g.add_raw_material({"pbrMetallicRoughness": {"baseColorFactor": [1.0, 0.0, 0.0, 1.0]},
                               "extensions": {"KHR_materials_pbrSpecularGlossiness": gloss}})


def gloss_quad():
    g = AssetGltf()
    specular_glossiness(g, (0.9, 0.6, 0.3), 1.0, (255, 188, 0, 255))
    g.add_node({"mesh": g.add_uv_mesh(quad(-10, -10, 10, 10, 0.0), quad_uv(), 0)})
    g.add_orthographic_camera({"translation": [0.0, 0.0, 3.0]}, 1.0)
    return g


def gloss_highlight(textured):
    g = AssetGltf()
    g.doc["extensionsUsed"] += ["KHR_lights_punctual"]
    if textured:
        specular_glossiness(g, (1.0, 1.0, 1.0), 1.0, (255, 255, 255, 64))
    else:
        specular_glossiness(g, (1.0, 1.0, 1.0), 64 / 255)
    g.add_node({"mesh": g.add_uv_mesh(quad(-1, -1, 1, 1, 0.0), quad_uv(), 0)})
    g.add_light({"type": "point", "intensity": 1.0}, {"translation": [0.0, 0.0, 0.5]})
    g.add_orthographic_camera({"translation": [0.0, 0.0, 2.0]}, 1.0)
    return g


def unlit_quad():
    g = Gltf()
    g.doc["extensionsUsed"] += ["KHR_materials_unlit"]
    g.doc["materials"].append({"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1.0]},
                               "emissiveFactor": [1.0, 1.0, 1.0],
                               "extensions": {"KHR_materials_unlit": {}}})
    g.add_node({"mesh": g.add_mesh(quad(-10, -10, 10, 10, 0.0), 0)})
    g.add_orthographic_camera({"translation": [0.0, 0.0, 3.0]}, 1.0)
    return g


def pointer_scene(animated):
    g = Gltf()
    g.doc["extensionsUsed"] += ["KHR_materials_emissive_strength"]
    base, strength, yfov = (0.25, 1.0, 0.5) if animated else (0.5, 2.0, 0.625)
    g.doc["materials"].append({"pbrMetallicRoughness": {"baseColorFactor": [base, base, base, 1.0], "metallicFactor": 0.0},
                               "emissiveFactor": [0.5, 0.25, 0.125],
                               "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": strength}}})
    g.add_node({"mesh": g.add_mesh(quad(-1, -1, 1, 1, 0.0), 0)})
    g.add_perspective_camera({"translation": [0.0, 0.0, 3.0]}, yfov)
    if animated:
        g.doc["extensionsUsed"] += ["KHR_animation_pointer"]
        times = g.add_floats([0.0, 1.0], kind="SCALAR", count=2)
        channels = [("/materials/0/pbrMetallicRoughness/baseColorFactor",
                     g.add_floats([0.25, 0.25, 0.25, 1.0, 0.75, 0.75, 0.75, 1.0], kind="VEC4", count=2)),
                    ("/materials/0/extensions/KHR_materials_emissive_strength/emissiveStrength",
                     g.add_floats([1.0, 3.0], kind="SCALAR", count=2)),
                    ("/cameras/0/perspective/yfov", g.add_floats([0.5, 0.75], kind="SCALAR", count=2))]
        g.doc["animations"] = [{
            "samplers": [{"input": times, "output": output} for _, output in channels],
            "channels": [{"sampler": i, "target": {"path": "pointer",
                                                   "extensions": {"KHR_animation_pointer": {"pointer": pointer}}}}
                         for i, (pointer, _) in enumerate(channels)]}]
    return g


def unlit_quad_animated():
    g = unlit_quad()
    g.doc["extensionsUsed"] += ["KHR_animation_pointer"]
    times = g.add_floats([0.0, 1.0], kind="SCALAR", count=2)
    colors = g.add_floats([0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 1.0], kind="VEC4", count=2)
    pointer = {"KHR_animation_pointer": {"pointer": "/materials/0/pbrMetallicRoughness/baseColorFactor"}}
    g.doc["animations"] = [{"samplers": [{"input": times, "output": colors, "interpolation": "LINEAR"}],
                            "channels": [{"sampler": 0, "target": {"path": "pointer", "extensions": pointer}}]}]
    return g


def main():
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    scenes = {
        "coat_black_quad": scene(coated((0.0, 0.0, 0.0), 1.0, 1.0, 0.0, specular=0.0), quad(-10, -10, 10, 10, 0.0),
                                 lambda g: g.add_orthographic_camera({"translation": [0.0, 0.0, 3.0]}, 1.0)),
        "coat_furnace": scene(coated((1.0, 1.0, 1.0), 0.5, 1.0, 0.3), icosphere(4),
                              lambda g: g.add_perspective_camera({"translation": [0.0, 0.0, 3.0]}, 0.8)),
        "sheen_black_quad": scene(sheened((0.0, 0.0, 0.0), (1.0, 1.0, 1.0), 1.0, specular=0.0),
                                  quad(-10, -10, 10, 10, 0.0),
                                  lambda g: g.add_orthographic_camera({"translation": [0.0, 0.0, 3.0]}, 1.0)),
        "diffuse_sheet": diffuse_sheet(),
        "anisotropy_0": highlight(0.6, 0.0),
        "anisotropy_90": highlight(0.6, math.pi / 2),
        "isotropic_highlight": highlight(0.0, 0.0),
        "anisotropy_furnace": anisotropy_furnace(),
        "film_black_quad": film_black_quad(),
        "unlit_quad": unlit_quad(),
        "unlit_quad_animated": unlit_quad_animated(),
        "pointer_animated": pointer_scene(True),
        "pointer_static": pointer_scene(False),
        "specular_texture_quad": specular_texture_quad(),
        "gloss_quad": gloss_quad(),
        "gloss_highlight_texture": gloss_highlight(True),
        "gloss_highlight_factor": gloss_highlight(False),
        "metal_furnace_r30": scene(white_metal(0.3), icosphere(4),
                                   lambda g: g.add_perspective_camera({"translation": [0.0, 0.0, 3.0]}, 0.8)),
        "layer_furnace_r100": scene(mirror_layer(1.0), icosphere(4),
                                    lambda g: g.add_perspective_camera({"translation": [0.0, 0.0, 3.0]}, 0.8)),
        "metal_furnace_r100": scene(white_metal(1.0), icosphere(4),
                                    lambda g: g.add_perspective_camera({"translation": [0.0, 0.0, 3.0]}, 0.8)),
    }
    for name, g in scenes.items():
        g.write(out / f"{name}.gltf")


if __name__ == "__main__":
    main()
