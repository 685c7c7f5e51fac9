#!/bin/bash
# Error against samples from faure's checkpoints: one `oas-render --sampler faure --checkpoints`
# render per seed, read at each count, against a Sobol render and an OA-chooser render (`oa`) of
# each count, relMSE against the study's reference (docs/study/scenes/<scene>_reference.exr,
# 64 x 64). Prints "scene sampler spp seed relMSE" lines; docs/BENCHMARKS.md has a run.
# Usage: scripts/checkpoint_curve.sh SCENE SEEDS COUNT... (the counts q, q^2, ... of the scene's
# faure base, largest last), e.g. scripts/checkpoint_curve.sh cornell7d 16 8 64 512 4096
set -euo pipefail
cd "$(dirname "$0")/.."
scene=$1 seeds=$2
shift 2
counts="$*" max=${*: -1}
ref=docs/study/scenes/${scene}_reference.exr
[ -f "$ref" ] || { echo "checkpoint_curve.sh: no reference $ref (the study's scene part makes it)" >&2; exit 2; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
relmse() { build/oas-diff "$1" "$ref" | awk '/^whole/{print $4}'; }
for seed in $(seq 1 "$seeds"); do
    build/oas-render "scenes/$scene.json" --sampler faure --spp "$max" --resolution 64x64 --device cpu --seed "$seed" \
        --checkpoints -o "$out/faure.exr" >/dev/null 2>&1
    for c in $counts; do
        f="$out/faure.spp$c.exr"
        [ "$c" = "$max" ] && f="$out/faure.exr"
        echo "$scene faure $c $seed $(relmse "$f")"
        for s in sobol oa; do
            # A count below q^2 has no orthogonal array: oas-render refuses it as bad input (exit 2),
            # and the line says n/a; any other failure stops the script.
            rc=0
            build/oas-render "scenes/$scene.json" --sampler $s --spp "$c" --resolution 64x64 --device cpu --seed "$seed" \
                -o "$out/$s.exr" >/dev/null 2>&1 || rc=$?
            if [ "$rc" = 2 ] && [ "$s" = oa ]; then
                echo "$scene $s $c $seed n/a"
            elif [ "$rc" = 0 ]; then
                echo "$scene $s $c $seed $(relmse "$out/$s.exr")"
            else
                echo "checkpoint_curve.sh: oas-render --sampler $s --spp $c failed (exit $rc)" >&2
                exit 1
            fi
        done
    done
done
