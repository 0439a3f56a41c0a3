"""The worked example of docs/python.md: weights, locality statistics, a deformation and a plot.

Run from the repository root, with the package built in build/:
    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 python/examples/worked_example.py
It writes docs/images/python_example.png (or the path given as the first argument; ctest runs
it as python.worked_example with the bundled data and writes to build/testing/output).
"""
import sys
import time

import os

import numpy as np

import barylab

DATA = os.environ.get("BARYLAB_DATA_DIR", "data")

# The bundled gingerbread man: a 20-vertex polygon cage, the model's 2,488 points and the cage
# posed (arms and head moved).
cage = barylab.read(os.path.join(DATA, "cage2d.obj"))
model = barylab.read(os.path.join(DATA, "model2d.obj"))
posed = barylab.read(os.path.join(DATA, "cage2d_posed.obj"))
X = barylab.points_of(model)

# Weights as (n_points, n_controls) arrays, one per method; settings by their table keys.
W = {}
for method, settings in [("mvc", {}), ("harmonic", {}), ("lbc", {"target_cells": 1000})]:
    t0 = time.perf_counter()
    W[method] = barylab.weights(model, cage, method, **settings)
    print(f"{method:9s} {W[method].shape}  partition of unity "
          f"{np.abs(W[method].sum(axis=1) - 1).max():.1e}  reproduction "
          f"{np.abs(W[method] @ barylab.points_of(cage) - X).max():.1e}  "
          f"min {W[method].min():+.3f}  {time.perf_counter() - t0:.2f} s")

# Locality statistics (Zhang et al. 2014, §5): weights above 1e-3/n per point, P(t) and Q(k).
loc = {m: barylab.locality(X, w) for m, w in W.items()}
for m, s in loc.items():
    print(f"{m:9s} mean support {s['mean_support']:.1f} of {W[m].shape[1]}, "
          f"max {s['max_support']}")

# Deformation: the model moved with the posed cage, by each method's weights.
deformed = {m: barylab.deform(model, cage, posed, weights=w) for m, w in W.items()}

# The plot: Q(k) of the three methods, and the LBC deformation coloured by one control's weight.
try:
    import matplotlib
except ImportError:  # ctest runs this example on machines without python3-matplotlib
    print("matplotlib is not installed: no plot")
    sys.exit(0)
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

fig, (left, middle, right) = plt.subplots(1, 3, figsize=(13, 4.2))
for m, s in loc.items():
    left.plot(s["k"], s["Q"], marker="o", ms=3, label=m)
left.set_xlabel("k")
left.set_ylabel("Q(k): fraction of points with ≥ k weights > 10⁻³/n")
left.set_title("Locality (Zhang et al. 2014, Eq. 21)")
left.legend()
control = 10  # the top of the head
C = barylab.points_of(cage)
P = barylab.points_of(posed)
for ax, (title, pts, cage_pts, w) in zip(
        (middle, right),
        [("rest: LBC weight of control 10", X, C, W["lbc"][:, control]),
         ("posed with LBC weights", deformed["lbc"], P, W["lbc"][:, control])]):
    sc = ax.scatter(pts[:, 0], pts[:, 1], c=w, s=2, cmap="viridis", vmin=0, vmax=1)
    loop = np.vstack([cage_pts, cage_pts[:1]])
    ax.plot(loop[:, 0], loop[:, 1], "-o", color="tab:red", ms=3, lw=1)
    ax.plot(*cage_pts[control, :2], "s", color="black", ms=6)
    ax.set_aspect("equal")
    ax.set_title(title)
    ax.axis("off")
fig.colorbar(sc, ax=right, shrink=0.8)
fig.tight_layout()
output = sys.argv[1] if len(sys.argv) > 1 else "docs/images/python_example.png"
fig.savefig(output, dpi=90)
print("wrote", output)
