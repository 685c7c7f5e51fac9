#!/usr/bin/env bash
# Profiles lavapipe's JIT code, which Debian's release Mesa gives perf no symbols for: it starts a
# long GPU render, samples it with perf once the pipeline is built, dumps the JIT code pages with
# gdb from the same process (so the addresses match), disassembles them, and prints the share of
# the samples in lavapipe's per-lane loops (jit_lanes.py), with the hottest of them.
#
#   bench/lavapipe/jit_profile.sh OUTDIR [SCENE [oas-render options...]]
#
# Defaults: scenes/cornell7d.json at 512x512 and 1225 spp, rendered by build/oas-render (or
# $OAS_RENDER) (a render of a minute or more, so the
# sampling window sees steady-state tracing). Needs perf and gdb:
# scripts/setup.sh linux-perf gdb. Leaves perf.data, code.bin, code.asm, hist.txt in OUTDIR.
# The figures in docs/BENCHMARKS.md ("texel buffers") came from this script.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
out=${1:?usage: $0 OUTDIR [SCENE [oas-render options...]]}
scene=${2:-$root/scenes/cornell7d.json}
shift $(($# < 2 ? $# : 2))
render=${OAS_RENDER:-$root/build/oas-render}
warmup=${OAS_JIT_WARMUP_S:-8}    # pipeline build and first dispatches, not sampled
window=${OAS_JIT_WINDOW_S:-6}    # sampled seconds
for tool in perf gdb objdump python3; do
  command -v "$tool" >/dev/null || { echo "jit_profile: $tool is missing (scripts/setup.sh linux-perf gdb)" >&2; exit 1; }
done
mkdir -p "$out"
extra=("$@")
((${#extra[@]})) || extra=(--resolution 512x512 --spp 1225)
"$render" "$scene" --device gpu -o "$out/render.exr" "${extra[@]}" >"$out/render.log" 2>&1 &
pid=$!
trap 'kill $pid 2>/dev/null || true' EXIT
sleep "$warmup"
kill -0 $pid 2>/dev/null || { echo "jit_profile: the render ended before the window (see $out/render.log)" >&2; exit 1; }
perf record -o "$out/perf.data" -F 1999 -p $pid -- sleep "$window" >/dev/null 2>&1
# The JIT code: the first anonymous executable mapping (lavapipe's LLVM code section).
range=$(awk '$2 == "r-xp" && $4 == "00:00" && $5 == "0" && NF == 5 {print $1; exit}' /proc/$pid/maps)
[[ -n "$range" ]] || { echo "jit_profile: no anonymous executable mapping in process $pid" >&2; exit 1; }
lo=0x${range%-*}
hi=0x${range#*-}
gdb -p $pid -batch -ex "dump binary memory $out/code.bin $lo $hi" >/dev/null 2>&1
kill $pid 2>/dev/null || true
perf script -i "$out/perf.data" -F ip 2>/dev/null | awk '{print $1}' | sort | uniq -c | sort -rn >"$out/hist.txt"
objdump -D -b binary -m i386:x86-64 --adjust-vma="$lo" "$out/code.bin" >"$out/code.asm"
python3 "$(dirname "$0")/jit_lanes.py" "$out"
