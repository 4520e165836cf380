#!/usr/bin/env python3
"""Plots docs/images/spectral_error.png from the CSV files tools/spectral_report writes.

Top: Delta E*ab (CIE 1976) of the 24 ColorChecker patches after the round trip through each
wavelength preset (bars), and after white balancing the preset's own white to D65 (dots).
Bottom left: the distribution of Delta E*ab over 10,000 random linear-sRGB colours per preset.
Bottom right: the RGB -> spectrum table's error against its resolution, lookup alone and with
the Gauss-Newton polish.

Needs matplotlib and numpy (Debian: python3-matplotlib python3-numpy; tools/install_deps.sh).
Usage: plot_spectral.py [DIR]   (DIR holds the CSV files and receives the PNG; default docs/images)
"""
import csv
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
PRESETS = ["daisyriot", "meyer4", "visible", "fine"]
COLOURS = {"daisyriot": "#d62728", "meyer4": "#9467bd", "visible": "#1f77b4", "fine": "#2ca02c"}


def read(path):
    with path.open(newline="") as f:
        return list(csv.DictReader(f))


def main():
    folder = Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "docs" / "images"
    patches = read(folder / "spectral_error.csv")
    quantiles = read(folder / "spectral_random_quantiles.csv")
    resolution = read(folder / "spectral_table_resolution.csv")

    fig = plt.figure(figsize=(12, 8.5), dpi=110)
    grid = fig.add_gridspec(2, 2, height_ratios=[1.15, 1], hspace=0.42, wspace=0.22)

    ax = fig.add_subplot(grid[0, :])
    names = [row["patch"] for row in patches if row["preset"] == PRESETS[0]]
    swatches = [tuple(int(row[f"srgb8_{c}"]) / 255 for c in "rgb")
                for row in patches if row["preset"] == PRESETS[0]]
    x = np.arange(len(names))
    width = 0.8 / len(PRESETS)
    for k, preset in enumerate(PRESETS):
        rows = [row for row in patches if row["preset"] == preset]
        samples = rows[0]["samples"]
        raw = [float(row["delta_e"]) for row in rows]
        balanced = [float(row["delta_e_balanced"]) for row in rows]
        offset = (k - (len(PRESETS) - 1) / 2) * width
        ax.bar(x + offset, raw, width, color=COLOURS[preset],
               label=f"{preset} ({samples} samples)")
        ax.plot(x + offset, balanced, "o", color="black", markersize=2.5,
                label="white-balanced" if k == 0 else None)
    ax.set_yscale("log")
    ax.set_ylim(5e-3, 400)
    ax.axhline(1.0, color="grey", linewidth=0.8, linestyle="--")
    ax.text(len(names) - 0.5, 1.08, "dE*ab = 1", ha="right", va="bottom", fontsize=8,
            color="grey")
    ax.set_xticks(x)
    ax.set_xticklabels(names, rotation=55, ha="right", fontsize=8)
    for tick, swatch in zip(ax.get_xticklabels(), swatches):
        tick.set_bbox(dict(facecolor=swatch, edgecolor="none", pad=1.5))
        tick.set_color("white" if sum(swatch) < 1.2 else "black")
    ax.set_xlim(-0.6, len(names) - 0.4)
    ax.set_ylabel("dE*ab (CIE 1976) vs the input colour")
    ax.set_title("ColorChecker patches under D65: RGB -> spectrum -> samples -> XYZ -> RGB")
    ax.legend(fontsize=8, ncol=5, loc="upper left")

    ax = fig.add_subplot(grid[1, 0])
    for preset in PRESETS:
        rows = [row for row in quantiles if row["preset"] == preset]
        q = [float(row["quantile"]) for row in rows]
        de = [max(float(row["delta_e"]), 1e-4) for row in rows]
        ax.plot(de, q, color=COLOURS[preset], label=preset)
    ax.set_xscale("log")
    ax.set_xlabel("dE*ab")
    ax.set_ylabel("fraction of colours")
    ax.set_title("10,000 random linear-sRGB colours")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)

    ax = fig.add_subplot(grid[1, 1])
    res = [int(row["resolution"]) for row in resolution]
    for key, label, style in [("lookup_max", "lookup, max", "-o"),
                              ("lookup_p99", "lookup, 99th percentile", "--o"),
                              ("lookup_median", "lookup, median", ":o"),
                              ("polished_max", "lookup + Gauss-Newton, max", "-s")]:
        ax.plot(res, [float(row[key]) for row in resolution], style, markersize=4, label=label)
    ax.axhline(2e-3, color="grey", linewidth=0.8, linestyle="--")
    ax.text(res[0], 2.2e-3, "2e-3", fontsize=8, color="grey")
    ax.set_yscale("log")
    ax.set_xticks(res)
    ax.set_xlabel("table resolution (nodes per axis)")
    ax.set_ylabel("max |RGB error| (linear sRGB)")
    ax.set_title("RGB -> spectrum table (1 nm colorimetry)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)

    out = folder / "spectral_error.png"
    fig.savefig(out, bbox_inches="tight")
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
