#!/bin/sh
# The table "Held-out-like problems against the peers" of
# docs/performance/root-solvers.md, in one run: signorini's default method
# (`local`, the status method on an LCP, `--friction auto` on Coulomb) against
# a NumPy primal-dual active set on the LCPs and every Siconos solver on the
# Coulomb problems, problem by problem, from the files that
# `signorini bench --suite root --families halfspace_lcp_2d,halfspace_lcp_3d,halfspace_coulomb_2d,halfspace_coulomb_3d --sizes 784,800,2025 --export --out DIR`
# writes in DIR/problems.
# Usage: sh docs/peers/heldout_root.sh [DIR/problems] [signorini binary]
D=${1:-/tmp/hs/problems}
B=${2:-target/release/signorini}
P=$(dirname "$0")
OPENBLAS_NUM_THREADS=2 /usr/bin/python3 "$P/pdas_root.py" "$D/halfspace_lcp_2d_m2025.npz" "$D/halfspace_lcp_3d_m2025.npz" --repeat 10 --signorini "$B"
for f in "$D/halfspace_coulomb_2d_m800.npz" "$D/halfspace_coulomb_3d_m784.npz"; do
    "$B" local "$f" --repeat 5
    OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 /usr/bin/python3 "$P/siconos_root.py" "$f" --max-s 120
done
