# blender_addon.py - the add-on side of tests/blender.sh.  Run as
#
#   BLENDER_USER_CONFIG=D/config BLENDER_USER_SCRIPTS=D/scripts \
#   blender -b --factory-startup --python-exit-code 1 --python blender_addon.py --
#       ZIP MANIFEST [--render OUT.exr] [--expect-error REGEX] [OPTION=VALUE ...]
#
# As a user would: installs ZIP (seabake-blender.zip) with Preferences'
# Install... operator into the user scripts directory (which must lie under
# $BLENDER_USER_SCRIPTS, never ~/.config), enables the add-on "seabake",
# finds its entry in File > Import, then runs File > Import > seabake bake
# on MANIFEST with the operator's OPTION=VALUE (frames=ONE frame=5,
# levels=UP_TO max_level=0, projection=0, material=visible, ...).  Checks:
#   install     the package directory seabake/ in the user's add-ons with
#               __init__.py, seabake_import.py and blender_manifest.toml
#   enable      the add-on listed as enabled; bpy.ops.import_scene.seabake
#               registered and a draw function of TOPBAR_MT_file_import is the
#               add-on's menu entry
#   import      the operator finishes into a new scene shown in the window,
#               the startup scene's objects untouched
#   --expect-error  instead, the operator fails with an error matching
#               REGEX, the window back on the startup scene and no scene left
#   disable     after addon_disable the operator and the menu entry are gone
# and prints what the import built (one line each: scene, images, objects,
# materials, projection), for tests/blender.sh to check; --render renders
# the imported scene's current frame with Cycles (the settings the import
# made, as the script's --render) to OUT.exr.  Exits 1 on any failure.

import os
import re
import sys

import bpy

failures = 0


def report(ok, msg):
    global failures
    print(("ok: " if ok else "FAIL: ") + msg)
    if not ok:
        failures += 1
    return ok


def value(key, text):
    """An operator option from the command line, typed as the operator's."""
    if key in ("frame", "max_level"):
        return int(text)
    if key == "projection":
        return text not in ("0", "false", "False", "off")
    return text


def args():
    a = sys.argv[sys.argv.index("--") + 1:]
    if len(a) < 2:
        print("usage: blender_addon.py -- ZIP MANIFEST [--render OUT.exr] "
              "[--expect-error REGEX] [OPTION=VALUE ...]", file=sys.stderr)
        sys.exit(2)
    zip_path, manifest = a[0], a[1]
    render, expect, opts = None, None, {}
    i = 2
    while i < len(a):
        if a[i] in ("--render", "--expect-error") and i + 1 < len(a):
            if a[i] == "--render":
                render = a[i + 1]
            else:
                expect = a[i + 1]
            i += 2
            continue
        key, sep, text = a[i].partition("=")
        if not sep:
            print("blender_addon.py: %r is not OPTION=VALUE" % a[i], file=sys.stderr)
            sys.exit(2)
        opts[key] = value(key, text)
        i += 1
    return zip_path, manifest, render, expect, opts


def registered():
    """Whether the operator is registered: hasattr(bpy.ops.import_scene, NAME)
    is true for any NAME, dir() lists the registered ones."""
    return "seabake" in dir(bpy.ops.import_scene)


def menu_entries():
    """The draw functions File > Import runs that belong to the add-on."""
    funcs = bpy.types.TOPBAR_MT_file_import._dyn_ui_initialize()
    return [f for f in funcs if f.__module__.split(".")[-1] == "seabake_import"]


def install(zip_path):
    user = os.path.realpath(os.environ.get("BLENDER_USER_SCRIPTS", ""))
    addons = os.path.realpath(bpy.utils.user_resource("SCRIPTS", path="addons"))
    report(bool(user) and os.path.commonpath([user, addons]) == user,
           "user add-ons directory %s lies under $BLENDER_USER_SCRIPTS" % addons)
    report(not registered() and not menu_entries(),
           "before the install: no operator import_scene.seabake, no menu entry")
    res = bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True)
    report(res == {"FINISHED"}, "addon_install: %s" % sorted(res))
    files = sorted(os.listdir(os.path.join(addons, "seabake"))) \
        if os.path.isdir(os.path.join(addons, "seabake")) else []
    want = ["__init__.py", "blender_manifest.toml", "seabake_import.py"]
    report(all(f in files for f in want), "installed seabake/: %s" % files)
    res = bpy.ops.preferences.addon_enable(module="seabake")
    report(res == {"FINISHED"}, "addon_enable: %s" % sorted(res))
    report("seabake" in bpy.context.preferences.addons, "the add-on is enabled")
    report(registered(), "bpy.ops.import_scene.seabake is registered")
    entries = menu_entries()
    report(len(entries) == 1, "File > Import has the add-on's entry (%d draw function%s)"
           % (len(entries), "" if len(entries) == 1 else "s"))


def describe(scene):
    """What the import built, one line each."""
    print("scene: %s, frames %d to %d, current %d"
          % (scene.name, scene.frame_start, scene.frame_end, scene.frame_current))
    imgs = [im for im in bpy.data.images if im.filepath]
    print("images: %d, %d sequences" % (len(imgs), sum(im.source == "SEQUENCE" for im in imgs)))
    sea = sorted((o for o in scene.objects if o.type == "MESH"), key=lambda o: o.name)
    print("objects: %s" % " ".join(o.name for o in sea))
    print("materials: %s" % " ".join(o.active_material.name if o.active_material else "-"
                                     for o in sea))
    em = [o.active_material for o in sea if o.active_material is not None and
          o.active_material.name.startswith("seabake_emission")]
    projected = sum(any(n.type == "TEX_COORD" and n.object is not None
                        for n in mat.node_tree.nodes) for mat in em)
    print("projection: %d of %d emission materials" % (projected, len(em)))


def main():
    zip_path, manifest, render, expect, opts = args()
    install(zip_path)
    window = bpy.context.window
    start = window.scene
    start_objects = sorted(o.name for o in start.objects)
    n_scenes = len(bpy.data.scenes)
    try:
        res = bpy.ops.import_scene.seabake(filepath=manifest, **opts)
        error = None
    except RuntimeError as e:
        res, error = None, str(e)
    if expect is not None:
        report(error is not None and re.search(expect, error) is not None,
               "import refused: %s" % error)
        report(window.scene == start and len(bpy.data.scenes) == n_scenes,
               "the window back on scene %s, %d scene%s"
               % (window.scene.name, len(bpy.data.scenes),
                  "" if len(bpy.data.scenes) == 1 else "s"))
    elif report(res == {"FINISHED"}, "import_scene.seabake: %s" % (error or sorted(res))):
        scene = window.scene
        report(scene != start and bpy.context.scene == scene,
               "imported into a new scene, %s, shown in the window" % scene.name)
        report(sorted(o.name for o in start.objects) == start_objects,
               "scene %s keeps its objects (%s)" % (start.name, " ".join(start_objects)))
        describe(scene)
        if render is not None:
            scene.render.filepath = os.path.abspath(render)
            bpy.ops.render.render(write_still=True)
            report(os.path.isfile(scene.render.filepath), "rendered %s" % render)
    bpy.ops.preferences.addon_disable(module="seabake")
    report(not registered() and not menu_entries(),
           "addon_disable: the operator and the menu entry gone")
    print("blender_addon: %d failure%s" % (failures, "" if failures == 1 else "s"))
    sys.exit(1 if failures else 0)


main()
