#!/usr/bin/python3
"""Render one frame on a Dask.distributed cluster: the samples are split into shards, workers run
oas-render on them, and oas-merge adds them up on this machine.

    scripts/cluster.py render SCENE.json --shards K [--workers W | --scheduler tcp://HOST:PORT]
                       [--retries R] [--renderer PATH] [--merger PATH] [--worker-env NAME=VALUE]
                       [oas-render options] -o OUT.exr

The frame's N samples per pixel (what `oas-render --explain` says, after --spp) are split into K
contiguous ranges [A, B) as even as possible (the first N mod K get one sample more); shard i is
`oas-render SCENE --samples A:B -o shard.exr` on some worker. oas-render's accumulation EXRs hold
exact sums, so `oas-merge` makes the image a single `oas-render` would have made, bit for bit
(`--shards 1` equals a plain render). The output is written only by oas-merge (atomically), with
its PNG preview beside it.

Options other than the ones below (--device, --sampler, --spp, --offset, --strength, --seed and any
other oas-render option) are passed unchanged to every oas-render call. An oas-render option this
script does not know that takes a value must be written --option=value (argparse would otherwise
take its value for the scene). --samples, --explain and --output are the driver's own.

  --shards K            number of shards, 1 <= K <= N
  --workers W           LocalCluster worker processes on this machine (default min(K, CPUs))
  --scheduler ADDR      use a running cluster instead (tcp://HOST:8786)
  --retries R           times Dask reruns a failed shard before giving up (default 2)
  --renderer PATH       oas-render on the workers (default: this repository's build/oas-render;
                        with --scheduler the path is looked up on the workers, a bare name in
                        their PATH)
  --merger PATH         oas-merge on this machine (default: this repository's build/oas-merge)
  --worker-env N=V      set an environment variable for the renderer on the workers (repeatable),
                        e.g. LP_NUM_THREADS=1 to keep lavapipe to one thread per worker

Nothing is assumed shared between this machine and the workers: the driver sends each task the
scene file and every mesh file it references (shapes with "type": "mesh", `file` relative to the
scene's directory; absolute mesh paths are refused), and the worker recreates them, with the same
relative layout, in a temporary directory that it removes afterwards. The worker returns the
shard's EXR as bytes. A failed shard (non-zero exit, no output) is rerun by Dask up to R times;
one line per finished shard goes to stderr (index, range, seconds, worker).

Exit status: 0 done; 2 bad input (missing scene, renderer or merger, bad --shards, an option
oas-render refuses, ...); 1 a shard failed after all retries (with the renderer's stderr tail),
oas-merge refused the shards, or another error; 130 interrupted.

A cluster of several machines (Dask 2022.12, Debian 12's python3-distributed; client and workers
need the same Python minor version, since the task function travels pickled by value):

    # on the scheduler machine
    dask scheduler                        # listens on tcp://HOST:8786
    # on every worker machine, with oas-render built or copied there; one task per worker at a
    # time, since oas-render (lavapipe or the CPU tracer) already uses every core
    dask worker tcp://HOST:8786 --nthreads 1
    # anywhere that reaches the scheduler
    scripts/cluster.py render scene.json --shards 32 --scheduler tcp://HOST:8786 \\
        --renderer /opt/oas/build/oas-render -o out/scene.exr

On Slurm, PBS, SGE or LSF, dask-jobqueue starts the workers as batch jobs, for example in a Python
session that stays open while you render:

    from dask_jobqueue import SLURMCluster
    cluster = SLURMCluster(cores=1, processes=1, memory="4GB", walltime="01:00:00",
                           job_extra_directives=["--cpus-per-task=16"])
    cluster.scale(jobs=8)
    print(cluster.scheduler_address)      # pass this to --scheduler

Without --scheduler the driver starts a LocalCluster of W worker processes (one thread each, no
dashboard) on this machine and stops it at the end.
"""

import argparse
import contextlib
import json
import logging
import os
import shutil
import subprocess
import sys
import tempfile
import time

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EVENT_TOPIC = "oas-cluster"


class UsageError(Exception):
    """Bad input: the driver exits with status 2."""


# ---- run on the workers (pickled by value with the function: keep imports inside) -------------

def _materialize(files, root):
    """Writes {relative path: bytes} under root, creating directories."""
    import os

    for rel, data in files.items():
        path = os.path.join(root, rel)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "wb") as f:
            f.write(data)


def _run_in_sandbox(program, args, files, env_extra, collect):
    """Recreates `files` ({relative path: bytes}) in a fresh directory, runs `program args` there
    (relative paths in args resolve inside it) and removes the directory. `collect`: None, or the
    relative path of the output to return: a file's bytes, or a directory as gzipped tar bytes.
    Returns (exit status, stdout, stderr, output bytes or None, seconds, worker address)."""
    import ctypes
    import io
    import os
    import shutil
    import signal
    import subprocess
    import tarfile
    import tempfile
    import time

    try:
        from distributed import get_worker

        worker = get_worker()
        parent, address = worker.local_directory, worker.address
    except ValueError:  # not in a worker (cannot happen through the drivers)
        parent, address = None, "?"
    exe = program if os.sep in program else (shutil.which(program) or program)

    # A killed worker takes its program along (PR_SET_PDEATHSIG, Linux). prctl is looked up before
    # the fork, so that the child only calls it.
    try:
        prctl = ctypes.CDLL(None, use_errno=True).prctl
    except (OSError, AttributeError):
        prctl = None

    def die_with_worker():
        if prctl is not None:
            prctl(1, int(signal.SIGTERM))

    sandbox = tempfile.mkdtemp(prefix="oas-task-", dir=parent)
    try:
        _materialize(files, sandbox)
        env = dict(os.environ)
        env.update(env_extra)
        start = time.monotonic()
        try:
            proc = subprocess.run([exe, *args], cwd=sandbox, env=env, stdin=subprocess.DEVNULL,
                                  stdout=subprocess.PIPE, stderr=subprocess.PIPE, preexec_fn=die_with_worker)
        except OSError as e:
            return (127, "", f"cannot run {program!r} on worker {address}: {e}\n", None,
                    time.monotonic() - start, address)
        seconds = time.monotonic() - start
        data = None
        if collect is not None and proc.returncode == 0:
            path = os.path.join(sandbox, collect)
            try:
                if os.path.isdir(path):
                    buffer = io.BytesIO()
                    with tarfile.open(fileobj=buffer, mode="w:gz") as tar:
                        tar.add(path, arcname=".")
                    data = buffer.getvalue()
                else:
                    with open(path, "rb") as f:
                        data = f.read()
            except OSError as e:
                return (1, proc.stdout.decode(errors="replace"),
                        proc.stderr.decode(errors="replace") + f"\nexit 0 but no output: {e}\n", None, seconds,
                        address)
        return (proc.returncode, proc.stdout.decode(errors="replace"), proc.stderr.decode(errors="replace"),
                data, seconds, address)
    finally:
        shutil.rmtree(sandbox, ignore_errors=True)


def _render_shard(renderer, scene_rel, files, args, env_extra, index, count, lo, hi, topic):
    """One shard on a worker: returns {bytes, seconds, worker, host}; raises (so that Dask retries)
    when the renderer fails."""
    import socket

    output = "shard-out/shard.exr"
    rc, _, err, data, seconds, address = _run_in_sandbox(
        renderer, [scene_rel, *args, "--samples", f"{lo}:{hi}", "-o", output], files, env_extra, output)
    if rc != 0 or data is None:
        lines = err.rstrip().splitlines()
        where = f"shard {index + 1}/{count} [{lo}, {hi}) failed on worker {address} ({socket.gethostname()})"
        message = f"{where}: renderer exit {rc} after {seconds:.2f} s; its stderr ends:\n" + "\n".join(lines[-20:])
        try:
            from distributed import get_worker

            get_worker().log_event(topic, f"{where}: exit {rc}: {lines[-1] if lines else '(no stderr)'}")
        except Exception:
            pass
        raise RuntimeError(message)
    return {"bytes": data, "seconds": seconds, "worker": address, "host": socket.gethostname()}


def _explain(renderer, scene_rel, files, args, env_extra):
    """`renderer SCENE args --explain` on a worker: (exit status, stdout, stderr)."""
    rc, out, err, _, _, _ = _run_in_sandbox(renderer, [scene_rel, *args, "--explain"], files, env_extra, None)
    return rc, out, err


# ---- the client ------------------------------------------------------------------------------

class _Passthrough(argparse.Action):
    """Collects a known oas-render option and its value, in command-line order."""

    def __call__(self, parser, namespace, values, option_string=None):
        namespace.passthrough.extend([option_string, values])


def parse_args(argv):
    parser = argparse.ArgumentParser(
        prog="cluster.py", allow_abbrev=False,
        description="Render a frame as sample shards on a Dask cluster and merge them (see the module docstring).")
    commands = parser.add_subparsers(dest="command", required=True, metavar="render")
    p = commands.add_parser("render", allow_abbrev=False, help="render SCENE in shards and merge them",
                            description="Render SCENE's samples in K shards on Dask workers and merge them "
                                        "with oas-merge. Unknown options go to every oas-render call.")
    p.add_argument("scene", help="scene file (JSON, scenes/README.md)")
    p.add_argument("--shards", type=int, required=True, metavar="K", help="number of sample shards, 1 <= K <= N")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, metavar="W",
                       help="LocalCluster worker processes on this machine (default min(K, CPUs))")
    where.add_argument("--scheduler", metavar="ADDR", help="address of a running Dask scheduler (tcp://HOST:8786)")
    p.add_argument("--retries", type=int, default=2, metavar="R", help="reruns of a failed shard (default 2)")
    p.add_argument("--renderer", default=os.path.join(REPO, "build", "oas-render"),
                   help="oas-render on the workers (default %(default)s)")
    p.add_argument("--merger", default=os.path.join(REPO, "build", "oas-merge"),
                   help="oas-merge on this machine (default %(default)s)")
    p.add_argument("--worker-env", action="append", default=[], metavar="NAME=VALUE",
                   help="environment variable for the renderer on the workers (repeatable)")
    p.add_argument("-o", "--output", required=True, metavar="OUT.exr", help="merged EXR (PNG preview beside it)")
    p.set_defaults(passthrough=[])
    for option in ("--device", "--sampler", "--spp", "--offset", "--strength", "--seed"):
        p.add_argument(option, action=_Passthrough, metavar="VALUE", help=argparse.SUPPRESS)
    args, unknown = parser.parse_known_args(argv)
    args.passthrough = args.passthrough + unknown
    return args


def fail(message, status=2):
    print(f"cluster: error: {message}", file=sys.stderr)
    sys.exit(status)


def worker_options(args):
    """Checks --workers and --retries; returns --worker-env's NAME=VALUE items as a dict. Shared by
    the frame and study drivers; raises UsageError."""
    if args.workers is not None and args.workers < 1:
        raise UsageError(f"--workers {args.workers}: valid at least 1")
    if args.retries < 0:
        raise UsageError(f"--retries {args.retries}: valid at least 0")
    env_extra = {}
    for item in args.worker_env:
        name, eq, value = item.partition("=")
        if not eq or not name:
            raise UsageError(f"--worker-env {item!r}: valid NAME=VALUE")
        env_extra[name] = value
    return env_extra


def resolve_program(value, what, local):
    """An absolute path for a program (a bare name is looked up in PATH). With local, it must exist
    and be executable here."""
    if os.sep not in value:
        found = shutil.which(value)
        if found:
            return os.path.abspath(found)
        if local:
            raise UsageError(f"{what} {value!r} not found in PATH")
        return value  # looked up in the workers' PATH
    path = os.path.abspath(value)
    if local and not (os.path.isfile(path) and os.access(path, os.X_OK)):
        raise UsageError(f"{what} {path} does not exist or is not executable"
                         + (" (build oas first: scripts/build.sh)" if path.startswith(os.path.join(REPO, "build")) else ""))
    return path


def scene_files(scene_path):
    """The scene and the mesh files it references as ({relative path: bytes}, the scene's relative
    path), laid out relative to the deepest directory holding them all."""
    scene_abs = os.path.abspath(scene_path)
    scene_dir = os.path.dirname(scene_abs)
    try:
        with open(scene_abs, "rb") as f:
            scene_bytes = f.read()
        doc = json.loads(scene_bytes)
    except (OSError, ValueError) as e:
        raise UsageError(f"{scene_path}: {e}")
    meshes = {}
    shapes = doc.get("shapes") if isinstance(doc, dict) else None
    for i, shape in enumerate(shapes if isinstance(shapes, list) else []):
        if not (isinstance(shape, dict) and shape.get("type") == "mesh" and isinstance(shape.get("file"), str)):
            continue
        name = shape["file"]
        if os.path.isabs(name):
            raise UsageError(f"{scene_path}: shapes[{i}].file: absolute mesh path {name!r}: the workers share no "
                             "file system with this machine; write it relative to the scene's directory")
        source = os.path.join(scene_dir, name)
        try:
            with open(source, "rb") as f:
                meshes[os.path.normpath(source)] = f.read()
        except OSError as e:
            raise UsageError(f"{scene_path}: shapes[{i}].file: cannot read mesh {name!r}: {e}")
    root = os.path.commonpath([scene_dir] + [os.path.dirname(m) for m in meshes])
    files = {os.path.relpath(m, root): data for m, data in meshes.items()}
    scene_rel = os.path.relpath(scene_abs, root)
    files[scene_rel] = scene_bytes
    return files, scene_rel


def shard_ranges(n, k):
    """[0, n) in k contiguous ranges, the first n mod k one longer."""
    base, extra = divmod(n, k)
    ranges, lo = [], 0
    for i in range(k):
        hi = lo + base + (1 if i < extra else 0)
        ranges.append((lo, hi))
        lo = hi
    return ranges


def samples_per_pixel(rc, out, err, where):
    """N from `--explain` output, or exits."""
    if rc != 0:
        sys.stderr.write(err if err.endswith("\n") or not err else err + "\n")
        fail(f"cannot run the renderer ({where})" if rc == 127 else
             f"the renderer refused the scene or options ({where}, `--explain` exit {rc})", 2 if rc in (2, 127) else 1)
    for line in out.splitlines():
        if line.startswith("samples per pixel: "):
            try:
                return int(line.split(":", 1)[1])
            except ValueError:
                break
    fail(f"the renderer's --explain printed no 'samples per pixel: N' line ({where}): "
         "is it an oas-render that knows --samples?")


def main(argv):
    args = parse_args(argv)
    if args.shards < 1:
        fail(f"--shards {args.shards}: valid 1 .. N (the frame's samples per pixel)")
    try:
        env_extra = worker_options(args)
    except UsageError as e:
        fail(str(e))
    for option in args.passthrough:
        name = option.split("=", 1)[0]
        if name in ("--samples", "--explain"):
            fail(f"{name} is the driver's own: it gives every shard its --samples range")
    if not os.path.isfile(args.scene):
        fail(f"scene file {args.scene} does not exist" if not os.path.exists(args.scene)
             else f"scene {args.scene} is not a file")
    output = os.path.abspath(args.output)
    if not output.lower().endswith(".exr") or os.path.isdir(output):
        fail(f"--output {args.output}: valid a file name ending in .exr (its PNG preview goes beside it)")
    local = args.scheduler is None
    try:
        renderer = resolve_program(args.renderer, "--renderer", local)
        merger = resolve_program(args.merger, "--merger", True)
    except UsageError as e:
        fail(str(e))

    n = None
    if local:  # the renderer is here: check the scene and options before starting a cluster
        env = dict(os.environ, **env_extra)
        proc = subprocess.run([renderer, args.scene, *args.passthrough, "--explain"], env=env,
                              stdin=subprocess.DEVNULL, capture_output=True, text=True)
        n = samples_per_pixel(proc.returncode, proc.stdout, proc.stderr, "on this machine")
        if args.shards > n:
            fail(f"--shards {args.shards} is more than the frame's {n} samples per pixel: valid 1 .. {n}")
    try:
        files, scene_rel = scene_files(args.scene)
    except UsageError as e:
        fail(str(e))

    with tempfile.TemporaryDirectory(prefix="oas-cluster-") as tmp, \
            open_client(args.workers or min(args.shards, os.cpu_count() or 1), args.scheduler) as (client, where):
        return run(client, args, renderer, merger, files, scene_rel, env_extra, n, output, tmp, where)


@contextlib.contextmanager
def open_client(workers, scheduler):
    """A Dask client and a description of where it runs: a LocalCluster of `workers` processes
    (one thread each, no dashboard) on this machine, stopped at the end, or the running cluster at
    `scheduler` (exits with status 2 when it cannot connect)."""
    import distributed  # here, not at the top: LocalCluster's spawned workers import the driver's file

    cluster = None
    try:
        if scheduler is None:
            cluster = distributed.LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                               dashboard_address=":0", silence_logs=logging.ERROR)
            client = distributed.Client(cluster)
            where = f"a LocalCluster of {workers} worker process{'es' if workers > 1 else ''}"
        else:
            try:
                client = distributed.Client(scheduler)
            except (OSError, ValueError, TypeError) as e:
                fail(f"--scheduler {scheduler}: cannot connect: {e}")
            count = len(client.scheduler_info().get("workers", {}))
            where = f"the cluster at {scheduler} ({count} workers now)"
            if count == 0:
                print("cluster: the scheduler has no workers yet; the tasks wait for some", file=sys.stderr)
        with client:
            yield client, where
    finally:
        if cluster is not None:
            cluster.close()


def run(client, args, renderer, merger, files, scene_rel, env_extra, n, output, tmp, where):
    import distributed

    start = time.monotonic()
    [files_future] = client.scatter([files], hash=False)
    if n is None:  # with --scheduler the renderer is the workers': ask one of them
        rc, out, err = client.submit(_explain, renderer, scene_rel, files_future, args.passthrough, env_extra,
                                     pure=False).result()
        n = samples_per_pixel(rc, out, err, "on a worker")
        if args.shards > n:
            fail(f"--shards {args.shards} is more than the frame's {n} samples per pixel: valid 1 .. {n}")
    ranges = shard_ranges(n, args.shards)
    k = len(ranges)
    print(f"cluster: {k} shard{'s' if k > 1 else ''} of {n} samples per pixel on {where}, "
          f"--retries {args.retries}", file=sys.stderr)

    def on_failure(event):  # a shard's try failed; Dask reruns it unless that was the last
        print(f"cluster: {event[1]}", file=sys.stderr, flush=True)

    client.subscribe_topic(EVENT_TOPIC, on_failure)
    futures = {}
    for i, (lo, hi) in enumerate(ranges):
        future = client.submit(_render_shard, renderer, scene_rel, files_future, args.passthrough, env_extra,
                               i, k, lo, hi, EVENT_TOPIC, retries=args.retries, pure=False,
                               key=f"oas-shard-{i}-{lo}-{hi}-{os.getpid()}-{time.time_ns()}")
        futures[future] = i
    shard_paths = [None] * k
    done = 0
    for future in distributed.as_completed(list(futures)):
        i = futures[future]
        lo, hi = ranges[i]
        if future.status != "finished":
            try:
                error = future.exception()
            except Exception as e:  # cancelled
                error = e
            for other in futures:
                other.cancel()
            fail(f"gave up after {args.retries + 1} tr{'y' if args.retries == 0 else 'ies'} (--retries {args.retries}): "
                 f"{error}", 1)
        result = future.result()
        future.release()
        path = os.path.join(tmp, f"shard-{i:05d}.exr")
        with open(path, "wb") as f:
            f.write(result["bytes"])
        shard_paths[i] = path
        done += 1
        print(f"cluster: shard {i + 1}/{k} [{lo}, {hi}) done in {result['seconds']:.2f} s on {result['worker']} "
              f"({result['host']}); {done}/{k} done, {time.monotonic() - start:.1f} s", file=sys.stderr, flush=True)
    client.unsubscribe_topic(EVENT_TOPIC)

    merge_start = time.monotonic()
    os.makedirs(os.path.dirname(output), exist_ok=True)  # as oas-render does for its -o
    proc = subprocess.run([merger, *shard_paths, "-o", output, "--expect", f"0:{n}"], stdin=subprocess.DEVNULL,
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    sys.stderr.write(proc.stdout + proc.stderr)
    if proc.returncode != 0:
        fail(f"oas-merge ({merger}) failed with exit {proc.returncode}: no output written", 1)
    print(f"cluster: merged {k} shard{'s' if k > 1 else ''} into {output} in {time.monotonic() - merge_start:.2f} s; "
          f"{time.monotonic() - start:.1f} s in all", file=sys.stderr)
    return 0


def run_main(main_function, name):
    """Runs a driver's main on the command line: its return value is the exit status, 130 after ^C."""
    try:
        sys.exit(main_function(sys.argv[1:]))
    except KeyboardInterrupt:
        print(f"{name}: interrupted", file=sys.stderr)
        sys.exit(130)


if __name__ == "__main__":
    run_main(main, "cluster")
