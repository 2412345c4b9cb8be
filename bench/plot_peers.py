#!/usr/bin/env python3
"""Plots the peers table (bench/peers/run_peers.py's Markdown output) as time against error:
one log-log panel per comparison, render seconds across, relMSE against each renderer's own
converged image up, one curve per renderer, points labelled with samples per pixel.

    python3 bench/plot_peers.py PEERS.md OUT.svg

Standard library only; bench/run_all.sh turns the SVG into a PNG with headless Chromium.
"""
import math
import sys
from collections import OrderedDict

COLOURS = ["#1f6fb4", "#d9572b", "#2a9d5c", "#8e44ad"]
PANEL_W, PANEL_H, MARGIN = 420, 300, 60


def read_rows(path):
    rows = []
    for line in open(path):
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        try:
            spp = float(cells[2]) if len(cells) >= 8 else None
        except ValueError:
            spp = None
        if spp is None:
            continue
        if cells[7] in ("reference", "-", ""):
            continue
        rows.append({"comparison": cells[0], "renderer": cells[1], "spp": spp,
                     "seconds": float(cells[3]), "relmse": float(cells[7])})
    return rows


def log_scale(lo, hi, size, flip=False):
    a, b = math.log10(lo), math.log10(hi)
    def f(v):
        t = (math.log10(v) - a) / (b - a)
        return size * (1 - t) if flip else size * t
    return f


def decade_bounds(values):
    return 10 ** math.floor(math.log10(min(values))), 10 ** math.ceil(math.log10(max(values)))


def panel(out, x0, y0, title, curves):
    xs = [p["seconds"] for c in curves.values() for p in c]
    ys = [p["relmse"] for c in curves.values() for p in c]
    xlo, xhi = decade_bounds(xs)
    ylo, yhi = decade_bounds(ys)
    fx, fy = log_scale(xlo, xhi, PANEL_W), log_scale(ylo, yhi, PANEL_H, flip=True)
    out.append(f'<g transform="translate({x0},{y0})">')
    out.append(f'<text x="{PANEL_W / 2}" y="-12" text-anchor="middle" font-size="14">{title}</text>')
    out.append(f'<rect width="{PANEL_W}" height="{PANEL_H}" fill="none" stroke="#333"/>')
    for e in range(int(math.log10(xlo)), int(math.log10(xhi)) + 1):
        x = fx(10 ** e)
        out.append(f'<line x1="{x}" y1="0" x2="{x}" y2="{PANEL_H}" stroke="#ddd"/>')
        out.append(f'<text x="{x}" y="{PANEL_H + 16}" text-anchor="middle" font-size="11">1e{e}</text>')
    for e in range(int(math.log10(ylo)), int(math.log10(yhi)) + 1):
        y = fy(10 ** e)
        out.append(f'<line x1="0" y1="{y}" x2="{PANEL_W}" y2="{y}" stroke="#ddd"/>')
        out.append(f'<text x="-6" y="{y + 4}" text-anchor="end" font-size="11">1e{e}</text>')
    out.append(f'<text x="{PANEL_W / 2}" y="{PANEL_H + 34}" text-anchor="middle" font-size="12">'
               'render seconds (log)</text>')
    out.append(f'<text transform="translate(-44,{PANEL_H / 2}) rotate(-90)" text-anchor="middle" '
               'font-size="12">relMSE vs own reference (log)</text>')
    for i, (name, points) in enumerate(curves.items()):
        colour = COLOURS[i % len(COLOURS)]
        pts = sorted(points, key=lambda p: p["spp"])
        path = " ".join(f'{fx(p["seconds"]):.1f},{fy(p["relmse"]):.1f}' for p in pts)
        out.append(f'<polyline points="{path}" fill="none" stroke="{colour}" stroke-width="2"/>')
        for p in pts:
            x, y = fx(p["seconds"]), fy(p["relmse"])
            out.append(f'<circle cx="{x:.1f}" cy="{y:.1f}" r="4" fill="{colour}"/>')
            out.append(f'<text x="{x + 6:.1f}" y="{y - 6:.1f}" font-size="10" fill="{colour}">'
                       f'{p["spp"]:g}</text>')
        out.append(f'<rect x="{PANEL_W - 150}" y="{10 + 18 * i}" width="12" height="12" fill="{colour}"/>')
        out.append(f'<text x="{PANEL_W - 132}" y="{20 + 18 * i}" font-size="12">{name}</text>')
    out.append("</g>")


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: plot_peers.py PEERS.md OUT.svg")
    groups = OrderedDict()
    for row in read_rows(sys.argv[1]):
        if "Lambert" in row["comparison"]:
            continue
        groups.setdefault(row["comparison"], OrderedDict()).setdefault(row["renderer"], []).append(row)
    if not groups:
        sys.exit(f"plot_peers.py: {sys.argv[1]}: no rows with a relMSE")
    width = len(groups) * (PANEL_W + 2 * MARGIN)
    height = PANEL_H + 2 * MARGIN + 20
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
           'font-family="DejaVu Sans, sans-serif">',
           f'<rect width="{width}" height="{height}" fill="white"/>']
    for i, (title, curves) in enumerate(groups.items()):
        panel(out, MARGIN + i * (PANEL_W + 2 * MARGIN), MARGIN, title, curves)
    out.append("</svg>")
    with open(sys.argv[2], "w") as f:
        f.write("\n".join(out) + "\n")
    print(f"wrote {sys.argv[2]} ({len(groups)} panels, {width}x{height})")


if __name__ == "__main__":
    main()
