#!/usr/bin/python3
"""gallery-tone.py - the gallery's triptych (scripts/gallery): one bake seen
by seabake render, POV-Ray and Blender/Cycles, written as 8-bit greyscale
PNGs on ONE tone curve, so that they compare grey for grey.

    gallery-tone.py OUTDIR REF.npy NAME=IMAGE.npy:SCALE ...

REF.npy is seabake render's radiance (seabake convert ... --channel Y: float32,
shape (H, W)); each NAME=IMAGE.npy:SCALE an exporter's render (seabake
convert ... --channel R,G,B: (H, W, 3), grey), whose values are the radiance
times SCALE (POV-Ray: sea.inc's Seabake_Radiance_Scale; Cycles: the
manifest's emission_scale).  The tone curve is linear in log radiance from
the reference's 0.5 % quantile (black) to its 99.5 % quantile (white),
clamped: at 4 um a glint is over 100 times the sea's own radiance, and a
curve linear in radiance leaves the sea outside the glint black.
Writes OUTDIR/triptych_seabake.png and OUTDIR/triptych_NAME.png, and prints,
for each exporter, the relative RMS and largest relative difference of its
radiance from the reference over the whole image, and the RMS difference of
the 8-bit grey levels.

Needs numpy alone (the PNG writer is zlib and struct): no PIL.
"""
import struct
import sys
import zlib

import numpy as np


def write_png(path, grey):
    """An 8-bit greyscale PNG of GREY (uint8, shape (H, W)): filter Up on
    every row but the first (None), zlib level 9."""
    h, w = grey.shape
    rows = np.empty((h, w + 1), dtype=np.uint8)
    rows[:, 0] = 2  # Up
    rows[0, 0] = 0  # None: the first row has nothing above it
    rows[0, 1:] = grey[0]
    rows[1:, 1:] = grey[1:] - grey[:-1]  # uint8: modulo 256, as PNG wants
    data = zlib.compress(rows.tobytes(), 9)

    def chunk(kind, body):
        return (struct.pack(">I", len(body)) + kind + body +
                struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF))

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 0, 0, 0, 0)))
        f.write(chunk(b"IDAT", data))
        f.write(chunk(b"IEND", b""))


def tone(radiance, lo, hi):
    """Radiance -> 8-bit grey, linear in log radiance from LO (0) to HI
    (255), clamped (a radiance of 0 or below is black)."""
    r = np.maximum(radiance.astype(np.float64), lo * 1e-3)
    t = np.log(r / lo) / np.log(hi / lo)
    return np.clip(np.rint(255.0 * t), 0, 255).astype(np.uint8)


def main(argv):
    if len(argv) < 3:
        sys.exit("usage: gallery-tone.py OUTDIR REF.npy NAME=IMAGE.npy:SCALE ...")
    outdir, ref_path = argv[0], argv[1]
    ref = np.load(ref_path).astype(np.float64)
    if ref.ndim != 2 or not np.all(np.isfinite(ref)) or ref.min() <= 0:
        sys.exit("gallery-tone.py: %s: not a positive finite (H, W) radiance" % ref_path)
    lo, hi = np.quantile(ref, [0.005, 0.995])
    if not hi > lo:
        sys.exit("gallery-tone.py: %s: no range to tone (%.6g to %.6g)" % (ref_path, lo, hi))
    print("tone curve: log radiance from %.6g (black) to %.6g (white), seabake render's "
          "0.5 %% and 99.5 %% quantiles" % (lo, hi))
    ref_grey = tone(ref, lo, hi)
    write_png("%s/triptych_seabake.png" % outdir, ref_grey)
    for arg in argv[2:]:
        name, rest = arg.split("=", 1)
        path, scale = rest.rsplit(":", 1)
        img = np.load(path).astype(np.float64)
        if img.ndim == 3:
            # The exporters write grey as R = G = B: check it, take R.
            spread = np.max(np.abs(img - img[:, :, :1]))
            if spread > 1e-6 * np.max(np.abs(img)):
                sys.exit("gallery-tone.py: %s: not grey (channels differ by %.3g)" % (path, spread))
            img = img[:, :, 0]
        if img.shape != ref.shape:
            sys.exit("gallery-tone.py: %s: shape %s, the reference's %s" % (path, img.shape, ref.shape))
        rad = img / float(scale)
        rel = (rad - ref) / ref
        grey = tone(rad, lo, hi)
        dgrey = grey.astype(np.float64) - ref_grey
        print("%s: relative RMS %.2e, max %.2e against seabake render over %d pixels; "
              "grey levels RMS %.3f, max %d" % (name, np.sqrt(np.mean(rel ** 2)), np.max(np.abs(rel)),
                                                 rel.size, np.sqrt(np.mean(dgrey ** 2)),
                                                 int(np.max(np.abs(dgrey)))))
        write_png("%s/triptych_%s.png" % (outdir, name), grey)


if __name__ == "__main__":
    main(sys.argv[1:])
