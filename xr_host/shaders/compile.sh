#!/usr/bin/env bash
# Regenerates the SPIR-V next to each GLSL shader. The .spv files are
# committed so that building the host needs no shader compiler; run this
# after editing a shader (needs `glslangValidator`, Debian: glslang-tools).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")"
for s in mesh.vert mesh.frag line.vert line.frag; do
  glslangValidator --quiet -V --target-env vulkan1.1 "$s" -o "$s.spv"
done
