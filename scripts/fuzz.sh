#!/usr/bin/env bash
# Fuzzes the scene loader and the OBJ reader (docs/FUZZING.md).
#
#   scripts/fuzz.sh [minutes]        default 2 minutes per libFuzzer target
#
# 1. Installs what is missing (clang, libclang-rt-14-dev, cmake, ninja, the header libraries),
#    needs root or sudo only then.
# 2. Builds fuzz/ (ASan + UBSan + libFuzzer) into build-fuzz/ with one compile job.
# 3. Replays the reproducers in fuzz/regressions (known open ones: fuzz/regressions/OPEN).
# 4. Runs each libFuzzer target for the given minutes on a corpus seeded from scenes/ and
#    fuzz/seeds/ (build-fuzz/corpus-<target>/, which grows from run to run); artifacts go to
#    build-fuzz/artifacts/<target>/, logs to build-fuzz/logs/<target>.log.
# 5. Runs fuzz/mutate_scenes.py against build/oas-render when it exists (skipped, visibly, if not).
# Prints executions, crashes, timeouts, leaks and OOMs per target; exits 1 on any finding.
#
# Environment:
#   FUZZ_TARGETS="fuzz_scene fuzz_obj"  which libFuzzer targets to run
#   FUZZ_KEEP_GOING=1   fork mode (-fork=1 -ignore_crashes/timeouts/ooms): keep fuzzing past a crash
#                       and count every artifact (default: stop at the first, as libFuzzer does)
#   FUZZ_JOBS=1         compile jobs (at most 2 on the shared 2-core machine)
#   FUZZ_CASES=300 FUZZ_SEED=1   structured mutator cases and seed
#   OAS_RENDER=build/oas-render  the renderer the mutator runs
#   OAS_FUZZ_IGNORE=cat1,cat2    invariant categories the harnesses do not check (known findings)
#   CXX=clang++         the compiler (must be clang)
#   FUZZ_EXTRA_ARGS     more libFuzzer flags for every target
set -euo pipefail
cd "$(dirname "$0")/.."
minutes="${1:-2}"
if ! [[ "$minutes" =~ ^[0-9]+([.][0-9]+)?$ ]]; then
  echo "usage: scripts/fuzz.sh [minutes per target]" >&2
  exit 2
fi
seconds=$(awk -v m="$minutes" 'BEGIN { s = int(m * 60 + 0.5); print (s < 1 ? 1 : s) }')
targets=(${FUZZ_TARGETS:-fuzz_scene fuzz_obj})
jobs="${FUZZ_JOBS:-1}"
build=build-fuzz

# --- 1. packages --------------------------------------------------------------------------------
scripts/setup.sh clang libclang-rt-14-dev python3

findings=0

# --- 2. build -----------------------------------------------------------------------------------
cxx="${CXX:-clang++}"
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
if [[ ! -f $build/CMakeCache.txt ]]; then
  cmake -S fuzz -B "$build" "${generator[@]}" -DCMAKE_CXX_COMPILER="$cxx" >/dev/null
fi
cmake --build "$build" -j "$jobs"
mkdir -p "$build/logs" "$build/artifacts"

# --- 3. replay fuzz/regressions -----------------------------------------------------------------
# Reproducers of earlier findings. Those listed in fuzz/regressions/OPEN are known and not fixed
# yet: they are reported but do not fail the run; any other reproducer that fails is a regression.
# scene/*.json go through fuzz_scene (meshes resolve in fuzz/regressions/scene), obj/* through
# fuzz_obj, cli/*.json through the renderer, which must refuse each (exit 2, naming the file) in 5 s.
render="${OAS_RENDER:-build/oas-render}"
regressions=0 open_failing=0 replayed=0
is_open() { grep -qxF "${1#fuzz/regressions/}" <(sed -e 's/[[:space:]].*//' fuzz/regressions/OPEN 2>/dev/null); }
replay_result() {  # file ok(0/1)
  replayed=$((replayed + 1))
  if [[ $2 == 0 ]]; then
    if is_open "$1"; then echo "  replay: $1 passes now: fixed? then take it out of fuzz/regressions/OPEN"; fi
  elif is_open "$1"; then
    open_failing=$((open_failing + 1))
  else
    regressions=$((regressions + 1))
    echo "  replay: REGRESSION $1"
  fi
}
for f in fuzz/regressions/scene/*.json fuzz/regressions/obj/*; do
  [[ -f $f ]] || continue
  t=fuzz_scene; [[ $f == fuzz/regressions/obj/* ]] && t=fuzz_obj
  ok=0
  OAS_FUZZ_MESH_DIR=fuzz/regressions/scene OAS_FUZZ_IGNORE= timeout 30 "$build/$t" -rss_limit_mb=2048 "$f" \
    >"$build/logs/replay.log" 2>&1 || ok=1
  replay_result "$f" "$ok"
done
if [[ -x $render ]]; then
  for f in fuzz/regressions/cli/*.json; do
    [[ -f $f ]] || continue
    ok=0
    err=$( (ulimit -v 4194304; timeout 5 "$render" "$f" --explain 2>&1 >/dev/null); echo "rc=$?") || true
    [[ $err == *"rc=2" && $err == "oas-render: error: "*"$f"* ]] || ok=1
    replay_result "$f" "$ok"
  done
fi
echo "fuzz: replayed $replayed reproducers from fuzz/regressions: $open_failing known open (fuzz/regressions/OPEN), $regressions regressions"
((regressions == 0)) || findings=1

# --- 4. libFuzzer targets -----------------------------------------------------------------------
declare -A dict=([fuzz_scene]=fuzz/scene.dict [fuzz_obj]=fuzz/obj.dict)
declare -A maxlen=([fuzz_scene]=65536 [fuzz_obj]=65536)
seed_corpus() {  # target dir
  mkdir -p "$2"
  case "$1" in
    fuzz_scene) cp -n scenes/*.json fuzz/seeds/scene/* "$2"/ 2>/dev/null || true ;;
    fuzz_obj) find scenes fuzz/seeds/obj -name '*.obj' -exec cp -n {} "$2"/ \; ;;
  esac
}
# The last value of a libFuzzer stat (stat::name: N) or of a status line field in a log.
libfuzzer_stat() { grep -a "^stat::$2:" "$1" | tail -1 | awk '{print $2}'; }

declare -A execs secs crashes timeouts leaks ooms rss exitcode
for t in "${targets[@]}"; do
  [[ -x $build/$t ]] || { echo "fuzz: no $build/$t" >&2; exit 1; }
  corpus="$build/corpus-${t#fuzz_}"
  art="$build/artifacts/$t"
  seed_corpus "$t" "$corpus"
  if [[ -d $art ]] && compgen -G "$art/*" >/dev/null; then
    rm -rf "$art.prev" && mv "$art" "$art.prev"
    echo "fuzz: previous artifacts of $t moved to $art.prev"
  fi
  mkdir -p "$art"
  log="$build/logs/$t.log"
  flags=(-max_total_time="$seconds" -timeout=5 -rss_limit_mb=2048 -max_len="${maxlen[$t]}"
         -dict="${dict[$t]}" -artifact_prefix="$art/" -print_final_stats=1 -use_value_profile=1)
  [[ "${FUZZ_KEEP_GOING:-0}" == 1 ]] && flags+=(-fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1)
  echo "fuzz: $t for ${seconds} s (log $log)"
  set +e
  # Seeds in fuzz/seeds and scenes/ are read, new inputs are written to $corpus only.
  "$build/$t" "${flags[@]}" ${FUZZ_EXTRA_ARGS:-} "$corpus" >"$log" 2>&1
  exitcode[$t]=$?
  set -e
  # Executions: libFuzzer's final stats, else "Done N runs", else the last status line (fork mode).
  n=$(libfuzzer_stat "$log" number_of_executed_units)
  [[ -n $n ]] || n=$(grep -aoE '^Done [0-9]+ runs' "$log" | tail -1 | awk '{print $2}')
  [[ -n $n ]] || n=$(grep -aoE '^#[0-9]+' "$log" | tail -1 | tr -d '#')
  execs[$t]=${n:-0}
  s=$(grep -aoE '^Done [0-9]+ runs in [0-9]+ second' "$log" | tail -1 | awk '{print $5}')
  [[ -n $s ]] || s=$(grep -aoE 'time: [0-9]+s' "$log" | tail -1 | tr -dc 0-9)
  secs[$t]=${s:-$seconds}
  r=$(libfuzzer_stat "$log" peak_rss_mb)
  [[ -n $r ]] || r=$(grep -aoE 'rss: [0-9]+Mb' "$log" | tail -1 | tr -dc 0-9)
  rss[$t]=${r:-?}
  count() { find "$art" -maxdepth 1 -name "$1-*" | wc -l; }
  crashes[$t]=$(count crash)
  timeouts[$t]=$(count timeout)
  leaks[$t]=$(count leak)
  ooms[$t]=$(count oom)
  if ((crashes[$t] + timeouts[$t] + leaks[$t] + ooms[$t] > 0)) || [[ ${exitcode[$t]} != 0 ]]; then
    findings=1
    grep -aE 'oas-fuzz: invariant|ERROR: (AddressSanitizer|libFuzzer|LeakSanitizer)|runtime error:|SUMMARY:' "$log" |
      sort | uniq -c | sort -rn | head -8 | sed 's/^/  /'
  fi
done

# --- 5. structured mutator through the CLI ------------------------------------------------------
mutate="skipped: $render not built (scripts/build.sh builds it)"
mutate_rc=0
if [[ -x $render ]]; then
  echo "fuzz: fuzz/mutate_scenes.py on $render"
  set +e
  python3 fuzz/mutate_scenes.py "$render" --cases "${FUZZ_CASES:-300}" --seed "${FUZZ_SEED:-1}" \
    --failures "$build/mutate-failures" | tee "$build/logs/mutate_scenes.log" | grep -E '^(FAIL|  [0-9]+ x|[0-9]+ passed)'
  mutate_rc=${PIPESTATUS[0]}
  set -e
  mutate=$(grep -E '^[0-9]+ passed, [0-9]+ failed' "$build/logs/mutate_scenes.log" | tail -1)
  [[ -n $mutate ]] || mutate="did not finish (exit $mutate_rc)"
  ((mutate_rc == 0)) || findings=1
else
  echo "fuzz: SKIPPED the structured mutator: $render does not exist"
fi

# --- summary ------------------------------------------------------------------------------------
echo
printf '%-12s %12s %8s %8s %9s %6s %6s %8s %5s\n' target executions seconds crashes timeouts leaks ooms peak-rss exit
for t in "${targets[@]}"; do
  printf '%-12s %12s %8s %8s %9s %6s %6s %6sMB %5s\n' "$t" "${execs[$t]}" "${secs[$t]}" "${crashes[$t]}" \
    "${timeouts[$t]}" "${leaks[$t]}" "${ooms[$t]}" "${rss[$t]}" "${exitcode[$t]}"
done
echo "mutate_scenes: $mutate"
echo "regressions: $replayed replayed, $open_failing known open, $regressions regressions"
if ((findings)); then
  echo "fuzz: FINDINGS: artifacts in $build/artifacts/, mutator failures in $build/mutate-failures/ (docs/FUZZING.md: triage)"
  exit 1
fi
echo "fuzz: no findings"
