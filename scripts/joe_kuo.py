#!/usr/bin/env python3
"""Joe and Kuo's Sobol direction numbers for the Sobol baseline, from a pinned source.

Two steps, both reproducible:

  extract   scipy 1.10.1's scipy/stats/_sobol_direction_numbers.npz (sha256 pinned below; the
            Debian 12 package python3-scipy 1.10.1-2 and the PyPI wheel ship the same bytes)
            -> data/sobol/new-joe-kuo-6.21201.1024.txt, the first 1024 dimensions in Joe and
            Kuo's own text format (header "d s a m_i", one line per dimension d = 2 .. 1024;
            dimension 1, van der Corput, has no line). The columns are laid out as in their file
            new-joe-kuo-6.21201, so these lines read the same as its first 1024.
  generate  data/sobol/new-joe-kuo-6.21201.1024.txt -> host/oas/oas_joe_kuo.inc, the table that
            oas_sobol_directions() (host/oas/oas_pattern.c) expands with the Bratley-Fox
            recurrence.

Usage:
  scripts/joe_kuo.py [--npz PATH | --wheel PATH]   extract, then generate
  scripts/joe_kuo.py --generate-only               generate from the committed data file
  scripts/joe_kuo.py --check [...]                 regenerate in memory and compare with the
                                                   committed files; exit 1 on any difference

Without --npz/--wheel the npz is looked up in the installed scipy (apt-get install python3-scipy).
Provenance and the licence notice: data/sobol/README.md.
"""
import argparse
import hashlib
import importlib.util
import io
import pathlib
import sys
import zipfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
DATA = ROOT / "data/sobol/new-joe-kuo-6.21201.1024.txt"
INC = ROOT / "host/oas/oas_joe_kuo.inc"
NPZ_MEMBER = "scipy/stats/_sobol_direction_numbers.npz"
# scipy 1.10.1's npz: equal in python3-scipy_1.10.1-2_amd64.deb and in
# scipy-1.10.1-cp311-cp311-manylinux_2_17_x86_64.manylinux2014_x86_64.whl. A different file is
# refused: the committed data must come from exactly this one.
NPZ_SHA256 = "4859931147d42ce465b8605cb277f957d98b839d03194fdf06579357906d193b"
DIMS = 1024  # OAS_SOBOL_BLOCK_DIMS (host/oas/oas_pattern.h), OAS_SOBOL_BLOCK (oas_baselines.glsl)

# The first lines of new-joe-kuo-6.21201 as Joe and Kuo publish it (d, s, a, m_1 .. m_s): the
# conversion from scipy's encoding must reproduce them exactly.
KNOWN_FIRST = [
    (2, 1, 0, [1]),
    (3, 2, 1, [1, 3]),
    (4, 3, 1, [1, 3, 1]),
    (5, 3, 2, [1, 1, 1]),
    (6, 4, 1, [1, 1, 3, 3]),
    (7, 4, 4, [1, 3, 5, 13]),
    (8, 5, 2, [1, 1, 5, 5, 17]),
    (9, 5, 4, [1, 1, 5, 5, 5]),
    (10, 5, 7, [1, 1, 7, 11, 19]),
]

LICENCE = """\
Copyright (c) 2008, Frances Y. Kuo and Stephen Joe
All rights reserved.

Redistribution and use in source and binary forms, with or without
modification, are permitted provided that the following conditions are met:

    * Redistributions of source code must retain the above copyright
      notice, this list of conditions and the following disclaimer.

    * Redistributions in binary form must reproduce the above copyright
      notice, this list of conditions and the following disclaimer in the
      documentation and/or other materials provided with the distribution.

    * Neither the names of the copyright holders nor the names of the
      University of New South Wales and the University of Waikato
      and its contributors may be used to endorse or promote products derived
      from this software without specific prior written permission.

THIS SOFTWARE IS PROVIDED BY THE COPYRIGHT HOLDERS ``AS IS'' AND ANY
EXPRESS OR IMPLIED WARRANTIES, INCLUDING, BUT NOT LIMITED TO, THE IMPLIED
WARRANTIES OF MERCHANTABILITY AND FITNESS FOR A PARTICULAR PURPOSE ARE
DISCLAIMED. IN NO EVENT SHALL THE COPYRIGHT HOLDERS BE LIABLE FOR ANY
DIRECT, INDIRECT, INCIDENTAL, SPECIAL, EXEMPLARY, OR CONSEQUENTIAL DAMAGES
(INCLUDING, BUT NOT LIMITED TO, PROCUREMENT OF SUBSTITUTE GOODS OR SERVICES;
LOSS OF USE, DATA, OR PROFITS; OR BUSINESS INTERRUPTION) HOWEVER CAUSED AND
ON ANY THEORY OF LIABILITY, WHETHER IN CONTRACT, STRICT LIABILITY, OR TORT
(INCLUDING NEGLIGENCE OR OTHERWISE) ARISING IN ANY WAY OUT OF THE USE OF THIS
SOFTWARE, EVEN IF ADVISED OF THE POSSIBILITY OF SUCH DAMAGE.
"""


def fail(message):
    sys.exit(f"joe_kuo.py: {message}")


def installed_npz():
    spec = importlib.util.find_spec("scipy")
    if spec is None or not spec.submodule_search_locations:
        fail("scipy is not installed: apt-get install python3-scipy, or pass --npz / --wheel")
    return pathlib.Path(list(spec.submodule_search_locations)[0]) / "stats/_sobol_direction_numbers.npz"


def read_npz_bytes(args):
    if args.wheel:
        with zipfile.ZipFile(args.wheel) as wheel:
            return wheel.read(NPZ_MEMBER), f"{args.wheel}!{NPZ_MEMBER}"
    path = pathlib.Path(args.npz) if args.npz else installed_npz()
    return path.read_bytes(), str(path)


def parse_scipy(blob):
    """(d, s, a, m) for Joe-Kuo dimensions 2 .. DIMS from scipy's arrays.

    scipy stores, for its row j (Joe-Kuo dimension j + 1; row 0 is the van der Corput dimension),
    the whole primitive polynomial as a bit mask, poly = 2^s + 2a + 1 (leading and constant terms
    included, Joe and Kuo's a in between), and vinit[j, :s] = m_1 .. m_s (zero padded to 18)."""
    import numpy as np  # only here: --generate-only and --check on the .inc need no numpy

    arrays = np.load(io.BytesIO(blob))
    poly, vinit = arrays["poly"], arrays["vinit"]
    if poly.shape[0] < DIMS or vinit.shape[0] < DIMS:
        fail(f"the npz has {poly.shape[0]} dimensions, {DIMS} needed")
    if int(poly[0]) != 1:
        fail(f"row 0 (van der Corput) should have poly 1, has {poly[0]}")
    rows = []
    for j in range(1, DIMS):
        p = int(poly[j])
        s = p.bit_length() - 1
        if s < 1 or p & 1 == 0:
            fail(f"row {j}: poly {p} is not x^s + ... + 1")
        a = (p >> 1) & ((1 << (s - 1)) - 1)
        m = [int(x) for x in vinit[j, :s]]
        if any(int(x) != 0 for x in vinit[j, s:]):
            fail(f"row {j}: vinit has values past the degree {s}")
        for k, mk in enumerate(m, start=1):
            # Sobol's conditions on the initial numbers: m_k odd and below 2^k.
            if mk % 2 == 0 or mk >= 1 << k:
                fail(f"row {j}: m_{k} = {mk} is not odd and < 2^{k}")
        rows.append((j + 1, s, a, m))
    for known, got in zip(KNOWN_FIRST, rows):
        if known != got:
            fail(f"conversion does not reproduce Joe and Kuo's line {known}: got {got}")
    return rows


def format_data(rows):
    # Joe and Kuo's layout: d, s and a left-aligned in 8 columns, then m_1 .. m_s each followed by
    # one space; newline-terminated lines.
    lines = ["d       s       a       m_i     "]
    for d, s, a, m in rows:
        lines.append(f"{d:<8}{s:<8}{a:<8}" + "".join(f"{x} " for x in m))
    return "\n".join(lines) + "\n"


def parse_data(text):
    lines = text.splitlines()
    if not lines or lines[0].split() != ["d", "s", "a", "m_i"]:
        fail(f"{DATA}: the first line should be the header 'd s a m_i'")
    rows = []
    for n, line in enumerate(lines[1:], start=2):
        fields = [int(x) for x in line.split()]
        if len(fields) < 4 or len(fields) != 3 + fields[1]:
            fail(f"{DATA}:{n}: expected d s a m_1 .. m_s")
        rows.append((fields[0], fields[1], fields[2], fields[3:]))
    if [r[0] for r in rows] != list(range(2, DIMS + 1)):
        fail(f"{DATA}: expected one line per dimension 2 .. {DIMS}")
    return rows


def format_inc(rows):
    for d, s, a, m in rows:
        # The table is uint16_t: it holds every value of the first 1024 dimensions (s <= 13).
        if s > 31 or a >= 1 << 16 or any(x >= 1 << 16 for x in m):
            fail(f"dimension {d} does not fit the uint16_t table")
    words = sum(2 + r[1] for r in rows)
    notice = "".join(f" * {line}".rstrip() + "\n" for line in LICENCE.splitlines())
    out = [
        f"/* generated by scripts/joe_kuo.py from data/sobol/{DATA.name}: do not edit.\n",
        " *\n",
        " * Joe and Kuo's Sobol direction numbers (new-joe-kuo-6.21201, search criterion D(6);\n",
        ' * S. Joe and F. Y. Kuo, "Constructing Sobol sequences with better two-dimensional\n',
        ' * projections", SIAM J. Sci. Comput. 30, 2635-2654, 2008), dimensions 2 .. 1024, which are\n',
        " * our dimensions 1 .. 1023 (dimension 1, our 0, is van der Corput and has no entry).\n",
        " * Provenance: data/sobol/README.md. Their licence:\n",
        " *\n",
        notice,
        " */\n",
        f"enum {{ OASP_JOE_KUO_DIMS = {DIMS}, OASP_JOE_KUO_WORDS = {words} }};\n",
        "/* Per dimension, in order: s (the primitive polynomial's degree), a (its inner coefficients,\n",
        " * x^(s-1) .. x^1, most significant first), m_1 .. m_s (the initial direction numbers). */\n",
        "static const uint16_t oasp_joe_kuo[OASP_JOE_KUO_WORDS] = {\n",
    ]
    for d, s, a, m in rows:
        out.append(f"    {s}, {a}, " + ", ".join(str(x) for x in m) + f",  /* {d} */\n")
    out.append("};\n")
    return "".join(out)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    source = parser.add_mutually_exclusive_group()
    source.add_argument("--npz", help="scipy's _sobol_direction_numbers.npz (default: the installed scipy's)")
    source.add_argument("--wheel", help="a scipy 1.10.1 wheel to read the npz from")
    parser.add_argument("--generate-only", action="store_true", help="only data file -> .inc")
    parser.add_argument("--check", action="store_true", help="compare with the committed files, write nothing")
    args = parser.parse_args()

    outputs = {}
    if args.generate_only:
        data_text = DATA.read_text()
    else:
        blob, where = read_npz_bytes(args)
        digest = hashlib.sha256(blob).hexdigest()
        if digest != NPZ_SHA256:
            fail(f"{where} has sha256 {digest}, not the pinned scipy 1.10.1 file {NPZ_SHA256}")
        data_text = format_data(parse_scipy(blob))
        outputs[DATA] = data_text
    rows = parse_data(data_text)
    if format_data(rows) != data_text:
        fail(f"{DATA} is not in the canonical layout (run without --generate-only to rewrite it)")
    outputs[INC] = format_inc(rows)

    stale = []
    for path, text in outputs.items():
        if args.check:
            if not path.exists() or path.read_text() != text:
                stale.append(str(path.relative_to(ROOT)))
        else:
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(text)
            print(f"wrote {path.relative_to(ROOT)}")
    if stale:
        fail("out of date: " + ", ".join(stale) + " (run scripts/joe_kuo.py)")
    if args.check:
        print("joe_kuo.py: committed files match")


if __name__ == "__main__":
    main()
