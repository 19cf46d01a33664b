#!/usr/bin/env python3
"""Writes the Cornell box's material variants beside cornell.usda (run from anywhere):

- cornell_preview_diffuse.usda: UsdPreviewSurface with useSpecularWorkflow = 1 and
  specularColor = 0, the usual way to author a plain diffuse surface;
- cornell_standard_surface.usda: inline MaterialX standard_surface under outputs:mtlx:surface,
  configured as pure diffuse (specular 0, metalness 0, diffuse_roughness 0);
- cornell_open_pbr.usda: the same with open_pbr_surface (specular_weight 0, base_metalness 0,
  base_diffuse_roughness 0);
- cornell_standard_surface_default.usda, cornell_open_pbr_default.usda: the models at their
  defaults but for base_color (specular lobes included), for per-sample timings.

Each keeps cornell.usda's geometry, light and camera; only the three Shader prims change.
"""
import pathlib
import re

here = pathlib.Path(__file__).resolve().parent
base = (here / "cornell.usda").read_text()
shader = re.compile(
    r'token outputs:surface\.connect = <(?P<mat>[^>]+)/Surface\.outputs:surface>\n'
    r'(?P<ind>\s*)def Shader "Surface"\n\s*\{\n'
    r'\s*uniform token info:id = "UsdPreviewSurface"\n'
    r'\s*color3f inputs:diffuseColor = (?P<c>\([^)]*\))\n'
    r'\s*token outputs:surface\n\s*\}'
)


def variant(make):
    out, n = shader.subn(lambda m: make(m["mat"], m["ind"], m["c"]), base)
    assert n == 3, n
    return out


def preview(mat, ind, c):
    return (f'token outputs:surface.connect = <{mat}/Surface.outputs:surface>\n'
            f'{ind}def Shader "Surface"\n{ind}{{\n'
            f'{ind}    uniform token info:id = "UsdPreviewSurface"\n'
            f'{ind}    color3f inputs:diffuseColor = {c}\n'
            f'{ind}    int inputs:useSpecularWorkflow = 1\n'
            f'{ind}    color3f inputs:specularColor = (0, 0, 0)\n'
            f'{ind}    token outputs:surface\n{ind}}}')


def mtlx(nodedef, inputs):
    def make(mat, ind, c):
        lines = "".join(f'{ind}    {t} inputs:{k} = {v}\n' for t, k, v in inputs(c))
        return (f'token outputs:mtlx:surface.connect = <{mat}/Surface.outputs:out>\n'
                f'{ind}def Shader "Surface"\n{ind}{{\n'
                f'{ind}    uniform token info:id = "{nodedef}"\n{lines}'
                f'{ind}    token outputs:out\n{ind}}}')
    return make


header = "# Material variant written by variants.py from cornell.usda.\n"
files = {
    "cornell_preview_diffuse.usda": variant(preview),
    "cornell_standard_surface.usda": variant(mtlx("ND_standard_surface_surfaceshader", lambda c: [
        ("float", "base", "1"), ("color3f", "base_color", c), ("float", "specular", "0"),
        ("float", "metalness", "0"), ("float", "diffuse_roughness", "0")])),
    "cornell_open_pbr.usda": variant(mtlx("ND_open_pbr_surface_surfaceshader", lambda c: [
        ("float", "base_weight", "1"), ("color3f", "base_color", c),
        ("float", "specular_weight", "0"), ("float", "base_metalness", "0"),
        ("float", "base_diffuse_roughness", "0")])),
    # The models with their defaults but for the colour (specular lobes, roughness): what
    # BENCHMARKS.md times per sample.
    "cornell_standard_surface_default.usda": variant(mtlx("ND_standard_surface_surfaceshader",
        lambda c: [("color3f", "base_color", c)])),
    "cornell_open_pbr_default.usda": variant(mtlx("ND_open_pbr_surface_surfaceshader",
        lambda c: [("color3f", "base_color", c)])),
}
for name, text in files.items():
    (here / name).write_text(text.replace(")\n\n# A Cornell", ")\n\n" + header + "# A Cornell", 1))
    print("wrote", name)
