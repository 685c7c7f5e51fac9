#!/usr/bin/env python3
"""Our hash-scrambled Sobol ("sobol": Burley's Laine-Karras scramble) integrates as well as
scipy.stats.qmc.Sobol(scramble=True): MSE no worse than 1.1x scipy's on the analytic integrands of
the randomization-quality test (2-additive Gaussian and binary step, 2-multiplicative Gaussian,
radial Gaussian, 4D), at N = 64, 256 and 1024, over 1024 independent randomizations each.

  sobol_mse_scipy_test.py PATH/TO/sobol_mse_check

scipy's scramble is a different randomization of the same Joe-Kuo points (a linear matrix
scramble with a digital shift; scipy 1.10), so this is a peer comparison, not an identity. A ratio
counts as worse only when it exceeds 1.1 by more than three of its standard errors (delta
method), so that noise alone fails about once in a thousand runs. The per-bit scramble
("sobol-owen") is printed beside it for reference. A missing scipy is a failure, not a skip.
"""
import math
import subprocess
import sys

SETS = 4096
COUNTS = (64, 256, 1024)
LIMIT = 1.1


from scipy_support import fail, import_scipy

np, scipy, qmc = import_scipy()


def run(checker, sampler, n, points):
    done = subprocess.run([checker, sampler, str(n), str(SETS)], input=points.astype("<f8").tobytes(),
                          capture_output=True, check=False)
    if done.returncode != 0:
        fail(f"{checker} {sampler} {n} exited {done.returncode}: {done.stderr.decode(errors='replace')}")
    rows = {}
    for line in done.stdout.decode().splitlines():
        name, *numbers = line.split()
        rows[name] = [float(x) for x in numbers]
    return rows


def main():
    if len(sys.argv) != 2:
        fail("usage: sobol_mse_scipy_test.py PATH/TO/sobol_mse_check")
    checker = sys.argv[1]
    print(f"scipy {scipy.__version__}: {SETS} randomizations per N; MSE ratio ours / scipy (+- s.e.)")
    rng = np.random.default_rng(20201)
    failures = []
    for n in COUNTS:
        points = np.stack([qmc.Sobol(4, scramble=True, seed=rng).random(n) for _ in range(SETS)])
        fast = run(checker, "sobol", n, points)
        owen = run(checker, "sobol-owen", n, points)
        for name, (ours, ours_se, theirs, theirs_se) in fast.items():
            ratio = ours / theirs
            se = ratio * math.hypot(ours_se / ours, theirs_se / theirs)
            owen_ratio = owen[name][0] / owen[name][2]
            print(f"N={n:5d} {name:34s} sobol {ratio:6.3f} +- {se:5.3f}   (sobol-owen {owen_ratio:6.3f})")
            if ratio - 3 * se > LIMIT:
                failures.append(f"N={n} {name}: MSE ratio {ratio:.3f} +- {se:.3f} above {LIMIT}")
    if failures:
        fail("; ".join(failures))
    print("PASS")


if __name__ == "__main__":
    main()
