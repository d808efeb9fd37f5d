#!/usr/bin/env bash
# Runs the bundled mini-app with Canopy's default pipelines, leaving images,
# a selection extract and data extracts in OUTPUT (default canopy-output).
#   scripts/run_miniapp.sh [--ranks N] [OUTPUT] [-- mini-app options...]
# Renders through xvfb-run when no X display is reachable; runs under mpirun.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
ranks=1
output=canopy-output
while (($#)); do
  case "$1" in
    --ranks) ranks="$2"; shift 2 ;;
    --) shift; break ;;
    *) output="$1"; shift ;;
  esac
done
binary="$here/build/miniapp/canopy_miniamr"
[ -x "$binary" ] || { echo "run_miniapp: $binary is missing; run scripts/setup.sh first" >&2; exit 1; }

launcher=(mpirun -np "$ranks")
((ranks > $(nproc))) && launcher+=(--oversubscribe)
if [ "$(id -u)" -eq 0 ]; then
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
fi
# OpenMPI's hwloc probes the X display (its "gl" component) and, under a virtual
# display, prints "Authorization required..." twice per rank; it finds nothing there.
export HWLOC_COMPONENTS="${HWLOC_COMPONENTS:--gl}"
# Debian's ParaView renders through X only: use a virtual display if needed.
# -noreset: by default the server resets when its last client disconnects and
# refuses connections meanwhile, failing a process that closes a display and
# opens the next (tests use tests/support/with_xvfb.sh instead: docs/testing.md).
if [ -z "${DISPLAY:-}" ] || ! xdpyinfo >/dev/null 2>&1; then
  launcher=(xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" "${launcher[@]}")
fi
mkdir -p "$output"
"${launcher[@]}" "$binary" --output "$output" "$@"
echo "run_miniapp: images and extracts are in $output/"
