#!/usr/bin/env bash
# The programs of a default GL voxelize as SPIR-V, for
# `yv_bench_compile_threads --cold-spirv DIR`: each program's text as the run
# composes it (--dump-sources), compiled by glslangValidator (Debian's
# glslang-tools) for OpenGL, the uniforms and buffers given the locations
# and bindings the text leaves to the driver. The GLSL's
# `#pragma optionNV(unroll none)` (NVIDIA's, which glslang passes over) is
# carried over as SPIR-V's DontUnroll on each of that program's loops, so
# the driver is asked for the same code. With -Os, the modules also pass
# through SPIRV-Tools' size optimiser.
#
#   bench/spirv_compile.sh BENCH_BINARY DIR [-Os]
set -euo pipefail
bench=$1 dir=$2
shift 2
command -v glslangValidator > /dev/null ||
  { echo "spirv_compile.sh: glslangValidator not found (Debian's glslang-tools: apt-get install glslang-tools)" >&2; exit 1; }
mkdir -p "$dir"
"$bench" --dump-sources "$dir"
for text in "$dir"/*.comp; do
  if grep -q '^#pragma optionNV(unroll none)' "$text"; then
    sed -i -e '1a #extension GL_EXT_control_flow_attributes : require' \
           -e 's/^\([ \t]*\)for (/\1[[dont_unroll]] for (/' "$text"
  fi
  glslangValidator -G --auto-map-locations --auto-map-bindings -S comp "$@" -o "${text%.comp}.spv" "$text" >/dev/null
done
echo "$dir: $(ls "$dir"/*.spv | wc -l) modules"
