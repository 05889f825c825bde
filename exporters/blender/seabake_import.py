# seabake_import.py - builds a Blender 3.4 scene from a directory that
# `seabake bake --blender` wrote (a copy of this script sits in it).
#
#   blender -b --factory-startup --python seabake_import.py -- DIR/manifest.json
#           [--frame F] [--single-frame] [--max-level N] [--no-projection]
#           [--material emission|visible] [--save FILE.blend]
#           [--render OUT.exr] [--render-frames OUT_####.exr]
#
# --single-frame loads only the --frame's maps (default the first frame's)
# as still images, the scene's frame range that frame alone; --max-level N
# only the levels of index N and finer (0 is the finest; each coarser level
# surrounds the finer ones, so the sea stays whole, only smaller);
# --no-projection the maps everywhere, though the bake has the sensor's
# image (see below).
#
# It is also the Blender add-on's importer: seabake-blender.zip (built by
# make, installed as PKGDATADIR/blender/seabake-blender.zip) holds it as
# seabake/seabake_import.py beside seabake/__init__.py, which registers it.
# Install the zip from Edit > Preferences > Add-ons > Install..., enable
# "seabake bake importer", then File > Import > seabake bake (manifest.json)
# imports into a new scene (the operator import_scene.seabake, at the end of
# this file), its options the switches above: Frames All or One (--frame F
# --single-frame), Levels All or Up to (--max-level N), Sensor projection
# (off: --no-projection) and Material Infrared or Visible (--material).  Both
# run import_bake(); headless scripts can call it too.
#
# What it builds, mirroring the POV-Ray export (scene.pov):
#   - one mesh per clipmap level, a flat ring at sea level: the level's
#     rectangle minus the next finer level's ("hole" in the manifest); the
#     low-resolution level as the manifest's "horizon": a polar mesh to the
#     farthest sea in view (on a spherical Earth, on the sphere, to the
#     horizon) textured with the radiance a low-resolution pixel has there
#     (older bakes without it: a flat ring of one value reaching 1000
#     sensor altitudes).
#     Each coarser level sits 1e-3 finest facets lower, so that where two
#     windows overlap the finer level is the one seen.  UVs map a level's
#     rectangle onto its maps: u = (x - x0) / w, v = (y - y0) / h, so
#     (0, 0) is the south-west corner (Blender's image origin is the bottom
#     row, and the maps' row 0 is the north edge).
#   - two materials per level: "Emission" (the infrared radiance x
#     emission_scale of the emission map, emitted with strength 1, the one
#     used by default) and "Visible" (Principled BSDF with the normal map and
#     the GGX roughness, anisotropy and rotation of the roughness map, for
#     visible-light renders with your own lights).
#   - every map loaded as a Non-Color image (4-channel maps CHANNEL_PACKED),
#     kept in the .blend even when not wired.  A bake of several frames
#     (--frames A:B) is loaded as image sequences: the scene's frame range
#     is A..B at the bake's frame rate, and each frame shows its own maps
#     (frame_set(f), or Blender's animation render).
#   - --material visible: a Sun lamp in the direction of the manifest's
#     [sun] with its angular diameter (none when the sun is below the
#     horizon), a light-blue sky and SAMPLES_VISIBLE samples with bounces,
#     so that a visible-light render is lit and not noisy.
#   - the sensor's camera, the sky as a constant World background and Cycles
#     settings that reproduce the emission exactly (view transform Standard,
#     no pixel filter, no bounces, 32-bit EXR output).
#
# World axes are seabake's: x east, y north, z up, metres.  Pixel values of
# a render are radiances times the manifest's emission_scale.
#
# Errors (unreadable manifest, wrong format or version, a missing map, a
# map outside the manifest's directory) print "seabake_import: error: ..."
# naming the file and exit with status 1.

import argparse
import json
import math
import os
import sys
import traceback

import bpy
import numpy as np
from bpy.props import BoolProperty, EnumProperty, IntProperty, StringProperty
from bpy_extras.io_utils import ImportHelper
from mathutils import Matrix

FORMAT = "seabake-bake"
VERSION = 1
# Each coarser level sits this many finest facets below the next finer one
# (as SEA_POV_LAYER in exporters/povray.c).
LAYER = 1e-3
# The low-resolution ring reaches this many sensor altitudes from the sensor.
LR_REACH = 1000.0
# Emission is all there is, and every camera ray ends on an emitter or the
# World: a few samples only average the (tiny) pixel footprint.
SAMPLES = 4
# The visible material is a glossy BSDF lit by the sun and the sky: samples
# and bounces for a render without visible noise at the sensor's size.
SAMPLES_VISIBLE = 64
BOUNCES_VISIBLE = 4
# The sun lamp's strength (W m^-2, Blender's unit) and the sky's colour for
# --material visible: a daylight exposure for Blender's Standard view, not
# a radiometric value (seabake's radiometry is the infrared emission).
SUN_STRENGTH = 4.0
SKY_VISIBLE = (0.35, 0.5, 0.75)


class ImportError_(Exception):
    """A user-facing error: printed without a traceback, exit status 1."""


def fail(msg):
    raise ImportError_(msg)


# ----------------------------------------------------------------- manifest

def load_manifest(path):
    try:
        with open(path, encoding="utf-8") as f:
            m = json.load(f)
    except OSError as e:
        fail("%s: cannot read: %s" % (path, e.strerror))
    except ValueError as e:
        fail("%s: not JSON: %s" % (path, e))
    if not isinstance(m, dict) or m.get("format") != FORMAT:
        fail('%s: not a seabake bake manifest (format is not "%s")' % (path, FORMAT))
    if m.get("version") != VERSION:
        fail("%s: manifest version %r, this script reads version %d"
             % (path, m.get("version"), VERSION))
    for key in ("camera", "levels", "emission_scale", "frames"):
        if key not in m:
            fail("%s: no \"%s\" in the manifest" % (path, key))
    return m


def frame_range(m, path):
    """The baked frames (first, last), consecutive as bake --frames writes
    them; (first, first) for one frame."""
    nums = [fr.get("frame") for fr in m["frames"]]
    if not nums or not all(isinstance(n, int) for n in nums):
        fail("%s: \"frames\" holds no frame numbers" % path)
    if nums != list(range(nums[0], nums[0] + len(nums))):
        fail("%s: frames %s are not consecutive" % (path, nums))
    return nums[0], nums[-1]


def frame_entry(level, frame, path):
    """The level's files of frame `frame` (None: the first frame)."""
    frames = level.get("frames") or []
    if not frames:
        fail("%s: level %s has no frames" % (path, level.get("index")))
    if frame is None:
        return frames[0]
    for fr in frames:
        if fr.get("frame") == frame:
            return fr
    fail("%s: level %s has no frame %d (frames %s)"
         % (path, level.get("index"), frame, [fr.get("frame") for fr in frames]))


def sky_scaled(m, path):
    """The sky radiance x emission_scale: recorded by seabake bake --blender
    (as it computes it for POV-Ray: band-weighted, in the maps' units)."""
    b = m.get("blender")
    if not isinstance(b, dict) or not isinstance(b.get("sky_emission"), (int, float)):
        fail("%s: no blender.sky_emission (bake with seabake bake --blender)" % path)
    return float(b["sky_emission"])


def sky_table(m, path):
    """A directional sky's table (blender.sky_table: emission at nodes s =
    sqrt(max(cos zenith, 0)), linear between them), as (s, emission) lists;
    None for an isotropic sky (one value, sky_scaled)."""
    t = m.get("blender", {}).get("sky_table")
    if t is None:
        return None
    s, v = t.get("s"), t.get("emission")
    if (not isinstance(s, list) or not isinstance(v, list) or len(s) != len(v) or len(s) < 2
            or s[0] != 0 or s[-1] != 1 or any(b <= a for a, b in zip(s, s[1:]))):
        fail("%s: blender.sky_table: \"s\" and \"emission\" must be lists of one length, "
             "s increasing from 0 to 1" % path)
    return [float(x) for x in s], [float(x) for x in v]


# --------------------------------------------------------------------- maps

def inside(directory, name, manifest_path):
    """The path of a file the manifest names, which must lie inside the
    manifest's directory: a manifest is data, and one edited or written by
    someone else must not make the import load ../../x.exr or /any/file.
    Symbolic links are resolved before the check."""
    if not isinstance(name, str) or not name:
        fail("%s: a map's file is %r, not a file name" % (manifest_path, name))
    root = os.path.realpath(directory)
    path = os.path.realpath(os.path.join(root, name))
    if os.path.commonpath([root, path]) != root:
        fail("%s: map %r lies outside the manifest's directory %s (allowed: a file "
             "inside it, as seabake bake writes them)" % (manifest_path, name, root))
    return path


def load_map(directory, name, n_channels, manifest_path):
    path = inside(directory, name, manifest_path)
    if not os.path.isfile(path):
        fail("%s: map not found" % path)
    try:
        img = bpy.data.images.load(path, check_existing=True)
    except RuntimeError as e:
        fail("%s: Blender cannot load it: %s" % (path, e))
    # Data, not colour: no view or display transform may touch it.
    img.colorspace_settings.name = "Non-Color"
    # Four unrelated quantities share a 4-channel file: alpha is data too.
    img.alpha_mode = "CHANNEL_PACKED" if n_channels == 4 else "STRAIGHT"
    # Kept in a saved .blend even when no material uses it.
    img.use_fake_user = True
    if SEQUENCE is not None:
        # name_<frame>.exr, one file per frame: Blender reads the number.
        img.source = "SEQUENCE"
    return img


# ----------------------------------------------------------------- geometry

def clip_hole(x0, y0, w, h, hole):
    """The part of the hole inside the rectangle: (0, None) no hole,
    (1, (hx0, hy0, hx1, hy1)) a hole, (2, None) it covers everything."""
    if hole is None:
        return 0, None
    hx0 = max(hole["origin_m"][0], x0)
    hy0 = max(hole["origin_m"][1], y0)
    hx1 = min(hole["origin_m"][0] + hole["extent_m"][0], x0 + w)
    hy1 = min(hole["origin_m"][1] + hole["extent_m"][1], y0 + h)
    if not (hx1 > hx0 and hy1 > hy0):
        return 0, None
    if hx0 <= x0 and hy0 <= y0 and hx1 >= x0 + w and hy1 >= y0 + h:
        return 2, None
    return 1, (hx0, hy0, hx1, hy1)


def ring_mesh(name, x0, y0, w, h, kind, hole, z):
    """The rectangle [x0, x0 + w] x [y0, y0 + h] at height z minus the hole,
    as up to 8 quads on the 4 x 4 vertices the two rectangles' edges define
    (the mesh2 of Seabake_Ring in seabake.inc), with the UV map "UVMap"."""
    if kind == 1:
        xs = [x0, hole[0], hole[2], x0 + w]
        ys = [y0, hole[1], hole[3], y0 + h]
    else:
        xs = [x0 + w * k / 3.0 for k in range(4)]
        ys = [y0 + h * k / 3.0 for k in range(4)]
    verts = [(xs[i], ys[j], z) for j in range(4) for i in range(4)]
    faces = []
    for j in range(3):
        for i in range(3):
            if kind == 1 and i == 1 and j == 1:
                continue
            if not (xs[i + 1] > xs[i] and ys[j + 1] > ys[j]):
                continue  # a hole touching an edge: a cell of zero width
            k = 4 * j + i
            faces.append((k, k + 1, k + 5, k + 4))  # counter-clockwise: normal +z
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    uv = mesh.uv_layers.new(name="UVMap")
    for loop in mesh.loops:
        x, y, _ = verts[loop.vertex_index]
        uv.data[loop.index].uv = ((x - x0) / w, (y - y0) / h)
    mesh.validate()
    mesh.update()
    return mesh


def level_rect(lv):
    """A high-resolution level's rectangle (x0, y0, x1, y1), metres."""
    (x0, y0), (w, h) = lv["origin_m"], lv["extent_m"]
    return (x0, y0, x0 + w, y0 + h)


def wave_mesh(name, x0, y0, w, h, n_w, n_h, finer, z, depth):
    """A level's ring with the waves: the (n_w x n_h) height samples of the
    manifest's "height" entry on a grid over [x0, x0 + w] x [y0, y0 + h] at
    z (the Displace modifier of add_waves raises each vertex to its sample,
    through the UV map "heights" at the samples' texel centres), the cells
    whose centre lies in a finer level's rectangle (finer: (x0, y0, x1, y1))
    left out, and a skirt hanging `depth` below every boundary edge (the
    same samples, so it follows the edge), which closes the gaps where two
    levels' surfaces meet at different heights.  UVs "UVMap" as ring_mesh."""
    kk, jj = np.meshgrid(np.arange(n_w, dtype=np.float64), np.arange(n_h, dtype=np.float64))
    sx, sy = w / (n_w - 1), h / (n_h - 1)
    gx, gy = (x0 + kk * sx).ravel(), (y0 + jj * sy).ravel()
    cx = x0 + (np.arange(n_w - 1) + 0.5) * sx
    cy = y0 + (np.arange(n_h - 1) + 0.5) * sy
    ccx, ccy = np.meshgrid(cx, cy)
    present = np.ones((n_h - 1, n_w - 1), dtype=bool)
    for fx0, fy0, fx1, fy1 in finer:
        present &= ~((ccx > fx0) & (ccx < fx1) & (ccy > fy0) & (ccy < fy1))
    # cells: vertex (j, k) is j n_w + k; counter-clockwise, normal +z
    j, k = np.nonzero(present)
    v = j * n_w + k
    quads = [np.stack([v, v + 1, v + n_w + 1, v + n_w], axis=1)]
    # boundary edges: between a present cell and an absent one or the outside
    pad = np.zeros((n_h + 1, n_w + 1), dtype=bool)
    pad[1:-1, 1:-1] = present
    # horizontal edge (j, k)-(j, k+1): cells (j-1, k) and (j, k)
    hj, hk = np.nonzero(pad[:-1, 1:-1] != pad[1:, 1:-1])
    # vertical edge (j, k)-(j+1, k): cells (j, k-1) and (j, k)
    vj, vk = np.nonzero(pad[1:-1, :-1] != pad[1:-1, 1:])
    a = np.concatenate([hj * n_w + hk, vj * n_w + vk])
    b = np.concatenate([hj * n_w + hk + 1, (vj + 1) * n_w + vk])
    n_grid, n_edge = n_w * n_h, a.size
    # each edge's two bottom vertices: copies of a and b
    src = np.concatenate([np.arange(n_grid), a, b])
    ia = n_grid + np.arange(n_edge)
    ib = n_grid + n_edge + np.arange(n_edge)
    quads.append(np.stack([a, b, ib, ia], axis=1))
    quads = np.concatenate(quads)
    vz = np.full(src.size, z)
    vz[n_grid:] -= depth
    # only the vertices that faces use (none inside the cut-out cells)
    keep = np.unique(quads)
    remap = np.full(src.size, -1, dtype=np.int64)
    remap[keep] = np.arange(keep.size)
    quads = remap[quads].astype(np.int32)
    src, vz = src[keep], vz[keep]
    co = np.stack([gx[src], gy[src], vz], axis=1)
    mesh = bpy.data.meshes.new(name)
    mesh.vertices.add(src.size)
    mesh.vertices.foreach_set("co", co.astype(np.float32).ravel())
    n_f = quads.shape[0]
    mesh.loops.add(4 * n_f)
    mesh.loops.foreach_set("vertex_index", quads.ravel())
    mesh.polygons.add(n_f)
    mesh.polygons.foreach_set("loop_start", np.arange(0, 4 * n_f, 4, dtype=np.int32))
    mesh.polygons.foreach_set("loop_total", np.full(n_f, 4, dtype=np.int32))
    loop_v = src[quads.ravel()]
    uv = mesh.uv_layers.new(name="UVMap")
    uv.data.foreach_set("uv", np.stack([(gx[loop_v] - x0) / w, (gy[loop_v] - y0) / h],
                                       axis=1).astype(np.float32).ravel())
    hu = mesh.uv_layers.new(name="heights")
    hu.data.foreach_set("uv", np.stack([((loop_v % n_w) + 0.5) / n_w,
                                        ((loop_v // n_w) + 0.5) / n_h],
                                       axis=1).astype(np.float32).ravel())
    mesh.uv_layers.active = uv
    # smooth shading: the surface's normals, for the visible material
    mesh.polygons.foreach_set("use_smooth", np.ones(n_f, dtype=bool))
    mesh.update(calc_edges=True)
    mesh.validate()
    return mesh


def add_waves(obj, img, name):
    """The Displace modifier that raises the wave mesh's vertices to their
    height samples: the image (metres, Non-Color: R = G = 0, B the height)
    at UV "heights", nearest texel (the UVs sit at texel centres), as a
    displacement vector (RGB to XYZ in the object's axes, which are the
    world's), strength 1, mid-level 0, negative values kept (use_clamp
    off)."""
    tex = bpy.data.textures.new(name, type="IMAGE")
    tex.image = img
    tex.extension = "EXTEND"
    tex.use_interpolation = False
    tex.use_mipmap = False
    # Blender sets negative texture values to zero for displacement by default
    tex.use_clamp = False
    follow_frames(tex.image_user, img)
    mod = obj.modifiers.new("seabake_waves", "DISPLACE")
    mod.texture = tex
    mod.texture_coords = "UV"
    mod.uv_layer = "heights"
    mod.direction = "RGB_TO_XYZ"
    mod.space = "LOCAL"
    mod.strength = 1.0
    mod.mid_level = 0.0
    return mod


def sea_point(hz, arc, az):
    """The world point of the sea at map distance arc (m) and azimuth az
    (rad) from the nadir point: flat, on z = 0; spherical, the azimuthal
    equidistant map point placed on the sphere (sea_camera_sea_point)."""
    x0, y0 = hz["nadir_m"]
    dx, dy = arc * math.cos(az), arc * math.sin(az)
    if hz["earth"] != "spherical":
        return (x0 + dx, y0 + dy, 0.0)
    r = float(hz["earth_radius_m"])
    a = arc / r
    horiz = r * math.sin(a)
    ux, uy = (dx / arc, dy / arc) if arc > 0.0 else (0.0, 0.0)
    return (x0 + horiz * ux, y0 + horiz * uy, r * math.cos(a) - r)


def horizon_mesh(name, hz, z, cut=()):
    """The low-resolution sea to the horizon: the manifest's polar grid of
    nodes, each at its sea point, lowered by z (< 0) below the rings, the
    cells whose centre lies in a rectangle of cut (x0, y0, x1, y1) left out
    (the rings with waves); UVs
    at the map's texel centres (node (i, j) -> ((j + 1/2) / n_az,
    (i + 1/2) / n_arc)); quads, a triangle where the first ring is the
    nadir point itself (the mesh2 of sea.inc)."""
    arcs = [float(a) for a in hz["arc_m"]]
    azs = [math.radians(float(a)) for a in hz["azimuth_deg"]]
    na, nz = len(arcs), len(azs)
    verts = []
    for a in arcs:
        for t in azs:
            x, y, h = sea_point(hz, a, t)
            verts.append((x, y, h + z))
    faces = []
    for i in range(na - 1):
        for j in range(nz - 1):
            k = i * nz + j
            face = (k, k + 1, k + nz + 1, k + nz) if arcs[i] > 0.0 else (k, k + nz + 1, k + nz)
            # under a ring with waves (cut): left out
            cx = sum(verts[q][0] for q in face) / len(face)
            cy = sum(verts[q][1] for q in face) / len(face)
            if any(x0 < cx < x1 and y0 < cy < y1 for x0, y0, x1, y1 in cut):
                continue
            faces.append(face)
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    uv = mesh.uv_layers.new(name="UVMap")
    for loop in mesh.loops:
        i, j = divmod(loop.vertex_index, nz)
        uv.data[loop.index].uv = ((j + 0.5) / nz, (i + 0.5) / na)
    mesh.validate()
    mesh.update()
    return mesh


# ---------------------------------------------------------------- materials

def new_material(name):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    out.location = (600, 0)
    return mat, nt, out


# The frames of image sequences, (first, count), set by build() for a bake
# of several frames; None for one frame.
SEQUENCE = None


def follow_frames(iu, img):
    """An image user that shows each scene frame its own file of a
    sequence (nothing for a single image)."""
    if SEQUENCE is not None and img.source == "SEQUENCE":
        # Scene frame f reads file number (f - frame_start) + 1 + offset: the
        # files are numbered by frame, so offset = first - 1 gives file f.
        first, count = SEQUENCE
        iu.frame_start = first
        iu.frame_offset = first - 1
        iu.frame_duration = count
        iu.use_cyclic = False
        iu.use_auto_refresh = True


def image_node(nt, img, interpolation, location):
    node = nt.nodes.new("ShaderNodeTexImage")
    node.image = img
    node.interpolation = interpolation
    follow_frames(node.image_user, img)
    # Edges clamp (as POV-Ray's maps): REPEAT would blend the opposite edge
    # into the outermost half texel.
    node.extension = "EXTEND"
    node.location = location
    return node


# The sensor's image projected from its position (--emission-space sensor):
# set by build() to (image, camera object, focal / width, focal / height).
SENSOR = None


def sensor_projection(nt, em_map):
    """The projected sensor image where the sensor sees, em_map elsewhere:
    the shading point in the camera's axes (x right, y up, -z forward),
    u = 1/2 + (f / W) x / -z, v = 1/2 + (f / H) y / -z (Blender's image
    origin is the bottom row, as the image's row H - 1), seen when -z > 0
    and 0 <= u, v <= 1.  Returns the shader to wire to the output."""
    img, cam_obj, kx, ky = SENSOR
    tc = nt.nodes.new("ShaderNodeTexCoord")
    tc.object = cam_obj
    tc.location = (-1200, -300)
    sep = nt.nodes.new("ShaderNodeSeparateXYZ")
    sep.location = (-1000, -300)
    nt.links.new(tc.outputs["Object"], sep.inputs["Vector"])
    depth = math_node(nt, "MULTIPLY", sep.outputs["Z"], -1.0, (-800, -500))
    u = math_node(nt, "DIVIDE", sep.outputs["X"], depth, (-800, -200))
    u = math_node(nt, "MULTIPLY_ADD", u, kx, (-600, -200))
    u.node.inputs[2].default_value = 0.5
    v = math_node(nt, "DIVIDE", sep.outputs["Y"], depth, (-800, -350))
    v = math_node(nt, "MULTIPLY_ADD", v, ky, (-600, -350))
    v.node.inputs[2].default_value = 0.5
    comb = nt.nodes.new("ShaderNodeCombineXYZ")
    comb.location = (-400, -300)
    nt.links.new(u, comb.inputs["X"])
    nt.links.new(v, comb.inputs["Y"])
    tex = image_node(nt, img, "Linear", (-200, -300))
    nt.links.new(comb.outputs["Vector"], tex.inputs["Vector"])
    em = nt.nodes.new("ShaderNodeEmission")
    em.location = (100, -300)
    em.inputs["Strength"].default_value = 1.0
    nt.links.new(tex.outputs["Color"], em.inputs["Color"])
    # seen: depth > 0, u and v in [0, 1] (1 - (x < 0) - (x > 1) for each)
    seen = math_node(nt, "GREATER_THAN", depth, 0.0, (-600, -600))
    for k, c in enumerate((u, v)):
        lo = math_node(nt, "LESS_THAN", c, 0.0, (-400, -600 - 150 * k))
        hi = math_node(nt, "GREATER_THAN", c, 1.0, (-400, -675 - 150 * k))
        out_k = math_node(nt, "SUBTRACT", 1.0, lo, (-200, -600 - 150 * k))
        out_k = math_node(nt, "SUBTRACT", out_k, hi, (0, -600 - 150 * k))
        seen = math_node(nt, "MULTIPLY", seen, out_k, (200, -600 - 150 * k))
    mix = nt.nodes.new("ShaderNodeMixShader")
    mix.location = (400, 0)
    nt.links.new(seen, mix.inputs["Fac"])
    nt.links.new(em_map.outputs["Emission"], mix.inputs[1])
    nt.links.new(em.outputs["Emission"], mix.inputs[2])
    return mix.outputs["Shader"]


def emission_material(name, constant=None, img=None,
                      interpolation="Linear"):
    """Emission: the map's colour (a grey map: Blender gives Y as R = G = B;
    or a constant) emitted with strength 1; with
    SENSOR, the sensor's image projected where the sensor sees."""
    mat, nt, out = new_material(name)
    em = nt.nodes.new("ShaderNodeEmission")
    em.location = (300, 0)
    em.inputs["Strength"].default_value = 1.0
    if img is not None:
        tex = image_node(nt, img, interpolation, (0, 0))
        nt.links.new(tex.outputs["Color"], em.inputs["Color"])
    else:
        em.inputs["Color"].default_value = (constant, constant, constant, 1.0)
    shader = em.outputs["Emission"] if SENSOR is None else sensor_projection(nt, em)
    nt.links.new(shader, out.inputs["Surface"])
    return mat


def blender_anisotropy(a):
    """Principled's Anisotropic A from seabake's a = (l1 - l2) / (l1 + l2).
    Principled (GGX) gives alpha_x / alpha_y = 1 / (1 - 0.9 A); the slope
    widths' ratio is sqrt(l1 / l2) = sqrt((1 + a) / (1 - a)), so
    A = (1 - sqrt((1 - a) / (1 + a))) / 0.9, clamped to [0, 1]."""
    if a >= 1.0:
        return 1.0
    return min(1.0, max(0.0, (1.0 - math.sqrt((1.0 - a) / (1.0 + a))) / 0.9))


def math_node(nt, op, a, b, location, clamp=False):
    node = nt.nodes.new("ShaderNodeMath")
    node.operation = op
    node.use_clamp = clamp
    node.location = location
    for k, v in enumerate((a, b)):
        if isinstance(v, (int, float)):
            node.inputs[k].default_value = v
        else:
            nt.links.new(v, node.inputs[k])
    return node.outputs[0]


def visible_material(name, normal_img=None, rough_img=None, constants=None):
    """Visible: Principled BSDF with the normal map (tangent space of the UV
    map: +x east, +y north; none on a mesh with the waves, whose geometry
    has the facets' slopes) and the roughness map; constants (roughness,
    anisotropy, rotation) for a low-resolution level."""
    mat, nt, out = new_material(name)
    bsdf = nt.nodes.new("ShaderNodeBsdfPrincipled")
    bsdf.location = (300, 0)
    bsdf.inputs["Base Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    bsdf.inputs["Metallic"].default_value = 0.0
    # Water, n = 1.33: F0 = 0.02 = 0.08 Specular (Blender 3); Blender 4
    # renamed the socket "Specular IOR Level", whose 0.5 takes F0 from the
    # IOR (untested here: Debian's Blender is 3.4).
    if "Specular" in bsdf.inputs:
        bsdf.inputs["Specular"].default_value = 0.25
    elif "Specular IOR Level" in bsdf.inputs:
        bsdf.inputs["Specular IOR Level"].default_value = 0.5
    bsdf.inputs["IOR"].default_value = 1.33
    nt.links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    # The anisotropy axes follow the UV map's u (east); unlinked, Cycles
    # would use a tangent radial around the object's z axis.
    tan = nt.nodes.new("ShaderNodeTangent")
    tan.direction_type = "UV_MAP"
    tan.uv_map = "UVMap"
    tan.location = (0, -500)
    nt.links.new(tan.outputs["Tangent"], bsdf.inputs["Tangent"])
    if rough_img is None:
        r, a, rot = constants
        bsdf.inputs["Roughness"].default_value = r
        bsdf.inputs["Anisotropic"].default_value = blender_anisotropy(a)
        bsdf.inputs["Anisotropic Rotation"].default_value = rot
        return mat
    if normal_img is not None:
        ntex = image_node(nt, normal_img, "Linear", (-600, 200))
        nmap = nt.nodes.new("ShaderNodeNormalMap")
        nmap.space = "TANGENT"
        nmap.uv_map = "UVMap"
        nmap.location = (-300, 200)
        nt.links.new(ntex.outputs["Color"], nmap.inputs["Color"])
        nt.links.new(nmap.outputs["Normal"], bsdf.inputs["Normal"])
    rtex = image_node(nt, rough_img, "Linear", (-900, -200))
    sep = nt.nodes.new("ShaderNodeSeparateColor")
    sep.location = (-600, -200)
    nt.links.new(rtex.outputs["Color"], sep.inputs["Color"])
    nt.links.new(sep.outputs["Red"], bsdf.inputs["Roughness"])
    nt.links.new(sep.outputs["Blue"], bsdf.inputs["Anisotropic Rotation"])
    # blender_anisotropy as nodes.
    a = sep.outputs["Green"]
    q = math_node(nt, "DIVIDE", math_node(nt, "SUBTRACT", 1.0, a, (-400, -350)),
                  math_node(nt, "ADD", 1.0, a, (-400, -450)), (-250, -400))
    s = math_node(nt, "SUBTRACT", 1.0, math_node(nt, "SQRT", q, 0.0, (-100, -400)), (50, -400))
    aniso = math_node(nt, "DIVIDE", s, 0.9, (200, -400), clamp=True)
    nt.links.new(aniso, bsdf.inputs["Anisotropic"])
    return mat


def lr_constants(moments):
    """Roughness, anisotropy and rotation of a low-resolution facet, as
    sea_bake_roughness computes them for the maps."""
    mx, my = moments["mx"], moments["my"]
    cxx = moments["mxx"] - mx * mx
    cyy = moments["myy"] - my * my
    cxy = moments["mxy"] - mx * my
    tr = max(cxx + cyy, 0.0)
    rough = math.sqrt(math.sqrt(tr))
    d = math.hypot(cxx - cyy, 2.0 * cxy)
    aniso = min(1.0, d / tr) if tr > 0.0 else 0.0
    theta = 0.5 * math.atan2(2.0 * cxy, cxx - cyy) if d > 0.0 else 0.0
    if theta < 0.0:
        theta += math.pi
    if theta >= math.pi:
        theta -= math.pi
    return rough, aniso, theta / (2.0 * math.pi)


# ------------------------------------------------------------ camera, world

def make_camera(scene, cam):
    """The pinhole sensor: -Z along forward, +Y along up, +X along right."""
    width, height = int(cam["width"]), int(cam["height"])
    fwd, right, up = cam["forward"], cam["right"], cam["up"]
    data = bpy.data.cameras.new("seabake_sensor")
    data.type = "PERSP"
    data.sensor_fit = "HORIZONTAL"
    # focal length in pixels -> mm on a sensor of sensor_width mm over width
    # pixels; the field of view is then exactly hfov.
    data.lens = data.sensor_width * float(cam["focal_px"]) / width
    alt = max(float(cam["position_m"][2]), 1e-3)
    data.clip_start = min(0.1, 1e-3 * alt)
    data.clip_end = 4.0 * LR_REACH * alt
    obj = bpy.data.objects.new("seabake_sensor", data)
    scene.collection.objects.link(obj)
    mw = Matrix(((right[0], up[0], -fwd[0], cam["position_m"][0]),
                 (right[1], up[1], -fwd[1], cam["position_m"][1]),
                 (right[2], up[2], -fwd[2], cam["position_m"][2]),
                 (0.0, 0.0, 0.0, 1.0)))
    obj.matrix_world = mw
    scene.camera = obj
    scene.render.resolution_x = width
    scene.render.resolution_y = height
    scene.render.resolution_percentage = 100
    scene.render.pixel_aspect_x = scene.render.pixel_aspect_y = 1.0
    hfov = math.degrees(data.angle_x)
    if abs(hfov - float(cam["hfov_deg"])) > 1e-4:
        print("seabake_import: warning: field of view %.6f deg, manifest says %.6f deg"
              % (hfov, cam["hfov_deg"]), file=sys.stderr)
    return obj


# A directional sky's image: SKY_TEXELS texels uniform in s = sqrt(max(cos
# zenith, 0)) from 0 to 1, each the manifest's table (linear between its
# nodes) at its s; Cycles interpolates them linearly again.  The image's
# interpolation departs from the table's only in the texels holding a
# node, by at most a quarter texel times the change of slope there: for
# clear skies at 10 um 9.8e-7 relative where the table itself is within
# 8.4e-6 of the sky (zenith emissivity 0.3, tests/scenes/pov_horizon_sky.ini),
# 1.3e-5 where it is within 1.3e-4 (0.01).
SKY_TEXELS = 4096


def make_world(scene, value, colour=(1.0, 1.0, 1.0), table=None):
    """The World: one value (x colour) everywhere, or with a sky table the
    sky toward each camera ray, looked up by its direction's z (Texture
    Coordinate Generated is the ray's unit direction in a world shader)."""
    world = bpy.data.worlds.new("seabake_sky")
    world.use_nodes = True
    nt = world.node_tree
    bg = nt.nodes["Background"]
    bg.inputs["Color"].default_value = (value * colour[0], value * colour[1], value * colour[2],
                                        1.0)
    bg.inputs["Strength"].default_value = 1.0
    if table is not None:
        s_nodes, values = table
        n = SKY_TEXELS
        row = np.interp(np.linspace(0.0, 1.0, n), np.array(s_nodes), np.array(values))
        img = bpy.data.images.new("seabake_sky", n, 1, alpha=False, float_buffer=True)
        img.colorspace_settings.name = "Non-Color"
        px = np.ones((n, 4), dtype=np.float32)
        px[:, 0] = px[:, 1] = px[:, 2] = row
        img.pixels.foreach_set(px.ravel())
        img.file_format = "OPEN_EXR"
        img.pack()
        coord = nt.nodes.new("ShaderNodeTexCoord")
        xyz = nt.nodes.new("ShaderNodeSeparateXYZ")
        clamp = nt.nodes.new("ShaderNodeMath")
        clamp.operation = "MAXIMUM"
        clamp.inputs[1].default_value = 0.0
        root = nt.nodes.new("ShaderNodeMath")
        root.operation = "SQRT"
        # texel i's centre, (i + 1/2) / n, holds s = i / (n - 1)
        u = nt.nodes.new("ShaderNodeMath")
        u.operation = "MULTIPLY_ADD"
        u.inputs[1].default_value = (n - 1.0) / n
        u.inputs[2].default_value = 0.5 / n
        uv = nt.nodes.new("ShaderNodeCombineXYZ")
        uv.inputs["Y"].default_value = 0.5
        tex = nt.nodes.new("ShaderNodeTexImage")
        tex.image = img
        tex.interpolation = "Linear"
        tex.extension = "EXTEND"
        nt.links.new(coord.outputs["Generated"], xyz.inputs[0])
        nt.links.new(xyz.outputs["Z"], clamp.inputs[0])
        nt.links.new(clamp.outputs[0], root.inputs[0])
        nt.links.new(root.outputs[0], u.inputs[0])
        nt.links.new(u.outputs[0], uv.inputs["X"])
        nt.links.new(uv.outputs[0], tex.inputs["Vector"])
        nt.links.new(tex.outputs["Color"], bg.inputs["Color"])
    scene.world = world


def make_sun(scene, sun):
    """A Sun lamp toward the manifest's sun (its zenith angle, and its
    azimuth counter-clockwise from east as in seabake's [sun]) with its
    angular diameter; None when the sun is below the horizon."""
    zen = math.radians(float(sun["zenith_deg"]))
    if zen >= math.pi / 2:
        return None
    az = math.radians(float(sun["azimuth_deg"]))
    s = (math.sin(zen) * math.cos(az), math.sin(zen) * math.sin(az), math.cos(zen))
    # A Sun lamp shines along its local -Z: local Z is the direction toward
    # the sun, X horizontal.
    x = (-math.sin(az), math.cos(az), 0.0)
    y = (s[1] * x[2] - s[2] * x[1], s[2] * x[0] - s[0] * x[2], s[0] * x[1] - s[1] * x[0])
    data = bpy.data.lights.new("seabake_sun", type="SUN")
    data.energy = SUN_STRENGTH
    omega = float(sun.get("solid_angle_sr", 6.8e-5))
    data.angle = 2.0 * math.acos(max(-1.0, 1.0 - omega / (2.0 * math.pi)))
    obj = bpy.data.objects.new("seabake_sun", data)
    obj.matrix_world = Matrix(((x[0], y[0], s[0], 0.0), (x[1], y[1], s[1], 0.0),
                               (x[2], y[2], s[2], 1000.0), (0.0, 0.0, 0.0, 1.0)))
    scene.collection.objects.link(obj)
    return obj


def set_frames(scene, m, first, last):
    """The scene's frame range and rate: the bake's."""
    scene.frame_start = first
    scene.frame_end = last
    rate = float(m.get("frame_rate_hz") or 25.0)
    fps = max(1, min(120, int(round(rate))))
    scene.render.fps = fps
    scene.render.fps_base = fps / rate


def render_settings(scene, material="emission"):
    scene.render.engine = "CYCLES"
    cy = scene.cycles
    cy.device = "CPU"
    cy.samples = SAMPLES if material == "emission" else SAMPLES_VISIBLE
    cy.use_adaptive_sampling = False
    cy.use_denoising = False
    cy.max_bounces = 0 if material == "emission" else BOUNCES_VISIBLE
    # The default pixel filter (1.5 px) blends neighbours: a tiny one gives
    # the value at the pixel centre, as seabake render samples it.
    cy.filter_width = 0.01
    cy.seed = 0
    vs = scene.view_settings
    vs.view_transform = "Standard"
    vs.look = "None"
    vs.exposure = 0.0
    vs.gamma = 1.0
    scene.display_settings.display_device = "sRGB"
    scene.render.use_compositing = False
    scene.render.use_sequencer = False
    scene.render.film_transparent = False
    im = scene.render.image_settings
    im.file_format = "OPEN_EXR"
    im.color_mode = "RGB"
    im.color_depth = "32"
    im.exr_codec = "ZIP"
    scene.render.use_file_extension = False


# --------------------------------------------------------------------- main

def build(manifest_path, frame, material, single_frame=False, max_level=None, projection=True):
    global SEQUENCE, SENSOR
    m = load_manifest(manifest_path)
    first, last = frame_range(m, manifest_path)
    if frame is not None and not first <= frame <= last:
        fail("%s: frame %d was not baked (frames %d to %d)" % (manifest_path, frame, first, last))
    if single_frame:
        # --single-frame: that frame's files alone, as a bake of one frame.
        first = last = first if frame is None else frame
    if max_level is not None and not any(lv["index"] <= max_level for lv in m["levels"]):
        fail("%s: no level of index %d or finer (levels %s)"
             % (manifest_path, max_level, [lv.get("index") for lv in m["levels"]]))
    SEQUENCE = (first, last - first + 1) if last > first else None
    directory = os.path.dirname(os.path.abspath(manifest_path))
    scale = float(m["emission_scale"])
    cam = m["camera"]
    if cam.get("earth") == "spherical" and "horizon" not in m:
        print("seabake_import: warning: the scene's Earth is spherical; this import is "
              "flat (the rings lie at z = 0 in map coordinates), so views near the "
              "horizon are approximate", file=sys.stderr)
    sky = sky_scaled(m, manifest_path)

    # A clean scene: --factory-startup has a cube, a light and a camera.
    # Only this scene's: the add-on imports into a new scene, and the
    # user's other scenes keep their objects.
    for obj in list(bpy.context.scene.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    scene = bpy.context.scene
    set_frames(scene, m, first, last)
    render_settings(scene, material)
    cam_obj = make_camera(scene, cam)
    SENSOR = None
    sensor = m.get("sensor") if projection else None
    if sensor is not None:
        # A sequence is loaded from its first frame's file.
        entries = sensor.get("frames") or fail("%s: \"sensor\" lists no frames" % manifest_path)
        entry = entries[0] if SEQUENCE else next(
            (e for e in entries if frame is None or int(e["frame"]) == frame), None)
        if entry is None:
            fail("%s: no sensor image for frame %d" % (manifest_path, frame))
        focal = float(cam["focal_px"])
        SENSOR = (load_map(directory, entry["exr"], 1, manifest_path), cam_obj,
                  focal / int(cam["width"]), focal / int(cam["height"]))
    sun = None
    if material == "visible":
        make_world(scene, 1.0, SKY_VISIBLE)
        sun = make_sun(scene, m.get("scene", {}).get("sun", {"zenith_deg": 90.0}))
    else:
        make_world(scene, sky, table=sky_table(m, manifest_path))

    levels = m["levels"]
    finest = min(float(lv["facet_m"]) for lv in levels)
    far = LR_REACH * float(cam["position_m"][2])
    coll = bpy.data.collections.new("seabake_sea")
    scene.collection.children.link(coll)
    rings = 0
    waves = 0
    horizon = m.get("horizon")
    horizon_built = False
    for lv in levels:
        idx = lv["index"]
        if max_level is not None and idx > max_level:
            continue  # --max-level: the finer levels only
        if lv["low_res"]:
            x0 = cam["position_m"][0] - far
            y0 = cam["position_m"][1] - far
            w = h = 2.0 * far
        else:
            x0, y0 = lv["origin_m"]
            w, h = lv["extent_m"]
        kind, hole = clip_hole(x0, y0, w, h, lv.get("hole"))
        if lv["low_res"] and horizon is not None:
            # The low-resolution sea as the sensor sees it, to the horizon.
            rank = sum(1 for o in levels if not o["low_res"])
            # cut out under the rings with waves (whose troughs dip below it)
            cut = [level_rect(o) for o in levels
                   if not o["low_res"] and "height" in o["frames"][0]]
            mesh = horizon_mesh("seabake_horizon", horizon, -LAYER * finest * rank, cut)
            img = load_map(directory, horizon["exr"], 1, manifest_path)
            em = emission_material("seabake_emission_%d" % idx, img=img)
            vis = visible_material("seabake_visible_%d" % idx,
                                   constants=lr_constants(lv["moments"]))
            em.use_fake_user = True
            vis.use_fake_user = True
            mesh.materials.append(em if material == "emission" else vis)
            obj = bpy.data.objects.new("seabake_horizon", mesh)
            coll.objects.link(obj)
            horizon_built = True
            continue
        if kind == 2:
            print("seabake_import: level %d is covered by the finer levels: no ring" % idx)
            continue
        rank = sum(1 for o in levels if o["facet_m"] < lv["facet_m"])
        height = None if lv["low_res"] else \
            frame_entry(lv, None if SEQUENCE else frame, manifest_path).get("height")
        if height is not None:
            # the waves: every finer level's rectangle cut out, a skirt as
            # deep as the heights' spread over the frames
            finer = [level_rect(o) for o in levels
                     if not o["low_res"] and o["facet_m"] < lv["facet_m"]]
            spans = [e["height"] for e in lv["frames"] if "height" in e]
            depth = max(e["max_m"] for e in spans) - min(e["min_m"] for e in spans) + 1.0
            mesh = wave_mesh("seabake_level_%d" % idx, x0, y0, w, h, int(height["width"]),
                             int(height["height"]), finer, -LAYER * finest * rank, depth)
        else:
            mesh = ring_mesh("seabake_level_%d" % idx, x0, y0, w, h, kind, hole,
                             -LAYER * finest * rank)
        if lv["low_res"]:
            const = float(lv["optics"]["radiance"]) * scale
            em = emission_material("seabake_emission_%d" % idx, constant=const)
            vis = visible_material("seabake_visible_%d" % idx,
                                   constants=lr_constants(lv["moments"]))
        else:
            # A sequence is loaded from its first frame's files.
            files = frame_entry(lv, None if SEQUENCE else frame, manifest_path)["files"]
            imgs = {}
            for group, names in files.items():
                n_ch = len(lv.get("maps", {}).get(group, [])) or 3
                imgs[group] = load_map(directory, names["exr"], n_ch, manifest_path)
            for need in ("emission", "normal", "roughness"):
                if need not in imgs:
                    fail("%s: level %d has no %s map" % (manifest_path, idx, need))
            em = emission_material("seabake_emission_%d" % idx, img=imgs["emission"])
            vis = visible_material("seabake_visible_%d" % idx,
                                   normal_img=imgs["normal"] if height is None else None,
                                   rough_img=imgs["roughness"])
        # The other material stays in the .blend for switching.
        em.use_fake_user = True
        vis.use_fake_user = True
        mesh.materials.append(em if material == "emission" else vis)
        obj = bpy.data.objects.new("seabake_level_%d" % idx, mesh)
        coll.objects.link(obj)
        if height is not None:
            if "exr" not in height:
                fail("%s: level %d has heights but no EXR of them" % (manifest_path, idx))
            add_waves(obj, load_map(directory, height["exr"], 3, manifest_path),
                      "seabake_waves_%d" % idx)
            waves += 1
        rings += 1
    scene.frame_set(first if frame is None else frame)
    print("seabake_import: %d ring%s%s%s of %d levels%s, %s, material %s%s, emission scale %g"
          % (rings, "" if rings == 1 else "s",
             " (%d with waves)" % waves if waves else "",
             " and the horizon mesh (%d x %d nodes)"
             % (len(horizon["arc_m"]), len(horizon["azimuth_deg"])) if horizon_built else "",
             len(levels),
             ", the sensor's image projected where it sees" if SENSOR is not None else "",
             "frame %d" % first if last == first else
             "frames %d to %d at %g Hz (now %d)" % (first, last, float(m["frame_rate_hz"]),
                                                    scene.frame_current),
             material,
             "" if material == "emission" else
             (", sun at %.1f deg from zenith" % float(m["scene"]["sun"]["zenith_deg"])
              if sun is not None else ", sun below the horizon: no lamp"),
             scale))
    return m


def parse_args(argv):
    p = argparse.ArgumentParser(
        prog="seabake_import.py",
        description="Builds a Blender scene from a seabake bake (manifest.json).")
    p.add_argument("manifest", help="DIR/manifest.json written by seabake bake --blender")
    p.add_argument("--frame", type=int, default=None,
                   help="the baked frame to show (default: the first)")
    p.add_argument("--material", choices=("emission", "visible"), default="emission",
                   help="the active material of the sea (default: emission)")
    p.add_argument("--single-frame", action="store_true",
                   help="load only the --frame's maps (default: the first frame's) as still "
                        "images, the scene's frame range that frame alone (default: every "
                        "baked frame, as image sequences)")
    p.add_argument("--max-level", type=int, default=None, metavar="N",
                   help="import the levels of index N and finer only (0 is the finest; "
                        "default: every level, the low-resolution sea included)")
    p.add_argument("--no-projection", action="store_true",
                   help="the maps everywhere, even where the bake has the sensor's image "
                        "(bake --emission-space sensor; default: that image where the sensor "
                        "sees)")
    p.add_argument("--save", metavar="FILE.blend", help="save the scene")
    p.add_argument("--render", metavar="OUT.exr",
                   help="render the current frame with Cycles to a 32-bit EXR")
    p.add_argument("--render-frames", metavar="OUT_#.exr",
                   help="render every baked frame (frame_set, then Cycles), the frame "
                        "number written over the run of '#' (zero-padded to its length)")
    args = p.parse_args(argv)
    if args.render_frames is not None and "#" not in args.render_frames:
        p.error("--render-frames: %r has no '#' for the frame number" % args.render_frames)
    return args


def frame_file(pattern, frame):
    """pattern with its last run of '#' replaced by the zero-padded frame."""
    end = pattern.rindex("#") + 1
    start = end
    while start > 0 and pattern[start - 1] == "#":
        start -= 1
    return pattern[:start] + "%0*d" % (end - start, frame) + pattern[end:]


def render_still(scene, path):
    """The current frame, rendered by Cycles to path (a 32-bit EXR)."""
    scene.render.filepath = os.path.abspath(path)
    bpy.ops.render.render(write_still=True)
    if not os.path.isfile(scene.render.filepath):
        fail("%s: the render was not written" % path)


def import_bake(manifest_path, frame=None, material="emission", single_frame=False,
                max_level=None, projection=True, save=None, render=None, render_frames=None):
    """The import into the current scene (bpy.context.scene), which it
    empties first, then the optional save and renders: what the command line
    and the add-on's File > Import operator both run.  Arguments as the
    command line's switches (projection=False is --no-projection).  Raises
    ImportError_ with a message naming the file.  Returns the manifest."""
    m = build(manifest_path, frame, material, single_frame, max_level, projection)
    scene = bpy.context.scene
    if save:
        bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(save))
    if render:
        render_still(scene, render)
    if render_frames:
        current = scene.frame_current
        for f in range(scene.frame_start, scene.frame_end + 1):
            scene.frame_set(f)
            render_still(scene, frame_file(render_frames, f))
        scene.frame_set(current)
    return m


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    args = parse_args(argv)
    try:
        import_bake(args.manifest, args.frame, args.material, args.single_frame,
                    args.max_level, not args.no_projection, args.save, args.render,
                    args.render_frames)
    except ImportError_ as e:
        print("seabake_import: error: %s" % e, file=sys.stderr)
        sys.exit(1)
    except Exception:
        traceback.print_exc()
        print("seabake_import: error: unexpected failure (see above)", file=sys.stderr)
        sys.exit(1)


# ------------------------------------------------------------------- add-on
# The add-on (seabake-blender.zip: seabake/__init__.py registers this
# module): File > Import > seabake bake (manifest.json) runs import_bake
# with the options below, each one a switch of the command line.

class IMPORT_SCENE_OT_seabake(bpy.types.Operator, ImportHelper):
    """Import a seabake bake (manifest.json) into a new scene"""
    bl_idname = "import_scene.seabake"
    bl_label = "Import seabake bake"
    bl_options = {"REGISTER", "UNDO"}

    filename_ext = ".json"
    filter_glob: StringProperty(default="*.json", options={"HIDDEN"})
    frames: EnumProperty(
        name="Frames",
        items=(("ALL", "All", "Every baked frame, as image sequences: the scene's frame "
                "range is the bake's"),
               ("ONE", "One", "Only the frame below, as still images (--single-frame)")),
        default="ALL")
    frame: IntProperty(name="Frame", default=0,
                       description="The baked frame to load (Frames: One; --frame)")
    levels: EnumProperty(
        name="Levels",
        items=(("ALL", "All", "Every level, the low-resolution sea to the horizon included"),
               ("UP_TO", "Up to", "The levels of index Max Level and finer only (--max-level)")),
        default="ALL")
    max_level: IntProperty(name="Max Level", default=0, min=0,
                           description="The coarsest level imported (0 is the finest)")
    projection: BoolProperty(
        name="Sensor projection", default=True,
        description="The sensor's image where the sensor sees, when the bake has it "
                    "(bake --emission-space sensor); off: the maps everywhere "
                    "(--no-projection)")
    material: EnumProperty(
        name="Material",
        items=(("emission", "Infrared", "The infrared radiance emitted (the maps' values "
                "render exactly)"),
               ("visible", "Visible", "Principled BSDF with the normal and roughness maps, a "
                "sun lamp and a sky (--material visible)")),
        default="emission")

    def draw(self, context):
        layout = self.layout
        layout.prop(self, "frames")
        row = layout.row()
        row.active = self.frames == "ONE"
        row.prop(self, "frame")
        layout.prop(self, "levels")
        row = layout.row()
        row.active = self.levels == "UP_TO"
        row.prop(self, "max_level")
        layout.prop(self, "projection")
        layout.prop(self, "material")

    def execute(self, context):
        # A new scene, shown in the window: the import empties the scene it
        # builds and sets its camera, world and render settings, which must
        # not be the user's.
        window = context.window
        if window is None:
            self.report({"ERROR"}, "seabake: no window to show the imported scene in")
            return {"CANCELLED"}
        previous = window.scene
        name = os.path.basename(os.path.dirname(os.path.abspath(self.filepath)))
        scene = bpy.data.scenes.new(name or "seabake")
        window.scene = scene
        try:
            import_bake(self.filepath,
                        frame=self.frame if self.frames == "ONE" else None,
                        material=self.material,
                        single_frame=self.frames == "ONE",
                        max_level=self.max_level if self.levels == "UP_TO" else None,
                        projection=self.projection)
        except Exception as e:
            window.scene = previous
            bpy.data.scenes.remove(scene)
            if isinstance(e, ImportError_):
                self.report({"ERROR"}, "seabake_import: error: %s" % e)
            else:
                traceback.print_exc()
                self.report({"ERROR"}, "seabake_import: error: unexpected failure: %s" % e)
            return {"CANCELLED"}
        self.report({"INFO"}, "seabake: %s imported into scene %s"
                    % (self.filepath, scene.name))
        return {"FINISHED"}


def menu_import(self, context):
    self.layout.operator(IMPORT_SCENE_OT_seabake.bl_idname,
                         text="seabake bake (manifest.json)")


def register():
    bpy.utils.register_class(IMPORT_SCENE_OT_seabake)
    bpy.types.TOPBAR_MT_file_import.append(menu_import)


def unregister():
    bpy.types.TOPBAR_MT_file_import.remove(menu_import)
    bpy.utils.unregister_class(IMPORT_SCENE_OT_seabake)


if __name__ == "__main__":
    main()
