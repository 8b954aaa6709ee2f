#!/bin/bash
# A/B in one sitting: the binary before the centroid change (nacre_old: 669 element types at 1M
# bricks) against the one after (2 types), BE and BIE at 980,535 bricks, order alternated
export OMP_NUM_THREADS=2
for round in 1 2; do
  if [ $round = 1 ]; then order="old new"; else order="new old"; fi
  for m in be bie; do
    for v in $order; do
      exe=build/openmp/src/nacre; [ $v = old ] && exe=OUT/nacre_old
      $exe bench OUT/${m}1000000.toml --steps 60 --repeat 2 -o OUT/ab_${v}_${m}_$round > OUT/ab_${v}_${m}_$round.txt 2>&1 || echo "FAIL $v $m"
    done
  done
done
python3 - <<'PY'
import json
for m in ("be", "bie"):
    for v in ("old", "new"):
        r = []
        for k in (1, 2):
            e = json.load(open(f"OUT/ab_{v}_{m}_{k}/bench.json"))["backends"]["openmp"]
            r.append(e["seconds_per_unit"])
        print(m, v, " ".join(f"{x:.4f}" for x in r), "s/step")
PY
