#!/usr/bin/env python3
"""The LBC paper's 3D experiments (Figs. 14-15, Table 1) on the bundled starfish, from the JSON
that bench_sparse_weights' LBC3DPaper writes (BARYLAB_PAPER3D_JSON).

Prints the per-method table as Markdown and, with -o, plots Q(k) (Eq. 21; over all mesh vertices
and over the interior ones) and P(t) (Eq. 20) of every method on one picture (needs python3-matplotlib):

    /usr/bin/python3 testing/benchmarks/plot_lbc_3d_paper.py \
        testing/benchmarks/results/lbc_3d_paper.json -o docs/images/lbc_3d_paper_locality.png
"""
import argparse
import json

LABELS = {
    "harmonic": "harmonic",
    "bbw_fast": "BBW (fast)",
    "bbw_coupled": "BBW (coupled)",
    "lbc_paper_rule": "LBC, paper's stopping rule",
    "lbc_converged": "LBC, converged",
    "mvc": "mean value (dense baseline)",
}
STYLES = {
    "harmonic": ("tab:green", "-"),
    "bbw_fast": ("tab:orange", "--"),
    "bbw_coupled": ("tab:orange", "-"),
    "lbc_paper_rule": ("tab:blue", "--"),
    "lbc_converged": ("tab:blue", "-"),
    "mvc": ("tab:gray", ":"),
}


def markdown(data):
    print("starfish: n = %d controls, |V| = %d (%d interior), |T| = %d (target %d tets), threshold "
          "1e-3/n = %.3g, boundary vertices %.1f%% of the lumped volume"
          % (data["n"], data["mesh_vertices"], data["interior_vertices"], data["mesh_tets"],
             data["target_tets"], data["threshold"], 100 * data["boundary_measure_fraction"]))
    print()
    print("| method | bind CPU | iterations | converged | support mean / max (mesh) | "
          "interior | model | memory CSC: mesh / model / grid | frame (grid) |")
    print("|---|---:|---:|---|---|---|---|---|---:|")
    for m in data["methods"]:
        print("| %s | %.2f s | %d | %s | %.1f / %.0f | %.1f / %.0f | %.1f / %.0f | %.1f%% / %.1f%% / %.1f%% | %.0f us |"
              % (LABELS.get(m["name"], m["name"]), m["cpu_s"], m["iterations"],
                 "yes" if m["converged"] else "no", m["mean_support"], m["max_support"],
                 m["interior_mean_support"], m["interior_max_support"], m["model_mean_support"], m["model_max_support"], 100 * m["memory_csc"],
                 100 * m["model_memory_csc"], 100 * m["grid_memory_csc"], m["frame_us"]))
    print()
    print("dense MVC frame at the grid points: %.0f us (%d points)"
          % (data["dense_mvc_frame_us"], data["grid_points"]))


def plot(data, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (axq, axi, axp) = plt.subplots(1, 3, figsize=(15, 4.4))
    for m in data["methods"]:
        color, line = STYLES.get(m["name"], (None, "-"))
        name = LABELS.get(m["name"], m["name"])
        axq.plot(m["k"], m["Q"], line, color=color, label="%s (%.1f)" % (name, m["mean_support"]))
        axi.plot(m["k"], m["interior_Q"], line, color=color,
                 label="%s (%.1f)" % (name, m["interior_mean_support"]))
        t = [x for x in m["t"] if x > 0]
        P = [p for x, p in zip(m["t"], m["P"]) if x > 0]
        axp.semilogx(t, P, line, color=color, label=name)
    for ax, title in ((axq, "Q(k), all mesh vertices (legend: mean support)"),
                      (axi, "Q(k), interior vertices only (boundary: %.0f%% of the volume)"
                       % (100 * data["boundary_measure_fraction"]))):
        ax.set_xlabel("k")
        ax.set_ylabel("fraction of the volume with >= k weights > 1e-3/n")
        ax.set_title(title, fontsize=9)
        ax.set_xlim(1, data["n"])
        ax.set_ylim(0, 1.02)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    axp.set_xlabel("t")
    axp.set_ylabel("mean fraction of the volume with |w_i| <= t")
    axp.set_title("P(t), all mesh vertices", fontsize=9)
    axp.set_ylim(0, 1.02)
    axp.grid(alpha=0.3)
    axp.legend(fontsize=7, loc="lower right")
    fig.suptitle("Starfish cage (n = %d): every method on the same tet mesh, %d vertices / %d tets "
                 "(Eq. 20-21 of Zhang et al. 2014, volume-weighted)"
                 % (data["n"], data["mesh_vertices"], data["mesh_tets"]), fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=90)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("json")
    parser.add_argument("-o", "--output", help="PNG of Q(k) and P(t)")
    args = parser.parse_args()
    with open(args.json) as f:
        data = json.load(f)
    markdown(data)
    if args.output:
        plot(data, args.output)


if __name__ == "__main__":
    main()
