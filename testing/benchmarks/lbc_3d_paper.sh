#!/bin/sh
# The LBC paper's 3D experiments at its scale on the bundled starfish (107 controls): converged
# LBC next to BBW (fast, coupled), harmonic and mean value coordinates on the same tet mesh;
# Q(k), P(t), supports, sparse memory against dense, bind time. One command, from the
# repository root (needs the Release build in build/, and python3-matplotlib for the plot):
#
#   sh testing/benchmarks/lbc_3d_paper.sh [TARGET_TETS ...]     (default: 1500 5000 12000)
#
# Writes testing/benchmarks/results/lbc_3d_paper_<target>.{json,txt} and
# docs/images/lbc_3d_paper_locality.png (from the last target). One thread per solver;
# see docs/benchmarks.md for the times this took.
set -e
cmake --build build --target bench_sparse_weights
targets=${*:-1500 5000 12000}
last=
for t in $targets; do
  out=testing/benchmarks/results/lbc_3d_paper_$t
  { uptime; OMP_NUM_THREADS=1 BARYLAB_PAPER3D_JSON=$out.json \
      build/bin/bench_sparse_weights --benchmark_filter="LBC3DPaper/$t/"; uptime; } > $out.txt 2>&1
  /usr/bin/python3 testing/benchmarks/plot_lbc_3d_paper.py $out.json
  last=$out.json
done
/usr/bin/python3 testing/benchmarks/plot_lbc_3d_paper.py "$last" -o docs/images/lbc_3d_paper_locality.png
