"""exr_read.py - the channels of an uncompressed scanline OpenEXR file
(and the size of any), read without OpenEXR (Python's standard library
only), for the tests that check seabake's images independently of the
library that wrote them (tests/cli.sh: the camera's noise and counts,
seabake convert, and the bake's emission maps' width).

    read(path) -> (channels, width, height)
    header(path) -> (width, height): the data window's size, from the
                    header alone (any compression)

channels maps each channel's name to its pixel type (1: HALF, 2: FLOAT)
and its values, a list of rows from the top, each a list of Python floats
(HALF and FLOAT widened exactly).  Both refuse (AssertionError) a tiled
or multi-part file and a UINT channel; read also a compressed one."""
import struct

_TYPES = {1: ("e", 2), 2: ("f", 4)}  # HALF, FLOAT: struct code and size


def _header(d):
    """The header of the file's bytes d: its channels [(name, type)], its
    compression, its data window's width and height, and where the header
    ends."""
    assert d[:4] == b"\x76\x2f\x31\x01", "not an OpenEXR file"
    assert d[5] & 0x1a == 0, "tiled, deep or multi-part"
    i, chans, comp, window = 8, [], None, None
    while d[i] != 0:
        j = d.index(b"\0", i)
        name = d[i:j]
        i = d.index(b"\0", j + 1) + 1  # past the attribute's type name
        (n,) = struct.unpack("<i", d[i:i + 4])
        v = d[i + 4:i + 4 + n]
        i += 4 + n
        if name == b"channels":
            k = 0
            while v[k] != 0:
                e = v.index(b"\0", k)
                (t,) = struct.unpack("<i", v[e + 1:e + 5])
                assert t in _TYPES, "a UINT channel"
                chans.append((v[k:e].decode(), t))
                k = e + 17
        elif name == b"dataWindow":
            window = struct.unpack("<4i", v)
        elif name == b"compression":
            comp = v[0]
    x0, y0, x1, y1 = window
    return chans, comp, x1 - x0 + 1, y1 - y0 + 1, i


def header(path):
    with open(path, "rb") as f:
        _, _, w, h, _ = _header(f.read())
    return w, h


def read(path):
    with open(path, "rb") as f:
        d = f.read()
    chans, comp, w, h, i = _header(d)
    assert comp == 0, "compressed"
    i += 1 + 8 * h  # the header's end and the line offsets
    out = {c: (t, []) for c, t in chans}
    for _ in range(h):
        i += 8  # the line's y and size
        for c, t in chans:  # channels are stored in the header's order
            code, size = _TYPES[t]
            out[c][1].append(list(struct.unpack("<%d%s" % (w, code), d[i:i + size * w])))
            i += size * w
    return out, w, h
