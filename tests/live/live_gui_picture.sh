#!/bin/bash
# docs/images/live_paraview_gui.png: ParaView 5.11's GUI watching the 3D mini-app
# through Catalyst Live. Run under the project's Xvfb wrapper from the source tree:
#   tests/support/with_xvfb.sh --screen 1600x1000x24 -- tests/live/live_gui_picture.sh OUT.png
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
out="$1"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/home/.config/ParaView"
printf '[General]\nGeneralSettings.ShowWelcomeDialog=false\n' \
  >"$work/home/.config/ParaView/ParaView5.11.0.ini"
export CANOPY_PLUGIN="$root/build/lib/canopy-plugins/CanopyPlugin/CanopyPlugin.so"
export CANOPY_LIVE_PORT=22621 CANOPY_GUI_FLAGS="$work"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
HOME="$work/home" paraview -qwindowgeometry 1600x1000+0+0 \
  --script="$here/live_gui_picture.py" >"$work/paraview.log" 2>&1 &
gui=$!
for _ in $(seq 120); do [ -f "$work/listening" ] && break; sleep 0.5; done
mpirun -np 2 "$root/build/miniapp/canopy_miniamr" --dimension 3 --roots 6 --max-level 3 \
  --steps 40 --image-every 1 --live localhost:$CANOPY_LIVE_PORT --output "$work/out" \
  >"$work/simulation.log" 2>&1 &
simulation=$!
for _ in $(seq 240); do [ -f "$work/done" ] && break; sleep 0.5; done
sleep 6 # the GUI repaints once the script returns
/usr/bin/python3 -c "import sys; from PIL import ImageGrab; ImageGrab.grab().save(sys.argv[1])" "$out"
wait "$simulation"
kill "$gui" 2>/dev/null || true
grep -E "done:|pipeline failure" "$work/simulation.log"
