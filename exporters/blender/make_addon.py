#!/usr/bin/env python3
# make_addon.py - builds the Blender add-on, seabake-blender.zip (Makefile.am):
#
#   python3 make_addon.py OUT.zip VERSION LICENSE SRCDIR
#
# SRCDIR is exporters/blender of the sources.  The zip holds one package
# directory, seabake/:
#   __init__.py            addon/__init__.py.in, bl_info's version VERSION
#   seabake_import.py      the import script itself, byte for byte (one
#                          implementation for the add-on and the command line)
#   blender_manifest.toml  addon/blender_manifest.toml.in (Blender 4.2+
#                          extensions), version VERSION, licence LICENSE (an
#                          SPDX identifier)
# Reproducible: the entries in that order, every one dated 1980-01-01 00:00
# (the earliest a zip can hold) with mode 0644 and deflated, whatever the
# files' dates and the umask; the same inputs give the same bytes.

import re
import sys
import zipfile

DATE = (1980, 1, 1, 0, 0, 0)
MODE = 0o100644
# Blender's extension manifest refuses a longer tagline.
TAGLINE_MAX = 64


def fail(msg):
    print("make_addon.py: error: %s" % msg, file=sys.stderr)
    sys.exit(1)


def read(path):
    """The file's bytes."""
    try:
        with open(path, "rb") as f:
            return f.read()
    except OSError as e:
        fail("%s: cannot read: %s" % (path, e.strerror))


def substitute(data, path, values):
    """The template's text, every @KEY@ replaced by values[KEY], as bytes."""
    text = data.decode("utf-8")
    for key, value in values.items():
        text = text.replace("@%s@" % key, value)
    left = re.findall(r"@[A-Z_]+@", text)
    if left:
        fail("%s: %s not substituted" % (path, ", ".join(sorted(set(left)))))
    return text.encode("utf-8")


def main(argv):
    if len(argv) != 5:
        fail("usage: make_addon.py OUT.zip VERSION LICENSE SRCDIR")
    out, version, licence, src = argv[1:]
    m = re.fullmatch(r"(\d+)\.(\d+)\.(\d+)", version)
    if m is None:
        fail("version %r is not MAJOR.MINOR.PATCH, as bl_info and Blender's "
             "extensions need" % version)
    if not re.fullmatch(r"[A-Za-z0-9.+-]+", licence):
        fail("licence %r is not an SPDX identifier" % licence)
    values = {"PACKAGE_VERSION": version,
              "VERSION_TUPLE": ", ".join(m.groups()),
              "LICENSE": '"SPDX:%s"' % licence}
    init = substitute(read(src + "/addon/__init__.py.in"), "__init__.py.in", values)
    toml = substitute(read(src + "/addon/blender_manifest.toml.in"),
                      "blender_manifest.toml.in", values)
    tag = re.search(r'^tagline = "(.*)"$', toml.decode("utf-8"), re.M)
    if tag is None or len(tag.group(1)) > TAGLINE_MAX:
        fail("blender_manifest.toml.in: the tagline is missing or longer than %d "
             "characters" % TAGLINE_MAX)
    entries = (("seabake/__init__.py", init),
               ("seabake/seabake_import.py", read(src + "/seabake_import.py")),
               ("seabake/blender_manifest.toml", toml))
    try:
        with zipfile.ZipFile(out, "w") as z:
            for name, data in entries:
                info = zipfile.ZipInfo(name, date_time=DATE)
                info.external_attr = MODE << 16
                info.create_system = 3  # Unix, so that the mode is read
                info.compress_type = zipfile.ZIP_DEFLATED
                z.writestr(info, data)
    except OSError as e:
        fail("%s: cannot write: %s" % (out, e.strerror))


if __name__ == "__main__":
    main(sys.argv)
