#!/usr/bin/env python3
"""Peer benchmark: oas against Mitsuba 3 on the same machine, runs interleaved.

Two measures, each repeated; every repeat runs ours and theirs back to back (the order alternates
between repeats so that drift on a shared machine hits both sides alike), and medians are compared:

  (a) sample generation, 16384 pixels x 121 spp x 8 dims: oas-bench rows against Mitsuba's
      `orthogonal`, `multijitter` and `independent` samplers on its LLVM backend;
  (b) rendering three scenes, each converted here to a Mitsuba scene dict (Mitsuba.convert):
      cornell7d (direct lighting, 121 spp), blue_spheres9d (path tracing without NEE, 121 spp) and
      interior_deep (path tracing with NEE, MIS and Russian roulette, 64 spp): oas-render-bench
      (GPU, lavapipe) and oas-render --device cpu against Mitsuba's `orthogonal` and
      `independent` samplers with its `direct` or `path` integrator.

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

SPP = 121  # (a)'s samples per pixel, 11^2: Mitsuba's orthogonal sampler needs a prime squared
DIMS = 8
GEN_PIXELS = 16384
RENDER_SIZE = 256
# (b)'s scenes (scenes/<name>.json) and samples per pixel, in the order they are measured. The
# counts are oas-render-bench's (kBenchScenes in bench/render_bench.cpp), whose rows are our GPU
# figures; every side renders at that count (checked against the bench's spp column), so
# blue_spheres9d runs at 121, not its file's 128. Mitsuba's `orthogonal` takes a prime squared
# only (it rounds anything else up: 64 -> 121), so it renders at the prime square nearest to this
# count (nearest_prime_square) and its Mpaths/s counts the paths it traced.
RENDER_SCENES = [("cornell7d", 121), ("blue_spheres9d", 121), ("interior_deep", 64)]

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
        m = re.search(r"CPU threads: \d+[^;]*; GPU: (.+)$", out, re.M)  # "2 (OA loops: AVX2); GPU: ..."
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
            # A storage-buffer element or a storage texel (imageStore) per value.
            return re.search(r"values\[[^\]]+\]\s*=|imageStore\s*\(", f.read()) is not None
    except OSError:
        return None


def run_oas_render_bench(binaries, scene_dir, size, name, spp):
    """Our GPU Mpaths/s for one scene: (OA, random).

    oas-render-bench renders its fixed list of scenes (--only picks ours by file name) and then
    cornell7d's effect variants (--no-effects skips them); it is stopped as soon as our row is out.
    Its sample count is its own, so the row's spp column is checked against ours."""
    cmd = [os.path.join(binaries, "oas-render-bench"), "--scenes", scene_dir, "--size", str(size),
           "--only", name, "--no-effects"]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    text, stopped = "", False
    try:
        for line in proc.stdout:
            text += line
            if line.startswith(f"{name} "):
                break
    finally:
        if proc.poll() is None:
            proc.terminate()
            stopped = True
        errors = proc.stderr.read() if not stopped else ""
        proc.wait()
        proc.stdout.close()
        proc.stderr.close()
    row = parse_table(text, "scene", RENDER_BENCH_COLUMNS).get(f"{name} gpu")
    if row is None:
        raise RuntimeError(f"oas-render-bench printed no {name} row:\n{text}{errors[-2000:]}")
    if number(row.get("spp")) != spp:
        raise RuntimeError(f"oas-render-bench renders {name} at {row.get('spp')} spp, this script at {spp}: "
                           "update RENDER_SCENES to match bench/render_bench.cpp")
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


def our_oa_choice(exe, scene_path, spp):
    """The construction our `oa` sampler picks for the scene at spp (oas-render --explain), for the
    table's label; None where it cannot be asked."""
    if exe is None:
        return None
    try:
        text = run_tool([exe, scene_path, "--spp", str(spp), "--explain"])
    except (OSError, RuntimeError):
        return None
    m = re.search(r"^sampler: chose (.+?),", text, re.M)
    return m.group(1) if m else None


def run_oas_render_cpu(exe, scene_path, sampler, spp, out_dir):
    name = os.path.splitext(os.path.basename(scene_path))[0]
    out = os.path.join(out_dir, f"oas-cpu-{name}-{sampler}.exr")
    cmd = [exe, scene_path, "--device", "cpu", "--spp", str(spp), "-o", out]
    if sampler != "oa":
        cmd += ["--sampler", sampler]
    text = run_tool(cmd)
    m = re.search(r"([0-9.]+) Mpaths/s", text)
    if not m:
        raise RuntimeError(f"oas-render printed no Mpaths/s:\n{text}")
    return float(m.group(1)), out


def scaled_scene(scene_path, size, out_dir):
    """A scene at `size` pixels wide (the benches rescale the same way: height keeps the aspect),
    written to out_dir for oas-render and oas-render-bench."""
    with open(scene_path) as f:
        scene = json.load(f)
    w, h = scene["resolution"]
    scene["resolution"] = [size, max(1, h * size // w)]
    os.makedirs(out_dir, exist_ok=True)
    path = os.path.join(out_dir, os.path.basename(scene_path))
    with open(path, "w") as f:
        json.dump(scene, f, indent=1)
    return path, scene


def nearest_prime_square(n):
    """The square of a prime nearest to n (the larger one on a tie): what Mitsuba's `orthogonal`
    sampler can render (strength-2 Bose arrays of p^2 runs, p prime)."""
    def is_prime(k):
        return k >= 2 and all(k % d for d in range(2, int(math.isqrt(k)) + 1))
    below = max((p * p for p in range(2, math.isqrt(n) + 1) if is_prime(p)), default=None)
    p = 2
    while p * p < n or not is_prime(p):
        p += 1
    return below if below is not None and n - below < p * p - n else p * p


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

    def convert(self, scene, sampler, spp):
        """Our scene JSON (scenes/README.md; exact meanings in shaders/pt/) as a Mitsuba scene dict
        whose sensor renders with `sampler` at `spp`; returns (dict, notes).

        Covers what cornell7d, blue_spheres9d and interior_deep use and refuses the rest, so a
        silent mismatch cannot creep in. Each note names a difference that remains: Mitsuba does
        other work there, or renders a slightly different image."""
        mi = self.mi
        notes = []

        def grey(c):  # "one number means grey" (scenes/README.md)
            return [float(c)] * 3 if isinstance(c, (int, float)) else [float(x) for x in c]

        def rgb(c):
            return {"type": "rgb", "value": grey(c)}
        w, h = scene["resolution"]
        cam = scene["camera"]
        shutter = scene.get("shutter", {})
        t_open, t_close = float(shutter.get("open", 0)), float(shutter.get("close", 0))
        sensor = {
            "type": "thinlens" if cam.get("apertureRadius", 0) > 0 else "perspective",
            "fov": float(cam["fovY"]),
            "fov_axis": "y",
            "to_world": self._look_at(mi, cam["position"], cam["lookAt"], cam.get("up", [0, 1, 0])),
            # Keeping the shutter open makes Mitsuba draw a time sample like ours, even though
            # nothing in its scene moves (see the shapes below).
            "shutter_open": t_open,
            "shutter_close": t_close,
            "film": {"type": "hdrfilm", "width": w, "height": h, "pixel_format": "rgb",
                     # Ours adds each sample to its own pixel: a box filter.
                     "rfilter": {"type": "box"}},
            "sampler": {"type": sampler, "sample_count": spp},
        }
        if sensor["type"] == "thinlens":
            sensor["aperture_radius"] = float(cam["apertureRadius"])
            dist = [b - a for a, b in zip(cam["position"], cam["lookAt"])]
            sensor["focus_distance"] = float(cam.get("focusDistance", math.sqrt(sum(d * d for d in dist))))

        # Materials (shaders/pt/pt_bsdf.glsl). Alpha below PT_SMOOTH_ALPHA is a delta lobe in ours.
        smooth_alpha = 1e-3
        materials = {}
        kinds = set()
        for m in scene["materials"]:
            kind = m.get("type", "diffuse")
            alpha = float(m.get("roughness", 0))
            if kind == "diffuse":
                inner = {"type": "diffuse", "reflectance": rgb(m.get("albedo", 0.8))}
            elif kind == "conductor":
                # Ours: GGX D, separable Smith G1(wo) G1(wi), Schlick Fresnel with F0 = albedo.
                # Mitsuba's conductors have no Schlick Fresnel: material "none" is a perfect
                # reflector (F = 1) scaled by specular_reflectance, i.e. F = F0 at every angle.
                # (A conductor with eta = (1 + sqrt F0) / (1 - sqrt F0), k = 0 is further from
                # Schlick's hemispherical average for F0 >= 0.3; `principled` with metallic 1 has
                # Schlick's Fresnel but evaluates more lobes: not the same work.)
                inner = {"type": "conductor", "material": "none",
                         "specular_reflectance": rgb(m.get("albedo", 0.9))}
                if alpha >= smooth_alpha:
                    inner.update({"type": "roughconductor", "distribution": "ggx", "alpha": alpha})
            elif kind == "dielectric":
                # ior is inside over outside; Mitsuba's ext_ior defaults to air (1.000277), ours is 1.
                tint = rgb(m.get("albedo", 1))
                inner = {"type": "dielectric", "int_ior": float(m.get("ior", 1.5)), "ext_ior": 1.0,
                         "specular_reflectance": tint, "specular_transmittance": tint}
                if alpha >= smooth_alpha:
                    inner.update({"type": "roughdielectric", "distribution": "ggx", "alpha": alpha})
            else:
                raise ValueError(f"material {m['name']}: type {kind} is not converted")
            kinds.add((kind, alpha >= smooth_alpha))
            # Ours scatters on both sides of every surface (n is flipped to face wo); Mitsuba's
            # diffuse and conductors are one-sided: `twosided` does the same. A dielectric has two
            # sides already.
            bsdf = inner if kind == "dielectric" else {"type": "twosided", "material": inner}
            materials[m["name"]] = (bsdf, grey(m.get("emission", 0)))

        out = {"type": "scene", "sensor": sensor}
        integ = scene.get("integrator", {})
        itype = integ.get("type", "path")
        nee = integ.get("nextEventEstimation", True)
        mis = integ.get("mis", nee)
        if itype == "direct":
            if not nee:
                raise ValueError("the direct integrator without next-event estimation is not converted")
            # One light sample per hit, and a BSDF sample only for MIS: with bsdf_samples 0
            # Mitsuba's MIS weight is 1, i.e. NEE without MIS; emitters seen directly are still
            # added, as ours does.
            out["integrator"] = {"type": "direct", "emitter_samples": 1, "bsdf_samples": 1 if mis else 0}
        elif itype == "path":
            depth = int(integ.get("maxDepth", 5))
            rr = int(integ.get("rouletteStartDepth", 0))
            # Ours: maxDepth counts path vertices x1..xD; with NEE each samples the lights, so
            # paths scatter up to D times; without NEE the last vertex only collects emission
            # (up to D - 1 scatterings). Mitsuba's max_depth counts segments: 1 = emission seen
            # directly, 2 = one scattering (direct lighting).
            max_depth = depth + 1 if nee else depth
            # Both roll after the BSDF sample at vertex k >= start (ours pt_integrator.glsl,
            # Mitsuba `depth >= rr_depth` after its increment); ours 0 = never, which Mitsuba's
            # max_depth makes unreachable.
            out["integrator"] = {"type": "path", "max_depth": max_depth,
                                 "rr_depth": rr if rr > 0 else max_depth}
            if not nee:
                notes.append(f"ours traces without next-event estimation (lights are found only by "
                             f"hitting them, maxDepth {depth} = up to {depth - 1} scatterings); Mitsuba's "
                             f"`path` (max_depth {max_depth}, the same paths) always samples an emitter at "
                             "every non-delta vertex and weights it by MIS against BSDF sampling: the same "
                             "expected image with less noise, but a shadow ray and a light-pdf evaluation "
                             "more per vertex")
            elif not mis:
                notes.append("ours does next-event estimation without MIS; Mitsuba's `path` always weights "
                             "it by MIS against BSDF sampling (the same expected image, other work)")
            if rr > 0:
                notes.append(f"Russian roulette from vertex {rr} in both: ours survives with "
                             "min(max(throughput), 0.95), Mitsuba with min(max(throughput) * eta^2, 0.95) "
                             "(eta: relative IOR accumulated through refractions), and Mitsuba rolls at "
                             "the last vertex too (noise only; the expected image is the same)")
        else:
            raise ValueError(f"integrator type {itype} is not converted")

        env = grey(scene.get("environment", 0))
        if nee and not mis:
            # Ours then takes no BSDF sample at the last vertex: light that only BSDF sampling
            # finds (the environment, emitters seen through a delta lobe) is missing there, where
            # Mitsuba, which samples the BSDF at every vertex, has it: a different image.
            if any(env):
                raise ValueError("an environment with NEE but without MIS is not converted (ours never "
                                 "light-samples it, and takes no BSDF sample at the last vertex)")
            if any(k == "dielectric" or (k == "conductor" and not rough) for k, rough in kinds):
                raise ValueError("delta and dielectric materials with NEE but without MIS are not converted "
                                 "(ours takes no BSDF sample at the last vertex)")
        if any(env):
            out["environment"] = {"type": "constant", "radiance": rgb(env)}
            notes.append("ours never light-samples the constant environment (it is added when a "
                         "BSDF-sampled ray escapes); Mitsuba samples it as one of its emitters "
                         "(the same expected image, other work)")
        for i, light in enumerate(scene.get("lights", [])):
            if light["type"] != "point":
                raise ValueError(f"light {i}: type {light['type']} is not converted")
            if not nee:
                raise ValueError(f"light {i}: point lights without NEE are not converted (they add "
                                 "nothing in ours; Mitsuba would light-sample them)")
            # Radiant intensity (W/sr), a delta: only light sampling reaches it, in both.
            out[f"light{i:02d}"] = {"type": "point", "position": [float(x) for x in light["position"]],
                                    "intensity": rgb(light["intensity"])}
        if ("conductor", True) in kinds or ("conductor", False) in kinds:
            notes.append("conductors: ours uses Schlick's Fresnel with F0 = albedo (F0 at normal "
                         "incidence, rising to 1 at grazing angles); Mitsuba's `roughconductor`/"
                         "`conductor` has no Schlick Fresnel, so it gets material \"none\" scaled by "
                         "specular_reflectance = albedo: F = F0 at every angle (a cosine-weighted "
                         "hemispherical average 0.002-0.04 lower for F0 in 0.15-0.95; darker at grazing "
                         "angles). GGX D and the separable Smith G are the same; Mitsuba samples "
                         "visible normals, ours D(m) cos(m) (noise only)")
        if ("dielectric", True) in kinds and nee:
            notes.append("rough dielectrics: ours treats them like delta lobes (no light sampling at "
                         "their vertices; emitters their BSDF samples hit count fully); Mitsuba's "
                         "`roughdielectric` is light-sampled with MIS (the same expected image, other work)")

        triangles = {}  # material -> [(p0, p1, p2)]: one Mitsuba mesh per material
        for i, s in enumerate(scene["shapes"]):
            bsdf, emission = materials[s["material"]]
            vel = [float(x) for x in s.get("velocity", [0, 0, 0])]
            if any(vel) and t_close > t_open:
                notes.append(f"shape {i} ({s['type']}) moves with velocity {vel} in ours but is static in "
                             f"Mitsuba at its t = {t_open:g} position (Mitsuba 3 has no animated shapes): "
                             "Mitsuba's scene has no motion blur")
            # Ours puts a shape at time t at its stated geometry + velocity * t; with open == close
            # every ray has t = open, so that is where Mitsuba's static shape goes (t = 0 here).
            shift = [v * t_open for v in vel]

            def moved(point):
                return [float(x) + d for x, d in zip(point, shift)]
            if s["type"] in ("quad", "rectangle"):
                c = moved(s["corner"])
                eu, ev = ([float(x) for x in s[k]] for k in ("edgeU", "edgeV"))
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
                shape = {"type": "sphere", "center": moved(s["center"]), "radius": float(s["radius"])}
            elif s["type"] == "triangle":
                triangles.setdefault(s["material"], []).append([moved(s[k]) for k in ("p0", "p1", "p2")])
                continue
            else:
                raise ValueError(f"shape {i}: type {s['type']} is not converted")
            shape["bsdf"] = bsdf
            if any(emission):
                # Mitsuba's area emitter emits on the front side only, like ours.
                shape["emitter"] = {"type": "area", "radiance": rgb(emission)}
            out[f"shape{i:02d}"] = shape
        for k, (name, tris) in enumerate(triangles.items()):
            out[f"triangles{k:02d}"] = self._triangle_mesh(f"triangles-{name}", tris, *materials[name])
        return out, notes

    def _triangle_mesh(self, name, tris, bsdf, emission):
        """Triangles as one Mitsuba mesh with face normals: Mitsuba's face normal is
        normalize(cross(p1 - p0, p2 - p0)), ours too (scenes/README.md), so front sides agree.
        An emitting mesh is one area light to Mitsuba (sampled by area) where ours has one light per
        triangle (chosen uniformly): the same expected image."""
        mi = self.mi
        props = mi.Properties()
        props["bsdf"] = mi.load_dict(bsdf)
        if any(emission):
            props["emitter"] = mi.load_dict({"type": "area", "radiance": {"type": "rgb", "value": emission}})
        props["face_normals"] = True
        mesh = mi.Mesh(name, 3 * len(tris), len(tris), props=props)
        params = mi.traverse(mesh)
        params["vertex_positions"] = mi.Float([x for t in tris for p in t for x in p])
        params["faces"] = mi.UInt32(list(range(3 * len(tris))))
        params.update()
        return mesh

    def load_scene(self, scene, sampler, spp):
        d, notes = self.convert(scene, sampler, spp)
        mscene = self.mi.load_dict(d)
        used = mscene.sensors()[0].sampler().sample_count()
        if used != spp:
            raise RuntimeError(f"Mitsuba's {sampler} renders {used} spp where {spp} were asked")
        return mscene, notes

    def render(self, mscene, spp, seed, label="render"):
        """(seconds, image) for one render at spp, waiting for the result."""
        dr, mi = self.dr, self.mi
        dr.kernel_history()
        start = time.perf_counter()
        image = mi.render(mscene, spp=spp, seed=seed)
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


def measure_rendering(args, mitsuba, tmp, name, spp):
    """One scene of (b): our GPU and CPU figures and Mitsuba's, interleaved per repeat."""
    scene_src = os.path.join(args.scenes, f"{name}.json")
    bench_dir = os.path.join(tmp, "bench-scenes")
    scene_path, scene = scaled_scene(scene_src, args.size, bench_dir)
    cpu_exe = cpu_render_command(args.binaries)
    pixels = scene["resolution"][0] * scene["resolution"][1]
    # The sample count each Mitsuba sampler renders at (see RENDER_SCENES).
    theirs_spp = {n: nearest_prime_square(spp) if n == "orthogonal" else spp for n in MITSUBA_RENDER_SAMPLERS}
    ours = {"gpu_oa": [], "gpu_rnd": [], "cpu_oa": [], "cpu_rnd": []}
    theirs = {n: [] for n in MITSUBA_RENDER_SAMPLERS}
    notes, our_exr, images = [], None, {}
    mscenes = {}
    if mitsuba:
        mark = len(mitsuba.cache_misses)  # the warm-up runs' misses are dropped below
        for n in MITSUBA_RENDER_SAMPLERS:
            mscenes[n], notes = mitsuba.load_scene(scene, n, theirs_spp[n])
            # Untimed warm-ups that compile the kernel. Two: the timed runs' kernel can differ from
            # the first render's (seen with `orthogonal`: every quick run's one timed render compiled).
            for seed in (0, 1 << 20):
                _, images[n] = mitsuba.render(mscenes[n], theirs_spp[n], seed=seed)
        del mitsuba.cache_misses[mark:]

    def run_ours():
        nonlocal our_exr
        oa, rnd = run_oas_render_bench(args.binaries, bench_dir, args.size, name, spp)
        ours["gpu_oa"].append(oa)
        ours["gpu_rnd"].append(rnd)
        if cpu_exe:
            m, our_exr = run_oas_render_cpu(cpu_exe, scene_path, "oa", spp, tmp)
            ours["cpu_oa"].append(m)
            ours["cpu_rnd"].append(run_oas_render_cpu(cpu_exe, scene_path, "random", spp, tmp)[0])

    def run_theirs(rep):
        for n in MITSUBA_RENDER_SAMPLERS:
            seconds, images[n] = mitsuba.render(mscenes[n], theirs_spp[n], seed=rep + 1, label=f"{name} {n}")
            theirs[n].append(pixels * theirs_spp[n] / seconds / 1e6)

    for rep in range(args.repeats):
        sides = [run_ours] + ([lambda: run_theirs(rep)] if mitsuba else [])
        for side in (sides if rep % 2 == 0 else sides[::-1]):
            side()
        log(f"  {name}: rendering repeat {rep + 1}/{args.repeats} done")

    check = None
    if mitsuba and our_exr:
        check = (mitsuba.image_means(mitsuba.read_exr(our_exr)), mitsuba.image_means(images["orthogonal"]))
    return {"name": name, "spp": spp, "theirs_spp": theirs_spp, "resolution": scene["resolution"],
            "integrator": scene.get("integrator", {}), "oa_choice": our_oa_choice(cpu_exe, scene_path, spp),
            "ours": ours, "theirs": theirs, "notes": notes, "have_cpu": cpu_exe is not None, "check": check}


def describe_integrator(integ):
    """Our integrator settings in words, for (b)'s headings."""
    if integ.get("type", "path") == "direct":
        return "direct lighting" + (", NEE + MIS" if integ.get("mis", True) else ", NEE without MIS")
    nee = integ.get("nextEventEstimation", True)
    words = [f"path tracing, maxDepth {integ.get('maxDepth', 5)}",
             ("NEE + MIS" if integ.get("mis", nee) else "NEE without MIS") if nee else "no NEE"]
    if integ.get("rouletteStartDepth", 0):
        words.append(f"Russian roulette from vertex {integ['rouletteStartDepth']}")
    return ", ".join(words)


def report_rendering(r, args, mitsuba):
    w, h = r["resolution"]
    spp, tspp = r["spp"], r["theirs_spp"]
    paths = w * h * spp
    log(f"\n== (b) rendering {r['name']} {w}x{h} x {spp} spp = {paths / 1e6:.2f} M paths, "
        f"{describe_integrator(r['integrator'])}; Mpaths/s (median of {args.repeats}) ==")
    log("ours GPU = oas-render-bench (lavapipe; pipeline build and one warm-up untimed); ours CPU = "
        + ("oas-render --device cpu (reference tracer, all cores)" if r["have_cpu"] else "not available"))
    if mitsuba:
        log("theirs = mi.render in one wavefront, warm (kernel cached), waiting for the image; "
            + ", ".join(f"{n} at {tspp[n]} spp" for n in MITSUBA_RENDER_SAMPLERS)
            + ("" if tspp["orthogonal"] == spp else
               f" (orthogonal needs a prime squared: {tspp['orthogonal']} is the nearest to {spp}; "
               f"its Mpaths/s counts the {w * h * tspp['orthogonal'] / 1e6:.2f} M paths it traced)"))
    oa = f"OA (ours oa = {r['oa_choice']})" if r["oa_choice"] else "OA (ours oa)"
    rows = [(oa, "gpu_oa", "cpu_oa", "orthogonal"), ("random", "gpu_rnd", "cpu_rnd", "independent")]
    width = max(24, len(oa))
    head = f"{'sampler':<{width}} {'ours GPU':>9} {'ours CPU':>9}"
    if mitsuba:
        head += f"  {'Mitsuba':<12} {'theirs':>8}  {'GPU/theirs':>10} {'CPU/theirs':>10}"
        log("ratios: median over repeats of ours/theirs within each interleaved pair")
    log(head)
    r_ours, r_theirs = r["ours"], r["theirs"]
    for label, kg, kc, tn in rows:
        gpu, cpu = median(r_ours[kg]), median(r_ours[kc])
        line = f"{label:<{width}} {fmt(gpu, 3):>9} {fmt(cpu, 3):>9}"
        if mitsuba:
            ths = r_theirs[tn]
            line += (f"  {tn:<12} {fmt(median(ths), 3):>8}  {fmt(paired_ratio(r_ours[kg], ths), 3):>10} "
                     f"{fmt(paired_ratio(r_ours[kc], ths), 3):>10}")
        log(line)
    for n in r["notes"]:
        log(f"note: {n}")
    if r["check"]:
        (o_mean, o_r, o_g), (t_mean, t_r, t_g) = r["check"]
        ratio = sum(o_mean) / sum(t_mean) if sum(t_mean) else float("nan")
        log("image check (ours CPU OA vs Mitsuba orthogonal, last renders): mean RGB "
            f"{' '.join(f'{v:.4f}' for v in o_mean)} vs {' '.join(f'{v:.4f}' for v in t_mean)} "
            f"(ours/theirs {ratio:.3f}); "
            f"red left/right {o_r[0]:.3f}/{o_r[1]:.3f} vs {t_r[0]:.3f}/{t_r[1]:.3f}; "
            f"green left/right {o_g[0]:.3f}/{o_g[1]:.3f} vs {t_g[0]:.3f}/{t_g[1]:.3f}")


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
        renders = []
        for name, spp in RENDER_SCENES:
            log(f"(b) rendering {name} at {args.size} px wide, {spp} spp")
            renders.append(measure_rendering(args, mitsuba, tmp, name, spp))
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"generation": {"ours": {p: {"gpu": v[0], "cpu": v[1]} for p, v in g_ours.items()},
                                      "theirs": {f"{n} {m}": v for (n, m), v in g_theirs.items()}},
                       "rendering": {r["name"]: {"spp": r["spp"], "resolution": r["resolution"],
                                                 "mitsuba_spp": r["theirs_spp"], "ours": r["ours"],
                                                 "theirs": r["theirs"], "notes": r["notes"]}
                                     for r in renders}}, f, indent=1)

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

    for r in renders:
        report_rendering(r, args, mitsuba)
    if mitsuba:
        # Warm-up runs are untimed, so a timed run should always find its kernel cached.
        misses = mitsuba.cache_misses
        log(f"\nMitsuba timed runs ((a) and (b)) whose kernel was not cached in memory: {len(misses)}"
            + (f" ({'; '.join(misses)}; medians absorb single outliers)" if misses else ""))


if __name__ == "__main__":
    main()
