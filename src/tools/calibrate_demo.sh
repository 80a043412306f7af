#!/bin/bash
# Calibration against synthetic machine recordings whose true parameters
# are known (make calibrate-demo; test_calibrate runs it with --short).
#
#   src/tools/calibrate_demo.sh OUT [--short]
#
# 1. A machine's commands: the spindle ramped to 1200 rpm in 0.5 s, 70 N.
# 2. The truth: that bag replayed on the cell's scene (elastic slip) with
#    contact.static_friction 0.28, contact.kinetic_friction 0.2 and
#    wire.bend.yield_curvature 2.0 1/m.
# 3. The machine's recording: the truth's sim/ topics as machine/ topics,
#    with 0.1 N of load-cell noise, 2 um of profile noise, stamps 3 ms late
#    and the profile sensor 0.02 mm off radially.
# 4. wire_sim calibrate from the scene's own values: OUT/calibration
#    (--short: four keys, one of them without effect in this scene;
#    otherwise the usual five and that one, with more evaluations).
# 5. A recording at 60 rpm, where the wire hardly slides: OUT/slow (kinetic
#    friction is not identifiable from it).
# 6. A machine with a servo dancer (supply.tensioner.kind dancer): the same
#    commands, the truth's arm spring 300 N/m and damper 4 N s/m against
#    the scene's 100 and 2, the machine's recording made as in 3; the two
#    fitted from it, the friction and yield at the scene's values:
#    OUT/tensioner.
# Also OUT/at_truth: the misfit at the true values (the fit must reach it),
# and OUT/plain: the start's misfit without the profile's offset removed,
# the terms compare_bags.py computes.
set -euo pipefail
out=$1
short=${2:-}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
wire_sim=${WIRE_SIM:-$root/.ws/devel/lib/coil_winding_sim/wire_sim}
python=/usr/bin/python3
scene=$root/config/scenes/winding_cell.yaml
# Without strike steps (solver.strike_step 0), as the demo was validated:
# with them contact.kinetic_friction is no longer pinned down by this
# recording (+-12 % of its range at 1 sigma). Left for issue 57.
law=(--set contact.friction_law=elastic_slip --set solver.strike_step=0)
truth=(--set contact.static_friction=0.28 --set contact.kinetic_friction=0.2
       --set wire.bend.yield_curvature=2.0)
mkdir -p "$out"
bags() {  # NAME RPM [KEY=VALUE ...]: commands, truth replay, perturbed machine bag
  local name=$1 rpm=$2
  shift 2
  local truth_keys=("${truth[@]}")
  [ $# -eq 0 ] || truth_keys=("$@")
  "$python" "$here/make_synthetic_bags.py" --machine-bag "$out/${name}_commands.bag" --duration 0.5 \
    --rate 100 --record-delay 0 --tension-command 70 --max-speed-rpm "$rpm" \
    --drop-topic port/command --drop-topic port/position --drop-topic profile
  "$wire_sim" replay "$out/${name}_commands.bag" --scene "$scene" "${law[@]}" "${truth_keys[@]}" \
    --profile-rate 20 --out "$out/${name}_truth"
  "$python" "$here/make_synthetic_bags.py" --from-sim-bag "$out/${name}_truth/replay.bag" \
    --machine-bag "$out/${name}.bag" --tension-noise 0.1 --profile-noise-mm 0.002 \
    --time-shift 0.003 --profile-offset-mm 0.02 --seed 3
}
bags machine 1200
bags machine_slow 60
dancer=(--set supply.tensioner.kind=dancer)
bags machine_dancer 1200 "${dancer[@]}" --set supply.tensioner.stiffness=300 \
  --set supply.tensioner.damping=4

fit=(--fit contact.static_friction=0.22:0.4 --fit contact.kinetic_friction=0.1:0.22
     --fit wire.bend.yield_curvature=1:3 --fit wire.torsion.yield_twist)
[ "$short" = --short ] || fit+=(--fit wire.stretch.yield_strain --fit contact.damping_ratio=0.5:1)
start=$SECONDS
"$wire_sim" calibrate "$out/machine.bag" --scene "$scene" "${law[@]}" "${fit[@]}" \
  --profile-rate 20 --out "$out/calibration"
echo "calibrate_demo: the calibration took $((SECONDS - start)) s"
"$wire_sim" calibrate "$out/machine_slow.bag" --scene "$scene" "${law[@]}" \
  --fit contact.kinetic_friction=0.1:0.22 --fit wire.bend.yield_curvature=1:3 \
  --design 4 --evaluations 12 --profile-rate 20 --out "$out/slow"
"$wire_sim" calibrate "$out/machine_dancer.bag" --scene "$scene" "${law[@]}" "${dancer[@]}" \
  --fit supply.tensioner.stiffness=30:1000 --fit supply.tensioner.damping=0.5:10 \
  --profile-rate 20 --out "$out/tensioner"
# One evaluation each: at the true values, and the start without offset removal.
"$wire_sim" calibrate "$out/machine.bag" --scene "$scene" "${law[@]}" "${truth[@]}" \
  --fit wire.bend.yield_curvature=1:3 --design 0 --evaluations 1 --profile-rate 20 \
  --out "$out/at_truth" > /dev/null
"$wire_sim" calibrate "$out/machine.bag" --scene "$scene" "${law[@]}" \
  --fit wire.bend.yield_curvature=1:3 --design 0 --evaluations 1 --profile-rate 20 \
  --keep-profile-offset --out "$out/plain" > /dev/null
