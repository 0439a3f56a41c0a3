#!/usr/bin/python3
"""Plot (and tabulate) the results of bench_mean_value_coordinates.

Usage:
  plot_mvc.py RESULTS.json [MORE.json ...] [-o docs/images/benchmark_mvc.png] [--markdown]

Each RESULTS.json is what `bench_mean_value_coordinates --benchmark_out=RESULTS.json
--benchmark_out_format=json --benchmark_repetitions=N --benchmark_report_aggregates_only=true`
wrote; several files (e.g. one run per cage with --benchmark_filter) are merged, a later file
replacing the results of an earlier one for the same cage and variant. The plot shows the median throughput (points/s) of every variant against the cage size
(number of triangles), and the speed-up of each variant over VTK on one thread. --markdown
prints the throughput / ratio / accuracy tables used in docs/benchmarks.md.
"""

import argparse
import json
import sys
from collections import defaultdict

VARIANTS = [  # (key in the benchmark name, label, style)
    ("vtk_1t", "VTK, 1 thread", dict(color="tab:gray", marker="o", linestyle="--")),
    ("vtk_smp_2t", "VTK, 2 threads (vtkSMPTools/TBB)", dict(color="tab:blue", marker="s", linestyle="--")),
    ("vtk_omp_2t", "VTK, 2 threads (OpenMP loop)", dict(color="tab:cyan", marker="D", linestyle="--")),
    ("barylab_1t", "BaryLab, threads=1", dict(color="tab:orange", marker="^", linestyle="-")),
    ("barylab_2t", "BaryLab, threads=2", dict(color="tab:red", marker="v", linestyle="-")),
]
ACCURACY = ["max_diff_vs_vtk", "pou_err_barylab", "pou_err_vtk", "repro_err_barylab", "repro_err_vtk"]


def load(paths):
    """Returns ({cage: {variant: {aggregate: entry}}}, context of the first file)."""
    results = defaultdict(lambda: defaultdict(dict))
    context = None
    for path in paths:
        with open(path) as f:
            data = json.load(f)
        if context is None:
            context = data.get("context", {})
        load_into(results, data)
    return results, context


def load_into(results, data):
    replaced = set()
    for b in data["benchmarks"]:
        if b.get("run_type") != "aggregate" or b.get("error_occurred"):
            continue
        # run_name: mvc3d/<cage>/<variant>/real_time
        parts = b["run_name"].split("/")
        if len(parts) < 3 or parts[0] != "mvc3d":
            continue
        if (parts[1], parts[2]) not in replaced:
            results[parts[1]][parts[2]] = {}
            replaced.add((parts[1], parts[2]))
        results[parts[1]][parts[2]][b["aggregate_name"]] = b


def cage_order(results):
    return sorted(results, key=lambda c: next(iter(results[c].values()))["median"]["cage_faces"])


def rate(results, cage, variant, aggregate="median"):
    try:
        return results[cage][variant][aggregate]["items_per_second"]
    except KeyError:
        return float("nan")


def best_rate(results, cage, variant):
    """Points/s of the fastest repetition (the 'max' aggregate of the rate)."""
    return rate(results, cage, variant, "max")


def markdown(results, context):
    cages = cage_order(results)
    out = []
    out.append("| cage | vertices | triangles | points | " +
               " | ".join(label for _, label, _ in VARIANTS) + " |")
    out.append("|---|---:|---:|---:|" + "---:|" * len(VARIANTS))
    for c in cages:
        m = next(iter(results[c].values()))["median"]
        cells = []
        for v, _, _ in VARIANTS:
            r = rate(results, c, v)
            cv = results[c].get(v, {}).get("cv", {}).get("real_time", float("nan"))
            cells.append(f"{r:,.0f} (cv {100 * cv:.1f}%)")
        out.append(f"| {c} | {m['cage_vertices']:.0f} | {m['cage_faces']:.0f} | {m['points']:.0f} | " +
                   " | ".join(cells) + " |")
    out.append("")
    out.append("Fastest repetition (points/s):")
    out.append("")
    out.append("| cage | " + " | ".join(label for _, label, _ in VARIANTS) + " |")
    out.append("|---|" + "---:|" * len(VARIANTS))
    for c in cages:
        out.append(f"| {c} | " + " | ".join(f"{best_rate(results, c, v):,.0f}" for v, _, _ in VARIANTS) + " |")
    out.append("")
    out.append("| cage | BaryLab 1t / VTK 1t | BaryLab 2t / VTK 1t | BaryLab 2t / VTK 2t (SMP) | "
               "BaryLab 2t / VTK 2t (OpenMP) | BaryLab 2t / BaryLab 1t | VTK 2t (SMP) / VTK 1t |")
    out.append("|---|---:|---:|---:|---:|---:|---:|")
    for c in cages:
        r = {v: rate(results, c, v) for v, _, _ in VARIANTS}
        out.append(f"| {c} | {r['barylab_1t'] / r['vtk_1t']:.2f} | {r['barylab_2t'] / r['vtk_1t']:.2f} | "
                   f"{r['barylab_2t'] / r['vtk_smp_2t']:.2f} | {r['barylab_2t'] / r['vtk_omp_2t']:.2f} | "
                   f"{r['barylab_2t'] / r['barylab_1t']:.2f} | {r['vtk_smp_2t'] / r['vtk_1t']:.2f} |")
    out.append("")
    out.append("| cage | max \\|w_BaryLab - w_VTK\\| | partition of unity BaryLab | partition of unity VTK | "
               "linear reproduction BaryLab | linear reproduction VTK |")
    out.append("|---|---:|---:|---:|---:|---:|")
    for c in cages:
        m = next(iter(results[c].values()))["median"]
        out.append(f"| {c} | " + " | ".join(f"{m[k]:.1e}" for k in ACCURACY) + " |")
    return "\n".join(out)


def plot(results, context, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    cages = cage_order(results)
    faces = [next(iter(results[c].values()))["median"]["cage_faces"] for c in cages]
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 4.8))
    for v, label, style in VARIANTS:
        ys = [rate(results, c, v) for c in cages]
        ax1.plot(faces, ys, label=label, **style)
        ax2.plot(faces, [y / rate(results, c, "vtk_1t") for y, c in zip(ys, cages)], label=label, **style)
    ax1.set_xscale("log")
    ax1.set_yscale("log")
    ax1.set_xlabel("cage triangles")
    ax1.set_ylabel("points / s (median)")
    ax1.set_title("3D mean value coordinates: throughput")
    ax1.grid(True, which="both", alpha=0.3)
    ax1.legend(fontsize=8)
    ax2.set_xscale("log")
    ax2.axhline(3.0, color="black", linewidth=0.8, linestyle=":")
    ax2.text(faces[0], 3.05, "target: 3x VTK 1 thread", fontsize=8, va="bottom")
    ax2.set_xlabel("cage triangles")
    ax2.set_ylabel("speed-up over VTK, 1 thread")
    ax2.set_title("speed-up over VTK (1 thread)")
    ax2.set_ylim(0, max(3.4, 1.1 * ax2.get_ylim()[1]))
    ax2.grid(True, which="both", alpha=0.3)
    for ax in (ax1, ax2):
        ax.set_xticks(faces)
        ax.set_xticklabels([f"{f:.0f}" for f in faces])
        ax.minorticks_off()
    npts = next(iter(results[cages[0]].values()))["median"]["points"]
    fig.suptitle(f"{context.get('num_cpus', '?')} CPUs, {npts:.0f} points per cage, "
                 f"median of {context.get('repetitions', '?')} repetitions", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    print(f"wrote {path}", file=sys.stderr)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("results", nargs="+")
    ap.add_argument("-o", "--output", help="PNG to write")
    ap.add_argument("--markdown", action="store_true", help="print the markdown tables")
    args = ap.parse_args()
    results, context = load(args.results)
    if not results:
        sys.exit(f"no aggregate mvc3d results in {' '.join(args.results)}")
    # repetitions: from the median entry
    first = next(iter(next(iter(results.values())).values()))
    context.setdefault("repetitions", first["median"].get("repetitions", "?"))
    if args.markdown:
        print(markdown(results, context))
    if args.output:
        plot(results, context, args.output)


if __name__ == "__main__":
    main()
