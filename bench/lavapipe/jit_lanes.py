#!/usr/bin/env python3
"""Share of a lavapipe JIT profile spent in per-lane loops (bench/lavapipe/jit_profile.sh).

Lavapipe (Mesa 22.3) runs 8 lanes in lock step in AVX2 registers, but some operations it does one
lane at a time: a storage-buffer load whose index differs across lanes, for instance, is a loop
over the 8 lanes with a branch and a bounds check each. Such a loop counts its lane in a register
and leaves when it reaches 8 (`cmp $0x8,%reg` then `jae`); this finds those loops in the
disassembly and sums the perf samples that fall inside them.

Usage: jit_lanes.py DIR   (DIR holds hist.txt, "count address" lines, and code.asm from objdump)
"""
import re
import sys


def main(folder):
    hist = {}
    with open(f"{folder}/hist.txt") as f:
        for line in f:
            count, address = line.split()
            hist[int(address, 16)] = int(count)
    total = sum(hist.values())
    code = []
    with open(f"{folder}/code.asm") as f:
        for line in f:
            m = re.match(r"\s*([0-9a-f]+):\s+(?:[0-9a-f]{2} )+\s*(.*)", line)
            if m:
                code.append((int(m.group(1), 16), m.group(2)))
    if not total or not code:
        sys.exit("jit_lanes: no samples or no code")
    lo, hi = code[0][0], code[-1][0]
    in_code = sum(c for a, c in hist.items() if lo <= a <= hi)
    lane_addresses, loops = set(), []
    for i, (address, text) in enumerate(code[:-1]):
        if not (re.match(r"cmp\s+\$0x8,%e", text) and code[i + 1][1].startswith("jae")):
            continue
        exit_at = int(re.search(r"0x([0-9a-f]+)", code[i + 1][1]).group(1), 16)
        head = address  # the loop's head: the earliest target of a jump back to at most here
        for b, t in code:
            if address - 400 < b < exit_at:
                m = re.match(r"j\w+\s+0x([0-9a-f]+)", t)
                if m and address - 400 < int(m.group(1), 16) <= address and b >= address:
                    head = min(head, int(m.group(1), 16))
        body = [b for b, _ in code if head <= b < exit_at]
        lane_addresses.update(body)
        loops.append((sum(hist.get(b, 0) for b in body), head, exit_at))
    in_lanes = sum(c for a, c in hist.items() if a in lane_addresses)
    print(f"samples: {total}; in the dumped JIT code: {100 * in_code / total:.1f}%; "
          f"in per-lane loops: {100 * in_lanes / total:.1f}% ({len(loops)} loops)")
    for count, head, exit_at in sorted(loops, reverse=True)[:8]:
        print(f"  {100 * count / total:5.1f}%  loop at {head:#x}..{exit_at:#x}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else ".")
