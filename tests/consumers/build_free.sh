#!/bin/sh
# The two ways to use oas without building its C++ side (docs/EMBEDDING.md): straight from the
# checkout with a C compiler and glslangValidator, and from an install configured with
# -DOAS_BUILD_CPP=OFF (oas::pattern_c and the GLSL only). Each compiles
# examples/build-free/pattern_words.c with oas_pattern.c and the example consumer shader, runs the
# program and checks what it prints against the construction's mathematics: Bose 64 is over
# GF(2^3) (field kind 1, degree 3), and Bose cannot make 63 (nearest squares of prime powers: 49, 64).
# Usage: build_free.sh <oas source dir> <scratch dir> <C compiler> <glslangValidator> <cmake generator>
set -eu
src=$1 work=$2 cc=$3 glslang=$4 generator=$5
rm -rf "$work"
mkdir -p "$work"

check() {  # $1: the program's output file
    grep -q "refused: 63 is not a square q^2; nearest valid spp: 49, 64" "$1" || { cat "$1"; echo "FAIL: refusal"; exit 1; }
    grep -q "specialization: construction=1 offset=3 fieldKind=1 fieldDegree=3 smallN=1 indexBits=24" "$1" ||
        { cat "$1"; echo "FAIL: specialization"; exit 1; }
    grep -q "pattern: construction=1 offset=3 N=64 s=8 " "$1" || { cat "$1"; echo "FAIL: pattern words"; exit 1; }
}

start=$(date +%s)
"$cc" -std=c99 -pedantic-errors -Wall -Werror -I "$src/host" "$src/host/oas/oas_pattern.c" \
    "$src/examples/build-free/pattern_words.c" -o "$work/from-checkout"
"$glslang" --target-env vulkan1.1 -I"$src/shaders" -o "$work/consumer.spv" "$src/examples/common/consumer.comp" > "$work/glslang.log" ||
    { cat "$work/glslang.log"; exit 1; }
"$work/from-checkout" > "$work/from-checkout.txt"
check "$work/from-checkout.txt"
echo "build-free from the checkout: $(($(date +%s) - start)) s"

start=$(date +%s)
cmake -S "$src" -B "$work/build" -G "$generator" -DOAS_BUILD_CPP=OFF -DOAS_BUILD_TOOLS=OFF -DOAS_BUILD_TESTS=OFF \
    -DOAS_BUILD_BENCHMARKS=OFF -DOAS_INSTALL=ON -DCMAKE_C_COMPILER="$cc" > "$work/configure.log" || { cat "$work/configure.log"; exit 1; }
cmake --build "$work/build" > "$work/build.log" || { cat "$work/build.log"; exit 1; }
cmake --install "$work/build" --prefix "$work/prefix" > "$work/install.log" || { cat "$work/install.log"; exit 1; }
[ -n "$(find "$work/prefix" -name liboas_pattern_c.a)" ] || { echo "FAIL: no liboas_pattern_c.a installed"; exit 1; }
[ -z "$(find "$work/prefix" -name liboas_pattern.a)" ] || { echo "FAIL: OAS_BUILD_CPP=OFF installed the C++ library"; exit 1; }
"$cc" -std=c99 -pedantic-errors -Wall -Werror -I "$work/prefix/include" "$work/prefix/share/oas/src/oas_pattern.c" \
    "$src/examples/build-free/pattern_words.c" -o "$work/from-install"
"$glslang" --target-env vulkan1.1 -I"$work/prefix/include" -o "$work/consumer-installed.spv" "$src/examples/common/consumer.comp" \
    > "$work/glslang.log" || { cat "$work/glslang.log"; exit 1; }
"$work/from-install" > "$work/from-install.txt"
check "$work/from-install.txt"
echo "C-only install (configure, build, install, compile): $(($(date +%s) - start)) s"
