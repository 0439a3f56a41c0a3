#!/usr/bin/env bash
# The organ workflow's steps timed on a label map of N^3 voxels (docs/benchmarks.md, "The organ
# workflow on a 256^3 label map"): the bundled organ resampled (nearest neighbour, same
# physical extent) to N^3, then segment, cage, MVC weights of the surface, the displacement field
# with its inverse on the label map's grid, and the label map warped. Each step's own seconds
# come from its --json summary; wall time and peak memory from /usr/bin/time.
#   tools/organ-benchmark.sh BUILD_DIR OUT_DIR [N=256] [THREADS=0]
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD=$(cd "$1" && pwd) OUT=$2 N=${3:-256} THREADS=${4:-0}
B=$BUILD/bin/barylab
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
/usr/bin/python3 - "$ROOT/data/organ_label.nii.gz" "$N" "$OUT/organ$N.mha" <<'PY'
# The bundled label map (LPS origin, identity direction, voxels in file order: see data/README.md)
# resampled by nearest neighbour onto N^3 voxels over the same physical extent.
import sys, vtk
src, n, dst = sys.argv[1], int(sys.argv[2]), sys.argv[3]
r = vtk.vtkNIFTIImageReader(); r.SetFileName(src); r.Update()
img = r.GetOutput(); dims = img.GetDimensions(); sp = img.GetSpacing()
origin_lps = (-166.125, -83.375, -205.0)  # data/README.md; the reader leaves the origin at 0
ext = [dims[k] * sp[k] for k in range(3)]
new_sp = [ext[k] / n for k in range(3)]
rs = vtk.vtkImageReslice(); rs.SetInputData(img); rs.SetInterpolationModeToNearestNeighbor()
rs.SetOutputSpacing(*new_sp)
rs.SetOutputOrigin(*[-0.5 * sp[k] + 0.5 * new_sp[k] for k in range(3)])
rs.SetOutputExtent(0, n - 1, 0, n - 1, 0, n - 1); rs.Update()
ch = vtk.vtkImageChangeInformation(); ch.SetInputConnection(rs.GetOutputPort())
ch.SetOutputOrigin(*[origin_lps[k] - 0.5 * sp[k] + 0.5 * new_sp[k] for k in range(3)])
w = vtk.vtkMetaImageWriter(); w.SetFileName(dst); w.SetInputConnection(ch.GetOutputPort())
w.SetCompression(True); w.Write()
PY
step() { # name, command...
  local name=$1; shift
  /usr/bin/time -f "%e %M" -o "$OUT/$name.time" "$@" --json "$OUT/$name.json" -q
  read -r wall kb < "$OUT/$name.time"
  printf '%-16s wall %8.2f s  peak %7.0f MB\n' "$name" "$wall" "$(echo "$kb / 1024" | bc -l)"
}
cd "$OUT"
step segment "$B" segment --image "organ$N.mha" --label 1 --output surface.vtp
step cage "$B" cage --model surface.vtp --vertices 60 --output cage.obj
"$B" deform --method tcc --control-points "$ROOT/data/organ_landmarks.mrk.json" \
  --deformed-control-points "$ROOT/data/organ_landmarks_moved.mrk.json" --points cage.obj \
  --output cage_moved.obj -q
step weights "$B" weights --cage cage.obj --points surface.vtp --output weights.vtp --threads "$THREADS"
step export-transform "$B" export-transform --cage cage.obj --deformed-cage cage_moved.obj \
  --reference "organ$N.mha" --output field.mha --inverse field_inverse.mha --threads "$THREADS"
step warp-image "$B" warp-image --image "organ$N.mha" --inverse-transform field_inverse.mha \
  --interpolation nearest --output warped.mha --threads "$THREADS"
/usr/bin/python3 - <<'PY'
import json
for name in ("segment", "cage", "weights", "export-transform", "warp-image"):
    s = json.load(open(name + ".json"))
    print(name, json.dumps(s.get("seconds", s.get("time", "")))[:300])
PY
