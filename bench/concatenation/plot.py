#!/usr/bin/python3
"""Plots bench/concatenation results (the paper's Fig. 11 / Fig. 13): measured points of the
4,000-vertex model split into N objects, before and after concatenation, over the fitted model
lines of eqs. (1)-(2), CPU / GPU / whole frame, one row per backend.
Usage: plot.py OUT_DIR  (reads OUT_DIR/split.csv and OUT_DIR/fit.txt, writes OUT_DIR/concat_model.png)"""
import csv
import sys

import matplotlib
matplotlib.use("Agg")  # no display on the build machine
import matplotlib.pyplot as plt

V = 4000
out = sys.argv[1] if len(sys.argv) > 1 else "concat-bench"
rows = list(csv.DictReader(open(f"{out}/split.csv")))
fits = {}
for line in open(f"{out}/fit.txt"):
    b, what, c0, oh, m, s, be, be3, rb, ra = line.strip().split(",")
    fits[(b, what)] = dict(c0=float(c0), oh=float(oh), m=float(m), s=float(s), be=float(be))
backends = sorted({r["backend"] for r in rows})
fig, axes = plt.subplots(len(backends), 3, figsize=(15, 4.6 * len(backends)), squeeze=False)
for i, b in enumerate(backends):
    for j, (what, col) in enumerate((("cpu", "cpu_ms"), ("gpu", "gpu_ms"), ("frame", "frame_ms"))):
        ax = axes[i][j]
        f = fits[(b, what)]
        for mode, mark, colour, label in (("before", "o", "tab:red", "before (N draws)"),
                                          ("after", "s", "tab:blue", "after (1 draw, all members moving)"),
                                          ("after_static", "^", "tab:green", "after, nothing moving (not in the model)")):
            pts = [(int(r["objects"]), float(r[col])) for r in rows if r["backend"] == b and r["mode"] == mode]
            ax.plot([p[0] for p in pts], [p[1] for p in pts], mark, color=colour, label=label)
        ns = list(range(1, 1001, 3))
        ax.plot(ns, [f["c0"] + f["oh"] * n + f["m"] * V for n in ns], "-", color="tab:red", alpha=0.6,
                label=f"eq.1 + c0={f['c0']:.2f} ms: oh={f['oh']*1000:.2f} us, m={f['m']*1e6:.1f} ns/vtx")
        ax.plot(ns, [f["c0"] + f["oh"] + (f["s"] + f["m"]) * V for n in ns], "-", color="tab:blue", alpha=0.6,
                label=f"eq.2: s={f['s']*1e6:.1f} ns/vtx; break-even N={f['be']:.1f}")
        ax.set_title(f"{b}: {what} time per frame, {V} vertices in N objects")
        ax.set_xlabel("objects N (vertices per object = 4000 / N)")
        ax.set_ylabel("ms (median)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
fig.tight_layout()
fig.savefig(f"{out}/concat_model.png", dpi=90)
print(f"wrote {out}/concat_model.png")
