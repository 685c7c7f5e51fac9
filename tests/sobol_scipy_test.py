#!/usr/bin/env python3
"""The Sobol baseline, unscrambled, equals scipy.stats.qmc.Sobol(d, scramble=False) bit for bit.

  sobol_scipy_test.py PATH/TO/sobol_reference_check

scipy 1.10.1 (Debian 12: python3-scipy) builds its Sobol points from Joe and Kuo's
new-joe-kuo-6.21201, the table our direction numbers come from (data/sobol/), so equality checks
the extraction, the generated host/oas/oas_joe_kuo.inc, the recurrence in oas_sobol_directions()
and the GLSL oas_sobol() in one go. scipy with bits=32 returns x / 2^32 for 32-bit integers x
(exact in a double), which we compare as integers.

scipy emits its points in Gray-code order (Antonov and Saleev): its row r is the Sobol point of
natural index r ^ (r >> 1), which is what oas_sobol(index, dim) computes; the first 2^k rows are
the same point set in another order.

A missing scipy is a failure, not a skip: CI always has it, and a silent skip would hide a
regression.
"""
import subprocess
import sys
import warnings

# (d, k): the first 2^k points in d dimensions, as the brief for the Joe-Kuo switch asks.
FIRST_POINTS = [(2, 10), (5, 10), (21, 10), (64, 10), (1024, 10)]
# A few rows around 2^16 in 1024 dimensions: natural indices with bits 15 and 16 set, so the
# 16th and 17th direction numbers of every dimension take part.
LATE_ROWS = (1024, 2**16 - 4, 8)
INDEX_BITS = 24


from scipy_support import fail, import_scipy

np, scipy, qmc = import_scipy()


def ours(checker, dims, indices):
    """oas_sobol(index, dim) for each index (rows) and dim < dims, as uint64."""
    text = " ".join(str(int(i)) for i in indices).encode()
    run = subprocess.run([checker, str(dims)], input=text, capture_output=True, check=False)
    if run.returncode != 0:
        fail(f"{checker} {dims} exited {run.returncode}: {run.stderr.decode(errors='replace')}")
    words = np.frombuffer(run.stdout, dtype="<u4")
    if words.size != len(indices) * dims:
        fail(f"{checker} {dims}: {words.size} words, expected {len(indices) * dims}")
    return words.reshape(len(indices), dims).astype(np.uint64)


def as_integers(points, what):
    scaled = points * 2.0**32
    if not np.all(scaled == np.floor(scaled)) or scaled.min() < 0 or scaled.max() >= 2.0**32:
        fail(f"{what}: scipy's points are not k / 2^32 for 32-bit k (bits=32 ignored?)")
    return scaled.astype(np.uint64)


def compare(d, rows, theirs, mine, what):
    bad = np.argwhere(theirs != mine)
    if bad.size:
        r, dim = (int(x) for x in bad[0])
        fail(f"{what}: first mismatch at d={d}, scipy row {rows[r]} (index {gray(rows[r])}), dim {dim}: "
             f"scipy {int(theirs[r, dim]):#010x}, ours {int(mine[r, dim]):#010x} "
             f"({len(bad)} mismatching values in all)")


def gray(r):
    return r ^ (r >> 1)


def main():
    if len(sys.argv) != 2:
        fail("usage: sobol_scipy_test.py PATH/TO/sobol_reference_check")
    checker = sys.argv[1]
    print(f"scipy {scipy.__version__}, numpy {np.__version__}")

    for d, k in FIRST_POINTS:
        theirs = as_integers(qmc.Sobol(d, scramble=False, bits=32).random_base2(k), f"d={d}")
        rows = list(range(2**k))
        compare(d, rows, theirs, ours(checker, d, [gray(r) for r in rows]), f"first 2^{k} points")
        print(f"d={d}: first 2^{k} points equal")

    d, first, count = LATE_ROWS
    engine = qmc.Sobol(d, scramble=False, bits=32)
    engine.fast_forward(first)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # "balance properties ... power of 2": not the point here
        theirs = as_integers(engine.random(count), f"d={d} late rows")
    rows = list(range(first, first + count))
    compare(d, rows, theirs, ours(checker, d, [gray(r) for r in rows]), f"rows {first} .. {first + count - 1}")
    print(f"d={d}: rows {first} .. {first + count - 1} equal")

    # Every direction number an index can select: the point of natural index 2^b is direction
    # number b, which scipy keeps in its (private) matrix _sv[dim, b] when bits=32. Points beyond
    # 2^16 are too slow to reach through scipy's public API, so this is how bits 17 .. 24 get
    # checked; if a scipy release drops _sv, the point checks above still stand and this part
    # says so. The samplers' indices are below N <= 2^24, so oas_sobol reads the first 24
    # direction numbers only (INDEX_BITS, the GLSL's OAS_INDEX_BITS).
    engine = qmc.Sobol(1024, scramble=False, bits=32)
    sv = getattr(engine, "_sv", None)
    if sv is None or np.shape(sv) != (1024, 32):
        print(f"note: scipy {scipy.__version__} has no _sv of shape (1024, 32); direction numbers 17 .. 24 "
              "not compared")
    else:
        bits = list(range(INDEX_BITS))
        mine = ours(checker, 1024, [1 << b for b in bits])  # row b = direction number b
        theirs = np.asarray(sv, dtype=np.uint64).T[:INDEX_BITS]
        bad = np.argwhere(theirs != mine)
        if bad.size:
            b, dim = (int(x) for x in bad[0])
            fail(f"direction number {b} of dim {dim}: scipy {int(theirs[b, dim]):#010x}, "
                 f"ours {int(mine[b, dim]):#010x} ({len(bad)} mismatching words in all)")
        print(f"all 1024 x {INDEX_BITS} direction numbers equal")
    print("PASS")


if __name__ == "__main__":
    main()
