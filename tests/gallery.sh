#!/bin/bash
# gallery.sh - the README's gallery (issue 45) against doc/gallery: every
# image the "## Gallery" section of README.md shows (doc/gallery/NAME.png)
# is there, a valid 8-bit greyscale or RGB PNG (signature, chunk CRCs, IHDR,
# the IDAT stream inflating to the image's rows) of at most 80 KB, all of
# them at most 600 KB, and every PNG in doc/gallery is shown: the test fails
# when the README and the directory diverge.  It does not render the
# gallery (make gallery, scripts/gallery, does).
[ -n "${BASH_VERSION:-}" ] || exec bash "$0" "$@"
set -u
TEST_NAME=gallery
. "$(dirname "$0")/lib.sh"

: "${top_srcdir:?top_srcdir must name the source directory}"
PY=${PYTHON3:-python3}
README="$top_srcdir/README.md"
GALLERY="$top_srcdir/doc/gallery"
MAX_PNG=81920
MAX_TOTAL=614400

# The section: from "## Gallery" to the next "## " heading.
section=$(awk '/^## Gallery[[:space:]]*$/ { on = 1; next } on && /^## / { exit } on' "$README")
check gallery.section test -n "$section"
shown=$(printf '%s\n' "$section" | grep -o 'doc/gallery/[A-Za-z0-9_.-]*\.png' | sort -u)
check gallery.images test -n "$shown"
check_match gallery.regenerate "$section" 'make gallery'

total=0
for path in $shown; do
    f="$top_srcdir/$path"
    name=$(basename "$path")
    if [ -f "$f" ]; then
        pass
    else
        fail "gallery.$name.exists" "README.md shows $path, not in doc/gallery"
        continue
    fi
    size=$(wc -c <"$f")
    total=$((total + size))
    num_check "gallery.$name.size" "s <= $MAX_PNG" "s=$size"
    SB_CMD="png check $f"
    SB_ERR=$("$PY" - "$f" <<'EOF' 2>&1
import struct, sys, zlib
data = open(sys.argv[1], "rb").read()
assert data[:8] == b"\x89PNG\r\n\x1a\n", "no PNG signature"
pos, chunks, idat = 8, [], b""
while pos < len(data):
    n, kind = struct.unpack(">I4s", data[pos:pos + 8])
    body = data[pos + 8:pos + 8 + n]
    crc, = struct.unpack(">I", data[pos + 8 + n:pos + 12 + n])
    assert len(body) == n and zlib.crc32(kind + body) & 0xFFFFFFFF == crc, "bad chunk %r" % kind
    chunks.append(kind)
    if kind == b"IHDR":
        w, h, depth, ctype, _, _, interlace = struct.unpack(">IIBBBBB", body)
    if kind == b"IDAT":
        idat += body
    pos += 12 + n
assert chunks[0] == b"IHDR" and chunks[-1] == b"IEND" and b"IDAT" in chunks, "chunks %r" % chunks
channels = {0: 1, 2: 3}.get(ctype)
assert depth == 8 and channels and interlace == 0, "not 8-bit grey or RGB: %d, %d" % (depth, ctype)
raw = zlib.decompress(idat)
assert len(raw) == h * (1 + w * channels), "IDAT holds %d bytes for %d x %d" % (len(raw), w, h)
print("%d x %d, %s, %d bytes" % (w, h, "grey" if ctype == 0 else "RGB", len(data)))
EOF
)
    SB_RC=$?
    echo "gallery: $name: $SB_ERR"
    check_rc "gallery.$name.png" 0
done
num_check gallery.total "t <= $MAX_TOTAL" "t=$total"

# Every PNG in the directory is shown in the README.
on_disk=$(cd "$GALLERY" 2>/dev/null && ls -1 -- *.png 2>/dev/null | sed 's|^|doc/gallery/|' | sort -u)
check_eq gallery.same_set "$on_disk" "$shown"
finish
