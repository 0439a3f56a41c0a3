#!/usr/bin/env python3
"""The LBC paper's Table 2 analog from bench_local_barycentric_coordinates' JSON output.

Prints the LBCTable2 and LBCReference rows as Markdown tables and, with -o, plots one-thread
CPU time against mesh vertices for LBC (paper's rule), BBW fast and BBW coupled on the same
meshes (needs python3-matplotlib):

    /usr/bin/python3 testing/benchmarks/plot_lbc.py testing/benchmarks/results/lbc.json \
        -o docs/images/lbc_table2_time.png
"""
import argparse
import json


def rows(path):
    with open(path) as f:
        data = json.load(f)
    return data["context"], [b for b in data["benchmarks"] if b.get("run_type", "iteration") == "iteration"]


def table2(benchmarks):
    out = []
    for b in benchmarks:
        if not b["name"].startswith("LBCTable2/"):
            continue
        _, case, tol = b["name"].split("/")[:3]
        out.append(dict(b, case=int(case), tight=tol == "1", label=b.get("label", "")))
    return out


def markdown(benchmarks):
    print("| case | n | |V| / cells | LBC iterations | LBC CPU | BBW fast CPU | BBW coupled CPU |"
          " LBC / fast | support LBC / fast / coupled |")
    print("|---|---:|---|---:|---:|---:|---:|---:|---|")
    for b in table2(benchmarks):
        name = b["label"].split(",")[0] + (" (1e-7 / 1e-6)" if b["tight"] else "")
        fast = b.get("bbw_fast_cpu_seconds")
        coupled = b.get("bbw_coupled_cpu_seconds")
        print("| {} | {:.0f} | {:.0f} / {:.0f} | {:.0f} | {:.3g} s | {} | {} | {} | {:.2f} / {} / {} |".format(
            name, b["n"], b["vertices"], b["cells"], b["lbc_iterations"], b["lbc_cpu_seconds"],
            "–" if fast is None else "{:.3g} s".format(fast),
            "–" if coupled is None else "{:.3g} s".format(coupled),
            "–" if fast is None else "{:.1f}".format(b["lbc_cpu_seconds"] / fast),
            b["lbc_support_mean"],
            "–" if fast is None else "{:.2f}".format(b["bbw_fast_support_mean"]),
            "–" if coupled is None else "{:.2f}".format(b["bbw_coupled_support_mean"])))
    print()
    print("| reference run | iterations | CPU | ref CPU | speed-up | objective | ref objective | rel |"
          " max / mean dW | support mean/max (ref) | min w (ref) | partition / repro |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---|---|---|---|")
    for b in benchmarks:
        if not b["name"].startswith("LBCReference/"):
            continue
        print("| {} | {:.0f} ({:.0f}) | {:.3g} s | {:.3g} s | {:.1f}x | {:.6g} | {:.6g} | {:+.4f}% | {:.2g} / {:.2g} |"
              " {:.2f} / {:.0f} ({:.2f} / {:.0f}) | {:.2g} ({:.2g}) | {:.2g} / {:.2g} |".format(
                  b["label"], b["iterations"], b["ref_iterations"], b["cpu_s"], b["ref_cpu_s"],
                  b["speedup"], b["objective"], b["ref_objective"], 100 * b["objective_rel"],
                  b["max_dW"], b["mean_dW"], b["support_mean"], b["support_max"],
                  b["ref_support_mean"], b["ref_support_max"], b["min_w"], b["ref_min_w"],
                  b["partition_err"], b["repro_err"]))


def plot(benchmarks, output):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t2 = [b for b in table2(benchmarks) if not b["tight"]]
    fig, ax = plt.subplots(figsize=(7, 4.5))
    series = [("lbc_cpu_seconds", "LBC (paper's rule)", "C0"),
              ("bbw_fast_cpu_seconds", "BBW fast", "C1"),
              ("bbw_coupled_cpu_seconds", "BBW coupled", "C2")]
    for key, name, colour in series:
        for dim, marker in ((2, "o"), (3, "s")):
            pts = [(b["vertices"], b[key]) for b in t2
                   if key in b and (b["case"] in (5, 6, 7, 8)) == (dim == 3)]
            if pts:
                ax.scatter(*zip(*pts), marker=marker, color=colour,
                           facecolors=colour if dim == 2 else "none",
                           label="{} ({}D)".format(name, dim))
    for b in t2:
        ax.annotate(b["label"].split(",")[0].replace(" (paper's |V|)", "*"),
                    (b["vertices"], b["lbc_cpu_seconds"]), fontsize=7,
                    xytext=(3, 3), textcoords="offset points")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("mesh vertices |V|")
    ax.set_ylabel("CPU time, one thread (s)")
    ax.set_title("LBC vs BBW on the same meshes (Table 2 analog; * = paper's |V|)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, ncol=2)
    fig.tight_layout()
    fig.savefig(output, dpi=110)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("json")
    p.add_argument("-o", "--output", help="PNG to write")
    a = p.parse_args()
    context, benchmarks = rows(a.json)
    print("load_avg:", context.get("load_avg"), " date:", context.get("date"))
    markdown(benchmarks)
    if a.output:
        plot(benchmarks, a.output)


if __name__ == "__main__":
    main()
