#!/usr/bin/env bash
# ISA isolation check (an inline function compiled into files with different ISA flags is merged by the linker, and the wider copy may run on a CPU without it), on a linked binary:
#  1. no function outside the avx2/avx512 kernels contains a VEX/EVEX instruction (mnemonics
#     starting with "v"): neither the sse2 kernel nor baseline code nor an inline function that an
#     ISA file instantiated and the linker then chose as the only copy;
#  2. the sse2 kernel is present (so 1. looked at it);
#  3. the avx2 kernel does contain VEX instructions (so the scan can see them at all).
# usage: check_isa_isolation.sh BINARY
set -euo pipefail
binary="$1"
objdump -d -C --no-show-raw-insn "$binary" | awk '
  /^[0-9a-f]+ <.*>:$/ { name = $0; sub(/^[0-9a-f]+ </, "", name); sub(/>:$/, "", name); next }
  /^ +[0-9a-f]+:\t/ {
    split($0, parts, "\t"); split(parts[2], words, " "); m = words[1]
    isa = (name ~ /avx2|avx512/)
    if (name ~ /simd::sse2::shade/) seen_sse2 = 1
    if (m ~ /^v/) {
      if (isa) { vex_in_avx2 += (name ~ /avx2/) }
      else if (!(name in reported)) { reported[name] = 1; bad++; print "VEX/EVEX instruction " m " in non-AVX function: " name }
    }
  }
  END {
    if (!seen_sse2) { print "the sse2 kernel was not found in the binary"; exit 1 }
    if (vex_in_avx2 == 0) { print "no VEX instruction found in the avx2 kernel: the scan cannot see them"; exit 1 }
    if (bad > 0) { print bad " function(s) outside the AVX kernels use AVX instructions"; exit 1 }
    print "ok: sse2 kernel and baseline code free of VEX/EVEX; " vex_in_avx2 " VEX instructions in avx2 code"
  }'
