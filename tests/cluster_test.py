#!/usr/bin/python3
"""scripts/cluster.py on a Dask LocalCluster (loopback only): a frame rendered as sample shards and
merged equals a plain oas-render render bit for bit, a shard that fails once is rerun, one that
always fails ends the driver with exit 1, and bad input is refused without writing anything.

    cluster_test.py CLUSTER_PY OAS_RENDER OAS_MERGE OAS_DIFF

Run it with an interpreter that can import distributed (Debian 12: python3-distributed); the
driver runs with the same one. The main case runs on the GPU (lavapipe unless a driver is chosen);
without a Vulkan device it runs on the CPU tracer instead, unless OAS_REQUIRE_GPU=1, where a
missing device fails the test.
"""

import os
import re
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from script_test_support import check, finish, run, step, write_flaky_wrapper  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.join(HERE, "data", "cluster_8x8.json")
OPTIONS = ["--seed", "3"]  # passed through to every oas-render call; the plain renders use it too




def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    cluster_py, render, merge, diff = (os.path.abspath(p) for p in sys.argv[1:])
    try:
        import distributed
    except ImportError as e:
        sys.exit(f"FAILED: {sys.executable} cannot import distributed ({e}): install python3-distributed "
                 "(scripts/setup.sh does)")
    print(f"python {sys.executable}, distributed {distributed.__version__}", flush=True)
    for program in (cluster_py, render, merge, diff):
        if not os.access(program, os.X_OK):
            sys.exit(f"FAILED: {program} is missing or not executable")

    with tempfile.TemporaryDirectory(prefix="oas_cluster_test_") as tmp:
        scratch = os.path.join(tmp, "scratch")  # TMPDIR of the driver and its workers
        os.makedirs(scratch)
        wrapper = os.path.join(tmp, "flaky-oas-render")
        write_flaky_wrapper(wrapper, "--samples")
        marker = os.path.join(tmp, "failed-once")
        env = dict(os.environ, TMPDIR=scratch, OAS_TEST_REAL=render, OAS_TEST_MARKER=marker)

        def driver(args, extra_env=None):
            """The driver with the binaries under test (the wrapper where args name --renderer)."""
            defaults = ["--merger", merge] + ([] if "--renderer" in args else ["--renderer", render])
            proc = run([sys.executable, cluster_py, "render", *args, *defaults], env=dict(env, **(extra_env or {})))
            if proc.returncode != 0:
                print("   driver stderr:\n" + proc.stderr, flush=True)
            return proc

        def same_image(a, b, what):
            proc = run([diff, "--exact", a, b])
            check(proc.returncode == 0, f"{what}: oas-diff --exact says the pixels are identical",
                  proc.stdout + proc.stderr)
            with open(a[:-4] + ".png", "rb") as fa, open(b[:-4] + ".png", "rb") as fb:
                check(fa.read() == fb.read(), f"{what}: the PNG previews are byte-identical")

        def nothing_left(what):
            left = [os.path.join(d, name) for d, dirs, names in os.walk(scratch) for name in dirs + names
                    if name.startswith(("oas-shard-", "oas-cluster-"))]
            check(not left, f"{what}: no temporary directory left behind", "\n".join(left))

        step("samples per pixel of the test scene (oas-render --explain)")
        proc = run([render, SCENE, *OPTIONS, "--explain"])
        found = re.search(r"^samples per pixel: (\d+)$", proc.stdout, re.M)
        if not check(proc.returncode == 0 and found, "--explain prints 'samples per pixel: N'", proc.stdout + proc.stderr):
            sys.exit(1)
        n = int(found.group(1))
        print(f"   N = {n}")

        step("plain renders: the default device (GPU) and --device cpu")
        plain = {}
        for device in ("gpu", "cpu"):
            out = os.path.join(tmp, f"plain-{device}.exr")
            proc = run([render, SCENE, *OPTIONS, "--device", device, "-o", out])
            if proc.returncode != 0 and device == "gpu" and re.search(r"Vulkan|VK_ERROR", proc.stderr) \
                    and os.environ.get("OAS_REQUIRE_GPU") != "1":
                print(f"   SKIPPED the GPU case: no Vulkan device:\n{proc.stderr}", flush=True)
                continue
            if not check(proc.returncode == 0 and os.path.exists(out), f"plain {device} render", proc.stderr):
                sys.exit(1)
            plain[device] = out
        main_device = "gpu" if "gpu" in plain else "cpu"

        shards = min(4, n)
        base, extra = divmod(n, shards)  # shard 2's range, as the driver splits [0, N)
        lo = base + (1 if extra > 0 else 0)
        fail_range = f"{lo}:{lo + base + (1 if extra > 1 else 0)}"
        step(f"{shards} shards on 2 workers, {main_device}; shard 2 ({fail_range}) fails once and is rerun")
        out = os.path.join(tmp, "out", "sharded.exr")
        proc = driver([SCENE, "--shards", str(shards), "--workers", "2", "--renderer", wrapper, "--device", main_device,
                       *OPTIONS, "-o", out], {"OAS_TEST_FAIL_VALUE": fail_range})
        if check(proc.returncode == 0, "the driver succeeds", proc.stderr):
            check(os.path.exists(marker), "the injected failure happened (marker file written)")
            check(proc.stderr.count(") done in ") == shards, f"{shards} progress lines", proc.stderr)
            same_image(out, plain[main_device], f"{shards} shards on {main_device}")
        nothing_left("after the sharded render")

        step("--shards 1 --workers 1 --device cpu equals a plain CPU render")
        out1 = os.path.join(tmp, "one.exr")
        proc = driver([SCENE, "--shards", "1", "--workers", "1", "--device", "cpu", *OPTIONS, "-o", out1])
        if check(proc.returncode == 0, "the driver succeeds", proc.stderr):
            same_image(out1, plain["cpu"], "1 shard on cpu")

        step("a shard that always fails: exit 1 after --retries 1 (two tries), nothing written")
        os.remove(marker)
        bad = os.path.join(tmp, "bad.exr")
        proc = driver([SCENE, "--shards", "2", "--workers", "2", "--retries", "1", "--renderer", wrapper,
                       "--device", "cpu", *OPTIONS, "-o", bad],
                      {"OAS_TEST_FAIL_VALUE": f"0:{(n + 1) // 2}", "OAS_TEST_FAIL_MODE": "always"})
        check(proc.returncode == 1, "exit 1", proc.stderr)
        check("injected failure" in proc.stderr, "the message quotes the renderer's stderr", proc.stderr)
        tries = open(marker).read().split() if os.path.exists(marker) else []
        check(len(tries) == 2, "the shard ran twice (1 retry)", f"tries: {tries}")
        check(not os.path.exists(bad) and not os.path.exists(bad[:-4] + ".png"), "no output written")
        nothing_left("after the failed render")

        step("refusals: exit 2, a message naming the option or file, no output")
        refusals = [
            (["--shards", "0"], "--shards 0"),
            (["--shards", str(n + 1)], f"--shards {n + 1}"),
            (["--shards", "2", "--renderer", os.path.join(tmp, "no-such-oas-render")], "no-such-oas-render"),
        ]
        for args, needle in refusals:
            refused = os.path.join(tmp, "refused.exr")
            proc = driver([SCENE, *args, "--device", "cpu", "-o", refused])
            check(proc.returncode == 2 and needle in proc.stderr, f"{' '.join(args)}: exit 2 naming {needle!r}",
                  proc.stderr)
            check(not os.path.exists(refused) and not os.path.exists(refused[:-4] + ".png"), "no output written")
        missing = os.path.join(tmp, "no-such-scene.json")
        proc = driver([missing, "--shards", "2", "-o", os.path.join(tmp, "refused.exr")])
        check(proc.returncode == 2 and missing in proc.stderr, "a missing scene: exit 2 naming the file", proc.stderr)
        check(not os.path.exists(os.path.join(tmp, "refused.exr")), "no output written")

    finish()


if __name__ == "__main__":
    main()
