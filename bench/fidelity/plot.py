#!/usr/bin/python3
"""Frame time vs PSNR for every scene x quality-ladder point (meter-bench accuracy's accuracy.csv).

Usage: plot.py accuracy.csv out.png
Two panels, x = median frame time (ms): left y = PSNR against the supersampled maximum-quality
render (identical = plotted at 60 dB), right y = PSNR against the Blender reference (the
integrator's question: only there do the environment map and supersampling show what they buy).
The Pareto front (no other point of the same scene is both faster and more accurate) is drawn as a
line per scene, its points filled; dominated points are hollow.
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

CAP_DB = 60.0


def pareto(pts):
    """Points of one scene that no other point beats on both time (lower) and dB (higher)."""
    return sorted(p for p in pts
                  if not any(q[0] <= p[0] and q[1] >= p[1] and q != p and (q[0] < p[0] or q[1] > p[1]) for q in pts))


def panel(ax, by_scene, ylabel, title):
    cmap = plt.get_cmap("tab20")
    for i, (scene, pts) in enumerate(sorted(by_scene.items())):
        c = cmap(i % 20)
        front = pareto(pts)
        ax.scatter([p[0] for p in pts], [p[1] for p in pts], facecolors="none", edgecolors=[c], s=22)
        ax.plot([p[0] for p in front], [p[1] for p in front], "-o", color=c, ms=5, label=scene)
        for p in front:
            ax.annotate(p[2], (p[0], p[1]), fontsize=6, xytext=(3, 2), textcoords="offset points")
    ax.set_xscale("log")
    ax.set_xlabel("median frame time (ms, llvmpipe, log scale)")
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, ncol=2, loc="lower right")


def main(src, dst):
    rows = list(csv.DictReader(open(src)))
    if not rows:
        sys.exit(f"{src}: no rows")
    vs_ss, vs_blender = {}, {}
    for r in rows:
        ms = float(r["median_ms"])
        db = float(r["psnr_vs_supersampled_db"])
        db = CAP_DB if math.isinf(db) else min(db, CAP_DB)
        vs_ss.setdefault(r["scene"], []).append((ms, db, r["setting"]))
        ref = float(r["psnr_vs_blender_db"])
        if not math.isnan(ref):  # a scene without a reference has no point on the right panel
            vs_blender.setdefault(r["scene"], []).append((ms, min(ref, CAP_DB), r["setting"]))
    fig, (left, right) = plt.subplots(1, 2, figsize=(18, 7))
    panel(left, vs_ss, f"PSNR vs supersampled max quality (dB, identical plotted at {CAP_DB:.0f})",
          "vs the engine's own supersampled maximum (filled + line = Pareto front per scene)")
    panel(right, vs_blender, "PSNR vs the Blender reference (dB)",
          "vs the authoring tool: where environment maps and supersampling pay")
    fig.tight_layout()
    fig.savefig(dst, dpi=100)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
