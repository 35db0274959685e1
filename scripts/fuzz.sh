#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan + UBSan: the `fuzz` preset) and
# fuzzes them, one at a time, single process (docs/fuzzing.md):
#   scripts/fuzz.sh TARGET SECONDS [libFuzzer flags...]
#   scripts/fuzz.sh all SECONDS [libFuzzer flags...]     (every target, SECONDS each)
# TARGET: scenario sweep mot seqinfo gltf assimp. First each target runs once
# over fuzz/regressions/TARGET/ (past crashes), then fuzzes a copy of
# fuzz/corpus/TARGET/ in build/fuzz/corpus-work/TARGET/ (the repository is not
# modified); HCPF_FUZZ_CORPUS=DIR fuzzes DIR/TARGET/ instead and keeps it.
# Exit status 1 when any target crashes, leaks, times out or runs out of
# memory; the inputs that did are in build/fuzz/artifacts/TARGET/.
set -euo pipefail
cd "$(dirname "$0")/.."

TARGETS=(scenario sweep mot seqinfo gltf assimp)
usage() {
  echo "usage: scripts/fuzz.sh {all|$(IFS='|'; echo "${TARGETS[*]}")} SECONDS [libFuzzer flags...]" >&2
  exit 2
}
[ "$#" -ge 2 ] || usage
target="$1"
seconds="$2"
shift 2
[[ "$seconds" =~ ^[1-9][0-9]*$ ]] || usage
if [ "$target" = all ]; then
  selected=("${TARGETS[@]}")
elif [[ " ${TARGETS[*]} " == *" $target "* ]]; then
  selected=("$target")
else
  usage
fi

bash scripts/setup.sh
cmake --preset fuzz > /dev/null
cmake --build --preset fuzz -j "$(nproc)"

# Longest input per target: text formats stay small (a scenario is ~1 KiB);
# the glTF seeds include the project's vehicles (up to 28 KiB).
max_len() {
  case "$1" in
    gltf) echo 32768 ;;
    assimp) echo 8192 ;;
    *) echo 4096 ;;
  esac
}

root="$PWD"
out="$root/build/fuzz"
export ASAN_OPTIONS="detect_leaks=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
# Leaks inside Debian's third-party libraries that we cannot fix (the file says which).
export LSAN_OPTIONS="suppressions=$root/fuzz/lsan.supp:print_suppressions=0${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
# Scratch files of the path-taking loaders (fuzz/fuzz_support.h); a crashed
# process leaves its folder behind, so start empty.
export TMPDIR="$out/tmp"
rm -rf "$TMPDIR"
mkdir -p "$TMPDIR"
common=(-timeout=10 -rss_limit_mb=2048)

failed=()
for t in "${selected[@]}"; do
  exe="$out/fuzz/fuzz_$t"
  artifacts="$out/artifacts/$t"
  mkdir -p "$artifacts"
  regressions_dir="$root/fuzz/regressions/$t"
  mapfile -t regressions < <(find "$regressions_dir" -type f ! -name '.*' | sort)
  if [ "${#regressions[@]}" -gt 0 ]; then
    echo "fuzz: $t: ${#regressions[@]} regression input(s)"
    if ! (cd "$out" && "$exe" "${common[@]}" "${regressions[@]}") > "$out/regressions-$t.log" 2>&1; then
      cat "$out/regressions-$t.log"
      echo "fuzz: $t: a regression input fails again (log: $out/regressions-$t.log)" >&2
      failed+=("$t (regression)")
      continue
    fi
  fi
  if [ -n "${HCPF_FUZZ_CORPUS:-}" ]; then
    corpus="$(realpath -m "$HCPF_FUZZ_CORPUS")/$t"
    mkdir -p "$corpus"
    for seed in "fuzz/corpus/$t/"*; do
      [ -e "$corpus/$(basename "$seed")" ] || cp "$seed" "$corpus/"
    done
  else
    corpus="$out/corpus-work/$t"
    rm -rf "$corpus"
    mkdir -p "$corpus"
    cp "fuzz/corpus/$t/"* "$corpus/"
  fi
  echo "fuzz: $t: ${seconds} s on $corpus (artifacts: $artifacts/)"
  # Run in build/fuzz: with -jobs libFuzzer writes fuzz-N.log files to the current folder.
  # The full log keeps libFuzzer's progress lines (#N NEW/REDUCE/pulse); the console does not.
  set +e
  (cd "$out" && "$exe" "${common[@]}" -max_total_time="$seconds" -max_len="$(max_len "$t")" \
    -artifact_prefix="$artifacts/" -print_final_stats=1 "$@" "$corpus" "$regressions_dir") \
    2>&1 | tee "$out/fuzz-$t.log" | { grep -v -E '^(#[0-9]+|"|###### )' || true; }
  status="${PIPESTATUS[0]}"
  set -e
  if [ "$status" -ne 0 ]; then
    echo "fuzz: $t: FAILED; the input is in $artifacts/ (log: $out/fuzz-$t.log)" >&2
    failed+=("$t")
  fi
done

if [ "${#failed[@]}" -gt 0 ]; then
  echo "fuzz: failed: ${failed[*]}; see docs/fuzzing.md for turning a crash into a regression" >&2
  exit 1
fi
echo "fuzz: ${selected[*]}: no crash, leak, timeout or out-of-memory"
