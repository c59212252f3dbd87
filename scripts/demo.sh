#!/usr/bin/env bash
# The main job on the embedded default (make demo): a real ball-screw stage (EMPS benchmark data, shipped in
# diagrams/emps/data). Compare the benchmark's rigid-body model with the measurement, see where it fails and
# what is missing, add the suggested effect block, refit, and validate on the held-out record. Last, the seed
# paper's experiments on the linear-motor twin (`reproduce --quick`, under a minute).
set -euo pipefail
BIN=${1:-build/release/tools/motionblocks}
OUT=${OUT:-out/demo}
DATA=diagrams/emps/data
mkdir -p "$OUT"

step() { printf '\n== %s\n' "$*"; }

step "1. Base model (rigid body + viscous + Coulomb + offset) vs DATA_EMPS: refit, diagnose, suggest"
"$BIN" compare diagrams/emps/rigid_body.json --measurement "$DATA/DATA_EMPS.csv" \
  --out "$OUT/1_base" --write-fitted "$OUT/rigid_body_fitted.json" \
  --suggest "$OUT/rigid_body_suggested.json"

step "2. The suggested diagram (effect block added), refit jointly on DATA_EMPS"
"$BIN" compare "$OUT/rigid_body_suggested.json" --measurement "$DATA/DATA_EMPS.csv" \
  --out "$OUT/2_suggested" --write-fitted "$OUT/rigid_body_suggested_fitted.json"

step "3. Validation on the held-out record DATA_EMPS_PULSES (nothing refit): base model"
"$BIN" compare "$OUT/rigid_body_fitted.json" --measurement "$DATA/DATA_EMPS_PULSES.csv" --no-fit \
  --out "$OUT/3_validate_base"

step "4. Validation on DATA_EMPS_PULSES: with the added effect (its shape from DATA_EMPS; only its position reference, the encoder zero of this record, refit)"
"$BIN" compare "$OUT/rigid_body_suggested_fitted.json" --measurement "$DATA/DATA_EMPS_PULSES.csv" --fit ripple.position_offset \
  --out "$OUT/4_validate_suggested"

step "5. The TISO-GPR paper on the linear-motor twin (quick): training scans, DS/PS fits, Tables 1 and 2, payload, stability, cost per step"
"$BIN" reproduce --quick --out "$OUT/5_reproduce"

step "6. The loop in one command on EMPS: improve adds the ranked effects one at a time, refits jointly, keeps an effect only if the held-out error (DATA_EMPS_PULSES) falls"
"$BIN" improve diagrams/emps/rigid_body.json --measurement "$DATA/DATA_EMPS.csv" \
  --validation "$DATA/DATA_EMPS_PULSES.csv" --max-effects 1 --max-trials 6 --out "$OUT/6_improve_emps"

step "7. improve on the paper's twin: the 'measurement' is the twin's closed loop with its cogging (run here, and a held-out run at other speeds); the model lacks the cogging"
"$BIN" run diagrams/paper/cogging_scan.json --out "$OUT/7_twin_scan" >/dev/null
"$BIN" run diagrams/paper/cogging_scan.json --set 'reference.velocities=[0.15,0.25]' --out "$OUT/7_twin_validation" >/dev/null
"$BIN" improve diagrams/paper/motor_rigid_body.json --measurement "$OUT/7_twin_scan/signals.csv" \
  --validation "$OUT/7_twin_validation/signals.csv" --max-effects 2 --out "$OUT/7_improve_twin"

step "Reports"
for d in 1_base 2_suggested 3_validate_base 4_validate_suggested 5_reproduce 6_improve_emps 7_improve_twin; do
  echo "  $OUT/$d/report.html"
done
