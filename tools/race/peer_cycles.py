#!/usr/bin/env python3
"""Blender Cycles as a peer in the equal-error race on a luxtest frame (what a lighting TD would pick instead).

Usage (the bpy venv that setup.sh --cycles makes):
  peer_cycles.py SCENE|STAGE.usda FRAME --gt GT.exr [--scene-dir DIR] [--spp 4,16,64,256] [--targets a,b] [--threads 2]
                 [--out DIR] [--json OUT] [--fixes all] [--bounces 0] [--check-spp 1024] [--units-tol --bias-tol --block-tol]
race.py runs it with --cycles PYTHON and prints lux/cycles ratios beside the Mitsuba ones.
The stage is imported with Blender's own USD importer (bpy.ops.wm.usd_import) and rendered by Cycles on the
CPU, direct light only (max_bounces 0), box pixel filter of width 1, no adaptive sampling, no denoiser, no
clamping: the same estimator contract as lux and Mitsuba in race.py. What the importer gets wrong against the
ground truth's reading of the stage (usd-core through usd_desc.py, in the lux-peer venv: $LUX_PEER_PY) is
corrected after import (setup(): stage units, light units and shapes, cylinder lights as emissive tubes, cages
with flat shading, one-sided receivers, colours, Lambertian BSDFs of a constant colour or of the UsdUVTexture read
as stored; CYCLES.md has the measurements). A 1024-spp check (two halves:
Cycles' own noise) must then draw the ground truth's picture: image means equal (the units are converted, not
fitted), per-pixel error beyond both images' noise and 16 x 16-block error small (check_verdict), else Cycles
sits the frame out and says why. Its image is still scaled to the ground truth's mean (a factor within 2 % of 1).
Time is the render alone (scene already imported and synced once by a warm-up render).
Prints the same rows as race.py and "cycles: time at <target> = S s (N spp)".
"""
import argparse, json, math, os, subprocess, sys, time
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from race import fit  # noqa: E402

DEFAULT_SCENE_DIR = os.environ.get("LUXTEST_DIR", os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "testdata", "luxtest", "usd"))


def read_rgb(p):
    import OpenEXR
    ch = OpenEXR.File(p).channels()
    if "RGBA" in ch:
        return np.asarray(ch["RGBA"].pixels, np.float64)[..., :3]
    if "RGB" in ch:
        return np.asarray(ch["RGB"].pixels, np.float64)
    return np.stack([np.asarray(ch[c].pixels, np.float64) for c in "RGB"], -1)


FIXES = ("lights", "cylinder", "occluders", "flat", "sided", "colours", "lambert", "pixel")


def usd_desc(path, frame):
    """The stage as peer_mitsuba (the ground truth's builder) reads it: lights with their UsdLux radiance, mesh
    sidedness and colours, the camera. Blender's bpy has no pxr module, so the lux-peer venv reads it."""
    py = os.environ.get("LUX_PEER_PY", os.path.expanduser("~/.cache/lux-peer/bin/python"))
    r = subprocess.run([py, os.path.join(HERE, "usd_desc.py"), path, str(frame)], capture_output=True, text=True)
    if r.returncode != 0:
        raise SystemExit(f"cannot read {path} with usd-core ({py}): {(r.stderr.strip().splitlines() or ['?'])[-1]}")
    return json.loads(r.stdout)


def _usd_to_blender(sc, desc):
    """The importer's world change (Y-up stages are turned Z-up): the map that takes the USD camera position to
    Blender's, as a 4x4 column-vector matrix."""
    import mathutils
    cand = [mathutils.Matrix.Identity(4), mathutils.Matrix.Rotation(math.pi / 2, 4, "X")]
    cu = mathutils.Vector(desc["camera"]["world"][3][:3])
    cb = sc.camera.matrix_world.translation
    return min(cand, key=lambda m: ((m @ cu) - cb).length)


def _match(objs, path, pos_b):
    """The imported object of USD prim `path`: its name (Blender appends .001 on a clash), nearest to pos_b."""
    leaf = path.rsplit("/", 1)[-1]
    cands = [o for o in objs if o.name == leaf or (o.name.startswith(leaf + ".") and o.name[len(leaf) + 1:].isdigit())]
    if not cands:
        raise SystemExit(f"Blender's importer made nothing of {path}")
    return min(cands, key=lambda o: (o.matrix_world.translation - pos_b).length)


def _emissive_cylinder(L, light_obj, radiance, visible_camera):
    """A UsdLux CylinderLight (axis local X, centred, no caps, emitting outwards) as an emissive mesh: Blender
    has no cylinder light (its importer makes a point light of radius 0). Emission = radiance on the front
    (outer) side only; no BSDF, so it is a black occluder for other lights, as Mitsuba's cylinder shape is."""
    import bpy
    n = 128
    r = L["radius"] * (math.pi / n) / math.sin(math.pi / n)  # polygon of the circle's perimeter
    h = L["length"] / 2
    verts = [(x, r * math.cos(2 * math.pi * i / n), r * math.sin(2 * math.pi * i / n)) for i in range(n) for x in (-h, h)]
    faces = [(2 * i, 2 * ((i + 1) % n), 2 * ((i + 1) % n) + 1, 2 * i + 1) for i in range(n)]  # outward normals
    me = bpy.data.meshes.new(light_obj.name + "_tube"); me.from_pydata(verts, [], faces); me.update()
    ob = bpy.data.objects.new(light_obj.name + "_tube", me)
    bpy.context.scene.collection.objects.link(ob)
    ob.matrix_world = light_obj.matrix_world.copy()
    mat = bpy.data.materials.new("tube_emission"); mat.use_nodes = True
    nt = mat.node_tree; nt.nodes.clear()
    em = nt.nodes.new("ShaderNodeEmission"); em.inputs["Strength"].default_value = 1.0
    em.inputs["Color"].default_value = tuple(radiance) + (1.0,)
    geo = nt.nodes.new("ShaderNodeNewGeometry"); mix = nt.nodes.new("ShaderNodeMixShader")
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    nt.links.new(geo.outputs["Backfacing"], mix.inputs["Fac"]); nt.links.new(em.outputs["Emission"], mix.inputs[1])
    nt.links.new(mix.outputs["Shader"], out.inputs["Surface"])
    mat.cycles.emission_sampling = "FRONT"
    me.materials.append(mat)
    ob.visible_camera = visible_camera
    return ob


def _light_occluder(L, light_obj):
    """A black, camera-invisible stand-in for a light's shape, so that it shadows the other lights as Mitsuba's
    light shapes (black BSDF) do in the ground truth. A sphere 2 % inside the light's radius (its own samples,
    on the sphere, stay visible); a disk or rect 1e-4 behind its emitting side."""
    import bpy, bmesh
    bm = bmesh.new()
    if L["type"] == "SphereLight":
        bmesh.ops.create_uvsphere(bm, u_segments=48, v_segments=24, radius=0.98 * L["radius"])
    elif L["type"] == "DiskLight":
        bmesh.ops.create_circle(bm, cap_ends=True, segments=64, radius=L["radius"])
    elif L["type"] == "RectLight":
        for v in [(-1, -1), (1, -1), (1, 1), (-1, 1)]:
            bm.verts.new((v[0] * L["width"] / 2, v[1] * L["height"] / 2, 0.0))
        bm.faces.new(bm.verts)
    else:
        bm.free(); return None
    if L["type"] != "SphereLight":
        for v in bm.verts:
            v.co.z += 1e-4
    me = bpy.data.meshes.new(light_obj.name + "_occluder"); bm.to_mesh(me); bm.free()
    ob = bpy.data.objects.new(light_obj.name + "_occluder", me)
    bpy.context.scene.collection.objects.link(ob)
    ob.matrix_world = light_obj.matrix_world.copy()
    mat = bpy.data.materials.new("black"); mat.use_nodes = True
    nt = mat.node_tree; nt.nodes.clear()
    bsdf = nt.nodes.new("ShaderNodeBsdfDiffuse"); bsdf.inputs["Color"].default_value = (0, 0, 0, 1)
    out = nt.nodes.new("ShaderNodeOutputMaterial"); nt.links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    me.materials.append(mat)
    ob.visible_camera = False
    return ob


# UsdPreviewSurface's diffuseColor when its UsdUVTexture names a file that does not resolve: the Mitsuba peer and
# lux shade with the input's default (peer_mitsuba._uv_texture), where Blender's importer leaves an Image Texture
# without an image, which Cycles draws magenta. (A UsdUVTexture with no file at all is its fallback in the ground
# truth; Blender's node cannot tell the two apart, the stage's reading with `colours` can.)
UNRESOLVED_GREY = (0.18, 0.18, 0.18, 1.0)


def _clear_custom_normals(me):
    """Drop a mesh's imported (authored) normals: the Mitsuba peer shades every mesh with its face normal, and an
    authored normal that disagrees with the winding would light or darken a face where the ground truth does not."""
    if me.has_custom_normals:
        for name in ("custom_normal", "custom_normals"):
            if name in me.attributes:
                me.attributes.remove(me.attributes[name])
        if me.has_custom_normals:
            raise SystemExit(f"{me.name}: cannot clear its imported normals")


def _imported_base(mat):
    """What Blender's importer made of a material's diffuseColor: the Principled BSDF's Base Color value and the
    Image Texture node linked to it (a UsdUVTexture becomes an Image Texture fed by a UV Map node), or None."""
    base, tex = (1.0, 1.0, 1.0, 1.0), None
    for n in (mat.node_tree.nodes if mat and mat.node_tree else []):
        if n.type == "BSDF_PRINCIPLED":
            base = tuple(n.inputs["Base Color"].default_value)
            tex = next((l.from_node for l in n.inputs["Base Color"].links if l.from_node.type == "TEX_IMAGE"), None)
    return base, tex


def _image_file(tex):
    """The file of an imported Image Texture node if it exists on disk, else None (no image, or unresolved)."""
    import bpy
    im = tex.image if tex is not None else None
    f = bpy.path.abspath(im.filepath) if im is not None and im.source == "FILE" else ""
    return os.path.realpath(f) if f and os.path.isfile(f) else None


def _raw_texture(nt, tex, scale=(1.0, 1.0, 1.0), bias=(0.0, 0.0, 0.0)):
    """The importer's Image Texture `tex` (its image and UV map) rebuilt in node tree `nt`, read as the Mitsuba peer
    reads a UsdUVTexture's EXR: its stored values (Blender's importer tags these images sRGB, which would decode the
    floats as sRGB-encoded, and Blender might tag a '.ACEScg.exr' ACEScg: Non-Color keeps the values as stored),
    alpha ignored, bilinear, repeating, times scale plus bias (linear, so applying them after the lookup is the
    same as Mitsuba's applying them to the pixels). Returns the colour output socket."""
    im = tex.image
    im.colorspace_settings.name = "Non-Color"
    im.alpha_mode = "CHANNEL_PACKED"  # RGB as stored, never (un)premultiplied by the alpha channel
    node = nt.nodes.new("ShaderNodeTexImage"); node.image = im
    node.interpolation = "Linear"; node.extension = "REPEAT"; node.projection = "FLAT"
    uv_src = next((l.from_node for l in tex.inputs["Vector"].links if l.from_node.type == "UVMAP"), None)
    if uv_src is not None:  # the primvar the UsdPrimvarReader_float2 reads (else the mesh's default UV map)
        uv = nt.nodes.new("ShaderNodeUVMap"); uv.uv_map = uv_src.uv_map
        nt.links.new(uv.outputs["UV"], node.inputs["Vector"])
    out = node.outputs["Color"]
    if tuple(scale) != (1.0, 1.0, 1.0) or tuple(bias) != (0.0, 0.0, 0.0):
        ma = nt.nodes.new("ShaderNodeVectorMath"); ma.operation = "MULTIPLY_ADD"
        nt.links.new(out, ma.inputs[0]); ma.inputs[1].default_value = scale; ma.inputs[2].default_value = bias
        out = ma.outputs["Vector"]
    return out


def setup(path, frame, w, h, threads, assist=True, hide_lights=True, bounces=0, fixes=FIXES, pixel_shift=None):
    """Import `path` with Blender's USD importer and set Cycles up like the other peers. With assist, the
    importer's output is corrected against the stage as usd-core reads it (`fixes`, all by default; the stage is
    then imported in its own units, and never with subdivision modifiers):
      lights   every light gets the UsdLux radiance the ground truth uses (energy = pi * radiance, Blender's
               unnormalised convention), sphere lights become spheres of their radius with no cone and no
               soft falloff, rect/disk lights keep their size with a 180-degree spread;
      cylinder a CylinderLight (a radius-0 point light after import) becomes an emissive mesh tube;
      flat     meshes are drawn as their cages (no subdivision modifier) and shaded with their face normals (the
               importer smooth-shades a mesh without authored normals and keeps authored ones as custom normals;
               the Mitsuba peer, like hdEmbree, shades with the geometric normal);
      sided    a mesh that is not doubleSided is black from behind (Cycles' surfaces are two-sided);
      colours  receivers take the stage's diffuseColor / displayColor, as the Mitsuba peer does;
      lambert  receivers are Lambertian (Blender makes UsdPreviewSurface a Principled BSDF): a diffuse BSDF of a
               constant colour or, where the Principled Base Color is linked to an Image Texture (the importer's
               UsdUVTexture), of that texture through its UV map, read as the stored values (Non-Color; the
               importer tags these EXRs sRGB) as the Mitsuba peer reads the file, times the texture's scale plus
               bias (colours); an Image Texture whose file does not resolve gives UsdPreviewSurface's 0.18 grey.
               With colours the ground truth's reading decides: a texture only where it reads one (the same file),
               else its constant colour;
      occluders each light's shape becomes a black camera-invisible occluder for the other
               lights, as Mitsuba's light shapes are in the ground truth (UsdLux lights, lux's and Cycles' are not);
      pixel    the camera is shifted by `pixel_shift` pixels (x, y) if given (see CYCLES.md: none is needed).
    """
    import bpy, mathutils
    fixes = set(fixes) if assist else set()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    # Subdivision surfaces are drawn as their cages (the Mitsuba peer's and lux's hdembree contract): no subdivision
    # modifier. With assist the stage keeps its own units, as the ground truth reads it: the importer would scale
    # a stage of metersPerUnit != 1 (the StandardShaderBall's 0.01) to metres, and the lights' positions and sizes
    # are corrected in stage units below.
    bpy.ops.wm.usd_import(filepath=path, import_subdivision=False, apply_unit_conversion_scale=not assist)
    sc = bpy.context.scene
    sc.frame_set(frame)
    cams = [o for o in sc.objects if o.type == "CAMERA"]
    sc.camera = cams[0]
    r = sc.render
    r.engine = "CYCLES"; r.resolution_x, r.resolution_y, r.resolution_percentage = w, h, 100
    r.threads_mode = "FIXED"; r.threads = threads
    c = sc.cycles
    c.device = "CPU"; c.use_adaptive_sampling = False; c.use_denoising = False
    # bounces 0 = direct light only; a path-tracing comparison passes its own count
    c.max_bounces = bounces; c.diffuse_bounces = bounces; c.glossy_bounces = 0; c.transmission_bounces = 0
    c.sample_clamp_direct = 0.0; c.sample_clamp_indirect = 0.0
    c.pixel_filter_type = "BOX"; c.filter_width = 1.0
    if not any(o.type == "LIGHT" for o in sc.objects) and sc.world is not None:
        pass  # a DomeLight arrives as the world: keep it
    else:
        sc.world = bpy.data.worlds.new("black")  # Blender's default grey world is no UsdLux light
        sc.world.color = (0, 0, 0)
        for n in getattr(sc.world.node_tree, "nodes", []):
            if n.type == "BACKGROUND":
                n.inputs["Strength"].default_value = 0.0
    desc = usd_desc(path, frame) if fixes else None
    if "pixel" in fixes and pixel_shift:
        cam = sc.camera.data  # shift is in units of the larger image side
        cam.shift_x += pixel_shift[0] / max(w, h); cam.shift_y += pixel_shift[1] / max(w, h)
    for o in sc.objects:
        if o.type == "LIGHT":
            o.visible_camera = not hide_lights  # hdEmbree hides lights from the camera (visibleRect aside)
    if "lights" in fixes:
        U = _usd_to_blender(sc, desc)
        lights = [o for o in sc.objects if o.type == "LIGHT"]
        for L in desc["lights"]:
            pos = U @ mathutils.Vector(L["world"][3][:3])
            o = _match(lights, L["path"], pos)
            if (o.matrix_world.translation - pos).length > 1e-3 * max(1.0, pos.length):
                raise SystemExit(f"{L['path']}: imported at {tuple(o.matrix_world.translation)}, stage says {tuple(pos)}")
            d = o.data
            if L["type"] == "DistantLight":
                E = L["irradiance"]; m = max(E)
                d.type = "SUN"; d.energy = m; d.color = [e / m for e in E] if m > 0 else (1, 1, 1); d.angle = 0.0
                continue
            rad = L["radiance"]; m = max(rad)
            if L["type"] == "CylinderLight":
                if "cylinder" in fixes:
                    _emissive_cylinder(L, o, rad, not hide_lights)
                    bpy.data.objects.remove(o)
                continue
            if L["type"] == "SphereLight":
                sv = np.linalg.svd(np.asarray(L["world"])[:3, :3], compute_uv=False)
                d.type = "POINT"; d.shadow_soft_size = L["radius"] * sv[0]; d.use_soft_falloff = False
            else:
                d.type = "AREA"; d.spread = math.pi
                if L["type"] == "RectLight":
                    d.shape = "RECTANGLE"; d.size = L["width"]; d.size_y = L["height"]
                else:
                    d.shape = "DISK"; d.size = 2 * L["radius"]
            # Blender's unnormalised lights emit radiance energy / pi (sphere and area alike)
            d.normalize = False; d.energy = math.pi * m; d.color = [x / m for x in rad] if m > 0 else (1, 1, 1)
            if "occluders" in fixes:
                _light_occluder(L, o)
    elif assist:
        for o in sc.objects:
            if o.type != "LIGHT":
                continue
            d = o.data
            # the earlier peer's two corrections: a sphere light with a no-op cone arrives as a spot cut to a
            # hemisphere, and Blender's soft falloff is not UsdLux's sphere
            if d.type == "SPOT" and d.spot_size >= math.pi - 1e-4 and d.spot_blend == 0:
                d.type = "POINT"
            if d.type in ("POINT", "SPOT"):
                d.use_soft_falloff = False
    if "flat" in fixes:
        for o in sc.objects:
            if o.type == "MESH":
                for mod in [mod for mod in o.modifiers if mod.type == "SUBSURF"]:
                    o.modifiers.remove(mod)  # the cage, whatever the importer's options
                _clear_custom_normals(o.data)
                o.data.shade_flat() if hasattr(o.data, "shade_flat") else o.data.polygons.foreach_set(
                    "use_smooth", [False] * len(o.data.polygons))
    if "lambert" in fixes:
        # The race's receivers are Lambertian (hdEmbree's, lux's and the Mitsuba peer's contract). Blender turns
        # UsdPreviewSurface into a Principled BSDF with a specular lobe: each becomes a diffuse BSDF of the stage's
        # colour (colours) or of the imported base colour (else white); a diffuseColor read from a UsdUVTexture
        # keeps its texture (the importer's Image Texture and UV map, read as stored values as the Mitsuba peer
        # reads the EXR), one whose file does not resolve is UsdPreviewSurface's 0.18 grey.
        meshes = {m["path"].rsplit("/", 1)[-1]: m for m in desc["meshes"]} if desc else {}
        for o in sc.objects:
            if o.type != "MESH" or o.name.endswith(("_tube", "_occluder")):
                continue
            base, tex = _imported_base(o.active_material)
            tfile = _image_file(tex)
            if tex is not None and tfile is None:
                base, tex = UNRESOLVED_GREY, None  # an unresolvable texture file: UsdPreviewSurface's default
            scale, bias = (1.0, 1.0, 1.0), (0.0, 0.0, 0.0)
            um = meshes.get(o.name.split(".")[0]) if desc else None
            if "colours" in fixes and um is not None:
                # the stage as usd-core reads it decides: a texture where the ground truth has one, else its colour
                ut = um.get("texture")
                if ut and (tex is None or tfile != os.path.realpath(ut["file"])):
                    raise SystemExit(f"{um['path']}: the ground truth reads diffuseColor from {ut['file']}, Blender's "
                                     f"importer from {tfile or 'no image file'}")
                tex = tex if ut else None
                if ut:
                    scale, bias = ut["scale"], ut["bias"]
                else:
                    base = tuple(um["color"]) + (1.0,)
            lam = bpy.data.materials.new("lambert"); lam.use_nodes = True
            nodes = lam.node_tree.nodes; nodes.clear()
            bsdf = nodes.new("ShaderNodeBsdfDiffuse"); bsdf.inputs["Color"].default_value = base
            if tex is not None:  # a UsdUVTexture diffuseColor: the texture, as the Mitsuba peer reads it
                lam.node_tree.links.new(_raw_texture(lam.node_tree, tex, scale, bias), bsdf.inputs["Color"])
            outn = nodes.new("ShaderNodeOutputMaterial")
            if "sided" in fixes and um is not None and not um["double_sided"]:
                # one-sided: black from behind (Mitsuba's 'diffuse', hdEmbree's and lux's one-sided receivers)
                geo = nodes.new("ShaderNodeNewGeometry"); mix = nodes.new("ShaderNodeMixShader")
                lam.node_tree.links.new(geo.outputs["Backfacing"], mix.inputs["Fac"])
                lam.node_tree.links.new(bsdf.outputs["BSDF"], mix.inputs[1])
                lam.node_tree.links.new(mix.outputs["Shader"], outn.inputs["Surface"])
            else:
                lam.node_tree.links.new(bsdf.outputs["BSDF"], outn.inputs["Surface"])
            o.data.materials.clear(); o.data.materials.append(lam)
    r.image_settings.file_format = "OPEN_EXR"; r.image_settings.color_depth = "32"
    sc.view_settings.view_transform = "Standard"
    return sc


def render(sc, spp, seed, path):
    import bpy
    sc.cycles.samples = spp; sc.cycles.seed = seed; sc.render.filepath = path
    t = time.perf_counter(); bpy.ops.render.render(write_still=True)
    return read_rgb(path), time.perf_counter() - t


def write_rgb(p, img):
    import OpenEXR
    OpenEXR.File({"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage},
                 {"RGB": np.ascontiguousarray(img, np.float32)}).write(p)


def downsample(img, k):
    """Box-average k x k pixels: with a box pixel filter, exactly the picture rendered at 1/k the resolution."""
    if k == 1:
        return img
    H, W, C = img.shape
    return img[:H - H % k, :W - W % k].reshape(H // k, k, W // k, k, C).mean(axis=(1, 3))


def picture_check(img, gt, sig_img, sig_gt, block=16):
    """Judge the picture, not the noise. img (Cycles) and gt (Mitsuba) at one resolution; sig_* their own
    per-pixel noise (RMSE of two halves / 2). Returns
      ratio     per-channel image-mean ratio Cycles / GT (units: 1 when the lights are converted right),
      scale     GT mean / Cycles mean (what the race multiplies Cycles by),
      rel_rmse  per-pixel RMSE / GT mean after scaling (the old check: noise and edges included),
      bias      the same with both images' noise removed: sqrt(RMSE^2 - sig_img^2 - sig_gt^2) / mean,
      blocks    RMS over block x block means of (scaled Cycles - GT) / GT mean, their noise removed,
      block_max the largest block difference / GT mean (a local error: a wrong light, a lit face)."""
    m = gt.mean()
    ratio = [float(img[..., c].mean() / max(gt[..., c].mean(), 1e-30)) for c in range(3)]
    scale = float(m / max(img.mean(), 1e-30))
    d = img * scale - gt
    r = float(np.sqrt(np.mean(d * d)))
    bias = float(np.sqrt(max(r * r - (scale * sig_img) ** 2 - sig_gt ** 2, 0.0)) / m)
    bd = downsample(d, block)
    bnoise2 = ((scale * sig_img) ** 2 + sig_gt ** 2) / block ** 2
    blocks = float(np.sqrt(max(np.mean(bd * bd) - bnoise2, 0.0)) / m)
    bmax = float(np.abs(bd).mean(-1).max() / m)
    return dict(ratio=ratio, scale=scale, rel_rmse=r / m, bias=bias, blocks=blocks, block_max=bmax,
                noise_img=sig_img / m, noise_gt=sig_gt / m)


def format_check(c):
    return (f"mean ratio R/G/B {c['ratio'][0]:.4f}/{c['ratio'][1]:.4f}/{c['ratio'][2]:.4f}; per-pixel rel RMSE "
            f"{c['rel_rmse']:.4f} (noise Cycles {c['noise_img']:.4f}, GT {c['noise_gt']:.4f}; bias {c['bias']:.4f}); "
            f"16x16 blocks rel RMS {c['blocks']:.4f}, max {c['block_max']:.4f}")


# The picture check's limits (CYCLES.md: a faithful render measures <= 0.5 % / 1.6 % / 0.3 % on the clutter
# scenes and the Cornell box, the importer's own picture 3-950 % / 22-44 % / 1-58 %).
UNITS_TOL = 0.02   # |Cycles / GT image mean - 1| per channel: the lights' units are converted, not fitted
BIAS_TOL = 0.02    # per-pixel RMSE / GT mean with both images' noise removed
BLOCK_TOL = 0.01   # RMS of 16 x 16-block mean differences / GT mean, their noise removed


def check_verdict(c, units_tol=UNITS_TOL, bias_tol=BIAS_TOL, block_tol=BLOCK_TOL):
    """'' if the picture passes, else why not."""
    why = []
    if max(abs(r - 1) for r in c["ratio"]) > units_tol:
        why.append(f"image mean ratio {'/'.join(f'{r:.3f}' for r in c['ratio'])}, allowed 1 +- {units_tol}")
    if c["bias"] > bias_tol:
        why.append(f"per-pixel error beyond noise {c['bias']:.3f} of the mean, allowed {bias_tol}")
    if c["blocks"] > block_tol:
        why.append(f"16x16-block error {c['blocks']:.3f} of the mean, allowed {block_tol}")
    return "; ".join(why)


def rmse(a, b):
    return float(np.sqrt(np.mean((a - b) ** 2)))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("scene"); ap.add_argument("frame", type=int); ap.add_argument("--gt", required=True)
    ap.add_argument("--spp", default="4,16,64,256"); ap.add_argument("--targets", default="")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--check-spp", type=int, default=1024); ap.add_argument("--out", default="/tmp/peer_cycles")
    ap.add_argument("--json"); ap.add_argument("--scene-dir", default=DEFAULT_SCENE_DIR)
    ap.add_argument("--units-tol", type=float, default=UNITS_TOL); ap.add_argument("--bias-tol", type=float, default=BIAS_TOL)
    ap.add_argument("--block-tol", type=float, default=BLOCK_TOL)
    ap.add_argument("--bounces", type=int, default=0, help="Cycles bounces: 0 direct light, 7 = depth 8 (path)")
    ap.add_argument("--fixes", default="all", help="the importer corrections to apply (setup()): all, none (the "
                    "importer's own picture) or a comma list of " + ",".join(FIXES) + "; 'lambert' alone is the earlier peer")
    a = ap.parse_args()
    fixes = FIXES if a.fixes == "all" else () if a.fixes == "none" else tuple(a.fixes.split(","))
    os.makedirs(a.out, exist_ok=True)
    gt = read_rgb(a.gt); sig_gt = json.load(open(a.gt + ".json"))["sigma"]
    h, w = gt.shape[:2]
    # a luxtest name (SCENE_DIR/NAME.usda) or a stage's path, as race.py takes it
    stage = a.scene if os.path.isfile(a.scene) else os.path.join(a.scene_dir, f"{a.scene}.usda")
    sc = setup(os.path.abspath(stage), a.frame, w, h, a.threads, assist=a.fixes != "none",
               fixes=fixes, bounces=a.bounces)
    render(sc, 4, 1, os.path.join(a.out, "warm.exr"))
    # The picture check: two halves of --check-spp give Cycles' own noise, the GT's comes from its sidecar; both
    # are taken out of the per-pixel error, and 16 x 16-block means judge the picture at a scale noise cannot reach.
    h1, t1 = render(sc, a.check_spp // 2, 3, os.path.join(a.out, "check1.exr"))
    h2, t2 = render(sc, a.check_spp // 2, 4, os.path.join(a.out, "check2.exr"))
    big = 0.5 * (h1 + h2); write_rgb(os.path.join(a.out, "check.exr"), big)
    chk = picture_check(big, gt, rmse(h1, h2) / 2, sig_gt)
    scale = chk["scale"]
    flipped = rmse(big[::-1] * scale, gt) / gt.mean()
    print(f"cycles {a.check_spp} spp in {t1 + t2:.1f} s; scale to GT {scale:.4f}; " + format_check(chk)
          + f" (upside down: rel RMSE {flipped:.4f})")
    if flipped < chk["rel_rmse"]:
        raise SystemExit("Cycles image is upside down relative to the ground truth: fix read_rgb orientation")
    why = check_verdict(chk, a.units_tol, a.bias_tol, a.block_tol)
    if why:
        raise SystemExit(f"Cycles draws another picture of this frame ({why}): no race")
    rows = []
    for s in [int(x) for x in a.spp.split(",")]:
        img, secs = render(sc, s, 11 + s, os.path.join(a.out, f"c{s}.exr"))
        rows.append(dict(spp=s, seconds=secs, rmse=rmse(img * scale, gt)))
        print(f"| cycles | {s} | {secs:.2f} | {rows[-1]['rmse']:.6f} |", flush=True)
    targets = [float(x) for x in a.targets.split(",") if x]
    out = dict(scene=a.scene, frame=a.frame, scale=scale, check=chk, rows=rows, at={})
    for tg, (spp, secs) in fit(rows, sig_gt, targets).items():  # race.py's own fit: same rules for every peer
        out["at"][tg] = dict(spp=spp, seconds=secs)
        print(f"cycles: time at {tg:.6f} = {secs:.2f} s ({spp:.0f} spp)")
    if a.json:
        json.dump(out, open(a.json, "w"), indent=1)


if __name__ == "__main__":
    main()
