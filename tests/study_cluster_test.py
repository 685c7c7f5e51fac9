#!/usr/bin/python3
"""scripts/study_cluster.py on a Dask LocalCluster (loopback only): the study's scene part split
into tasks gives the same error figures, byte for byte, on 1 worker and on 2 (with an extra
budget, so that the adaptive renders are exercised, and a task that fails once and is rerun);
a budget without a cost run, a task failing every time and bad input are refused.

    study_cluster_test.py STUDY_CLUSTER_PY OAS_STUDY

Run it with an interpreter that can import distributed (Debian 12: python3-distributed). The
scene part renders on the Vulkan device: without one the test prints SKIPPED and passes, unless
OAS_REQUIRE_GPU=1, where a missing device fails it.
"""

import csv
import os
import shutil
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from script_test_support import check, finish, run, step, write_flaky_wrapper  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
SCENES = os.path.join(os.path.dirname(HERE), "scenes")
# A few seconds per task on lavapipe: cornell7d at 8 x 8 pixels, counts up to 128, the quick
# mode's four samplers (3 renders per point, and cornell7d's rare-pixel renders on the CPU).
SETTINGS = ["--scene", "cornell7d", "--quick", "--scene-width", "8", "--scene-max-spp", "128", "--no-plot",
            "--study-md", ""]
# Extra renders beyond the minimum: 4 cost-run seconds for the scene, up to 12 renders a point.
BUDGET = ["--scene-extra-seconds", "4", "--scene-max-trials", "12"]




def error_figures(folder):
    """scenes.csv without its wall-time column, and scene_references.csv's reference errors and
    rare pixels: everything the renders' images decide."""
    with open(os.path.join(folder, "scenes.csv"), newline="") as f:
        rows = [{k: v for k, v in row.items() if k != "seconds"} for row in csv.DictReader(f)]
    with open(os.path.join(folder, "scene_references.csv"), newline="") as f:
        refs = [{k: row[k] for k in ("scene", "reference_spp", "ref_rel_mse", "ref_rel_mse_crop", "rare_pixels")}
                for row in csv.DictReader(f)]
    return rows, refs


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    driver_py, study = (os.path.abspath(p) for p in sys.argv[1:])
    try:
        import distributed
    except ImportError as e:
        sys.exit(f"FAILED: {sys.executable} cannot import distributed ({e}): install python3-distributed "
                 "(scripts/setup.sh does)")
    print(f"python {sys.executable}, distributed {distributed.__version__}", flush=True)

    with tempfile.TemporaryDirectory(prefix="oas_study_cluster_test_") as tmp:
        scratch = os.path.join(tmp, "scratch")  # TMPDIR of the driver and its workers
        os.makedirs(scratch)
        wrapper = os.path.join(tmp, "flaky-oas-study")
        write_flaky_wrapper(wrapper, "--only")
        marker = os.path.join(tmp, "failed-once")
        env = dict(os.environ, TMPDIR=scratch, OAS_TEST_REAL=study, OAS_TEST_MARKER=marker)

        def driver(out, args, extra_env=None, program=study):
            os.makedirs(out, exist_ok=True)
            proc = run([sys.executable, driver_py, "--study", program, "--out-dir", out, "--scenes-dir", SCENES, *args],
                       env=dict(env, **(extra_env or {})))
            if proc.returncode != 0:
                print("   driver stderr:\n" + proc.stderr, flush=True)
            return proc

        step("the scene part without an extra budget, 1 worker (the points a cost run times)")
        first = os.path.join(tmp, "first")
        proc = driver(first, ["--workers", "1", *SETTINGS])
        if proc.returncode != 0 and "Vulkan" in proc.stderr and os.environ.get("OAS_REQUIRE_GPU") != "1":
            print("SKIPPED: no Vulkan device for the scene part (set OAS_REQUIRE_GPU=1 to fail instead)", flush=True)
            return
        if not check(proc.returncode == 0, "the driver succeeds", proc.stderr):
            sys.exit(1)
        rows, _ = error_figures(first)
        samplers = sorted({row["sampler"] for row in rows})
        check(samplers == ["BoseCMJ", "CMJ2D-pad", "Random", "Sobol"], "every quick-mode sampler has rows",
              str(samplers))
        check(proc.stderr.count(" done in ") == 4, "one progress line per task (4)", proc.stderr)

        step("a cost run of those points (oas-study --parts scene-costs)")
        proc = run([study, "--parts", "scene-costs", "--scene", "cornell7d", "--out-dir", first, "--scenes-dir", SCENES,
                    "--study-md", "", "--no-plot"], env=env)
        if not check(proc.returncode == 0, "the cost run succeeds", proc.stderr):
            sys.exit(1)

        step("with an extra budget: 1 worker, then 2 workers with the Random task failing once")
        outs = {}
        for workers in (1, 2):
            out = os.path.join(tmp, f"budget-{workers}")
            os.makedirs(out)
            shutil.copy(os.path.join(first, "scene_costs.csv"), out)
            flaky = workers == 2
            proc = driver(out, ["--workers", str(workers), *SETTINGS, *BUDGET],
                          {"OAS_TEST_FAIL_VALUE": "Random"} if flaky else None, wrapper if flaky else study)
            if check(proc.returncode == 0, f"{workers} worker(s): the driver succeeds", proc.stderr):
                outs[workers] = error_figures(out)
            if flaky:
                check(os.path.exists(marker), "the injected failure happened and the task was rerun")
        if len(outs) == 2:
            one, two = outs[1], outs[2]
            check(len(one[0]) > len(rows), "the budget bought extra renders",
                  f"{len(one[0])} rows with the budget, {len(rows)} without")
            check(one == two, "1 and 2 workers give the same error figures, byte for byte (scenes.csv but its "
                              "seconds column; the reference errors)",
                  f"rows {len(one[0])} vs {len(two[0])}; first difference: " +
                  next((f"{a} vs {b}" for a, b in zip(one[0], two[0]) if a != b), "in the references or row count"))

        step("an extra budget without a cost run: the tasks fail, exit 1, scenes.csv not written")
        bare = os.path.join(tmp, "bare")
        proc = driver(bare, ["--workers", "1", "--retries", "0", *SETTINGS, *BUDGET])
        check(proc.returncode == 1 and "scene_costs.csv" in proc.stderr, "exit 1 naming scene_costs.csv", proc.stderr)
        check(not os.path.exists(os.path.join(bare, "scenes.csv")), "nothing merged")

        step("a task failing every time: exit 1 after --retries 1 (two tries)")
        os.remove(marker)
        always = os.path.join(tmp, "always")
        proc = driver(always, ["--workers", "2", "--retries", "1", *SETTINGS],
                      {"OAS_TEST_FAIL_VALUE": "BoseCMJ", "OAS_TEST_FAIL_MODE": "always"}, wrapper)
        check(proc.returncode == 1 and "injected failure" in proc.stderr, "exit 1 quoting the task's stderr",
              proc.stderr)
        tries = open(marker).read().split() if os.path.exists(marker) else []
        check(len(tries) == 2, "the task ran twice (1 retry)", f"tries: {tries}")
        check(not os.path.exists(os.path.join(always, "scenes.csv")), "nothing merged")

        step("refusals: exit 2 naming the option or value")
        for args, needle in [(["--workers", "0"], "--workers 0"),
                             (["--scene", "no_such_scene"], "no_such_scene"),
                             (["--only", "NoSuchSampler"], "NoSuchSampler"),
                             (["--parts", "scenes"], "--parts"),
                             (["--scene-join"], "--scene-join")]:
            proc = driver(os.path.join(tmp, "refused"), [*args, "--quick"])
            check(proc.returncode == 2 and needle in proc.stderr, f"{' '.join(args)}: exit 2 naming {needle!r}",
                  proc.stderr)
        check(not os.path.exists(os.path.join(tmp, "refused", "scenes.csv")), "nothing written")

        left = [os.path.join(d, name) for d, dirs, names in os.walk(scratch) for name in dirs + names
                if name.startswith(("oas-task-", "oas-study-cluster-"))]
        check(not left, "no temporary folder left behind", str(left))

    finish()


if __name__ == "__main__":
    main()
