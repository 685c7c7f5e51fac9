#!/usr/bin/env python3
"""Peer benchmark: oas against Mitsuba 3 on the same machine, runs interleaved.

Two measures, each repeated; every repeat runs ours and theirs back to back (the order alternates
between repeats so that drift on a shared machine hits both sides alike), and medians are compared:

  (a) sample generation, 16384 pixels x 121 spp x 8 dims: oas-bench rows against Mitsuba's
      `orthogonal`, `multijitter` and `independent` samplers on its LLVM backend;
  (b) rendering cornell7d (scenes/cornell7d.json, converted here to a Mitsuba scene dict) with
      the `direct` integrator at 121 spp: oas-render-bench (GPU, lavapipe) and oas-render
      --device cpu against Mitsuba's `orthogonal` and `independent` samplers.

Mitsuba is optional: with --no-mitsuba REASON (mitsuba_peer.sh passes it when Mitsuba cannot be
installed) this prints the reason and our figures alone. Only the standard library is needed then.
"""
import argparse
import json
import math
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

SPP = 121  # 11^2: Mitsuba's orthogonal sampler needs a prime squared
DIMS = 8
GEN_PIXELS = 16384
RENDER_SIZE = 256

# oas-bench rows (label prefixes) and the Mitsuba sampler each is compared with. Ours run per
# sampler name (--only matches the construction name, not the label), so the filters below pick
# the rows; bose also prints a few rows we do not pair.
GEN_PAIRS = [
    ("bose q=11 N=121 t=2 cmj", "orthogonal", "OA strength 2 (Bose), jittered, vs OA strength 2"),
    ("bose q=11 N=121 t=2 mj", "multijitter", "OA strength 2, MJ offsets, vs 2D CMJ padded"),
    ("cmj2d N=121", "multijitter", "2D CMJ padded vs 2D CMJ padded (like for like)"),
    ("random N=121", "independent", "independent uniform vs independent uniform"),
]
GEN_FILTERS = ["bose", "cmj2d", "random"]
MITSUBA_GEN_SAMPLERS = ["orthogonal", "multijitter", "independent"]
MITSUBA_RENDER_SAMPLERS = ["orthogonal", "independent"]
OAS_BENCH_COLUMNS = ["spp", "CPU 1 thr M/s", "CPU all M/s", "GPU M/s", "GPU/hash", "build s"]
RENDER_BENCH_COLUMNS = ["dims", "spp", "OA Mpaths/s", "rnd Mpaths/s", "OA/random", "OA build", "rnd build"]


def log(msg=""):
    print(msg, flush=True)


def median(values):
    return statistics.median(values) if values else float("nan")


def fmt(x, digits=1):
    return "-" if x is None or (isinstance(x, float) and math.isnan(x)) else f"{x:.{digits}f}"


def paired_ratio(ours, theirs):
    """Median over repeats of ours/theirs within each interleaved pair: slow drift of a shared
    machine cancels within a pair, so this is steadier than a ratio of medians."""
    r = [a / b for a, b in zip(ours, theirs) if a is not None and b]
    return median(r) if r else None


# ----------------------------------------------------------------------------- machine

def machine_description():
    model = "unknown CPU"
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True, check=True).stdout
        m = re.search(r"^Model name:\s*(.+)$", out, re.M)
        if m:
            model = m.group(1).strip()
    except (OSError, subprocess.CalledProcessError):
        pass
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    return model, cores


# ----------------------------------------------------------------------------- ours

def parse_table(text, header_word, columns):
    """Rows of one of our benchmark tables: {label: {column: value}}.

    Labels and column names both contain spaces, so the columns are named by the caller and
    checked against the header (a changed format fails here instead of being misread), and each
    row's values are taken from the right."""
    lines = text.splitlines()
    for i, line in enumerate(lines):
        if line.split()[:1] == [header_word]:
            break
    else:
        raise RuntimeError(f"no table header starting with {header_word!r} in:\n{text}")
    pos = 0
    for name in columns:
        pos = line.find(name, pos)
        if pos < 0:
            raise RuntimeError(f"table header lacks column {name!r} (or has another order): {line!r}")
    rows = {}
    for line in lines[i + 1:]:
        if not line.strip():
            break  # a table ends at its first blank line
        tokens = line.split()
        if len(tokens) > len(columns):
            label = " ".join(tokens[: len(tokens) - len(columns)])
            rows[label] = dict(zip(columns, tokens[len(tokens) - len(columns):]))
    return rows


def run_tool(cmd):
    """stdout of one of our tools; a failure carries its stderr, which says what went wrong."""
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed ({proc.returncode}):\n{proc.stderr[-2000:]}")
    return proc.stdout


def number(field):
    try:
        return float(field.rstrip("s"))
    except (AttributeError, ValueError):
        return None


def run_oas_bench(binaries, pixels):
    """One timed run (after oas-bench's own warm-up) of every paired row: label -> (GPU, CPU)."""
    found = {}
    device = None
    for only in GEN_FILTERS:
        cmd = [os.path.join(binaries, "oas-bench"), "--pixels", str(pixels), "--dims", str(DIMS),
               "--repeats", "1", "--only", only]
        out = run_tool(cmd)
        m = re.search(r"CPU threads: \d+; GPU: (.+)$", out, re.M)
        device = m.group(1) if m else device
        for label, cols in parse_table(out, "sampler", OAS_BENCH_COLUMNS).items():
            for prefix, _, _ in GEN_PAIRS:
                if label.startswith(prefix):
                    found[prefix] = (number(cols.get("GPU M/s")), number(cols.get("CPU all M/s")))
    missing = [p for p, _, _ in GEN_PAIRS if p not in found]
    if missing:
        raise RuntimeError(f"oas-bench printed no row for {missing}")
    return found, device


def our_kernel_stores(repo):
    """Whether our generation kernel writes every sample-dim out (it is what oas-bench times)."""
    try:
        with open(os.path.join(repo, "shaders", "oas_generate.comp")) as f:
            return re.search(r"values\[[^\]]+\]\s*=", f.read()) is not None
    except OSError:
        return None


def run_oas_render_bench(binaries, scene_dir, size):
    """Our GPU Mpaths/s for cornell7d: (OA, random).

    oas-render-bench renders a fixed list of scenes from --scenes and then cornell7d's effect
    variants; we only need its cornell7d row, so it gets a directory holding cornell7d alone and
    is stopped as soon as that row is out (it would otherwise stop at the next, missing scene)."""
    cmd = [os.path.join(binaries, "oas-render-bench"), "--scenes", scene_dir, "--size", str(size),
           "--only", "cornell7d", "--no-effects"]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    text, stopped = "", False
    try:
        for line in proc.stdout:
            text += line
            if line.startswith("cornell7d "):
                break
    finally:
        if proc.poll() is None:
            proc.terminate()
            stopped = True
        errors = proc.stderr.read() if not stopped else ""
        proc.wait()
        proc.stdout.close()
        proc.stderr.close()
    row = parse_table(text, "scene", RENDER_BENCH_COLUMNS).get("cornell7d gpu")
    if row is None:
        raise RuntimeError(f"oas-render-bench printed no cornell7d row:\n{text}{errors[-2000:]}")
    return number(row.get("OA Mpaths/s")), number(row.get("rnd Mpaths/s"))


def cpu_render_command(binaries):
    """oas-render-bench has no CPU mode (as of 6c51d4e); oas-render --device cpu times the
    reference tracer (all cores) and prints Mpaths/s, so that is our CPU figure where it exists."""
    exe = os.path.join(binaries, "oas-render")
    try:
        helptext = subprocess.run([exe, "--help"], capture_output=True, text=True).stdout
    except OSError:
        return None
    return exe if re.search(r"--device\b.*cpu", helptext) else None


def run_oas_render_cpu(exe, scene_path, sampler, out_dir):
    out = os.path.join(out_dir, f"oas-cpu-{sampler}.exr")
    cmd = [exe, scene_path, "--device", "cpu", "--spp", str(SPP), "-o", out]
    if sampler != "oa":
        cmd += ["--sampler", sampler]
    text = run_tool(cmd)
    m = re.search(r"([0-9.]+) Mpaths/s", text)
    if not m:
        raise RuntimeError(f"oas-render printed no Mpaths/s:\n{text}")
    return float(m.group(1)), out


def scaled_scene(scene_path, size, out_dir):
    """cornell7d at `size` pixels wide (oas-render has no size option; the benches rescale the
    same way: height keeps the aspect)."""
    with open(scene_path) as f:
        scene = json.load(f)
    w, h = scene["resolution"]
    scene["resolution"] = [size, max(1, h * size // w)]
    os.makedirs(out_dir, exist_ok=True)
    path = os.path.join(out_dir, os.path.basename(scene_path))
    with open(path, "w") as f:
        json.dump(scene, f, indent=1)
    return path, scene


# ----------------------------------------------------------------------------- Mitsuba

class Mitsuba:
    def __init__(self):
        import drjit as dr
        import mitsuba as mi

        self.dr, self.mi = dr, mi
        wanted = ["llvm_ad_rgb", "llvm_rgb"]
        self.variant = next((v for v in wanted if v in mi.variants()), None)
        if self.variant is None:
            raise RuntimeError(f"no LLVM RGB variant in this build (have {mi.variants()})")
        mi.set_variant(self.variant)
        if not dr.has_backend(dr.JitBackend.LLVM):
            raise RuntimeError("Dr.Jit could not load libLLVM (set DRJIT_LIBLLVM_PATH)")
        # Kernel history tells whether a timed run reused a cached kernel, as intended.
        dr.set_flag(dr.JitFlag.KernelHistory, True)
        self.cache_misses = []  # timed runs whose kernel was not in the in-memory cache
        self.samplers = {}

    def describe(self):
        dr, mi = self.dr, self.mi
        llvm = ".".join(map(str, dr.detail.llvm_version()))
        return (f"Mitsuba {mi.__version__}, Dr.Jit {dr.__version__}, variant {self.variant}, "
                f"LLVM {llvm} from {os.environ.get('DRJIT_LIBLLVM_PATH', '(Dr.Jit default search)')}, "
                f"{dr.thread_count()} threads")

    def _count_misses(self, label):
        for k in self.dr.kernel_history():
            if str(k.get("type")).endswith("JIT") and not k.get("cache_hit", True):
                where = "from the disk cache" if k.get("cache_disk") else "compiled"
                self.cache_misses.append(f"{label} ({where}, {k.get('backend_time', 0):.0f} ms)")

    def generate(self, name, pixels, mode, seed):
        """Seconds for one generation pass.

        mode "store": all 8 dims of every sample are evaluated into memory (what ours does);
        mode "accumulate": each sample's dims are summed and scatter-added into one float per
        pixel inside the same kernel (symbolic block_sum), so no per-sample value is stored."""
        dr, mi = self.dr, self.mi
        sampler = self.samplers.get(name)
        if sampler is None:
            sampler = self.samplers[name] = mi.load_dict({"type": name, "sample_count": SPP})
        dr.kernel_history()  # clear
        start = time.perf_counter()
        # One pixel's SPP samples are consecutive lanes, as Mitsuba's integrators lay them out.
        sampler.set_samples_per_wavefront(SPP)
        sampler.seed(seed, pixels * SPP)
        xs = [sampler.next_1d() for _ in range(DIMS)]
        if mode == "store":
            dr.eval(*xs)
        else:
            total = xs[0]
            for x in xs[1:]:
                total = total + x
            per_pixel = dr.block_sum(total, SPP, mode="symbolic")
            dr.eval(per_pixel)
        dr.sync_thread()
        seconds = time.perf_counter() - start
        self._count_misses(f"generate {name} {mode} seed {seed}")
        return seconds

    @staticmethod
    def _look_at(mi, origin, target, up):
        T = mi.ScalarTransform4f
        try:
            return T().look_at(origin=origin, target=target, up=up)  # Mitsuba >= 3.6
        except TypeError:
            return T.look_at(origin=origin, target=target, up=up)

    def convert(self, scene, sampler):
        """Our scene JSON (scenes/README.md) as a Mitsuba scene dict; returns (dict, notes).

        Covers what cornell7d uses and refuses the rest, so a silent mismatch cannot creep in."""
        mi = self.mi
        notes = []

        def grey(c):  # "one number means grey" (scenes/README.md)
            return [float(c)] * 3 if isinstance(c, (int, float)) else [float(x) for x in c]
        w, h = scene["resolution"]
        cam = scene["camera"]
        shutter = scene.get("shutter", {})
        t_open, t_close = float(shutter.get("open", 0)), float(shutter.get("close", 0))
        sensor = {
            "type": "thinlens" if cam.get("apertureRadius", 0) > 0 else "perspective",
            "fov": float(cam["fovY"]),
            "fov_axis": "y",
            "to_world": self._look_at(mi, cam["position"], cam["lookAt"], cam.get("up", [0, 1, 0])),
            # Keeping the shutter open makes Mitsuba draw a time sample like ours (7 dims), even
            # though nothing in its scene moves (see the sphere below).
            "shutter_open": t_open,
            "shutter_close": t_close,
            "film": {"type": "hdrfilm", "width": w, "height": h, "pixel_format": "rgb",
                     # Ours adds each sample to its own pixel: a box filter.
                     "rfilter": {"type": "box"}},
            "sampler": {"type": sampler, "sample_count": SPP},
        }
        if sensor["type"] == "thinlens":
            sensor["aperture_radius"] = float(cam["apertureRadius"])
            dist = [b - a for a, b in zip(cam["position"], cam["lookAt"])]
            sensor["focus_distance"] = float(cam.get("focusDistance", math.sqrt(sum(d * d for d in dist))))

        materials = {}
        for m in scene["materials"]:
            if m.get("type", "diffuse") != "diffuse":
                raise ValueError(f"material {m['name']}: only diffuse is converted")
            # Ours scatters on both sides of every surface; Mitsuba's diffuse is one-sided.
            bsdf = {"type": "twosided", "material": {
                "type": "diffuse", "reflectance": {"type": "rgb", "value": grey(m.get("albedo", 0.8))}}}
            materials[m["name"]] = (bsdf, grey(m.get("emission", 0)))

        out = {"type": "scene", "sensor": sensor}
        integ = scene.get("integrator", {})
        if integ.get("type") != "direct" or not integ.get("nextEventEstimation", True) or integ.get("mis", True):
            raise ValueError("only the direct integrator with NEE and without MIS is converted")
        # One light sample and no BSDF sample per hit: Mitsuba's MIS weight is then 1, i.e. NEE
        # without MIS; emitters seen directly are still added, as ours does.
        out["integrator"] = {"type": "direct", "emitter_samples": 1, "bsdf_samples": 0}
        env = grey(scene.get("environment", 0))
        if any(env):
            out["environment"] = {"type": "constant", "radiance": {"type": "rgb", "value": env}}
        if scene.get("lights"):
            raise ValueError("point and spot lights are not converted")

        for i, s in enumerate(scene["shapes"]):
            bsdf, emission = materials[s["material"]]
            vel = s.get("velocity", [0, 0, 0])
            if any(vel) and t_close > t_open:
                notes.append(f"shape {i} ({s['type']}) moves with velocity {vel} in ours but is static in "
                             "Mitsuba at its t = 0 position (Mitsuba 3 has no animated shapes): "
                             "Mitsuba's scene has no motion blur")
            if s["type"] in ("quad", "rectangle"):
                c, eu, ev = ([float(x) for x in s[k]] for k in ("corner", "edgeU", "edgeV"))
                n = [eu[1] * ev[2] - eu[2] * ev[1], eu[2] * ev[0] - eu[0] * ev[2], eu[0] * ev[1] - eu[1] * ev[0]]
                ln = math.sqrt(sum(x * x for x in n))
                n = [x / ln for x in n]
                centre = [c[k] + 0.5 * (eu[k] + ev[k]) for k in range(3)]
                # Mitsuba's rectangle is [-1,1]^2 at z = 0 with normal +z: x -> edgeU/2, y ->
                # edgeV/2, z -> our normal cross(edgeU, edgeV), so front sides (and the emitting
                # side) agree.
                m = [[eu[k] / 2, ev[k] / 2, n[k], centre[k]] for k in range(3)] + [[0, 0, 0, 1]]
                shape = {"type": "rectangle", "to_world": mi.ScalarTransform4f(m)}
            elif s["type"] == "sphere":
                shape = {"type": "sphere", "center": [float(x) for x in s["center"]],
                         "radius": float(s["radius"])}
            else:
                raise ValueError(f"shape {i}: type {s['type']} is not converted")
            shape["bsdf"] = bsdf
            if any(emission):
                # Mitsuba's area emitter emits on the front side only, like ours.
                shape["emitter"] = {"type": "area", "radiance": {"type": "rgb", "value": emission}}
            out[f"shape{i:02d}"] = shape
        return out, notes

    def load_scene(self, scene, sampler):
        d, notes = self.convert(scene, sampler)
        return self.mi.load_dict(d), notes

    def render(self, mscene, seed, label="render"):
        """(seconds, image) for one render at SPP, waiting for the result."""
        dr, mi = self.dr, self.mi
        dr.kernel_history()
        start = time.perf_counter()
        image = mi.render(mscene, spp=SPP, seed=seed)
        dr.eval(image)
        dr.sync_thread()
        seconds = time.perf_counter() - start
        self._count_misses(f"{label} seed {seed}")
        return seconds, image

    def image_means(self, image):
        """Mean RGB over the image, and the red and green channels' means over the left and right
        halves (the red wall is on the left): enough to catch a mirrored or misconverted scene."""
        dr, mi = self.dr, self.mi
        t = mi.TensorXf(image)
        w = t.shape[1]

        def mean(c, x0, x1):
            return float(dr.mean(t[:, x0:x1, c].array)[0])
        return ([mean(c, 0, w) for c in range(3)],
                (mean(0, 0, w // 2), mean(0, w // 2, w)), (mean(1, 0, w // 2), mean(1, w // 2, w)))

    def read_exr(self, path):
        return self.mi.TensorXf(self.mi.Bitmap(path))


# ----------------------------------------------------------------------------- measures

def measure_generation(args, mitsuba):
    pixels = args.gen_pixels
    ours = {p: ([], []) for p, _, _ in GEN_PAIRS}
    theirs = {(n, m): [] for n in MITSUBA_GEN_SAMPLERS for m in ("store", "accumulate")}
    device = None
    work = pixels * SPP * DIMS
    if mitsuba:
        for n in MITSUBA_GEN_SAMPLERS:  # first runs compile the kernels: untimed
            for m in ("store", "accumulate"):
                mitsuba.generate(n, pixels, m, seed=0)
        mitsuba.cache_misses.clear()

    def run_ours():
        nonlocal device
        found, device = run_oas_bench(args.binaries, pixels)
        for p, (gpu, cpu) in found.items():
            ours[p][0].append(gpu)
            ours[p][1].append(cpu)

    def run_theirs(rep):
        for n in MITSUBA_GEN_SAMPLERS:
            for m in ("store", "accumulate"):
                theirs[(n, m)].append(work / mitsuba.generate(n, pixels, m, seed=rep + 1) / 1e6)

    for rep in range(args.repeats):
        sides = [run_ours] + ([lambda: run_theirs(rep)] if mitsuba else [])
        for side in (sides if rep % 2 == 0 else sides[::-1]):
            side()
        log(f"  generation repeat {rep + 1}/{args.repeats} done")
    return ours, theirs, device


def measure_rendering(args, mitsuba, tmp):
    scene_src = os.path.join(args.scenes, "cornell7d.json")
    bench_dir = os.path.join(tmp, "bench-scenes")
    scene_path, scene = scaled_scene(scene_src, args.size, bench_dir)
    cpu_exe = cpu_render_command(args.binaries)
    paths = args.size * scene["resolution"][1] * SPP
    ours = {"gpu_oa": [], "gpu_rnd": [], "cpu_oa": [], "cpu_rnd": []}
    theirs = {n: [] for n in MITSUBA_RENDER_SAMPLERS}
    notes, our_exr, images = [], None, {}
    mscenes = {}
    if mitsuba:
        for n in MITSUBA_RENDER_SAMPLERS:
            mscenes[n], notes = mitsuba.load_scene(scene, n)
            _, images[n] = mitsuba.render(mscenes[n], seed=0)  # compiles the kernel: untimed
        mitsuba.cache_misses.clear()

    def run_ours():
        nonlocal our_exr
        oa, rnd = run_oas_render_bench(args.binaries, bench_dir, args.size)
        ours["gpu_oa"].append(oa)
        ours["gpu_rnd"].append(rnd)
        if cpu_exe:
            m, our_exr = run_oas_render_cpu(cpu_exe, scene_path, "oa", tmp)
            ours["cpu_oa"].append(m)
            ours["cpu_rnd"].append(run_oas_render_cpu(cpu_exe, scene_path, "random", tmp)[0])

    def run_theirs(rep):
        for n in MITSUBA_RENDER_SAMPLERS:
            seconds, images[n] = mitsuba.render(mscenes[n], seed=rep + 1, label=f"render {n}")
            theirs[n].append(paths / seconds / 1e6)

    for rep in range(args.repeats):
        sides = [run_ours] + ([lambda: run_theirs(rep)] if mitsuba else [])
        for side in (sides if rep % 2 == 0 else sides[::-1]):
            side()
        log(f"  rendering repeat {rep + 1}/{args.repeats} done")

    check = None
    if mitsuba and our_exr:
        check = (mitsuba.image_means(mitsuba.read_exr(our_exr)), mitsuba.image_means(images["orthogonal"]))
    return ours, theirs, notes, cpu_exe is not None, check


# ----------------------------------------------------------------------------- report

def main():
    here = os.path.dirname(os.path.abspath(__file__))
    repo = os.path.dirname(os.path.dirname(here))
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--binaries", default=os.path.join(repo, "build"),
                    help="directory holding oas-bench, oas-render-bench, oas-render")
    ap.add_argument("--scenes", default=os.path.join(repo, "scenes"))
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--quick", action="store_true", help="smoke run: small sizes, one repeat")
    ap.add_argument("--no-mitsuba", metavar="REASON", help="skip Mitsuba, saying why")
    ap.add_argument("--json", metavar="PATH", help="also write every per-repeat figure here")
    args = ap.parse_args()
    args.gen_pixels, args.size = GEN_PIXELS, RENDER_SIZE
    if args.quick:
        args.gen_pixels, args.size, args.repeats = 1024, 64, 1
    for exe in ("oas-bench", "oas-render-bench"):
        if not os.access(os.path.join(args.binaries, exe), os.X_OK):
            sys.exit(f"mitsuba_peer: {exe} not found in {args.binaries} (build the project or pass --binaries)")

    mitsuba, reason = None, args.no_mitsuba
    if reason is None:
        try:
            mitsuba = Mitsuba()
        except Exception as e:  # any import or backend failure means: ours alone
            reason = f"{type(e).__name__}: {e}"
    model, cores = machine_description()
    log(f"machine: {model}, {cores} cores")
    log("ours: oas-bench / oas-render-bench on lavapipe (Mesa's Vulkan on the CPU, all cores), "
        "CPU figures on all cores")
    if mitsuba:
        log(f"theirs: {mitsuba.describe()}")
    else:
        log(f"Mitsuba 3 not available: {reason}; printing oas figures alone")
    log(f"repeats: {args.repeats}" + (", interleaved (ours then theirs, order alternating)" if mitsuba else "")
        + ", medians reported\n")

    tmp = tempfile.mkdtemp(prefix="oas-peer-")
    try:
        log(f"(a) sample generation: {args.gen_pixels} pixels x {SPP} spp x {DIMS} dims")
        g_ours, g_theirs, device = measure_generation(args, mitsuba)
        log(f"(b) rendering cornell7d at {args.size} px wide, {SPP} spp, direct lighting")
        r_ours, r_theirs, notes, have_cpu, check = measure_rendering(args, mitsuba, tmp)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"generation": {"ours": {p: {"gpu": v[0], "cpu": v[1]} for p, v in g_ours.items()},
                                      "theirs": {f"{n} {m}": v for (n, m), v in g_theirs.items()}},
                       "rendering": {"ours": r_ours, "theirs": r_theirs}}, f, indent=1)

    stores = our_kernel_stores(repo)
    log(f"\n== (a) sample generation, M sample-dims/s (median of {args.repeats}) ==")
    log(f"ours GPU = oas-bench 'GPU M/s' on {device}; ours CPU = 'CPU all M/s' (a slice of at most 4096 pixels)")
    log("ours: " + {True: "the kernel STORES every sample-dim to a device buffer (no copy-back); it does "
                          "not accumulate", False: "the kernel does not store every value",
                    None: "could not read shaders/oas_generate.comp"}[stores])
    if mitsuba:
        log("theirs store = all 8 dims evaluated into memory (the same work as ours); theirs accum = dims "
            "summed and scatter-added per pixel in the kernel, nothing per sample stored")
        log("ratios: median over repeats of ours/theirs within each interleaved pair")
    head = f"{'ours row':<26} {'GPU':>7} {'CPU':>7}"
    if mitsuba:
        head += f"  {'Mitsuba':<12} {'store':>7} {'accum':>7}  {'GPU/store':>9} {'CPU/store':>9} {'GPU/accum':>9}"
    log(head)
    for prefix, theirs_name, _ in GEN_PAIRS:
        gpus, cpus = g_ours[prefix]
        gpu, cpu = (median([v for v in vals if v is not None]) for vals in (gpus, cpus))
        line = f"{prefix:<26} {fmt(gpu):>7} {fmt(cpu):>7}"
        if mitsuba:
            sts, acs = g_theirs[(theirs_name, "store")], g_theirs[(theirs_name, "accumulate")]
            line += (f"  {theirs_name:<12} {fmt(median(sts)):>7} {fmt(median(acs)):>7}  "
                     f"{fmt(paired_ratio(gpus, sts), 2):>9} {fmt(paired_ratio(cpus, sts), 2):>9} "
                     f"{fmt(paired_ratio(gpus, acs), 2):>9}")
        log(line)
    if mitsuba:
        log("pairs: " + "; ".join(f"{p} ~ {t}: {why}" for p, t, why in GEN_PAIRS))

    paths = args.size * args.size * SPP
    log(f"\n== (b) rendering cornell7d {args.size}x{args.size} x {SPP} spp = {paths / 1e6:.2f} M paths, "
        f"Mpaths/s (median of {args.repeats}) ==")
    log("ours GPU = oas-render-bench (lavapipe; pipeline build and one warm-up untimed); ours CPU = "
        + ("oas-render --device cpu (reference tracer, all cores)" if have_cpu else "not available"))
    if mitsuba:
        log("theirs = mi.render at 121 spp in one wavefront, warm (kernel cached), waiting for the image")
    rows = [("OA (ours oa = bose cmj)", "gpu_oa", "cpu_oa", "orthogonal"),
            ("random", "gpu_rnd", "cpu_rnd", "independent")]
    head = f"{'sampler':<24} {'ours GPU':>9} {'ours CPU':>9}"
    if mitsuba:
        head += f"  {'Mitsuba':<12} {'theirs':>8}  {'GPU/theirs':>10} {'CPU/theirs':>10}"
        log("ratios: median over repeats of ours/theirs within each interleaved pair")
    log(head)
    for label, kg, kc, tn in rows:
        gpu, cpu = median(r_ours[kg]), median(r_ours[kc])
        line = f"{label:<24} {fmt(gpu, 3):>9} {fmt(cpu, 3):>9}"
        if mitsuba:
            ths = r_theirs[tn]
            line += (f"  {tn:<12} {fmt(median(ths), 3):>8}  {fmt(paired_ratio(r_ours[kg], ths), 3):>10} "
                     f"{fmt(paired_ratio(r_ours[kc], ths), 3):>10}")
        log(line)
    for n in notes:
        log(f"note: {n}")
    if check:
        (o_mean, o_r, o_g), (t_mean, t_r, t_g) = check
        log("image check (ours CPU OA vs Mitsuba orthogonal, last renders): mean RGB "
            f"{' '.join(f'{v:.4f}' for v in o_mean)} vs {' '.join(f'{v:.4f}' for v in t_mean)}; "
            f"red left/right {o_r[0]:.3f}/{o_r[1]:.3f} vs {t_r[0]:.3f}/{t_r[1]:.3f}; "
            f"green left/right {o_g[0]:.3f}/{o_g[1]:.3f} vs {t_g[0]:.3f}/{t_g[1]:.3f}")
    if mitsuba:
        # Warm-up runs are untimed, so a timed run should always find its kernel cached.
        misses = mitsuba.cache_misses
        log(f"Mitsuba timed runs whose kernel was not cached in memory: {len(misses)}"
            + (f" ({'; '.join(misses)}; medians absorb single outliers)" if misses else ""))


if __name__ == "__main__":
    main()
