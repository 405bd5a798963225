#!/usr/bin/env bash
# Runs every fuzz target for a bounded time on this stable toolchain (no sanitizer; set
# SANITIZER=address with RUSTC_BOOTSTRAP=1 for AddressSanitizer). Seeds and dictionaries are
# ours (fuzz/seeds, fuzz/dicts); the growing corpus stays in fuzz/corpus (git-ignored).
# `command_line` runs `view --screenshot` lines with the binary VCUTS_BIN (one built with the
# viewer), when it is set; without it those lines are only parsed.
# Usage: fuzz/run.sh [SECONDS_PER_TARGET] [TARGET...]
set -euo pipefail
cd "$(dirname "$0")/.."
secs="${1:-60}"
shift || true
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  targets=(scene_toml scene_files hdr exr cut_decode merge vcuts vleaf sampling light_tree brdf mesh_precompute command_line)
fi
command -v cargo-fuzz >/dev/null || cargo install --locked cargo-fuzz
for t in "${targets[@]}"; do
  mkdir -p "fuzz/corpus/$t"
  cp -n fuzz/seeds/"$t"/* "fuzz/corpus/$t/" 2>/dev/null || true
  dict=()
  [ -f "fuzz/dicts/$t.dict" ] && dict=(-dict="fuzz/dicts/$t.dict")
  echo "fuzz: $t for ${secs}s"
  cargo fuzz run --sanitizer "${SANITIZER:-none}" "$t" "fuzz/corpus/$t" -- \
    -max_total_time="$secs" -max_len=65536 -timeout=10 -rss_limit_mb=4096 "${dict[@]}" 2>&1 \
    | grep -E "^(#[0-9]+ +DONE|Done|==|SUMMARY|thread|panicked|INFO: Running|ERROR|artifact_prefix|Test unit written)" || true
  # cargo fuzz exits non-zero on a crash; pipefail is masked by grep above, so check artifacts.
  if compgen -G "fuzz/artifacts/$t/crash-*" >/dev/null || compgen -G "fuzz/artifacts/$t/oom-*" >/dev/null; then
    echo "fuzz: $t found a failing input in fuzz/artifacts/$t" >&2
    exit 1
  fi
done
echo "fuzz: all targets ran without a crash"
