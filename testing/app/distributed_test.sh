#!/usr/bin/env bash
# Distributed runs (issue 16): `mpirun -np 2 barylab ...` against the serial run, one scenario
# per ctest (label mpi). The pieces must equal the serial file point by point (through their
# GlobalPointIds): bitwise for the methods whose per-point stage does not depend on the other
# points, to the Newton tolerance for celestial coordinates (warm starts follow each piece's
# points). Bad input must fail on every process with one error line and a non-zero exit code,
# leave no output, and never hang (timeout 120 s).
#
# usage: distributed_test.sh SCENARIO   (env: BARYLAB, PYTHON, DATA, OUT, PYTHONPATH)
set -uo pipefail
scenario=$1
B=$BARYLAB; D=$DATA; PY=${PYTHON:-/usr/bin/python3}
HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
W="$OUT/distributed_$scenario"
rm -rf "$W" && mkdir -p "$W" && cd "$W" || exit 1
MPI=(timeout 120 mpirun --oversubscribe --allow-run-as-root -np 2)
fail() { echo "FAIL: $*" >&2; exit 1; }
compare() { "$PY" "$HERE/compare_pieces.py" "$@" || fail "pieces differ from the serial run"; }
# weights METHOD TOLERANCE ARRAY CAGE-OPTION CAGE MODEL [options...]
weights() {
  local method=$1 tol=$2 array=$3 copt=$4 cage=$5 model=$6; shift 6
  "$B" weights --method "$method" "$copt" "$cage" --points "$model" -o serial.vtp -q "$@" ||
    fail "serial run"
  "${MPI[@]}" "$B" weights --method "$method" "$copt" "$cage" --points "$model" -o dist.pvtp \
    --json dist.json -q "$@" || fail "distributed run (rc $?)"
  [ -f dist_0.vtp ] && [ -f dist_1.vtp ] || fail "missing piece files"
  "$PY" - dist.json <<'PYEOF' || fail "summary"
import json, sys
s = json.load(open(sys.argv[1]))
assert s["processes"] == 2, s.get("processes")
assert s["points"]["count"] == s["statistics"]["points"], (s["points"], s["statistics"]["points"])
PYEOF
  compare serial.vtp dist.pvtp "$array" "$tol"
}
# expect_error RC PATTERN command...: fails unless the run exits RC, prints exactly one
# "barylab: error" / "usage error" line matching PATTERN, and leaves no out* file
expect_error() {
  local rc=$1 pattern=$2; shift 2
  "${MPI[@]}" "$@" > log.txt 2>&1; local got=$?
  [ "$got" -eq 124 ] && fail "hung (timeout): $*"
  [ "$got" -eq "$rc" ] || { cat log.txt; fail "exit code $got, expected $rc: $*"; }
  local lines; lines=$(grep -c '^barylab: \(usage \)\?error' log.txt)
  [ "$lines" -eq 1 ] || { cat log.txt; fail "$lines error lines, expected 1"; }
  grep -q -- "$pattern" log.txt || { cat log.txt; fail "message does not say '$pattern'"; }
  ! ls out* > /dev/null 2>&1 || fail "partial output left: $(ls out*)"
}

case $scenario in
  mvc3d) weights mvc 0 Weights --cage "$D/cage3d.obj" "$D/model3d.off" ;;
  green2d)
    weights green 0 Weights --cage "$D/cage2d.obj" "$D/model2d.obj"
    compare serial.vtp dist.pvtp FaceWeights 0 ;;
  harmonic2d) weights harmonic 0 Weights --cage "$D/cage2d.obj" "$D/model2d.obj" ;;
  bbw2d) weights bbw 0 Weights --cage "$D/cage2d.obj" "$D/model2d.obj" ;;
  lbc2d) weights lbc 0 Weights --cage "$D/cage2d.obj" "$D/model2d.obj" ;;
  tcc3d) # hull points from all the pieces (every piece gets the whole's columns)
    weights tcc 1e-10 Weights --control-points "$D/heart_controls.obj" "$D/heart.off" \
      --hull-points always ;;
  deform)
    "$B" deform --method mvc --cage "$D/cage3d.obj" -d "$D/cage3d_posed.obj" \
      --points "$D/model3d.off" -o serial.vtp -q || fail "serial deform"
    "${MPI[@]}" "$B" deform --method mvc --cage "$D/cage3d.obj" -d "$D/cage3d_posed.obj" \
      --points "$D/model3d.off" -o dist.pvtp -q || fail "distributed deform"
    compare serial.vtp dist.pvtp Weights 0 # coordinates: the deformed points, bitwise
    # from a distributed weights file: its pieces are the model
    "${MPI[@]}" "$B" weights --method mvc --cage "$D/cage3d.obj" --points "$D/model3d.off" \
      -o w.pvtp -q || fail "distributed weights"
    "${MPI[@]}" "$B" deform --method mvc --cage "$D/cage3d.obj" -d "$D/cage3d_posed.obj" \
      --weights w.pvtp -o dist2.pvtp -q || fail "distributed deform from weights"
    compare serial.vtp dist2.pvtp Weights 0
    # the serial commands read the pieces whole; stats counts the points flagged as another
    # piece's duplicates once
    "$B" stats --input w.pvtp --json > stats.json || fail "stats of a .pvtp"
    "$PY" -c "
import json, sys
s = json.load(open('stats.json'))
sys.exit(0 if s['points'] == 2562 else 'stats saw %d points, not 2562' % s['points'])" ||
      fail "stats of a .pvtp" ;;
  animate)
    frames=("$D/cage2d_posed.obj" "$D/cage2d.obj" "$D/cage2d_posed.obj")
    "$B" animate --method harmonic --cage "$D/cage2d.obj" --frames "${frames[@]}" \
      --points "$D/model2d.obj" --output-dir serial -q || fail "serial animate"
    "${MPI[@]}" "$B" animate --method harmonic --cage "$D/cage2d.obj" --frames "${frames[@]}" \
      --points "$D/model2d.obj" --output-dir dist -q || fail "distributed animate"
    cmp serial/animation.pvd dist/animation.pvd || fail ".pvd differs"
    for f in 000 001 002; do # frames 0, 2 by process 0, frame 1 by process 1
      compare "serial/animation_$f.vtp" "dist/animation_$f.vtp" Weights 0
    done ;;
  python)
    "${MPI[@]}" "$PY" "$HERE/../../python/examples/distributed_weights.py" "$D/cage2d.obj" \
      "$D/model2d.obj" harmonic || fail "python distributed weights" ;;
  errors)
    expect_error 1 "not closed" "$B" weights --method harmonic --cage "$D/bad/open_cage.obj" \
      --points "$D/model3d.off" -o out.pvtp
    expect_error 1 "did not converge" "$B" weights --method lbc --cage "$D/cage2d.obj" \
      --points "$D/model2d.obj" --max-iterations 2 -o out.pvtp
    expect_error 1 "parallel XML" "$B" weights --method mvc --cage "$D/cage2d.obj" \
      --points "$D/model2d.obj" -o out.vtp
    expect_error 1 "insert-points" "$B" weights --method harmonic --insert-points \
      --cage "$D/cage2d.obj" --points "$D/model2d.obj" -o out.pvtp
    expect_error 2 "runs on one process" "$B" mesh --cage "$D/cage2d.obj" -o out.vtu
    # a NaN in process 1's piece only: that process fails, process 0 must not wait forever
    "${MPI[@]}" "$B" weights --method mvc --cage "$D/cage2d.obj" --points "$D/model2d.obj" \
      -o good.pvtp -q || fail "distributed weights"
    "$PY" -c "
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader, vtkXMLPolyDataWriter
r = vtkXMLPolyDataReader(); r.SetFileName('good_1.vtp'); r.Update()
data = r.GetOutput(); data.GetPoints().SetPoint(5, float('nan'), 0.5, 0)
w = vtkXMLPolyDataWriter(); w.SetFileName('good_1.vtp'); w.SetInputData(data); w.Write()"
    for method in mvc harmonic tcc; do
      copt=--cage; [ $method = tcc ] && copt=--control-points
      expect_error 1 "of 2).*non-finite" "$B" weights --method $method $copt \
        "$D/cage2d.obj" --points good.pvtp -o out.pvtp
    done ;;
  *) fail "unknown scenario $scenario" ;;
esac
echo "distributed $scenario: passed"
