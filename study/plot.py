#!/usr/bin/env python3
"""Figures of the oas analytic-integrand study from the CSVs that oas-study writes.

usage: python3 study/plot.py [OUT_DIR]   (default docs/study)
writes OUT_DIR/mse_<D>d.png (MSE vs N, every integrand), goal_2additive_binary.png,
projections.png (2D projections from points.csv), the scene figures scene_error_vs_spp.png,
scene_error_vs_time.png and scene_equal_time.png (from scene_curves.csv, scene_equal_time.csv and
the PNGs under OUT_DIR/scenes/), and spectra.png (plot_spectra.py). Each figure is drawn only when
its CSV exists. Needs python3-matplotlib.
"""
import csv
import math
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

STYLE = {
    "BoseCMJ": ("tab:red", "-", "o"), "BoseMJ": ("tab:orange", "-", "s"),
    "BushMJ(t=2)": ("tab:brown", "-", "^"), "BoseBushCMJ": ("tab:pink", "-", "v"),
    "AddelmanKempthorneCMJ": ("tab:purple", "-", "D"), "OA-chooser(t=2,cmj)": ("black", "-", "x"),
    "CMJND(t=4)": ("tab:olive", "-", "*"), "Random": ("gray", "--", "."),
    "Jittered2D-pad": ("tab:cyan", "--", "s"), "CMJ2D-pad": ("tab:blue", "--", "o"),
    "ZeroTwo-pad": ("tab:green", "--", "^"), "Halton": ("tab:gray", ":", "v"), "Sobol": ("navy", ":", "D"),
}


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def slopes(out):
    path = os.path.join(out, "slopes.csv")
    table = {}
    if os.path.exists(path):
        for r in read(path):
            table[(r["dims"], r["integrand"], r["sampler"])] = float(r["slope"])
    return table


def errorbar_loglog(ax, x, y, se, floor, **kw):
    """y ± 1 s.e. on log-log axes; the lower bar is clipped at floor (a bar reaching 0 has no log)."""
    y = [max(v, floor) for v in y]
    lo = [min(e, v - floor) if e == e else 0 for v, e in zip(y, se)]  # NaN s.e. (n = 1): no bar
    hi = [e if e == e else 0 for e in se]
    ax.errorbar(x, y, yerr=[lo, hi], capsize=1.5, elinewidth=0.6, **kw)
    ax.set_xscale("log")
    ax.set_yscale("log")


def draw(ax, rows, integrand, dims, slope_table, samplers=None):
    by = defaultdict(list)
    for r in rows:
        if r["integrand"] == integrand:
            # mse_stderr: the standard error of the MSE over the trials (analytic.csv).
            by[r["sampler"]].append((int(r["N"]), float(r["mse"]), float(r.get("mse_stderr") or 0)))
    for name, pts in by.items():
        if samplers and name not in samplers:
            continue
        pts.sort()
        color, ls, mk = STYLE.get(name, (None, "-", "o"))
        s = slope_table.get((dims, integrand, name))
        label = f"{name} ({s:.2f})" if s is not None else name
        errorbar_loglog(ax, [p[0] for p in pts], [p[1] for p in pts], [p[2] for p in pts], 1e-300, ls=ls,
                        marker=mk, ms=3, color=color, lw=1, label=label)
    ax.set_title(integrand, fontsize=8)
    ax.set_xlabel("N", fontsize=7)
    ax.set_ylabel("MSE", fontsize=7)
    ax.tick_params(labelsize=6)
    ax.grid(True, which="both", alpha=0.2)


def scene_figures(out):
    path = os.path.join(out, "scene_curves.csv")
    if not os.path.exists(path):
        return
    rows = read(path)
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    # Times come from each scene's one cost run (scene_costs.csv), never from the accuracy renders.
    costs = {}
    cost_path = os.path.join(out, "scene_costs.csv")
    if os.path.exists(cost_path):
        for r in read(cost_path):
            costs[(r["scene"], r["sampler"], float(r["spp"]))] = float(r["seconds"])

    def highlighted(scene):
        """At most five lines stand out per panel: Random, Sobol, the best padded 2D sampler and the
        best OA (lowest mean relMSE near 128 spp) and BoseCMJ, the OA the chooser picks."""
        near = {}
        for r in rows:
            if r["scene"] != scene:
                continue
            d = abs(math.log(float(r["spp"]) / 128))
            if r["sampler"] not in near or d < near[r["sampler"]][0]:
                near[r["sampler"]] = (d, float(r["rel_mse"]))
        def best(pred):
            c = [(v[1], k) for k, v in near.items() if pred(k)]
            return min(c)[1] if c else None
        is_oa = lambda k: k.startswith(("Bose", "Bush", "Addelman", "CMJND", "OA-"))
        keep = ["Random", "Sobol", best(lambda k: k.endswith("-pad")), "BoseCMJ", best(is_oa)]
        return [k for k in dict.fromkeys(keep) if k]

    def curve(scene, name, xkey, ykey):
        pts = []
        for r in rows:
            if r["scene"] != scene or r["sampler"] != name:
                continue
            x = float(r["spp"]) if xkey == "spp" else costs.get((scene, name, float(r["spp"])))
            if x is not None:
                pts.append((x, float(r[ykey]), float(r.get(ykey + "_se") or 0)))
        return sorted(pts)

    for xkey, fname, xlabel in (("spp", "scene_error_vs_spp.png", "samples per pixel"),
                                ("seconds", "scene_error_vs_time.png", "render time, one cost run per scene (s)")):
        panels = (("rel_mse", "full image"), ("rel_mse_crop", "crop")) + ((("ratio", "÷ Sobol"),) if xkey == "seconds" else ())
        fig, axes = plt.subplots(len(panels), len(scenes), figsize=(5.5 * len(scenes), 4.5 * len(panels)), squeeze=False)
        for j, scene in enumerate(scenes):
            keep = highlighted(scene)
            names = list(dict.fromkeys(r["sampler"] for r in rows if r["scene"] == scene))
            timed = xkey == "spp" or any(k[0] == scene for k in costs)
            for i, (ykey, what) in enumerate(panels):
                ax = axes[i][j]
                if ykey == "ratio":
                    # Each highlighted sampler's full-image relMSE ÷ Sobol's at the same time (Sobol's
                    # curve interpolated in log-log), with a ±1 s.e. band (relative s.e.s added in quadrature).
                    sob = curve(scene, "Sobol", xkey, "rel_mse")
                    for name in keep:
                        pts = curve(scene, name, xkey, "rel_mse")
                        xs, rs, lo, hi = [], [], [], []
                        for x, y, se in pts:
                            if len(sob) < 2 or not (sob[0][0] <= x <= sob[-1][0]):
                                continue
                            k = max(i for i in range(len(sob) - 1) if sob[i][0] <= x) if x < sob[-1][0] else len(sob) - 2
                            (x0, y0, s0), (x1, y1, s1) = sob[k], sob[k + 1]
                            t = math.log(x / x0) / math.log(x1 / x0) if x1 != x0 else 0
                            ys = math.exp((1 - t) * math.log(y0) + t * math.log(y1))
                            rse = math.sqrt((se / y) ** 2 + ((1 - t) * s0 / y0 + t * s1 / y1) ** 2)
                            r = y / ys
                            xs.append(x); rs.append(r); lo.append(r * (1 - rse)); hi.append(r * (1 + rse))
                        color, ls, mk = STYLE.get(name, (None, "-", "o"))
                        if xs:
                            ax.plot(xs, rs, ls=ls, marker=mk, ms=3, color=color, lw=1.2, label=name)
                            ax.fill_between(xs, lo, hi, color=color, alpha=0.15, lw=0)
                    ax.axhline(1.0, color="black", lw=0.8)
                    ax.set_xscale("log")
                    ax.set_yscale("log")
                    ax.set_ylabel("relMSE ÷ Sobol's at equal time", fontsize=8)
                    ax.set_title(f"{scene}: error ÷ Sobol's (below 1: better), ± 1 s.e.", fontsize=9)
                else:
                    for name in sorted(names, key=lambda n: n in keep):  # highlighted lines on top
                        pts = curve(scene, name, xkey, ykey)
                        if not pts:
                            continue
                        color, ls, mk = STYLE.get(name, (None, "-", "o"))
                        if name in keep:
                            errorbar_loglog(ax, [p[0] for p in pts], [p[1] for p in pts], [p[2] for p in pts], 1e-12,
                                            ls=ls, marker=mk, ms=3, color=color, lw=1.4, label=name)
                        else:
                            ax.loglog([p[0] for p in pts], [p[1] for p in pts], color="0.7", lw=0.6, alpha=0.6)
                    ax.set_ylabel("relative MSE", fontsize=8)
                    ax.set_title(f"{scene}: relMSE, {what} (± 1 s.e.; others grey)" if timed
                                 else f"{scene}: no cost run (scene_costs.csv)", fontsize=9)
                ax.set_xlabel(xlabel, fontsize=8)
                ax.tick_params(labelsize=7)
                ax.grid(True, which="both", alpha=0.2)
                if i == 0 or ykey == "ratio":
                    ax.legend(fontsize=6)
        fig.tight_layout()
        fig.savefig(os.path.join(out, fname), dpi=90)
        plt.close(fig)

    eq_path = os.path.join(out, "scene_equal_time.csv")
    if not os.path.exists(eq_path):
        return
    import matplotlib.image as mpimg
    eq = read(eq_path)
    samplers = list(dict.fromkeys(r["sampler"] for r in eq))
    fig, axes = plt.subplots(len(scenes), len(samplers) + 1, figsize=(1.9 * (len(samplers) + 1), 2.1 * len(scenes)),
                             squeeze=False)
    for i, scene in enumerate(scenes):
        ref = os.path.join(out, "scenes", f"{scene}_reference.png")
        for ax in axes[i]:
            ax.axis("off")
        if os.path.exists(ref):
            axes[i][0].imshow(mpimg.imread(ref))
            axes[i][0].set_title(f"{scene}\nreference", fontsize=6)
        for j, name in enumerate(samplers):
            r = [x for x in eq if x["scene"] == scene and x["sampler"] == name]
            img = os.path.join(out, "scenes", r[0]["image"]) if r else None
            if img and os.path.exists(img):
                axes[i][j + 1].imshow(mpimg.imread(img), interpolation="nearest")
                axes[i][j + 1].set_title(f"{name}\n{r[0]['spp']} spp, {1000 * float(r[0]['seconds']):.0f} ms\n"
                                         f"relMSE {float(r[0]['rel_mse']):.2e}", fontsize=5)
    fig.suptitle("relative squared error at equal time (log colour scale 1e-5 .. 10)", fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "scene_equal_time.png"), dpi=110)
    plt.close(fig)


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "docs/study"
    scene_figures(out)
    if os.path.exists(os.path.join(out, "spectra.csv")):
        import plot_spectra
        plot_spectra.main(["plot_spectra.py", out])
    if not os.path.exists(os.path.join(out, "analytic.csv")):
        return
    rows = read(os.path.join(out, "analytic.csv"))
    st = slopes(out)
    for dims in sorted({r["dims"] for r in rows}, key=int):
        drows = [r for r in rows if r["dims"] == dims]
        integrands = list(dict.fromkeys(r["integrand"] for r in drows))
        fig, axes = plt.subplots(4, 3, figsize=(15, 18))
        for ax, integ in zip(axes.flat, integrands):
            draw(ax, drows, integ, dims, st)
            ax.legend(fontsize=5, ncol=2)
        fig.suptitle(f"MSE vs N, {dims}D (legend: fitted log-log slope)")
        fig.tight_layout()
        fig.savefig(os.path.join(out, f"mse_{dims}d.png"), dpi=90)
        plt.close(fig)
    dims = "4" if any(r["dims"] == "4" for r in rows) else rows[0]["dims"]
    fig, ax = plt.subplots(figsize=(7, 5))
    integ = f"2-additive binary-step {dims}D"
    draw(ax, [r for r in rows if r["dims"] == dims], integ, dims, st)
    n = [16, 4096]
    ref = [r for r in rows if r["integrand"] == integ and r["N"] == "16" and r["sampler"] == "Random"]
    if ref:
        m0 = float(ref[0]["mse"])
        ax.loglog(n, [m0 * (x / 16) ** -1.0 for x in n], color="gray", lw=0.6, alpha=0.5, label="N^-1")
        ax.loglog(n, [m0 * 0.5 * (x / 16) ** -1.5 for x in n], color="red", lw=0.6, alpha=0.5, label="N^-1.5")
    ax.legend(fontsize=6, ncol=2)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "goal_2additive_binary.png"), dpi=110)
    plt.close(fig)

    pp = os.path.join(out, "points.csv")
    if os.path.exists(pp):
        pts = read(pp)
        samplers = list(dict.fromkeys(r["sampler"] for r in pts))
        pairs = 4
        fig, axes = plt.subplots(len(samplers), pairs, figsize=(2.2 * pairs, 2.2 * len(samplers)))
        for i, s in enumerate(samplers):
            srows = [r for r in pts if r["sampler"] == s]
            names = list(dict.fromkeys(r["pair"] for r in srows))
            for j, pname in enumerate(names[:pairs]):
                ax = axes[i][j]
                p = [r for r in srows if r["pair"] == pname]
                ax.scatter([float(r["x"]) for r in p], [float(r["y"]) for r in p], s=2, color="k")
                ax.set_xlim(0, 1)
                ax.set_ylim(0, 1)
                ax.set_aspect("equal")
                ax.set_xticks([])
                ax.set_yticks([])
                ax.set_title(f"{s} N={p[0]['N']}\ndims {pname}", fontsize=6)
        fig.tight_layout()
        fig.savefig(os.path.join(out, "projections.png"), dpi=90)
        plt.close(fig)


if __name__ == "__main__":
    main()
