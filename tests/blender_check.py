# blender_check.py - the Blender side of tests/blender.sh.  Run as
#
#   blender -b --factory-startup --python-exit-code 1 --python blender_check.py --
#       DIR/manifest.json POV_DRIVER WORKDIR [--half-of FLOAT_DIR/manifest.json]
#       [--markers] [--normal-map]
#
# It imports the bake with the copy of seabake_import.py that bake --blender
# put in DIR (the script users run), then checks:
#   maps        every map the manifest lists is loaded, Non-Color,
#               CHANNEL_PACKED exactly when it has four channels, and its
#               image.pixels (rows bottom-up) equal, row-flipped, the texels
#               that seabake's own EXR reader gives (pov_driver dump): exactly,
#               for float and for half files alike, since both readers turn
#               the stored values into floats without rounding.
#   --half-of   the maps of a --format half bake against those of the float
#               bake of the same scene: |half - float| <= 2^-11 |float| +
#               2^-25, the rounding of a float to the nearest half (11
#               significant bits; 2^-25 is half the spacing of the subnormal
#               halves, for values near 0).
#   --markers   single emission texels of the finest level set to a distinct
#               value: the centroid of the change in Cycles' render lies
#               within 1 px of the pinhole projection of the texel centre
#               (from the manifest's camera), which checks the camera and the
#               UV orientation (row 0 north, v = 0 south) together.
#   --normal-map  the normal maps through Blender's Normal Map node (tangent
#               space of the UV map, the rings flat: their waves off),
#               re-encoded as 0.5 + 0.5 n, give back the map's colours: the
#               maps are in the node's encoding.
#   --waves     every level with waves, at every baked frame (frame_set):
#               each face corner's evaluated height (after the Displace
#               modifier) is its height sample (the frame's height EXR at the
#               corner's "heights" UV, seabake's reader) plus the level's
#               layer offset, or that minus the skirt's depth, within 1e-5 m
#               (float32 coordinates a few hundred metres from the origin).
# Prints one line per check; exits 1 on any failure.

import importlib.util
import math
import os
import subprocess
import sys

import bpy
import numpy as np

# One texel's change must land this close to the projection of its centre.
MARKER_MAX_PX = 1.0
# Markers only where a texel spans at least a pixel: the bilinear footprint
# of a texel (a tent two texels wide) then covers pixel centres, and its
# samples at unit spacing have their centroid at the tent's centre.
MARKER_MIN_TEXEL_PX = 1.0
MARKER_GRID = 24
N_MARKERS = 4
# Normal Map node: decode, normalise, re-encode in float32; the stored
# normals are unit up to the format's rounding (half: 2^-11 relative), which
# the node's normalisation then moves by about as much.
NORMAL_TOL = {"float": 1e-5, "half": 2e-3}
# The normals must differ from flat by much more than the tolerance, or a
# flipped axis could not be seen.
NORMAL_MIN_SLOPE_SIGNAL = 10.0
HALF_REL = 2.0 ** -11
HALF_ABS = 2.0 ** -25

failures = 0


def report(ok, msg):
    global failures
    print(("ok: " if ok else "FAIL: ") + msg)
    if not ok:
        failures += 1


def args():
    a = sys.argv[sys.argv.index("--") + 1:]
    opts = {"half_of": None, "markers": False, "normal_map": False, "waves": False}
    pos = []
    i = 0
    while i < len(a):
        if a[i] == "--half-of":
            opts["half_of"] = a[i + 1]
            i += 2
            continue
        if a[i] == "--markers":
            opts["markers"] = True
        elif a[i] == "--normal-map":
            opts["normal_map"] = True
        elif a[i] == "--waves":
            opts["waves"] = True
        else:
            pos.append(a[i])
        i += 1
    if len(pos) != 3:
        print("usage: blender_check.py -- MANIFEST POV_DRIVER WORKDIR [options]", file=sys.stderr)
        sys.exit(2)
    return pos[0], pos[1], pos[2], opts


def load_importer(manifest):
    path = os.path.join(os.path.dirname(os.path.abspath(manifest)), "seabake_import.py")
    spec = importlib.util.spec_from_file_location("seabake_import", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def dump(driver, exr, workdir):
    raw = os.path.join(workdir, os.path.basename(exr) + ".raw")
    out = subprocess.run([driver, "dump", exr, raw], capture_output=True, text=True)
    if out.returncode != 0:
        raise RuntimeError("pov_driver dump %s: %s" % (exr, out.stderr.strip()))
    w, h, n = (int(v) for v in out.stdout.split())
    return np.fromfile(raw, dtype=np.float32).reshape(h, w, 4), n


def pixels(img):
    """image.pixels as an (H, W, 4) array, row 0 at the top."""
    w, h = img.size
    buf = np.empty(w * h * 4, dtype=np.float32)
    img.pixels.foreach_get(buf)
    return buf.reshape(h, w, 4)[::-1]


def map_files(m, directory):
    """(level index, group, channels, path) of every map of the first frame,
    and the sensor's image (level None) when the bake projects it."""
    for lv in m["levels"]:
        if lv["low_res"]:
            continue
        for group, names in lv["frames"][0]["files"].items():
            yield lv["index"], group, len(lv["maps"][group]), os.path.join(directory, names["exr"])
    if "sensor" in m:
        yield None, "sensor", 1, os.path.join(directory, m["sensor"]["frames"][0]["exr"])
    for lv in m["levels"]:
        height = None if lv["low_res"] else lv["frames"][0].get("height")
        if height is not None and "exr" in height:
            yield lv["index"], "height", 3, os.path.join(directory, height["exr"])


def check_maps(m, directory, driver, workdir):
    by_path = {os.path.abspath(bpy.path.abspath(img.filepath)): img for img in bpy.data.images}
    worst = 0.0
    count = 0
    for level, group, n_ch, path in map_files(m, directory):
        name = os.path.basename(path)
        img = by_path.get(os.path.abspath(path))
        if img is None:
            report(False, "%s: not loaded by the import" % name)
            continue
        report(img.colorspace_settings.name == "Non-Color",
               "%s: colour space %s" % (name, img.colorspace_settings.name))
        want_alpha = "CHANNEL_PACKED" if n_ch == 4 else "STRAIGHT"
        report(img.alpha_mode == want_alpha,
               "%s: %d channels, alpha mode %s" % (name, n_ch, img.alpha_mode))
        ref, n = dump(driver, path, workdir)
        got = pixels(img)
        if got.shape != ref.shape or n != n_ch:
            report(False, "%s: Blender %s, seabake %s with %d channels"
                   % (name, got.shape, ref.shape, n))
            continue
        d = float(np.max(np.abs(got.astype(np.float64) - ref)))
        worst = max(worst, d)
        count += 1
        report(d == 0.0, "%s: image.pixels against seabake's reader, max |difference| %g"
               % (name, d))
    print("maps: %d compared (%s), largest difference %g" % (count, m["pixel_type"], worst))


def check_half(m, directory, float_manifest, driver, workdir):
    fdir = os.path.dirname(os.path.abspath(float_manifest))
    worst = 0.0
    for level, group, n_ch, path in map_files(m, directory):
        half, _ = dump(driver, path, workdir)
        fpath = os.path.join(fdir, os.path.basename(path))
        full, _ = dump(driver, fpath, os.path.join(workdir, "float"))
        full = full.astype(np.float64)
        err = np.abs(half.astype(np.float64) - full)
        excess = err - (HALF_REL * np.abs(full) + HALF_ABS)
        rel = float(np.max(err / np.maximum(np.abs(full), 2.0 ** -14)))
        worst = max(worst, rel)
        report(float(np.max(excess)) <= 0.0,
               "%s: half against float, max relative %.3g (bound 2^-11 = %.3g)"
               % (os.path.basename(path), rel, HALF_REL))
    print("half: largest relative rounding %.3g" % worst)


def render(scene, path):
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    img = bpy.data.images.load(path)
    img.colorspace_settings.name = "Non-Color"
    px = pixels(img).astype(np.float64)
    bpy.data.images.remove(img)
    return px


def project(cam, p):
    """Pixel (u right, v down) of world point p through the pinhole sensor."""
    d = [p[k] - cam["position_m"][k] for k in range(3)]
    dot = lambda a, b: sum(x * y for x, y in zip(a, b))
    z = dot(d, cam["forward"])
    f = cam["focal_px"]
    return (0.5 * cam["width"] + f * dot(d, cam["right"]) / z,
            0.5 * cam["height"] - f * dot(d, cam["up"]) / z)


def finest_level(m):
    hr = [lv for lv in m["levels"] if not lv["low_res"]]
    return min(hr, key=lambda lv: lv["facet_m"])


def check_markers(m, directory, scene, workdir):
    cam = m["camera"]
    W, H = int(cam["width"]), int(cam["height"])
    lv = finest_level(m)
    path = os.path.join(directory, lv["frames"][0]["files"]["emission"]["exr"])
    img = next(i for i in bpy.data.images
               if os.path.abspath(bpy.path.abspath(i.filepath)) == os.path.abspath(path))
    # The emission map has K x K texels per facet (manifest emission_texels)
    # over the level's rectangle.
    nx, ny = int(lv["emission_texels"][0]), int(lv["emission_texels"][1])
    report((nx, ny) == tuple(img.size), "markers: emission map %d x %d texels" % (nx, ny))
    x0, y0 = lv["origin_m"]
    cx, cy = lv["extent_m"][0] / nx, lv["extent_m"][1] / ny

    def centre(col, row):
        # texel (col, row) is centred at (x0 + (col + 1/2) cx, y0 + (ny - row - 1/2) cy)
        return (x0 + (col + 0.5) * cx, y0 + (ny - row - 0.5) * cy, 0.0)

    # Candidates on a grid over the map, kept where a texel spans enough
    # pixels, inside the image and apart from each other.
    chosen = []
    for b in range(1, MARKER_GRID):
        for a in range(1, MARKER_GRID):
            col = int(nx * (a + 0.3 * (b % 2)) / MARKER_GRID)
            row = int(ny * b / MARKER_GRID)
            if not (0 < col < nx - 1 and 0 < row < ny - 1):
                continue
            u, v = project(cam, centre(col, row))
            ue, ve = project(cam, centre(col + 1, row))
            un, vn = project(cam, centre(col, row - 1))
            size = min(math.hypot(ue - u, ve - v), math.hypot(un - u, vn - v))
            reach = int(math.ceil(1.5 * max(size, 1.0))) + 1
            if size < MARKER_MIN_TEXEL_PX:
                continue
            if not (reach + 1 <= u <= W - reach - 1 and reach + 1 <= v <= H - reach - 1):
                continue
            if any(math.hypot(u - c[2], v - c[3]) < 2 * (reach + c[4]) for c in chosen):
                continue
            chosen.append((col, row, u, v, reach))
            if len(chosen) == N_MARKERS:
                break
        if len(chosen) == N_MARKERS:
            break
    report(len(chosen) >= 3, "markers: %d places in level %d" % (len(chosen), lv["index"]))
    if len(chosen) < 3:
        return
    w, h = img.size
    base = np.empty(w * h * 4, dtype=np.float32)
    img.pixels.foreach_get(base)
    # Cycles reads a file image from its file, edited or not: both renders
    # use a generated float image holding the map (read from Blender's
    # buffer), first as it is, then with the markers.
    gen = bpy.data.images.new("markers", w, h, alpha=True, float_buffer=True)
    gen.colorspace_settings.name = "Non-Color"
    gen.pixels.foreach_set(base)
    nodes = [n for mat in bpy.data.materials if mat.node_tree
             for n in mat.node_tree.nodes if n.type == "TEX_IMAGE" and n.image == img]
    report(len(nodes) == 1, "markers: %d image node(s) show %s" % (len(nodes), img.name))
    for n in nodes:
        n.image = gen
    before = render(scene, os.path.join(workdir, "markers_before.exr"))
    marked = base.copy().reshape(h, w, 4)
    top = float(np.max(base))
    for col, row, _, _, _ in chosen:
        marked[h - 1 - row, col, :3] = 3.0 * top + 1.0
    gen.pixels.foreach_set(marked.ravel())
    after = render(scene, os.path.join(workdir, "markers_after.exr"))
    diff = after[:, :, 0] - before[:, :, 0]
    for k, (col, row, u, v, reach) in enumerate(chosen):
        ci, cj = int(math.floor(u)), int(math.floor(v))
        js, is_ = np.mgrid[cj - reach:cj + reach + 1, ci - reach:ci + reach + 1]
        x = np.clip(diff[cj - reach:cj + reach + 1, ci - reach:ci + reach + 1], 0.0, None)
        s = float(np.sum(x))
        if s <= 0.0:
            report(False, "marker %d (texel %d, %d): no change near (%.2f, %.2f)"
                   % (k, col, row, u, v))
            continue
        mu = float(np.sum(x * (is_ + 0.5))) / s
        mv = float(np.sum(x * (js + 0.5))) / s
        d = math.hypot(mu - u, mv - v)
        report(d <= MARKER_MAX_PX,
               "marker %d (texel %d, %d): projection (%.3f, %.3f), Cycles centroid (%.3f, %.3f), "
               "error %.3f px" % (k, col, row, u, v, mu, mv, d))
    # Nothing else may change: the whole change is within the windows.
    inside = np.zeros(diff.shape, dtype=bool)
    for col, row, u, v, reach in chosen:
        ci, cj = int(math.floor(u)), int(math.floor(v))
        inside[max(cj - reach, 0):cj + reach + 1, max(ci - reach, 0):ci + reach + 1] = True
    stray = float(np.max(np.abs(diff[~inside])))
    report(stray == 0.0, "markers: largest change outside the marker windows %g" % stray)
    for n in nodes:
        n.image = img


def emission_of(mat_name, build):
    """A material emitting build(node_tree) -> socket, strength 1."""
    mat = bpy.data.materials.new(mat_name)
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    em = nt.nodes.new("ShaderNodeEmission")
    em.inputs["Strength"].default_value = 1.0
    sock = build(nt)
    if sock is None:
        em.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    else:
        nt.links.new(sock, em.inputs["Color"])
    nt.links.new(em.outputs["Emission"], out.inputs["Surface"])
    return mat


def check_normal_map(m, directory, scene, workdir):
    normal_imgs = {}
    for level, group, _, path in map_files(m, directory):
        if group == "normal":
            normal_imgs[level] = next(
                i for i in bpy.data.images
                if os.path.abspath(bpy.path.abspath(i.filepath)) == os.path.abspath(path))

    def tex(nt, img):
        t = nt.nodes.new("ShaderNodeTexImage")
        t.image = img
        t.interpolation = "Closest"
        t.extension = "EXTEND"
        return t.outputs["Color"]

    def decoded(nt, img):
        nm = nt.nodes.new("ShaderNodeNormalMap")
        nm.space = "TANGENT"
        nm.uv_map = "UVMap"
        nt.links.new(tex(nt, img), nm.inputs["Color"])
        ma = nt.nodes.new("ShaderNodeVectorMath")
        ma.operation = "MULTIPLY_ADD"
        nt.links.new(nm.outputs["Normal"], ma.inputs[0])
        ma.inputs[1].default_value = (0.5, 0.5, 0.5)
        ma.inputs[2].default_value = (0.5, 0.5, 0.5)
        return ma.outputs["Vector"]

    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0, 0, 0, 1)
    # the encoding against the flat rings' tangent frame: the waves off
    waves = [mod for obj in bpy.data.collections["seabake_sea"].objects
             for mod in obj.modifiers if mod.type == "DISPLACE"]
    for mod in waves:
        mod.show_render = mod.show_viewport = False
    images = {}
    for which, build in (("plain", lambda nt, img: tex(nt, img)), ("node", decoded)):
        for obj in bpy.data.collections["seabake_sea"].objects:
            # the horizon mesh (the low-resolution level) has no normal map
            level = None if obj.name == "seabake_horizon" else int(obj.name.rsplit("_", 1)[1])
            img = normal_imgs.get(level)
            mat = emission_of("check_%s_%s" % (which, level),
                              lambda nt: build(nt, img) if img is not None else None)
            obj.data.materials.clear()
            obj.data.materials.append(mat)
        images[which] = render(scene, os.path.join(workdir, "normal_%s.exr" % which))
    for mod in waves:
        mod.show_render = mod.show_viewport = True
    plain, node = images["plain"][:, :, :3], images["node"][:, :, :3]
    sea = np.any(plain > 0.0, axis=2)
    d = float(np.max(np.abs(node - plain)[sea]))
    signal = float(np.max(np.abs(plain[sea][:, :2] - 0.5)))
    tol = NORMAL_TOL[m["pixel_type"]]
    report(signal > NORMAL_MIN_SLOPE_SIGNAL * tol,
           "normal map: largest |colour - 0.5| in x, y %.3g (must exceed %g)"
           % (signal, NORMAL_MIN_SLOPE_SIGNAL * tol))
    report(d <= tol, "normal map: Normal Map node round trip over %d pixels, max |difference| "
           "%.3g (tolerance %g)" % (int(np.sum(sea)), d, tol))


def check_waves(m, directory, scene, driver, workdir):
    levels = [lv for lv in m["levels"] if not lv["low_res"] and "height" in lv["frames"][0]]
    report(len(levels) > 0, "waves: %d levels with waves" % len(levels))
    finest = min(float(lv["facet_m"]) for lv in m["levels"])
    worst, corners = 0.0, 0
    for entry in m["frames"]:
        f = int(entry["frame"])
        scene.frame_set(f)
        dg = bpy.context.evaluated_depsgraph_get()
        for lv in levels:
            fe = next(e for e in lv["frames"] if int(e["frame"]) == f)
            hgt = fe["height"]
            ref, _ = dump(driver, os.path.join(directory, hgt["exr"]), workdir)
            z_ref = ref[::-1, :, 2]  # row 0 south, as Blender's v = 0
            n_w, n_h = int(hgt["width"]), int(hgt["height"])
            rank = sum(1 for o in m["levels"] if o["facet_m"] < lv["facet_m"])
            layer = -1e-3 * finest * rank
            spans = [e["height"] for e in lv["frames"]]
            depth = max(e["max_m"] for e in spans) - min(e["min_m"] for e in spans) + 1.0
            obj = bpy.data.objects["seabake_level_%d" % lv["index"]]
            mesh = obj.evaluated_get(dg).to_mesh()
            co = np.empty(len(mesh.vertices) * 3)
            mesh.vertices.foreach_get("co", co)
            vi = np.empty(len(mesh.loops), dtype=np.int64)
            mesh.loops.foreach_get("vertex_index", vi)
            uv = np.empty(len(mesh.loops) * 2)
            mesh.uv_layers["heights"].data.foreach_get("uv", uv)
            uv = uv.reshape(-1, 2)
            k = np.floor(uv[:, 0] * n_w).astype(np.int64)
            j = np.floor(uv[:, 1] * n_h).astype(np.int64)
            d = co.reshape(-1, 3)[vi, 2] - (z_ref[j, k] + layer)
            err = np.minimum(np.abs(d), np.abs(d + depth))
            top = int(np.sum(np.abs(d) < 1e-5))
            e = float(err.max())
            worst = max(worst, e)
            corners += err.size
            report(e < 1e-5 and top > 0,
                   "waves: frame %d level %d: %d corners (%d on the surface), largest "
                   "difference from the samples %.3g m" % (f, lv["index"], err.size, top, e))
            obj.evaluated_get(dg).to_mesh_clear()
    print("waves: %d corners compared over %d frames, largest difference %.3g m"
          % (corners, len(m["frames"]), worst))


def main():
    manifest, driver, workdir, opts = args()
    os.makedirs(os.path.join(workdir, "float"), exist_ok=True)
    imp = load_importer(manifest)
    m = imp.build(manifest, None, "emission")
    directory = os.path.dirname(os.path.abspath(manifest))
    scene = bpy.context.scene
    check_maps(m, directory, driver, workdir)
    if opts["half_of"]:
        check_half(m, directory, opts["half_of"], driver, workdir)
    if opts["markers"]:
        check_markers(m, directory, scene, workdir)
    if opts["normal_map"]:
        check_normal_map(m, directory, scene, workdir)
    if opts["waves"]:
        check_waves(m, directory, scene, driver, workdir)
    print("blender_check: %d failures" % failures)
    sys.exit(1 if failures else 0)


main()
