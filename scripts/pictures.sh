#!/usr/bin/env bash
# Regenerates the guide's pictures in docs/guide/src/images/ from the shared scenes, with `topoccd render`.
#
#   scripts/pictures.sh            # from anywhere; the data is looked for in ../shared/data
#   TOPOCCD_DATA=/path/to/data scripts/pictures.sh
#
# The pictures are palette PNGs (--indexed) to keep them small in the repository; the output is
# deterministic, so an unchanged renderer and data give byte-identical files.
set -euo pipefail
cd "$(dirname "$0")/.."
data=${TOPOCCD_DATA:-../shared/data}
scenes=$data/scenes
for scene in cloth-ball cloth-funnel; do
    if [ ! -d "$scenes/$scene/frames" ]; then
        echo "error: $scenes/$scene/frames not found (set TOPOCCD_DATA to the shared data folder)" >&2
        exit 1
    fi
done

cargo build --release -q -p topoccd-cli
topoccd() { cargo run --release -q -p topoccd-cli -- "$@"; }
mkdir -p docs/guide/src/images

# Every picture carries a title and a legend; the up axis is chosen from the data (`--up auto`:
# y for cloth-ball, a sheet thinnest along y; z for cloth-funnel, falling along -z; z for the
# generated scene) and printed.
#
# 1. The clusters of cloth-ball's step (frame 92 to 93): leaf clusters in distinct colours,
#    intermediate-cluster boundaries outlined, as in the paper's figures 4 and 5.
ball=$scenes/cloth-ball/frames
topoccd render "$ball/cloth_ball92.ply" --step "$ball/cloth_ball93.ply" --color clusters \
    --indexed --out docs/guide/src/images/cloth-ball-clusters.png

# 2. The contacts of cloth-funnel's step (frame 227 to 228), found by the whole-step query:
#    the triangles involved in red (faded where the funnel's wall hides them), framed on them;
#    the cloth's position at the end of the step outlined in blue.
funnel=$scenes/cloth-funnel/frames
pairs=$(mktemp "${TMPDIR:-/tmp}/topoccd-funnel-pairs.XXXXXX")
trap 'rm -f "$pairs"' EXIT
topoccd step "$funnel/227.ply" "$funnel/228.ply" --pairs "$pairs"
topoccd render "$funnel/227.ply" --step "$funnel/228.ply" --color contacts --pairs "$pairs" \
    --camera 35,20 --fit contacts --indexed --out docs/guide/src/images/cloth-funnel-contacts.png

# 3. The contacts of a fracture step: step 1 of the generated bunny-dragon scene (scale 0.05),
#    the first that breaks pieces off the dragon, seen while the bunny's ears and the dragon's
#    body are still whole: collisions in red, contacts along the fresh cracks (features joined
#    through a split vertex) in orange; contacts computed by the whole-step query.
scene=$(mktemp -d "${TMPDIR:-/tmp}/topoccd-bunny-dragon.XXXXXX")
trap 'rm -f "$pairs"; rm -rf "$scene"' EXIT
rmdir "$scene"
topoccd gen bunny-dragon "$scene" --scale 0.05 --frames 3 --seed 1
topoccd render "$scene/0001.ply" --step "$scene/0002.ply" --color contacts \
    --indexed --out docs/guide/src/images/fracture-contacts.png

ls -l docs/guide/src/images/cloth-ball-clusters.png docs/guide/src/images/cloth-funnel-contacts.png docs/guide/src/images/fracture-contacts.png
