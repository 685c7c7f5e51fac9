#!/usr/bin/env bash
# Peer benchmark against Mitsuba 3 (issue 9): sets up Mitsuba in a private venv where it can, then
# runs mitsuba_peer.py, which interleaves our runs with Mitsuba's and prints medians and ratios.
# Every setup failure is reported and degrades to our figures alone, so the script is useful on a
# machine without network or root as well.
#
# Usage: bench/peer/mitsuba_peer.sh [--repeats N] [--binaries DIR] [--quick] [--venv DIR] [--json F]
# Environment: OAS_PEER_VENV (venv path), OAS_PEER_MITSUBA (pip requirement, default pinned below),
#              DRJIT_LIBLLVM_PATH (use this libLLVM instead of Debian's libllvm19).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(cd "$here/../.." && pwd)

# The versions this was measured with (bench/peer/RESULTS.md); drjit comes pinned by mitsuba.
mitsuba_req=${OAS_PEER_MITSUBA:-mitsuba==3.9.1}
# HOME can be a throwaway directory (CI, sandboxes): the venv path is overridable.
venv=${OAS_PEER_VENV:-${XDG_CACHE_HOME:-${HOME:-/tmp}/.cache}/oas-peer-venv}
binaries=$repo/build
driver_args=()

usage() {
    sed -n '2,9p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'
}

while [[ $# -gt 0 ]]; do
    case $1 in
        --repeats) driver_args+=(--repeats "${2:?--repeats needs a number}"); shift 2 ;;
        --binaries) binaries=${2:?--binaries needs a directory}; shift 2 ;;
        --quick) driver_args+=(--quick); shift ;;
        --venv) venv=${2:?--venv needs a directory}; shift 2 ;;
        --json) driver_args+=(--json "${2:?--json needs a file name}"); shift 2 ;;
        -h | --help) usage; exit 0 ;;
        *) echo "mitsuba_peer.sh: unknown option $1" >&2; usage >&2; exit 2 ;;
    esac
done
[[ -d $binaries ]] || { echo "mitsuba_peer.sh: no directory $binaries (build first, or pass --binaries)" >&2; exit 2; }
binaries=$(cd "$binaries" && pwd)
driver_args+=(--binaries "$binaries")

if ! command -v python3 > /dev/null; then
    echo "mitsuba_peer.sh: python3 is needed to run the benchmark (apt-get install python3)" >&2
    exit 1
fi

# Setup output goes to a log so that the benchmark's own output stays readable; its tail is shown
# when a step fails.
setup_log=$(mktemp "${TMPDIR:-/tmp}/oas-peer-setup.XXXXXX")
trap 'rm -f "$setup_log"' EXIT
reason=""

fail() {
    reason=$1
    if [[ -s $setup_log ]]; then
        echo "--- last lines of the setup log ---" >&2
        tail -n 5 "$setup_log" >&2
        echo "---" >&2
    fi
    return 1
}

can_apt() {
    [[ $(id -u) -eq 0 ]] && command -v apt-get > /dev/null
}

apt_install() {
    # An index that was never fetched (fresh containers) makes install fail: update once, retry.
    DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "$@" >> "$setup_log" 2>&1 ||
        { apt-get update -q >> "$setup_log" 2>&1 &&
            DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "$@" >> "$setup_log" 2>&1; }
}

find_libllvm() {
    # Dr.Jit dlopens libLLVM at run time and takes the first it finds; with several LLVMs
    # installed (bookworm has 14, 15 for Mesa, and 19), naming one keeps the figures comparable.
    dpkg -L libllvm19 2> /dev/null | grep -E '/libLLVM[^/]*\.so[^/]*$' | sort | head -n 1 || true
}

setup_mitsuba() {
    if ! "$venv/bin/python" -c 'import mitsuba' > /dev/null 2>&1; then
        echo "setting up Mitsuba in $venv (one-off; log: $setup_log)"
        if ! python3 -m venv "$venv" >> "$setup_log" 2>&1; then
            if can_apt; then
                apt_install python3-venv || { fail "apt-get install python3-venv failed"; return 1; }
                rm -rf "$venv"
                python3 -m venv "$venv" >> "$setup_log" 2>&1 || { fail "python3 -m venv failed"; return 1; }
            else
                fail "python3 -m venv failed (install python3-venv, e.g. apt-get install python3-venv)"
                return 1
            fi
        fi
        "$venv/bin/python" -m pip install -q --retries 1 --timeout 20 "$mitsuba_req" >> "$setup_log" 2>&1 ||
            { fail "pip install $mitsuba_req failed (no network, or no wheel for this Python/platform)"; return 1; }
    fi

    if [[ -n ${DRJIT_LIBLLVM_PATH:-} ]]; then
        [[ -e $DRJIT_LIBLLVM_PATH ]] || { fail "DRJIT_LIBLLVM_PATH=$DRJIT_LIBLLVM_PATH does not exist"; return 1; }
    else
        local lib
        lib=$(find_libllvm)
        if [[ -z $lib ]]; then
            if can_apt; then
                echo "installing Debian's libllvm19 for Dr.Jit's LLVM backend"
                apt_install libllvm19 || { fail "apt-get install libllvm19 failed"; return 1; }
                lib=$(find_libllvm)
            else
                fail "no libLLVM for Dr.Jit (as root: apt-get install libllvm19; or set DRJIT_LIBLLVM_PATH)"
                return 1
            fi
        fi
        [[ -n $lib ]] || { fail "libllvm19 is installed but lists no libLLVM*.so"; return 1; }
        export DRJIT_LIBLLVM_PATH=$lib
    fi

    "$venv/bin/python" - >> "$setup_log" 2>&1 << 'EOF' ||
import drjit as dr, mitsuba as mi
assert any(v.startswith("llvm_") for v in mi.variants()), mi.variants()
mi.set_variant(next(v for v in ("llvm_ad_rgb", "llvm_rgb") if v in mi.variants()))
assert dr.has_backend(dr.JitBackend.LLVM)
EOF
        { fail "Mitsuba is installed but its LLVM variant does not start (DRJIT_LIBLLVM_PATH=$DRJIT_LIBLLVM_PATH)"; return 1; }
}

# No exec below: the EXIT trap must still remove the setup log. The driver prints the reason.
if setup_mitsuba; then
    "$venv/bin/python" "$here/mitsuba_peer.py" "${driver_args[@]}"
else
    python3 "$here/mitsuba_peer.py" --no-mitsuba "$reason" "${driver_args[@]}"
fi
