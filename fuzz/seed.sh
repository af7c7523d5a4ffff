#!/usr/bin/env bash
# Builds the fuzzers' seed corpora in fuzz/corpus/<target>/ from the shared data (never copied
# into the repository: the corpus folder is ignored by git) and from small hand-made files.
#
#   fuzz/seed.sh [SHARED_DATA_DIR]     (default: ../shared/data beside the repository)
#
# Seeds are kept small (a few KiB) so that libFuzzer mutates structure, not bulk.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
data="${1:-$here/../../shared/data}"
corpus="$here/corpus"
mkdir -p "$corpus"/{ply,obj,stl,parents,queries_csv,step}

if [[ ! -d "$data" ]]; then
    echo "seed.sh: shared data not found at $data; only the hand-made seeds are written" >&2
fi

python3 - "$data" "$corpus" <<'PY'
import glob, os, struct, sys

data, corpus = sys.argv[1], sys.argv[2]

def put(target, name, payload):
    if isinstance(payload, str):
        payload = payload.encode()
    with open(os.path.join(corpus, target, name), "wb") as f:
        f.write(payload)

# --- PLY: real frames cut down to a few elements, plus hand-made small meshes ---------------
for path in sorted(glob.glob(os.path.join(data, "scenes/*/frames/*.ply"))):
    raw = open(path, "rb").read()
    end = raw.find(b"end_header\n")
    if end < 0:
        continue
    header, body = raw[: end + 11], raw[end + 11 :]
    stem = os.path.basename(os.path.dirname(os.path.dirname(path))) + "-" + os.path.basename(path)
    lines = header.decode("ascii", "replace").split("\n")
    # Only float xyz vertices and uchar/int face lists are cut exactly; others are just prefixes.
    simple = "property float x" in lines and "property list uchar int vertex_indices" in lines
    nverts = 12
    if simple:
        vb = body[: 12 * nverts]
        for nfaces in (0, 6):
            be = "binary_big_endian" in lines[1]
            pack = ">" if be else "<"
            faces = b"".join(
                struct.pack(pack + "B3i", 3, i, (i + 1) % nverts, (i + 5) % nverts) for i in range(nfaces)
            )
            new = []
            for l in lines:
                if l.startswith("element vertex"):
                    l = f"element vertex {nverts}"
                elif l.startswith("element face"):
                    l = f"element face {nfaces}"
                new.append(l)
            put("ply", f"{stem}-{nverts}v{nfaces}f", "\n".join(new).encode() + vb + faces)
    # The real header with a short, truncated body.
    put("ply", f"{stem}-prefix", header + body[:200])

tri_ascii = (
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0\n1 0 0\n0 1 0\n1 1 0.5\n3 0 1 2\n3 1 3 2\n"
)
put("ply", "ascii-two-triangles", tri_ascii)
le = (
    b"ply\nformat binary_little_endian 1.0\ncomment hand-made\nelement vertex 3\n"
    b"property double x\nproperty double y\nproperty double z\nproperty uchar red\n"
    b"element face 1\nproperty list int uint vertex_index\nproperty float quality\n"
    b"element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n"
)
for p in ((0, 0, 0), (1, 0, 0), (0, 1, 0)):
    le += struct.pack("<3dB", *p, 7)
le += struct.pack("<i3If", 3, 0, 1, 2, 0.5) + struct.pack("<2i", 0, 1)
put("ply", "le-double-extras", le)
put("ply", "empty-mesh", "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
    "property float z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n")

# --- OBJ: small hand-made meshes, and a real frame's first vertices written as OBJ ----------
put("obj", "triangle", "# a triangle\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
put("obj", "corners", "o mesh\nv 0 0 0 1\nv 1 0 0 0.5 0.5 0.5\nv 0 1 0\nvt 0 0\nvn 0 0 1\n"
    "g group\ns off\nusemtl m\nf 1/1/1 2//1 -1/1\nf 3 2 1\n")
put("obj", "forward", "f 1 2 3\nv 0 0 0\nv 1e300 -1e-300 0\nv nan inf -inf\n")
for path in sorted(glob.glob(os.path.join(data, "scenes/*/frames/*.ply")))[:1]:
    raw = open(path, "rb").read()
    end = raw.find(b"end_header\n")
    lines = raw[:end].decode("ascii", "replace").split("\n")
    if "property float x" in lines and "binary_big_endian" in lines[1]:
        body = raw[end + 11 :]
        pts = [struct.unpack(">3f", body[12 * i : 12 * i + 12]) for i in range(8)]
        text = "".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in pts)
        text += "".join(f"f {i + 1} {i + 2} {i + 3}\n" for i in range(6))
        put("obj", "frame-prefix", text)

# --- STL: hand-made ASCII and binary soups (a square whose corners repeat, a degenerate facet) --
facet = "facet normal 0 0 1\n outer loop\n vertex {} \n vertex {} \n vertex {} \n endloop\nendfacet\n"
put("stl", "ascii-square", "solid square\n" + facet.format("0 0 0", "1 0 0", "1 1 0")
    + facet.format("0 0 0", "1 1 0", "0 1 0") + facet.format("0 0 0", "-0 0 0", "1 1 1")
    + "endsolid square\nsolid second\n" + facet.format("1e300 nan 0", "1 1 1", "2 2 2")
    + "endsolid\n")
soup = [((0, 0, 0), (1, 0, 0), (1, 1, 0)), ((0, 0, 0), (1, 1, 0), (0, 1, 0)),
        ((0, 0, 0), (-0.0, 0, 0), (1, 1, 1))]
binary = b"solid but binary".ljust(80, b" ") + struct.pack("<I", len(soup))
for tri in soup:
    binary += struct.pack("<3f", 0, 0, 1) + b"".join(struct.pack("<3f", *c) for c in tri) + b"\0\0"
put("stl", "binary-square", binary)

# --- parents: two bytes of vertex counts (previous, new), then the text ----------------------
put("parents", "simple", bytes([4, 2]) + b"# NEW_ID PARENT_ID\n4 0\n5 2\n")
put("parents", "comments", bytes([10, 5]) + b"\n10 3 # crack\n\n14 9\n12\t1\n")
put("parents", "empty", bytes([0, 0]))

# --- query CSV: the first few queries of each file --------------------------------------------
for path in sorted(glob.glob(os.path.join(data, "queries/*/*/data_0_0.csv"))):
    rows = open(path).read().splitlines()
    kind = os.path.basename(os.path.dirname(path))
    scene = os.path.basename(os.path.dirname(os.path.dirname(path)))
    put("queries_csv", f"{scene}-{kind}", "\n".join(rows[: 8 * 2]) + "\n")
put("queries_csv", "hand-made", "".join(f"{i},1,-{i},2,0,4,1\n" for i in range(8)))
PY

for t in ply obj stl parents queries_csv step; do
    echo "$t: $(ls "$corpus/$t" | wc -l) seeds"
done
