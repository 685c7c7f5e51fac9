#!/usr/bin/env python3
"""Averaged power spectra of 2D projections next to the projections themselves.

usage: python3 study/plot_spectra.py [OUT_DIR]   (default docs/study)
reads OUT_DIR/spectra.csv (oas::study::writeSpectra: sampler,pattern,N,pair,kx,ky,power) and,
when present, OUT_DIR/points.csv (sampler,pattern,N,pair,dim_a,dim_b,i,x,y); writes
OUT_DIR/spectra.png: one row per sampler; for each pair a scatter plot of one point set and the
averaged periodogram P(k) of that pair, plus the radially averaged power of all its pairs.

How to read it (Jarosz et al. 2019 explain OA sampling with such pictures; Heck et al. 2013 read
blue-noise patterns the same way): independent uniform points have E[P(k)] = 1 at every k != 0,
so the colour scale is fixed at 0..2 with 1 in the middle for every panel. A dark horizontal and
vertical axis means both 1D projections are stratified (Latin hypercube); a dark disc around the
centre means the 2D projection is stratified too; bright isolated peaks (clipped at 2) are
regular structure (aliasing). The DC term P(0) = N carries no information and is stored as 0.
Needs python3-matplotlib (numpy comes with it).
"""
import csv
import os
import sys
from collections import OrderedDict, defaultdict

VMAX = 2.0  # shared colour range 0..VMAX: white noise (random points) sits at 1


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def main(argv):
    out = argv[1] if len(argv) > 1 else "docs/study"
    spectra_path = os.path.join(out, "spectra.csv")
    if not os.path.isfile(spectra_path):
        sys.stderr.write(
            f"plot_spectra: {spectra_path} not found; write it first with oas::study::writeSpectra "
            "(study/spectrum.hpp)\n")
        return 2
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        import numpy as np
    except ImportError as e:
        sys.stderr.write(f"plot_spectra: {e}; install python3-matplotlib (Debian) and run with /usr/bin/python3\n")
        return 2

    # (sampler, pair) -> {(kx, ky): power}; keep file order of samplers and of each sampler's pairs.
    spectra = OrderedDict()
    described = {}
    for r in read_rows(spectra_path):
        key = (r["sampler"], r["pair"])
        spectra.setdefault(key, {})[(int(r["kx"]), int(r["ky"]))] = float(r["power"])
        described[r["sampler"]] = (r["pattern"], r["N"])
    if not spectra:
        sys.stderr.write(f"plot_spectra: {spectra_path} has no rows\n")
        return 2
    samplers = list(OrderedDict.fromkeys(s for s, _ in spectra))
    pairs_of = OrderedDict((s, [p for t, p in spectra if t == s]) for s in samplers)

    points = defaultdict(list)
    points_path = os.path.join(out, "points.csv")
    if os.path.isfile(points_path):
        seen = set()
        for r in read_rows(points_path):
            key = (r["sampler"], r["pair"])
            # points.csv may list a pair twice (older dumps repeated a pair that equals the
            # cross-block one); keep the first copy of each sample index.
            if (key, r["i"]) in seen:
                continue
            seen.add((key, r["i"]))
            points[key].append((float(r["x"]), float(r["y"])))

    def grid(values):
        r = max(max(abs(kx), abs(ky)) for kx, ky in values)
        g = np.zeros((2 * r + 1, 2 * r + 1))
        for (kx, ky), v in values.items():
            g[ky + r, kx + r] = v  # row = ky (origin="lower" puts -r at the bottom)
        return r, g

    def radial(values):
        # Mean power in rings of width 1 around integer |k| (DC excluded), as radialProfile().
        sums, counts = defaultdict(float), defaultdict(int)
        for (kx, ky), v in values.items():
            if kx == 0 and ky == 0:
                continue
            b = int(np.floor(np.hypot(kx, ky) + 0.5))
            sums[b] += v
            counts[b] += 1
        r = max(max(abs(kx), abs(ky)) for kx, ky in values)
        ks = [b for b in sorted(sums) if b <= r]  # full rings only
        return ks, [sums[b] / counts[b] for b in ks]

    max_pairs = max(len(p) for p in pairs_of.values())
    ncols = 2 * max_pairs + 1
    nrows = len(samplers)
    fig, axes = plt.subplots(nrows, ncols, figsize=(1.75 * ncols + 0.8, 1.85 * nrows + 0.6), squeeze=False)
    image = None
    for row, s in enumerate(samplers):
        for c in range(ncols):
            axes[row][c].set_axis_off()
        for j, pair in enumerate(pairs_of[s]):
            ax_pts, ax_spec = axes[row][2 * j], axes[row][2 * j + 1]
            pts = points.get((s, pair))
            ax_pts.set_axis_on()
            ax_pts.set_xlim(0, 1)
            ax_pts.set_ylim(0, 1)
            ax_pts.set_aspect("equal")
            ax_pts.set_xticks([])
            ax_pts.set_yticks([])
            if pts:
                xs, ys = zip(*pts)
                ax_pts.scatter(xs, ys, s=2.5, c="black", linewidths=0)
            else:
                ax_pts.text(0.5, 0.5, "no points", ha="center", va="center", fontsize=7, color="gray")
            ax_pts.set_title(f"{pair}", fontsize=7)

            r, g = grid(spectra[(s, pair)])
            ax_spec.set_axis_on()
            image = ax_spec.imshow(g, origin="lower", extent=(-r - 0.5, r + 0.5, -r - 0.5, r + 0.5),
                                   cmap="magma", vmin=0.0, vmax=VMAX, interpolation="nearest")
            ax_spec.set_xticks([-r, 0, r])
            ax_spec.set_yticks([-r, 0, r])
            ax_spec.tick_params(labelsize=5, length=2, pad=1)
            ax_spec.set_title(f"P(k) {pair}", fontsize=7)
        pattern, n = described[s]
        axes[row][0].set_ylabel(f"{s}\nN={n}", fontsize=8)

        ax_rad = axes[row][ncols - 1]
        ax_rad.set_axis_on()
        for pair in pairs_of[s]:
            ks, ps = radial(spectra[(s, pair)])
            ax_rad.plot(ks, ps, lw=0.9, label=pair)
        ax_rad.axhline(1.0, color="gray", lw=0.6, ls="--")
        ax_rad.set_ylim(0, VMAX)
        ax_rad.tick_params(labelsize=5, length=2, pad=1)
        ax_rad.set_title("radial mean vs |k|", fontsize=7)
        ax_rad.legend(fontsize=4.5, loc="lower right", frameon=False)

    fig.suptitle("2D projections (one randomization) and their averaged power spectra P(k) "
                 f"(DC set to 0; colour 0..{VMAX:g}, random points: 1; brighter peaks clipped)", fontsize=9)
    fig.tight_layout(rect=(0, 0, 0.94, 0.98))
    if image is not None:
        cax = fig.add_axes((0.95, 0.25, 0.012, 0.5))
        fig.colorbar(image, cax=cax).ax.tick_params(labelsize=7)
    path = os.path.join(out, "spectra.png")
    fig.savefig(path, dpi=130)
    plt.close(fig)
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
