#!/usr/bin/python3
"""The study's scene part (its accuracy renders) on a Dask.distributed cluster.

    scripts/study_cluster.py [--workers W | --scheduler tcp://HOST:PORT] [--retries R]
                             [--study PATH] [--worker-env NAME=VALUE] [--out-dir DIR]
                             [--study-md FILE] [--scenes-dir DIR] [--scene NAME ...]
                             [--only LABEL ...] [--quick] [other oas-study scene options]

(`scripts/study.sh --workers W` or `--scheduler ADDR` runs this, and only this: the other parts,
scene-costs included, run on one machine with `scripts/study.sh --parts ...` as usual.)

The work is cut the same way whatever the number of workers, so that the error figures do not
depend on it: per scene, one task renders the reference and Sobol's points
(`oas-study --parts scenes --scene X --only Sobol`); when it is done, one task per other sampler
renders that sampler's points against the same reference (`--only S --scene-join`: a sampler
shard that must join the scene's record). Every task adds extra renders from its share of the
scene's budget as the s.e. asks, charging each render its point's seconds in the scene's cost run
(`--scene-render-cost cost-run`, docs/study/scene_costs.csv) rather than its own measured time,
so the renders a task makes depend on the settings alone, and the images are bit-identical on
any machine. Then `oas-study --parts none --merge-scene-shards` merges the tasks' folders into
--out-dir on this machine, scene by scene, in the study's sampler order. So scenes.csv's error
columns (everything but `seconds`, each render's wall time) and everything computed from them are
the same byte for byte for 1 worker, 2 workers or a cluster; tests/study_cluster_test.py checks it.
The extra budget needs each scene's cost run (`oas-study --parts scene-costs`, which times the
points that scenes.csv holds): a scene without one is refused when the budget is not 0.

Options other than the ones below go unchanged to every oas-study task (--quick,
--scene-width, --scene-max-spp, --scene-extra-seconds, ...); --parts, --merge-scene-shards,
--merge-command, --scene-join, --scene-render-cost and --list-scene-samplers are the driver's own.

  --workers W        LocalCluster worker processes on this machine (default: CPUs)
  --scheduler ADDR   use a running cluster instead (see scripts/cluster.py for setting one up)
  --retries R        times Dask reruns a failed task (default 1)
  --study PATH       oas-study on the workers (default: this repository's build/oas-study; with
                     --scheduler looked up on the workers, a bare name in their PATH); without
                     --scheduler it also lists the samplers and merges, with --scheduler this
                     repository's build/oas-study does
  --worker-env N=V   environment variable for oas-study on the workers (repeatable)
  --out-dir DIR      the study's data folder (default docs/study); its scene_costs.csv goes to
                     every task, the merged data come back to it (the rows of other scenes kept)
  --study-md FILE    summary markdown reassembled at the end (default docs/STUDY.md; "" none)
  --scenes-dir DIR   scene folder sent to the workers (default scenes)
  --scene NAME ...   scenes (default: the three study scenes)
  --only LABEL ...   samplers (default: every sampler of the mode; Sobol always, for the reference)
  --no-plot          do not redraw the plots after the merge

Exit status: 0 done; 2 bad input; 1 a task failed after all retries (its stderr tail printed) or
the merge failed; 130 interrupted. Nothing in --out-dir changes unless every task succeeded.
"""

import argparse
import io
import os
import subprocess
import sys
import tarfile
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cluster  # noqa: E402  (the sandbox runner and the client, shared with the frame renderer)

REPO = cluster.REPO
STUDY_SCENES = ("cornell7d", "blue_spheres9d", "interior_deep")
DRIVER_OWN = ("--parts", "--merge-scene-shards", "--merge-command", "--scene-join", "--scene-render-cost",
              "--list-scene-samplers")


def fail(message, status=2):
    print(f"study_cluster: error: {message}", file=sys.stderr)
    sys.exit(status)


# ---- run on the workers (pickled by value: keep imports inside) -------------------------------

def _study_task(study, files, args, env_extra, base, label, topic):
    """One oas-study run in a sandbox holding the scenes (scenes/) and, for a sampler shard, its
    base's output folder (out/): returns {tar, seconds, worker, host} with out/ as gzipped tar
    bytes; raises (so that Dask retries) when oas-study fails."""
    import io
    import socket
    import tarfile

    files = dict(files)
    if base is not None:
        with tarfile.open(fileobj=io.BytesIO(base["tar"]), mode="r:gz") as tar:
            for member in tar.getmembers():
                if member.isfile():
                    files[os.path.normpath(os.path.join("out", member.name))] = tar.extractfile(member).read()
    rc, _, err, data, seconds, address = cluster._run_in_sandbox(study, args, files, env_extra, "out")
    if rc != 0 or data is None:
        lines = err.rstrip().splitlines()
        where = f"{label} failed on worker {address} ({socket.gethostname()})"
        try:
            from distributed import get_worker

            get_worker().log_event(topic, f"{where}: exit {rc}: {lines[-1] if lines else '(no stderr)'}")
        except Exception:
            pass
        raise RuntimeError(f"{where}: oas-study exit {rc} after {seconds:.1f} s; its stderr ends:\n" +
                           "\n".join(lines[-20:]))
    return {"tar": data, "seconds": seconds, "worker": address, "host": socket.gethostname()}


# ---- the client ------------------------------------------------------------------------------

def parse_args(argv):
    parser = argparse.ArgumentParser(prog="study_cluster.py", allow_abbrev=False,
                                     description="The study's scene part on Dask workers (see the module docstring).")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, metavar="W")
    where.add_argument("--scheduler", metavar="ADDR")
    parser.add_argument("--retries", type=int, default=1, metavar="R")
    parser.add_argument("--study", default=os.path.join(REPO, "build", "oas-study"))
    parser.add_argument("--worker-env", action="append", default=[], metavar="NAME=VALUE")
    parser.add_argument("--out-dir", default="docs/study")
    parser.add_argument("--study-md", default="docs/STUDY.md")
    parser.add_argument("--scenes-dir", default="scenes")
    parser.add_argument("--scene", nargs="+", default=list(STUDY_SCENES), metavar="NAME")
    parser.add_argument("--only", nargs="+", default=[], metavar="LABEL")
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--no-plot", action="store_true")
    args, passthrough = parser.parse_known_args(argv)
    for option in passthrough:
        if option.split("=", 1)[0] in DRIVER_OWN:
            fail(f"{option.split('=', 1)[0]} is the driver's own (see --help)")
    args.passthrough = passthrough + (["--quick"] if args.quick else [])
    return args


def read_tree(root, prefix):
    """{prefix/relative path: bytes} of every file under root."""
    files = {}
    for directory, _, names in os.walk(root):
        for name in names:
            path = os.path.join(directory, name)
            with open(path, "rb") as f:
                files[os.path.normpath(os.path.join(prefix, os.path.relpath(path, root)))] = f.read()
    return files


def unpack(data, folder):
    os.makedirs(folder, exist_ok=True)
    with tarfile.open(fileobj=io.BytesIO(data), mode="r:gz") as tar:
        for member in tar.getmembers():
            if member.isfile() and not os.path.isabs(member.name) and ".." not in member.name.split("/"):
                tar.extract(member, folder)


def main(argv):
    args = parse_args(argv)
    try:
        env_extra = cluster.worker_options(args)
    except cluster.UsageError as e:
        fail(str(e))
    if not os.path.isdir(args.scenes_dir):
        fail(f"--scenes-dir {args.scenes_dir}: not a folder")
    for name in args.scene:
        if not os.path.isfile(os.path.join(args.scenes_dir, name + ".json")):
            fail(f"--scene {name}: {os.path.join(args.scenes_dir, name + '.json')} does not exist "
                 f"(study scenes: {', '.join(STUDY_SCENES)})")
    try:
        study = cluster.resolve_program(args.study, "--study", args.scheduler is None)
        # The sampler list and the merge run here: --study itself when it is a program here.
        local_study = study if args.scheduler is None else \
            cluster.resolve_program(os.path.join(REPO, "build", "oas-study"), "oas-study on this machine", True)
    except cluster.UsageError as e:
        fail(str(e))

    # The samplers, as oas-study names them (it checks --only and applies --quick).
    listing = subprocess.run([local_study, "--list-scene-samplers", *(["--only", *args.only] if args.only else []),
                              *(["--quick"] if args.quick else [])], capture_output=True, text=True)
    if listing.returncode != 0:
        sys.stderr.write(listing.stderr)
        fail("oas-study refused the sampler list (--only)")
    labels = listing.stdout.split()
    # The reference task renders Sobol; in --quick and the full mode alike it is a scene sampler.
    others = [label for label in labels if label != "Sobol"]

    # What every task gets: the scenes, and the cost runs (the extra budget's prices).
    files = read_tree(args.scenes_dir, "scenes")
    costs = os.path.join(args.out_dir, "scene_costs.csv")
    if os.path.isfile(costs):
        with open(costs, "rb") as f:
            files["out/scene_costs.csv"] = f.read()
    common = ["--parts", "scenes", "--scenes-dir", "scenes", "--out-dir", "out", "--study-md", "", "--no-plot",
              "--scene-render-cost", "cost-run", *args.passthrough]
    import cloudpickle

    cloudpickle.register_pickle_by_value(cluster)  # the workers need not find scripts/cluster.py

    start = time.monotonic()
    workers = args.workers or (os.cpu_count() or 1)
    with tempfile.TemporaryDirectory(prefix="oas-study-cluster-") as tmp, \
            cluster.open_client(workers, args.scheduler) as (client, where):
        import distributed

        topic = "oas-study-cluster"
        client.subscribe_topic(topic, lambda event: print(f"study_cluster: {event[1]}", file=sys.stderr, flush=True))
        [files_future] = client.scatter([files], hash=False)
        tasks = {}  # future -> (scene, label)
        for scene in args.scene:
            base = client.submit(_study_task, study, files_future, [*common, "--scene", scene, "--only", "Sobol"],
                                 env_extra, None, f"{scene} reference + Sobol", topic, retries=args.retries,
                                 pure=False, key=f"oas-study-{scene}-Sobol-{os.getpid()}-{time.time_ns()}")
            tasks[base] = (scene, "Sobol")
            for label in others:
                future = client.submit(_study_task, study, files_future,
                                       [*common, "--scene", scene, "--only", label, "--scene-join"], env_extra, base,
                                       f"{scene} {label}", topic, retries=args.retries, pure=False,
                                       key=f"oas-study-{scene}-{label}-{os.getpid()}-{time.time_ns()}")
                tasks[future] = (scene, label)
        print(f"study_cluster: {len(tasks)} tasks ({len(args.scene)} scenes x {len(labels)} samplers) on {where}",
              file=sys.stderr, flush=True)
        folders = {}
        for done, future in enumerate(distributed.as_completed(list(tasks)), 1):
            scene, label = tasks[future]
            if future.status != "finished":
                try:
                    error = future.exception()
                except Exception as e:  # cancelled
                    error = e
                for other in tasks:
                    other.cancel()
                fail(f"gave up after {args.retries + 1} tries (--retries {args.retries}): {error}", 1)
            result = future.result()
            folder = os.path.join(tmp, scene, label)
            unpack(result["tar"], folder)
            folders[(scene, label)] = folder
            print(f"study_cluster: {scene} {label} done in {result['seconds']:.1f} s on {result['worker']} "
                  f"({result['host']}); {done}/{len(tasks)} done, {time.monotonic() - start:.0f} s",
                  file=sys.stderr, flush=True)

        # The merge, scene by scene, in the study's sampler order: the same files for any placement.
        os.makedirs(args.out_dir, exist_ok=True)
        for i, scene in enumerate(args.scene):
            last = i == len(args.scene) - 1
            cmd = [local_study, "--parts", "none", "--out-dir", args.out_dir, "--scenes-dir", args.scenes_dir,
                   "--study-md", args.study_md if last else "", *(["--no-plot"] if args.no_plot or not last else []),
                   "--merge-command", "scripts/study_cluster.py " + " ".join(argv),
                   "--merge-scene-shards", folders[(scene, "Sobol")], *[folders[(scene, label)] for label in others]]
            proc = subprocess.run(cmd, stdin=subprocess.DEVNULL, capture_output=True, text=True)
            sys.stderr.write(proc.stderr)
            if proc.returncode != 0:
                fail(f"the merge of {scene} failed (exit {proc.returncode}): {' '.join(cmd)}", 1)
    print(f"study_cluster: merged into {args.out_dir}; {time.monotonic() - start:.0f} s in all", file=sys.stderr)
    return 0


if __name__ == "__main__":
    cluster.run_main(main, "study_cluster")
