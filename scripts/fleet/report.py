"""The HTML report of a fleet run: RUN/index.html (every drive with its verdict, duration and a
thumbnail) and RUN/drives/NAME/report.html (contact sheet and video, each bound signal as published
against what the frames drew, frame latency, faults). Static files with relative links, inline
SVG plots: opens from disk, no server. The one script reports a file the page cannot load (a
thumbnail, a frame) as a console error and on the page's root element (data-load-errors), so a
broken link is seen in a browser, not only by a link check."""
import html
import os
import re

from . import checks, results

STYLE = """body{font-family:sans-serif;margin:1.5em;background:#fafafa;color:#222}
table{border-collapse:collapse;margin:.5em 0}td,th{border:1px solid #ccc;padding:.3em .6em;text-align:left;vertical-align:top}
tr.pass td.verdict{background:#d8f5d8}tr.fail td.verdict,tr.error td.verdict,tr.lost td.verdict,tr.cancelled td.verdict{background:#f8d0d0;font-weight:bold}
img.thumb{width:200px}.sheet{display:flex;flex-wrap:wrap;gap:6px}.sheet figure{margin:0}.sheet img{width:320px}
figcaption{font-size:80%;color:#555}svg{background:#fff;border:1px solid #ddd;margin:.3em 0}.bad{color:#b00;font-weight:bold}"""
MARK = {"pass": "PASS", "fail": "FAIL ✗", "error": "ERROR ✗", "lost": "LOST ✗", "cancelled": "CANCELLED ✗"}
E = html.escape


LOAD_CHECK = """<script>
addEventListener("error", function (e) {
  var what = e.target && (e.target.currentSrc || e.target.src || e.target.href);
  if (!what) return;
  var root = document.documentElement;
  root.setAttribute("data-load-errors", (+(root.getAttribute("data-load-errors") || 0) + 1).toString());
  console.error("meter-fleet report: cannot load " + what);
}, true);
addEventListener("load", function () { document.documentElement.setAttribute("data-loaded", "1"); });
</script>"""


def _page(title, body):
    return (f"<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>{E(title)}</title>"
            f"<style>{STYLE}</style>{LOAD_CHECK}</head><body>\n{body}\n</body></html>\n")


def _rel(path, start):
    return os.path.relpath(path, start).replace(os.sep, "/")


def _spaced(items, n):
    """n items evenly spaced, first and last included (the rule of scripts/make-video's sheet)."""
    if len(items) <= n:
        return list(items)
    return [items[(j * (len(items) - 1) + (n - 1) // 2) // (n - 1)] for j in range(n)]


def write(run_dir, summary, drives):
    for r in drives:
        d = results.drive_dir(run_dir, r["name"])
        os.makedirs(d, exist_ok=True)
        with open(os.path.join(d, "report.html"), "w") as f:
            f.write(drive_page(run_dir, d, r))
    rows = []
    for r in drives:
        d = results.drive_dir(run_dir, r["name"])
        page = _rel(os.path.join(d, "report.html"), run_dir)
        thumb = ""
        if r.get("dumped"):
            png = os.path.join(d, "frames", r["dumped"][len(r["dumped"]) // 2])
            if os.path.isfile(png):
                thumb = f"<a href=\"{E(page)}\"><img class=\"thumb\" src=\"{E(_rel(png, run_dir))}\" alt=\"{E(r['name'])}\"></a>"
        v = r["verdict"]
        rows.append(f"<tr class=\"{v}\" data-drive=\"{E(r['name'])}\" data-verdict=\"{v}\"><td><a href=\"{E(page)}\">{E(r['name'])}</a></td>"
                    f"<td class=\"verdict\">{MARK.get(v, v)}</td><td>{r.get('wall_s', 0):.2f} s</td><td>{r.get('cpu_s', 0):.2f}</td>"
                    f"<td>{thumb}</td><td>{'<br>'.join(E(x) for x in r.get('reasons', []))}</td></tr>")
    counts = ", ".join(f"{summary[k]} {k}" for k in ("pass", "fail", "error", "lost", "cancelled") if summary.get(k))
    extra = "".join(f"<p>{E(k.replace('_', ' '))}: {E(', '.join(summary[k]))}</p>" for k in ("retried", "requeued_by_slurm") if summary.get(k))
    body = (f"<h1>meter-fleet: {summary['total']} drives</h1><p id=\"counts\">{E(counts)} — executor {E(summary['executor'])}, "
            f"{summary['wall_s']:.1f} s wall, {summary['cpu_s']:.1f} CPU-s in drives; manifest {E(summary.get('manifest', ''))}</p>{extra}"
            f"<p><a href=\"summary.json\">summary.json</a> · <a href=\"junit.xml\">junit.xml</a></p>"
            "<table id=\"drives\"><tr><th>drive</th><th>verdict</th><th>duration</th><th>CPU-s</th><th>frame</th><th>reason</th></tr>"
            + "\n".join(rows) + "</table>")
    with open(os.path.join(run_dir, "index.html"), "w") as f:
        f.write(_page("meter-fleet report", body))


def _read_csv(path):
    return checks.read_csv_rows(path, missing_ok=True)


_UPDATE = re.compile(r'(\S+?)=(-?[0-9][^:\s]*|-?inf|nan):([a-z-]+)')


def published(rec, start_ns=None):
    """{signal: [(t_s, value)]} from a link recording's SNAPSHOT/DELTA lines, t from the first."""
    series, first = {}, start_ns
    try:
        with open(rec, errors="replace") as f:
            for line in f:
                parts = line.split(" ", 4)
                if len(parts) < 5 or parts[1] not in ("SNAPSHOT", "DELTA"):
                    continue
                sent = int(parts[3][5:].replace(".", "")) if parts[3].startswith("sent=") else 0
                first = sent if first is None else first
                for name, value, _status in _UPDATE.findall(parts[4]):
                    series.setdefault(name, []).append(((sent - first) / 1e9, float(value)))
    except (OSError, ValueError):
        pass
    return series


def svg_plot(title, lines, points, marks, width=640, height=180, unit=""):
    """lines: [(label, colour, [(x, y)])] as polylines, points: [(label, colour, [(x, y)])] as dots,
    marks: [(x, lo, hi, ok)] as error bars (an expectation's bound)."""
    xs = [x for _, _, pts in lines + points for x, _ in pts] + [m[0] for m in marks]
    ys = [y for _, _, pts in lines + points for _, y in pts] + [v for m in marks for v in m[1:3]]
    if not xs:
        return f"<p>{E(title)}: no data</p>"
    x0, x1 = min(xs), max(xs) or 1.0
    y0, y1 = min(ys), max(ys)
    if x1 == x0:
        x1 = x0 + 1
    if y1 == y0:
        y0, y1 = y0 - 1, y1 + 1
    ml, mr, mt, mb = 50, 10, 20, 25

    def px(x):
        return ml + (x - x0) / (x1 - x0) * (width - ml - mr)

    def py(y):
        return height - mb - (y - y0) / (y1 - y0) * (height - mt - mb)
    out = [f"<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{height}\" role=\"img\" aria-label=\"{E(title)}\">",
           f"<text x=\"{ml}\" y=\"14\" font-size=\"12\">{E(title)}</text>",
           f"<text x=\"2\" y=\"{mt + 8}\" font-size=\"10\">{y1:.4g}{E(unit)}</text><text x=\"2\" y=\"{height - mb}\" font-size=\"10\">{y0:.4g}{E(unit)}</text>",
           f"<text x=\"{ml}\" y=\"{height - 8}\" font-size=\"10\">{x0:.3g} s</text><text x=\"{width - mr - 40}\" y=\"{height - 8}\" font-size=\"10\">{x1:.3g} s</text>",
           f"<rect x=\"{ml}\" y=\"{mt}\" width=\"{width - ml - mr}\" height=\"{height - mt - mb}\" fill=\"none\" stroke=\"#bbb\"/>"]
    legend = ml + 150
    for label, colour, pts in lines:
        # A step line: the value holds until the next update (how the view samples it).
        path = []
        for k, (x, y) in enumerate(pts):
            if k:
                path.append(f"{px(x):.1f},{py(pts[k - 1][1]):.1f}")
            path.append(f"{px(x):.1f},{py(y):.1f}")
        out.append(f"<polyline fill=\"none\" stroke=\"{colour}\" stroke-width=\"1.2\" points=\"{' '.join(path)}\"/>")
        out.append(f"<text x=\"{legend}\" y=\"14\" font-size=\"11\" fill=\"{colour}\">— {E(label)}</text>")
        legend += 170
    for label, colour, pts in points:
        out += [f"<circle cx=\"{px(x):.1f}\" cy=\"{py(y):.1f}\" r=\"2.5\" fill=\"{colour}\"/>" for x, y in pts]
        out.append(f"<text x=\"{legend}\" y=\"14\" font-size=\"11\" fill=\"{colour}\">● {E(label)}</text>")
        legend += 170
    for x, lo, hi, ok in marks:
        c = "#080" if ok else "#d00"
        out.append(f"<line x1=\"{px(x):.1f}\" x2=\"{px(x):.1f}\" y1=\"{py(lo):.1f}\" y2=\"{py(hi):.1f}\" stroke=\"{c}\" stroke-width=\"3\"/>")
    out.append("</svg>")
    return "".join(out)


def _signal_plots(d, r, rows):
    if not rows:
        return "<p>No frames.csv (nothing dumped).</p>"
    pub = published(os.path.join(d, "link.rec"))
    sigs = [k for k in rows[0] if k.count(".") >= 1 and not k.endswith((".status", ".failsafe", ".text"))
            and k not in ("frame", "time_s", "png", "link_up", "drawn")]
    checks = {c["signal"]: c for c in r.get("checks", []) if c.get("kind") == "signal"}
    out = []
    for s in sigs:
        drawn = [(float(x["time_s"]), float(x[s])) for x in rows if x[s] not in ("", None)]
        marks = []
        for c in (c for c in r.get("checks", []) if c.get("kind") == "signal" and c["signal"] == s):
            if isinstance(c.get("expected"), (int, float)) and c.get("tolerance") is not None:
                marks.append((c["at"], c["expected"] - c["tolerance"], c["expected"] + c["tolerance"], c["ok"]))
        title = s + ("  (checked)" if s in checks else "")
        out.append(svg_plot(title, [("published (link.rec)", "#36c", pub.get(s, []))], [("drawn (frames.csv)", "#e80", drawn)], marks))
    return "\n".join(out)


def _latency(d):
    rows = _read_csv(os.path.join(d, "timing.csv"))
    if not rows:
        return "<p>No timing.csv.</p>"
    pts = [(float(x["time_s"]), float(x["update_ms"]) + float(x["submit_ms"]) + float(x["gpu_readback_ms"])) for x in rows]
    ms = sorted(y for _, y in pts)
    p50, p99 = ms[len(ms) // 2], ms[min(len(ms) - 1, int(len(ms) * 0.99))]
    return (f"<p>Render time per frame (update + submit + GPU/readback, wall ms on the machine that ran it): "
            f"median {p50:.2f} ms, p99 {p99:.2f} ms over {len(ms)} frames. On the simulated clock a frame shows "
            f"the state published at or before its time: at most one frame period late.</p>"
            + svg_plot("render ms per frame", [], [("frame", "#555", pts)], [], unit=" ms"))


def _sheet(d, r, frames):
    out = []
    sheet, video = os.path.join(d, "frames", "contact-sheet.png"), os.path.join(d, "frames", "replay.mp4")
    if os.path.isfile(sheet):
        out.append(f"<p><a href=\"frames/contact-sheet.png\"><img src=\"frames/contact-sheet.png\" alt=\"contact sheet\" style=\"max-width:100%\"></a></p>")
    if os.path.isfile(video):
        out.append("<p><video controls preload=\"none\" src=\"frames/replay.mp4\" width=\"640\"></video> <a href=\"frames/replay.mp4\">replay.mp4</a></p>")
    times = {x["png"]: x["time_s"] for x in frames}
    if out:  # make-video's sheet and video (video = true in the manifest) stand for the frames
        return "\n".join(out)
    figs = [f"<figure><a href=\"frames/{E(p)}\"><img src=\"frames/{E(p)}\" alt=\"{E(p)}\"></a><figcaption>{E(p)} · t = {float(times.get(p, 'nan')):.2f} s</figcaption></figure>"
            for p in _spaced(r.get("dumped", []), 12) if os.path.isfile(os.path.join(d, "frames", p))]
    if figs:
        out.append("<div class=\"sheet\">" + "".join(figs) + "</div>")
    return "\n".join(out) or "<p>No frames dumped.</p>"


def drive_page(run_dir, d, r):
    v = r["verdict"]
    frames = _read_csv(os.path.join(d, "frames", "frames.csv"))  # read once: the sheet and the plots
    reasons = "".join(f"<li class=\"bad\">{E(x)}</li>" for x in r.get("reasons", []))
    stages = "".join(f"<tr><td>{E(s['name'])}</td><td>{s['exit']}</td><td>{s['wall_s']:.2f}</td><td>{s['cpu_s']:.2f}</td>"
                     f"<td><a href=\"{E(_rel(s['log'], d))}\">{E(os.path.basename(s['log']))}</a></td></tr>"
                     for s in r.get("stages", []) if os.path.isfile(s["log"]))
    checks = "".join(f"<tr class=\"{'pass' if c['ok'] else 'fail'}\"><td>{E(c['kind'])}</td><td class=\"verdict\">{'ok' if c['ok'] else 'FAILED ✗'}</td>"
                     f"<td>{E(c['message'])}</td></tr>" for c in r.get("checks", []))
    faults = "".join(f"<li>{E(x)}</li>" for x in r.get("faults", [])) or "<li>none reported</li>"
    files = " · ".join(f"<a href=\"{n}\">{n}</a>" for n in ("result.json", "junit.xml", "link.rec", "frames/frames.csv", "timing.csv")
                       if os.path.isfile(os.path.join(d, n)))
    body = (f"<p><a href=\"{E(_rel(os.path.join(run_dir, 'index.html'), d))}\">← all drives</a></p>"
            f"<h1 class=\"{v}\">{E(r['name'])}: <span id=\"verdict\" data-verdict=\"{v}\">{MARK.get(v, v)}</span></h1>"
            + (f"<ul>{reasons}</ul>" if reasons else "")
            + f"<p>{r.get('wall_s', 0):.2f} s wall, {r.get('cpu_s', 0):.2f} CPU-s on {E(str(r.get('host', '?')))}, attempt {r.get('attempt', '?')}. {files}</p>"
            + f"<h2>Stages</h2><table><tr><th>stage</th><th>exit</th><th>wall s</th><th>CPU s</th><th>log</th></tr>{stages}</table>"
            + f"<h2>Checks</h2><table><tr><th>kind</th><th>result</th><th>what</th></tr>{checks}</table>"
            + f"<h2>Frames</h2>{_sheet(d, r, frames)}"
            + f"<h2>Signals: published vs drawn</h2><p>Blue: the value the controller published (the recording); orange: "
              f"the value each dumped frame drew (frames.csv); bars: the expectations (green held, red failed).</p>{_signal_plots(d, r, frames)}"
            + f"<h2>Latency</h2>{_latency(d)}"
            + f"<h2>Faults</h2><ul>{faults}</ul><p>controller: {E(r.get('controller_summary', ''))}</p>"
              f"<p>view: {E(r.get('view_summary', ''))}</p>")
    return _page(f"{r['name']} — meter-fleet", body)
