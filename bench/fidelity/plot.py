#!/usr/bin/python3
"""Frame time vs PSNR for every scene x quality-ladder point (meter-bench accuracy's accuracy.csv).

Usage: plot.py accuracy.csv out.png
One panel: x = median frame time (ms), y = PSNR against the supersampled maximum-quality render
(identical = plotted at 60 dB). The Pareto front (no other point of the same scene is both faster
and more accurate) is drawn as a line per scene, its points filled; dominated points are hollow.
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

CAP_DB = 60.0


def main(src, dst):
    rows = list(csv.DictReader(open(src)))
    if not rows:
        sys.exit(f"{src}: no rows")
    by_scene = {}
    for r in rows:
        db = float(r["psnr_vs_supersampled_db"])
        db = CAP_DB if math.isinf(db) else min(db, CAP_DB)
        by_scene.setdefault(r["scene"], []).append((float(r["median_ms"]), db, r["setting"]))
    fig, ax = plt.subplots(figsize=(11, 7))
    cmap = plt.get_cmap("tab20")
    for i, (scene, pts) in enumerate(sorted(by_scene.items())):
        c = cmap(i % 20)
        front = [p for p in pts if not any(q[0] <= p[0] and q[1] >= p[1] and q != p and (q[0] < p[0] or q[1] > p[1]) for q in pts)]
        front.sort()
        ax.scatter([p[0] for p in pts], [p[1] for p in pts], facecolors="none", edgecolors=[c], s=22)
        ax.plot([p[0] for p in front], [p[1] for p in front], "-o", color=c, ms=5, label=scene)
        for p in front:
            ax.annotate(p[2], (p[0], p[1]), fontsize=6, xytext=(3, 2), textcoords="offset points")
    ax.set_xscale("log")
    ax.set_xlabel("median frame time (ms, llvmpipe, log scale)")
    ax.set_ylabel(f"PSNR vs supersampled max quality (dB, identical plotted at {CAP_DB:.0f})")
    ax.set_title("meter quality ladder: frame time vs accuracy (filled + line = Pareto front per scene)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, ncol=2, loc="lower right")
    fig.tight_layout()
    fig.savefig(dst, dpi=110)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
