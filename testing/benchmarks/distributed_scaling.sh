#!/usr/bin/env bash
# Strong scaling of distributed runs (docs/distributed.md): `barylab weights` / `deform` on
# 10^6 and 10^7 points on 1 and 2 processes (mpirun), wall time and peak memory per process.
# The models are random points (fixed seed) inside the cage, written once as .vtp point clouds.
#
# usage: testing/benchmarks/distributed_scaling.sh BUILD_DIR WORK_DIR [SIZES...]
# (default sizes 1000000 10000000; 10^7 points x 8 controls needs ~6 GB per process)
set -euo pipefail
BUILD=$(cd "$1" && pwd); WORK=$2; shift 2
SIZES=("${@:-1000000 10000000}")
[ $# -eq 0 ] && SIZES=(1000000 10000000)
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
B=$BUILD/bin/barylab; D=$ROOT/data
mkdir -p "$WORK" && cd "$WORK"
MPI=(mpirun --oversubscribe --allow-run-as-root)
# a cube cage (8 controls) for 10^7 points; the bundled 72-vertex sphere-like cage for 10^6
/usr/bin/python3 - <<'PY'
v = [(x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)]
f = [(1,3,4,2),(5,6,8,7),(1,2,6,5),(3,7,8,4),(1,5,7,3),(2,4,8,6)]  # outward quads, 1-based
with open("cube.obj", "w") as out:
    out.writelines("v %g %g %g\n" % p for p in v)
    for a, b, c, d in f:
        out.write("f %d %d %d\nf %d %d %d\n" % (a, b, c, a, c, d))
PY
python_points() { # n lo hi file
  /usr/bin/python3 - "$@" <<'PY'
import sys
import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkPolyData
from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter
n, lo, hi, path = int(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3]), sys.argv[4]
x = np.random.default_rng(7).uniform(lo, hi, size=(n, 3))
points = vtkPoints(); points.SetData(numpy_to_vtk(x, deep=1))
data = vtkPolyData(); data.SetPoints(points)
w = vtkXMLPolyDataWriter(); w.SetFileName(path); w.SetInputData(data); w.SetDataModeToAppended()
w.EncodeAppendedDataOff(); w.Write()
PY
}
pieces() { # n src: the same points as two .vtp pieces and a .pvtp summary (q$n.pvtp)
  /usr/bin/python3 - "$@" <<'PY'
import sys
import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkPolyData
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader, vtkXMLPolyDataWriter
n, src = sys.argv[1], sys.argv[2]
r = vtkXMLPolyDataReader(); r.SetFileName(src); r.Update()
x = vtk_to_numpy(r.GetOutput().GetPoints().GetData())
for k, part in enumerate(np.array_split(x, 2)):
    points = vtkPoints(); points.SetData(numpy_to_vtk(np.ascontiguousarray(part), deep=1))
    data = vtkPolyData(); data.SetPoints(points)
    w = vtkXMLPolyDataWriter(); w.SetFileName("q%s_%d.vtp" % (n, k)); w.SetInputData(data)
    w.SetDataModeToAppended(); w.EncodeAppendedDataOff(); w.Write()
with open("q%s.pvtp" % n, "w") as out:
    out.write('<?xml version="1.0"?>\n<VTKFile type="PPolyData" version="0.1" '
              'byte_order="LittleEndian">\n<PPolyData GhostLevel="0">\n<PPoints><PDataArray '
              'type="Float64" NumberOfComponents="3"/></PPoints>\n<Piece Source="q%s_0.vtp"/>\n'
              '<Piece Source="q%s_1.vtp"/>\n</PPolyData>\n</VTKFile>\n' % (n, n))
PY
}
row() { # label processes command...: one OpenMP thread per process (strong scaling by processes)
  local label=$1 np=$2; shift 2
  local t0 t1
  t0=$(date +%s.%N)
  if [ "$np" -eq 1 ]; then OMP_NUM_THREADS=1 /usr/bin/time -f "%M" -o rss.txt "$@" -q --json s.json; else
    "${MPI[@]}" -x OMP_NUM_THREADS=1 -np "$np" /usr/bin/time -f "%M" -o rss.txt "$@" -q --json s.json; fi
  t1=$(date +%s.%N)
  printf "| %s | %d | %.1f | %.1f | %.0f |\n" "$label" "$np" "$(echo "$t1 - $t0" | bc)" \
    "$(/usr/bin/python3 -c 'import json; print(json.load(open("s.json"))["seconds"])')" \
    "$(( $(cat rss.txt) / 1024 ))"
}
echo "| job | processes | wall s | computing s (slowest process) | peak MB (a process) |"
echo "|---|---|---|---|---|"
for n in "${SIZES[@]}"; do
  if [ "$n" -le 2000000 ]; then
    cage=$D/cage3d.obj; posed=$D/cage3d_posed.obj
    [ -f "p$n.vtp" ] || python_points "$n" -0.3 0.3 "p$n.vtp"
  else
    cage=cube.obj; posed=cube.obj
    [ -f "p$n.vtp" ] || python_points "$n" 0.05 0.95 "p$n.vtp"
  fi
  for np in 1 2; do
    row "mvc weights, $n points" "$np" "$B" weights --method mvc --cage "$cage" --points "p$n.vtp" -o "w$n-$np.pvtp"
    rm -f "w$n-$np"*
    row "harmonic weights, $n points" "$np" "$B" weights --method harmonic --cage "$cage" --points "p$n.vtp" -o "h$n-$np.pvtp"
    rm -f "h$n-$np"*
    row "mvc deform, $n points" "$np" "$B" deform --method mvc --cage "$cage" -d "$posed" --points "p$n.vtp" -o "d$n-$np.pvtp"
    rm -f "d$n-$np"*
  done
  # the model as pieces (.pvtp): each process reads only its own
  [ -f "q$n.pvtp" ] || pieces "$n" "p$n.vtp"
  for np in 1 2; do
    row "mvc weights, $n points as 2 .pvtp pieces" "$np" "$B" weights --method mvc --cage "$cage" --points "q$n.pvtp" -o "w$n-$np.pvtp"
    rm -f "w$n-$np"*
  done
done
