#!/usr/bin/env bash
# The real-servo experiment of docs/gap.md ("A real servo"): orcs-gap on the eight XL330 pendulum logs, fitted on
# the four runs at one firmware gain and scored on the four at the other, both ways, with no parameter re-tuned per
# gain (each replay takes its log's gain and its measured supply voltage), fitted on the mean absolute error (BAM's
# metric, --loss absolute). Then the table and the figures.
#
#   scripts/gap_xl330.sh [DATA_DIR] [OUT_DIR] [WORKERS]
#
# DATA_DIR defaults to scenarios/data/xl330-pendulum, OUT_DIR to build/gap-xl330, WORKERS to the number of cores.
# GAP_OPTIONS passes more orcs-gap options (e.g. GAP_OPTIONS=--no-race). LOG_EXT=json reads BAM's JSON logs instead of
# the CSVs (scripts/xl330_to_bam.py makes them; docs/gap_measured_data.md, "BAM's JSON logs").
# Writes OUT_DIR/kp100_to_kp400/ and OUT_DIR/kp400_to_kp100/ (orcs-gap reports, with scripts/plot_gap.py's
# plots), OUT_DIR/servo_gains.png and OUT_DIR/servo_gains.md. About 10 minutes per direction on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."
data=${1:-scenarios/data/xl330-pendulum}
out=${2:-build/gap-xl330}
workers=${3:-$(nproc 2>/dev/null || echo 2)}
ext=${LOG_EXT:-csv}
gap=build/bin/orcs-gap
[[ -x $gap ]] || { echo "gap_xl330.sh: $gap is missing; run scripts/build.sh first" >&2; exit 2; }
for gain in 100 400; do
  for trajectory in sin_sin lift_and_drop up_and_down sin_time_square; do
    [[ -r $data/${trajectory}_kp$gain.$ext ]] || { echo "gap_xl330.sh: $data/${trajectory}_kp$gain.$ext: cannot read" >&2; exit 2; }
  done
done
runs() { for t in sin_sin lift_and_drop up_and_down sin_time_square; do echo "$data/${t}_kp$1.$ext"; done; }

# The rig: a pole of the load's gravity torque (0.49 kg × 9.81 × 0.10 m) and inertia (0.49 kg × 0.10² m²): a uniform
# pole of mass M and length L has M·L/2 = 0.049 kg·m and M·L²/3 = 0.0049 kg·m², so L = 0.15 m and M = 0.6533 kg.
diagnose() {  # FIT_GAIN HELD_OUT_GAIN
  local report=$out/kp$1_to_kp$2
  mapfile -t fit < <(runs "$1")
  mapfile -t held < <(runs "$2")
  echo "gap_xl330.sh: fitting on kp$1, scoring on kp$2 → $report" >&2
  "$gap" --rig pendulum --pole-mass 0.6533 --pole-length 0.15 --start-measured \
    --model scenarios/gap/xl330/model.val --mapping scenarios/gap/xl330/mapping.json \
    --measured "${fit[@]}" --holdout "${held[@]}" --loss absolute --workers "$workers" ${GAP_OPTIONS:-} --out "$report"
  scripts/plot_gap.py "$report" --run "sin_sin_kp$2"  # a held-out run in the panels
}
diagnose 100 400
diagnose 400 100

# BAM's published XL330 models on the same logs (the data's README): M1 Coulomb–viscous, M3 load-dependent
# friction; mean absolute error over the four runs at the held-out gain (kp400, then kp100).
scripts/plot_servo_gains.py --run "fitted on kp100, scored on kp400" "$out/kp100_to_kp400" \
  --run "fitted on kp400, scored on kp100" "$out/kp400_to_kp100" \
  --reference "BAM M1=90.8,40.8" --reference "BAM M3=73.5,27.8" \
  --out "$out/servo_gains.png" --table "$out/servo_gains.md"
cat "$out/servo_gains.md"
