#!/usr/bin/env python3
"""Structured mutation fuzzing of whole scene files through `oas-render SCENE --explain`.

Takes the scenes in scenes/ (and their meshes), applies one structured mutation per case (a
fraction of cases stack two or three), writes the result with any generated mesh files into a
fresh temporary directory and runs the renderer's own loader, semantic checks, dimension plan and
sampler choice on it. Python 3 standard library only; deterministic for a given --seed.

A case fails (a finding) when
  - the process dies from a signal, or exits with anything but 0 (loaded) or 2 (refused);
  - it runs longer than --timeout seconds (default 5);
  - exit 2 comes without a message that starts with "oas-render: error:" and names the scene file;
  - exit 0 comes without the --explain report on stdout;
  - anything is written (the scene's directory and the working directory are compared before and
    after);
  - the mutation makes the scene invalid by the rules of scenes/README.md (a truncated file, a
    NaN token, a wrong type, a duplicate key, JSON nested deeper than 64, a zero-area shape, a
    missing or broken mesh...) and the renderer accepts it (exit 0), or the mutation keeps the
    scene valid (the unmodified scenes, a consistent material rename, a large valid mesh) and
    the renderer refuses it.
Mutations whose validity depends on details (a random byte flip, a huge but finite number in
some field, garbage bytes as a mesh) only get the first five checks.

Failing inputs are saved under --failures (default build-fuzz/mutate-failures), one directory per
case with the scene, its generated meshes, and report.txt (command, exit status, stderr, reason).
Reproduce one case with --only N (same --seed and --cases). Prints "N passed, M failed"; exits 1
when any case failed, 2 on usage errors.
"""

import argparse
import copy
import json
import os
import random
import resource
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
FLT_MAX = 3.4028234663852886e38
MAX_JSON_DEPTH = 64

# ----------------------------------------------------------------------------------------------
# A JSON tree that keeps duplicate keys and can hold raw text (tokens JSON does not have, deep
# nesting, invalid bytes). Objects are Obj (a list of [key, value] pairs).


class Pair(list):
    """[key, value] of an object member (so members and array elements can be told apart)."""


class Obj(list):
    def __init__(self, pairs=()):
        super().__init__(Pair(p) for p in pairs)

    def add(self, key, value, at=None):
        self.insert(len(self) if at is None else at, Pair([key, value]))

    def get(self, key, default=None):
        for k, v in self:
            if k == key:
                return v
        return default

    def set(self, key, value):
        for pair in self:
            if pair[0] == key:
                pair[1] = value
                return
        self.append(Pair([key, value]))

    def remove(self, key):
        self[:] = [p for p in self if p[0] != key]


class Raw:
    """Text (bytes) written into the file as is."""

    def __init__(self, data):
        self.data = data if isinstance(data, bytes) else data.encode("utf-8", "surrogatepass")


def load_tree(text):
    return json.loads(text, object_pairs_hook=Obj)


def dump(node, out):
    if isinstance(node, Raw):
        out.append(node.data)
    elif isinstance(node, Obj):
        out.append(b"{")
        for i, (k, v) in enumerate(node):
            if i:
                out.append(b", ")
            dump(k, out)
            out.append(b": ")
            dump(v, out)
        out.append(b"}")
    elif isinstance(node, list):
        out.append(b"[")
        for i, v in enumerate(node):
            if i:
                out.append(b", ")
            dump(v, out)
        out.append(b"]")
    elif isinstance(node, str):
        out.append(json.dumps(node).encode("ascii"))
    elif node is True:
        out.append(b"true")
    elif node is False:
        out.append(b"false")
    elif node is None:
        out.append(b"null")
    elif isinstance(node, int):
        out.append(str(node).encode())
    elif isinstance(node, float):
        out.append(repr(node).encode())
    else:
        raise TypeError(type(node))


def to_bytes(tree):
    out = []
    dump(tree, out)
    return b"".join(out) + b"\n"


def locations(node, path=""):
    """Every (container, key-or-index, path, field) below node; field is the nearest object key."""
    found = []

    def walk(n, p, field):
        if isinstance(n, Obj):
            for pair in n:
                q = f"{p}.{pair[0]}" if p else str(pair[0])
                found.append((pair, 1, q, pair[0]))
                walk(pair[1], q, pair[0])
        elif isinstance(n, list):
            for i, v in enumerate(n):
                q = f"{p}[{i}]"
                found.append((n, i, q, field))
                walk(v, q, field)

    walk(node, path, None)
    return found


def get_at(loc):
    container, key, _, _ = loc
    return container[key]


def set_at(loc, value):
    container, key, _, _ = loc
    container[key] = value


# What JSON kinds each field accepts (scenes/README.md): number, string, bool, array, object.
FIELD_KINDS = {}
for f in ("fovY", "apertureRadius", "focusDistance", "open", "close", "roughness", "ior", "radius", "outerAngle",
          "innerAngle", "version", "maxDepth", "rouletteStartDepth", "spp", "strength", "seed"):
    FIELD_KINDS[f] = {"number"}
for f in ("name", "comment", "type", "material", "file", "offset"):
    FIELD_KINDS[f] = {"string"}
for f in ("nextEventEstimation", "mis"):
    FIELD_KINDS[f] = {"bool"}
for f in ("resolution", "position", "lookAt", "up", "center", "corner", "edgeU", "edgeV", "p0", "p1", "p2",
          "velocity", "translate", "direction", "materials", "shapes", "lights"):
    FIELD_KINDS[f] = {"array"}
for f in ("albedo", "emission", "environment", "intensity", "scale"):
    FIELD_KINDS[f] = {"number", "array"}
for f in ("camera", "shutter", "integrator", "sampler"):
    FIELD_KINDS[f] = {"object"}
# Elements of arrays: what an element of each array field must be.
ELEMENT_KINDS = {"materials": {"object"}, "shapes": {"object"}, "lights": {"object"}}
for f in ("resolution", "position", "lookAt", "up", "center", "corner", "edgeU", "edgeV", "p0", "p1", "p2",
          "velocity", "translate", "direction", "albedo", "emission", "environment", "intensity", "scale"):
    ELEMENT_KINDS[f] = {"number"}


def kind(v):
    if isinstance(v, bool):
        return "bool"
    if isinstance(v, (int, float)):
        return "number"
    if isinstance(v, str):
        return "string"
    if isinstance(v, Obj):
        return "object"
    if isinstance(v, list):
        return "array"
    if v is None:
        return "null"
    return "raw"


def accepted_kinds(loc):
    container, _, _, field = loc
    return FIELD_KINDS.get(field) if isinstance(container, Pair) else ELEMENT_KINDS.get(field)


# ----------------------------------------------------------------------------------------------
# Cases.


class Case:
    def __init__(self, index, rng, base_name, base_text, workdir):
        self.index = index
        self.rng = rng
        self.base_name = base_name
        self.tree = load_tree(base_text)
        self.text = None            # bytes, when a mutation works on the text
        self.workdir = workdir      # the scene's directory (meshes are written here)
        self.file_name = base_name  # the scene file's name
        self.labels = []
        self.invalid_why = []       # changes that make the scene invalid (scenes/README.md)
        self.valid_why = []         # changes that keep a valid scene valid
        self.certain = True         # False once a change has an unknown effect on validity

    def want(self, expect, why=""):
        """Records what a change does: "reject" (makes the scene invalid), "accept" (keeps it
        valid) or None (unknown: the scene may or may not be valid afterwards)."""
        if expect == "reject":
            self.invalid_why.append(why)
        elif expect == "accept":
            self.valid_why.append(why)
        else:
            self.certain = False

    def scramble(self):
        """A change to the bytes that may undo earlier ones (byte flips): nothing is known."""
        self.invalid_why.clear()
        self.certain = False

    @property
    def expect(self):
        if self.invalid_why:
            return "reject"
        return "accept" if self.certain and self.valid_why else None

    @property
    def why(self):
        return "; ".join(self.invalid_why if self.invalid_why else self.valid_why if self.expect else [])

    def write_mesh(self, name, data):
        path = self.workdir / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(data if isinstance(data, bytes) else data.encode("utf-8", "surrogatepass"))
        return name

    def material_names(self):
        mats = self.tree.get("materials") if isinstance(self.tree, Obj) else None
        return [m.get("name") for m in mats if isinstance(m, Obj)] if isinstance(mats, list) else []

    def shapes(self):
        s = self.tree.get("shapes") if isinstance(self.tree, Obj) else None
        return s if isinstance(s, list) else None

    def any_material(self):
        names = [n for n in self.material_names() if isinstance(n, str)]
        return self.rng.choice(names) if names else "nope"


def mut_truncate(c):
    data = c.text if c.text is not None else to_bytes(c.tree)
    end = len(data.rstrip())
    cut = c.rng.randrange(0, end)
    c.text = data[:cut]
    c.labels.append(f"truncate@{cut}/{len(data)}")
    c.want("reject", f"truncated at byte {cut} of {len(data)}")


def mut_deep_nest(c):
    depth = c.rng.choice([65, 66, 100, 1000, 10000, 65000, 65536, 100000, c.rng.randrange(65, 100001)])
    style = c.rng.choice(["array", "object", "mixed"])
    if style == "array":
        raw = "[" * depth + "1" + "]" * depth
    elif style == "object":
        raw = '{"a": ' * depth + "1" + "}" * depth
    else:
        opens = []
        for i in range(depth):
            opens.append("[" if i % 2 else '{"k": ')
        raw = "".join(opens) + "0" + "".join("]" if i % 2 else "}" for i in reversed(range(depth)))
    locs = locations(c.tree)
    if not locs or c.rng.random() < 0.15:
        c.tree = Raw(raw)
        where = "(root)"
    else:
        loc = c.rng.choice(locs)
        set_at(loc, Raw(raw))
        where = loc[2]
    c.labels.append(f"deep-nest:{style}x{depth}@{where}")
    c.want("reject", f"{style} nesting {depth} levels deep at {where} (limit {MAX_JSON_DEPTH})")


WRONG_VALUES = {
    "number": [0, 1, -1, 2.5, 1e30],
    "string": ["", "1.0", "x", "sphere", "\u0000"],
    "bool": [True, False],
    "null": [None],
    "array": [[], [1], [1, 2], [1, 2, 3], [1, 2, 3, 4], ["1", "2", "3"], [[1, 2, 3]], [None, None, None]],
    "object": [Obj(), Obj([["x", 1]])],
}


def mut_wrong_type(c):
    locs = [l for l in locations(c.tree) if accepted_kinds(l)]
    if not locs:
        return mut_truncate(c)
    loc = c.rng.choice(locs)
    ok = accepted_kinds(loc)
    wrong_kind = c.rng.choice([k for k in WRONG_VALUES if k not in ok])
    value = copy.deepcopy(c.rng.choice(WRONG_VALUES[wrong_kind]))
    set_at(loc, value)
    c.labels.append(f"wrong-type:{loc[2]}={wrong_kind}")
    c.want("reject", f"{loc[2]} set to {wrong_kind} {json.dumps(value, default=str)[:40]}; valid {sorted(ok)}")


HUGE = ["1e308", "-1e308", "1e39", "-1e39", "3.4028236e38", "-3.4028236e38", "3.4028234e38", "-3.4028234e38",
        "-0", "-0.0", "0e0", "1e-45", "-1e-45", "4.9e-324", "2.2250738585072014e-308", "1e-38", "1.17549435e-38",
        "4294967295", "4294967296", "18446744073709551615", "18446744073709551616", "-9223372036854775809",
        "123456789012345678901234567890", "1e19", "16777216", "16777217", "16385", "1e999", "-1e999",
        "0.1e-999999", "1" + "0" * 400, "0." + "0" * 400 + "1"]


def numeric_value(token):
    try:
        return float(token)
    except (ValueError, OverflowError):
        return float("inf")


def mut_huge_number(c):
    locs = [l for l in locations(c.tree) if kind(get_at(l)) == "number"]
    if not locs:
        return mut_truncate(c)
    loc = c.rng.choice(locs)
    token = c.rng.choice(HUGE)
    set_at(loc, Raw(token))
    c.labels.append(f"number:{loc[2]}={token[:24]}")
    if abs(numeric_value(token)) > FLT_MAX:
        c.want("reject", f"{loc[2]} = {token[:40]} is beyond the 32-bit float range")
    else:
        c.want(None)


def mut_nan_inf(c):
    locs = [l for l in locations(c.tree) if kind(get_at(l)) == "number"] or locations(c.tree)
    if not locs:
        return mut_truncate(c)
    loc = c.rng.choice(locs)
    token = c.rng.choice(["NaN", "nan", "-NaN", "Infinity", "-Infinity", "inf", "-inf", "+1", ".5", "1.", "01",
                          "0x10", "1e", "--1", "1_000", "\u221e"])
    set_at(loc, Raw(token))
    c.labels.append(f"token:{loc[2]}={token}")
    c.want("reject", f"{loc[2]} = {token} is not a JSON number")


def objects(tree):
    out = [tree] if isinstance(tree, Obj) else []
    for loc in locations(tree):
        v = get_at(loc)
        if isinstance(v, Obj):
            out.append(v)
    return out


def mut_duplicate_key(c):
    objs = [o for o in objects(c.tree) if len(o)]
    if not objs:
        return mut_truncate(c)
    o = c.rng.choice(objs)
    k, v = c.rng.choice(list(o))
    o.add(k, copy.deepcopy(v) if c.rng.random() < 0.5 else c.rng.choice([0, "x", None, [1, 2, 3]]),
          c.rng.randrange(len(o) + 1))
    c.labels.append(f"duplicate-key:{k}")
    c.want("reject", f"duplicate key \"{k}\"")


NAMES_OK = ["a\u0000b", "\u00fc\u00df", "\U0001F600", "\u202eevil", " ", "\t", "x" * 100000, "na\"me", "back\\slash",
            "../../etc/passwd", "\u0000", "\ufeff", "\uffff"]
NAMES_BAD = [(Raw(b'"\\ud800"'), "a lone high surrogate \\ud800"), (Raw(b'"\\udc00x"'), "a lone low surrogate"),
             (Raw(b'"\xff\xfe"'), "invalid UTF-8 bytes"), (Raw(b'"\xc3"'), "a truncated UTF-8 sequence"),
             (Raw(b'"a\x01b"'), "a raw control character in a string"), (Raw(b'"a\nb"'), "a raw newline in a string"),
             (Raw(b'"\\x41"'), "an invalid escape \\x")]


def mut_names(c):
    names = [n for n in c.material_names() if isinstance(n, str)]
    if c.rng.random() < 0.4 or not names:
        target = c.tree if isinstance(c.tree, Obj) else None
        if target is None:
            return mut_truncate(c)
        if c.rng.random() < 0.5:
            value, why = c.rng.choice(NAMES_BAD)
            target.set("name", value)
            c.labels.append(f"scene-name:bad:{why}")
            c.want("reject", f"scene name with {why}")
        else:
            value = c.rng.choice(NAMES_OK)
            target.set("name", value)
            c.labels.append(f"scene-name:{value[:12]!r}")
            c.want("accept", "a scene name is any string")
        return
    old = c.rng.choice(names)
    bad = c.rng.random() < 0.4
    if bad:
        new, why = c.rng.choice(NAMES_BAD)
    else:
        new = c.rng.choice(NAMES_OK)
        if new in names:
            new = new + "#"
    for loc in locations(c.tree):
        if loc[3] in ("name", "material") and get_at(loc) == old and isinstance(loc[0], Pair):
            set_at(loc, new)
    if bad:
        c.labels.append(f"material-name:bad:{why}")
        c.want("reject", f"material name with {why}")
    else:
        c.labels.append(f"material-rename:{new[:12]!r}")
        c.want("accept", f"material {old!r} renamed consistently to {new[:20]!r}")


def add_shape(c, shape):
    shapes = c.shapes()
    if shapes is None:
        return False
    shapes.insert(c.rng.randrange(len(shapes) + 1), (shape))
    return True


def mut_degenerate(c):
    r = c.rng
    m = c.any_material()
    mats = c.tree.get("materials") if isinstance(c.tree, Obj) else None
    emit = [mat.get("name") for mat in mats if isinstance(mat, Obj) and mat.get("emission")] if isinstance(mats, list) else []
    if emit and r.random() < 0.5:
        m = r.choice(emit)
    s = r.uniform(0.01, 100.0)
    u = [r.uniform(-1, 1) * s for _ in range(3)]
    k = r.choice([0.0, 1.0, -1.0, 2.0, 1e-3, 1e3, 0.1])
    choice = r.randrange(9)
    if choice == 0:
        shape = Obj([["type", "quad"], ["material", m], ["corner", [0, 1, 0]], ["edgeU", [0, 0, 0]], ["edgeV", u]])
        why = "quad with a zero edgeU"
    elif choice == 1:
        shape = Obj([["type", r.choice(["quad", "rectangle"])], ["material", m], ["corner", [1, 2, 3]], ["edgeU", u],
                     ["edgeV", [x * k for x in u]]])
        why = f"quad with parallel edges (edgeV = {k} edgeU)"
    elif choice == 2:
        shape = Obj([["type", "triangle"], ["material", m], ["p0", [0, 0, 0]], ["p1", u], ["p2", [x * k for x in u]]])
        why = f"collinear triangle (p2 = {k} p1)"
    elif choice == 3:
        shape = Obj([["type", "triangle"], ["material", m], ["p0", u], ["p1", u], ["p2", u]])
        why = "triangle with three equal points"
    elif choice == 4:
        radius = r.choice([0, -0.0, -1, -1e-30, Raw("-0"), Raw("0e0")])
        shape = Obj([["type", "sphere"], ["material", m], ["center", [0, 0, 0]], ["radius", radius]])
        why = f"sphere of radius {radius.data.decode() if isinstance(radius, Raw) else radius}"
    elif choice == 5:
        p = [r.choice([1e-3, 1.0, 1e6]) * i for i in (1, 2, 3)]
        shape = Obj([["type", "triangle"], ["material", m], ["p0", [0, 0, 0]], ["p1", [p[0], 0, 0]], ["p2", [p[1], 0, 0]]])
        why = "triangle with its points on the x axis"
    elif choice == 6:
        shape = Obj([["type", "quad"], ["material", m], ["corner", [0, 0, 0]], ["edgeU", [0, 0, 0]], ["edgeV", [0, 0, 0]]])
        why = "quad with zero edges"
    elif choice == 7:
        name = c.write_mesh("meshes/collinear.obj", "v 0 0 0\nv 1 1 1\nv 2 2 2\nv 3 3 3\nf 1 2 3\nf 1 2 3 4\n")
        shape = Obj([["type", "mesh"], ["material", m], ["file", name]])
        why = "mesh whose triangles are all collinear"
    else:
        name = c.write_mesh("meshes/flat.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
        shape = Obj([["type", "mesh"], ["material", m], ["file", name], ["scale", [1, 1, r.choice([0, Raw("-0")])]]])
        why = "mesh scaled by a zero factor"
    if not add_shape(c, shape):
        return mut_truncate(c)
    c.labels.append(f"degenerate:{why}")
    c.want("reject", why)


def gen_huge_mesh(r, triangles):
    n = int(triangles ** 0.5) + 1
    lines = ["# generated grid"]
    for i in range(n + 1):
        for j in range(n + 1):
            lines.append(f"v {i / n:.6f} {r.random() * 0.01:.6f} {j / n:.6f}")
    count = 0
    for i in range(n):
        for j in range(n):
            a = i * (n + 1) + j + 1
            lines.append(f"f {a} {a + 1} {a + n + 2} {a + n + 1}")
            count += 2
            if count >= triangles:
                break
        if count >= triangles:
            break
    return "\n".join(lines) + "\n"


def mut_mesh(c):
    r = c.rng
    m = c.any_material()
    variants = [
        ("missing", "reject"), ("directory", "reject"), ("empty", "reject"), ("vertices-only", "reject"),
        ("index-out-of-range", "reject"), ("index-zero", "reject"), ("nan-vertex", "reject"),
        ("overflow-vertex", "reject"), ("too-few-corners", "reject"), ("bad-corner", "reject"),
        ("overflow-scale", "reject"), ("garbage-bytes", None), ("garbage-tokens", None), ("long-line", None),
        ("continuations", "accept"), ("huge-valid", "accept"), ("absolute-path", "accept"),
        ("crlf-valid", "accept"), ("dev-null", "reject"), ("dev-zero", "reject"),
    ]
    variant, expect = r.choice(variants)
    if expect == "accept" and m not in c.material_names():
        expect = None
    file = f"meshes/fuzz_{variant}.obj"
    shape = Obj([["type", "mesh"], ["material", m], ["file", file]])
    valid_tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"
    if variant == "missing":
        file = r.choice(["meshes/nope.obj", "", "nope/../../nope.obj", "/nonexistent/x.obj", "meshes/"])
        shape.set("file", file)
        if file == "meshes/":
            variant = "directory"
    elif variant == "directory":
        (c.workdir / "meshes" / "adir.obj").mkdir(parents=True, exist_ok=True)
        shape.set("file", "meshes/adir.obj")
    elif variant == "empty":
        c.write_mesh(file, "")
    elif variant == "vertices-only":
        c.write_mesh(file, "v 0 0 0\nv 1 0 0\nv 0 1 0\n" * r.randrange(1, 100))
    elif variant == "index-out-of-range":
        c.write_mesh(file, f"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 {r.choice([4, -4, 4294967297, -9223372036854775808, 10**30])}\n")
    elif variant == "index-zero":
        c.write_mesh(file, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n")
    elif variant == "nan-vertex":
        c.write_mesh(file, f"v 0 0 0\nv {r.choice(['nan', 'inf', '-inf', 'NaN', 'infinity'])} 0 0\nv 0 1 0\nf 1 2 3\n")
    elif variant == "overflow-vertex":
        c.write_mesh(file, f"v 0 0 0\nv {r.choice(['1e39', '-3.5e38', '1e999'])} 0 0\nv 0 1 0\nf 1 2 3\n")
    elif variant == "too-few-corners":
        c.write_mesh(file, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n")
    elif variant == "bad-corner":
        corner = r.choice(["1/2/3/4", "1/x", "a", "1//", "//1", "1/1/1", "1/-5", "1.5", "+", "1 /2"])
        c.write_mesh(file, f"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf {corner} 2 3\n")  # "1 /2": corner "/2"
    elif variant == "overflow-scale":
        c.write_mesh(file, valid_tri)
        shape.set("scale", r.choice([1e38, [1, 3e38, 1]]))
        shape.set("translate", [3e38, 3e38, 3e38])
    elif variant == "garbage-bytes":
        c.write_mesh(file, bytes(r.randrange(256) for _ in range(r.randrange(1, 20000))))
    elif variant == "garbage-tokens":
        toks = ["v", "f", "vt", "vn", "1", "-1", "0", "/", "//", "\\\n", "#", "\n", "1e38", "nan", " ", "\t", "o", "g"]
        c.write_mesh(file, "".join(r.choice(toks) + r.choice([" ", "", "\n"]) for _ in range(r.randrange(1, 5000))))
    elif variant == "long-line":
        c.write_mesh(file, valid_tri + "v " + " ".join(["1"] * r.randrange(3, 500000)) + "\n"
                     + "f " + " ".join(["1", "2", "3"] * r.randrange(1, 100000)) + "\n")
    elif variant == "continuations":
        c.write_mesh(file, "v 0 \\\n 0 \\\n 0\nv 1 0 0\nv 0 1 0\nf 1 \\\n2 \\\r\n3\n" + "\\\n" * r.randrange(1, 100000)
                     + "# end\n")
    elif variant == "huge-valid":
        tris = r.choice([10000, 50000, 100000, 200000])
        c.write_mesh(file, gen_huge_mesh(r, tris))
        variant = f"huge-valid:{tris}"
    elif variant == "absolute-path":
        c.write_mesh(file, valid_tri)
        shape.set("file", str((c.workdir / file).resolve()))
    elif variant == "crlf-valid":
        c.write_mesh(file, valid_tri.replace("\n", "\r\n"))
    elif variant == "dev-null":
        shape.set("file", "/dev/null")
    elif variant == "dev-zero":
        shape.set("file", "/dev/zero")
    if variant in ("missing", "directory") and c.rng.random() < 0.3:
        shape.set("file", 7)  # also a wrong type
    replace = [i for i, s in enumerate(c.shapes() or []) if isinstance(s, Obj) and s.get("type") == "mesh"]
    if replace and r.random() < 0.5:
        c.shapes()[r.choice(replace)] = (shape)
    elif not add_shape(c, shape):
        return mut_truncate(c)
    c.labels.append(f"mesh:{variant}")
    c.want(expect, f"mesh file: {variant}")


def mut_structure(c):
    r = c.rng
    t = c.tree
    choice = r.randrange(12)
    if not isinstance(t, Obj):
        return mut_truncate(c)
    if choice == 0:
        key = r.choice(["resolution", "camera", "materials", "shapes"])
        t.remove(key)
        why = f"required key {key} removed"
    elif choice == 1:
        objs = objects(t)
        o = r.choice(objs)
        key = r.choice(["raduis", "colour", "x", "", "Type", "comment ", "\u0000"])
        o.add(key, 1)
        why = f"unknown key {key!r}"
    elif choice == 2:
        t.set("shapes", [])
        why = "empty shapes"
    elif choice == 3:
        t.set("materials", [])
        why = "no materials (shapes refer to undefined ones)"
    elif choice == 4:
        c.tree = r.choice([[], 0, "scene", None, True, Obj()])
        why = f"root is {kind(c.tree)}"
    elif choice == 5:
        c.text = r.choice([b"", b" ", b"\n", b"\x00", b"\xef\xbb\xbf", b"{", b"}", b"[]", b"\"\""])
        why = f"file is {c.text!r}"
    elif choice == 6:
        c.text = to_bytes(t) + r.choice([b"x", b"{}", b"\x00", b",", b"]"])
        why = "trailing garbage after the JSON value"
    elif choice == 7:
        data = to_bytes(t)
        c.text = b"/* comment */" + data if r.random() < 0.5 else data.rstrip()[:-1] + b", }"
        why = "a comment or a trailing comma (strict JSON)"
    elif choice == 8:
        cam = t.get("camera")
        if not isinstance(cam, Obj):
            return mut_truncate(c)
        sub = r.randrange(4)
        if sub == 0:
            cam.set("lookAt", cam.get("position"))
            why = "camera lookAt equals position"
        elif sub == 1:
            p, l = cam.get("position"), cam.get("lookAt")
            cam.set("up", [l[i] - p[i] for i in range(3)] if isinstance(p, list) and isinstance(l, list) else [0, 0, 0])
            why = "camera up parallel to the view direction"
        elif sub == 2:
            cam.set("fovY", r.choice([0, 180, -1, 180.0001, 360]))
            why = "fovY out of (0, 180)"
        else:
            cam.set("type", "pinhole")
            cam.set("apertureRadius", r.choice([0.1, 1e-30, 5]))
            why = "pinhole camera with an aperture"
    elif choice == 9:
        sampler = t.get("sampler") if isinstance(t.get("sampler"), Obj) else Obj([["name", "oa"]])
        sampler = (Obj(list(sampler)))
        t.set("sampler", sampler)
        sub = r.randrange(5)
        if sub == 0:
            sampler.set("spp", r.choice([0, 16777217, -1, 2.5]))
            why = "spp out of range"
        elif sub == 1:
            sampler.set("name", r.choice(["OA", "sobolx", "", "oa "]))
            why = "unknown sampler"
        elif sub == 2:
            sampler.set("name", "random")
            sampler.set("spp", 16)
            sampler.set("offset", "cmj")
            why = "offset for a non-OA sampler"
        elif sub == 3:
            sampler.set("spp", 16)
            sampler.set("strength", 1)
            why = "strength 1"
        else:
            sampler.set("seed", r.choice([4294967296, -1]))
            why = "seed out of range"
    elif choice == 10:
        integ = (Obj([["type", "path"], ["maxDepth", 5]]))
        t.set("integrator", integ)
        sub = r.randrange(4)
        if sub == 0:
            integ.set("maxDepth", r.choice([0, 257, 1e9]))
            why = "maxDepth out of range"
        elif sub == 1:
            integ.set("nextEventEstimation", False)
            integ.set("mis", True)
            why = "MIS without NEE"
        elif sub == 2:
            integ.set("rouletteStartDepth", 6)
            why = "rouletteStartDepth beyond maxDepth"
        else:
            integ.set("type", "direct")
            why = "maxDepth 5 on a direct integrator"
    else:
        t.set("resolution", r.choice([[0, 16], [16, 16385], [-1, 1], [16, 16, 16], [1.5, 2]]))
        why = "resolution out of range"
    c.labels.append(f"structure:{why}")
    c.want("reject", why)


def mut_extremes(c):
    """Valid-looking but extreme values where the scene stays within the documented ranges."""
    r = c.rng
    t = c.tree
    if not isinstance(t, Obj):
        return mut_truncate(c)
    sub = r.randrange(8)
    if sub == 0:
        sampler = t.get("sampler") if isinstance(t.get("sampler"), Obj) else (Obj([["name", "oa"]]))
        t.set("sampler", sampler)
        sampler.set("spp", r.choice([16777216, 16777215, 1, 2, 4096 * 4096, 65536, 999983]))
        why = "extreme spp"
    elif sub == 1:
        t.set("resolution", r.choice([[16384, 16384], [1, 16384], [1, 1]]))
        why = "extreme resolution"
    elif sub == 2:
        integ = t.get("integrator") if isinstance(t.get("integrator"), Obj) else None
        if integ is None or integ.get("type") != "path":
            integ = (Obj([["type", "path"]]))
            t.set("integrator", integ)
        integ.set("maxDepth", 256)
        integ.set("rouletteStartDepth", r.choice([0, 1, 256]))
        why = "maxDepth 256"
    elif sub == 3:
        cam = t.get("camera")
        if isinstance(cam, Obj):
            big = r.choice([3.4e38, 1.7e38, 1e38, 1e30])
            cam.set("position", [-big, 0, 0])
            cam.set("lookAt", [big, 0, 0])
            cam.set("up", [0, 1, 0])
            cam.remove("focusDistance")
        why = "camera spanning the float range"
    elif sub == 4:
        t.set("shutter", (Obj([["open", -3e38], ["close", 3e38]])))
        for s in c.shapes() or []:
            if isinstance(s, Obj) and s.get("type") != "mesh":
                s.set("velocity", [r.choice([1e38, -1e38, 3e38]), 0, 0])
        why = "huge shutter interval and velocities"
    elif sub == 5:
        lights = t.get("lights") if isinstance(t.get("lights"), list) else []
        t.set("lights", lights)
        lights.append((Obj([["type", "spot"], ["position", [0, 1, 0]], ["intensity", 3e38],
                                     ["direction", r.choice([[3e38, 3e38, 3e38], [1e-30, 0, 0], [1e-45, 1e-45, 0]])],
                                     ["outerAngle", r.choice([1e-30, 180, 1e-45])]])))
        why = "spot light with extreme direction and angle"
    elif sub == 6:
        add_shape(c, Obj([["type", "sphere"], ["material", c.any_material()], ["center", [3e38, -3e38, 3e38]],
                          ["radius", r.choice([5e18, 1e-38, 1e-45, 3e38])]]))
        why = "sphere at the edge of the float range"
    else:
        mats = t.get("materials")
        if isinstance(mats, list):
            for mat in mats:
                if isinstance(mat, Obj):
                    mat.set("emission", r.choice([3.4e38, [0, 0, 3.4e38], 1e-45]))
        why = "huge emission everywhere"
    c.labels.append(f"extreme:{why}")
    c.want(None)


def mut_byte_flip(c):
    data = bytearray(c.text if c.text is not None else to_bytes(c.tree))
    n = c.rng.choice([1, 1, 2, 4, 16])
    for _ in range(n):
        if not data:
            break
        i = c.rng.randrange(len(data))
        op = c.rng.randrange(4)
        if op == 0:
            data[i] = c.rng.randrange(256)
        elif op == 1:
            del data[i]
        elif op == 2:
            data.insert(i, c.rng.choice(b'{}[]",:0123456789-+.eE \\u\x00'))
        else:
            j = c.rng.randrange(len(data))
            data[i:i] = data[j:j + c.rng.randrange(1, 64)]
    c.text = bytes(data)
    c.labels.append(f"byte-flip:{n}")
    c.scramble()


def mut_file_name(c):
    c.file_name = c.rng.choice(["sc\u00e8ne with spaces.json", "\U0001F600.json", "-dash.json", "a'b\"c.json",
                                "noext", "x" * 200 + ".json", ".hidden.json", "new\nline.json", "back\\slash.json"])
    c.labels.append(f"file-name:{c.file_name[:16]!r}")


MUTATIONS = [
    (mut_truncate, 10), (mut_deep_nest, 8), (mut_wrong_type, 14), (mut_huge_number, 12), (mut_nan_inf, 5),
    (mut_duplicate_key, 6), (mut_names, 7), (mut_degenerate, 10), (mut_mesh, 14), (mut_structure, 10),
    (mut_extremes, 8), (mut_byte_flip, 6), (mut_file_name, 3),
]


# ----------------------------------------------------------------------------------------------
# Running.


def snapshot(*dirs):
    state = {}
    for d in dirs:
        for root, subdirs, files in os.walk(d):
            for name in subdirs + files:
                p = os.path.join(root, name)
                try:
                    st = os.lstat(p)
                except OSError:
                    continue
                state[p] = (st.st_size, st.st_mtime_ns, st.st_mode)
    return state


def limit_child():
    os.setsid()
    # 4 GiB of address space: a runaway allocation fails fast instead of taking the machine.
    resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30))
    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))


def first_line(err):
    return err.decode("utf-8", "replace").splitlines()[0] if err.strip() else ""


def run_case(binary, c, timeout):
    scene_dir = c.workdir
    cwd = scene_dir.parent / "cwd"
    cwd.mkdir()
    scene_path = scene_dir / c.file_name
    data = c.text if c.text is not None else to_bytes(c.tree)
    scene_path.write_bytes(data)
    before = snapshot(scene_dir, cwd)
    # The path as the user types it: relative to the working directory, so messages must name it.
    arg = os.path.relpath(scene_path, cwd)
    cmd = [str(binary), arg, "--explain"]
    start = time.monotonic()
    proc = subprocess.Popen(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, preexec_fn=limit_child)
    timed_out = False
    try:
        out, err = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        timed_out = True
        os.killpg(proc.pid, signal.SIGKILL)
        out, err = proc.communicate()
    seconds = time.monotonic() - start
    after = snapshot(scene_dir, cwd)
    rc = proc.returncode
    problems = []
    if timed_out:
        problems.append(("timeout", f"timeout: still running after {timeout:g} s"))
    elif rc < 0:
        problems.append(("signal", f"killed by signal {signal.Signals(-rc).name}"))
    elif rc not in (0, 2):
        problems.append(("exit-status", f"exit status {rc} (valid 0 or 2): {first_line(err)[:200]!r}"))
    if not timed_out and rc == 2:
        first = first_line(err)
        if not err.startswith(b"oas-render: error:"):
            problems.append(("message-prefix", f"exit 2 but stderr does not start with 'oas-render: error:': {first[:200]!r}"))
        elif os.fsencode(arg) not in err:
            problems.append(("message-names-file",
                             f"exit 2 but the message does not name the scene file {arg!r}: {first[:200]!r}"))
    if not timed_out and rc == 0 and b"dimension plan:" not in out:
        problems.append(("no-report", "exit 0 without the --explain report on stdout"))
    if before != after:
        changed = sorted(set(after) ^ set(before) | {p for p in after if p in before and after[p] != before[p]})
        problems.append(("wrote-files", "wrote files: " + ", ".join(os.path.relpath(p, scene_dir.parent) for p in changed[:5])))
    if not timed_out and rc in (0, 2):
        if c.expect == "reject" and rc == 0:
            problems.append(("accepted-invalid", f"accepted an invalid scene ({c.why})"))
        if c.expect == "accept" and rc == 2:
            problems.append(("refused-valid", f"refused a valid scene ({c.why}): {first_line(err)[:300]!r}"))
    return cmd, rc, timed_out, seconds, out, err, problems


def save_failure(failures, c, cmd, rc, timed_out, seconds, out, err, problems, seed, cases):
    dest = failures / f"case{c.index:05d}"
    if dest.exists():
        shutil.rmtree(dest)
    shutil.copytree(c.workdir, dest / "scene", symlinks=True, ignore_dangling_symlinks=True)
    report = [
        f"case {c.index} (--seed {seed} --cases {cases} --only {c.index})",
        f"base scene: scenes/{c.base_name}",
        f"mutations: {' + '.join(c.labels)}",
        f"expected: {c.expect or 'any of exit 0 / 2'}{' (' + c.why + ')' if c.why else ''}",
        f"command (cwd = an empty directory beside scene/): {' '.join(cmd)}",
        f"result: {'timeout' if timed_out else 'exit ' + str(rc)} after {seconds:.2f} s",
        "problems:",
        *(f"  - [{cat}] {text}" for cat, text in problems),
        "stdout (first 2000 bytes):",
        out[:2000].decode("utf-8", "replace"),
        "stderr (first 4000 bytes):",
        err[:4000].decode("utf-8", "replace"),
    ]
    (dest / "report.txt").write_text("\n".join(report) + "\n", encoding="utf-8", errors="replace")
    return dest


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("binary", nargs="?", default=str(REPO / "build" / "oas-render"), help="oas-render to test")
    ap.add_argument("--binary", dest="binary_opt", help="same as the positional argument")
    ap.add_argument("--scenes", default=str(REPO / "scenes"), help="directory of base scenes (*.json, meshes/)")
    ap.add_argument("--cases", type=int, default=300, help="number of cases (default 300)")
    ap.add_argument("--seed", type=int, default=1, help="random seed (default 1)")
    ap.add_argument("--timeout", type=float, default=5.0, help="seconds per run (default 5)")
    ap.add_argument("--failures", default=str(REPO / "build-fuzz" / "mutate-failures"),
                    help="where failing cases are saved")
    ap.add_argument("--only", type=int, action="append", help="run only this case index (repeatable)")
    ap.add_argument("--keep", action="store_true", help="keep every case's directory (prints where)")
    ap.add_argument("-v", "--verbose", action="store_true", help="one line per case")
    args = ap.parse_args()
    binary = Path(args.binary_opt or args.binary)
    if not (binary.is_file() and os.access(binary, os.X_OK)):
        print(f"mutate_scenes: {binary} is not an executable file", file=sys.stderr)
        return 2
    binary = binary.resolve()
    scenes_dir = Path(args.scenes)
    bases = sorted(scenes_dir.glob("*.json"))
    if not bases:
        print(f"mutate_scenes: no *.json in {scenes_dir}", file=sys.stderr)
        return 2
    texts = {p.name: p.read_text(encoding="utf-8") for p in bases}
    failures = Path(args.failures)
    if failures.is_dir() and not args.only:  # a fresh run: drop the cases an earlier run saved here
        for old in failures.glob("case[0-9][0-9][0-9][0-9][0-9]"):
            shutil.rmtree(old, ignore_errors=True)
    root = Path(tempfile.mkdtemp(prefix="oas-mutate-"))
    passed = failed = 0
    by_reason = {}
    slowest = (0.0, -1)
    start = time.monotonic()
    mutation_fns = [f for f, _ in MUTATIONS]
    weights = [w for _, w in MUTATIONS]
    try:
        for index in range(args.cases):
            if args.only and index not in args.only:
                continue
            rng = random.Random(f"{args.seed}:{index}")
            names = sorted(texts)
            base = names[index % len(names)] if index < len(names) else rng.choice(names)
            workdir = root / f"case{index:05d}" / "scene"
            workdir.mkdir(parents=True)
            if (scenes_dir / "meshes").is_dir():
                shutil.copytree(scenes_dir / "meshes", workdir / "meshes")
            c = Case(index, rng, base, texts[base], workdir)
            if index < len(names):
                c.labels.append("unmodified")
                c.want("accept", "an unmodified scene from scenes/")
            else:
                count = rng.choices([1, 2, 3], weights=[75, 18, 7])[0]
                for _ in range(count):
                    rng.choices(mutation_fns, weights=weights)[0](c)
                    if c.text is not None:  # the file's bytes are final: later tree edits would be lost
                        break
            cmd, rc, timed_out, seconds, out, err, problems = run_case(binary, c, args.timeout)
            if seconds > slowest[0]:
                slowest = (seconds, index)
            status = "timeout" if timed_out else f"exit {rc}"
            if problems:
                failed += 1
                dest = save_failure(failures, c, cmd, rc, timed_out, seconds, out, err, problems, args.seed, args.cases)
                for cat, _ in problems:
                    by_reason.setdefault(cat, []).append(index)
                print(f"FAIL case {index} [{base}: {' + '.join(c.labels)}] {status} {seconds:.2f} s: "
                      f"{'; '.join(text for _, text in problems)[:300]} -> {dest}", flush=True)
            else:
                passed += 1
                if args.verbose:
                    print(f"ok   case {index} [{base}: {' + '.join(c.labels)}] {status} {seconds:.2f} s", flush=True)
            if not args.keep:
                shutil.rmtree(root / f"case{index:05d}", ignore_errors=True)
    finally:
        if args.keep:
            print(f"mutate_scenes: cases kept under {root}")
        else:
            shutil.rmtree(root, ignore_errors=True)
    total = time.monotonic() - start
    for reason, cases in sorted(by_reason.items()):
        print(f"  {len(cases)} x {reason}: cases {', '.join(map(str, cases[:20]))}{' ...' if len(cases) > 20 else ''}")
    print(f"mutate_scenes: seed {args.seed}, {passed + failed} cases in {total:.1f} s (slowest case {slowest[1]}: "
          f"{slowest[0]:.2f} s)")
    print(f"{passed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
