#!/bin/sh
# The README's first pictures, from `make run`'s own command on the default settings (balanced, the generic HMD's
# lens, GI), 8 frames so that the saved one has the temporal history a viewer's frame has (frame 0 has none), at
# 320x360 per eye:
#   tools/readme_pictures.sh [path/to/fovea]
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
fovea=${1:-$root/build/release/tools/fovea/fovea}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for scene in cornell pillars; do
  "$fovea" run --scene "$scene" --frames 8 --eye-size 320x360 --out "$tmp/$scene" >/dev/null
  cp "$tmp/$scene/frame_00007.png" "$root/docs/img/${scene}_stereo.png"
  echo "docs/img/${scene}_stereo.png"
done
