#!/usr/bin/env bash
# Writes every barylab-viewer screenshot of docs/user-guide.md into OUT_DIR (default:
# docs/images), with the viewer's own --screenshot (under Xvfb when there is no display).
#   tools/doc-screenshots.sh [OUT_DIR] [BUILD_DIR]
# The test suite runs it into the build tree (ctest -R viewer_docScreenshots), so the commands
# the guide shows keep working; run it on docs/images to refresh the guide's pictures.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
OUT=${1:-$ROOT/docs/images}
BUILD=${2:-$ROOT/build}
VIEWER=$BUILD/bin/barylab-viewer
BARYLAB=$BUILD/bin/barylab
DATA=$ROOT/data
mkdir -p "$OUT"
if [ -z "${DISPLAY:-}" ] && [ "${BARYLAB_DOC_XVFB:-0}" != "1" ]; then
  export BARYLAB_DOC_XVFB=1
  exec xvfb-run -a -s "-screen 0 1280x1024x24" "$0" "$OUT" "$BUILD"
fi
shot() { # PNG, viewer arguments...
  local png=$1
  shift
  "$VIEWER" "$@" --screenshot "$OUT/$png"
  echo "wrote $OUT/$png"
}
shot viewer_gingerbread_mvc.png --example gingerbread-mvc --control 14
shot viewer_gingerbread_mvc_posed.png --example gingerbread-mvc --control 14 --pose example
shot viewer_kidney_mvc.png --example kidney-mvc --control 36
shot viewer_kidney_clip_gradient.png --example kidney-mvc --control 36 --field gradient --log --clip
shot viewer_gingerbread_bbw.png --example gingerbread-bbw --control 3 --pose example
shot viewer_heart_scc.png --example heart-scc --control 0 --pose example
shot viewer_compare_mvc_harmonic.png "$DATA/cage2d.obj" "$DATA/model2d.obj" --compare harmonic \
  --control 14 --locality "$OUT/viewer_locality_mvc_harmonic"
rm -f "$OUT/viewer_locality_mvc_harmonic_P.csv" "$OUT/viewer_locality_mvc_harmonic_Q.csv"
shot viewer_gingerbread_image.png --example gingerbread-image --pose example
shot viewer_surface_torus.png --example torus-averages --field weight --control 4
shot viewer_surface_decal.png --example torus-averages --field decal
TETS=$(mktemp -d)/kidney_tets.vtu
"$BARYLAB" mesh --cage "$DATA/cage3d.obj" --cells 20000 --output "$TETS" --quiet
shot viewer_kidney_tets_sliced.png "$DATA/cage3d.obj" "$TETS" --method harmonic --control 36 \
  --clip --log
rm -rf "$(dirname "$TETS")"
# the spline mode: an identity 2.5D spline edited by `barylab spline edit` (the organism bent
# towards its picture, the top surface raised in the middle), opened with the model and picture
SPLINE=$(mktemp -d)
"$BARYLAB" spline create --domain "$DATA/spline_domain.obj" --prism -0.1 0.1 \
  --output "$SPLINE/identity.vtu" --quiet
cat > "$SPLINE/edits.json" <<'EOF_EDITS'
{"edits": [
  {"op": "translate", "near": [0.5, 0.0], "by": [0.0, 0.18], "delta_max": 8},
  {"op": "translate", "near": [-0.5, 0.0], "by": [0.0, -0.18], "delta_max": 8},
  {"op": "translate", "spline": "top", "near": [0.0, 0.0], "by": [0.04], "delta_max": 6}
]}
EOF_EDITS
"$BARYLAB" spline edit --spline "$SPLINE/identity.vtu" --edits "$SPLINE/edits.json" \
  --output "$SPLINE/bent.vtu" --quiet
shot viewer_spline_organism.png --spline "$SPLINE/bent.vtu" --model "$DATA/spline_organism.obj" \
  --picture "$DATA/spline_organism_picture.png"
shot viewer_spline_top.png --spline "$SPLINE/bent.vtu" --model "$DATA/spline_organism.obj" \
  --picture "$DATA/spline_organism_picture.png" --edit top
rm -rf "$SPLINE"
