#!/bin/bash
# Whether a change keeps results bit-identical: runs a set of cases with two
# wire_sim builds (each with the scene files of its own tree) and compares
# their outputs byte for byte (summary.json without its wall-time and
# real-time lines). Prints one line per case; exits 1 if any differs.
#
# usage: src/tools/same_results.sh BASE_TREE NEW_TREE [OUT_DIR]
#   a tree is a checkout built with `make build` (TREE/.ws/devel/... and
#   TREE/config/scenes). E.g. for the last commit:
#   git worktree add /tmp/base HEAD~1 && (cd /tmp/base && make build SKIP_DEPS=1)
#   src/tools/same_results.sh /tmp/base .
set -u
base=$(cd "$1" && pwd)
new=$(cd "$2" && pwd)
out=${3:-$(mktemp -d)}
exe() { echo "$1/.ws/devel/lib/coil_winding_sim/wire_sim"; }
for t in "$base" "$new"; do
  [ -x "$(exe "$t")" ] || { echo "same_results: $(exe "$t") is not built" >&2; exit 2; }
done
differs=0
run_case() {
  local name=$1
  shift
  for side in base new; do
    local tree=$base
    [ $side = new ] && tree=$new
    local dir=$out/$side/$name
    rm -rf "$dir" && mkdir -p "$dir"
    local args=("${@//@S/$tree/config/scenes}")
    "$(exe "$tree")" run "${args[@]}" --out "$dir" > "$dir.log" 2>&1 ||
      echo "  $name: $side exited $? ($dir.log)"
  done
  local same=yes f
  for f in $(ls "$out/base/$name"); do
    if [ "$f" = summary.json ]; then
      diff <(grep -v -e wall_time -e real_time "$out/base/$name/$f") \
        <(grep -v -e wall_time -e real_time "$out/new/$name/$f") > /dev/null || same=no
    else
      cmp -s "$out/base/$name/$f" "$out/new/$name/$f" || same=no
    fi
  done
  [ -n "$(ls "$out/base/$name")" ] || same=no
  echo "$name: identical $same ($(ls "$out/base/$name" | wc -l) files)"
  [ $same = yes ] || differs=1
}
run_case paper_rkf45 --scene @S/default.yaml --set process.turns=0.3
run_case paper_bdf2 --scene @S/default.yaml --set solver.integrator=bdf2
run_case paper_bdf2_3_turns --scene @S/default.yaml --set solver.integrator=bdf2 --set process.turns=3
run_case paper_implicit_euler --scene @S/default.yaml --set solver.integrator=implicit_euler \
  --set process.turns=0.5
run_case paper_symplectic --scene @S/default.yaml --set solver.integrator=symplectic_euler \
  --set process.turns=0.2
run_case paper_damped --scene @S/default.yaml --set solver.integrator=bdf2 \
  --set physics.damping=true --set damping.translational=1 --set damping.rotational=1e-6
run_case paper_bdf2_gravity --scene @S/default.yaml --set solver.integrator=bdf2 \
  --set physics.gravity=true
run_case paper_3d_bdf2 --scene @S/paper_case_3d.yaml --set solver.integrator=bdf2 \
  --set process.turns=0.5
run_case two_layers_4 --scene @S/two_layers.yaml --set process.turns=4
run_case two_layers_8 --scene @S/two_layers.yaml --set process.turns=8
run_case cell --scene @S/winding_cell.yaml
run_case cantilever --scene @S/cantilever_plastic.yaml
run_case cantilever_bdf2 --scene @S/cantilever_plastic.yaml --set solver.integrator=bdf2
exit $differs
